//! Metrics stage: one measure of every plan, whichever planner made it (docs/methods.md, metrics §1–§4).

use geo::algorithm::buffer::{BufferStyle, LineCap};
use geo::{Area, BooleanOps, Buffer, Coord, Euclidean, Length, LineString, MultiLineString, MultiPolygon, Polygon, Simplify};
use serde::{Deserialize, Serialize};

use super::camera::CameraPlan;
use super::energy::PathEstimate;
use super::geom::distance;
use super::path::{FlightPath, PieceKind};
use super::sortie::SortieTotals;

#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Stats {
    pub length_m: f64,
    pub sweep_length_m: f64,
    pub turn_length_m: f64,
    pub transit_length_m: f64,
    /// Flight time and energy, take-off and landing included (each sortie's).
    pub duration_s: f64,
    pub energy_j: f64,
    pub energy_wh: f64,
    /// Of `energy_j`: climbing to the flight altitude and descending from it.
    pub takeoff_landing_energy_j: f64,
    /// Flights from home and back the plan is split into (1: one battery suffices).
    pub sorties: usize,
    /// Each sortie's figures, in flight order.
    pub sortie_totals: Vec<SortieTotals>,
    /// Batteries the plan needs: with a home, the lower bound (total energy over one battery's
    /// usable energy; `sorties` says how many the split flies); without one, a battery per
    /// stretch between `battery_swap` points.
    pub batteries_needed: usize,
    /// What the caller should know about this plan (for example that it needs several batteries
    /// and has no home to return to).
    #[serde(default)]
    pub warnings: Vec<String>,
    /// The planner that made the plan (with `auto`, the one chosen).
    #[serde(default)]
    pub planner: String,
    /// With `auto`: how every other planner did.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub alternatives: Vec<Alternative>,
    /// Share of the area to cover (field − holes − no-fly zones with their margin) under the swaths.
    pub coverage_ratio: f64,
    /// Share of the area to cover inside at least one photo's footprint (with a camera).
    pub photo_coverage_ratio: Option<f64>,
    /// Swath area flown more than once, as a share of the area swept: the summed swath areas
    /// over the area of their union, minus 1 (0 = no overlap between lines).
    pub overlap_ratio: f64,
    pub area_to_cover_m2: f64,
    /// Number of turns between sweep lines.
    pub turns: usize,
    /// Metres of the path inside a no-fly zone (must be 0).
    pub nfz_intrusion_m: f64,
    pub sweep_lines: usize,
    pub cells: usize,
    pub photos: usize,
    pub line_spacing_m: f64,
    /// Compass bearing of the sweep lines.
    pub sweep_heading_deg: f64,
    /// Area divided by spacing: the sweep length no plan can beat.
    pub lower_bound_m: f64,
    /// `lower_bound_m / length_m`.
    pub efficiency: f64,
    pub planning_time_ms: f64,
    /// Metres of sweep line flown above the survey altitude to clear obstacles (not imaged).
    #[serde(default)]
    pub lost_coverage_m: f64,
    /// From planners whose search can prove its result (`eg_cpp`): whether it did.
    pub optimality: Option<Optimality>,
    /// Fleet: from the first take-off to the last landing (battery changes not counted). The
    /// totals above add up every drone's.
    pub makespan_s: Option<f64>,
    /// Fleet: each drone's figures, in the request's order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vehicles: Vec<VehicleTotals>,
    /// Fleet: every time two drones come within 10 m horizontally and 5 m vertically of each
    /// other (empty: none do).
    pub conflicts: Option<Vec<Conflict>>,
    /// Ground vehicle: the headland and the turns.
    pub ground: Option<GroundStats>,
    /// Inspection: the weighted share of the points of interest seen.
    pub inspection_coverage: Option<f64>,
    /// Inspection: what each target shows, the budget and the search.
    pub inspection: Option<InspectionStats>,
    /// With `altitude_reference` `terrain`: the height above ground flown, the climbs.
    pub terrain: Option<crate::terrain::TerrainStats>,
}

/// An inspection's figures.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct InspectionStats {
    /// Points of interest on the targets, and how many are seen.
    pub pois: usize,
    pub pois_seen: usize,
    pub weighted_total: f64,
    pub weighted_seen: f64,
    /// Per structure and face.
    pub targets: Vec<TargetCoverage>,
    /// Viewpoints flown, and sampled in all (initial and added during the search).
    pub viewpoints: usize,
    pub viewpoints_sampled: usize,
    /// `length_m`, `time_s` or `energy_j`.
    pub budget_measure: String,
    pub budget_limit: f64,
    /// The path's cost in that measure (never above the limit).
    pub budget_used: f64,
    /// Search iterations, and why it stopped: `iterations`, `no_improvement` or `time_limit`.
    pub iterations: usize,
    pub search_end: String,
    /// The camera's fields of view and the range a point counts as seen in, as planned.
    pub fov_deg: [f64; 2],
    pub range_m: [f64; 2],
}

/// What is seen of one target: a structure's walls or roof.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct TargetCoverage {
    pub name: String,
    /// `walls` or `roof`.
    pub face: String,
    pub seen: usize,
    pub total: usize,
    pub weighted_seen: f64,
    pub weighted_total: f64,
    /// `weighted_seen / weighted_total`.
    pub coverage: f64,
}

/// A ground plan's figures: how much of the mainland and of the headland is worked, and how
/// the vehicle turns.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct GroundStats {
    pub headland_width_m: f64,
    pub headland_passes: usize,
    pub headland_length_m: f64,
    pub mainland_area_m2: f64,
    pub headland_area_m2: f64,
    /// Shares of the mainland and of the headland band the implement works.
    pub mainland_coverage: f64,
    pub headland_coverage: f64,
    pub u_turns: usize,
    pub omega_turns: usize,
    pub fishtail_turns: usize,
    /// Connections between two swaths driven along a headland pass (where no turn fits), and
    /// those that cross the mainland (where nothing in the headland joins the swaths).
    pub headland_drives: usize,
    pub mainland_crossings: usize,
    /// Turns that leave the field or enter a hole or no-fly zone: 0 unless the planner is wrong.
    pub turns_leaving_field: usize,
    pub turns_crossing_holes: usize,
}

/// The ground figures of `path`, worked as `swept`, with the headland `spec` over its
/// `(mainland, band)`; `field` is the fields with their holes, `keep_out` the no-fly zones
/// grown by the margin.
pub fn ground_stats(
    path: &FlightPath,
    swept: &MultiPolygon,
    spec: &super::params::HeadlandSpec,
    (mainland, band): (&MultiPolygon, &MultiPolygon),
    field: &MultiPolygon,
    keep_out: &MultiPolygon,
) -> GroundStats {
    use super::path::{Piece, TurnShape};
    let turns: Vec<&Piece> = path.pieces.iter().filter(|p| p.kind == PieceKind::Turn).collect();
    let shaped = |shape: TurnShape| turns.iter().filter(|p| p.shape == Some(shape)).count();
    let pieces = &path.pieces;
    let between_swaths =
        (1..pieces.len().saturating_sub(1)).filter(|&i| pieces[i].kind == PieceKind::Transit && pieces[i - 1].kind == PieceKind::Sweep && pieces[i + 1].kind == PieceKind::Sweep);
    let outer = MultiPolygon(field.iter().map(|p| Polygon::new(p.exterior().clone(), vec![])).collect());
    let holes = MultiPolygon(field.iter().flat_map(|p| p.interiors().iter().map(|r| Polygon::new(r.clone(), vec![]))).chain(keep_out.iter().cloned()).collect());
    let inside_length = |zones: &MultiPolygon, p: &Piece| {
        let line = MultiLineString(vec![LineString::from(p.points.clone())]);
        zones.clip(&line, false).0.iter().map(|l| Euclidean.length(l)).sum::<f64>()
    };
    let share = |part: &MultiPolygon| {
        let area = part.unsigned_area();
        if area > 0.0 { (under(swept, part).0 / area).min(1.0) } else { 1.0 }
    };
    let crossings = between_swaths.clone().filter(|&i| inside_length(mainland, &pieces[i]) > 1.0).count();
    GroundStats {
        headland_width_m: spec.width_m,
        headland_passes: spec.passes,
        headland_length_m: path.pieces.iter().filter(|p| p.kind == PieceKind::Headland).map(|p| p.length()).sum(),
        mainland_area_m2: mainland.unsigned_area(),
        headland_area_m2: band.unsigned_area(),
        mainland_coverage: share(mainland),
        headland_coverage: share(band),
        u_turns: shaped(TurnShape::U),
        omega_turns: shaped(TurnShape::Omega),
        fishtail_turns: shaped(TurnShape::Fishtail),
        mainland_crossings: crossings,
        headland_drives: between_swaths.count() - crossings,
        // a centimetre of slack: the turns' arcs are sampled
        turns_leaving_field: turns.iter().filter(|p| inside_length(&outer, p) < p.length() - 0.01).count(),
        turns_crossing_holes: turns.iter().filter(|p| inside_length(&holes, p) > 0.01).count(),
    }
}

/// One drone's part of a fleet plan.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct VehicleTotals {
    /// 0-based, as in the request's `fleet` (or the copy of `vehicles`).
    pub vehicle: usize,
    pub profile: String,
    /// Area of its part of the field (0: the drone is not needed).
    pub area_m2: f64,
    pub sweep_lines: usize,
    pub sorties: usize,
    pub length_m: f64,
    pub duration_s: f64,
    pub energy_j: f64,
    /// Seconds after the fleet's start it takes off (drones sharing a home leave in turn).
    pub departure_s: f64,
    /// Seconds after the fleet's start it lands for the last time.
    pub landing_s: f64,
    /// Altitude of its transits, with `altitude_separation_m`.
    pub transit_altitude_m: Option<f64>,
}

/// Two drones of a fleet too close at the same time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Conflict {
    pub vehicles: [usize; 2],
    /// Seconds after the fleet's start.
    pub from_s: f64,
    pub to_s: f64,
    /// Their least horizontal distance.
    pub closest_m: f64,
    /// [longitude, latitude] midway between them at their closest.
    pub position: [f64; 2],
}

/// Whether a planner's search proved its plan the cheapest under the method's rules.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Optimality {
    pub status: OptimalityStatus,
    /// How much cheaper than this plan's search cost the best plan could still be, as a share
    /// of it (0 when proven): the search's lower bound for what it left unsearched.
    pub gap: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum OptimalityStatus {
    /// The search was complete: no cheaper plan exists under the method's rules.
    Proven,
    /// The search budget ran out first; `gap` bounds what it may have missed.
    SearchLimited,
    /// The plan's time limit came first; `gap` bounds what it may have missed.
    TimeLimited,
}

impl OptimalityStatus {
    pub fn as_str(self) -> &'static str {
        match self {
            OptimalityStatus::Proven => "proven",
            OptimalityStatus::SearchLimited => "search_limited",
            OptimalityStatus::TimeLimited => "time_limited",
        }
    }
}

/// How another planner did on the same problem.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Alternative {
    pub planner: String,
    /// Figures of its plan (without take-off and landing, the same for every planner).
    pub length_m: Option<f64>,
    pub duration_s: Option<f64>,
    pub energy_j: Option<f64>,
    pub coverage_ratio: Option<f64>,
    /// Why it made no plan.
    pub error: Option<String>,
}

/// Coverage at which a plan counts as covering its field (the issue-24 rule, as the spec's
/// benchmark targets): such plans compete on cost per covered area.
pub const COVERAGE_TARGET: f64 = 0.99;

/// When no candidate reaches [`COVERAGE_TARGET`], one may cover this much less than the
/// best-covering one and still be chosen.
pub const COVERAGE_SLACK: f64 = 0.01;

/// The rule by which `auto` chooses among planners and `sweep_direction: optimal` among
/// directions: the least cost per covered share of the field (cost / coverage) among the
/// candidates that cover at least [`COVERAGE_TARGET`], or, when none does, among those within
/// [`COVERAGE_SLACK`] of the best-covering one. A cheap plan that leaves ground unflown does not
/// win, and of two plans that both cover, the one that flies less per hectare covered does.
/// Costs within 1e-9 tie, and a tie goes to the earlier candidate. `None` when there are no
/// candidates.
///
/// ```
/// use coverplan_planner::metrics::best_covering;
/// // (coverage, length): the shortest plan covers too little, the next one qualifies
/// let plans = [(0.90, 800.0), (0.995, 1000.0), (1.0, 1200.0)];
/// assert_eq!(best_covering(&plans, |p| p.0, |p| p.1), Some(1));
/// // both cover; the second costs less per covered share (1005 against 1008)
/// let close = [(0.992, 1000.0), (0.999, 1004.0)];
/// assert_eq!(best_covering(&close, |p| p.0, |p| p.1), Some(1));
/// // none covers 99 %: the best coverage within 1 % competes
/// let poor = [(0.95, 900.0), (0.97, 1000.0), (0.962, 950.0)];
/// assert_eq!(best_covering(&poor, |p| p.0, |p| p.1), Some(2));
/// assert_eq!(best_covering(&[] as &[(f64, f64)], |p| p.0, |p| p.1), None);
/// ```
pub fn best_covering<T>(candidates: &[T], coverage: impl Fn(&T) -> f64, cost: impl Fn(&T) -> f64) -> Option<usize> {
    let most = candidates.iter().map(&coverage).fold(0.0, f64::max);
    let floor = if most >= COVERAGE_TARGET { COVERAGE_TARGET } else { most * (1.0 - COVERAGE_SLACK) };
    let per_covered = |c: &T| cost(c) / coverage(c).max(1e-12);
    let mut best: Option<usize> = None;
    for (i, c) in candidates.iter().enumerate() {
        if coverage(c) >= floor && best.is_none_or(|b| per_covered(c) < per_covered(&candidates[b]) - 1e-9) {
            best = Some(i);
        }
    }
    best
}

/// The swath of a sweep piece as a polygon.
fn swath(points: &[Coord], half: f64) -> Option<Polygon> {
    let (a, b) = (points[0], *points.last()?);
    let d = b - a;
    let len = d.x.hypot(d.y);
    if len == 0.0 || half <= 0.0 {
        return None;
    }
    let n = Coord { x: -d.y / len * half, y: d.x / len * half };
    Some(Polygon::new(LineString::from(vec![a - n, b - n, b + n, a + n, a - n]), vec![]))
}

/// A photo: where it is taken, and the direction of flight (math radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Photo {
    pub at: Coord,
    pub heading: f64,
}

pub fn photo_points(photos: &[Photo]) -> Vec<Coord> {
    photos.iter().map(|p| p.at).collect()
}

/// The ground the photos from `first` to `last` (taken along one line) image: `across` wide,
/// from half a footprint (`along`) behind the first to half a footprint past the last.
fn photo_footprint(first: &Photo, last: &Photo, across: f64, along: f64) -> Polygon {
    let (s, c) = first.heading.sin_cos();
    let u = Coord { x: c * along / 2.0, y: s * along / 2.0 };
    let n = Coord { x: -s * across / 2.0, y: c * across / 2.0 };
    let (a, b) = (first.at, last.at);
    Polygon::new(LineString::from(vec![a - u - n, b + u - n, b + u + n, a - u + n, a - u - n]), vec![])
}

/// True when `next` is taken on `photo`'s line, ahead of it and no further than a footprint
/// (`along`): their footprints overlap or touch along the line.
fn continues(photo: &Photo, next: &Photo, along: f64) -> bool {
    let d = next.at - photo.at;
    let (s, c) = photo.heading.sin_cos();
    let (ahead, aside) = (d.x * c + d.y * s, d.y * c - d.x * s);
    (next.heading - photo.heading).abs() < 1e-9 && (0.0..=along + 1e-6).contains(&ahead) && aside.abs() < 1e-6
}

/// The ground the photos image, in as few shapes as it takes: a run of photos along one line
/// overlap one another (the front overlap is never negative), so the run images one strip. The
/// union of thousands of overlapping footprints is the same ground, but slow to compute.
fn photo_strips(photos: &[Photo], across: f64, along: f64) -> Vec<Polygon> {
    let mut strips = Vec::new();
    let mut first = 0;
    for i in 0..photos.len() {
        if photos.get(i + 1).is_none_or(|next| !continues(&photos[i], next, along)) {
            strips.push(photo_footprint(&photos[first], &photos[i], across, along));
            first = i + 1;
        }
    }
    strips
}

/// How far a swath's centreline may be straightened before it is measured.
const SWATH_TOLERANCE_M: f64 = 0.01;

/// The swath of a polyline flown without stopping to turn: a sensor or boom `half` to either
/// side, across the direction of travel, turns with the vehicle at each bend, so its footprint
/// is a rectangle per straight stretch and, at each bend, the fan the swath sweeps on the
/// outside as the vehicle turns (seed 002's continuous footprint). (A buffer with round joins
/// is the same ground, but `geo`'s leaves out the middle of a loop tighter than the swath.)
fn footprint(line: &[Coord], half: f64) -> Vec<Polygon> {
    let mut shapes: Vec<Polygon> = line.windows(2).filter_map(|w| swath(w, half)).collect();
    let closed = line.len() > 3 && line.first() == line.last();
    let bends = line.windows(3).map(|w| (w[0], w[1], w[2]));
    let closing = closed.then(|| (line[line.len() - 2], line[0], line[1]));
    for (a, v, b) in bends.chain(closing) {
        let (d_in, d_out) = (v - a, b - v);
        let turn = (d_in.x * d_out.y - d_in.y * d_out.x).atan2(d_in.x * d_out.x + d_in.y * d_out.y);
        if turn.abs() < 1e-6 {
            continue;
        }
        // the outside of a left turn is on the right: the fan starts across the way in, there
        let start = d_in.y.atan2(d_in.x) - turn.signum() * std::f64::consts::FRAC_PI_2;
        let steps = (turn.abs() / FAN_STEP_RAD).ceil() as usize;
        // counter-clockwise, as the union wants its shapes: a right turn's fan is drawn backwards
        let (from, sweep) = if turn > 0.0 { (start, turn) } else { (start + turn, -turn) };
        let arc = (0..=steps).map(|k| {
            let angle = from + sweep * k as f64 / steps as f64;
            v + Coord { x: half * angle.cos(), y: half * angle.sin() }
        });
        shapes.push(Polygon::new(LineString::from(std::iter::once(v).chain(arc).collect::<Vec<_>>()), vec![]));
    }
    shapes
}

/// The angle of one straight piece of a fan's arc (5°).
const FAN_STEP_RAD: f64 = std::f64::consts::PI / 36.0;

/// What one strip of swept ground is drawn from.
enum Strip {
    /// A ground vehicle's headland pass: a closed ring.
    Pass(Vec<Coord>, f64),
    /// Sweeps flown one after another.
    Line(Vec<Coord>, f64),
}

impl Strip {
    /// A pass, a closed ring from its first point in canonical form: the same ring driven from
    /// anywhere, either way round, gives the same strip.
    fn pass(ring: &[Coord], half: f64) -> Strip {
        if ring.len() < 4 || ring.first() != ring.last() {
            return Strip::Pass(ring.to_vec(), half);
        }
        let n = ring.len() - 1;
        let forward: Vec<Coord> = ring[..n].to_vec();
        let backward: Vec<Coord> = forward.iter().rev().copied().collect();
        let lowest = forward.iter().copied().min_by(|a, b| compare_points(&[*a], &[*b])).unwrap_or_default();
        // every rotation that starts at the lowest point, either way round: the least
        let starts = |seq: &[Coord]| (0..n).filter(|&i| seq[i] == lowest).map(|i| seq[i..].iter().chain(&seq[..=i]).copied().collect::<Vec<Coord>>()).collect::<Vec<_>>();
        let first = starts(&forward).into_iter().chain(starts(&backward)).min_by(|a, b| compare_points(a, b)).unwrap_or_else(|| ring.to_vec());
        Strip::Pass(first, half)
    }

    /// A single straight sweep from its lower end: flown either way, the same strip.
    fn line(mut points: Vec<Coord>, half: f64) -> Strip {
        if points.len() == 2 && compare_points(&points[1..], &points[..1]).is_lt() {
            points.reverse();
        }
        Strip::Line(points, half)
    }

    fn points(&self) -> &[Coord] {
        match self {
            Strip::Pass(p, _) | Strip::Line(p, _) => p,
        }
    }

    fn half(&self) -> f64 {
        match self {
            Strip::Pass(_, h) | Strip::Line(_, h) => *h,
        }
    }

    fn draw(&self) -> Vec<Polygon> {
        match self {
            Strip::Pass(ring, half) => {
                // the same ground as [`footprint`], faster on passes of thousands of short
                // segments (and the passes turn no tighter than the swath is wide, where `geo`'s
                // buffer errs)
                let style = BufferStyle::new(*half).line_cap(LineCap::Butt);
                LineString::from(ring.clone()).buffer_with_style(style).0
            }
            Strip::Line(line, half) => {
                let mut line = LineString::from(line.clone()).simplify(SWATH_TOLERANCE_M);
                line.0.dedup_by(|a, b| distance(*a, *b) < SWATH_TOLERANCE_M);
                if *half > 0.0 { footprint(&line.0, *half) } else { Vec::new() }
            }
        }
    }
}

/// Point sequences in lexicographic order of their coordinates.
fn compare_points(a: &[Coord], b: &[Coord]) -> std::cmp::Ordering {
    a.iter().zip(b).map(|(p, q)| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y))).find(|o| o.is_ne()).unwrap_or(a.len().cmp(&b.len()))
}

/// The swaths of `path`. Sweeps flown one after another (a spiral's rings, a grid path's runs)
/// are one polyline, straightened to within [`SWATH_TOLERANCE_M`] (offset curves come as
/// thousands of sub-millimetre segments) and measured by [`footprint`]; a ground vehicle's
/// headland passes cover the same ground, measured by their buffer.
fn sweep_strips(path: &FlightPath) -> Vec<Strip> {
    let mut strips = Vec::new();
    let pieces = &path.pieces;
    let mut i = 0;
    while i < pieces.len() {
        if pieces[i].kind == PieceKind::Headland {
            strips.push(Strip::pass(&pieces[i].points, pieces[i].half_swath_m));
            i += 1;
            continue;
        }
        if pieces[i].kind != PieceKind::Sweep {
            i += 1;
            continue;
        }
        let half = pieces[i].half_swath_m;
        let mut line = pieces[i].points.clone();
        i += 1;
        // joined sweeps only: a fleet's path runs one drone's flight after another's
        while let Some(next) = pieces.get(i).filter(|p| p.kind == PieceKind::Sweep && p.half_swath_m == half && line.last() == p.points.first()) {
            line.extend_from_slice(&next.points[1..]);
            i += 1;
        }
        strips.push(Strip::line(line, half));
    }
    strips
}

/// The union of the strips and their areas summed, whatever order they come in: drawn side
/// by side (a headland pass's buffer takes a millisecond) and joined in a canonical order, so
/// that the same strips always give the same polygons.
fn cover(mut strips: Vec<Strip>) -> (MultiPolygon, f64) {
    use rayon::prelude::*;
    strips.sort_by(|a, b| compare_points(a.points(), b.points()).then(a.half().total_cmp(&b.half())));
    let shapes: Vec<Polygon> = strips.par_iter().flat_map_iter(Strip::draw).collect();
    (union_of(&shapes), shapes.iter().map(|s| s.unsigned_area()).sum())
}

/// What [`swept_and_strip_area`] gives for a ground vehicle's path whose sweeps are `swaths`
/// and whose headland passes are `passes` (rings), in any order, direction and first point: for a
/// planner to measure beside its search for the order.
pub fn ground_swept(swaths: &[(Coord, Coord)], passes: &[Vec<Coord>], half: f64) -> (MultiPolygon, f64) {
    let lines = swaths.iter().map(|&(a, b)| Strip::line(vec![a, b], half));
    cover(passes.iter().map(|ring| Strip::pass(ring, half)).chain(lines).collect())
}

/// The union of `shapes` (empty without shapes).
fn union_of(shapes: &[Polygon]) -> MultiPolygon {
    if shapes.is_empty() { MultiPolygon(vec![]) } else { geo::unary_union(shapes) }
}

/// The area of `region` inside `union`, and the area of `union`.
fn under(union: &MultiPolygon, region: &MultiPolygon) -> (f64, f64) {
    if union.0.is_empty() {
        return (0.0, 0.0);
    }
    (region.intersection(union).unsigned_area(), union.unsigned_area())
}

/// The area of `region` inside the union of `shapes`, and the area of that union.
fn covered_by(shapes: &[Polygon], region: &MultiPolygon) -> (f64, f64) {
    under(&union_of(shapes), region)
}

/// The area of `region` under the swaths of `path`, in m²; with `photos` (a camera plan), under
/// what its photos image at least (see [`photographed`]).
pub fn covered_area(path: &FlightPath, region: &MultiPolygon, photos: bool) -> f64 {
    under(&covered(path, photos), region).0
}

/// The ground `path` covers: its swaths, or with `photos` what its photos image at least.
pub fn covered(path: &FlightPath, photos: bool) -> MultiPolygon {
    if photos { photographed(path) } else { swept(path) }
}

/// Pieces of uncovered ground smaller than this are rounding between swaths, not gaps.
const UNCOVERED_SLIVER_M2: f64 = 1.0;

/// The ground under the swaths of `path`: computed once per plan, since the union of many
/// strips is the costliest step of measuring it.
pub fn swept(path: &FlightPath) -> MultiPolygon {
    swept_and_strip_area(path).0
}

/// [`swept`], and the swaths' areas summed (ground swept twice counted twice), for
/// [`Stats::overlap_ratio`]: both from the same strips.
pub fn swept_and_strip_area(path: &FlightPath) -> (MultiPolygon, f64) {
    cover(sweep_strips(path))
}

/// The ground photos on the sweeps of `path` image at least: each sweep's own rectangle, as
/// photos fitted flush with a sweep's ends image it (camera §6), with nothing at the bends.
pub fn photographed(path: &FlightPath) -> MultiPolygon {
    let strips: Vec<Polygon> = path.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).filter_map(|p| swath(&p.points, p.half_swath_m)).collect();
    union_of(&strips)
}

/// The part of `target` outside `swept` (see [`swept`]): the clearance band around no-fly
/// zones, corners the lines do not reach. Slivers under a square metre are left out.
pub fn uncovered(swept: &MultiPolygon, target: &MultiPolygon) -> MultiPolygon {
    let rest = if swept.0.is_empty() { target.clone() } else { target.difference(swept) };
    MultiPolygon(rest.0.into_iter().filter(|p| p.unsigned_area() >= UNCOVERED_SLIVER_M2).collect())
}

/// Metres of `path` inside `zones`.
pub fn length_inside(path: &FlightPath, zones: &MultiPolygon) -> f64 {
    if zones.0.is_empty() {
        return 0.0;
    }
    let lines = MultiLineString(path.pieces.iter().map(|p| LineString::from(p.points.clone())).collect());
    // + 0.0 turns an empty sum's -0.0 into 0.0
    zones.clip(&lines, false).0.iter().map(|l| Euclidean.length(l)).sum::<f64>() + 0.0
}

pub struct MeasureInput<'a> {
    /// The whole flight: its sorties one after another.
    pub path: &'a FlightPath,
    pub sorties: &'a [FlightPath],
    /// One per sortie.
    pub estimates: &'a [PathEstimate],
    /// Energy one battery gives above its reserve, for each sortie (a fleet's drones differ).
    pub usable_j: &'a [f64],
    /// Batteries the flights need (see [`Stats::batteries_needed`]), counted per vehicle.
    pub batteries_needed: usize,
    pub region: &'a MultiPolygon,
    /// [`swept`] of `path`.
    pub swept: &'a MultiPolygon,
    /// The swaths' areas summed ([`swept_and_strip_area`]).
    pub strip_area_m2: f64,
    pub no_fly_zones: &'a MultiPolygon,
    pub spacing: f64,
    pub sweep_heading_deg: f64,
    pub cells: usize,
    pub photos: Option<(&'a [Photo], CameraPlan)>,
}

pub fn measure(m: &MeasureInput<'_>) -> Stats {
    // from +0: an empty sum is -0.0, which the stats would show as "-0.0"
    let by_kind = |k: PieceKind| m.path.pieces.iter().filter(|p| p.kind == k).fold(0.0, |sum, p| sum + p.length());
    let length_m = m.path.length();
    let energy_j: f64 = m.estimates.iter().map(PathEstimate::energy_j).sum();
    let area = m.region.unsigned_area();
    let lower_bound_m = area / m.spacing;
    let (covered, swept) = under(m.swept, m.region);
    let photo_coverage_ratio = m.photos.map(|(photos, cam)| {
        let imaged = photo_strips(photos, cam.footprint_across_m, cam.footprint_along_m);
        if area > 0.0 { (covered_by(&imaged, m.region).0 / area).min(1.0) } else { 0.0 }
    });
    Stats {
        length_m,
        sweep_length_m: by_kind(PieceKind::Sweep),
        turn_length_m: by_kind(PieceKind::Turn),
        transit_length_m: by_kind(PieceKind::Transit),
        duration_s: m.estimates.iter().map(PathEstimate::duration_s).sum(),
        energy_j,
        energy_wh: energy_j / 3600.0,
        takeoff_landing_energy_j: m.estimates.iter().map(|e| e.takeoff_landing_j).sum(),
        sorties: m.sorties.len(),
        sortie_totals: m
            .sorties
            .iter()
            .zip(m.estimates)
            .zip(m.usable_j)
            .enumerate()
            .map(|(k, ((s, e), usable_j))| SortieTotals {
                sortie: k + 1,
                vehicle: None,
                sweep_lines: s.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).count(),
                length_m: s.length(),
                duration_s: e.duration_s(),
                energy_j: e.energy_j(),
                battery_used: e.energy_j() / usable_j,
            })
            .collect(),
        batteries_needed: m.batteries_needed,
        warnings: Vec::new(),
        planner: String::new(),
        alternatives: Vec::new(),
        coverage_ratio: if area > 0.0 { (covered / area).min(1.0) } else { 0.0 },
        photo_coverage_ratio,
        overlap_ratio: if swept > 0.0 { (m.strip_area_m2 / swept - 1.0).max(0.0) } else { 0.0 },
        area_to_cover_m2: area,
        turns: m.path.pieces.iter().filter(|p| p.kind == PieceKind::Turn).count(),
        nfz_intrusion_m: length_inside(m.path, m.no_fly_zones),
        sweep_lines: m.path.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).count(),
        cells: m.cells,
        photos: m.photos.map_or(0, |(p, _)| p.len()),
        line_spacing_m: m.spacing,
        sweep_heading_deg: m.sweep_heading_deg,
        lower_bound_m,
        efficiency: if length_m > 0.0 { lower_bound_m / length_m } else { 0.0 },
        planning_time_ms: 0.0,
        lost_coverage_m: 0.0,
        optimality: None,
        makespan_s: None,
        vehicles: Vec::new(),
        conflicts: None,
        ground: None,
        inspection_coverage: None,
        inspection: None,
        terrain: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Contains, polygon};
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// A ground path's swept ground is the same whatever the order of its swaths and passes,
        /// the way each is driven and where each ring is entered: the ground that
        /// [`ground_swept`] measures without the order.
        #[test]
        fn ground_swept_ground_does_not_depend_on_order_direction_or_entry(
            swaths in prop::collection::vec((0.0..200.0f64, 0.0..200.0f64, 5.0..80.0f64), 1..12),
            rings in prop::collection::vec((20.0..180.0f64, 20.0..180.0f64, 5.0..30.0f64, 3usize..9), 1..4),
            entries in prop::collection::vec((any::<bool>(), 0usize..100), 4),
            reversed in prop::collection::vec(any::<bool>(), 12),
            shuffle in any::<u64>(),
        ) {
            let half = 3.0;
            let lines: Vec<(Coord, Coord)> = swaths.iter().map(|&(x, y, l)| (Coord { x, y }, Coord { x: x + l, y: y + 0.3 * l })).collect();
            let polygons: Vec<Vec<Coord>> = rings
                .iter()
                .map(|&(cx, cy, r, n)| {
                    let mut ring: Vec<Coord> = (0..n).map(|k| k as f64 * std::f64::consts::TAU / n as f64).map(|a| Coord { x: cx + r * a.cos(), y: cy + r * a.sin() }).collect();
                    ring.push(ring[0]);
                    ring
                })
                .collect();
            // the path: rings entered anywhere, either way round; swaths either way; all shuffled
            let mut pieces: Vec<(PieceKind, Vec<Coord>)> = Vec::new();
            for (k, ring) in polygons.iter().enumerate() {
                let (forward, at) = entries[k % entries.len()];
                let n = ring.len() - 1;
                let start = at % n;
                let points: Vec<Coord> = (0..=n).map(|j| if forward { ring[(start + j) % n] } else { ring[(start + n - j % n) % n] }).collect();
                pieces.push((PieceKind::Headland, points));
            }
            for (k, &(a, b)) in lines.iter().enumerate() {
                pieces.push((PieceKind::Sweep, if reversed[k] { vec![b, a] } else { vec![a, b] }));
            }
            let mut rng = crate::route::gtsp::Rng(shuffle | 1);
            for i in (1..pieces.len()).rev() {
                pieces.swap(i, rng.below(i + 1));
            }
            let mut path = FlightPath::default();
            let mut last: Option<Coord> = None;
            for (kind, points) in pieces {
                // a turn between pieces, as a plan has: sweeps are never joined
                if let Some(from) = last {
                    path.push(PieceKind::Turn, vec![from, Coord { x: from.x + 1.0, y: from.y - 1.0 }, points[0]], 0.0);
                }
                last = points.last().copied();
                path.push(kind, points, half);
            }
            let (swept, strips) = swept_and_strip_area(&path);
            let (measured, measured_strips) = ground_swept(&lines, &polygons, half);
            prop_assert!(swept == measured && strips == measured_strips, "{} m² against {} m²", swept.unsigned_area(), measured.unsigned_area());
        }
    }

    /// A ring flown as thousands of sub-millimetre sweeps under a swath wider than its radius
    /// (what an inset of a spiral looks like) is measured on its straightened centreline, and as
    /// flown: the swath turns with the vehicle, so the whole disc out to radius + half is swept.
    #[test]
    fn a_ring_of_tiny_sweeps_is_measured_on_its_straightened_centreline() {
        let (radius, half, steps) = (40.0, 58.0, 200_000);
        let at = |k: usize| {
            let a = k as f64 / steps as f64 * std::f64::consts::TAU;
            Coord { x: radius * a.cos(), y: radius * a.sin() }
        };
        let mut path = FlightPath::default();
        for k in 0..steps {
            path.push(PieceKind::Sweep, vec![at(k), at(k + 1)], half);
        }
        let expected = std::f64::consts::PI * (radius + half).powi(2);
        let swept = swept(&path).unsigned_area();
        assert!((swept - expected).abs() < 0.005 * expected, "{swept} m² swept, {expected} m² expected");
    }

    /// Two sweeps joined at a right angle: two rectangles, less the square where they overlap
    /// inside the bend, plus the quarter disc the swath sweeps outside it as the vehicle turns.
    #[test]
    fn a_bend_sweeps_a_fan_on_its_outside() {
        let half = 10.0;
        let mut path = FlightPath::default();
        path.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, Coord { x: 100.0, y: 0.0 }], half);
        path.push(PieceKind::Sweep, vec![Coord { x: 100.0, y: 0.0 }, Coord { x: 100.0, y: 100.0 }], half);
        let expected = 2.0 * 100.0 * 2.0 * half - half * half + std::f64::consts::PI * half * half / 4.0;
        let swept = swept(&path);
        assert!((swept.unsigned_area() - expected).abs() < 0.5, "{} m² swept, {expected} m² expected", swept.unsigned_area());
        // the fan lies outside the bend (below and right of the corner), not inside it
        assert!(swept.contains(&Coord { x: 105.0, y: -5.0 }) && !swept.contains(&Coord { x: 109.0, y: -9.0 }));
        // a right turn's fan too, on its own outside (above and right of the corner)
        let mut right = FlightPath::default();
        right.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, Coord { x: 100.0, y: 0.0 }], half);
        right.push(PieceKind::Sweep, vec![Coord { x: 100.0, y: 0.0 }, Coord { x: 100.0, y: -100.0 }], half);
        let right = super::swept(&right);
        assert!((right.unsigned_area() - expected).abs() < 0.5, "{} m² swept after a right turn", right.unsigned_area());
        assert!(right.contains(&Coord { x: 105.0, y: 5.0 }));
        // sweeps apart (a turn between them) are rectangles only
        let mut apart = FlightPath::default();
        apart.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, Coord { x: 100.0, y: 0.0 }], half);
        apart.push(PieceKind::Turn, vec![Coord { x: 100.0, y: 0.0 }, Coord { x: 100.0, y: 0.5 }], 0.0);
        apart.push(PieceKind::Sweep, vec![Coord { x: 100.0, y: 0.5 }, Coord { x: 100.0, y: 100.0 }], half);
        assert!(!super::swept(&apart).contains(&Coord { x: 105.0, y: -5.0 }));
    }

    #[test]
    fn coverage_and_intrusion_are_measured_on_the_geometry() {
        let c = |x, y| Coord { x, y };
        let region = MultiPolygon(vec![polygon![(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 20.), (x: 0., y: 20.)]]);
        let mut path = FlightPath::default();
        path.push(PieceKind::Sweep, vec![c(0.0, 5.0), c(100.0, 5.0)], 5.0);
        assert!((covered_area(&path, &region, false) - 1000.0).abs() < 1e-6);
        path.push(PieceKind::Turn, vec![c(100.0, 5.0), c(100.0, 15.0)], 0.0);
        path.push(PieceKind::Sweep, vec![c(100.0, 15.0), c(50.0, 15.0)], 5.0);
        assert!((covered_area(&path, &region, false) - 1500.0).abs() < 1e-6);
        let zone = MultiPolygon(vec![polygon![(x: 40., y: 0.), (x: 60., y: 0.), (x: 60., y: 10.), (x: 40., y: 10.)]]);
        assert!((length_inside(&path, &zone) - 20.0).abs() < 1e-9);
    }

    proptest! {
        /// Runs of photos along lines image the same ground as their footprints one by one.
        #[test]
        fn photo_strips_image_what_the_photos_do(
            lines in prop::collection::vec((0.0..std::f64::consts::TAU, -200.0..200.0f64, -200.0..200.0f64, 1usize..12, 0.2..1.0f64), 1..6),
            across in 5.0..60.0f64,
            along in 5.0..60.0f64,
        ) {
            let mut photos = Vec::new();
            for (heading, x, y, count, step) in lines {
                let (s, c) = heading.sin_cos();
                photos.extend((0..count).map(|k| Photo { at: Coord { x: x + c * k as f64 * step * along, y: y + s * k as f64 * step * along }, heading }));
            }
            let one_by_one: Vec<Polygon> = photos.iter().map(|p| photo_footprint(p, p, across, along)).collect();
            let strips = photo_strips(&photos, across, along);
            prop_assert!(strips.len() <= photos.len());
            let (a, b) = (union_of(&one_by_one).unsigned_area(), union_of(&strips).unsigned_area());
            prop_assert!((a - b).abs() <= 1e-6 * a.max(1.0), "{a} m² one by one, {b} m² as strips");
        }
    }
}
