//! Where each drone of a fleet is, second by second, and where two come too close at the same
//! time (docs/methods.md, fleets §3). Between samples the drones move in straight lines, and
//! the closest approach within each second is computed exactly, so fast drones crossing
//! between two samples are not missed.

use geo::Coord;

use crate::energy::PathEstimate;
use crate::geom::{distance, polyline_length};
use crate::path::FlightPath;

/// Two drones closer than this horizontally, and [`CONFLICT_HEIGHT_M`] vertically, at the same
/// time are in conflict.
pub const CONFLICT_DISTANCE_M: f64 = 10.0;
pub const CONFLICT_HEIGHT_M: f64 = 5.0;

/// Seconds between samples.
const STEP_S: f64 = 1.0;

/// A drone's position every [`STEP_S`] from its departure: (x, y, altitude).
pub struct Track {
    pub departure_s: f64,
    samples: Vec<(Coord, f64)>,
}

impl Track {
    /// The flight of `sorties` (each with its estimate), leaving at `departure_s`; points without
    /// an altitude of their own are at `altitude_m` (0 when the plan has none). Take-off and
    /// landing are spent at the sortie's first and last point.
    pub fn new(sorties: &[FlightPath], estimates: &[PathEstimate], departure_s: f64, altitude_m: f64) -> Track {
        // (time from departure, position, altitude) at every vertex
        let mut knots: Vec<(f64, Coord, f64)> = Vec::new();
        let mut t = 0.0;
        for (sortie, estimate) in sorties.iter().zip(estimates) {
            let Some(first) = sortie.pieces.first() else { continue };
            knots.push((t, first.start(), first.z.first().copied().unwrap_or(altitude_m)));
            t += estimate.takeoff.duration_s;
            for (piece, e) in sortie.pieces.iter().zip(&estimate.pieces) {
                let length = polyline_length(&piece.points);
                let start = t;
                let mut along = 0.0;
                for (i, w) in piece.points.windows(2).enumerate() {
                    along += distance(w[0], w[1]);
                    let share = if length > 0.0 { along / length } else { 1.0 };
                    knots.push((start + share * e.duration_s, w[1], piece.z.get(i + 1).copied().unwrap_or(altitude_m)));
                }
                t = start + e.duration_s;
            }
            t += estimate.landing.duration_s;
            if let Some(&(_, c, z)) = knots.last() {
                knots.push((t, c, z));
            }
        }
        let samples = sample(&knots);
        Track { departure_s, samples }
    }

    /// Time the drone lands for the last time, from the fleet's start.
    pub fn end_s(&self) -> f64 {
        self.departure_s + (self.samples.len().max(1) - 1) as f64 * STEP_S
    }

    /// Position at sample `k` of the fleet's clock, if the drone is flying then.
    fn at(&self, k: usize) -> Option<(Coord, f64)> {
        let offset = (self.departure_s / STEP_S).round() as usize;
        k.checked_sub(offset).and_then(|i| self.samples.get(i).copied())
    }
}

/// Positions every [`STEP_S`] along the knots (times ascending).
fn sample(knots: &[(f64, Coord, f64)]) -> Vec<(Coord, f64)> {
    let Some(&(end, _, _)) = knots.last() else { return Vec::new() };
    let mut out = Vec::with_capacity((end / STEP_S) as usize + 2);
    let mut i = 0;
    let mut t = 0.0;
    while t <= end + 1e-9 {
        while i + 1 < knots.len() && knots[i + 1].0 < t {
            i += 1;
        }
        let (t0, a, za) = knots[i];
        let (t1, b, zb) = knots[(i + 1).min(knots.len() - 1)];
        let f = if t1 > t0 { ((t - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 1.0 };
        out.push((Coord { x: a.x + (b.x - a.x) * f, y: a.y + (b.y - a.y) * f }, za + (zb - za) * f));
        t += STEP_S;
    }
    out
}

/// Departure times: a drone whose home lies within [`CONFLICT_DISTANCE_M`] of earlier drones'
/// leaves once the last of them is clear of it, `clear_s[j]` seconds after drone j left (its
/// climb to altitude and the flight out of conflict distance).
pub fn departures(homes: &[Option<Coord>], clear_s: &[f64]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::with_capacity(homes.len());
    for (k, home) in homes.iter().enumerate() {
        let shared = |j: &usize| home.zip(homes[*j]).is_some_and(|(h, o)| distance(o, h) < CONFLICT_DISTANCE_M);
        out.push((0..k).filter(shared).map(|j| out[j] + clear_s[j]).fold(0.0, f64::max));
    }
    out
}

/// Two drones too close at the same time, over one stretch of time.
#[derive(Debug, Clone, PartialEq)]
pub struct Encounter {
    pub vehicles: [usize; 2],
    pub from_s: f64,
    pub to_s: f64,
    pub closest_m: f64,
    /// Midpoint between the two drones at their closest.
    pub at: Coord,
}

/// Closest distance between two points moving in straight lines from `a0`, `b0` to `a1`, `b1`
/// over the same interval, and the fraction of it at which they are closest.
fn closest_approach(a0: Coord, a1: Coord, b0: Coord, b1: Coord) -> (f64, f64) {
    let (p, q) = (a0 - b0, a1 - b1);
    let d = q - p;
    let dd = d.x * d.x + d.y * d.y;
    let f = if dd > 0.0 { (-(p.x * d.x + p.y * d.y) / dd).clamp(0.0, 1.0) } else { 0.0 };
    let r = p + d * f;
    ((r.x * r.x + r.y * r.y).sqrt(), f)
}

/// Every stretch of time in which two vehicles are within `distance_m` horizontally (drones:
/// [`CONFLICT_DISTANCE_M`]; ground machines: their implements' width) and [`CONFLICT_HEIGHT_M`]
/// vertically.
pub fn encounters(tracks: &[Track], distance_m: f64) -> Vec<Encounter> {
    let steps = tracks.iter().map(|t| (t.end_s() / STEP_S).round() as usize + 1).max().unwrap_or(0);
    let mut out = Vec::new();
    for i in 0..tracks.len() {
        for j in i + 1..tracks.len() {
            let mut open: Option<Encounter> = None;
            for k in 0..steps {
                let pair = |k: usize| tracks[i].at(k).zip(tracks[j].at(k));
                let close = match (pair(k), pair(k + 1)) {
                    (Some(((a0, za), (b0, zb))), next) => {
                        let ((a1, _), (b1, _)) = next.unwrap_or(((a0, za), (b0, zb)));
                        let (d, f) = closest_approach(a0, a1, b0, b1);
                        let at = (a0 + (a1 - a0) * f + b0 + (b1 - b0) * f) / 2.0;
                        (d < distance_m && (za - zb).abs() < CONFLICT_HEIGHT_M).then_some((d, at, (k as f64 + f) * STEP_S))
                    }
                    _ => None,
                };
                match (close, open.as_mut()) {
                    (Some((d, at, t)), Some(e)) => {
                        e.to_s = t;
                        if d < e.closest_m {
                            (e.closest_m, e.at) = (d, at);
                        }
                    }
                    (Some((d, at, t)), None) => open = Some(Encounter { vehicles: [i, j], from_s: t, to_s: t, closest_m: d, at }),
                    (None, _) => out.extend(open.take()),
                }
            }
            out.extend(open);
        }
    }
    out.sort_by(|a, b| a.from_s.total_cmp(&b.from_s));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::PieceEstimate;
    use crate::path::PieceKind;

    fn straight(a: Coord, b: Coord, seconds: f64) -> (FlightPath, PathEstimate) {
        let mut path = FlightPath::default();
        path.push(PieceKind::Transit, vec![a, b], 0.0);
        let e = PieceEstimate { speed_mps: distance(a, b) / seconds, duration_s: seconds, energy_j: 0.0, v_in_mps: 0.0, v_out_mps: 0.0, wind: None };
        (path, PathEstimate { pieces: vec![e], ..PathEstimate::default() })
    }

    #[test]
    fn crossing_paths_conflict_only_when_timed_together() {
        let c = |x, y| Coord { x, y };
        // two drones crossing at (50, 0) at 15 m/s, between samples
        let (p, e) = straight(c(0.0, 0.0), c(100.0, 0.0), 100.0 / 15.0);
        let (q, f) = straight(c(50.0, -50.0), c(50.0, 50.0), 100.0 / 15.0);
        let together = [Track::new(std::slice::from_ref(&p), std::slice::from_ref(&e), 0.0, 30.0), Track::new(std::slice::from_ref(&q), std::slice::from_ref(&f), 0.0, 30.0)];
        let found = encounters(&together, CONFLICT_DISTANCE_M);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].closest_m < 1.0 && distance(found[0].at, c(50.0, 0.0)) < 1.0, "{found:?}");
        // the second one leaves 20 s later: they never meet
        let apart = [Track::new(std::slice::from_ref(&p), std::slice::from_ref(&e), 0.0, 30.0), Track::new(std::slice::from_ref(&q), std::slice::from_ref(&f), 20.0, 30.0)];
        assert!(encounters(&apart, CONFLICT_DISTANCE_M).is_empty());
        // the same timing, 10 m apart vertically
        let layered = [Track::new(&[p], &[e], 0.0, 30.0), Track::new(&[q], &[f], 0.0, 40.0)];
        assert!(encounters(&layered, CONFLICT_DISTANCE_M).is_empty());
    }

    #[test]
    fn shared_homes_take_off_in_turn() {
        let h = Some(Coord { x: 0.0, y: 0.0 });
        let elsewhere = Some(Coord { x: 500.0, y: 0.0 });
        assert_eq!(departures(&[h, h, elsewhere, h], &[30.0, 20.0, 5.0, 1.0]), vec![0.0, 30.0, 0.0, 50.0]);
    }
}
