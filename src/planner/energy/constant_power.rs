//! The default energy model, until a measured one replaces it: the vehicle cruises at its
//! cruise speed drawing its cruise power; a multirotor stops at every corner sharper than
//! 0.5° (decelerating and accelerating at `acceleration_mps2`), which costs `v/a` seconds more
//! than flying the same distance at cruise speed, at cruise power. Take-off and landing are
//! not counted.

use super::{EnergyModel, PieceEstimate, heading_change};
use crate::path::FlightPath;
use crate::vehicle::{Vehicle, VehicleKind};

pub struct ConstantPower<'a> {
    pub vehicle: &'a Vehicle,
}

const CORNER_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

impl EnergyModel for ConstantPower<'_> {
    fn estimate(&self, path: &FlightPath) -> Vec<PieceEstimate> {
        let v = self.vehicle.cruise_speed_mps;
        let stop_s = match self.vehicle.kind {
            VehicleKind::Multirotor => v / self.vehicle.acceleration_mps2,
            VehicleKind::FixedWing => 0.0,
        };
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
        path.pieces
            .iter()
            .zip(stops)
            .map(|(p, s)| {
                let duration_s = p.length() / v + s * stop_s;
                PieceEstimate { speed_mps: v, duration_s, energy_j: duration_s * self.vehicle.cruise_power_w }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::PieceKind;
    use crate::vehicle::builtin_profiles;
    use geo::Coord;

    #[test]
    fn corners_cost_time_and_energy_grows_with_length() {
        let v = &builtin_profiles()[0];
        let c = |x, y| Coord { x, y };
        let mut straight = FlightPath::default();
        straight.push(PieceKind::Sweep, vec![c(0.0, 0.0), c(100.0, 0.0)], 5.0);
        straight.push(PieceKind::Sweep, vec![c(100.0, 0.0), c(200.0, 0.0)], 5.0);
        let mut bent = FlightPath::default();
        bent.push(PieceKind::Sweep, vec![c(0.0, 0.0), c(100.0, 0.0)], 5.0);
        bent.push(PieceKind::Turn, vec![c(100.0, 0.0), c(100.0, 100.0)], 0.0);
        let m = ConstantPower { vehicle: v };
        let t_straight: f64 = m.estimate(&straight).iter().map(|e| e.duration_s).sum();
        let t_bent: f64 = m.estimate(&bent).iter().map(|e| e.duration_s).sum();
        let stop = v.cruise_speed_mps / v.acceleration_mps2;
        assert!((t_straight - (200.0 / v.cruise_speed_mps + stop)).abs() < 1e-9);
        assert!((t_bent - (200.0 / v.cruise_speed_mps + 2.0 * stop)).abs() < 1e-9);
        let e: f64 = m.estimate(&bent).iter().map(|e| e.energy_j).sum();
        assert!((e - t_bent * v.cruise_power_w).abs() < 1e-6);
    }
}
