//! The simplest energy model, for vehicles without a measured one: the vehicle cruises at its
//! cruise speed drawing one power figure; a multirotor stops at every corner sharper than
//! 0.5° (decelerating and accelerating at `acceleration_mps2`), which costs `v/a` seconds more
//! than flying the same distance at cruise speed, at cruise power. Take-off and landing climb
//! and descend at `vertical_speed_mps`, at the same power.

use serde::{Deserialize, Serialize};

use super::{EnergyModel, PieceEstimate, Vertical, heading_change, multirotor_landing};
use crate::error::{InputError, check_range};
use crate::path::FlightPath;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct PowerFigures {
    /// Electrical power drawn in flight.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 1e6))]
    pub cruise_power_w: f64,
    /// Take-off climb and landing descent rate.
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 50.0))]
    pub vertical_speed_mps: f64,
}

impl PowerFigures {
    /// Checks the figures; `at` is the JSON pointer of the parameters.
    pub fn check(&self, at: &str) -> Result<(), InputError> {
        check_range(self.cruise_power_w, 1.0, 1e6, &format!("{at}/cruise_power_w"), "W")?;
        check_range(self.vertical_speed_mps, 0.1, 50.0, &format!("{at}/vertical_speed_mps"), "m/s")
    }
}

pub struct ConstantPower<'a> {
    pub power: &'a PowerFigures,
    pub speed_mps: f64,
    /// Seconds a full stop at a corner adds (0: corners are flown through).
    pub corner_stop_s: f64,
    /// Lands as a multirotor's autopilot does.
    pub multirotor: bool,
}

const CORNER_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

impl EnergyModel for ConstantPower<'_> {
    fn pieces(&self, path: &FlightPath) -> Vec<PieceEstimate> {
        let (v, stop_s) = (self.speed_mps, self.corner_stop_s);
        let n = path.pieces.len();
        let mut stops = vec![0.0f64; n]; // in units of one full stop
        for (i, piece) in path.pieces.iter().enumerate() {
            let pts = &piece.points;
            stops[i] += pts.windows(3).filter(|w| heading_change(w[0], w[1], w[2]) > CORNER_RAD).count() as f64;
            if i + 1 < n {
                let next = &path.pieces[i + 1].points;
                if heading_change(pts[pts.len() - 2], pts[pts.len() - 1], next[1]) > CORNER_RAD {
                    stops[i] += 0.5;
                    stops[i + 1] += 0.5;
                }
            }
        }
        if n > 0 {
            // starting from and ending at rest
            stops[0] += 0.5;
            stops[n - 1] += 0.5;
        }
        let power = self.power.cruise_power_w;
        path.pieces
            .iter()
            .zip(stops)
            .map(|(p, s)| {
                let duration_s = p.length() / v + s * stop_s;
                let v_ends = if stop_s > 0.0 { 0.0 } else { v };
                PieceEstimate { speed_mps: v, duration_s, energy_j: duration_s * power, v_in_mps: v_ends, v_out_mps: v_ends, wind: None }
            })
            .collect()
    }

    /// A fixed wing holds its airspeed; a multirotor its ground speed, at the same power.
    fn holds_airspeed(&self) -> Option<f64> {
        (!self.multirotor).then_some(self.speed_mps)
    }

    fn takeoff_landing(&self, up_m: f64, down_m: f64) -> (f64, f64) {
        let t = (up_m + down_m) / self.power.vertical_speed_mps;
        (t, t * self.power.cruise_power_w)
    }

    /// A multirotor lands as its autopilot does ([`multirotor_landing`]); a fixed wing's or
    /// a ground vehicle's on the spot.
    fn flight_ends(&self, up_m: f64, down_m: f64) -> [Vertical; 2] {
        let takeoff = Vertical::new(self.takeoff_landing(up_m, 0.0));
        if self.multirotor {
            return [takeoff, multirotor_landing(down_m, |d| self.takeoff_landing(0.0, d), self.power.cruise_power_w)];
        }
        [takeoff, Vertical::new(self.takeoff_landing(0.0, down_m))]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::EnergyParams;
    use crate::path::PieceKind;
    use crate::vehicle::builtin_profiles;
    use geo::Coord;

    #[test]
    fn corners_cost_time_and_energy_grows_with_length() {
        let v = builtin_profiles().into_iter().find(|v| v.profile == "generic_multirotor").unwrap();
        let EnergyParams::ConstantPower(power) = &v.energy else { panic!("generic_multirotor has a constant power") };
        let v = &v;
        let c = |x, y| Coord { x, y };
        let mut straight = FlightPath::default();
        straight.push(PieceKind::Sweep, vec![c(0.0, 0.0), c(100.0, 0.0)], 5.0);
        straight.push(PieceKind::Sweep, vec![c(100.0, 0.0), c(200.0, 0.0)], 5.0);
        let mut bent = FlightPath::default();
        bent.push(PieceKind::Sweep, vec![c(0.0, 0.0), c(100.0, 0.0)], 5.0);
        bent.push(PieceKind::Turn, vec![c(100.0, 0.0), c(100.0, 100.0)], 0.0);
        let m = ConstantPower { power, speed_mps: v.cruise_speed_mps, corner_stop_s: v.cruise_speed_mps / v.acceleration_mps2, multirotor: true };
        let t_straight = m.estimate(&straight, None).duration_s();
        let t_bent = m.estimate(&bent, None).duration_s();
        let stop = v.cruise_speed_mps / v.acceleration_mps2;
        assert!((t_straight - (200.0 / v.cruise_speed_mps + stop)).abs() < 1e-9);
        assert!((t_bent - (200.0 / v.cruise_speed_mps + 2.0 * stop)).abs() < 1e-9);
        let e = m.estimate(&bent, None).energy_j();
        assert!((e - t_bent * power.cruise_power_w).abs() < 1e-6);
        let climbing = m.estimate(&bent, Some(40.0));
        assert!((climbing.takeoff.duration_s - 40.0 / power.vertical_speed_mps).abs() < 1e-9);
    }
}
