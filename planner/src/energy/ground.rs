//! A ground vehicle's fuel: `working_power_w` while the implement works (swaths and headland
//! passes, at the working speed), `travel_power_w` in turns and transits (at the headland
//! speed). The energy per worked hectare is then `working_power_w / (width × speed)`: 60 kW
//! at 2.5 m/s with 6 m is 40 MJ/ha, about 1.1 l of diesel, a sprayer's figure. A three-point
//! turn stops twice to change direction, each reversal adding `reversal_s` at travel power.
//! There is no take-off: a tractor starts and ends on the ground.

use serde::{Deserialize, Serialize};

use super::{EnergyModel, PieceEstimate};
use crate::error::{InputError, check_range};
use crate::path::{FlightPath, TurnShape};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct GroundPower {
    /// Fuel power drawn while working, W.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 2e6))]
    pub working_power_w: f64,
    /// Fuel power drawn while turning or driving with the implement lifted, W.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 2e6))]
    pub travel_power_w: f64,
}

impl GroundPower {
    /// Checks the figures; `at` is the JSON pointer of the parameters.
    pub fn check(&self, at: &str) -> Result<(), InputError> {
        check_range(self.working_power_w, 1.0, 2e6, &format!("{at}/working_power_w"), "W")?;
        check_range(self.travel_power_w, 1.0, 2e6, &format!("{at}/travel_power_w"), "W")
    }
}

pub struct Ground<'a> {
    pub power: &'a GroundPower,
    pub working_speed_mps: f64,
    pub headland_speed_mps: f64,
    /// Seconds one change of direction adds.
    pub reversal_s: f64,
}

impl EnergyModel for Ground<'_> {
    fn pieces(&self, path: &FlightPath) -> Vec<PieceEstimate> {
        path.pieces
            .iter()
            .map(|p| {
                let (speed, power) = if p.kind.works() { (self.working_speed_mps, self.power.working_power_w) } else { (self.headland_speed_mps, self.power.travel_power_w) };
                let reversals = match p.shape {
                    Some(TurnShape::Fishtail) => 2.0,
                    Some(TurnShape::Corner) => cusps(&p.points) as f64,
                    _ => 0.0,
                };
                let moving_s = p.length() / speed + reversals * self.reversal_s;
                // standing at a refill point: time, and no fuel counted for it (the engine idles
                // or is off; the implement's pump or auger is not modelled)
                let duration_s = moving_s + p.refill_s.unwrap_or(0.0);
                PieceEstimate { speed_mps: speed, duration_s, energy_j: moving_s * power, v_in_mps: speed, v_out_mps: speed, wind: None }
            })
            .collect()
    }

    fn takeoff_landing(&self, _up_m: f64, _down_m: f64) -> (f64, f64) {
        (0.0, 0.0)
    }
}

/// Where a manoeuvre's points turn back on themselves: its changes of direction.
fn cusps(points: &[geo::Coord]) -> usize {
    points.windows(3).filter(|w| (w[1] - w[0]).x * (w[2] - w[1]).x + (w[1] - w[0]).y * (w[2] - w[1]).y < 0.0).count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::PieceKind;
    use geo::Coord;

    #[test]
    fn work_and_turns_are_priced_at_their_own_speed_and_power() {
        let power = GroundPower { working_power_w: 60_000.0, travel_power_w: 30_000.0 };
        let model = Ground { power: &power, working_speed_mps: 2.5, headland_speed_mps: 1.5, reversal_s: 4.0 };
        let c = |x, y| Coord { x, y };
        let mut path = FlightPath::default();
        path.push(PieceKind::Sweep, vec![c(0.0, 0.0), c(100.0, 0.0)], 3.0);
        path.push_turn(TurnShape::Fishtail, vec![c(100.0, 0.0), c(100.0, 6.0)]);
        let e = model.pieces(&path);
        assert!((e[0].duration_s - 40.0).abs() < 1e-9 && (e[0].energy_j - 2.4e6).abs() < 1e-3);
        // 6 m at 1.5 m/s and two reversals of 4 s
        assert!((e[1].duration_s - 12.0).abs() < 1e-9 && (e[1].energy_j - 12.0 * 30_000.0).abs() < 1e-3);
        // 40 MJ per hectare worked: 100 m × 6 m is 0.06 ha
        assert!((e[0].energy_j / 0.06 - 40e6).abs() < 1.0);
        // a drive to a refill point: its 30 m, then 900 s standing there, without fuel
        path.pieces.push(crate::path::Piece { refill_s: Some(900.0), ..crate::path::Piece::new(PieceKind::Transit, vec![c(100.0, 6.0), c(130.0, 6.0)], 0.0) });
        let e = model.pieces(&path);
        assert!((e[2].duration_s - 920.0).abs() < 1e-9 && (e[2].energy_j - 20.0 * 30_000.0).abs() < 1e-3);
    }
}
