//! The fishtail (three-point) turn of a vehicle that may reverse, between anti-parallel
//! poses: forward along the first heading as far as the other end lies further out, a quarter
//! circle towards the other line, a straight (in reverse when the lines are closer than a
//! turning diameter), a second quarter circle, and forward to the entry (docs/methods.md,
//! ground §3). Where the lines are a diameter apart or more it is the plain U turn. The quarter
//! turns are circles, or continuous-curvature turns for slow steering.

use std::f64::consts::FRAC_PI_2;

use geo::Coord;

use super::dubins::{Pose, arc_step};

/// A left quarter turn from the origin facing +x: its points (the origin left out), ending at
/// `(reach, reach)` facing +y, and its length. On a circle `reach` is the radius.
#[derive(Debug, Clone, PartialEq)]
pub struct QuarterTurn {
    pub points: Vec<Coord>,
    pub reach: f64,
    pub length: f64,
}

impl QuarterTurn {
    /// The quarter circle of radius `r`.
    pub fn circle(r: f64, chord_tolerance_m: f64) -> Self {
        let k = (FRAC_PI_2 / arc_step(r, chord_tolerance_m)).ceil() as usize;
        let points = (1..=k)
            .map(|i| {
                let a = FRAC_PI_2 * i as f64 / k as f64;
                Coord { x: r * a.sin(), y: r - r * a.cos() }
            })
            .collect();
        QuarterTurn { points, reach: r, length: FRAC_PI_2 * r }
    }
}

/// A fishtail from `from` to `to` with two of `quarter`, or `None` unless the two face
/// opposite ways (within 1e-6 rad): the points (first and last exactly the poses), the length
/// driven, and whether any of it is driven in reverse.
pub fn fishtail(from: Pose, to: Pose, quarter: &QuarterTurn) -> Option<(Vec<Coord>, f64, bool)> {
    let opposite = (to.theta - from.theta - std::f64::consts::PI).rem_euclid(std::f64::consts::TAU);
    if opposite.min(std::f64::consts::TAU - opposite) > 1e-6 {
        return None;
    }
    // `to` in `from`'s frame: `along` ahead, `across` to the left
    let (sin, cos) = from.theta.sin_cos();
    let (dx, dy) = (to.x - from.x, to.y - from.y);
    let (along, across) = (dx * cos + dy * sin, -dx * sin + dy * cos);
    let side = if across >= 0.0 { 1.0 } else { -1.0 };
    let d = across.abs();
    let (first, last) = (along.max(0.0), (-along).max(0.0));
    let reach = quarter.reach;
    let middle = d - 2.0 * reach;
    let mut local = vec![Coord { x: 0.0, y: 0.0 }, Coord { x: first, y: 0.0 }];
    // from heading 0 to π/2, then (turned a quarter) from π/2 to π, ending at (first, d)
    local.extend(quarter.points.iter().map(|p| Coord { x: first + p.x, y: p.y }));
    local.push(Coord { x: first + reach, y: reach + middle });
    local.extend(quarter.points.iter().map(|p| Coord { x: first + reach - p.y, y: d - reach + p.x }));
    local.push(Coord { x: first - last, y: d });
    local.dedup_by(|a, b| (a.x - b.x).hypot(a.y - b.y) < 1e-9);
    let mut points: Vec<Coord> = local.iter().map(|p| Coord { x: from.x + p.x * cos - side * p.y * sin, y: from.y + p.x * sin + side * p.y * cos }).collect();
    points[0] = from.coord();
    *points.last_mut().expect("points") = to.coord();
    let length = first + last + 2.0 * quarter.length + middle.abs();
    Some((points, length, middle < 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::polyline_length;

    #[test]
    fn reverses_between_close_lines_and_is_a_u_turn_between_far_ones() {
        let r = 7.0;
        let from = Pose::new(0.0, 0.0, 0.0);
        // lines 6 m apart, the next one's end 2 m further out: 2 + 7π + 8 m in reverse
        let quarter = QuarterTurn::circle(r, 0.05);
        let (pts, length, reverse) = fishtail(from, Pose::new(2.0, 6.0, std::f64::consts::PI), &quarter).unwrap();
        assert!(reverse && (length - (2.0 + r * std::f64::consts::PI + 8.0)).abs() < 1e-9);
        assert!((polyline_length(&pts) - length).abs() < 0.1, "{}", polyline_length(&pts));
        // never further out than the farther end plus the radius
        assert!(pts.iter().all(|p| p.x <= 2.0 + r + 1e-9));
        // to the right, 20 m apart: forward all the way
        let (pts, length, reverse) = fishtail(from, Pose::new(-3.0, -20.0, std::f64::consts::PI), &quarter).unwrap();
        assert!(!reverse && (length - (3.0 + r * std::f64::consts::PI + 6.0)).abs() < 1e-9);
        assert_eq!(*pts.last().unwrap(), Coord { x: -3.0, y: -20.0 });
        assert!(pts.iter().all(|p| p.y <= 1e-9));
        assert!(fishtail(from, Pose::new(0.0, 6.0, 0.0), &quarter).is_none());
    }
}
