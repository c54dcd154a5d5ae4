//! The improved energy model (IEM) of seed 002 for multirotors (docs/methods.md, energy §1–§4): every
//! straight leg is flown at its own energy-optimal speed, accelerating from the speed kept
//! through the previous corner and slowing to the speed the next corner allows.
//!
//! The coefficients are the measured 3DR IRIS ones ([`IemCoefficients::iris`]); another
//! airframe needs its own identification.

use std::collections::HashMap;
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use geo::Coord;

use super::{EnergyModel, Leg, PieceEstimate, Vertical, legs, multirotor_landing, spread_over_pieces};
use crate::error::{InputError, check_range};
use crate::path::FlightPath;
use crate::wind::components;

/// Measured polynomials and rates of a multirotor (polynomials highest power first).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct IemCoefficients {
    /// Power in steady level flight against speed, W(m/s).
    #[cfg_attr(feature = "schema", schema(min_items = 1, max_items = 12))]
    pub level_power: Vec<f64>,
    /// Power while accelerating at 1 m/s², against the current speed.
    #[cfg_attr(feature = "schema", schema(min_items = 1, max_items = 12))]
    pub accel_power: Vec<f64>,
    /// Power while decelerating at 1 m/s², against the time since braking began from
    /// `decel_reference_mps`.
    #[cfg_attr(feature = "schema", schema(min_items = 1, max_items = 12))]
    pub decel_power: Vec<f64>,
    #[cfg_attr(feature = "schema", schema(minimum = 1e-3, maximum = 100.0))]
    pub decel_reference_mps: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 1e-3, maximum = 50.0))]
    pub climb_rate_mps: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 1e-3, maximum = 1e6))]
    pub climb_power_w: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 1e-3, maximum = 50.0))]
    pub descent_rate_mps: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 1e-3, maximum = 1e6))]
    pub descent_power_w: f64,
    /// Yaw in place: rate and power.
    #[cfg_attr(feature = "schema", schema(minimum = 1e-3, maximum = 3600.0))]
    pub yaw_rate_deg_s: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 1e-3, maximum = 1e6))]
    pub yaw_power_w: f64,
    /// Fraction of the leg speed kept into a corner, as knots `[interior angle °, fraction]`,
    /// linear between them.
    #[cfg_attr(feature = "schema", schema(min_items = 1))]
    pub exit_speed_fraction: Vec<[f64; 2]>,
    /// The autopilot turns to face each next waypoint (ArduCopter-style), costing yaw energy.
    #[serde(default = "yes")]
    pub yaw_at_waypoints: bool,
    /// Hover at each corner, seconds.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 600.0))]
    pub waypoint_hold_s: f64,
}

fn yes() -> bool {
    true
}

impl IemCoefficients {
    /// The 3DR IRIS of seed 002 (docs/methods.md, energy §1).
    pub fn iris() -> Self {
        IemCoefficients {
            level_power: vec![3.683806457168736e-03, 2.254081880192812e-02, -6.962411567465551e-01, 3.2981881218628495e-01, 2.212786072982807e+02],
            accel_power: vec![2.0278506913465286e-05, 1.4859611872955931e-02, -4.6042074697189045e-01, 5.152279814553939, -2.1182532841734336e+01, 2.3359704981556033e+02],
            decel_power: vec![1.072166051486935e-02, -4.9382831070964694e-01, 8.343857073684925, -5.7737401560222374e+01, 3.4187228951032466e+02],
            decel_reference_mps: 15.0,
            climb_rate_mps: 2.0912162162162167,
            climb_power_w: 249.01213766816142,
            descent_rate_mps: 1.2794117647058822,
            descent_power_w: 212.4678513196481,
            yaw_rate_deg_s: 36.0,
            yaw_power_w: 220.2112745098039,
            exit_speed_fraction: [
                (50.0, 0.0),
                (60.0, 0.041),
                (70.0, 0.0816667),
                (80.0, 0.1491667),
                (90.0, 0.4955),
                (100.0, 0.6733333),
                (110.0, 0.7108333),
                (120.0, 0.7225),
                (130.0, 0.7433333),
                (140.0, 0.7433333),
                (150.0, 0.7888333),
                (160.0, 0.827),
                (170.0, 0.8585),
                (180.0, 1.0),
            ]
            .iter()
            .map(|&(a, f)| [a, f])
            .collect(),
            // seed 002's flights kept the heading and did not stop at waypoints (its Tables 5
            // and 6 match the model so, not with yaw in place)
            yaw_at_waypoints: false,
            waypoint_hold_s: 0.0,
        }
    }

    /// Fraction of the speed kept through a heading change of `turn_deg` (0 = straight on).
    pub fn exit_fraction(&self, turn_deg: f64) -> f64 {
        let interior = 180.0 - turn_deg.abs().min(180.0);
        let knots = &self.exit_speed_fraction;
        let Some(first) = knots.first() else { return 0.0 };
        if interior <= first[0] {
            return first[1];
        }
        for w in knots.windows(2) {
            if interior <= w[1][0] {
                let t = (interior - w[0][0]) / (w[1][0] - w[0][0]);
                return w[0][1] + t * (w[1][1] - w[0][1]);
            }
        }
        knots.last().map_or(1.0, |k| k[1])
    }

    pub fn hover_power_w(&self) -> f64 {
        polyval(&self.level_power, 0.0)
    }

    /// Checks the coefficients for legs flown up to `cruise_speed_mps`; `at` is the JSON
    /// pointer of the coefficients.
    pub fn check(&self, cruise_speed_mps: f64, at: &str) -> Result<(), InputError> {
        let p = |field: &str| format!("{at}/{field}");
        for (field, poly) in [("level_power", &self.level_power), ("accel_power", &self.accel_power), ("decel_power", &self.decel_power)] {
            if poly.is_empty() || poly.len() > 12 || poly.iter().any(|k| !k.is_finite()) {
                return Err(InputError::new("invalid_energy_model", p(field), "a polynomial needs 1 to 12 finite coefficients, highest power first"));
            }
        }
        for (field, v, hi) in [
            ("decel_reference_mps", self.decel_reference_mps, 100.0),
            ("climb_rate_mps", self.climb_rate_mps, 50.0),
            ("climb_power_w", self.climb_power_w, 1e6),
            ("descent_rate_mps", self.descent_rate_mps, 50.0),
            ("descent_power_w", self.descent_power_w, 1e6),
            ("yaw_rate_deg_s", self.yaw_rate_deg_s, 3600.0),
            ("yaw_power_w", self.yaw_power_w, 1e6),
        ] {
            check_range(v, 1e-3, hi, &p(field), "")?;
        }
        check_range(self.waypoint_hold_s, 0.0, 600.0, &p("waypoint_hold_s"), "s")?;
        let knots_ok = !self.exit_speed_fraction.is_empty()
            && self.exit_speed_fraction.iter().all(|[a, f]| (0.0..=180.0).contains(a) && (0.0..=1.0).contains(f))
            && self.exit_speed_fraction.windows(2).all(|w| w[0][0] < w[1][0]);
        if !knots_ok {
            return Err(InputError::new("invalid_energy_model", p("exit_speed_fraction"), "knots [angle 0..180°, fraction 0..1] with increasing angles"));
        }
        if (0..=12).any(|k| polyval(&self.level_power, k as f64 * cruise_speed_mps / 12.0) <= 0.0) {
            return Err(InputError::new("invalid_energy_model", p("level_power"), "level power must be positive from 0 to the cruise speed"));
        }
        Ok(())
    }
}

pub fn polyval(c: &[f64], x: f64) -> f64 {
    c.iter().fold(0.0, |acc, &k| acc * x + k)
}

/// ∫ₐᵇ p(x) dx for a polynomial, highest power first.
fn integral(c: &[f64], a: f64, b: f64) -> f64 {
    let n = c.len();
    let anti = |x: f64| c.iter().enumerate().fold(0.0, |acc, (i, &k)| acc * x + k / (n - i) as f64) * x;
    anti(b) - anti(a)
}

/// One leg flown: its cruise speed, the speed it ends with, energy and time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegFlight {
    pub cruise_mps: f64,
    pub v_out: f64,
    pub energy_j: f64,
    pub duration_s: f64,
    /// Too short to reach the exit speed: the leg is one deceleration.
    pub short: bool,
}

impl IemCoefficients {
    /// Energy of accelerating (or braking) from `from` to `to` at 1 m/s².
    fn speed_change(&self, from: f64, to: f64) -> f64 {
        let r = self.decel_reference_mps;
        if to >= from { integral(&self.accel_power, from, to) } else { integral(&self.decel_power, r - from, r - to) }
    }

    /// Energy and time of a leg of length `d` entered at `v_in`, cruised at `v` over the ground
    /// and left at `p·v`, in a wind `(along, across)` the leg (m/s; level power at the airspeed
    /// the wind makes of `v`); `None` when no cruise phase fits.
    fn at_speed(&self, d: f64, v_in: f64, v: f64, p: f64, (along, across): (f64, f64)) -> Option<(f64, f64)> {
        let d1 = (v * v - v_in * v_in).abs() / 2.0;
        let d3 = (1.0 - p * p) * v * v / 2.0;
        let d2 = d - d1 - d3;
        if d2 < -1e-9 || v <= 0.0 {
            return None;
        }
        let d2 = d2.max(0.0);
        // with no wind the airspeed is exactly v
        let airspeed = (v - along).hypot(across);
        let energy = self.speed_change(v_in, v) + polyval(&self.level_power, airspeed) * d2 / v + self.speed_change(v, p * v);
        Some((energy, (v - v_in).abs() + d2 / v + v * (1.0 - p)))
    }

    /// The leg at its energy-optimal cruise speed, at most `cap` (docs/methods.md, energy §3).
    pub fn leg(&self, d: f64, v_in: f64, p: f64, cap: f64) -> LegFlight {
        self.leg_in_wind(d, v_in, p, cap, (0.0, 0.0))
    }

    /// [`Self::leg`] with a wind `(along, across)` the leg: the ground speed that costs least,
    /// the level power at its airspeed (docs/methods.md, wind §2).
    pub fn leg_in_wind(&self, d: f64, v_in: f64, p: f64, cap: f64, wind: (f64, f64)) -> LegFlight {
        if d < (1.0 - p * p) * v_in * v_in / 2.0 {
            let v_out = (v_in * v_in - 2.0 * d).max(0.0).sqrt();
            return LegFlight { cruise_mps: v_in, v_out, energy_j: self.speed_change(v_in, v_out), duration_s: v_in - v_out, short: true };
        }
        let energy = |v: f64| self.at_speed(d, v_in, v, p, wind).map(|(e, _)| e);
        // the fastest feasible speed on the accelerating branch is a candidate of its own
        let bound = ((2.0 * d + v_in * v_in) / (2.0 - p * p)).sqrt();
        let hi = if bound >= v_in { cap.min(bound) } else { cap };
        const SAMPLES: usize = 200;
        let mut best: Option<(f64, f64)> = None;
        let step = hi / SAMPLES as f64;
        let candidates = (1..=SAMPLES).map(|k| k as f64 * step).chain(std::iter::once(hi));
        for v in candidates {
            if let Some(e) = energy(v)
                && best.is_none_or(|(_, b)| e < b)
            {
                best = Some((v, e));
            }
        }
        let Some((mut v, mut e)) = best else {
            // no cruise at any sampled speed: brake as far as the leg allows
            let v_out = (v_in * v_in - 2.0 * d).max(0.0).sqrt();
            return LegFlight { cruise_mps: v_in, v_out, energy_j: self.speed_change(v_in, v_out), duration_s: v_in - v_out, short: true };
        };
        // golden-section refinement between the neighbouring samples
        let (mut a, mut b) = ((v - step).max(step * 1e-3), (v + step).min(hi));
        let g = (5f64.sqrt() - 1.0) / 2.0;
        let f = |x: f64| energy(x).unwrap_or(f64::INFINITY);
        while b - a > 1e-4 {
            let (x1, x2) = (b - g * (b - a), a + g * (b - a));
            if f(x1) <= f(x2) { b = x2 } else { a = x1 }
        }
        let refined = (a + b) / 2.0;
        if f(refined) < e {
            (v, e) = (refined, f(refined));
        }
        let (_, t) = self.at_speed(d, v_in, v, p, wind).expect("feasible");
        LegFlight { cruise_mps: v, v_out: p * v, energy_j: e, duration_s: t, short: false }
    }
}

/// The IEM applied to a whole path, with take-off and landing at the measured vertical rates.
pub struct Iem<'a> {
    pub coefficients: &'a IemCoefficients,
    /// Highest leg speed (the profile's one explicit speed limit).
    pub max_speed_mps: f64,
    /// Legs already flown by this model: splitting a route into sorties prices the same legs
    /// in many candidate sorties (a 220 km corridor: 7 s of the 7.3 s it took to plan).
    pub flown: LegMemo,
}

/// Each leg's speed search, by its exact figures (length, entry speed, exit fraction, speed
/// cap, wind along and across): the search is a pure function of them.
#[derive(Default)]
pub struct LegMemo(Mutex<HashMap<[u64; 6], LegFlight, foldhash::fast::FixedState>>);

/// Legs remembered at most; beyond, the memo starts again.
const MEMO_LEGS: usize = 1 << 20;

impl LegMemo {
    fn get_or(&self, key: [f64; 6], fly: impl FnOnce() -> LegFlight) -> LegFlight {
        let key = key.map(f64::to_bits);
        if let Some(f) = self.0.lock().ok().and_then(|m| m.get(&key).copied()) {
            return f;
        }
        let f = fly();
        if let Ok(mut m) = self.0.lock() {
            if m.len() >= MEMO_LEGS {
                m.clear();
            }
            m.insert(key, f);
        }
        f
    }
}

impl Iem<'_> {
    fn vertical(&self, up_m: f64, down_m: f64) -> (f64, f64) {
        let c = self.coefficients;
        let t = up_m / c.climb_rate_mps + down_m / c.descent_rate_mps;
        (t, up_m / c.climb_rate_mps * c.climb_power_w + down_m / c.descent_rate_mps * c.descent_power_w)
    }

    /// Flies `legs` in order from rest to rest.
    pub fn fly(&self, legs: &[Leg]) -> Vec<LegFlight> {
        self.fly_in_wind(legs, Coord { x: 0.0, y: 0.0 })
    }

    /// Flies `legs` in order from rest to rest in a wind blowing at `wind` (m/s, local frame).
    pub fn fly_in_wind(&self, legs: &[Leg], wind: Coord) -> Vec<LegFlight> {
        let c = self.coefficients;
        let mut v_in = 0.0;
        legs.iter()
            .enumerate()
            .map(|(i, leg)| {
                let p = if i + 1 == legs.len() { 0.0 } else { c.exit_fraction(leg.turn_after_deg) };
                let (along, across) = components(wind, leg.direction);
                let key = [leg.length_m, v_in, p, self.max_speed_mps, along, across];
                let mut f = self.flown.get_or(key, || c.leg_in_wind(leg.length_m, v_in, p, self.max_speed_mps, (along, across)));
                v_in = f.v_out;
                // the corner: yaw towards the next waypoint, and any hold
                let yaw_s = if c.yaw_at_waypoints { leg.turn_after_deg.abs() / c.yaw_rate_deg_s } else { 0.0 };
                let hold_s = if i + 1 < legs.len() { c.waypoint_hold_s } else { 0.0 };
                f.duration_s += yaw_s + hold_s;
                f.energy_j += yaw_s * c.yaw_power_w + hold_s * c.hover_power_w();
                let (t, e) = self.vertical(leg.climb_m, leg.descent_m);
                f.duration_s += t;
                f.energy_j += e;
                f
            })
            .collect()
    }
}

impl EnergyModel for Iem<'_> {
    fn pieces(&self, path: &FlightPath) -> Vec<PieceEstimate> {
        self.pieces_in_wind(path, Coord { x: 0.0, y: 0.0 })
    }

    /// The autopilot holds each leg's ground speed; the wind changes the airspeed, and so the
    /// level power and the speed that costs least.
    fn pieces_in_wind(&self, path: &FlightPath, wind: Coord) -> Vec<PieceEstimate> {
        let legs = legs(path);
        let flown = self.fly_in_wind(&legs, wind);
        spread_over_pieces(path, &legs, &flown, |f| PieceEstimate {
            speed_mps: f.cruise_mps,
            duration_s: f.duration_s,
            energy_j: f.energy_j,
            v_in_mps: 0.0,
            v_out_mps: f.v_out,
            wind: None,
        })
    }

    fn takeoff_landing(&self, up_m: f64, down_m: f64) -> (f64, f64) {
        self.vertical(up_m, down_m)
    }

    fn flight_ends(&self, up_m: f64, down_m: f64) -> [Vertical; 2] {
        [Vertical::new(self.vertical(up_m, 0.0)), multirotor_landing(down_m, |d| self.vertical(0.0, d), self.coefficients.hover_power_w())]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference legs of the improved model (docs/methods.md, energy §3): (v_in, d, heading change or None = stop, E, t, v*, v_out).
    type Vector = (f64, f64, Option<f64>, f64, f64, f64, f64);
    const VECTORS: [Vector; 7] = [
        (0.0, 100.0, None, 4371.6, 20.62, 7.800, 0.0),
        (0.0, 100.0, Some(90.0), 3707.3, 17.71, 7.800, 3.865),
        (0.0, 100.0, Some(45.0), 3542.2, 16.98, 7.800, 5.798),
        (3.0, 50.0, Some(90.0), 1863.4, 8.88, 7.800, 3.865),
        (0.0, 20.0, Some(90.0), 1532.4, 7.18, 4.775, 2.366),
        (0.0, 10.0, None, 1384.9, 6.32, 3.162, 0.0),
        (5.0, 200.0, Some(30.0), 5437.5, 26.32, 7.800, 6.153),
    ];

    #[test]
    fn legs_match_the_reference_vectors() {
        let c = IemCoefficients::iris();
        for (v_in, d, turn, e, t, v, v_out) in VECTORS {
            let p = turn.map_or(0.0, |a| c.exit_fraction(a));
            let leg = c.leg(d, v_in, p, 7.8);
            assert!((leg.energy_j - e).abs() <= 0.1 + e * 1e-5, "{v_in} {d} {turn:?}: E {} against {e}", leg.energy_j);
            assert!((leg.duration_s - t).abs() <= 0.01, "{v_in} {d} {turn:?}: t {} against {t}", leg.duration_s);
            assert!((leg.cruise_mps - v).abs() <= 0.002, "{v_in} {d} {turn:?}: v* {} against {v}", leg.cruise_mps);
            assert!((leg.v_out - v_out).abs() <= 0.002, "{v_in} {d} {turn:?}: v_out {} against {v_out}", leg.v_out);
        }
    }

    #[test]
    fn exit_fractions_follow_the_interior_angle() {
        let c = IemCoefficients::iris();
        assert_eq!(c.exit_fraction(0.0), 1.0);
        assert!((c.exit_fraction(90.0) - 0.4955).abs() < 1e-12);
        assert_eq!(c.exit_fraction(150.0), 0.0);
        assert!((c.exit_fraction(15.0) - (0.827 + 0.8585) / 2.0).abs() < 1e-9);
    }

    #[test]
    fn a_leg_too_short_to_brake_is_one_deceleration_with_positive_energy() {
        let c = IemCoefficients::iris();
        let leg = c.leg(2.0, 7.0, 0.0, 7.8);
        assert!(leg.short && leg.energy_j > 0.0);
        assert!((leg.v_out - (49.0f64 - 4.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn polynomials_integrate_exactly() {
        // ∫₀² (3x² + 2x + 1) dx = 8 + 4 + 2
        assert!((integral(&[3.0, 2.0, 1.0], 0.0, 2.0) - 14.0).abs() < 1e-12);
        assert!((IemCoefficients::iris().hover_power_w() - 221.2786).abs() < 1e-3);
    }
}
