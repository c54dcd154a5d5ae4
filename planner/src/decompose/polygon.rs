//! Polygon primitives of the convex decompositions (docs/methods.md, decomposition §4, §6.2, §7): width by
//! the hull, reflex vertices, rays to the boundary, splitting along a chord, monotonicity.
//!
//! Rings here are open vertex lists (no closing point), counter-clockwise.

use geo::{ConvexHull, Coord, LineString, MultiPoint, Point};

use crate::geom;
use crate::sweep::width_across;

/// Cross product of two vectors.
fn cross(a: Coord, b: Coord) -> f64 {
    geom::cross(Coord { x: 0.0, y: 0.0 }, a, b)
}

/// Angle from `a` to `b` counter-clockwise, in [0, 2π).
fn ccw_angle(a: Coord, b: Coord) -> f64 {
    (cross(a, b).atan2(a.x * b.x + a.y * b.y)).rem_euclid(std::f64::consts::TAU)
}

/// The vertices of a closed `LineString` without the closing point.
pub fn open_ring(ring: &LineString) -> Vec<Coord> {
    let mut v = ring.0.clone();
    if v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
    v
}

/// Width of the points (the least extent across any direction) and the line direction that
/// attains it (math radians mod π). The minimum lies along a hull edge; ties keep the first.
pub fn min_width_of(points: &[Coord]) -> (f64, f64) {
    let hull = MultiPoint(points.iter().map(|&c| Point(c)).collect()).convex_hull();
    let hull = &hull.exterior().0;
    let mut best = (f64::INFINITY, 0.0);
    for w in hull.windows(2) {
        let d = w[1] - w[0];
        if d.x == 0.0 && d.y == 0.0 {
            continue;
        }
        let angle = d.y.atan2(d.x).rem_euclid(std::f64::consts::PI);
        let width = width_across(hull, angle);
        if width < best.0 - 1e-9 {
            best = (width, angle);
        }
    }
    if best.0.is_infinite() { (0.0, 0.0) } else { best }
}

/// [`min_width_of`] a ring.
pub fn min_width(ring: &LineString) -> (f64, f64) {
    min_width_of(&ring.0)
}

/// Interior angle at vertex `i` (the free side is on the left of every edge).
pub fn interior_angle(ring: &[Coord], i: usize) -> f64 {
    let n = ring.len();
    let (p, v, q) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
    ccw_angle(q - v, p - v)
}

/// Indices of the reflex vertices, in ring order.
pub fn reflex_vertices(ring: &[Coord]) -> Vec<usize> {
    (0..ring.len()).filter(|&i| interior_angle(ring, i) > std::f64::consts::PI + 1e-9).collect()
}

/// True when `dir` points strictly into the interior angle at vertex `i`.
pub fn points_inside(ring: &[Coord], i: usize, dir: Coord) -> bool {
    let n = ring.len();
    let (v, q) = (ring[i], ring[(i + 1) % n]);
    let a = ccw_angle(q - v, dir);
    a > 1e-9 && a < interior_angle(ring, i) - 1e-9
}

/// Where a ray from vertex `i` first meets the boundary: `(distance along the unit ray, index
/// of the edge hit, point hit)`. The two edges at `i` are not counted.
pub fn ray_hit(ring: &[Coord], i: usize, dir: Coord) -> Option<(f64, usize, Coord)> {
    let n = ring.len();
    let len = dir.x.hypot(dir.y);
    if len == 0.0 {
        return None;
    }
    let d = Coord { x: dir.x / len, y: dir.y / len };
    let v = ring[i];
    let mut best: Option<(f64, usize, Coord)> = None;
    for j in 0..n {
        if j == i || (j + 1) % n == i {
            continue;
        }
        let (a, b) = (ring[j], ring[(j + 1) % n]);
        let e = b - a;
        let denom = cross(d, e);
        if denom.abs() < 1e-12 {
            continue;
        }
        let t = cross(a - v, e) / denom;
        let s = cross(a - v, d) / denom;
        if t > 1e-7 && (-1e-9..=1.0 + 1e-9).contains(&s) && best.is_none_or(|(bt, _, _)| t < bt) {
            let s = s.clamp(0.0, 1.0);
            best = Some((t, j, Coord { x: a.x + e.x * s, y: a.y + e.y * s }));
        }
    }
    best
}

/// Splits the ring along the chord from vertex `i` to `hit` on edge `j` (as found by
/// [`ray_hit`]). A hit within 1 µm of a vertex snaps to it.
pub fn split(ring: &[Coord], i: usize, j: usize, hit: Coord) -> (Vec<Coord>, Vec<Coord>) {
    let n = ring.len();
    let near = |a: Coord, b: Coord| (a.x - b.x).hypot(a.y - b.y) < 1e-6;
    let next = (j + 1) % n;
    // walk i → … → j, then the hit; and the hit → j+1 → … → i
    let mut first = walk(ring, i, j);
    if !near(hit, ring[j]) && !near(hit, ring[next]) {
        first.push(hit);
    }
    let mut second = Vec::new();
    if !near(hit, ring[next]) {
        second.push(if near(hit, ring[j]) { ring[j] } else { hit });
    }
    second.extend(walk(ring, next, i));
    if near(hit, ring[next]) {
        // the chord ends on vertex j+1, which closes the first ring
        first.push(ring[next]);
    }
    (clean(first), clean(second))
}

/// The vertices from index `from` to index `to`, both included, in ring order.
fn walk(ring: &[Coord], from: usize, to: usize) -> Vec<Coord> {
    let steps = (to + ring.len() - from) % ring.len();
    (0..=steps).map(|k| ring[(from + k) % ring.len()]).collect()
}

/// Drops repeated and collinear vertices.
pub fn clean(mut ring: Vec<Coord>) -> Vec<Coord> {
    loop {
        let n = ring.len();
        if n < 3 {
            return ring;
        }
        let drop = (0..n).find(|&i| {
            let (p, v, q) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let (a, b) = (v - p, q - v);
            let (la, lb) = (a.x.hypot(a.y), b.x.hypot(b.y));
            la < 1e-6 || lb < 1e-6 || (cross(a, b).abs() <= 1e-9 * la * lb && a.x * b.x + a.y * b.y > 0.0)
        });
        match drop {
            Some(i) => {
                ring.remove(i);
            }
            None => return ring,
        }
    }
}

/// True when every line of direction `angle` meets the ring's inside in one interval: the
/// offsets across the lines have exactly one minimum and one maximum around the ring.
pub fn is_monotone(ring: &[Coord], angle: f64) -> bool {
    let (s, c) = angle.sin_cos();
    let h: Vec<f64> = ring.iter().map(|p| -p.x * s + p.y * c).collect();
    // drop flat runs so that every step goes up or down
    let mut steps: Vec<f64> = Vec::new();
    let n = h.len();
    for i in 0..n {
        let d = h[(i + 1) % n] - h[i];
        if d.abs() > 1e-9 {
            steps.push(d.signum());
        }
    }
    let changes = (0..steps.len()).filter(|&i| steps[i] != steps[(i + 1) % steps.len()]).count();
    changes == 2
}

/// The ring as a closed `LineString`.
pub fn closed(ring: &[Coord]) -> LineString {
    let mut v = ring.to_vec();
    v.push(ring[0]);
    LineString::from(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::signed_area;

    fn ring(pts: &[(f64, f64)]) -> Vec<Coord> {
        pts.iter().map(|&(x, y)| Coord { x, y }).collect()
    }

    #[test]
    fn widths_match_the_spec_vectors() {
        // docs/methods.md, decomposition §4: (points, width, direction in degrees)
        type Case<'a> = (&'a [(f64, f64)], f64, f64);
        let cases: [Case; 4] = [
            (&[(0., 0.), (4., 0.), (0., 3.)], 2.4, 143.13),
            (&[(0., 0.), (500., 0.), (500., 200.), (0., 200.)], 200.0, 0.0),
            (&[(50., 122.), (396., 271.), (477., 676.), (-62., 520.)], 409.8, 23.3),
            (&[(638., 271.), (772., 312.), (871., 825.), (753., 844.)], 123.3, 78.7),
        ];
        for (pts, w, deg) in cases {
            let (width, angle) = min_width_of(&ring(pts));
            assert!((width - w).abs() < 0.05, "{width} vs {w}");
            assert!((angle.to_degrees() - deg).abs() < 0.05, "{} vs {deg}", angle.to_degrees());
        }
    }

    #[test]
    fn reflex_rays_and_splits() {
        // an L: reflex corner at (10, 10)
        let l = ring(&[(0., 0.), (20., 0.), (20., 10.), (10., 10.), (10., 20.), (0., 20.)]);
        assert_eq!(reflex_vertices(&l), vec![3]);
        // extension of the incoming edge (20,10)→(10,10) goes west to the edge x = 0
        let dir = l[3] - l[2];
        assert!(points_inside(&l, 3, dir));
        let (t, j, hit) = ray_hit(&l, 3, dir).unwrap();
        assert_eq!((t, j, hit), (10.0, 5, Coord { x: 0.0, y: 10.0 }));
        let (a, b) = split(&l, 3, j, hit);
        assert!((signed_area(&a) + signed_area(&b) - signed_area(&l)).abs() < 1e-9);
        assert!(reflex_vertices(&a).is_empty() && reflex_vertices(&b).is_empty());
        // a U meets horizontal lines twice, vertical ones once
        let u = ring(&[(0., 0.), (30., 0.), (30., 20.), (20., 20.), (20., 10.), (10., 10.), (10., 20.), (0., 20.)]);
        assert!(!is_monotone(&u, 0.0) && is_monotone(&u, std::f64::consts::FRAC_PI_2));
        // a direction pointing outside the interior angle is refused
        assert!(!points_inside(&l, 3, Coord { x: 1.0, y: 1.0 }));
    }
}
