//! Shortest paths of a car that may reverse (Reeds and Shepp 1990): turning radius at least
//! `r`, forward or backward, cusps free. Every optimal path is one of 48 words of at most five
//! parts in the families CSC, C|C|C, CC|C, C|CC, CC|CC, C|CC|C, C|C_{π/2}SC, CSC_{π/2}|C and
//! C|C_{π/2}SC_{π/2}|C (`|` a cusp); each family's closed form is written for one word and
//! the others follow by symmetry: time-flip (drive it backwards), reflection (swap left and
//! right) and reversal (read it from the end) (docs/methods.md, ground §3).

use std::f64::consts::{FRAC_PI_2, PI};

use geo::Coord;

use super::dubins::{Part, Pose, advance, arc_step};

const MAX_PARTS: usize = 5;
/// Slack on the sign tests of the closed forms (normalised units).
const EPS: f64 = 1e-10;

/// A Reeds–Shepp path: up to five parts, each with its signed length (negative: in reverse;
/// arcs in radians, straights in radii).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReedsSheppPath {
    pub start: Pose,
    pub radius: f64,
    parts: [(Part, f64); MAX_PARTS],
    count: usize,
}

/// The angle in (-π, π].
fn wrap(a: f64) -> f64 {
    let v = a.rem_euclid(std::f64::consts::TAU);
    if v > PI { v - std::f64::consts::TAU } else { v }
}

fn polar(x: f64, y: f64) -> (f64, f64) {
    (x.hypot(y), y.atan2(x))
}

/// A closed form's word in its base orientation, when it exists: the parts and their signed
/// lengths.
type Found = Option<(&'static [Part], [f64; MAX_PARTS])>;
/// One family's closed form, of the goal `(x, y, φ)` in radii.
type Family = fn(f64, f64, f64) -> Found;

use Part::{L, R, S};

/// L+ S+ L+ (formula 8.1).
fn lsl(x: f64, y: f64, phi: f64) -> Found {
    let (u, t) = polar(x - phi.sin(), y - 1.0 + phi.cos());
    let v = wrap(phi - t);
    (t >= -EPS && v >= -EPS).then_some((&[L, S, L], [t, u, v, 0.0, 0.0]))
}

/// L+ S+ R+ (8.2).
fn lsr(x: f64, y: f64, phi: f64) -> Found {
    let (u1, t1) = polar(x + phi.sin(), y - 1.0 - phi.cos());
    let u1 = u1 * u1;
    if u1 < 4.0 {
        return None;
    }
    let u = (u1 - 4.0).sqrt();
    let t = wrap(t1 + 2.0f64.atan2(u));
    let v = wrap(t - phi);
    (t >= -EPS && v >= -EPS).then_some((&[L, S, R], [t, u, v, 0.0, 0.0]))
}

/// L+ R- L (8.3, 8.4).
fn lrl(x: f64, y: f64, phi: f64) -> Found {
    let (u1, theta) = polar(x - phi.sin(), y - 1.0 + phi.cos());
    if u1 > 4.0 {
        return None;
    }
    let u = -2.0 * (u1 / 4.0).asin();
    let t = wrap(theta + u / 2.0 + PI);
    let v = wrap(phi - t + u);
    (t >= -EPS && u <= EPS).then_some((&[L, R, L], [t, u, v, 0.0, 0.0]))
}

/// The last two parameters of the CC|CC and C|CC|C forms.
fn tau_omega(u: f64, v: f64, xi: f64, eta: f64, phi: f64) -> (f64, f64) {
    let delta = wrap(u - v);
    let a = u.sin() - delta.sin();
    let b = u.cos() - delta.cos() - 1.0;
    let t1 = (eta * a - xi * b).atan2(xi * a + eta * b);
    let t2 = 2.0 * (delta.cos() - v.cos() - u.cos()) + 3.0;
    let tau = if t2 < 0.0 { wrap(t1 + PI) } else { wrap(t1) };
    (tau, wrap(tau - u + v - phi))
}

/// L+ R+ L- R- (8.7).
fn lrlr_in(x: f64, y: f64, phi: f64) -> Found {
    let (xi, eta) = (x + phi.sin(), y - 1.0 - phi.cos());
    let rho = 0.25 * (2.0 + xi.hypot(eta));
    if rho > 1.0 {
        return None;
    }
    let u = rho.acos();
    let (t, v) = tau_omega(u, -u, xi, eta, phi);
    (t >= -EPS && v <= EPS).then_some((&[L, R, L, R], [t, u, -u, v, 0.0]))
}

/// L+ R- L- R+ (8.8).
fn lrlr_out(x: f64, y: f64, phi: f64) -> Found {
    let (xi, eta) = (x + phi.sin(), y - 1.0 - phi.cos());
    let rho = (20.0 - xi * xi - eta * eta) / 16.0;
    if !(0.0..=1.0).contains(&rho) {
        return None;
    }
    let u = -rho.acos();
    if u < -FRAC_PI_2 {
        return None;
    }
    let (t, v) = tau_omega(u, u, xi, eta, phi);
    (t >= -EPS && v >= -EPS).then_some((&[L, R, L, R], [t, u, u, v, 0.0]))
}

/// L+ R-π/2 S- L- (8.9).
fn lrsl(x: f64, y: f64, phi: f64) -> Found {
    let (rho, theta) = polar(x - phi.sin(), y - 1.0 + phi.cos());
    if rho < 2.0 {
        return None;
    }
    let r = (rho * rho - 4.0).sqrt();
    let u = 2.0 - r;
    let t = wrap(theta + r.atan2(-2.0));
    let v = wrap(phi - FRAC_PI_2 - t);
    (t >= -EPS && u <= EPS && v <= EPS).then_some((&[L, R, S, L], [t, -FRAC_PI_2, u, v, 0.0]))
}

/// L+ R-π/2 S- R- (8.10).
fn lrsr(x: f64, y: f64, phi: f64) -> Found {
    let (xi, eta) = (x + phi.sin(), y - 1.0 - phi.cos());
    let (rho, theta) = polar(-eta, xi);
    if rho < 2.0 {
        return None;
    }
    let t = theta;
    let u = 2.0 - rho;
    let v = wrap(t + FRAC_PI_2 - phi);
    (t >= -EPS && u <= EPS && v <= EPS).then_some((&[L, R, S, R], [t, -FRAC_PI_2, u, v, 0.0]))
}

/// L+ R-π/2 S- L-π/2 R+ (8.11).
fn lrslr(x: f64, y: f64, phi: f64) -> Found {
    let (xi, eta) = (x + phi.sin(), y - 1.0 - phi.cos());
    let (rho, _) = polar(xi, eta);
    if rho < 2.0 {
        return None;
    }
    let u = 4.0 - (rho * rho - 4.0).sqrt();
    if u > EPS {
        return None;
    }
    let t = wrap(((4.0 - u) * xi - 2.0 * eta).atan2(-2.0 * xi + (u - 4.0) * eta));
    let v = wrap(t - phi);
    (t >= -EPS && v >= -EPS).then_some((&[L, R, S, L, R], [t, -FRAC_PI_2, u, -FRAC_PI_2, v]))
}

/// The families, each with whether it is also read from the end: the forms with a cusp on one
/// side only (C|CC gives CC|C, C|C_{π/2}SC gives CSC_{π/2}|C).
const FAMILIES: [(Family, bool); 8] = [(lsl, false), (lsr, false), (lrl, true), (lrlr_in, false), (lrlr_out, false), (lrsl, true), (lrsr, true), (lrslr, false)];

impl ReedsSheppPath {
    /// Length in metres.
    pub fn length(&self) -> f64 {
        self.radius * self.parts().iter().map(|p| p.1.abs()).sum::<f64>()
    }

    /// The parts with their signed normalised lengths (negative: in reverse).
    pub fn parts(&self) -> &[(Part, f64)] {
        &self.parts[..self.count]
    }

    /// Whether any part of it is driven in reverse.
    pub fn reverses(&self) -> bool {
        self.parts().iter().any(|p| p.1 < -EPS)
    }

    /// Whether it has a straight part.
    pub fn has_straight(&self) -> bool {
        self.parts().iter().any(|p| p.0 == S && p.1.abs() > EPS)
    }

    /// The pose where the path ends (by following its parts).
    #[cfg(test)]
    fn end_pose(&self) -> Pose {
        self.parts().iter().fold(self.start, |q, &(part, s)| advance(q, part, s * self.radius, self.radius))
    }

    /// Points along the path: arcs with a chord error of at most `chord_tolerance_m` (at most
    /// 10° a step), straights by their ends, every cusp a point. The last point is the end.
    pub fn sample(&self, chord_tolerance_m: f64) -> Vec<Coord> {
        let r = self.radius;
        let step = arc_step(r, chord_tolerance_m);
        let mut out = vec![self.start.coord()];
        let mut q = self.start;
        for &(part, s) in self.parts() {
            if s.abs() <= EPS {
                continue;
            }
            let k = if part == S { 1 } else { (s.abs() / step).ceil().max(1.0) as usize };
            out.extend((1..k).map(|i| advance(q, part, s * r * i as f64 / k as f64, r).coord()));
            q = advance(q, part, s * r, r);
            out.push(q.coord());
        }
        out
    }
}

/// Every Reeds–Shepp word from `q0` to `q1` with radius `r > 0` that the closed forms give.
pub fn all_paths(q0: Pose, q1: Pose, r: f64) -> Vec<ReedsSheppPath> {
    debug_assert!(r > 0.0);
    // the goal in the start's frame, in radii
    let (dx, dy) = ((q1.x - q0.x) / r, (q1.y - q0.y) / r);
    let (s, c) = q0.theta.sin_cos();
    let (x, y, phi) = (dx * c + dy * s, -dx * s + dy * c, wrap(q1.theta - q0.theta));
    let (xb, yb) = (x * phi.cos() + y * phi.sin(), x * phi.sin() - y * phi.cos());
    let mut out = Vec::new();
    for (family, has_reversal) in FAMILIES {
        let readings: &[(f64, f64, bool)] = if has_reversal { &[(x, y, false), (xb, yb, true)] } else { &[(x, y, false)] };
        for &(x, y, backwards) in readings {
            // (goal, time-flipped, reflected)
            for (gx, gy, gphi, flip, reflect) in [(x, y, phi, false, false), (-x, y, -phi, true, false), (x, -y, -phi, false, true), (-x, -y, phi, true, true)] {
                let Some((parts, lengths)) = family(gx, gy, gphi) else { continue };
                let n = parts.len();
                let mut word = [(S, 0.0); MAX_PARTS];
                for (i, slot) in word.iter_mut().take(n).enumerate() {
                    let k = if backwards { n - 1 - i } else { i };
                    let part = match (parts[k], reflect) {
                        (L, true) => R,
                        (R, true) => L,
                        (p, _) => p,
                    };
                    *slot = (part, if flip { -lengths[k] } else { lengths[k] });
                }
                out.push(ReedsSheppPath { start: q0, radius: r, parts: word, count: n });
            }
        }
    }
    out
}

/// The shortest Reeds–Shepp path from `q0` to `q1` with radius `r > 0`.
pub fn shortest(q0: Pose, q1: Pose, r: f64) -> ReedsSheppPath {
    all_paths(q0, q1, r).into_iter().min_by(|a, b| a.length().total_cmp(&b.length())).expect("some Reeds–Shepp word always joins two poses")
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::TAU;

    fn pose() -> impl Strategy<Value = Pose> {
        (-60.0..60.0f64, -60.0..60.0f64, -PI..PI).prop_map(|(x, y, t)| Pose::new(x, y, t))
    }

    fn angle_gap(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(TAU);
        d.min(TAU - d)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Every word reaches the goal; the shortest is never longer than the forward-only
        /// path, is the same both ways round, and the samples follow it.
        #[test]
        fn words_reach_the_goal_and_the_shortest_beats_dubins(q0 in pose(), q1 in pose(), r in prop::sample::select(vec![1.0, 7.0, 30.0])) {
            let paths = all_paths(q0, q1, r);
            prop_assert!(!paths.is_empty());
            for p in &paths {
                let end = p.end_pose();
                prop_assert!((end.x - q1.x).hypot(end.y - q1.y) < 1e-6 * r, "{:?} misses by {}", p.parts(), (end.x - q1.x).hypot(end.y - q1.y));
                prop_assert!(angle_gap(end.theta, q1.theta) < 1e-6, "{:?} heading off", p.parts());
            }
            let best = shortest(q0, q1, r);
            let dubins = super::super::dubins::shortest(q0, q1, r).length();
            prop_assert!(best.length() <= dubins + 1e-9, "{} above the forward {}", best.length(), dubins);
            prop_assert!(best.length() >= (q1.x - q0.x).hypot(q1.y - q0.y) - 1e-9);
            let back = shortest(q1, q0, r).length();
            prop_assert!((back - best.length()).abs() < 1e-6 * r, "{} one way, {} the other", best.length(), back);
            let points = best.sample(0.01 * r);
            let sampled: f64 = points.windows(2).map(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y)).sum();
            prop_assert!(sampled <= best.length() + 1e-6 && sampled >= 0.998 * best.length() - 1e-6);
            let last = *points.last().unwrap();
            prop_assert!((last.x - q1.x).hypot(last.y - q1.y) < 1e-6 * r);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Against an independent implementation (the `reeds_shepp` crate, radius 1): never
        /// longer, and as long wherever it finds its optimum.
        #[test]
        fn as_short_as_an_independent_implementation(x in -8.0..8.0f64, y in -8.0..8.0f64, theta in -180.0..180.0f64) {
            let theirs = reeds_shepp_lib::get_optimal_path(
                reeds_shepp_lib::Pose { x: 0.0, y: 0.0, theta_degree: 0.0 },
                reeds_shepp_lib::Pose { x, y, theta_degree: theta },
            ).map(|p| reeds_shepp_lib::path_length(&p));
            let ours = shortest(Pose::new(0.0, 0.0, 0.0), Pose::new(x, y, theta.to_radians()), 1.0).length();
            let theirs = theirs.expect("the crate finds a path");
            prop_assert!((ours - theirs).abs() < 1e-6, "ours {ours}, theirs {theirs}");
        }
    }

    #[test]
    fn known_shortest_paths() {
        // straight back: a reverse of 10 m
        let p = shortest(Pose::new(0.0, 0.0, 0.0), Pose::new(-10.0, 0.0, 0.0), 5.0);
        assert!((p.length() - 10.0).abs() < 1e-9 && p.reverses());
        // side-step by a diameter, same heading: no forward path is shorter than 2πr - …, the
        // best reverses (a parallel-parking manoeuvre)
        let side = shortest(Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 2.0, 0.0), 1.0);
        assert!(side.reverses() && side.length() < super::super::dubins::shortest(Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 2.0, 0.0), 1.0).length());
        // turning round on the spot's neighbourhood: a half turn in place costs less than πr
        // forward plus the way back
        let about = shortest(Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 0.0, PI), 1.0);
        assert!(about.reverses() && about.length() < PI + 1e-9, "{}", about.length());
        // far ahead in the same heading: straight on, forward
        let ahead = shortest(Pose::new(0.0, 0.0, 0.0), Pose::new(100.0, 0.0, 0.0), 5.0);
        assert!(!ahead.reverses() && (ahead.length() - 100.0).abs() < 1e-9);
    }
}
