//! Shortest transits around no-fly zones on a visibility graph (docs/methods.md, decomposition §10.5).
//!
//! Nodes are the convex corners of the no-fly zones grown by the margin; a straight leg is
//! allowed when it does not enter the zones grown by half the margin, so a path that runs
//! along the grown outline keeps at least half the margin of clearance.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use geo::{BoundingRect, Coord, Intersects, LineString, MultiPolygon, Polygon, Rect};

use crate::geom::{bounding, cross, distance, point_in_ring, signed_area};

/// The shortest ways from a place to every node of a [`TransitPlanner`].
pub struct Tree {
    from: Coord,
    dist: Vec<f64>,
    /// Each node's predecessor (`usize::MAX`: reached straight from `from`).
    prev: Vec<usize>,
}

pub struct TransitPlanner {
    /// Rings a leg may not enter, with their bounding boxes.
    walls: Vec<(Rect, Vec<Coord>)>,
    nodes: Vec<Coord>,
    /// `visible[i]` lists the nodes seen from node i, with the distance.
    visible: Vec<Vec<(usize, f64)>>,
}

impl TransitPlanner {
    /// `corners`: the zones grown by the margin (their convex vertices become nodes);
    /// `walls`: the zones a leg may not enter.
    /// The graph's O(n²) pairs, each checked against the walls, are checked in parallel rows;
    /// [`Self::node_count`] tells beforehand how many nodes there will be at most.
    pub fn new(corners: &MultiPolygon, walls: &MultiPolygon) -> Self {
        use rayon::prelude::*;
        let walls: Vec<(Rect, Vec<Coord>)> = walls.iter().flat_map(rings).collect();
        let mut nodes = corner_nodes(corners);
        let mut planner = TransitPlanner { walls, nodes: Vec::new(), visible: Vec::new() };
        nodes.retain(|&n| !planner.inside_wall(n));
        planner.nodes = nodes;
        let n = planner.nodes.len();
        let seen_after: Vec<Vec<(usize, f64)>> = (0..n)
            .into_par_iter()
            .map(|i| (i + 1..n).filter(|&j| planner.is_clear(planner.nodes[i], planner.nodes[j])).map(|j| (j, distance(planner.nodes[i], planner.nodes[j]))).collect())
            .collect();
        let mut visible = vec![Vec::new(); n];
        for (i, row) in seen_after.into_iter().enumerate() {
            for (j, d) in row {
                visible[i].push((j, d));
                visible[j].push((i, d));
            }
        }
        planner.visible = visible;
        planner
    }

    /// The most nodes a planner on `corners` has: their convex corners.
    pub fn node_count(corners: &MultiPolygon) -> usize {
        corner_nodes(corners).len()
    }

    /// Shortest polyline from `a` to `b` that never enters a wall, or `None` when there is none.
    pub fn path(&self, a: Coord, b: Coord) -> Option<Vec<Coord>> {
        if self.is_clear(a, b) {
            return Some(vec![a, b]);
        }
        self.path_between(&self.tree_from(a), b, &self.seen_from(b))
    }

    /// The shortest ways from `a` to every node, for [`Self::path_between`]: a place that many
    /// paths start from computes it once.
    pub fn tree_from(&self, a: Coord) -> Tree {
        self.tree_seeing(a, &self.seen_from(a))
    }

    /// [`Self::tree_from`] `a`, whose nodes in sight are `seen` (from [`Self::seen_from`]): a
    /// place kept as a target too has them already, and finding them was most of a tree's time.
    pub fn tree_seeing(&self, a: Coord, seen: &[(usize, f64)]) -> Tree {
        let (dist, prev) = self.dijkstra(seen);
        Tree { from: a, dist, prev }
    }

    /// Shortest polyline from the tree's place to `b`, whose nodes in sight are `seen` (from
    /// [`Self::seen_from`]), through at least one node; `None` when there is none.
    pub fn path_between(&self, tree: &Tree, b: Coord, seen: &[(usize, f64)]) -> Option<Vec<Coord>> {
        // the last corner: the one seen from `b` that ends the shortest way (first minimum)
        let (mut cur, total) = seen.iter().map(|&(w, d)| (w, tree.dist[w] + d)).fold((usize::MAX, f64::INFINITY), |acc, x| if x.1 < acc.1 { x } else { acc });
        if !total.is_finite() {
            return None;
        }
        let mut out = vec![b];
        while cur != usize::MAX {
            out.push(self.nodes[cur]);
            cur = tree.prev[cur];
        }
        out.push(tree.from);
        out.reverse();
        Some(out)
    }

    /// The nodes seen from `p`, with their distance.
    pub fn seen_from(&self, p: Coord) -> Vec<(usize, f64)> {
        (0..self.nodes.len()).filter(|&i| self.is_clear(p, self.nodes[i])).map(|i| (i, distance(p, self.nodes[i]))).collect()
    }

    /// Lengths of the shortest transits between all pairs of `points` (infinite where there is
    /// none): straight where the way is clear, otherwise one Dijkstra per source point.
    pub fn distance_matrix(&self, points: &[Coord]) -> Vec<Vec<f64>> {
        use rayon::prelude::*;
        let clear: Vec<Vec<bool>> = points.par_iter().map(|&a| points.iter().map(|&b| self.is_clear(a, b)).collect()).collect();
        let blocked = clear.iter().any(|row| row.iter().any(|c| !c));
        // nodes seen from each point, only needed when some pair is blocked
        let seen: Vec<Vec<(usize, f64)>> = if blocked { points.par_iter().map(|&p| self.seen_from(p)).collect() } else { Vec::new() };
        (0..points.len())
            .into_par_iter()
            .map(|i| {
                let row = &clear[i];
                if row.iter().all(|&c| c) {
                    return points.iter().map(|&b| distance(points[i], b)).collect();
                }
                let (dist, _) = self.dijkstra(&seen[i]);
                (0..points.len()).map(|j| if row[j] { distance(points[i], points[j]) } else { seen[j].iter().map(|&(w, d)| dist[w] + d).fold(f64::INFINITY, f64::min) }).collect()
            })
            .collect()
    }

    /// Distances from a source that sees `sources` (node, distance) to every node, and each
    /// node's predecessor on its shortest way (`usize::MAX`: reached straight from the source).
    fn dijkstra(&self, sources: &[(usize, f64)]) -> (Vec<f64>, Vec<usize>) {
        let mut dist = vec![f64::INFINITY; self.nodes.len()];
        let mut prev = vec![usize::MAX; self.nodes.len()];
        let mut heap = BinaryHeap::new();
        for &(i, d) in sources {
            if d < dist[i] {
                dist[i] = d;
                heap.push(State { cost: d, node: i });
            }
        }
        while let Some(State { cost, node }) = heap.pop() {
            if cost > dist[node] {
                continue;
            }
            for &(next, w) in &self.visible[node] {
                if cost + w < dist[next] {
                    dist[next] = cost + w;
                    prev[next] = node;
                    heap.push(State { cost: cost + w, node: next });
                }
            }
        }
        (dist, prev)
    }

    /// True when the segment `a`–`b` does not enter the interior of any wall.
    pub fn is_clear(&self, a: Coord, b: Coord) -> bool {
        self.walls.iter().all(|(wall_box, ring)| !leg_enters(wall_box, ring, a, b))
    }

    /// The corners a transit may bend around.
    pub fn corners(&self) -> &[Coord] {
        &self.nodes
    }

    /// True when no leg of the polyline enters a wall. Walls are tested one at a time against
    /// the legs in their box: a sampled arc has dozens of short legs, which most walls'
    /// boxes miss.
    pub fn is_polyline_clear(&self, points: &[Coord]) -> bool {
        let Some(bb) = bounding(points) else { return true };
        self.walls.iter().filter(|(wall_box, _)| wall_box.intersects(&bb)).all(|(wall_box, ring)| points.windows(2).all(|w| !leg_enters(wall_box, ring, w[0], w[1])))
    }

    /// True when there is any wall at all.
    pub fn has_walls(&self) -> bool {
        !self.walls.is_empty()
    }

    /// True when some wall's bounding box overlaps `rect`.
    pub fn any_wall_in(&self, rect: &Rect) -> bool {
        self.walls.iter().any(|(bb, _)| bb.intersects(rect))
    }

    fn inside_wall(&self, p: Coord) -> bool {
        self.walls.iter().any(|(_, r)| point_in_ring(p, r))
    }
}

#[derive(PartialEq)]
struct State {
    cost: f64,
    node: usize,
}
impl Eq for State {}
impl Ord for State {
    fn cmp(&self, o: &Self) -> Ordering {
        o.cost.total_cmp(&self.cost).then(o.node.cmp(&self.node))
    }
}
impl PartialOrd for State {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Every ring of the polygon with its bounding box.
fn rings(p: &Polygon) -> Vec<(Rect, Vec<Coord>)> {
    std::iter::once(p.exterior()).chain(p.interiors()).filter_map(|r| Some((r.bounding_rect()?, r.0.clone()))).collect()
}

/// Vertices where the polygon's interior angle is below 180° (seen from the free side, these
/// are the corners a shortest path bends around). Works for exteriors (CCW) of obstacles.
fn corner_nodes(corners: &MultiPolygon) -> Vec<Coord> {
    corners.iter().flat_map(|poly| std::iter::once(poly.exterior()).chain(poly.interiors())).flat_map(convex_corners).collect()
}

fn convex_corners(ring: &LineString) -> Vec<Coord> {
    let pts = &ring.0[..ring.0.len().saturating_sub(1)];
    let n = pts.len();
    let ccw = signed_area(pts) > 0.0;
    (0..n)
        .filter(|&i| {
            let (p, v, q) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
            let cross = (v.x - p.x) * (q.y - v.y) - (v.y - p.y) * (q.x - v.x);
            if ccw { cross > 0.0 } else { cross < 0.0 }
        })
        .map(|i| pts[i])
        .collect()
}

/// Does the leg a–b enter the wall `ring` (bounding box `wall_box`)? The boxes first.
fn leg_enters(wall_box: &Rect, ring: &[Coord], a: Coord, b: Coord) -> bool {
    wall_box.intersects(&Rect::new(a, b)) && segment_enters(a, b, ring)
}

/// Does the open segment a–b pass through the interior of the closed ring?
fn segment_enters(a: Coord, b: Coord, ring: &[Coord]) -> bool {
    let d = b - a;
    let len2 = d.x * d.x + d.y * d.y;
    let tolerance = 1e-9 * len2.sqrt().max(1.0);
    // where a ring vertex lies on the segment: its parameter along a–b
    let touch = |c: Coord| -> Option<f64> {
        if len2 == 0.0 || cross(a, b, c).abs() > tolerance {
            return None;
        }
        let t = ((c.x - a.x) * d.x + (c.y - a.y) * d.y) / len2;
        (t > 0.0 && t < 1.0).then_some(t)
    };
    // an edge whose box misses the segment's, grown by the farthest a touching vertex may lie
    // off it, neither crosses it nor has a vertex on it
    let off = if len2 > 0.0 { tolerance / len2.sqrt() } else { 0.0 };
    let (lo, hi) = (Coord { x: a.x.min(b.x) - off, y: a.y.min(b.y) - off }, Coord { x: a.x.max(b.x) + off, y: a.y.max(b.y) + off });
    let mut touched = false;
    for w in ring.windows(2) {
        let (p, q) = (w[0], w[1]);
        if p.x.max(q.x) < lo.x || p.x.min(q.x) > hi.x || p.y.max(q.y) < lo.y || p.y.min(q.y) > hi.y {
            continue;
        }
        let (d1, d2) = (cross(a, b, p), cross(a, b, q));
        let (d3, d4) = (cross(p, q, a), cross(p, q, b));
        if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
            return true; // proper crossing
        }
        touched = touched || touch(p).is_some() || touch(q).is_some();
    }
    let enters_between = |t0: f64, t1: f64| {
        t1 - t0 > 1e-12 && {
            let t = (t0 + t1) / 2.0;
            let m = Coord { x: a.x + d.x * t, y: a.y + d.y * t };
            point_in_ring(m, ring) && !on_ring(m, ring)
        }
    };
    if !touched {
        // no crossing and no vertex on it: the segment lies wholly inside or wholly outside
        return enters_between(0.0, 1.0);
    }
    // the pieces between the vertices it touches, each wholly inside or outside
    let mut ts: Vec<f64> = [0.0, 1.0].into_iter().chain(ring.iter().filter_map(|&c| touch(c))).collect();
    ts.sort_by(f64::total_cmp);
    ts.windows(2).any(|w| enters_between(w[0], w[1]))
}

/// Is `p` on the ring's boundary (within 1e-7 m)?
fn on_ring(p: Coord, ring: &[Coord]) -> bool {
    ring.windows(2).any(|w| {
        let (a, b) = (w[0], w[1]);
        let ab = b - a;
        let len2 = ab.x * ab.x + ab.y * ab.y;
        let t = if len2 > 0.0 { (((p.x - a.x) * ab.x + (p.y - a.y) * ab.y) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let q = Coord { x: a.x + ab.x * t, y: a.y + ab.y * t };
        (p.x - q.x).hypot(p.y - q.y) < 1e-7
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::polygon;

    fn square(x0: f64, y0: f64, s: f64) -> Polygon {
        polygon![(x: x0, y: y0), (x: x0 + s, y: y0), (x: x0 + s, y: y0 + s), (x: x0, y: y0 + s)]
    }

    #[test]
    fn goes_around_a_zone() {
        let walls = MultiPolygon(vec![square(40.0, 40.0, 20.0)]);
        let corners = MultiPolygon(vec![square(38.0, 38.0, 24.0)]);
        let tp = TransitPlanner::new(&corners, &walls);
        let a = Coord { x: 0.0, y: 50.0 };
        let b = Coord { x: 100.0, y: 50.0 };
        let p = tp.path(a, b).unwrap();
        assert_eq!(p.len(), 4);
        let len: f64 = p.windows(2).map(|w| distance(w[0], w[1])).sum();
        let expected = 2.0 * (38.0f64.hypot(12.0)) + 24.0;
        assert!((len - expected).abs() < 1e-9, "{len} vs {expected}");
        assert!(p.windows(2).all(|w| tp.is_clear(w[0], w[1])));
    }

    #[test]
    fn one_tree_from_a_place_gives_its_shortest_paths_to_many_places() {
        let walls = MultiPolygon(vec![square(40.0, 20.0, 20.0), square(40.0, 60.0, 20.0), square(80.0, 35.0, 10.0)]);
        let corners = MultiPolygon(walls.iter().map(|p| square(p.exterior().0[0].x - 2.0, p.exterior().0[0].y - 2.0, p.exterior().0[2].x - p.exterior().0[0].x + 4.0)).collect());
        let tp = TransitPlanner::new(&corners, &walls);
        let a = Coord { x: 0.0, y: 50.0 };
        let tree = tp.tree_from(a);
        let mut blocked = 0;
        for k in 0..40 {
            let b = Coord { x: 70.0 + (k % 8) as f64 * 8.0, y: 5.0 + (k / 8) as f64 * 20.0 };
            if tp.inside_wall(b) || tp.is_clear(a, b) {
                continue;
            }
            blocked += 1;
            // the shortest way by Floyd–Warshall over the corners, `a` and `b`
            let mut places = tp.corners().to_vec();
            places.extend([a, b]);
            let n = places.len();
            let mut d: Vec<Vec<f64>> = (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| {
                            if i == j {
                                0.0
                            } else if tp.is_clear(places[i], places[j]) {
                                distance(places[i], places[j])
                            } else {
                                f64::INFINITY
                            }
                        })
                        .collect()
                })
                .collect();
            for m in 0..n {
                for i in 0..n {
                    for j in 0..n {
                        d[i][j] = d[i][j].min(d[i][m] + d[m][j]);
                    }
                }
            }
            let path = tp.path_between(&tree, b, &tp.seen_from(b)).expect("a way round");
            assert_eq!((path[0], *path.last().unwrap()), (a, b));
            assert!(path.windows(2).all(|w| tp.is_clear(w[0], w[1])), "to {b:?}");
            let length: f64 = path.windows(2).map(|w| distance(w[0], w[1])).sum();
            assert!((length - d[n - 2][n - 1]).abs() < 1e-9, "to {b:?}: {length} vs {}", d[n - 2][n - 1]);
        }
        assert!(blocked >= 10, "{blocked} blocked places");
    }

    #[test]
    fn a_chord_through_a_zone_is_refused_and_an_edge_along_it_is_not() {
        let ring = square(0.0, 0.0, 10.0).exterior().0.clone();
        assert!(segment_enters(Coord { x: 0.0, y: 0.0 }, Coord { x: 10.0, y: 10.0 }, &ring));
        assert!(!segment_enters(Coord { x: 0.0, y: 0.0 }, Coord { x: 10.0, y: 0.0 }, &ring));
        assert!(!segment_enters(Coord { x: -5.0, y: 0.0 }, Coord { x: 15.0, y: 0.0 }, &ring));
    }

    /// Segments that pass through corners: the parts between the corners they touch decide.
    #[test]
    fn a_segment_through_corners_enters_only_where_a_part_between_them_lies_inside() {
        let c = |x: f64, y: f64| Coord { x, y };
        let ring = square(0.0, 0.0, 10.0).exterior().0.clone();
        // across the diagonal, in at one corner and out at the other; from outside through a
        // corner to the middle (its midpoint is the corner), also a millimetre long
        assert!(segment_enters(c(-5.0, -5.0), c(15.0, 15.0), &ring));
        assert!(segment_enters(c(-5.0, -5.0), c(5.0, 5.0), &ring));
        assert!(segment_enters(c(-0.0005, -0.0005), c(0.0005, 0.0005), &ring));
        // grazing one corner from outside, and a millimetre long beside it
        assert!(!segment_enters(c(-5.0, 5.0), c(5.0, -5.0), &ring));
        assert!(!segment_enters(c(-0.0005, 0.0005), c(0.0005, -0.0005), &ring));
        // a millimetre inside, and a millimetre from a corner inwards
        assert!(segment_enters(c(5.0, 5.0), c(5.001, 5.0), &ring));
        assert!(segment_enters(c(0.0, 0.0), c(0.0007, 0.0007), &ring));
        // along an edge past both its corners, and wholly outside
        assert!(!segment_enters(c(-1.0, 10.0), c(11.0, 10.0), &ring));
        assert!(!segment_enters(c(20.0, 0.0), c(30.0, 10.0), &ring));
    }
}
