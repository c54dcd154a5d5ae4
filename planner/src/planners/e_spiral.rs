//! E-Spiral (seed 002 §4.1, docs/methods.md, multirotor planners §1): rings that follow the field's
//! boundary inwards, one swath apart, so that corners are wide and a multirotor keeps much of
//! its speed through them. Each ring is the field inset by mitred offsets (the "inner
//! side-lines" of the thesis); a ring that splits becomes one spiral per part; what no ring
//! reaches because it is narrower than a swath (the middle, a strip) is flown along its centre
//! line, or round it where it bends. Rings are entered on an edge, so that every corner is a bend
//! the swath turns through; spurs then fly into the largest pieces still unswept (sharp corners,
//! the middle's ends) until 99.2 % is swept.
//!
//! Seed 002 states the method for areas without holes or inner no-fly zones; this planner
//! refuses those instead of flying into them.

use geo::algorithm::buffer::{BufferStyle, LineJoin};
use geo::orient::{Direction, Orient};
use geo::{
    Area, BooleanOps, Buffer, Contains, Coord, Distance, Euclidean, InteriorPoint, Line, LineString, MinimumRotatedRect, MultiLineString, MultiPolygon, Point, Polygon, Simplify,
};

use super::{PlannedPath, Planner, Problem, Progress, connect, no_sweep_lines};
use crate::error::{InputError, PlanError};
use crate::geom::distance;
use crate::metrics;
use crate::path::{FlightPath, PieceKind};
use crate::sweep::Footprint;
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

/// The longest piece inside `part` of its centre line: the long middle line of the smallest
/// rectangle round it, which sweeps all of a straight part narrower than a swath.
fn centre_line(part: &Polygon) -> Option<(Coord, Coord)> {
    let rect = part.minimum_rotated_rect()?;
    let c = &rect.exterior().0;
    let mid = |i: usize, j: usize| (c[i] + c[j]) / 2.0;
    let (from, to) = if distance(c[0], c[1]) >= distance(c[1], c[2]) { (mid(0, 3), mid(1, 2)) } else { (mid(0, 1), mid(2, 3)) };
    // a hair beyond the rectangle, so that the clipped line reaches the part's boundary
    let (from, to) = (from + (from - to) * 1e-6, to + (to - from) * 1e-6);
    let inside = part.clip(&MultiLineString::new(vec![LineString::new(vec![from, to])]), false);
    inside.0.iter().filter_map(|l| Some((*l.0.first()?, *l.0.last()?))).max_by(|a, b| distance(a.0, a.1).total_cmp(&distance(b.0, b.1)))
}

/// What a thin part's centre line may leave to the spurs, in swath squares (a ring corner's
/// kite at 60° is a sixth of one); a part that bends leaves more and is flown round.
const SPURS_SWEEP: f64 = 0.125;

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
        // insets bring vertices a hair apart (arcs of sub-millimetre segments, doubled mitred
        // corners): waypoints a flight file should not carry, and doubled again by every inset
        // inside (17 insets of a 10-gon grew it to 1 063 vertices and took a second)
        inset(area, d).0.into_iter().map(|p| p.simplify(RING_TOLERANCE_M)).filter(|p| !self.negligible(p)).collect()
    }

    /// The passes over `space`, ground no pass so far sweeps (at first a whole field), depth
    /// first: a ring round its inset by half a swath, then the ground inside that ring; or,
    /// where `space` is too thin for a ring (its middle), the pass of [`Layers::thin`].
    fn cover(&mut self, space: &Polygon) {
        if self.passes.len() >= MAX_PASSES {
            return;
        }
        let rings = self.inset(space, self.half);
        if rings.is_empty() {
            self.thin(space);
        }
        for ring in rings {
            self.push_ring(&ring);
            for inside in self.inset(&ring, self.half) {
                self.cover(&inside);
            }
        }
    }

    /// True for unswept ground left to the spurs, no more than a swath's square: a corner's
    /// kite. Larger pieces are strips no ring reaches (where a fleet's band is cut past a zone
    /// it notches), too long for a spur.
    fn spur_sized(&self, piece: &Polygon) -> bool {
        piece.unsigned_area() <= self.step * self.step
    }

    /// A pass over `part`, narrower than a swath: its centre line where that leaves no more
    /// than spurs sweep; else a ring round it a quarter swath in, which follows its bends and
    /// sweeps all of it (a bent middle, a fleet's band about a swath wide); else the line.
    fn thin(&mut self, part: &Polygon) {
        let line = centre_line(part);
        if let Some((a, b)) = line
            && part.difference(&LineString::new(vec![a, b]).buffer(self.half)).unsigned_area() <= SPURS_SWEEP * self.step * self.step
        {
            self.passes.push(Pass::Line(a, b));
            return;
        }
        let rings = self.inset(part, self.half / 2.0);
        if rings.is_empty() {
            self.passes.extend(line.map(|(a, b)| Pass::Line(a, b)));
        }
        rings.iter().for_each(|ring| self.push_ring(ring));
    }

    /// One pass round `ring`, without the rings inside it.
    fn push_ring(&mut self, ring: &Polygon) {
        let mut pts = ring.exterior().0.clone();
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
            // a line from its end nearer to where the last pass ended
            Pass::Line(a, b) if here.is_some_and(|h| distance(h, *b) < distance(h, *a)) => (None, vec![1, 0]),
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

/// The pieces of `unswept` without the slivers between swaths that touch (rounding, which
/// would join separate pieces into one).
fn opened(unswept: &MultiPolygon) -> impl Iterator<Item = Polygon> {
    unswept.buffer(-SLIVER_M).0.into_iter().flat_map(|p| p.buffer(SLIVER_M).0)
}

/// The ground `path` leaves unswept, in pieces of a square metre or more, largest first.
/// With a camera, what the photos image counts: the photo at each ring corner reaches over the
/// corner (see [`metrics::photo_positions`]).
fn unswept(path: &FlightPath, region: &MultiPolygon, camera: Option<Footprint>) -> Vec<Polygon> {
    let mut pieces: Vec<Polygon> = opened(&metrics::uncovered(&metrics::covered(path, camera), region)).filter(|p| p.unsigned_area() >= 1.0).collect();
    pieces.sort_by(|a, b| b.unsigned_area().total_cmp(&a.unsigned_area()));
    pieces
}

/// How far short of a piece's far corner a spur stops, so that it stays inside the area.
const SPUR_CLEARANCE_M: f64 = 0.05;

/// Spurs into `pieces`, the ground the passes leave unswept (largest first): beyond each ring
/// corner of interior angle θ, the kite between the field's edges and the two swath ends
/// (half²·cot(θ/2)) less the fan the swath sweeps as the vehicle turns, large only at sharp
/// corners; and the middle's ends.
/// A spur from the pass vertex nearest to a piece out to the piece's far corner sweeps it (the
/// kite lies within half a swath of the line from the ring's vertex to the field's corner).
fn corner_spurs(passes: &[Pass], pieces: &[Polygon], region: &MultiPolygon) -> Vec<Spur> {
    let target = region.unsigned_area();
    let mut left: f64 = pieces.iter().map(Area::unsigned_area).sum();
    let mut spurs = Vec::new();
    for piece in pieces {
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
        // the far corner, or where the spur to it is not inside the area (it runs along the
        // area's edge, from a pass that ends on that edge: a fleet's band), a point pulled
        // towards the piece's inside
        let inside = piece.interior_point().map_or(far, |p| p.0);
        let spur = SPUR_PULLS.iter().map(|&s| far + (inside - far) * s).find_map(|aim| {
            let reach = distance(at, aim);
            let along = |d: f64| at + (aim - at) * (d / reach);
            // checked from a hair past the vertex, which lies on the edge where a pass ends there
            let clear = reach > 2.0 * SPUR_CLEARANCE_M && region.0.iter().any(|p| p.contains(&Line::new(along(SPUR_CLEARANCE_M), along(reach - SPUR_CLEARANCE_M))));
            clear.then(|| along(reach - SPUR_CLEARANCE_M))
        });
        if let Some(tip) = spur {
            spurs.push(Spur { pass, vertex, tip });
            left -= piece.unsigned_area();
        }
    }
    spurs
}

/// Where a spur may aim, as shares of the way from a piece's far corner towards its inside: the
/// corner first; a spur along the area's edge is not inside it and sweeps half its swath outside.
const SPUR_PULLS: [f64; 3] = [0.0, 0.25, 0.5];

impl Planner for ESpiral {
    fn lays_parallel_lines(&self) -> bool {
        false
    }
    fn id(&self) -> &'static str {
        "e_spiral"
    }

    fn name(&self) -> &'static str {
        "Energy-aware spiral (E-Spiral)"
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
            layers.cover(field);
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
        let camera = problem.layout.photographed();
        let mut spurs = Vec::new();
        let mut path = fly(&layers.passes, &spurs, problem, half)?;
        let (strips, mut pieces): (Vec<Polygon>, Vec<Polygon>) = unswept(&path, problem.region, camera).into_iter().partition(|p| !layers.spur_sized(p));
        if !strips.is_empty() {
            strips.iter().for_each(|strip| layers.thin(strip));
            path = fly(&layers.passes, &spurs, problem, half)?;
            pieces = unswept(&path, problem.region, camera);
        }
        // a spur may sweep less than the piece it aims at: measured again, up to a few rounds
        for round in 1..=SPUR_ROUNDS {
            let more = corner_spurs(&layers.passes, &pieces, problem.region);
            if more.is_empty() {
                break;
            }
            spurs.extend(more);
            path = fly(&layers.passes, &spurs, problem, half)?;
            if !progress.report(0.4 + 0.5 * round as f64 / SPUR_ROUNDS as f64) {
                return Err(PlanError::Cancelled);
            }
            if round < SPUR_ROUNDS {
                pieces = unswept(&path, problem.region, camera);
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
        layers.cover(&square);
        let rings: Vec<&Vec<Coord>> = layers.passes.iter().filter_map(|p| if let Pass::Ring(r) = p { Some(r) } else { None }).collect();
        // insets 10, 30 and 50 − ε: rings of side 80, 40 and none (the centre is a point)
        assert_eq!(rings.len(), 2);
        let side = |r: &Vec<Coord>| distance(r[0], r[1]);
        assert!((side(rings[0]) - 80.0).abs() < 1e-6 && (side(rings[1]) - 40.0).abs() < 1e-6);
        assert!(layers.passes.iter().filter(|p| matches!(p, Pass::Line(..))).count() <= 1);
    }

    /// The ground the passes' swaths sweep, spurs aside.
    fn swept(layers: &Layers) -> MultiPolygon {
        let lines = layers.passes.iter().map(|p| match p {
            Pass::Ring(r) => LineString::new(r.iter().chain(r.first()).copied().collect()),
            Pass::Line(a, b) => LineString::new(vec![*a, *b]),
        });
        geo::MultiLineString::new(lines.collect()).buffer(layers.half)
    }

    fn unswept_m2(area: &Polygon, layers: &Layers) -> f64 {
        area.difference(&swept(layers)).unsigned_area()
    }

    /// A fleet's band about a swath wide with slanted ends: its centre line ends on the band's
    /// edge, and spurs into the corners beside those ends, inside the band, bring it to the
    /// coverage goal. The line's end lies on the edge (or a hair outside), and a spur from it to
    /// a corner's far vertex runs along the edge: both were refused as not inside the band,
    /// 0.988 coverage in the fleet property test.
    #[test]
    fn spurs_reach_the_corners_beside_a_line_that_ends_on_the_edge() {
        for slant in [1.2, 1.4, 1.6, 1.8] {
            let band = polygon![(x: 0., y: 0.), (x: 80., y: 0.), (x: 80. + 18. * slant, y: 18.), (x: 18. * slant, y: 18.)];
            let mut layers = Layers { step: 20.0, half: 10.0, passes: Vec::new() };
            layers.cover(&band);
            assert!(matches!(layers.passes[..], [Pass::Line(..)]), "slant {slant}: one line down the band");
            let goal = (1.0 - COVERAGE_GOAL) * band.unsigned_area();
            let mut swath = swept(&layers);
            let pieces: Vec<Polygon> = band.difference(&swath).0.into_iter().filter(|p| p.unsigned_area() >= 1.0).collect();
            assert!(pieces.iter().map(Area::unsigned_area).sum::<f64>() > goal, "slant {slant}: the line alone reaches the goal");
            let spurs = corner_spurs(&layers.passes, &pieces, &MultiPolygon(vec![band.clone()]));
            for spur in &spurs {
                let leg = LineString::new(vec![layers.passes[spur.pass].vertex(spur.vertex), spur.tip]);
                assert!(band.buffer(0.01).contains(&leg), "slant {slant}: a spur leaves the band");
                swath = swath.union(&leg.buffer(10.0));
            }
            let left = band.difference(&swath).unsigned_area();
            assert!(left <= goal, "slant {slant}: {left:.1} m² left unswept after {} spurs, goal {goal:.1} m²", spurs.len());
        }
    }

    #[test]
    fn a_thin_part_is_flown_along_its_centre_or_round_where_it_bends() {
        // a straight strip 15 m wide, swath 20 m: one line down its middle sweeps it
        let strip = polygon![(x: 0., y: 0.), (x: 200., y: 0.), (x: 200., y: 15.), (x: 0., y: 15.)];
        let mut layers = Layers { step: 20.0, half: 10.0, passes: Vec::new() };
        layers.cover(&strip);
        assert!(matches!(layers.passes[..], [Pass::Line(a, b)] if (a.y - 7.5).abs() < 1e-6 && (b.y - 7.5).abs() < 1e-6));
        assert!(unswept_m2(&strip, &layers) < 1e-3);
        // a quarter of a ring 15 m wide: no straight line sweeps it, one pass round it does
        let arc = |r: f64| (0..=32).map(move |k| (k as f64 / 32.0 * std::f64::consts::FRAC_PI_2).sin_cos()).map(move |(s, c)| Coord { x: r * c, y: r * s });
        let bend = Polygon::new(LineString::new(arc(100.0).chain(arc(115.0).collect::<Vec<_>>().into_iter().rev()).collect()), vec![]);
        let mut layers = Layers { step: 20.0, half: 10.0, passes: Vec::new() };
        layers.cover(&bend);
        assert!(matches!(layers.passes[..], [Pass::Ring(_)]));
        assert!(unswept_m2(&bend, &layers) < 1e-3 * bend.unsigned_area(), "{} m² unswept", unswept_m2(&bend, &layers));
    }
}
