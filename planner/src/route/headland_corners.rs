//! Corners of the headland passes (docs/methods.md, ground §1b). A pass's ring is rounded to the
//! turning radius, so a corner sharper than the vehicle turns is cut by an arc and the ground
//! between the arc and the corner is left. A vehicle that may reverse works the corner as
//! drivers do: on along the pass into the corner until its swath reaches the corner's mitre
//! (or the field's edge stops it), back out by the shortest manoeuvre that stays in the
//! headland (driven without working), and on along the next edge from as far back.
//!
//! A forward-only vehicle keeps the arc: to reach within half a swath of a right angle's corner
//! point its centre must run on an arc tangent to both edges, along the field's very edge, with
//! half its swath outside the field (§1b works this out).
//!
//! A corner is worked where that covers at least [`MIN_GAIN_M2`] more of the pass's own band
//! (its edges with mitred corners) than the arc, and at least [`M2_PER_EXTRA_M`] per metre
//! more driven.

use geo::algorithm::buffer::{BufferStyle, LineCap};
use geo::{Area, BooleanOps, Buffer, Coord, LineString, MultiPolygon};

use super::headland_route::HeadlandRoutes;
use crate::geom::{distance, heading, polyline_length, unit};
use crate::turn::dubins::Pose;

/// Least gain in worked ground for a corner manoeuvre to be driven.
const MIN_GAIN_M2: f64 = 2.0;
/// Ground each metre more of driving must gain.
const M2_PER_EXTRA_M: f64 = 0.1;
/// Corners turning less than this lose next to nothing to the arc (a 20° corner rounded on
/// 7 m leaves 0.1 m² of a 6 m swath).
const MIN_DEFLECTION: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// Corners turning more than this are hairpins: their mitre lies far out, beyond any field.
const MAX_DEFLECTION: f64 = 150.0 * std::f64::consts::PI / 180.0;
/// The radii, as shares of the rounding radius, of the circles through an arc's vertices.
const ARC_RADII: std::ops::Range<f64> = 0.8..1.3;
/// How far from the field's edge (or a hole's) a driven corner stops, in metres.
const EDGE_MARGIN_M: f64 = 0.1;

/// A headland pass as the vehicle drives it: a closed ring (first point repeated last), parts
/// of which may be corner manoeuvres driven without working.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PassRing {
    pub points: Vec<Coord>,
    /// Index ranges `[from, to]` of `points` driven idle, in order; none wraps past the end.
    pub idle: Vec<(usize, usize)>,
}

impl PassRing {
    /// A ring driven as it is, worked all round.
    pub fn plain(points: Vec<Coord>) -> Self {
        PassRing { points, idle: Vec::new() }
    }

    /// Whether the leg between vertices `u` and `w` (neighbours) is driven idle.
    pub fn is_idle(&self, u: usize, w: usize) -> bool {
        let (lo, hi) = (u.min(w), u.max(w));
        self.idle.iter().any(|&(from, to)| from <= lo && hi <= to)
    }

    /// Whether the vehicle may join the ring at vertex `i`: not inside a manoeuvre.
    pub fn may_enter_at(&self, i: usize) -> bool {
        self.idle.iter().all(|&(from, to)| i < from || i > to)
    }

    /// The worked stretches: the closed ring when nothing is idle, else the open polylines
    /// between the manoeuvres.
    pub fn worked(&self) -> Vec<Vec<Coord>> {
        if self.idle.is_empty() {
            return vec![self.points.clone()];
        }
        let n = self.points.len() - 1;
        let mut out: Vec<Vec<Coord>> = self.idle.windows(2).map(|w| self.points[w[0].1..=w[1].0].to_vec()).collect();
        // from the last manoeuvre round past the ring's start to the first
        let (first, last) = (self.idle[0].0, self.idle[self.idle.len() - 1].1);
        out.push(self.points[last..n].iter().chain(&self.points[..=first]).copied().collect());
        out.retain(|s| s.len() >= 2);
        out
    }
}

/// A rounded corner of a ring: the arc between vertices `first` and `last`, the straight edges
/// it joins meeting at `corner`, leaving `first` along `d_in` and reaching `last` along
/// `d_out`, turning by `deflection` (signed, counter-clockwise positive).
#[derive(Debug, Clone, Copy)]
struct Arc {
    first: usize,
    last: usize,
    corner: Coord,
    d_in: Coord,
    d_out: Coord,
    deflection: f64,
}

/// A corner as driven: between the ring's vertices `begin` and `resume` (the arc's ends), the
/// `manoeuvre` from the tip of one edge to the tip of the next, driven without working.
struct Worked {
    begin: usize,
    resume: usize,
    manoeuvre: Vec<Coord>,
}

/// `ring` (closed, rounded on `radius`) with its corners worked where the vehicle of `routes`
/// can, for a swath `half` wide each side.
pub fn work_corners(ring: &[Coord], routes: &HeadlandRoutes, radius: f64, half: f64) -> PassRing {
    let n = ring.len().saturating_sub(1);
    if !routes.reverses() {
        return PassRing::plain(ring.to_vec());
    }
    let corners: Vec<Worked> = arcs(ring, radius).iter().filter_map(|arc| work_corner(ring, arc, routes, half)).collect();
    let span = |w: &Worked| (w.resume + n - w.begin) % n;
    // start where no corner is driven (one's ends will do): none then wraps past the ring's end
    let inside = |j: usize| corners.iter().any(|w| (1..span(w)).contains(&((j + n - w.begin) % n)));
    let Some(start) = (0..n).find(|&j| !inside(j)).filter(|_| !corners.is_empty()) else { return PassRing::plain(ring.to_vec()) };
    let mut out = PassRing::default();
    let mut k = 0;
    while k < n {
        let j = (start + k) % n;
        out.points.push(ring[j]);
        // a corner overlapping the one before is left rounded
        match corners.iter().find(|w| w.begin == j && k + span(w) <= n) {
            Some(w) => {
                out.idle.push((out.points.len(), out.points.len() + w.manoeuvre.len() - 1));
                out.points.extend_from_slice(&w.manoeuvre);
                k += span(w);
            }
            None => k += 1,
        }
    }
    out.points.push(out.points[0]);
    out
}

/// The rounded corners of `ring`: runs of vertices turning one way on about the rounding
/// `radius` (a buffer's arcs are polygons, their vertices a few per cent off the circle).
fn arcs(ring: &[Coord], radius: f64) -> Vec<Arc> {
    let n = ring.len().saturating_sub(1);
    if n < 4 {
        return Vec::new();
    }
    let at = |j: usize| ring[j % n];
    // each vertex's turning sign where the circle through it and its neighbours is the rounding's
    let on_arc: Vec<Option<f64>> = (0..n)
        .map(|j| {
            let (a, b, c) = (at(j + n - 1), at(j), at(j + 1));
            let r = distance(circumcentre(a, b, c)?, b);
            let turn = crate::geom::cross(a, b, c);
            (ARC_RADII.contains(&(r / radius)) && turn != 0.0).then_some(turn.signum())
        })
        .collect();
    let same = |i: usize, j: usize| matches!((on_arc[i % n], on_arc[j % n]), (Some(a), Some(b)) if a == b);
    let mut out = Vec::new();
    // a run starts where the vertex before is not on the same arc
    for j in (0..n).filter(|&j| on_arc[j].is_some() && !same(j + n - 1, j)) {
        let mut end = j;
        while end < j + n - 3 && same(end, end + 1) {
            end += 1;
        }
        // the arc's ends, and the edges it joins: the legs before and after it
        let (first, last) = ((j + n - 1) % n, (end + 1) % n);
        let (d_in, d_out) = (unit(at(first + n - 1), ring[first]), unit(ring[last], at(last + 1)));
        let deflection = (d_in.x * d_out.y - d_in.y * d_out.x).atan2(d_in.x * d_out.x + d_in.y * d_out.y);
        if !(MIN_DEFLECTION..=MAX_DEFLECTION).contains(&deflection.abs()) {
            continue;
        }
        // where the two edges meet
        let denom = d_in.x * d_out.y - d_in.y * d_out.x;
        let q = ring[last] - ring[first];
        let t = (q.x * d_out.y - q.y * d_out.x) / denom;
        if t <= 0.0 || t > 4.0 * radius {
            continue;
        }
        out.push(Arc { first, last, corner: ring[first] + d_in * t, d_in, d_out, deflection });
    }
    out
}

/// The centre of the circle through three points (`None` when they are in line).
fn circumcentre(a: Coord, b: Coord, c: Coord) -> Option<Coord> {
    let (b, c) = (b - a, c - a);
    let d = 2.0 * (b.x * c.y - b.y * c.x);
    if d.abs() < 1e-12 {
        return None;
    }
    let (bb, cc) = (b.x * b.x + b.y * b.y, c.x * c.x + c.y * c.y);
    Some(a + Coord { x: (c.y * bb - b.y * cc) / d, y: (b.x * cc - c.x * bb) / d })
}

/// How a vehicle that may reverse works `arc`'s corner: on along the edge into it, back out
/// idle, on from as far back along the next edge; `None` where that gains too little.
fn work_corner(ring: &[Coord], arc: &Arc, routes: &HeadlandRoutes, half: f64) -> Option<Worked> {
    let n = ring.len() - 1;
    let (t1, t2) = (ring[arc.first], ring[arc.last]);
    // the pass's own band at the corner: its two edges' swaths run on to the corner's mitre
    let mitre = half * (arc.deflection.abs() / 2.0).tan();
    let band = strip(&[t1, arc.corner + arc.d_in * mitre], half).union(&strip(&[arc.corner - arc.d_out * mitre, t2], half));
    let rounded: Vec<Coord> = (0..=(arc.last + n - arc.first) % n).map(|k| ring[(arc.first + k) % n]).collect();
    // how far past the corner each edge may run: to the mitre, stopped short of the field's edge
    let tip_in = arc.corner + arc.d_in * room(routes, t1, arc.corner, arc.d_in, mitre)?;
    let tip_out = arc.corner - arc.d_out * room(routes, t2, arc.corner, -arc.d_out, mitre)?;
    let pose = |p: Coord, d: Coord| Pose::at(p, heading(Coord { x: 0.0, y: 0.0 }, d));
    let way = routes.corner_way(pose(tip_in, arc.d_in), pose(tip_out, arc.d_out))?;
    let worked = strip(&[t1, tip_in], half).union(&strip(&[tip_out, t2], half));
    let gain = worked.intersection(&band).unsigned_area() - strip(&rounded, half).intersection(&band).unsigned_area();
    let extra_m = distance(t1, tip_in) + polyline_length(&way) + distance(tip_out, t2) - polyline_length(&rounded);
    if gain < MIN_GAIN_M2 || gain < M2_PER_EXTRA_M * extra_m {
        return None;
    }
    Some(Worked { begin: arc.first, resume: arc.last, manoeuvre: dedup(way) })
}

/// How far past `corner` along `d` (from `from`, on the same line) the vehicle may drive, up to
/// `wanted`, stopping [`EDGE_MARGIN_M`] short of the field's or a hole's edge (to a centimetre);
/// `None` where the corner itself lies beyond the headland (a pass round a small pond, rounded
/// all round).
fn room(routes: &HeadlandRoutes, from: Coord, corner: Coord, d: Coord, wanted: f64) -> Option<f64> {
    let fits = |e: f64| routes.keeps_to_headland(&[from, corner + d * (e + EDGE_MARGIN_M)]);
    if fits(wanted) {
        return Some(wanted);
    }
    if !fits(0.0) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, wanted);
    while hi - lo > 0.01 {
        let mid = (lo + hi) / 2.0;
        if fits(mid) { lo = mid } else { hi = mid }
    }
    Some(lo)
}

/// The ground a swath `half` wide each side covers along `points`, square at its ends.
fn strip(points: &[Coord], half: f64) -> MultiPolygon {
    if points.len() < 2 || polyline_length(points) == 0.0 {
        return MultiPolygon(vec![]);
    }
    LineString::from(points.to_vec()).buffer_with_style(BufferStyle::new(half).line_cap(LineCap::Butt))
}

/// `points` without repeats of the point before.
fn dedup(mut points: Vec<Coord>) -> Vec<Coord> {
    points.dedup_by(|a, b| distance(*a, *b) < 1e-9);
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decompose::headland::headland;
    use crate::turn::ground::Steering;
    use geo::{MultiPolygon, polygon};

    /// A 120 m by 80 m field's outer pass (3 m in, 6 m swaths, rounded on 7 m) and its routes.
    fn square(reverse: bool) -> (MultiPolygon, Vec<Coord>, HeadlandRoutes) {
        let field = MultiPolygon(vec![polygon![(x: 0.0, y: 0.0), (x: 120.0, y: 0.0), (x: 120.0, y: 80.0), (x: 0.0, y: 80.0)]]);
        let h = headland(&field, 12.0, 2, 7.0);
        let rings: Vec<Vec<Coord>> = h.passes.iter().flatten().cloned().collect();
        let routes = HeadlandRoutes::new(&field, &h.mainland, &rings, Steering::new(7.0, reverse, None), 12.0);
        (field, h.passes[0][0].clone(), routes)
    }

    /// The ground of the outer 6 m band that `pass` works.
    fn covered(pass: &PassRing, field: &MultiPolygon) -> f64 {
        let band = field.difference(&MultiPolygon(vec![polygon![(x: 6.0, y: 6.0), (x: 114.0, y: 6.0), (x: 114.0, y: 74.0), (x: 6.0, y: 74.0)]]));
        let strips = pass.worked().iter().map(|s| strip(s, 3.0)).fold(MultiPolygon(vec![]), |a, b| a.union(&b));
        strips.intersection(&band).unsigned_area()
    }

    #[test]
    fn a_rectangles_four_rounded_corners_are_found_at_its_pass_corners() {
        let (_, ring, _) = square(true);
        let arcs = arcs(&ring, 7.0);
        assert_eq!(arcs.len(), 4, "{arcs:?}");
        for arc in &arcs {
            assert!((arc.deflection.abs() - std::f64::consts::FRAC_PI_2).abs() < 0.02, "{arc:?}");
            let near = [(3.0, 3.0), (117.0, 3.0), (117.0, 77.0), (3.0, 77.0)].iter().any(|&(x, y)| distance(arc.corner, Coord { x, y }) < 0.05);
            assert!(near, "{arc:?}");
        }
    }

    #[test]
    fn a_reversing_vehicle_works_each_corner_by_a_manoeuvre_driven_idle() {
        let (field, ring, routes) = square(true);
        let plain = PassRing::plain(ring.clone());
        let worked = work_corners(&ring, &routes, 7.0, 3.0);
        assert_eq!(worked.idle.len(), 4);
        // the outer 6 m band is 120 × 80 − 108 × 68; the rounded ring leaves 4 × (10² − π 10² / 4)
        let band = 120.0 * 80.0 - 108.0 * 68.0;
        let left = |pass: &PassRing| band - covered(pass, &field);
        // (the arcs are polygons a little inside the circle)
        assert!((left(&plain) - 4.0 * 100.0 * (1.0 - std::f64::consts::FRAC_PI_4)).abs() < 5.0, "{}", left(&plain));
        // a right angle's mitre is reached 0.1 m short of the edge: 0.1 m squares left
        assert!(left(&worked) < 4.0 * 0.05, "{}", left(&worked));
        // every corner's manoeuvre stays in the field and starts and ends on the pass
        for &(from, to) in &worked.idle {
            assert!(routes.keeps_to_headland(&worked.points[from..=to]));
        }
        assert_eq!(worked.points.first(), worked.points.last());
    }

    #[test]
    fn a_forward_only_vehicle_keeps_the_rounded_corners() {
        let (_, ring, routes) = square(false);
        assert_eq!(work_corners(&ring, &routes, 7.0, 3.0), PassRing::plain(ring));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// On star-shaped fields with a square pond, a reversing vehicle's corners: each
        /// manoeuvre and the legs into and out of it keep to the headland, and the passes cover
        /// at least as much of the headland as the arcs did (how tight the manoeuvres turn is
        /// checked with the plans, in `tests/sweeps/ground_plans.rs`).
        #[test]
        fn worked_corners_keep_to_the_headland_and_cover_at_least_the_arcs(
            radii in proptest::collection::vec(70.0..160.0f64, 5..9),
            pond in proptest::option::of((-25.0..25.0f64, -25.0..25.0f64, 6.0..20.0f64)),
            radius in 4.0..9.0f64,
            width in 4.0..8.0f64,
        ) {
            use geo::{LineString, Polygon};
            let n = radii.len();
            let mut edge: Vec<Coord> = radii.iter().enumerate().map(|(k, r)| {
                let a = k as f64 * std::f64::consts::TAU / n as f64;
                Coord { x: r * a.cos(), y: r * a.sin() }
            }).collect();
            edge.push(edge[0]);
            let ponds = pond.map(|(x, y, s)| LineString::from(vec![(x, y), (x + s, y), (x + s, y + s), (x, y + s), (x, y)])).into_iter().collect();
            let field = MultiPolygon(vec![Polygon::new(LineString::from(edge), ponds)]);
            let h = headland(&field, 2.0 * width, 2, radius);
            proptest::prop_assume!(!h.mainland.0.is_empty());
            let rings: Vec<Vec<Coord>> = h.passes.iter().flatten().cloned().collect();
            let routes = HeadlandRoutes::new(&field, &h.mainland, &rings, Steering::new(radius, true, None), 2.0 * width);
            let half = width / 2.0;
            let cover = |stretches: &[Vec<Coord>]| stretches.iter().map(|s| strip(s, half)).fold(MultiPolygon(vec![]), |a, b| a.union(&b)).intersection(&h.band).unsigned_area();
            let mut worked = Vec::new();
            for ring in &rings {
                let pass = work_corners(ring, &routes, radius, half);
                proptest::prop_assert_eq!(pass.points.first(), pass.points.last());
                for &(a, b) in &pass.idle {
                    proptest::prop_assert!(a > 0 && b + 1 < pass.points.len());
                    proptest::prop_assert!(routes.keeps_to_headland(&pass.points[a - 1..=b + 1]), "a corner leaves the headland at {:?}", pass.points[a]);
                }
                worked.extend(pass.worked());
            }
            let (with, without) = (cover(&worked), cover(&rings));
            proptest::prop_assert!(with >= without - 0.5, "the corners cover {with} m² of the headland, the arcs {without} m²");
        }
    }
}
