//! A fixed wing's connections in a steady wind (docs/methods.md, wind §5). At constant airspeed
//! and bank a turn is a circle in the air, which the wind carries into a trochoid over the
//! ground. A connection between two ground poses is a Dubins path in the air's frame, to the
//! target moved back by the wind over the flight time T (Techy & Woolsey 2009; McGee & Hedrick
//! 2005): for each word, a T with L(T) = V_a·T, by an accelerated fixed-point iteration, or where
//! that does not settle (a word's length jumps by a whole turn where one of its arcs wraps round)
//! by a scan and regula falsi that step over such jumps.

use geo::Coord;

use super::dubins::{self, DubinsPath, Part, Pose, Word, advance, arc_step, word_path};
use crate::wind::air_displacement;

/// The wind, and the airspeed the aircraft holds in it (faster than the wind).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drift {
    /// The air's velocity, m/s, local frame.
    pub wind: Coord,
    pub airspeed: f64,
}

/// A connection in wind: the air path and the time it takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trochoid {
    pub air: DubinsPath,
    pub time_s: f64,
    drift: Drift,
}

/// Steps of the scan for a word's flight time, over the longest time it can take.
const SCAN_STEPS: usize = 96;

impl Drift {
    /// The wind's speed, m/s.
    pub fn wind_speed(&self) -> f64 {
        self.wind.x.hypot(self.wind.y)
    }

    fn speed_ratio(&self) -> f64 {
        self.wind_speed() / self.airspeed
    }

    /// The air heading that keeps the ground track `track` (math radians).
    pub fn heading_for_track(&self, track: f64) -> f64 {
        let air = air_displacement(Coord { x: track.cos(), y: track.sin() }, self.wind, self.airspeed);
        air.y.atan2(air.x)
    }

    /// The ground radius on which a circle can be flown all round in this wind within the
    /// bank of an air radius `r`: r·(1 + w/V_a)² (the tightest point is downwind, where the
    /// ground speed is V_a + w).
    pub fn safe_radius(&self, r: f64) -> f64 {
        r * (1.0 + self.speed_ratio()).powi(2)
    }

    /// The longest any word's connection from `from` to `to` (air radius `r`) may take: no
    /// word is longer than the air distance plus two whole turns, and the target drifts at w
    /// (a third turn of slack).
    pub fn longest_time(&self, from: Pose, to: Pose, r: f64) -> f64 {
        let d = (to.x - from.x).hypot(to.y - from.y);
        (d + 3.0 * std::f64::consts::TAU * r) / (self.airspeed * (1.0 - self.speed_ratio()))
    }

    /// Each word's connection from `from` to `to` (poses on the ground, headings their ground
    /// tracks) flown on circles of air radius `r`, quickest first, found by the fixed point
    /// T = L(T) / V_a (L grows by at most w a second, so the iteration contracts by w / V_a);
    /// a word whose iteration does not settle (its length jumps) is left out.
    pub fn connections(&self, from: Pose, to: Pose, r: f64) -> Vec<Trochoid> {
        let (start, arrive) = self.air_ends(from, to);
        let mut found: Vec<Trochoid> = Word::ALL.iter().filter_map(|&word| self.settle(start, to.coord(), arrive, r, word)).collect();
        found.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
        found
    }

    /// Every connection of every word, quickest first: each word's flight times found by a
    /// scan over [`Self::longest_time`] and regula falsi, the later ones too (a word whose target
    /// has drifted past a whole loop of an arc arrives again later, which may be the way clear
    /// of a zone). Slower than [`Self::connections`]: for where none of those is clear.
    pub fn all_connections(&self, from: Pose, to: Pose, r: f64) -> Vec<Trochoid> {
        let (start, arrive) = self.air_ends(from, to);
        let mut found: Vec<Trochoid> = self.scan(start, to.coord(), arrive, r);
        found.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
        found
    }

    /// The air pose a connection leaves from and the air heading it arrives with.
    fn air_ends(&self, from: Pose, to: Pose) -> (Pose, f64) {
        (Pose { theta: self.heading_for_track(from.theta), ..from }, self.heading_for_track(to.theta))
    }

    /// `word`'s air path from `start` to where the ground point `to` is in the air after `t`.
    fn word_at(&self, start: Pose, to: Coord, arrive: f64, r: f64, word: Word, t: f64) -> Option<DubinsPath> {
        word_path(start, Pose::at(to - self.wind * t, arrive), r, word)
    }

    /// The fixed point of T = L(T) / V_a for `word`, from T = 0. The iteration contracts by
    /// q = w / V_a, slowly in a strong wind (up to 31 steps at q = 0.5), so each step is
    /// Steffensen's from two plain ones, kept where it lands within q / (1 − q) of their
    /// difference (where the contraction puts the fixed point), else the plain step: 7 to 9
    /// words priced.
    fn settle(&self, start: Pose, to: Coord, arrive: f64, r: f64, word: Word) -> Option<Trochoid> {
        let q = self.speed_ratio();
        let next = |t: f64| self.word_at(start, to, arrive, r, word, t).map(|air| (air.length() / self.airspeed, air));
        let settled = |t: f64, g: f64| (g - t).abs() <= 1e-9 * (1.0 + g);
        let mut t = 0.0;
        // after a leap: the plain step it replaced, and the path there
        let mut leapt_from: Option<(f64, DubinsPath)> = None;
        for _ in 0..100 {
            let here = next(t);
            if let Some((plain, before)) = leapt_from.take() {
                // a leap that made the word infeasible or wrapped an arc round a whole turn
                // crossed a jump of the length: the plain step instead
                if here.is_none_or(|(_, air)| wraps(&before, &air)) {
                    t = plain;
                    continue;
                }
            }
            let (g1, air) = here?;
            if settled(t, g1) {
                return Some(Trochoid { air, time_s: g1, drift: *self });
            }
            let (g2, air) = next(g1)?;
            if settled(g1, g2) {
                return Some(Trochoid { air, time_s: g2, drift: *self });
            }
            let curve = g2 - 2.0 * g1 + t;
            let leap = t - (g1 - t).powi(2) / curve;
            let within = q / (1.0 - q) * (g2 - g1).abs();
            t = if curve != 0.0 && leap >= 0.0 && (leap - g2).abs() <= within {
                leapt_from = Some((g2, air));
                leap
            } else {
                g2
            };
        }
        None
    }

    /// Every word's flight times within [`Self::longest_time`]: a scan of all six words at
    /// once (one normalised configuration a step), each sign change closed by [`Self::root_within`].
    fn scan(&self, start: Pose, to: Coord, arrive: f64, r: f64) -> Vec<Trochoid> {
        let va = self.airspeed;
        // how much each air path is longer than the time allows: positive too soon, negative late
        let excesses = |t: f64| dubins::each_word(start, Pose::at(to - self.wind * t, arrive), r).map(|p| p.map(|p| p.length() - va * t));
        let t_max = self.longest_time(start, Pose::at(to, arrive), r);
        let step = t_max / SCAN_STEPS as f64;
        let mut found = Vec::new();
        let mut before = excesses(0.0);
        for k in 1..=SCAN_STEPS {
            let t = k as f64 * step;
            let now = excesses(t);
            for (w, &word) in Word::ALL.iter().enumerate() {
                if let (Some(e0), Some(e1)) = (before[w], now[w])
                    && e0 > 0.0
                    && e1 <= 0.0
                {
                    let excess = |t: f64| self.word_at(start, to, arrive, r, word, t).map(|p| (p, p.length() - va * t));
                    found.extend(self.root_within(&excess, (t - step, e0), (t, e1)));
                }
            }
            before = now;
        }
        found
    }

    /// The root of `excess` between `lo` (positive) and `hi` (not), when it is one and not a
    /// jump of the word's length: regula falsi with the Illinois halving (a few steps where
    /// the length is smooth), bisection's bracket where it is not.
    fn root_within(&self, excess: &impl Fn(f64) -> Option<(DubinsPath, f64)>, (mut lo, mut e_lo): (f64, f64), (mut hi, mut e_hi): (f64, f64)) -> Option<Trochoid> {
        let mut last_side = 0;
        for _ in 0..100 {
            let mut t = hi - e_hi * (hi - lo) / (e_hi - e_lo);
            if !(t > lo && t < hi) {
                t = 0.5 * (lo + hi);
            }
            let (air, e) = excess(t)?;
            if e.abs() <= 1e-9 * (1.0 + air.length()) {
                return Some(Trochoid { air, time_s: air.length() / self.airspeed, drift: *self });
            }
            if e > 0.0 {
                (lo, e_lo) = (t, e);
                if last_side == 1 {
                    e_hi *= 0.5;
                }
                last_side = 1;
            } else {
                (hi, e_hi) = (t, e);
                if last_side == -1 {
                    e_lo *= 0.5;
                }
                last_side = -1;
            }
            if hi - lo <= 1e-12 * (1.0 + hi) {
                break;
            }
        }
        // a jump of the length: the bracket closed on it with no root
        None
    }
}

/// True when an arc of `b` differs from `a`'s by more than half a turn: the word's length
/// jumped between them.
fn wraps(a: &DubinsPath, b: &DubinsPath) -> bool {
    a.params.iter().zip(&b.params).any(|(x, y)| (x - y).abs() > std::f64::consts::PI)
}

impl Trochoid {
    /// Points over the ground from the start to the end: each air point carried by the wind
    /// for the time flown to it; arcs in steps whose chords stray at most `chord_tolerance_m`
    /// where the ground track bends most (upwind), straights by their ends.
    pub fn ground_points(&self, chord_tolerance_m: f64) -> Vec<Coord> {
        let Drift { wind, airspeed } = self.drift;
        let r = self.air.radius;
        // upwind the ground track is a circle of r·(1 − e)², turning 1 / (1 − e) times as fast
        // as the air heading
        let e = self.drift.speed_ratio();
        let step = arc_step(r * (1.0 - e).powi(2), chord_tolerance_m) * (1.0 - e);
        let mut out = vec![self.air.start.coord()];
        let (mut q, mut flown) = (self.air.start, 0.0);
        for (part, s) in self.air.segments() {
            if s <= 0.0 {
                continue;
            }
            let k = if part == Part::S { 1 } else { ((s / r) / step).ceil().max(1.0) as usize };
            for i in 1..=k {
                let along = s * i as f64 / k as f64;
                out.push(advance(q, part, along, r).coord() + wind * ((flown + along) / airspeed));
            }
            q = advance(q, part, s, r);
            flown += s;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wind::holding_airspeed;
    use geo::{Distance, Euclidean};
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    fn drift(w: f64, towards: f64) -> Drift {
        Drift { wind: Coord { x: w * towards.cos(), y: w * towards.sin() }, airspeed: 15.0 }
    }

    #[test]
    fn a_full_circle_in_wind_drifts_by_the_wind_over_its_time() {
        // a circle of 50 m flown at 15 m/s in 6 m/s: the ground track, integrated step by step,
        // ends w·2πr/V_a downwind of its start
        let d = drift(6.0, 0.3);
        let r = 50.0;
        let circle = Trochoid { air: DubinsPath { start: Pose::new(0.0, 0.0, 1.0), radius: r, word: Word::Lsl, params: [TAU, 0.0, 0.0] }, time_s: TAU * r / 15.0, drift: d };
        let points = circle.ground_points(0.01);
        let end = points[points.len() - 1];
        let expected = d.wind * (TAU * r / 15.0);
        assert!((end - expected).x.hypot((end - expected).y) < 1e-9, "{end:?} against {expected:?}");
        // numerical integration of the ground velocity V_a·(cos ψ, sin ψ) + w with ψ = ψ0 + V_a t / r
        let n = 200_000;
        let dt = circle.time_s / n as f64;
        let mut p = Coord { x: 0.0, y: 0.0 };
        let mut max_gap: f64 = 0.0;
        for i in 0..n {
            let psi = 1.0 + 15.0 * (i as f64 + 0.5) * dt / r;
            p = p + Coord { x: 15.0 * psi.cos(), y: 15.0 * psi.sin() } * dt + d.wind * dt;
            if (i + 1) % (n / 50) == 0 {
                // the sampled track passes within the chord tolerance of the integrated one
                let gap = points.windows(2).map(|w| Euclidean.distance(&geo::Point::from(p), &geo::Line::new(w[0], w[1]))).fold(f64::INFINITY, f64::min);
                max_gap = max_gap.max(gap);
            }
        }
        assert!((p - expected).x.hypot((p - expected).y) < 1e-3, "integrated end {p:?}");
        assert!(max_gap < 0.02, "the sampled trochoid strays {max_gap} m from the integrated one");
    }

    #[test]
    fn a_connection_arrives_where_and_how_it_should() {
        let r = 40.0;
        for (w, towards) in [(0.0, 0.0), (4.5, 0.0), (7.5, FRAC_PI_2), (7.5, 2.5), (7.0, PI)] {
            let d = drift(w, towards);
            for (to, heading) in [(Coord { x: 0.0, y: 30.0 }, PI), (Coord { x: 300.0, y: -80.0 }, 0.4), (Coord { x: -50.0, y: 10.0 }, -FRAC_PI_2)] {
                let from = Pose::new(0.0, 0.0, 0.0);
                let found = d.connections(from, Pose::at(to, heading), r);
                assert!(!found.is_empty(), "wind {w} towards {towards}: no connection to {to:?}");
                for t in &found {
                    let points = t.ground_points(0.05);
                    let end = points[points.len() - 1];
                    assert!((end - to).x.hypot((end - to).y) < 1e-4, "ends at {end:?}, not {to:?}");
                    // leaving and arriving on the ground tracks asked: the air heading that keeps them
                    assert!((t.air.start.theta - d.heading_for_track(0.0)).abs() < 1e-12);
                    // the time is the air path over the airspeed
                    assert!((t.time_s * 15.0 - t.air.length()).abs() < 1e-6);
                }
                assert!(found.windows(2).all(|p| p[0].time_s <= p[1].time_s));
                // the scan finds each word's connections too, the quickest no later
                let scanned = d.all_connections(from, Pose::at(to, heading), r);
                assert!(scanned[0].time_s <= found[0].time_s + 1e-6, "scan {} against {}", scanned[0].time_s, found[0].time_s);
                assert!(scanned.iter().all(|t| (t.time_s * 15.0 - t.air.length()).abs() < 1e-6));
                // the accelerated fixed point and the scan agree on every word they both find
                for t in &found {
                    let same_word = scanned.iter().filter(|s| s.air.word == t.air.word).map(|s| (s.time_s - t.time_s).abs()).fold(f64::INFINITY, f64::min);
                    assert!(same_word < 1e-6, "wind {w} towards {towards}, {:?}: settled at {} s, scanned {same_word} s off", t.air.word, t.time_s);
                }
                if w == 0.0 {
                    let still = super::super::dubins::shortest(from, Pose::at(to, heading), r);
                    assert!((found[0].air.length() - still.length()).abs() < 1e-6);
                }
            }
        }
    }

    #[test]
    fn the_safe_radius_holds_a_ground_circle_within_the_bank() {
        // flown at constant airspeed on a ground circle of the safe radius, the turn rate the
        // air heading needs never exceeds V_a / r anywhere round it
        let (r, d) = (50.0, drift(7.0, 1.1));
        let big = d.safe_radius(r);
        let n = 3600;
        let heading = |k: usize| d.heading_for_track(k as f64 * TAU / n as f64);
        for k in 0..n {
            let track = k as f64 * TAU / n as f64;
            let u = Coord { x: track.cos(), y: track.sin() };
            let ground = holding_airspeed(15.0, d.wind, u).ground_speed_mps;
            let dtrack_dt = ground / big;
            let dpsi = (heading(k + 1) - heading(k) + PI).rem_euclid(TAU) - PI;
            let rate = dpsi / (TAU / n as f64) * dtrack_dt;
            assert!(rate <= 15.0 / r * (1.0 + 1e-3), "at track {track:.2}: {rate} rad/s against {}", 15.0 / r);
        }
    }
}
