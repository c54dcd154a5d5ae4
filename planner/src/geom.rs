//! Small plane-geometry helpers on bare coordinates, shared by every stage.
//!
//! `geo` does the work on its own types (`Area`, `BoundingRect`, `Contains`, `Intersects`);
//! these are for the hot loops that hold open vertex lists (`&[Coord]`) and would otherwise
//! build a `LineString` per call.

use geo::algorithm::buffer::{BufferStyle, LineJoin};
use geo::{Buffer, Coord, MultiPolygon, Rect};
use rstar::{AABB, RTree, RTreeObject};

/// Euclidean distance between two points.
///
/// ```
/// use coverplan_planner::geo::Coord;
/// use coverplan_planner::geom::distance;
/// assert_eq!(distance(Coord { x: 0.0, y: 0.0 }, Coord { x: 3.0, y: 4.0 }), 5.0);
/// ```
pub fn distance(a: Coord, b: Coord) -> f64 {
    (a.x - b.x).hypot(a.y - b.y)
}

/// Length of a polyline.
pub fn polyline_length(points: &[Coord]) -> f64 {
    points.windows(2).map(|w| distance(w[0], w[1])).sum()
}

/// How far apart two axes are (radians, directions taken modulo π): at most π/2.
pub fn axial_difference(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::PI);
    d.min(std::f64::consts::PI - d)
}

/// Cross product of `a − o` and `b − o`: positive when `o → a → b` turns counter-clockwise.
pub fn cross(o: Coord, a: Coord, b: Coord) -> f64 {
    (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
}

/// The unit vector from `a` towards `b` (distinct points).
pub fn unit(a: Coord, b: Coord) -> Coord {
    let len = distance(a, b);
    Coord { x: (b.x - a.x) / len, y: (b.y - a.y) / len }
}

/// The direction from `a` to `b`, math radians.
pub fn heading(a: Coord, b: Coord) -> f64 {
    (b.y - a.y).atan2(b.x - a.x)
}

/// Where the lines through segments `a → b` and `c → d` cross, as fractions `(t, u)` along
/// each (0 at `a` or `c`, 1 at `b` or `d`); `None` for parallel segments.
pub fn segment_crossing(a: Coord, b: Coord, c: Coord, d: Coord) -> Option<(f64, f64)> {
    let (r, s) = (b - a, d - c);
    let denom = r.x * s.y - r.y * s.x;
    if denom.abs() <= 1e-12 * (r.x.hypot(r.y) * s.x.hypot(s.y)) {
        return None;
    }
    let q = c - a;
    Some(((q.x * s.y - q.y * s.x) / denom, (q.x * r.y - q.y * r.x) / denom))
}

/// Signed area of an open ring (no closing point): positive when counter-clockwise.
///
/// ```
/// use coverplan_planner::geo::Coord;
/// use coverplan_planner::geom::signed_area;
/// let square = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)].map(|(x, y)| Coord { x, y });
/// assert_eq!(signed_area(&square), 4.0);
/// ```
pub fn signed_area(ring: &[Coord]) -> f64 {
    let n = ring.len();
    let origin = Coord { x: 0.0, y: 0.0 };
    (0..n).map(|i| cross(origin, ring[i], ring[(i + 1) % n])).sum::<f64>() / 2.0
}

/// Bounding box of some points, `None` when there are none.
pub fn bounding(points: &[Coord]) -> Option<Rect> {
    let first = *points.first()?;
    let (lo, hi) = points.iter().fold((first, first), |(lo, hi), c| (Coord { x: lo.x.min(c.x), y: lo.y.min(c.y) }, Coord { x: hi.x.max(c.x), y: hi.y.max(c.y) }));
    Some(Rect::new(lo, hi))
}

/// Crossing-number test of `p` against a closed ring; points on the boundary may go either way.
pub fn point_in_ring(p: Coord, ring: &[Coord]) -> bool {
    let mut inside = false;
    for w in ring.windows(2) {
        let (a, b) = (w[0], w[1]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            inside = !inside;
        }
    }
    inside
}

/// Grows the zones by `d` metres with mitred corners (no more vertices than the input).
pub fn grow(zones: &MultiPolygon, d: f64) -> MultiPolygon {
    if zones.0.is_empty() {
        return MultiPolygon(vec![]);
    }
    zones.buffer_with_style(BufferStyle::new(d).line_join(LineJoin::Miter(2.0)))
}

/// An edge of an area's boundary.
struct Edge(Coord, Coord);

impl RTreeObject for Edge {
    type Envelope = AABB<[f64; 2]>;
    fn envelope(&self) -> Self::Envelope {
        AABB::from_corners([self.0.x, self.0.y], [self.1.x, self.1.y])
    }
}

/// The edges of an area's boundary in an R-tree: what a path inside the area may not cross.
pub struct EdgeIndex(RTree<Edge>);

impl EdgeIndex {
    pub fn new(area: &MultiPolygon) -> Self {
        let edges = area.iter().flat_map(|p| std::iter::once(p.exterior()).chain(p.interiors())).flat_map(|ring| ring.0.windows(2).map(|w| Edge(w[0], w[1]))).collect();
        EdgeIndex(RTree::bulk_load(edges))
    }

    /// True when some leg of `points` crosses an edge properly (touching one does not count:
    /// a ground vehicle's swaths end on the mainland's edge). The edges are looked up per run
    /// of [`LEGS_PER_SIFT`] legs, in order: a long manoeuvre over an area usually crosses its
    /// edge in its first runs, and one look-up for its whole box would gather most edges.
    pub fn crossed(&self, points: &[Coord]) -> bool {
        let size = |a: Coord, b: Coord| (b.x - a.x).abs() + (b.y - a.y).abs();
        let apart = |e: &Edge, lo: Coord, hi: Coord| e.0.x.max(e.1.x) < lo.x || e.0.x.min(e.1.x) > hi.x || e.0.y.max(e.1.y) < lo.y || e.0.y.min(e.1.y) > hi.y;
        let legs = points.len().saturating_sub(1);
        (0..legs).step_by(LEGS_PER_SIFT).any(|start| {
            let run = &points[start..=(start + LEGS_PER_SIFT).min(legs)];
            let bb = bounding(run).expect("a run has points");
            // each edge near the run against the run's legs, as the tree yields it
            self.0.locate_in_envelope_intersecting(&AABB::from_corners([bb.min().x, bb.min().y], [bb.max().x, bb.max().y])).any(|e| {
                run.windows(2).any(|w| {
                    let (a, b) = (w[0], w[1]);
                    if apart(e, Coord { x: a.x.min(b.x), y: a.y.min(b.y) }, Coord { x: a.x.max(b.x), y: a.y.max(b.y) }) {
                        return false;
                    }
                    let (p, q) = (e.0, e.1);
                    // orientations are products of two lengths: the tolerance scales with both
                    let eps = 1e-9 * size(a, b) * size(p, q);
                    let (d1, d2) = (cross(a, b, p), cross(a, b, q));
                    let (d3, d4) = (cross(p, q, a), cross(p, q, b));
                    ((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) && ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps))
                })
            })
        })
    }
}

/// Legs of a polyline checked against the edges found in their run's bounding box.
const LEGS_PER_SIFT: usize = 8;

#[cfg(test)]
mod tests {
    use super::*;

    fn c(x: f64, y: f64) -> Coord {
        Coord { x, y }
    }

    #[test]
    fn orientation_signs_agree() {
        let ccw = [c(0.0, 0.0), c(1.0, 0.0), c(0.0, 1.0)];
        assert!(cross(ccw[0], ccw[1], ccw[2]) > 0.0);
        assert!(signed_area(&ccw) > 0.0);
        let cw: Vec<Coord> = ccw.iter().rev().copied().collect();
        assert!(signed_area(&cw) < 0.0);
    }

    #[test]
    fn points_inside_and_outside_a_closed_ring() {
        let ring = [c(0.0, 0.0), c(4.0, 0.0), c(4.0, 4.0), c(0.0, 4.0), c(0.0, 0.0)];
        assert!(point_in_ring(c(1.0, 1.0), &ring));
        assert!(!point_in_ring(c(5.0, 1.0), &ring));
        let bb = bounding(&ring).expect("points");
        assert_eq!((bb.min(), bb.max()), (c(0.0, 0.0), c(4.0, 4.0)));
        assert!(bounding(&[]).is_none());
    }

    proptest::proptest! {
        /// Looking the edges up per run of legs finds every proper crossing a check of each
        /// leg against each edge finds, wherever along the polyline it lies: polylines of legs
        /// from 0.3 m (an arc's chords) to 40 m.
        #[test]
        fn crossed_finds_what_every_leg_against_every_edge_finds(
            radii in proptest::collection::vec(20.0..60.0f64, 12..40),
            start in (-80.0..80.0f64, -80.0..80.0f64),
            legs in proptest::collection::vec((0.0..std::f64::consts::TAU, 0.3..40.0f64), 1..60),
        ) {
            use geo::line_intersection::{LineIntersection, line_intersection};
            // a star-shaped ring round the origin
            let k = radii.len();
            let mut ring: Vec<Coord> = radii.iter().enumerate().map(|(i, r)| {
                let a = std::f64::consts::TAU * i as f64 / k as f64;
                c(r * a.cos(), r * a.sin())
            }).collect();
            ring.push(ring[0]);
            let area = MultiPolygon(vec![geo::Polygon::new(geo::LineString::from(ring.clone()), vec![])]);
            let points: Vec<Coord> = std::iter::once(c(start.0, start.1))
                .chain(legs.iter().scan(c(start.0, start.1), |at, &(a, l)| {
                    *at = c(at.x + l * a.cos(), at.y + l * a.sin());
                    Some(*at)
                }))
                .collect();
            let expected = points.windows(2).any(|leg| ring.windows(2).any(|edge| {
                matches!(line_intersection(geo::Line::new(leg[0], leg[1]), geo::Line::new(edge[0], edge[1])), Some(LineIntersection::SinglePoint { is_proper: true, .. }))
            }));
            proptest::prop_assert_eq!(EdgeIndex::new(&area).crossed(&points), expected);
        }
    }
}
