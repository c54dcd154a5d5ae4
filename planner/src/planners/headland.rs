//! Planner `headland`, for ground vehicles (docs/methods.md, ground): passes round the field's
//! edge and every hole, straight swaths over the mainland inside them, every turn between
//! swaths in the headland, the swaths' order a generalised TSP over the real turns.

use geo::{Coord, LineString, MultiPolygon};

use super::{PlannedPath, Planner, Problem, Progress};
use crate::decompose::headland::Headland;
use crate::error::PlanError;
use crate::frame::LocalFrame;
use crate::geom::distance;
use crate::metrics;
use crate::params::{HeadlandOrder, HeadlandSpec};
use crate::path::{FlightPath, PieceKind, TurnShape};
use crate::route::headland_corners::{PassRing, work_corners};
use crate::route::headland_route::{HeadlandRoutes, SwathLinks, Way, connect_anywhere, order, ring_pose};
use crate::route::line_tour::{Line, entry, exit};
use crate::route::refill::{Tank, plan_trips};
use crate::sweep::ends::SwathEnds;
use crate::sweep::{fewest_lines_direction, from_sweep_frame, sweep};
use crate::turn::dubins::Pose;
use crate::vehicle::{Vehicle, VehicleKind};
use rayon::prelude::*;

/// A ground plan's headland, computed and checked when the request is.
pub struct GroundSetup {
    pub spec: HeadlandSpec,
    pub headland: Headland,
    /// For naming places in messages.
    pub frame: LocalFrame,
}

impl GroundSetup {
    /// The headland passes' rings.
    pub fn rings(&self) -> Vec<Vec<Coord>> {
        self.headland.passes.iter().flatten().cloned().collect()
    }

    /// Where `vehicle` may drive in `region` (the field less its holes and zones) and how it
    /// turns: the passes' rings are its roads.
    pub fn routes(&self, region: &MultiPolygon, vehicle: &Vehicle) -> HeadlandRoutes {
        HeadlandRoutes::new(region, &self.headland.mainland, &self.rings(), vehicle.steering(), self.spec.width_m)
    }
}

pub struct HeadlandPlanner;

impl Planner for HeadlandPlanner {
    fn id(&self) -> &'static str {
        "headland"
    }

    fn name(&self) -> &'static str {
        "Headland and swaths"
    }

    fn description(&self) -> &'static str {
        "Ground vehicles: headland passes round the field's edge and every hole, swaths over the mainland, every turn inside the headland (Dubins, fishtail when the vehicle may reverse), swath order by GTSP over the real turns"
    }

    fn direction_rule(&self) -> &'static str {
        "shortest swaths and turns over the mainland (each turn counted as a U turn)"
    }

    fn for_ground_vehicles(&self) -> bool {
        true
    }

    fn default_for(&self) -> &'static [VehicleKind] {
        &[VehicleKind::Ground]
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        let setup = problem.ground.ok_or_else(|| PlanError::Infeasible("planner headland plans ground vehicles: give vehicle kind ground".into()))?;
        let laid = Swaths::lay(problem, setup);
        work(problem, setup, &laid, &Share::whole(), progress)
    }
}

/// The swaths of a ground plan: their direction, where they lie across it (the guidance line's
/// offset), the swaths themselves and which are tramlines.
pub struct Swaths {
    pub angle: f64,
    phase: Option<f64>,
    lines: Vec<Line>,
    tramlines: Vec<bool>,
}

impl Swaths {
    /// The swaths `problem.vehicle` works: along the guidance line, at the direction asked, or
    /// at the best direction for it ([`best_direction`]).
    pub fn lay(problem: &Problem<'_>, setup: &GroundSetup) -> Swaths {
        let routes = setup.routes(problem.region, problem.vehicle);
        let lines_at = |angle: f64, phase: Option<f64>| lines_for(problem, setup, &routes, (angle, phase));
        // a guidance line sets the swaths' direction and where they lie across it
        let guidance = setup.spec.guidance.map(|g| g.in_frame(&setup.frame));
        let angle = guidance
            .map(|g| g.1)
            .or(problem.sweep_angle)
            .unwrap_or_else(|| best_direction(&setup.headland.mainland, problem.layout, (&routes, setup.spec.width_m), &|a| lines_at(a, None)));
        let phase = guidance.map(|(a, _)| crate::sweep::to_sweep_frame(angle, a).y);
        let lines = lines_at(angle, phase);
        let tramlines = setup.spec.tramline_every.map(|n| tramlines(&lines, (angle, phase), problem.layout.spacing, n)).unwrap_or_default();
        Swaths { angle, phase, lines, tramlines }
    }

    /// Each swath's offset across the direction.
    fn offsets(&self) -> Vec<f64> {
        self.lines.iter().map(|l| crate::sweep::to_sweep_frame(self.angle, (l.a + l.b) * 0.5).y).collect()
    }
}

/// The swaths of `problem.region` at `(angle, phase)` whose ends `routes`' vehicle can turn at.
fn lines_for(problem: &Problem<'_>, setup: &GroundSetup, routes: &HeadlandRoutes, at: (f64, Option<f64>)) -> Vec<Line> {
    swaths(&setup.headland.mainland, problem.region, at, problem.layout.spacing, setup.spec.swath_ends, setup.spec.width_m)
        .into_iter()
        .filter_map(|l| routes.turnable(l.a, l.b).map(|(a, b)| Line { a, b, ..l }))
        .collect()
}

/// What one machine of several works in a field: the swaths whose offsets across the direction
/// lie in `[from, to)`, and the headland passes or not.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Share {
    pub from: f64,
    pub to: f64,
    pub passes: bool,
}

impl Share {
    /// The whole field, one machine.
    pub fn whole() -> Share {
        Share { from: f64::NEG_INFINITY, to: f64::INFINITY, passes: true }
    }
}

/// The field shared among machines working at `speeds` (m/s): each a band of neighbouring
/// swaths, the first the headland passes as well, the bands balanced so that the last machine
/// finishes soonest (each swath counted as its length and a U turn of `turn_m`).
pub fn share_out(laid: &Swaths, passes_m: f64, turn_m: f64, speeds: &[f64]) -> Vec<Share> {
    let mut across: Vec<(f64, f64)> = laid.offsets().into_iter().zip(laid.lines.iter().map(|l| l.length() + turn_m)).collect();
    across.sort_by(|a, b| a.0.total_cmp(&b.0));
    // whether every swath fits when each machine works for at most `t` seconds, and where
    // each band begins
    let fill = |t: f64| -> Option<Vec<usize>> {
        let mut begins = vec![0];
        let mut k = 0;
        let mut load = passes_m;
        for (i, &(_, m)) in across.iter().enumerate() {
            while (load + m) / speeds[k] > t && load > 0.0 {
                k += 1;
                if k == speeds.len() {
                    return None;
                }
                begins.push(i);
                load = 0.0;
            }
            load += m;
        }
        Some(begins)
    };
    let total: f64 = passes_m + across.iter().map(|a| a.1).sum::<f64>();
    let slowest = speeds.iter().copied().fold(f64::INFINITY, f64::min);
    let (mut lo, mut hi) = (0.0, total / slowest + 1.0);
    for _ in 0..60 {
        let mid = (lo + hi) / 2.0;
        if fill(mid).is_some() { hi = mid } else { lo = mid }
    }
    let begins = fill(hi).expect("the whole field fits one machine's time");
    // a band's edge half-way between its first swath and the last before it
    let edge = |i: usize| if i == 0 { f64::NEG_INFINITY } else { (across[i - 1].0 + across[i].0) / 2.0 };
    (0..speeds.len())
        .map(|k| match begins.get(k) {
            Some(&i) => Share { from: edge(i), to: begins.get(k + 1).map_or(f64::INFINITY, |&j| edge(j)), passes: k == 0 },
            // a machine not needed works nothing
            None => Share { from: f64::INFINITY, to: f64::INFINITY, passes: false },
        })
        .collect()
}

/// The route of `share` of the swaths `laid` (with `problem.vehicle`'s turns) and, where the
/// share says so, the headland passes; with a payload, its refill trips.
pub fn work(problem: &Problem<'_>, setup: &GroundSetup, laid: &Swaths, share: &Share, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
    let vehicle = problem.vehicle;
    let headland = &setup.headland;
    let routes = setup.routes(problem.region, vehicle);
    let half = setup.spec.working_width_m / 2.0;
    // the passes as driven, their corners worked where the vehicle can; the ground they cover
    let passes: Vec<Vec<PassRing>> = if share.passes {
        let radius = vehicle.planning_radius_m();
        headland.passes.par_iter().map(|rings| rings.par_iter().map(|ring| work_corners(ring, &routes, radius, half)).collect()).collect()
    } else {
        Vec::new()
    };
    let worked: Vec<Vec<Coord>> = passes.iter().flatten().flat_map(PassRing::worked).collect();
    let angle = laid.angle;
    let (lines, tramlines) = if *share == Share::whole() {
        (laid.lines.clone(), laid.tramlines.clone())
    } else {
        // one machine of several: its band, laid again for its own turns at the same
        // direction and phase, the tramlines where they were laid
        let offset_of = |l: &Line| crate::sweep::to_sweep_frame(angle, (l.a + l.b) * 0.5).y;
        let own: Vec<Line> = lines_for(problem, setup, &routes, (angle, laid.phase)).into_iter().filter(|l| (share.from..share.to).contains(&offset_of(l))).collect();
        let tramline_offsets: Vec<f64> = laid.offsets().into_iter().zip(&laid.tramlines).filter(|(_, t)| **t).map(|(o, _)| o).collect();
        let tramlines = own.iter().map(|l| tramline_offsets.iter().any(|t| (t - offset_of(l)).abs() < problem.layout.spacing / 4.0)).collect();
        (own, tramlines)
    };
    if !progress.report(0.3) {
        return Err(PlanError::Cancelled);
    }
    let spacing = setup.spec.width_m / headland.passes.len().max(1) as f64;
    let mut drive = Drive { path: FlightPath::default(), at: problem.start.map(|p| Pose::at(p, problem.start_heading.unwrap_or(angle))), routes: &routes, frame: &setup.frame };
    if share.passes && setup.spec.order == HeadlandOrder::First {
        drive.passes(&passes, false, half, spacing);
    }
    let links = SwathLinks::new(&lines, &routes);
    // the ground the swaths and passes cover does not depend on their order: measured
    // while the order is searched
    let swaths: Vec<(Coord, Coord)> = lines.iter().map(|l| (l.a, l.b)).collect();
    let end = problem.end.map(|p| Pose::at(p, problem.end_heading.unwrap_or(angle)));
    let (seq, swept) = order(&links, drive.at, end, &problem.connector.stop(), || metrics::ground_swept(&swaths, &worked, half));
    if !progress.report(0.8) {
        return Err(PlanError::Cancelled);
    }
    let mut previous: Option<usize> = None;
    for &v in &seq {
        let (a, b) = (entry(&lines, v), exit(&lines, v));
        match previous {
            Some(u) => {
                let (way, _) = links.link(u, v).ok_or_else(|| drive.no_turn(exit(&lines, u).coord()))?;
                drive.follow(way, a);
            }
            None => drive.go_to(a),
        }
        drive.path.push(PieceKind::Sweep, vec![a.coord(), b.coord()], half);
        if tramlines.get(v / 2) == Some(&true) {
            drive.path.pieces.last_mut().expect("just pushed").tramline = true;
        }
        drive.at = Some(b);
        previous = Some(v);
    }
    if share.passes && setup.spec.order == HeadlandOrder::Last {
        drive.passes(&passes, true, half, spacing);
    }
    if let Some(end) = problem.end {
        drive.go_to(Pose::at(end, problem.end_heading.unwrap_or_else(|| drive.at.map_or(angle, |p| p.theta))));
    }
    let (path, payload) = match &setup.spec.payload {
        Some(payload) => {
            let tank = Tank {
                capacity: payload.capacity,
                per_m2: payload.per_m2(),
                stations: payload.refill_points.iter().map(|p| setup.frame.to_local(p[0], p[1])).collect(),
                stand_s: payload.refill_s(),
                stand_m: payload.refill_s() * vehicle.headland_speed_mps(),
            };
            let (path, stats) = plan_trips(&drive.path, &tank, &routes).ok_or_else(|| {
                PlanError::Infeasible("no way inside the field leads from the swaths to a refill point: give refill points on the field's boundary or at its entrances".into())
            })?;
            (path, Some(stats))
        }
        None => (drive.path, None),
    };
    Ok(PlannedPath { swept: Some(swept), payload, ..PlannedPath::new(path, angle, 1) })
}

/// Directions whose swaths are measured for real: the best by the estimate.
const DIRECTIONS_MEASURED: usize = 8;
/// What a swath end costs, in turns, where a forward-only vehicle cannot turn back in the
/// headland: the drive along it to where it can (on the 2-pass sprayer's bench rows 6 turns
/// cut the crossings of the crop from 174 to 99 and the length by 2.8 %; 1 turn, 113 and 0.9 %;
/// the route's price of a crossing, 1 000 m, 99 and 2.5 %, with more rows longer).
const STUCK_END_TURNS: f64 = 6.0;
/// The longest edges of the mainland's hull whose square directions are measured as well where
/// the vehicle cannot turn round on the headland.
const SQUARE_TO_EDGES: usize = 4;

/// The direction whose swaths and turns are shortest, each turn counted as a U turn's length:
/// every candidate direction (the hull's edges, every degree) is estimated on the swaths'
/// bands (the mainland's intervals along each band's edges and centre line, merged), and the
/// real swaths of the best few decide. Ranking by the hull's width instead missed the best
/// direction of fields with two cells (81 turns where 72 do). A forward-only vehicle in a
/// headland narrower than its turning circle pays [`STUCK_END_TURNS`] turns more for each swath
/// end it cannot turn back at, and the directions square to the longest edges are measured too.
fn best_direction(mainland: &MultiPolygon, layout: crate::sweep::LineLayout, (routes, headland_m): (&HeadlandRoutes, f64), lines_at: &(dyn Fn(f64) -> Vec<Line> + Sync)) -> f64 {
    let radius = routes.bounding_radius();
    use geo::{BoundingRect, ConvexHull};
    use rayon::prelude::*;
    let hull: Vec<Coord> = mainland.convex_hull().exterior().0.clone();
    let turn = std::f64::consts::PI * radius + 2.0 * radius;
    // a swath spans what its band holds: the intervals at its band's edges and centre, merged
    let estimate = |a: f64| {
        let rotated = crate::sweep::rotate(mainland, a);
        let Some(bbox) = rotated.bounding_rect() else { return f64::INFINITY };
        let lines = layout.lines(bbox.min().y, bbox.max().y);
        let ys: Vec<f64> = lines.iter().flat_map(|&(offset, lo, hi)| [lo + 1e-6, offset, hi - 1e-6]).collect();
        let at = crate::sweep::scanlines_intervals(&rotated, &ys);
        at.chunks(3)
            .map(|band| {
                let mut all: Vec<(f64, f64)> = band.iter().flatten().copied().collect();
                all.sort_by(|x, y| x.0.total_cmp(&y.0));
                crate::sweep::merge_overlapping(all).into_iter().map(|(a, b)| b - a + turn).sum::<f64>()
            })
            .sum::<f64>()
    };
    let mut ranked: Vec<(f64, f64)> = crate::sweep::candidate_directions(&hull).into_par_iter().map(|a| (estimate(a), a)).collect();
    ranked.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut picked: Vec<f64> = Vec::new();
    for (_, a) in ranked {
        // directions within a degree of one already picked give the same swaths
        if picked.iter().all(|&p| crate::geom::axial_difference(a, p) > 1f64.to_radians()) {
            picked.push(a);
        }
        if picked.len() == DIRECTIONS_MEASURED {
            break;
        }
    }
    // a forward-only vehicle in a headland narrower than its turning circle cannot turn round
    // on it: a swath end where no half turn stays in the headland is left by a drive along the
    // headland to where it can, or across the crop; swaths square to the field's longest
    // edges, whose ends turn there, are measured too
    let turns_round_on_the_headland = routes.reverses() || 2.0 * radius <= headland_m;
    if !turns_round_on_the_headland {
        let mut edges: Vec<(f64, f64)> = hull.windows(2).map(|w| (crate::geom::distance(w[0], w[1]), (w[1].y - w[0].y).atan2(w[1].x - w[0].x))).collect();
        edges.sort_by(|x, y| y.0.total_cmp(&x.0));
        for (_, along) in edges.into_iter().take(SQUARE_TO_EDGES) {
            let square = along + std::f64::consts::FRAC_PI_2;
            if picked.iter().all(|&p| crate::geom::axial_difference(square, p) > 1f64.to_radians()) {
                picked.push(square);
            }
        }
    }
    let stuck_ends = |a: f64| {
        if turns_round_on_the_headland {
            return 0;
        }
        let ends = lines_at(a).into_iter().flat_map(|l| [(l.b, l.a), (l.a, l.b)]);
        ends.filter(|&(at, from)| !routes.turns_back_at(at, (at - from) / crate::geom::distance(at, from))).count()
    };
    let cost = |a: f64| {
        let pattern = sweep(mainland, &MultiPolygon(vec![]), a, layout);
        let segments = pattern.lines.iter().flatten();
        segments.map(|s| s.b - s.a + turn).sum::<f64>() + stuck_ends(a) as f64 * STUCK_END_TURNS * turn
    };
    picked.into_par_iter().map(|a| (cost(a), a)).min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1))).map_or_else(|| fewest_lines_direction(mainland, layout), |(_, a)| a)
}

/// The swaths over `mainland`: lines `spacing` apart at `angle` (at whole spacings from the
/// sweep-frame offset `phase` when given), ended by `rule`
/// ([`crate::sweep::ends::cut`]; a full-width end runs at most `slack` past the centre line's,
/// leaving room in the headland to turn). Each is tagged with the field of `region` it lies in.
fn swaths(mainland: &MultiPolygon, region: &MultiPolygon, (angle, phase): (f64, Option<f64>), spacing: f64, rule: SwathEnds, slack: f64) -> Vec<Line> {
    use geo::{Area, Contains};
    let pattern = sweep(mainland, &MultiPolygon(vec![]), angle, crate::sweep::LineLayout { phase, ..crate::sweep::LineLayout::centered(spacing) });
    let segments: Vec<_> = pattern.lines.into_iter().flatten().collect();
    let ends = crate::sweep::ends::cut(&crate::sweep::rotate(mainland, angle), &segments, rule, slack, mainland.unsigned_area());
    ends.into_iter()
        .zip(&segments)
        .filter(|((a, b), _)| b - a > 0.05)
        .map(|((a, b), s)| {
            let (a, b) = (from_sweep_frame(angle, a, s.offset), from_sweep_frame(angle, b, s.offset));
            let centre = from_sweep_frame(angle, (s.a + s.b) / 2.0, s.offset);
            let field = region.0.iter().position(|p| p.contains(&centre)).unwrap_or(0);
            Line { a, b, region: field }
        })
        .collect()
}

/// Which of `lines` (swaths at `angle`, `spacing` apart) are tramlines, one every `every`:
/// counted from the guidance line's offset `phase` (its own swath is one), else the middle
/// swath of the first `every` from the edge (where a sprayer `every` swaths wide runs flush
/// with it): the edge on the right of the swaths run at their compass bearing below 180°.
fn tramlines(lines: &[Line], (angle, phase): (f64, Option<f64>), spacing: f64, every: usize) -> Vec<bool> {
    // offsets grow to the left of the direction: for the edge rule, the direction whose bearing
    // is below 180° (the plan reports that bearing)
    let bearing_below_180 = crate::params::bearing_to_math(crate::params::math_to_bearing(angle) % 180.0);
    let across = if phase.is_some() { angle } else { bearing_below_180 };
    let offsets: Vec<f64> = lines.iter().map(|l| crate::sweep::to_sweep_frame(across, (l.a + l.b) * 0.5).y).collect();
    let first = offsets.iter().copied().fold(f64::INFINITY, f64::min);
    let (base, wanted) = match phase {
        Some(p) => (p, 0),
        None => (first, (every as i64 - 1) / 2),
    };
    offsets.iter().map(|o| ((o - base) / spacing).round() as i64).map(|k| k.rem_euclid(every as i64) == wanted).collect()
}

/// Vertices of a ring tried as its entry.
const RING_ENTRIES: usize = 16;

/// The path as it is driven, and where the vehicle is.
struct Drive<'a> {
    path: FlightPath,
    at: Option<Pose>,
    routes: &'a HeadlandRoutes,
    frame: &'a LocalFrame,
}

impl Drive<'_> {
    /// Appends `way` (a turn or a transit) and stands at `to`.
    fn follow(&mut self, way: Way, to: Pose) {
        match way.shape {
            Some(shape) => self.path.push_turn(shape, way.points),
            None => self.path.push(PieceKind::Transit, way.points, 0.0),
        }
        self.at = Some(to);
    }

    /// A transit from where the vehicle is to `to` (nothing before the first piece).
    fn go_to(&mut self, to: Pose) {
        if let Some(at) = self.at {
            self.path.push(PieceKind::Transit, connect_anywhere(self.routes, at, to).0.points, 0.0);
        }
        self.at = Some(to);
    }

    /// Where to enter `ring` (closed) and which way round to drive it: of the [`RING_ENTRIES`]
    /// vertices nearest the vehicle, each way round, the first a transit inside the field
    /// reaches without a detour (a transit keeps to the headland, where a ring driven the wrong
    /// way round may lead far off), else the one it reaches by the shortest. From a ring just
    /// driven, the vehicle may also drive on along it first (a pond's own ring leads round the
    /// pond); `lap` is that ring from the vehicle's position, and the answer's last figure is
    /// how many of its vertices to drive on. Else the nearest vertex.
    fn ring_entry(&self, pass: &PassRing, lap: Option<&[Coord]>) -> (usize, bool, usize) {
        let ring = &pass.points;
        let Some(here) = self.at else { return (0, true, 0) };
        let n = ring.len() - 1;
        // never in the middle of a corner's manoeuvre
        let nearest = |from: Coord| {
            let mut near: Vec<(f64, usize)> = (0..n).filter(|&i| pass.may_enter_at(i)).map(|i| (distance(from, ring[i]), i)).collect();
            near.sort_by(|a, b| a.0.total_cmp(&b.0));
            near
        };
        let lap = lap.unwrap_or(&[]);
        let stride = (lap.len() / RING_ENTRIES).max(1);
        let departures = std::iter::once((0, here)).chain((stride..lap.len().saturating_sub(1)).step_by(stride).map(|d| (d, ring_pose(lap, d, true))));
        for (d, from) in departures {
            let near = nearest(from.coord());
            let step = (n / RING_ENTRIES).max(1);
            // the first entry reached without a detour, else the one reached by the shortest
            let mut best: Option<(usize, bool, f64)> = None;
            for (i, forward) in near.iter().take(RING_ENTRIES * step).step_by(step).flat_map(|&(_, i)| [(i, true), (i, false)]) {
                let Some(way) = self.routes.transit(from, ring_pose(ring, i, forward)) else { continue };
                if best.is_none_or(|b| way.length < b.2) {
                    best = Some((i, forward, way.length));
                }
                if !self.routes.is_detour(way.length, from.coord(), ring[i]) {
                    break;
                }
            }
            if let Some((i, forward, _)) = best {
                return (i, forward, d);
            }
        }
        (nearest(here.coord())[0].1, true, 0)
    }

    /// Every headland pass, innermost first when `outwards`, else outermost first, in the
    /// shorter of two orders: pass by pass, or each ring as soon as the rings of the passes
    /// before it that lie near it are driven (one pond's passes in order, without going round
    /// every other pond's first). `spacing`: the distance between passes.
    fn passes(&mut self, passes: &[Vec<PassRing>], outwards: bool, half: f64, spacing: f64) {
        let drive_in = |local: bool| {
            let mut drive = Drive { path: self.path.clone(), ..*self };
            drive.rings(passes, outwards, half, spacing, local);
            drive
        };
        let (by_pass, local) = rayon::join(|| drive_in(false), || drive_in(true));
        *self = if local.path.length() < by_pass.path.length() { local } else { by_pass };
    }

    /// The rings of every pass in the order [`Drive::passes`] describes (`local`: as soon as
    /// the near ones before are driven), the nearest ready ring next.
    fn rings(&mut self, passes: &[Vec<PassRing>], outwards: bool, half: f64, spacing: f64, local: bool) {
        use geo::{Distance, Euclidean};
        let rings: Vec<(usize, &PassRing)> = passes.iter().enumerate().flat_map(|(k, rings)| rings.iter().map(move |r| (k, r))).collect();
        let lines: Vec<LineString> = rings.iter().map(|(_, r)| LineString::from(r.points.to_vec())).collect();
        let first = |a: usize, b: usize| if outwards { a > b } else { a < b };
        let waits_for: Vec<Vec<usize>> = (0..rings.len())
            .map(|j| {
                (0..rings.len())
                    .filter(|&i| first(rings[i].0, rings[j].0))
                    .filter(|&i| !local || Euclidean.distance(&lines[i], &lines[j]) <= 1.5 * spacing * rings[i].0.abs_diff(rings[j].0) as f64)
                    .collect()
            })
            .collect();
        let mut driven = vec![false; rings.len()];
        // the ring just driven, also of the pass before: the way onto the next ring may start
        // further along it (from a corner no ramp inside the field may reach the next pass)
        let mut lap: Option<Vec<Coord>> = None;
        loop {
            let here = self.at.map(|p| p.coord());
            let gap = |ring: &PassRing| here.map_or(0.0, |h| ring.points.iter().map(|&p| distance(h, p)).fold(f64::INFINITY, f64::min));
            let ready = (0..rings.len()).filter(|&j| !driven[j] && waits_for[j].iter().all(|&i| driven[i]));
            let Some(k) = ready.min_by(|&a, &b| gap(rings[a].1).total_cmp(&gap(rings[b].1)).then(a.cmp(&b))) else { break };
            driven[k] = true;
            let pass = rings[k].1;
            let ring = &pass.points;
            let (i, forward, drive_on) = self.ring_entry(pass, lap.as_deref());
            if let Some(lap) = lap.as_ref().filter(|_| drive_on > 0) {
                self.path.push(PieceKind::Transit, lap[..=drive_on].to_vec(), 0.0);
                self.at = Some(ring_pose(lap, drive_on, true));
            }
            let n = ring.len() - 1;
            let order: Vec<usize> = (0..=n).map(|j| if forward { (i + j) % n } else { (i + n - j) % n }).collect();
            let points: Vec<Coord> = order.iter().map(|&j| ring[j]).collect();
            self.go_to(ring_pose(ring, i, forward));
            let last = points[n - 1];
            // worked stretches, and the corners' manoeuvres between them driven idle
            let idle: Vec<bool> = order.windows(2).map(|leg| pass.is_idle(leg[0], leg[1])).collect();
            let mut start = 0;
            for run in idle.chunk_by(|a, b| a == b) {
                let stretch = points[start..=start + run.len()].to_vec();
                if run[0] {
                    self.path.push_turn(TurnShape::Corner, stretch)
                } else {
                    self.path.push(PieceKind::Headland, stretch, half)
                }
                start += run.len();
            }
            self.at = Some(Pose::at(ring[i], (ring[i].y - last.y).atan2(ring[i].x - last.x)));
            lap = Some(points);
        }
    }

    /// The refusal when no turn joins two swaths inside the field: where, and what to change.
    fn no_turn(&self, at: Coord) -> PlanError {
        let [lon, lat] = self.frame.to_wgs84(at);
        PlanError::Infeasible(format!(
            "no turn stays inside the field at the swath end near [{lon:.6}, {lat:.6}]: the headland is too narrow there for this turning radius; \
             add headland passes (or headland_width_m), allow reversing, or fix heading_deg along the narrow part"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::ends::CENTRE_LINE_PAST_M;
    use geo::polygon;

    /// Ten swaths 100 m long, 6 m apart, at 0°.
    fn ten_swaths() -> Swaths {
        let lines = (0..10).map(|k| Line { a: Coord { x: 0.0, y: 6.0 * k as f64 }, b: Coord { x: 100.0, y: 6.0 * k as f64 }, region: 0 }).collect();
        Swaths { angle: 0.0, phase: None, lines, tramlines: Vec::new() }
    }

    /// How many of `laid`'s swaths each share holds.
    fn counts(laid: &Swaths, shares: &[Share]) -> Vec<usize> {
        shares.iter().map(|s| laid.offsets().iter().filter(|o| (s.from..s.to).contains(*o)).count()).collect()
    }

    #[test]
    fn shares_balance_the_machines_time_with_the_passes_on_the_first() {
        let laid = ten_swaths();
        // equal machines: five swaths each; every swath in exactly one share
        let even = share_out(&laid, 0.0, 0.0, &[1.0, 1.0]);
        assert_eq!(counts(&laid, &even), vec![5, 5]);
        assert!(even[0].passes && !even[1].passes);
        // passes as long as two swaths: the first machine takes four, the other six
        assert_eq!(counts(&laid, &share_out(&laid, 200.0, 0.0, &[1.0, 1.0])), vec![4, 6]);
        // a machine twice as fast takes about twice as many
        assert_eq!(counts(&laid, &share_out(&laid, 0.0, 0.0, &[1.0, 2.0])), vec![3, 7]);
        // a machine not needed works nothing: one swath, three machines
        let one = Swaths { lines: laid.lines[..1].to_vec(), ..ten_swaths() };
        let shares = share_out(&one, 0.0, 0.0, &[1.0, 1.0, 1.0]);
        assert_eq!(counts(&one, &shares).iter().sum::<usize>(), 1);
    }

    #[test]
    fn swaths_fill_the_mainland_and_are_tagged_with_their_field() {
        let field = MultiPolygon(vec![polygon![(x: 0.0, y: 0.0), (x: 100.0, y: 0.0), (x: 100.0, y: 60.0), (x: 0.0, y: 60.0)]]);
        let mainland = MultiPolygon(vec![polygon![(x: 12.0, y: 12.0), (x: 88.0, y: 12.0), (x: 88.0, y: 48.0), (x: 12.0, y: 48.0)]]);
        let lines = swaths(&mainland, &field, (0.0, None), 6.0, SwathEnds::FullWidth, 5.0);
        assert_eq!(lines.len(), 6);
        assert!(lines.iter().all(|l| l.region == 0 && (l.length() - 76.0).abs() < 0.1));
    }

    #[test]
    fn balanced_ends_run_further_where_a_quarter_of_the_width_would_leave_too_much() {
        // 1 600 m² under a 45° edge (x = 60 − y), 10 m swaths: stopping where a quarter of the
        // width is left would leave 4 × 10² / 32 = 12.5 m² (0.78 %); three sixteenths, 0.44 %
        let field = MultiPolygon(vec![polygon![(x: -20.0, y: -20.0), (x: 100.0, y: -20.0), (x: 100.0, y: 60.0), (x: -20.0, y: 60.0)]]);
        let mainland = MultiPolygon(vec![polygon![(x: 0.0, y: 0.0), (x: 60.0, y: 0.0), (x: 20.0, y: 40.0), (x: 0.0, y: 40.0)]]);
        let lines = swaths(&mainland, &field, (0.0, None), 10.0, SwathEnds::Balanced, 20.0);
        assert_eq!(lines.len(), 4);
        for l in &lines {
            let (y, right) = (l.a.y, l.a.x.max(l.b.x));
            assert!((right - (60.0 - y) - 3.125).abs() < 1e-6, "{l:?}");
        }
    }

    #[test]
    fn at_a_slanted_edge_full_width_swaths_run_on_balanced_ones_part_way_and_centre_line_ones_stop() {
        // the right edge runs from (100, 0) to (80, 60): x = 100 − y / 3
        let field = MultiPolygon(vec![polygon![(x: -20.0, y: -20.0), (x: 120.0, y: -20.0), (x: 120.0, y: 80.0), (x: -20.0, y: 80.0)]]);
        let mainland = MultiPolygon(vec![polygon![(x: 0.0, y: 0.0), (x: 100.0, y: 0.0), (x: 80.0, y: 60.0), (x: 0.0, y: 60.0)]]);
        let full = swaths(&mainland, &field, (0.0, None), 6.0, SwathEnds::FullWidth, 10.0);
        let centre = swaths(&mainland, &field, (0.0, None), 6.0, SwathEnds::CentreLine, 10.0);
        let balanced = swaths(&mainland, &field, (0.0, None), 6.0, SwathEnds::Balanced, 10.0);
        assert_eq!((full.len(), centre.len(), balanced.len()), (10, 10, 10));
        for ((f, c), b) in full.iter().zip(&centre).zip(&balanced) {
            let right = |l: &Line| l.a.x.max(l.b.x);
            let y = c.a.y;
            // the centre line meets the edge at 100 − y / 3 (the end runs a centimetre on); the
            // band's lower edge, 3 m below, 1 m further on; a quarter of the width in from that
            // edge, 1.5 m below the centre, 0.5 m on
            assert!((right(c) - (100.0 - y / 3.0) - CENTRE_LINE_PAST_M).abs() < 1e-6, "{c:?}");
            assert!((right(f) - (100.0 - y / 3.0) - 1.0).abs() < 1e-6, "{f:?} {c:?}");
            assert!((right(b) - (100.0 - y / 3.0) - 0.5).abs() < 1e-6, "{b:?} {c:?}");
            // the left edge is square to the swaths: all three end on it
            let left = |l: &Line| l.a.x.min(l.b.x);
            assert!(left(b).abs() < 1e-6 && left(f).abs() < 1e-6 && left(c).abs() < 1e-6, "{b:?} {f:?} {c:?}");
        }
    }
}
