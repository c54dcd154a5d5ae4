//! Fixed-wing energy from the physics of steady flight (docs/methods.md, energy §8): parasitic and induced
//! power over an electrical efficiency, the induced part growing with the load factor of a
//! banked turn, climbs paying for the height gained.
//!
//! The default airframe ([`Airframe::default`]) is assumed, not measured: a 3 kg, 2.2 m-span
//! aircraft like seed 004's. Replace it with the airframe's own figures.

use serde::{Deserialize, Serialize};

use super::{EnergyModel, PieceEstimate, Vertical, heading_change};
use crate::error::{InputError, check_range};
use crate::geom::distance;
use crate::path::FlightPath;

const G: f64 = 9.81;

/// Seconds an autopilot following waypoints takes beyond the arc for each radian it turns: it
/// rolls in and out at each of the arc's corners (a roll time constant of about half a second)
/// and L1 guidance closes on each new leg gradually, so it flies the turn wider than the arc.
/// Measured with the follower (`export::follower`, ArduPlane's L1 defaults) over speeds of
/// 12-25 m/s and radii of 50-120 m: 0.41-0.59 s a radian (0.79 at 12 m/s and 120 m), 0.39 on
/// the random fields at 15 m/s (docs/flight-files.md).
pub const WAYPOINT_TURN_LAG_S_PER_RAD: f64 = 0.45;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Airframe {
    #[cfg_attr(feature = "schema", schema(minimum = 0.05, maximum = 1e4))]
    pub mass_kg: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 100.0))]
    pub wing_span_m: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 0.01, maximum = 1e3))]
    pub wing_area_m2: f64,
    /// Zero-lift drag coefficient.
    #[cfg_attr(feature = "schema", schema(minimum = 1e-4, maximum = 1.0))]
    pub drag_coefficient_zero_lift: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 1.0))]
    pub oswald_efficiency: f64,
    /// Battery to thrust power.
    #[cfg_attr(feature = "schema", schema(minimum = 0.05, maximum = 1.0))]
    pub propulsive_efficiency: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1e4))]
    pub avionics_power_w: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 2.0))]
    pub air_density_kg_m3: f64,
    /// Climb and descent rate for take-off and landing.
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 50.0))]
    pub climb_rate_mps: f64,
}

impl Default for Airframe {
    fn default() -> Self {
        Airframe {
            mass_kg: 3.0,
            wing_span_m: 2.2,
            wing_area_m2: 0.55,
            drag_coefficient_zero_lift: 0.030,
            oswald_efficiency: 0.80,
            propulsive_efficiency: 0.45,
            avionics_power_w: 8.0,
            air_density_kg_m3: 1.225,
            climb_rate_mps: 2.0,
        }
    }
}

impl Airframe {
    /// Checks every figure; `at` is the JSON pointer of the airframe.
    pub fn check(&self, at: &str) -> Result<(), InputError> {
        for (field, v, lo, hi) in [
            ("mass_kg", self.mass_kg, 0.05, 1e4),
            ("wing_span_m", self.wing_span_m, 0.1, 100.0),
            ("wing_area_m2", self.wing_area_m2, 0.01, 1e3),
            ("drag_coefficient_zero_lift", self.drag_coefficient_zero_lift, 1e-4, 1.0),
            ("oswald_efficiency", self.oswald_efficiency, 0.1, 1.0),
            ("propulsive_efficiency", self.propulsive_efficiency, 0.05, 1.0),
            ("avionics_power_w", self.avionics_power_w, 0.0, 1e4),
            ("air_density_kg_m3", self.air_density_kg_m3, 0.1, 2.0),
            ("climb_rate_mps", self.climb_rate_mps, 0.1, 50.0),
        ] {
            check_range(v, lo, hi, &format!("{at}/{field}"), "")?;
        }
        Ok(())
    }

    /// Electrical power at airspeed `v`, load factor `n` and vertical speed `v_z`.
    pub fn power_w(&self, v: f64, n: f64, v_z: f64) -> f64 {
        let (rho, s) = (self.air_density_kg_m3, self.wing_area_m2);
        let aspect = self.wing_span_m * self.wing_span_m / s;
        let parasitic = 0.5 * rho * v.powi(3) * s * self.drag_coefficient_zero_lift;
        let weight = n * self.mass_kg * G;
        let induced = 2.0 * weight * weight / (rho * v * s * std::f64::consts::PI * self.oswald_efficiency * aspect);
        let aero = parasitic + induced + self.mass_kg * G * v_z;
        aero.max(0.0) / self.propulsive_efficiency + self.avionics_power_w
    }

    /// Load factor of a level turn of radius `r` at `v`.
    pub fn load_factor(v: f64, r: f64) -> f64 {
        if r.is_infinite() {
            return 1.0;
        }
        (1.0 + (v * v / (G * r)).powi(2)).sqrt()
    }
}

pub struct FixedWing<'a> {
    pub airframe: &'a Airframe,
    pub speed_mps: f64,
    /// The tightest turn flown: sharper joints are taken as arcs of this radius.
    pub turn_radius_m: f64,
}

impl EnergyModel for FixedWing<'_> {
    fn pieces(&self, path: &FlightPath) -> Vec<PieceEstimate> {
        let v = self.speed_mps;
        // every segment of the path in order, with its piece
        let segments: Vec<(usize, usize)> = path.pieces.iter().enumerate().flat_map(|(i, p)| (1..p.points.len()).map(move |k| (i, k))).collect();
        let point = |(i, k): (usize, usize)| path.pieces[i].points[k];
        let turn_at = |j: usize| -> f64 {
            // heading change at the joint between segments j and j + 1
            if j + 1 >= segments.len() {
                return 0.0;
            }
            let (i, k) = segments[j];
            heading_change(path.pieces[i].points[k - 1], point(segments[j]), point(segments[j + 1]))
        };
        let mut pieces = vec![PieceEstimate::default(); path.pieces.len()];
        for (j, &(i, k)) in segments.iter().enumerate() {
            let piece = &path.pieces[i];
            let horizontal = distance(piece.points[k - 1], piece.points[k]);
            if horizontal < 1e-9 {
                continue;
            }
            let dz = match (piece.z.get(k - 1), piece.z.get(k)) {
                (Some(a), Some(b)) => b - a,
                _ => 0.0,
            };
            let turned = (if j > 0 { turn_at(j - 1) } else { 0.0 } + turn_at(j)) / 2.0;
            let radius = if turned > 1e-9 { (horizontal / turned).max(self.turn_radius_m) } else { f64::INFINITY };
            let t = horizontal.hypot(dz) / v;
            let power = self.airframe.power_w(v, Airframe::load_factor(v, radius), dz / t);
            let wider = WAYPOINT_TURN_LAG_S_PER_RAD * turned;
            let e = &mut pieces[i];
            e.speed_mps = v;
            e.v_in_mps = v;
            e.v_out_mps = v;
            e.duration_s += t + wider;
            e.energy_j += power * (t + wider);
        }
        pieces
    }

    fn holds_airspeed(&self) -> Option<f64> {
        Some(self.speed_mps)
    }

    /// Climbing and descending at the airframe's climb rate while cruising.
    fn takeoff_landing(&self, up_m: f64, down_m: f64) -> (f64, f64) {
        let (v, rate) = (self.speed_mps, self.airframe.climb_rate_mps);
        let up = self.airframe.power_w(v, 1.0, rate);
        let down = self.airframe.power_w(v, 1.0, -rate);
        ((up_m + down_m) / rate, up_m / rate * up + down_m / rate * down)
    }

    /// A fixed wing climbs after take-off while flying the first transit's climb-out, and
    /// glides down its landing approach (both pieces of the path, timed there): the ends add
    /// the climb's extra power only. Without an approach the flight ends over home, where the
    /// pilot lands it.
    fn flight_ends(&self, up_m: f64, _down_m: f64) -> [Vertical; 2] {
        let (v, rate) = (self.speed_mps, self.airframe.climb_rate_mps);
        let extra_w = self.airframe.power_w(v, 1.0, rate) - self.airframe.power_w(v, 1.0, 0.0);
        [Vertical { duration_s: 0.0, energy_j: up_m / rate * extra_w }, Vertical::default()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_match_the_spec_figures() {
        let a = Airframe::default();
        let level = a.power_w(15.0, 1.0, 0.0);
        assert!((level - 101.0).abs() < 0.05, "{level}");
        assert!((a.power_w(20.0, 1.0, 0.0) - 200.6).abs() < 0.05);
        assert!((Airframe::load_factor(15.0, 85.0) - 1.0358).abs() < 1e-4);
        assert!((a.power_w(15.0, Airframe::load_factor(15.0, 85.0), 0.0) - 102.3).abs() < 0.05);
        assert!((a.power_w(15.0, Airframe::load_factor(15.0, 40.0), 0.0) - 106.7).abs() < 0.05);
        assert!((a.power_w(15.0, 1.0, 2.0) - level - 130.8).abs() < 0.05);
    }

    #[test]
    fn tighter_arcs_cost_more_per_metre() {
        let a = Airframe::default();
        let arc = |r: f64| {
            let points: Vec<geo::Coord> = (0..=90).map(|k| (k as f64).to_radians()).map(|t| geo::Coord { x: r * t.sin(), y: r * (1.0 - t.cos()) }).collect();
            let mut p = FlightPath::default();
            p.push(crate::path::PieceKind::Turn, points, 0.0);
            let e = FixedWing { airframe: &a, speed_mps: 15.0, turn_radius_m: 30.0 }.estimate(&p, None);
            e.energy_j() / p.length()
        };
        let (wide, tight) = (arc(200.0), arc(40.0));
        let straight = a.power_w(15.0, 1.0, 0.0) / 15.0;
        assert!(straight < wide && wide < tight, "{straight} {wide} {tight}");
        // a quarter circle at the turn's power, flown for its length and the allowance of a
        // turn flown wider by an autopilot following waypoints
        let length = 40.0 * std::f64::consts::FRAC_PI_2;
        let seconds = length / 15.0 + WAYPOINT_TURN_LAG_S_PER_RAD * std::f64::consts::FRAC_PI_2;
        let expected = a.power_w(15.0, Airframe::load_factor(15.0, 40.0), 0.0) * seconds / length;
        assert!((tight - expected).abs() / tight < 0.01, "{tight} {expected}");
    }
}
