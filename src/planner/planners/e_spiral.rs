//! E-Spiral (seed 002 §4.1, docs/methods.md, multirotor planners §1): rings that follow the field's
//! boundary inwards, one swath apart, so that corners are wide and a multirotor keeps much of
//! its speed through them. Each ring is the field inset by mitred offsets (the "inner
//! side-lines" of the thesis); a ring that splits becomes one spiral per part; what the last
//! ring leaves in the middle is covered by its longest line that stays inside. Rings are entered
//! on an edge, so that every corner is a bend the swath turns through; spurs then fly into the
//! largest pieces still unswept (sharp corners, the middle's ends) until 99.2 % is swept.
//!
//! Seed 002 states the method for areas without holes or inner no-fly zones; this planner
//! refuses those instead of flying into them.

use geo::algorithm::buffer::{BufferStyle, LineJoin};
use geo::orient::{Direction, Orient};
use geo::{Area, Buffer, Contains, Coord, Distance, Euclidean, Line, MultiPolygon, Point, Polygon, Simplify};

use super::{PlannedPath, Planner, Problem, Progress, connect, no_sweep_lines};
use crate::error::{InputError, PlanError};
use crate::geom::distance;
use crate::metrics;
use crate::path::{FlightPath, PieceKind};
use crate::vehicle::VehicleKind;

pub struct ESpiral;

/// One pass of the spiral: a closed ring, or the line through the middle.
enum Pass {
    Ring(Vec<Coord>),
    Line(Coord, Coord),
}

impl Pass {
    fn len(&self) -> usize {
        match self {
            Pass::Ring(ring) => ring.len(),
            Pass::Line(..) => 2,
        }
    }

    fn vertex(&self, v: usize) -> Coord {
        match self {
            Pass::Ring(ring) => ring[v],
            Pass::Line(a, b) => [*a, *b][v],
        }
    }
}

/// Most rings one plan may have (a guard against absurd spacings; 2 000 km of sweep at 0.5 m).
const MAX_PASSES: usize = 20_000;

/// `area` shrunk by `d` with mitred corners, exteriors counter-clockwise.
fn inset(area: &Polygon, d: f64) -> MultiPolygon {
    let shrunk = area.buffer_with_style(BufferStyle::new(-d).line_join(LineJoin::Miter(4.0)));
    MultiPolygon(shrunk.0.into_iter().filter(|p| p.unsigned_area() > 1e-6).collect()).orient(Direction::Default)
}

/// The two vertices of `area` farthest apart whose line stays inside `within`, if any: the
/// middle of a concave field may bend, and its line must not cut across what it bends round.
fn longest_axis(area: &Polygon, within: &Polygon) -> Option<(Coord, Coord)> {
    let simple = area.simplify(AXIS_TOLERANCE_M);
    let pts = &simple.exterior().0;
    let mut best = None;
    let mut longest = 0.0;
    for (i, &a) in pts.iter().enumerate() {
        for &b in &pts[i + 1..] {
            let d = distance(a, b);
            if d > longest && within.contains(&Line::new(a, b)) {
                (best, longest) = (Some((a, b)), d);
            }
        }
    }
    best
}

/// How far a middle is straightened before its axis is sought (its vertices are tried in pairs).
const AXIS_TOLERANCE_M: f64 = 0.5;

struct Layers {
    step: f64,
    half: f64,
    passes: Vec<Pass>,
}

impl Layers {
    /// True for a sliver of an inset: less than a hundredth of a swath's square, nothing a
    /// ring or a line of its own should fly round.
    fn negligible(&self, part: &Polygon) -> bool {
        part.unsigned_area() <= 0.01 * self.step * self.step
    }

    /// The parts of `area` inset by `d` that are more than slivers.
    fn inset(&self, area: &Polygon, d: f64) -> Vec<Polygon> {
        inset(area, d).0.into_iter().filter(|p| !self.negligible(p)).collect()
    }

    /// The rings inside `flown` (a ring just flown) and their own inner rings, depth first.
    fn inside(&mut self, flown: &Polygon) {
        if self.passes.len() >= MAX_PASSES {
            return;
        }
        let next = inset(flown, self.step);
        if next.0.is_empty() {
            // the middle no ring reaches: one line along it
            for rest in self.inset(flown, self.half) {
                if let Some((a, b)) = longest_axis(&rest, flown) {
                    self.passes.push(Pass::Line(a, b));
                }
            }
            return;
        }
        for part in next.0 {
            self.ring(part);
        }
    }

    fn ring(&mut self, ring: Polygon) {
        self.push_ring(&ring);
        self.inside(&ring);
    }

    /// One pass round `ring`, without the rings inside it.
    fn push_ring(&mut self, ring: &Polygon) {
        // insets come with arcs of sub-millimetre segments: waypoints a flight file should not carry
        let mut pts = ring.exterior().simplify(RING_TOLERANCE_M).0;
        pts.pop(); // the closing point
        self.passes.push(Pass::Ring(pts));
    }
}

/// How far a ring may be straightened: a centimetre, nothing next to a swath.
const RING_TOLERANCE_M: f64 = 0.01;

/// A detour from a pass's vertex out to `tip` and back, into ground the passes leave unswept.
struct Spur {
    pass: usize,
    vertex: usize,
    tip: Coord,
}

/// Where to enter a ring from `here`: the point of the ring nearest to it, kept at least `half`
/// from the ring's vertices (a ring entered and left at a vertex would leave that corner
/// unswept), and the index of the edge it lies on.
fn entry(ring: &[Coord], here: Option<Coord>, half: f64) -> (usize, Coord) {
    let on_edge = |i: usize| {
        let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
        let len = distance(a, b);
        let keep = half.min(len / 2.0);
        let t = here.map_or(len / 2.0, |h| {
            let d = b - a;
            ((h - a).x * d.x + (h - a).y * d.y) / len.max(1e-12)
        });
        a + (b - a) * (t.clamp(keep, len - keep) / len.max(1e-12))
    };
    let Some(h) = here else { return (0, on_edge(0)) };
    (0..ring.len()).map(|i| (i, on_edge(i))).min_by(|x, y| distance(x.1, h).total_cmp(&distance(y.1, h))).expect("a ring has vertices")
}

/// The passes in order, with their spurs, joined by turns (a transit first, from the start).
fn fly(passes: &[Pass], spurs: &[Spur], problem: &Problem<'_>, half: f64) -> Result<FlightPath, PlanError> {
    let mut path = FlightPath::default();
    let mut here = problem.start;
    for (k, pass) in passes.iter().enumerate() {
        // the entry point on a ring's edge (where it is also left), and the vertices in order
        let (entry_point, order): (Option<Coord>, Vec<usize>) = match pass {
            Pass::Line(..) => (None, vec![0, 1]),
            Pass::Ring(ring) => {
                let (edge, at) = entry(ring, here, half);
                (Some(at), (edge + 1..ring.len()).chain(0..=edge).collect())
            }
        };
        let mut points: Vec<Coord> = entry_point.into_iter().collect();
        for v in order {
            let at = pass.vertex(v);
            points.push(at);
            for spur in spurs.iter().filter(|s| s.pass == k && s.vertex == v) {
                points.extend([spur.tip, at]);
            }
        }
        points.extend(entry_point);
        if let Some(h) = here {
            let kind = if path.pieces.is_empty() { PieceKind::Transit } else { PieceKind::Turn };
            connect(&mut path, kind, h, points[0], problem.transit)?;
        }
        for w in points.windows(2).filter(|w| distance(w[0], w[1]) > 1e-9) {
            path.push(PieceKind::Sweep, vec![w[0], w[1]], half);
        }
        here = path.end();
    }
    Ok(path)
}

/// Share of the area the spurs aim to leave swept at least: spurs go to the largest unswept
/// pieces first, until this much is swept. Each spur costs a stop (a kilojoule or more for a
/// small multirotor), so the goal sits just above the 99 % every planner must cover.
const COVERAGE_GOAL: f64 = 0.992;

/// Rounds of spurs at most: a second round finds what the first missed.
const SPUR_ROUNDS: usize = 3;

/// Unswept ground thinner than twice this is rounding between swaths that touch.
const SLIVER_M: f64 = 0.05;

/// How far short of a piece's far corner a spur stops, so that it stays inside the area.
const SPUR_CLEARANCE_M: f64 = 0.05;

/// Spurs into the ground `path` leaves unswept: beyond each ring corner of interior angle θ,
/// the kite between the field's edges and the two swath ends (half²·cot(θ/2)) less the fan the
/// swath sweeps as the vehicle turns, large only at sharp corners; and the middle's ends.
/// A spur from the pass vertex nearest to a piece out to the piece's far corner sweeps it (the
/// kite lies within half a swath of the line from the ring's vertex to the field's corner).
/// With a camera, what the photos image counts: their footprints stop flush with each sweep's
/// ends, so corners are measured without the turning swath.
fn corner_spurs(passes: &[Pass], path: &FlightPath, region: &MultiPolygon, camera: bool) -> Vec<Spur> {
    let target = region.unsigned_area();
    // thin slivers between swaths that touch would join the corners into one piece: opened
    let unswept = metrics::uncovered(&metrics::covered(path, camera), region).buffer(-SLIVER_M);
    let mut pieces: Vec<Polygon> = unswept.0.iter().flat_map(|p| p.buffer(SLIVER_M).0).filter(|p| p.unsigned_area() >= 1.0).collect();
    pieces.sort_by(|a, b| b.unsigned_area().total_cmp(&a.unsigned_area()));
    let mut left: f64 = pieces.iter().map(Area::unsigned_area).sum();
    let mut spurs = Vec::new();
    for piece in &pieces {
        if left <= (1.0 - COVERAGE_GOAL) * target {
            break;
        }
        let nearest = passes
            .iter()
            .enumerate()
            .flat_map(|(k, pass)| (0..pass.len()).map(move |v| (k, v, pass.vertex(v))))
            .map(|(k, v, at)| (k, v, at, Euclidean.distance(&Point::from(at), piece)))
            .min_by(|a, b| a.3.total_cmp(&b.3));
        let Some((pass, vertex, at, _)) = nearest else { break };
        let far = piece.exterior().0.iter().copied().max_by(|&a, &b| distance(a, at).total_cmp(&distance(b, at))).expect("a piece has vertices");
        let reach = distance(at, far);
        if reach <= SPUR_CLEARANCE_M {
            continue;
        }
        let tip = at + (far - at) * ((reach - SPUR_CLEARANCE_M) / reach);
        if region.0.iter().any(|p| p.contains(&Line::new(at, tip))) {
            spurs.push(Spur { pass, vertex, tip });
            left -= piece.unsigned_area();
        }
    }
    spurs
}

impl Planner for ESpiral {
    fn id(&self) -> &'static str {
        "e_spiral"
    }

    fn description(&self) -> &'static str {
        "Energy-aware spiral (seed 002 §4.1): rings along the boundary inwards, one swath apart, with wide corners \
         a multirotor flies without stopping; each leg at its energy-optimal speed. Multirotors; areas without holes \
         or inner no-fly zones."
    }

    fn direction_rule(&self) -> &'static str {
        "none: the rings follow the boundary"
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        if problem.vehicle.kind != VehicleKind::Multirotor {
            return Err(InputError::new("planner_not_applicable", "/vehicle/kind", "e_spiral is a multirotor planner: its corners are flown without a turning radius").into());
        }
        if problem.region.0.iter().any(|p| !p.interiors().is_empty()) {
            return Err(InputError::new(
                "planner_not_applicable",
                "/planner",
                "e_spiral covers areas without holes or no-fly zones inside them (seed 002 §4.1.4); use boustrophedon for this field",
            )
            .into());
        }
        let half = problem.layout.half_swath();
        let mut layers = Layers { step: problem.layout.spacing, half, passes: Vec::new() };
        for field in &problem.region.0 {
            let first = layers.inset(field, half);
            if !first.is_empty() {
                first.into_iter().for_each(|part| layers.ring(part));
                continue;
            }
            // a field about a swath wide (a fleet's strip, say) is flown round a quarter swath
            // in, which follows its bends; one straight line along it left the sides of a bent
            // strip unswept (20 % of one), and the slivers an inset leaves are no ring to fly
            let thin = layers.inset(field, half / 2.0);
            if thin.is_empty()
                && let Some((a, b)) = longest_axis(field, field)
            {
                layers.passes.push(Pass::Line(a, b));
            }
            thin.iter().for_each(|part| layers.push_ring(part));
        }
        if layers.passes.is_empty() {
            return Err(no_sweep_lines());
        }
        if layers.passes.len() >= MAX_PASSES {
            return Err(PlanError::Infeasible(format!("the spiral would need more than {MAX_PASSES} rings: use a wider spacing")));
        }
        if !progress.report(0.4) {
            return Err(PlanError::Cancelled);
        }
        let mut spurs = Vec::new();
        let mut path = fly(&layers.passes, &spurs, problem, half)?;
        // a spur may sweep less than the piece it aims at: measured again, up to a few rounds
        for round in 1..=SPUR_ROUNDS {
            let more = corner_spurs(&layers.passes, &path, problem.region, problem.layout.photographed());
            if more.is_empty() {
                break;
            }
            spurs.extend(more);
            path = fly(&layers.passes, &spurs, problem, half)?;
            if !progress.report(0.4 + 0.5 * round as f64 / SPUR_ROUNDS as f64) {
                return Err(PlanError::Cancelled);
            }
        }
        if let (Some(h), Some(end)) = (path.end().or(problem.start), problem.end) {
            connect(&mut path, PieceKind::Transit, h, end, problem.transit)?;
        }
        Ok(PlannedPath::new(path, 0.0, problem.region.0.len()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::polygon;

    #[test]
    fn rings_are_one_spacing_apart_and_end_in_a_middle_line() {
        let square = polygon![(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 100.), (x: 0., y: 100.)];
        let mut layers = Layers { step: 20.0, half: 10.0, passes: Vec::new() };
        for part in inset(&square, 10.0).0 {
            layers.ring(part);
        }
        let rings: Vec<&Vec<Coord>> = layers.passes.iter().filter_map(|p| if let Pass::Ring(r) = p { Some(r) } else { None }).collect();
        // insets 10, 30 and 50 − ε: rings of side 80, 40 and none (the centre is a point)
        assert_eq!(rings.len(), 2);
        let side = |r: &Vec<Coord>| distance(r[0], r[1]);
        assert!((side(rings[0]) - 80.0).abs() < 1e-6 && (side(rings[1]) - 40.0).abs() < 1e-6);
        assert!(layers.passes.iter().filter(|p| matches!(p, Pass::Line(..))).count() <= 1);
    }
}
