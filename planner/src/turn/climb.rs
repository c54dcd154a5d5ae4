//! Climbing over obstacles (docs/methods.md, dubins §7.3, seed 003): obstacles are prisms (footprint and
//! top height) that may be overflown but not flown through. The horizontal path is kept; its
//! altitude profile is the lowest one that clears every obstacle by the clearance and climbs
//! and descends within the angle limit. Where the profile leaves the survey altitude on a
//! sweep line, that part of the line images nothing: the coverage lost is counted, and
//! routing adds it, times a penalty, to the connection that causes it.

use geo::{BoundingRect, Buffer, Coord, Intersects, Polygon, Rect};

use crate::geom::{distance, point_in_ring};
use crate::path::{FlightPath, Piece, PieceKind};

/// Spacing of the altitude samples along the path.
pub const STEP_M: f64 = 1.0;
/// A line flown this much above the survey altitude no longer images the ground.
pub const TOLERANCE_M: f64 = 0.5;

pub struct Obstacles {
    /// Footprints grown by the clearance, with their bounding box and the altitude to clear.
    prisms: Vec<(Rect, Vec<Coord>, f64)>,
    pub survey_altitude_m: f64,
    /// tan of the steepest climb and descent.
    slope: f64,
    /// Metres of path a metre of lost coverage costs in routing.
    pub penalty: f64,
}

impl Obstacles {
    /// `footprints`: polygons (local frame) with their height above ground.
    pub fn new(footprints: &[(Polygon, f64)], survey_altitude_m: f64, clearance_m: f64, max_climb_deg: f64, penalty: f64) -> Self {
        let prisms = footprints
            .iter()
            .flat_map(|(poly, height)| {
                poly.buffer(clearance_m).0.into_iter().filter_map(move |p| Some((p.exterior().bounding_rect()?, p.exterior().0.clone(), height + clearance_m)))
            })
            .collect();
        Self { prisms, survey_altitude_m, slope: max_climb_deg.to_radians().tan(), penalty }
    }

    pub fn is_empty(&self) -> bool {
        self.prisms.is_empty()
    }

    /// Highest altitude the aircraft may not go below at `p`.
    fn required(&self, p: Coord) -> f64 {
        self.prisms.iter().filter(|(bb, ring, _)| bb.intersects(&p) && point_in_ring(p, ring)).map(|(_, _, top)| *top).fold(self.survey_altitude_m, f64::max)
    }

    /// Horizontal distance a climb from the survey altitude to the highest obstacle needs.
    pub fn reach_m(&self) -> f64 {
        let top = self.prisms.iter().map(|p| p.2).fold(self.survey_altitude_m, f64::max);
        (top - self.survey_altitude_m) / self.slope + STEP_M
    }

    /// True when an obstacle (grown by the clearance and the climb distance) may touch `rect`.
    pub fn near(&self, rect: &Rect) -> bool {
        let m = Coord { x: self.reach_m(), y: self.reach_m() };
        let grown = Rect::new(rect.min() - m, rect.max() + m);
        self.prisms.iter().any(|(bb, _, top)| *top > self.survey_altitude_m && bb.intersects(&grown))
    }

    /// The lowest profile over points `STEP_M` apart: at least the required altitude, and
    /// climbing or descending at most `slope` per metre (two passes, O(n)).
    pub fn profile(&self, samples: &[Coord]) -> Vec<f64> {
        let mut z: Vec<f64> = samples.iter().map(|&p| self.required(p)).collect();
        for i in 1..z.len() {
            let d = distance(samples[i - 1], samples[i]);
            z[i] = z[i].max(z[i - 1] - d * self.slope);
        }
        for i in (0..z.len().saturating_sub(1)).rev() {
            let d = distance(samples[i], samples[i + 1]);
            z[i] = z[i].max(z[i + 1] - d * self.slope);
        }
        z
    }

    /// A connection raised over the obstacles: its 3D length, and the metres of the line
    /// before (ending at `before.1`) and the line after (starting at `after.0`) flown above
    /// the survey altitude.
    pub fn connection(&self, before: (Coord, Coord), manoeuvre: &[Coord], after: (Coord, Coord)) -> (f64, f64) {
        let window = self.reach_m();
        let tail = resample(&[towards(before.1, before.0, window), before.1]);
        let body = resample(manoeuvre);
        let head = resample(&[after.0, towards(after.0, after.1, window)]);
        let samples: Vec<Coord> = tail.iter().chain(&body[1..]).chain(&head[1..]).copied().collect();
        let z = self.profile(&samples);
        let (t, b) = (tail.len() - 1, tail.len() - 1 + body.len() - 1);
        let length_3d: f64 = (t..b).map(|i| distance(samples[i], samples[i + 1]).hypot(z[i + 1] - z[i])).sum();
        let lost = |range: std::ops::Range<usize>| -> f64 {
            range.filter(|&i| z[i].max(z[i + 1]) > self.survey_altitude_m + TOLERANCE_M).map(|i| distance(samples[i], samples[i + 1])).sum()
        };
        (length_3d, lost(0..t) + lost(b..samples.len() - 1))
    }
}

impl Obstacles {
    /// The path with its altitude profile over the obstacles: pieces that climb carry their
    /// altitudes; the parts of sweeps flown above the survey altitude become transits. Returns
    /// the metres of sweep lost that way.
    pub fn raise(&self, path: &FlightPath) -> (FlightPath, f64) {
        let mut samples: Vec<Coord> = Vec::new();
        let mut ranges = Vec::with_capacity(path.pieces.len());
        for piece in &path.pieces {
            let dense = resample(&piece.points);
            let first = samples.len().saturating_sub(1);
            if samples.is_empty() {
                samples.extend(dense);
            } else {
                samples.extend_from_slice(&dense[1..]);
            }
            ranges.push(first..samples.len());
        }
        let z = self.profile(&samples);
        let high = |i: usize| z[i] > self.survey_altitude_m + 1e-9;
        let mut out = FlightPath::default();
        let mut lost = 0.0;
        for (piece, range) in path.pieces.iter().zip(ranges) {
            if !range.clone().any(high) {
                out.pieces.push(piece.clone());
                continue;
            }
            if piece.kind != PieceKind::Sweep {
                let (points, heights) = simplify(&samples[range.clone()], &z[range]);
                out.pieces.push(Piece { points, z: heights, ..piece.clone() });
                continue;
            }
            // split the sweep where it rises above the survey altitude
            let above = |i: usize| z[i].max(z[i + 1]) > self.survey_altitude_m + TOLERANCE_M;
            let mut start = range.start;
            while start + 1 < range.end {
                let raised = above(start);
                let mut end = start + 1;
                while end + 1 < range.end && above(end) == raised {
                    end += 1;
                }
                let (points, heights) = simplify(&samples[start..=end], &z[start..=end]);
                let part = if raised {
                    lost += crate::geom::polyline_length(&points);
                    Piece { z: heights, ..Piece::new(PieceKind::Transit, points, 0.0) }
                } else {
                    Piece { points, z: heights, ..piece.clone() }
                };
                out.pieces.push(part);
                start = end;
            }
        }
        (out, lost)
    }
}

/// Drops the points where neither the direction nor the slope changes.
fn simplify(points: &[Coord], z: &[f64]) -> (Vec<Coord>, Vec<f64>) {
    let mut keep = vec![0];
    for i in 1..points.len().saturating_sub(1) {
        let (a, b, c) = (points[*keep.last().expect("kept")], points[i], points[i + 1]);
        let (u, v) = (b - a, c - b);
        let turn = (u.x * v.y - u.y * v.x).abs() > 1e-6 * distance(a, b).max(1e-9) * distance(b, c).max(1e-9);
        let slope = |p: Coord, q: Coord, zp: f64, zq: f64| (zq - zp) / distance(p, q).max(1e-9);
        let bend = (slope(a, b, z[*keep.last().expect("kept")], z[i]) - slope(b, c, z[i], z[i + 1])).abs() > 1e-6;
        if turn || bend {
            keep.push(i);
        }
    }
    keep.push(points.len() - 1);
    (keep.iter().map(|&i| points[i]).collect(), keep.iter().map(|&i| z[i]).collect())
}

/// The point `d` metres from `from` towards `to`, at most `to`.
fn towards(from: Coord, to: Coord, d: f64) -> Coord {
    let len = distance(from, to);
    if len <= d || len == 0.0 {
        return to;
    }
    from + (to - from) * (d / len)
}

/// The polyline with extra points so that none is more than `STEP_M` from the next; keeps
/// every original vertex.
pub fn resample(points: &[Coord]) -> Vec<Coord> {
    let mut out = vec![points[0]];
    for w in points.windows(2) {
        let k = (distance(w[0], w[1]) / STEP_M).ceil().max(1.0) as usize;
        out.extend((1..=k).map(|i| w[0] + (w[1] - w[0]) * (i as f64 / k as f64)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::polygon;

    fn wall() -> Obstacles {
        // a 35 m tall strip across x = 100..110 (90..120 with the clearance); survey at 30 m,
        // clearance 10 m, 30° climbs
        let strip = polygon![(x: 100., y: -500.), (x: 110., y: -500.), (x: 110., y: 500.), (x: 100., y: 500.)];
        Obstacles::new(&[(strip, 35.0)], 30.0, 10.0, 30.0, 10.0)
    }

    #[test]
    fn profile_clears_the_obstacle_within_the_slope() {
        let obs = wall();
        let samples = resample(&[Coord { x: 0.0, y: 0.0 }, Coord { x: 200.0, y: 0.0 }]);
        let z = obs.profile(&samples);
        let slope = 30f64.to_radians().tan();
        for (i, p) in samples.iter().enumerate() {
            if (91.0..=119.0).contains(&p.x) {
                assert!(z[i] >= 45.0 - 1e-9, "at x = {}: {}", p.x, z[i]);
            }
            assert!(z[i] >= 30.0);
            if i > 0 {
                assert!((z[i] - z[i - 1]).abs() <= slope * STEP_M + 1e-9);
            }
        }
        // far from the wall the aircraft is back at survey altitude
        assert_eq!(z[0], 30.0);
        assert_eq!(*z.last().unwrap(), 30.0);
    }

    #[test]
    fn a_climb_that_starts_on_a_line_loses_coverage() {
        let obs = wall();
        // line along y = 0 ending at x = 80, a straight connection over the wall to x = 130,
        // the next line from there on
        let (a, b) = (Coord { x: -200.0, y: 0.0 }, Coord { x: 80.0, y: 0.0 });
        let (c, d) = (Coord { x: 130.0, y: 0.0 }, Coord { x: 400.0, y: 0.0 });
        let (l3, lost) = obs.connection((a, b), &[b, c], (c, d));
        // climbing 15 m at 30° takes 26 m: it starts at x = 64, 16 m before the line ends; the
        // descent ends 16 m into the next line
        assert!((lost - 32.0).abs() < 3.0, "lost {lost}");
        assert!(l3 > 50.0, "3D length {l3}");
        // without the wall nothing is lost
        let none = Obstacles::new(&[], 30.0, 10.0, 30.0, 10.0);
        assert_eq!(none.connection((a, b), &[b, c], (c, d)), (50.0, 0.0));
    }
}
