//! Continuous-curvature turns (Fraichard and Scheuer 2004), for a vehicle whose steering
//! changes the curvature at most `σ` per metre. A turn of deflection `δ` is a clothoid from
//! straight to the tightest curvature `κ = 1/r` (length `κ/σ`), an arc, and a clothoid back
//! (below `δ_min = κ²/σ`, two clothoids of a gentler sharpness meeting at a lower peak). Every
//! such turn starts and ends on the circle `C_Ω` of radius `R_Ω` about the arc's centre, its
//! heading `μ` off that circle's tangent, so its straight ends are tangent to the circle of
//! radius `R_Ω cos μ`: the six Dubins words follow with these turns in place of arcs (CC-Dubins;
//! docs/methods.md, ground §3). The headland is planned on `R_Ω`, which bounds every turn.

use std::f64::consts::{FRAC_PI_2, TAU};

use geo::Coord;

use super::dubins::{Part, Pose, Word, arc_step};

/// A stretch along which the curvature goes linearly from `k0` to `k1` (1/m, positive left).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    length: f64,
    k0: f64,
    k1: f64,
}

/// Integration steps along a piece, at most this long and turning at most this much: well
/// under a millimetre of error.
const STEP_M: f64 = 0.05;
const STEP_RAD: f64 = 0.005;

/// Follows `pieces` from `from`, handing `emit` a point whenever the heading has turned by
/// `emit_step` since the last one and at the end of every piece; returns the pose reached.
/// Circles and straights are exact in steps of `emit_step`; clothoids are integrated in small
/// steps, each the chord of the circle that turns the step's exact heading change. The heading
/// is carried as a unit vector turned by small-angle series (sines and cosines cost the most).
fn follow(from: Pose, pieces: &[Piece], emit_step: f64, mut emit: impl FnMut(Coord)) -> Pose {
    let (mut x, mut y, mut theta) = (from.x, from.y, from.theta);
    let (mut sin, mut cos) = theta.sin_cos();
    let mut turned = 0.0;
    for p in pieces.iter().filter(|p| p.length > 0.0) {
        let n = if p.k0 == p.k1 {
            (p.k0.abs() * p.length / emit_step).ceil().max(1.0)
        } else {
            let turned_by = (p.k0 + p.k1).abs() * p.length / 2.0;
            (p.length / STEP_M).max(turned_by / STEP_RAD).ceil().max(1.0)
        } as usize;
        let h = p.length / n as f64;
        let rate = (p.k1 - p.k0) / p.length;
        for i in 0..n {
            let s = i as f64 * h;
            let dtheta = p.k0 * h + rate * (2.0 * s * h + h * h) / 2.0;
            let half = dtheta / 2.0;
            let (sh, ch) = small_sin_cos(half);
            let chord = if half.abs() < 1e-12 { h } else { h * sh / half };
            // the chord leaves half-way round; the heading turns the other half after it
            let (dx, dy) = (cos * ch - sin * sh, sin * ch + cos * sh);
            x += chord * dx;
            y += chord * dy;
            (cos, sin) = (dx * ch - dy * sh, dy * ch + dx * sh);
            theta += dtheta;
            turned += dtheta.abs();
            if turned >= emit_step && i + 1 < n {
                emit(Coord { x, y });
                turned = 0.0;
            }
        }
        emit(Coord { x, y });
        turned = 0.0;
    }
    Pose::new(x, y, theta)
}

/// `(sin a, cos a)`, by series for the small angles of integration steps.
fn small_sin_cos(a: f64) -> (f64, f64) {
    if a.abs() < 0.01 {
        let a2 = a * a;
        (a * (1.0 - a2 / 6.0 * (1.0 - a2 / 20.0)), 1.0 - a2 / 2.0 * (1.0 - a2 / 12.0))
    } else {
        a.sin_cos()
    }
}

/// The continuous-curvature turns of one vehicle: its radius, sharpness and their circles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcTurns {
    r: f64,
    sigma: f64,
    /// Length of the clothoid from straight to `1/r`.
    clothoid: f64,
    /// Deflection of the two clothoids of a full turn, `κ²/σ`.
    delta_min: f64,
    /// The turn's centre seen from its start: `xc` ahead, `yc` to the side.
    xc: f64,
    yc: f64,
}

/// One part of a CC path: a turn to the left (`side` 1) or right (-1) by `delta`, or a straight.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Element {
    Turn { side: f64, delta: f64 },
    Straight(f64),
}

/// A CC-Dubins path from `start`.
#[derive(Debug, Clone, PartialEq)]
pub struct CcPath {
    pub start: Pose,
    pub word: Word,
    pub length: f64,
    /// The deflection of the middle turn of a CCC word (0 for CSC).
    middle_turn: f64,
    pieces: Vec<Piece>,
    /// The tightest radius, for sampling.
    r: f64,
}

impl CcTurns {
    /// Turns of minimum radius `r` with curvature rate `sigma` (1/m²).
    pub fn new(r: f64, sigma: f64) -> Self {
        let kappa = 1.0 / r;
        let clothoid = kappa / sigma;
        let delta_min = kappa * clothoid;
        let end = follow(Pose::new(0.0, 0.0, 0.0), &[Piece { length: clothoid, k0: 0.0, k1: kappa }], f64::INFINITY, |_| {});
        let (xc, yc) = (end.x - r * (delta_min / 2.0).sin(), end.y + r * (delta_min / 2.0).cos());
        CcTurns { r, sigma, clothoid, delta_min, xc, yc }
    }

    /// `R_Ω`: every turn stays within this distance of its centre.
    pub fn outer_radius(&self) -> f64 {
        self.xc.hypot(self.yc)
    }

    /// How far a quarter turn reaches ahead and to the side (the two are equal by symmetry).
    pub fn quarter_reach(&self) -> f64 {
        self.xc + self.yc
    }

    /// The curvature profile of a turn by `delta` (0 ≤ delta < 2π) to `side`, or `None`
    /// where the steering cannot make it end on the circle.
    fn turn(&self, side: f64, delta: f64) -> Option<Vec<Piece>> {
        let kappa = 1.0 / self.r;
        if delta >= self.delta_min {
            let arc = (delta - self.delta_min) * self.r;
            return Some(vec![
                Piece { length: self.clothoid, k0: 0.0, k1: side * kappa },
                Piece { length: arc, k0: side * kappa, k1: side * kappa },
                Piece { length: self.clothoid, k0: side * kappa, k1: 0.0 },
            ]);
        }
        // two clothoids of length `l` and sharpness δ/l²: the shape scales with `l`, which is
        // set so that the end lies on the circle |l·w − c| = R_Ω, c = (xc, yc)
        let unit = [Piece { length: 1.0, k0: 0.0, k1: delta }, Piece { length: 1.0, k0: delta, k1: 0.0 }];
        let w = follow(Pose::new(0.0, 0.0, 0.0), &unit, f64::INFINITY, |_| {});
        let l = 2.0 * (w.x * self.xc + w.y * self.yc) / (w.x * w.x + w.y * w.y);
        if delta == 0.0 {
            return Some(vec![Piece { length: 2.0 * l, k0: 0.0, k1: 0.0 }]);
        }
        let peak = delta / l;
        (l > 0.0 && peak <= kappa * (1.0 + 1e-9) && delta / (l * l) <= self.sigma * (1.0 + 1e-9))
            .then(|| vec![Piece { length: l, k0: 0.0, k1: side * peak }, Piece { length: l, k0: side * peak, k1: 0.0 }])
    }

    /// The turn's centre for a turn starting at `q` to `side`.
    fn centre_from(&self, q: Pose, side: f64) -> Coord {
        let (s, c) = q.theta.sin_cos();
        Coord { x: q.x + self.xc * c - side * self.yc * s, y: q.y + self.xc * s + side * self.yc * c }
    }

    /// The turn's centre for a turn ending at `q` to `side`.
    fn centre_to(&self, q: Pose, side: f64) -> Coord {
        let (s, c) = q.theta.sin_cos();
        Coord { x: q.x - self.xc * c - side * self.yc * s, y: q.y - self.xc * s + side * self.yc * c }
    }

    /// Every CC-Dubins word from `from` to `to` that the steering can drive, each CCC word
    /// with both choices of its middle circle.
    pub fn words(&self, from: Pose, to: Pose) -> Vec<CcPath> {
        let mut out = Vec::new();
        for word in Word::ALL {
            let sides = word.parts().map(|p| match p {
                Part::L => 1.0,
                Part::R => -1.0,
                Part::S => 0.0,
            });
            let candidates = if sides[1] == 0.0 { self.csc(from, to, sides[0], sides[2]).into_iter().collect() } else { self.ccc(from, to, sides[0]) };
            for elements in candidates {
                if let Some(path) = self.build(from, word, &elements) {
                    out.push(path);
                }
            }
        }
        out
    }

    fn csc(&self, from: Pose, to: Pose, s1: f64, s2: f64) -> Option<[Element; 3]> {
        let (c1, c2) = (self.centre_from(from, s1), self.centre_to(to, s2));
        let v = c2 - c1;
        let d = v.x.hypot(v.y);
        let base = v.y.atan2(v.x);
        let (psi, tangent) = if s1 == s2 {
            (base, d)
        } else {
            if d < 2.0 * self.yc {
                return None;
            }
            let l = (d * d - 4.0 * self.yc * self.yc).sqrt();
            (base + s1 * (2.0 * self.yc).atan2(l), l)
        };
        let straight = tangent - 2.0 * self.xc;
        (straight >= -1e-9).then(|| {
            [
                Element::Turn { side: s1, delta: deflection(s1 * (psi - from.theta)) },
                Element::Straight(straight.max(0.0)),
                Element::Turn { side: s2, delta: deflection(s2 * (to.theta - psi)) },
            ]
        })
    }

    fn ccc(&self, from: Pose, to: Pose, s: f64) -> Vec<[Element; 3]> {
        let (c1, c3) = (self.centre_from(from, s), self.centre_to(to, s));
        let big = self.outer_radius();
        let v = c3 - c1;
        let d = v.x.hypot(v.y);
        if d > 4.0 * big || d < 1e-9 {
            return Vec::new();
        }
        let mid = (c1 + c3) / 2.0;
        let height = (4.0 * big * big - d * d / 4.0).max(0.0).sqrt();
        let across = Coord { x: -v.y / d, y: v.x / d };
        [1.0, -1.0]
            .map(|k| {
                let c2 = mid + across * (k * height);
                let (q12, q23) = ((c1 + c2) / 2.0, (c2 + c3) / 2.0);
                let theta12 = (c1.y - q12.y).atan2(c1.x - q12.x) - (s * self.yc).atan2(-self.xc);
                let theta23 = (c3.y - q23.y).atan2(c3.x - q23.x) - (s * self.yc).atan2(self.xc);
                [
                    Element::Turn { side: s, delta: deflection(s * (theta12 - from.theta)) },
                    Element::Turn { side: -s, delta: deflection(-s * (theta23 - theta12)) },
                    Element::Turn { side: s, delta: deflection(s * (to.theta - theta23)) },
                ]
            })
            .to_vec()
    }

    fn build(&self, start: Pose, word: Word, elements: &[Element]) -> Option<CcPath> {
        let mut pieces = Vec::with_capacity(7);
        for e in elements {
            match *e {
                Element::Turn { side, delta } => pieces.extend(self.turn(side, delta)?),
                Element::Straight(l) => pieces.push(Piece { length: l, k0: 0.0, k1: 0.0 }),
            }
        }
        let length = pieces.iter().map(|p| p.length).sum();
        let middle_turn = match elements[1] {
            Element::Turn { delta, .. } => delta,
            Element::Straight(_) => 0.0,
        };
        Some(CcPath { start, word, length, middle_turn, pieces, r: self.r })
    }

    /// A left quarter turn from the origin facing +x, as points (the origin left out); it ends
    /// at `(reach, reach)` facing +y. Its length is the second value.
    pub fn quarter_turn(&self, chord_tolerance_m: f64) -> (Vec<Coord>, f64) {
        let pieces = self.turn(1.0, FRAC_PI_2).expect("a quarter turn always ends on the circle");
        let mut points = Vec::new();
        follow(Pose::new(0.0, 0.0, 0.0), &pieces, arc_step(self.r, chord_tolerance_m), |p| points.push(p));
        let reach = self.quarter_reach();
        *points.last_mut().expect("a turn has points") = Coord { x: reach, y: reach };
        (points, pieces.iter().map(|p| p.length).sum())
    }

    /// A half turn to `side` from the origin facing +x, as points from the origin on: the room
    /// a turn at a swath's end needs.
    pub fn half_turn(&self, side: f64, chord_tolerance_m: f64) -> Vec<Coord> {
        let pieces = self.turn(side, std::f64::consts::PI).expect("a half turn always ends on the circle");
        let mut points = vec![Coord { x: 0.0, y: 0.0 }];
        follow(Pose::new(0.0, 0.0, 0.0), &pieces, arc_step(self.r, chord_tolerance_m), |p| points.push(p));
        points
    }

    /// How far ahead of its start a half turn reaches: to the arc's centre, then a radius on.
    pub fn reach_ahead(&self) -> f64 {
        if self.delta_min < std::f64::consts::PI { self.xc + self.r } else { self.half_turn(1.0, 0.01).iter().map(|p| p.x).fold(0.0, f64::max) }
    }
}

/// A turn's deflection in [0, 2π), a hair below zero read as none.
fn deflection(a: f64) -> f64 {
    let d = a.rem_euclid(TAU);
    if d > TAU - 1e-9 { 0.0 } else { d }
}

impl CcPath {
    /// Whether it bulges out: its middle turn turns against the others by more than a quarter
    /// turn (a CCC word whose middle turn is slight is a U turn with a kink for a straight).
    pub fn is_omega(&self) -> bool {
        self.middle_turn > FRAC_PI_2
    }

    /// The pose where following the curvature profile ends.
    #[cfg(test)]
    fn end_pose(&self) -> Pose {
        follow(self.start, &self.pieces, f64::INFINITY, |_| {})
    }

    /// Points along the path, at most `chord_tolerance_m` off it on the tightest arc; the first
    /// is the start, the last the end.
    pub fn sample(&self, chord_tolerance_m: f64) -> Vec<Coord> {
        let mut points = vec![self.start.coord()];
        follow(self.start, &self.pieces, arc_step(self.r, chord_tolerance_m), |p| points.push(p));
        points
    }

    /// The largest change of curvature per metre and the largest curvature along the path.
    #[cfg(test)]
    fn steering_extremes(&self) -> (f64, f64) {
        let rate = self.pieces.iter().filter(|p| p.length > 0.0).map(|p| (p.k1 - p.k0).abs() / p.length).fold(0.0, f64::max);
        let kappa = self.pieces.iter().map(|p| p.k0.abs().max(p.k1.abs())).fold(0.0, f64::max);
        (rate, kappa)
    }
}

/// The radius of the circle bounding continuous-curvature turns of minimum radius `r` and
/// curvature rate `sigma` (1/m²).
pub fn cc_circle_radius(r: f64, sigma: f64) -> f64 {
    CcTurns::new(r, sigma).outer_radius()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    #[test]
    fn the_circle_grows_as_the_steering_slows() {
        // a clothoid of length L moves the circle's centre out by about L² / (24 r)
        let (r, sigma) = (7.0, 0.02);
        let l = 1.0 / (r * sigma);
        let shift = l * l / (24.0 * r);
        let big = cc_circle_radius(r, sigma);
        // the centre lies about L/2 along and r + shift across
        assert!((big - (l / 2.0).hypot(r + shift)).abs() < 0.05, "{big}");
        assert!(cc_circle_radius(r, 0.05) < big);
        assert!((cc_circle_radius(r, 10.0) - r).abs() < 0.01);
    }

    fn pose() -> impl Strategy<Value = Pose> {
        (-80.0..80.0f64, -80.0..80.0f64, -PI..PI).prop_map(|(x, y, t)| Pose::new(x, y, t))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Every word drives to the goal pose with curvature at most 1/r changing at most σ per
        /// metre; the shortest is never shorter than the Dubins path on r (whose arcs are the
        /// tightest) and the samples follow it. The steering reaches full lock within a quarter
        /// turn (`δ_min ≤ π/2`, the least rate the vehicle check accepts).
        #[test]
        fn words_reach_the_goal_within_the_steering(q0 in pose(), q1 in pose(), r in 3.0..12.0f64, delta_min in 0.01..FRAC_PI_2) {
            let sigma = 1.0 / (r * r * delta_min);
            let cc = CcTurns::new(r, sigma);
            // the turns the headland is planned with exist
            let _ = (cc.quarter_turn(0.05), cc.half_turn(1.0, 0.05), cc.half_turn(-1.0, 0.05));
            let words = cc.words(q0, q1);
            prop_assert!(!words.is_empty(), "no word");
            let dubins = super::super::dubins::shortest(q0, q1, r).length();
            for w in &words {
                let end = w.end_pose();
                prop_assert!((end.x - q1.x).hypot(end.y - q1.y) < 1e-3, "{:?} misses by {}", w.word, (end.x - q1.x).hypot(end.y - q1.y));
                let gap = (end.theta - q1.theta).rem_euclid(TAU);
                prop_assert!(gap.min(TAU - gap) < 1e-6, "{:?} heading off by {}", w.word, gap);
                let (rate, kappa) = w.steering_extremes();
                prop_assert!(rate <= sigma * (1.0 + 1e-6) && kappa <= (1.0 + 1e-6) / r, "{:?}: rate {rate}, curvature {kappa}", w.word);
                prop_assert!(w.length >= dubins - 1e-6, "{:?} {} under Dubins {}", w.word, w.length, dubins);
                let points = w.sample(0.05);
                let sampled: f64 = points.windows(2).map(|p| (p[1] - p[0]).x.hypot((p[1] - p[0]).y)).sum();
                prop_assert!(sampled <= w.length + 1e-6 && sampled >= 0.995 * w.length - 1e-6, "sampled {sampled} of {}", w.length);
            }
        }
    }

    #[test]
    fn a_u_turn_is_wider_and_longer_than_on_arcs() {
        let (r, sigma) = (7.0, 0.02);
        let cc = CcTurns::new(r, sigma);
        let (from, to) = (Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 30.0, PI));
        let best = cc.words(from, to).into_iter().min_by(|a, b| a.length.total_cmp(&b.length)).unwrap();
        let arcs = super::super::dubins::shortest(from, to, r).length();
        assert!(!best.is_omega());
        assert!(best.length > arcs, "{} vs {arcs}", best.length);
        // it bulges out ahead by the quarter turn's reach, more than the radius
        let ahead = best.sample(0.05).iter().map(|p| p.x).fold(f64::MIN, f64::max);
        assert!(ahead > r + 0.5 && ahead <= cc.quarter_reach() + 1e-3, "{ahead}");
        // a quarter turn ends where its reach says, facing +y
        let end = follow(Pose::new(0.0, 0.0, 0.0), &cc.turn(1.0, FRAC_PI_2).unwrap(), f64::INFINITY, |_| {});
        let reach = cc.quarter_reach();
        assert!((end.x - reach).hypot(end.y - reach) < 1e-3 && (end.theta - FRAC_PI_2).abs() < 1e-9, "{end:?}");
        assert!(cc.quarter_turn(0.05).1 > FRAC_PI_2 * r);
    }
}
