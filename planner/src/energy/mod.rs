//! Energy/time stage: speed, duration and energy of every piece of a flight path, one model
//! per file: [`iem`] (measured multirotor), [`fixed_wing`] (physics of steady flight),
//! [`constant_power`] (a single power figure), [`ground`] (a tractor's fuel, working and
//! turning). [`EnergyParams::model`] builds a profile's; [`InWind`] flies any of them in a
//! steady wind ([`crate::wind`]).
//!
//! The models take plain numbers (their own figures and the speed, turning radius and corner
//! stop of the flight) and check their own figures, so that they know nothing of vehicles.

pub mod constant_power;
pub mod fixed_wing;
pub mod ground;
pub mod iem;

use serde::{Deserialize, Serialize};

use super::error::InputError;
use super::path::FlightPath;
use super::wind;
use constant_power::PowerFigures;
use fixed_wing::Airframe;
use ground::GroundPower;
use iem::IemCoefficients;

/// The energy model of a vehicle profile and its parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(tag = "model", content = "parameters", rename_all = "snake_case")]
pub enum EnergyParams {
    /// Seed 002's improved model: measured polynomials, speed kept through corners.
    MultirotorIem(IemCoefficients),
    /// Steady-flight physics with banked turns and climbs.
    FixedWing(Airframe),
    /// One power figure for the whole flight.
    ConstantPower(PowerFigures),
    /// A ground vehicle's fuel: one power working, another turning and driving.
    Ground(GroundPower),
}

/// How the vehicle flies, as far as the models need to know.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// The fastest any leg is flown.
    pub cruise_speed_mps: f64,
    /// The tightest turn (fixed wing); sharper joints are flown as arcs of this radius.
    pub turn_radius_m: f64,
    /// Seconds a full stop at a corner adds to flying through it (0 when the vehicle does not
    /// stop); used by the constant-power model. For a ground vehicle, the time a reversal
    /// adds.
    pub corner_stop_s: f64,
    /// A ground vehicle's speed in turns and transits.
    pub headland_speed_mps: f64,
    pub multirotor: bool,
}

impl EnergyParams {
    /// The model with these parameters.
    pub fn model(&self, motion: Motion) -> Box<dyn EnergyModel + '_> {
        match self {
            EnergyParams::MultirotorIem(c) => Box::new(iem::Iem { coefficients: c, max_speed_mps: motion.cruise_speed_mps, flown: Default::default() }),
            EnergyParams::FixedWing(a) => Box::new(fixed_wing::FixedWing { airframe: a, speed_mps: motion.cruise_speed_mps, turn_radius_m: motion.turn_radius_m }),
            EnergyParams::ConstantPower(p) => {
                Box::new(constant_power::ConstantPower { power: p, speed_mps: motion.cruise_speed_mps, corner_stop_s: motion.corner_stop_s, multirotor: motion.multirotor })
            }
            EnergyParams::Ground(p) => {
                Box::new(ground::Ground { power: p, working_speed_mps: motion.cruise_speed_mps, headland_speed_mps: motion.headland_speed_mps, reversal_s: motion.corner_stop_s })
            }
        }
    }

    /// Checks every figure; `at` is the JSON pointer of the parameters in the request.
    pub fn check(&self, cruise_speed_mps: f64, at: &str) -> Result<(), InputError> {
        match self {
            EnergyParams::MultirotorIem(c) => c.check(cruise_speed_mps, at),
            EnergyParams::FixedWing(a) => a.check(at),
            EnergyParams::ConstantPower(p) => p.check(at),
            EnergyParams::Ground(p) => p.check(at),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct PieceEstimate {
    /// Cruise speed (the fastest leg's, where a piece has several).
    pub speed_mps: f64,
    pub duration_s: f64,
    pub energy_j: f64,
    /// Speed entering and leaving the piece.
    pub v_in_mps: f64,
    pub v_out_mps: f64,
    /// In wind: the piece's wind triangle ([`wind::piece_triangle`]).
    pub wind: Option<wind::Triangle>,
}

/// A path's estimate: one per piece, plus take-off to the flight altitude and landing.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PathEstimate {
    pub pieces: Vec<PieceEstimate>,
    pub takeoff: Vertical,
    pub landing: Vertical,
}

/// Time and energy of a flight's take-off or landing.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vertical {
    pub duration_s: f64,
    pub energy_j: f64,
}

impl Vertical {
    pub fn new((duration_s, energy_j): (f64, f64)) -> Self {
        Vertical { duration_s, energy_j }
    }
}

impl PathEstimate {
    pub fn duration_s(&self) -> f64 {
        self.pieces.iter().map(|e| e.duration_s).sum::<f64>() + self.takeoff_landing_s()
    }

    pub fn energy_j(&self) -> f64 {
        self.pieces.iter().map(|e| e.energy_j).sum::<f64>() + self.takeoff_landing_j()
    }

    pub fn takeoff_landing_s(&self) -> f64 {
        self.takeoff.duration_s + self.landing.duration_s
    }

    pub fn takeoff_landing_j(&self) -> f64 {
        self.takeoff.energy_j + self.landing.energy_j
    }
}

/// How a multirotor's autopilot lands (ArduCopter's defaults, the slower of ArduCopter's and
/// PX4's): after a return it hovers [`RTL_HOVER_S`] over home (`RTL_LOIT_TIME`), descends at
/// its own rate down to [`LAND_SLOW_BELOW_M`] (`LAND_ALT_LOW`), then at [`LAND_SPEED_MPS`]
/// (`LAND_SPEED`). Flown in software-in-the-loop, these were most of the 25 s a plan's duration
/// lacked against mission start to disarm (docs/flight-files.md).
pub const RTL_HOVER_S: f64 = 5.0;
pub const LAND_SLOW_BELOW_M: f64 = 10.0;
pub const LAND_SPEED_MPS: f64 = 0.5;

/// A multirotor's landing from `down_m` as its autopilot flies it: `descend` prices a descent at
/// the model's own rate, `hover_w` the power of hovering and of the slow last metres. Nothing
/// to land from: no landing.
pub fn multirotor_landing(down_m: f64, descend: impl Fn(f64) -> (f64, f64), hover_w: f64) -> Vertical {
    if down_m <= 0.0 {
        return Vertical::default();
    }
    let slow_m = down_m.min(LAND_SLOW_BELOW_M);
    let (fast_s, fast_j) = descend(down_m - slow_m);
    let held_s = RTL_HOVER_S + slow_m / LAND_SPEED_MPS;
    Vertical { duration_s: fast_s + held_s, energy_j: fast_j + held_s * hover_w }
}

pub trait EnergyModel {
    /// One estimate per piece of `path`, in order, from rest to rest.
    fn pieces(&self, path: &FlightPath) -> Vec<PieceEstimate>;

    /// Time and energy of climbing `up_m` and descending `down_m` on the spot.
    fn takeoff_landing(&self, up_m: f64, down_m: f64) -> (f64, f64);

    /// The take-off climbing `up_m` and the landing from `down_m` as the autopilot flies them
    /// (default: both on the spot at the model's rates).
    fn flight_ends(&self, up_m: f64, down_m: f64) -> [Vertical; 2] {
        [Vertical::new(self.takeoff_landing(up_m, 0.0)), Vertical::new(self.takeoff_landing(0.0, down_m))]
    }

    /// The airspeed the vehicle holds whatever the wind (its ground speed then follows the
    /// wind); `None`: it holds its ground speed.
    fn holds_airspeed(&self) -> Option<f64> {
        None
    }

    /// [`Self::pieces`] in a wind blowing at `wind` (m/s, local frame). By default a vehicle
    /// holding its airspeed is priced over the path as the air sees it, one holding its ground
    /// speed as in still air.
    fn pieces_in_wind(&self, path: &FlightPath, wind: geo::Coord) -> Vec<PieceEstimate> {
        match self.holds_airspeed() {
            Some(airspeed) => self.pieces(&wind::air_path(path, wind, airspeed)),
            None => self.pieces(path),
        }
    }

    /// The whole flight at `altitude_m` (or at ground level).
    fn estimate(&self, path: &FlightPath, altitude_m: Option<f64>) -> PathEstimate {
        let h = altitude_m.unwrap_or(0.0).max(0.0);
        let [takeoff, landing] = self.flight_ends(h, h);
        PathEstimate { pieces: self.pieces(path), takeoff, landing }
    }
}

/// A model flown in a steady wind: its pieces priced by [`EnergyModel::pieces_in_wind`], each
/// with its wind triangle; take-off and landing as in still air.
pub struct InWind<'a> {
    pub model: Box<dyn EnergyModel + 'a>,
    /// The air's velocity, m/s, local frame.
    pub wind: geo::Coord,
}

impl EnergyModel for InWind<'_> {
    fn pieces(&self, path: &FlightPath) -> Vec<PieceEstimate> {
        let mut pieces = self.model.pieces_in_wind(path, self.wind);
        let holds_airspeed = self.model.holds_airspeed();
        for (e, piece) in pieces.iter_mut().zip(&path.pieces) {
            let speed = holds_airspeed.unwrap_or(e.speed_mps);
            e.wind = wind::piece_triangle(&piece.points, self.wind, speed, holds_airspeed.is_some());
        }
        pieces
    }

    fn takeoff_landing(&self, up_m: f64, down_m: f64) -> (f64, f64) {
        self.model.takeoff_landing(up_m, down_m)
    }

    fn flight_ends(&self, up_m: f64, down_m: f64) -> [Vertical; 2] {
        self.model.flight_ends(up_m, down_m)
    }

    fn holds_airspeed(&self) -> Option<f64> {
        self.model.holds_airspeed()
    }
}

/// Heading change in radians (0..π) at the joint of `a→b` and `b→c`.
pub fn heading_change(a: geo::Coord, b: geo::Coord, c: geo::Coord) -> f64 {
    let (u, v) = (b - a, c - b);
    let cross = u.x * v.y - u.y * v.x;
    let dot = u.x * v.x + u.y * v.y;
    cross.atan2(dot).abs()
}

/// A straight run of the path between two corners.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Leg {
    pub length_m: f64,
    /// Heading change at the leg's end, degrees (0 for the last leg).
    pub turn_after_deg: f64,
    /// Height gained and lost along the leg.
    pub climb_m: f64,
    pub descent_m: f64,
    /// Metres of the leg in each piece it crosses: (piece index, metres).
    pub spans: Vec<(usize, f64)>,
    /// Unit vector along the leg's first segment.
    pub direction: geo::Coord,
}

/// Joints straighter than this are flown through: the legs merge (docs/methods.md, energy §4).
const COLLINEAR_DEG: f64 = 0.5;

/// The path as legs between its corners.
pub fn legs(path: &FlightPath) -> Vec<Leg> {
    let mut out: Vec<Leg> = Vec::new();
    let mut current = Leg::default();
    let mut last_dir: Option<geo::Coord> = None;
    for (i, piece) in path.pieces.iter().enumerate() {
        for k in 1..piece.points.len() {
            let (a, b) = (piece.points[k - 1], piece.points[k]);
            let d = b - a;
            let len = d.x.hypot(d.y);
            if len < 1e-9 {
                // straight up or down: the climb belongs to the leg it starts or ends
                if let (Some(za), Some(zb)) = (piece.z.get(k - 1), piece.z.get(k)) {
                    current.climb_m += (zb - za).max(0.0);
                    current.descent_m += (za - zb).max(0.0);
                }
                continue;
            }
            if let Some(prev) = last_dir {
                let turn = heading_change(geo::Coord { x: 0.0, y: 0.0 }, prev, prev + d).to_degrees();
                if turn >= COLLINEAR_DEG {
                    current.turn_after_deg = turn;
                    out.push(std::mem::take(&mut current));
                }
            }
            last_dir = Some(d);
            if current.length_m == 0.0 {
                current.direction = d / len;
            }
            current.length_m += len;
            match current.spans.last_mut() {
                Some((p, m)) if *p == i => *m += len,
                _ => current.spans.push((i, len)),
            }
            if let (Some(za), Some(zb)) = (piece.z.get(k - 1), piece.z.get(k)) {
                current.climb_m += (zb - za).max(0.0);
                current.descent_m += (za - zb).max(0.0);
            }
        }
    }
    if current.length_m > 0.0 {
        out.push(current);
    }
    out
}

/// Shares each leg's figures among the pieces it crosses, in proportion to length.
pub fn spread_over_pieces<F>(path: &FlightPath, legs: &[Leg], flown: &[F], as_estimate: impl Fn(&F) -> PieceEstimate) -> Vec<PieceEstimate> {
    let mut pieces = vec![PieceEstimate::default(); path.pieces.len()];
    let mut touched = vec![false; path.pieces.len()];
    let mut v_in = 0.0;
    for (leg, f) in legs.iter().zip(flown) {
        let e = as_estimate(f);
        for &(i, metres) in &leg.spans {
            let share = metres / leg.length_m;
            let p = &mut pieces[i];
            if !touched[i] {
                p.v_in_mps = v_in;
                touched[i] = true;
            }
            p.speed_mps = p.speed_mps.max(e.speed_mps);
            p.duration_s += e.duration_s * share;
            p.energy_j += e.energy_j * share;
            p.v_out_mps = e.v_out_mps;
        }
        v_in = e.v_out_mps;
    }
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::PieceKind;
    use crate::vehicle::builtin_profiles;
    use geo::Coord;

    fn square_path(side: f64) -> FlightPath {
        let c = |x, y| Coord { x, y };
        let mut p = FlightPath::default();
        p.push(PieceKind::Sweep, vec![c(0.0, 0.0), c(side / 2.0, 0.0), c(side, 0.0)], 5.0);
        p.push(PieceKind::Turn, vec![c(side, 0.0), c(side, side)], 0.0);
        p.push(PieceKind::Sweep, vec![c(side, side), c(0.0, side)], 5.0);
        p
    }

    #[test]
    fn legs_merge_straight_joints_and_keep_corners() {
        let legs = legs(&square_path(100.0));
        assert_eq!(legs.len(), 3);
        assert!((legs[0].length_m - 100.0).abs() < 1e-9 && (legs[0].turn_after_deg - 90.0).abs() < 1e-9);
        assert_eq!(legs[2].turn_after_deg, 0.0);
        assert_eq!(legs[1].spans, vec![(1, 100.0)]);
    }

    #[test]
    fn every_model_charges_more_for_longer_paths_and_sharper_turns() {
        let c = |x, y| Coord { x, y };
        let bent = |angle_deg: f64| {
            let a = angle_deg.to_radians();
            let mut p = FlightPath::default();
            p.push(PieceKind::Sweep, vec![c(0.0, 0.0), c(200.0, 0.0)], 5.0);
            p.push(PieceKind::Sweep, vec![c(200.0, 0.0), c(200.0 + 200.0 * a.cos(), 200.0 * a.sin())], 5.0);
            p
        };
        for v in builtin_profiles() {
            let m = v.energy_model();
            let e = |p: &FlightPath| m.estimate(p, Some(30.0)).energy_j();
            assert!(e(&square_path(200.0)) > e(&square_path(100.0)), "{}", v.profile);
            if matches!(v.energy, EnergyParams::MultirotorIem(_)) {
                // sharper corners cost more: less speed is kept through them, down to a full stop
                // (interior angles under 50°: turns of 130° and more cost the same)
                let energies: Vec<f64> = [10.0, 45.0, 90.0, 135.0, 170.0].iter().map(|&a| e(&bent(a))).collect();
                assert!(energies.windows(2).all(|w| w[1] >= w[0]) && energies[..4].windows(2).all(|w| w[1] > w[0]), "{}: {energies:?}", v.profile);
            }
        }
    }
}
