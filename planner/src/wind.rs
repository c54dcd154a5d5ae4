//! Flight in a steady wind (docs/methods.md, wind): the wind triangle of each straight leg, and
//! the path as the air sees it.
//!
//! An aircraft that holds its airspeed (a fixed wing) flies a ground leg of length `L` in the
//! time `L / v_g`, covering `v_a · L / v_g` metres of air: its still-air model priced over the
//! air-relative path gives its time and energy in wind. A multirotor's autopilot holds the ground
//! speed instead, and its power follows the airspeed the wind makes of it ([`super::iem`]).
//!
//! ```
//! use coverplan_planner::wind::{Wind, holding_airspeed};
//! // 5 m/s from the west, a 15 m/s aircraft flying east: 20 m/s over the ground, no crab
//! let w = Wind { speed_mps: 5.0, from_deg: 270.0, height_m: None }.velocity();
//! let t = holding_airspeed(15.0, w, geo::Coord { x: 1.0, y: 0.0 });
//! assert!((t.ground_speed_mps - 20.0).abs() < 1e-12 && t.crab_deg.abs() < 1e-12);
//! ```

use geo::Coord;
use serde::{Deserialize, Serialize};

use crate::error::{InputError, check_range};
use crate::path::FlightPath;

/// Exponent of the power law that carries a wind measured at one height to another (neutral
/// air over open ground; Peterson & Hennessey 1978).
pub const SHEAR_EXPONENT: f64 = 1.0 / 7.0;

/// Strongest wind accepted at all, m/s (a storm; any aircraft's own limit is lower).
pub const MAX_WIND_MPS: f64 = 60.0;

/// A steady, uniform wind.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Wind {
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 60.0))]
    pub speed_mps: f64,
    /// The compass bearing the wind blows from (meteorological: 270 is a west wind).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 360.0))]
    pub from_deg: f64,
    /// Height above ground the speed was measured at (a weather station's 10 m); the plan
    /// carries it to the flight altitude by the 1/7 power law. Default: measured at the flight
    /// altitude.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 1000.0))]
    pub height_m: Option<f64>,
}

impl Wind {
    /// Checks the figures; `at` is the JSON pointer of the wind.
    pub fn check(&self, at: &str) -> Result<(), InputError> {
        check_range(self.speed_mps, 0.0, MAX_WIND_MPS, &format!("{at}/speed_mps"), "m/s")?;
        check_range(self.from_deg, 0.0, 360.0, &format!("{at}/from_deg"), "°")?;
        if let Some(h) = self.height_m {
            check_range(h, 1.0, 1000.0, &format!("{at}/height_m"), "m")?;
        }
        Ok(())
    }

    /// The wind at `altitude_m` above ground (no height given, or no altitude: as given).
    pub fn at_altitude(&self, altitude_m: Option<f64>) -> Wind {
        match (self.height_m, altitude_m) {
            (Some(h), Some(z)) if z > 0.0 => Wind { speed_mps: self.speed_mps * (z / h).powf(SHEAR_EXPONENT), from_deg: self.from_deg, height_m: None },
            _ => Wind { height_m: None, ..*self },
        }
    }

    /// The air's velocity in the local frame (x east, y north): it blows towards the bearing
    /// opposite `from_deg`.
    pub fn velocity(&self) -> Coord {
        // a compass bearing b points along (sin b, cos b) in x east, y north
        let towards = (self.from_deg + 180.0).to_radians();
        Coord { x: self.speed_mps * towards.sin(), y: self.speed_mps * towards.cos() }
    }
}

/// A straight leg's wind triangle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Triangle {
    pub ground_speed_mps: f64,
    pub airspeed_mps: f64,
    /// The nose's angle to the track, degrees clockwise (into a wind from the right: positive).
    pub crab_deg: f64,
}

/// The wind along and across a track `u` (a unit vector): across is positive towards the
/// track's left.
pub fn components(wind: Coord, u: Coord) -> (f64, f64) {
    (wind.x * u.x + wind.y * u.y, -wind.x * u.y + wind.y * u.x)
}

/// Flying the track `u` (unit vector) at `airspeed`: the ground speed is the wind along the
/// track plus what the airspeed has left after cancelling the wind across it. The wind must be
/// slower than the airspeed.
pub fn holding_airspeed(airspeed: f64, wind: Coord, u: Coord) -> Triangle {
    let (along, across) = components(wind, u);
    let ahead = (airspeed * airspeed - across * across).max(0.0).sqrt();
    Triangle { ground_speed_mps: along + ahead, airspeed_mps: airspeed, crab_deg: across.atan2(ahead).to_degrees() }
}

/// Flying the track `u` (unit vector) at `ground_speed`: the airspeed is the ground velocity
/// less the wind's.
pub fn holding_ground_speed(ground_speed: f64, wind: Coord, u: Coord) -> Triangle {
    let (along, across) = components(wind, u);
    let ahead = ground_speed - along;
    Triangle { ground_speed_mps: ground_speed, airspeed_mps: ahead.hypot(across), crab_deg: across.atan2(ahead).to_degrees() }
}

/// A ground displacement `d` flown at `airspeed`, as the air sees it: `d` less the wind's drift
/// over its time; its length is the airspeed × that time. A vertical one (zero) stays.
pub fn air_displacement(d: Coord, wind: Coord, airspeed: f64) -> Coord {
    let length = d.x.hypot(d.y);
    if length <= 1e-12 {
        return d;
    }
    d - wind * (length / holding_airspeed(airspeed, wind, d / length).ground_speed_mps)
}

/// The metres of air flown along the ground `points` at `airspeed` (time × airspeed).
pub fn air_length(points: &[Coord], wind: Coord, airspeed: f64) -> f64 {
    points.windows(2).map(|w| air_displacement(w[1] - w[0], wind, airspeed)).map(|a| a.x.hypot(a.y)).sum()
}

/// `path` as the air sees it, flown at `airspeed`: each segment becomes its
/// [`air_displacement`]. Pieces keep their points, so that estimates of the air path are the
/// ground path's piece by piece.
pub fn air_path(path: &FlightPath, wind: Coord, airspeed: f64) -> FlightPath {
    let mut out = path.clone();
    let Some(first) = path.pieces.first().map(|p| p.points[0]) else { return out };
    let mut at = first;
    for (piece, air) in path.pieces.iter().zip(&mut out.pieces) {
        air.points[0] = at;
        for k in 1..piece.points.len() {
            at = at + air_displacement(piece.points[k] - piece.points[k - 1], wind, airspeed);
            air.points[k] = at;
        }
    }
    out
}

/// The wind triangle of a piece as a whole: the mean ground speed over its length, the airspeed
/// and the crab of its longest segment.
pub fn piece_triangle(points: &[Coord], wind: Coord, speed: f64, holds_airspeed: bool) -> Option<Triangle> {
    let (mut length, mut time, mut longest) = (0.0, 0.0, None::<(f64, Triangle)>);
    for w in points.windows(2) {
        let d = w[1] - w[0];
        let l = d.x.hypot(d.y);
        if l <= 1e-12 {
            continue;
        }
        let t = if holds_airspeed { holding_airspeed(speed, wind, d / l) } else { holding_ground_speed(speed, wind, d / l) };
        length += l;
        time += l / t.ground_speed_mps;
        if longest.is_none_or(|(m, _)| l > m) {
            longest = Some((l, t));
        }
    }
    longest.map(|(_, t)| Triangle { ground_speed_mps: length / time, ..t })
}

/// Headings a [`Tariff`] is sampled at (every 5°).
pub const TARIFF_HEADINGS: usize = 72;

/// What a metre over the ground costs by its direction in a wind, relative to still air: a
/// straight leg's time or energy in the wind over the same leg's in still air, sampled at
/// [`TARIFF_HEADINGS`] headings and interpolated between them. Routes weigh a vehicle's legs
/// by it where the vehicle's model, not the geometry, says what the wind costs (a multirotor
/// holding its ground speed: the energy model lives above the routes).
///
/// ```
/// use coverplan_planner::wind::Tariff;
/// // a metre flown east costs half again what one flown west does
/// let t = Tariff::sampled(|u| 1.0 + 0.25 * u.x);
/// assert!((t.price(geo::Coord { x: 1.0, y: 0.0 }) - 1.25).abs() < 1e-12);
/// assert!((t.length(&[geo::Coord { x: 0.0, y: 0.0 }, geo::Coord { x: -10.0, y: 0.0 }]) - 7.5).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Tariff {
    per_heading: Vec<f64>,
}

impl Tariff {
    /// The tariff of `price` (of a unit direction, math angle from east), sampled.
    pub fn sampled(price: impl Fn(Coord) -> f64) -> Self {
        let step = std::f64::consts::TAU / TARIFF_HEADINGS as f64;
        Tariff { per_heading: (0..TARIFF_HEADINGS).map(|k| price(Coord { x: (k as f64 * step).cos(), y: (k as f64 * step).sin() })).collect() }
    }

    /// The price of a metre along `d` (any length but zero).
    pub fn price(&self, d: Coord) -> f64 {
        let at = d.y.atan2(d.x).rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU * TARIFF_HEADINGS as f64;
        let k = (at.floor() as usize).min(TARIFF_HEADINGS - 1);
        let f = at - k as f64;
        self.per_heading[k] * (1.0 - f) + self.per_heading[(k + 1) % TARIFF_HEADINGS] * f
    }

    /// The priced length of the polyline `points`.
    pub fn length(&self, points: &[Coord]) -> f64 {
        points
            .windows(2)
            .map(|w| w[1] - w[0])
            .map(|d| {
                let l = d.x.hypot(d.y);
                if l <= 1e-12 { 0.0 } else { l * self.price(d) }
            })
            .sum()
    }

    /// The cheapest metre in any direction: no priced path is shorter than its straight
    /// length times this.
    pub fn cheapest(&self) -> f64 {
        self.per_heading.iter().copied().fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::PieceKind;

    fn unit(bearing_deg: f64) -> Coord {
        let b = bearing_deg.to_radians();
        Coord { x: b.sin(), y: b.cos() }
    }

    #[test]
    fn the_wind_triangle_closes_in_every_direction() {
        for k in 0..36 {
            for j in 0..8 {
                let (track, from) = (k as f64 * 10.0, j as f64 * 45.0 + 7.0);
                let w = Wind { speed_mps: 6.0, from_deg: from, height_m: None }.velocity();
                let u = unit(track);
                let t = holding_airspeed(15.0, w, u);
                // the air velocity (ground velocity less the wind) has the airspeed and the crab's heading
                let air = u * t.ground_speed_mps - w;
                assert!((air.x.hypot(air.y) - 15.0).abs() < 1e-9);
                let heading = air.x.atan2(air.y).to_degrees();
                let crab = (heading - track + 540.0).rem_euclid(360.0) - 180.0;
                assert!((crab - t.crab_deg).abs() < 1e-9, "{track} {from}: {crab} against {}", t.crab_deg);
                let back = holding_ground_speed(t.ground_speed_mps, w, u);
                assert!((back.airspeed_mps - 15.0).abs() < 1e-9 && (back.crab_deg - t.crab_deg).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn a_straight_legs_time_is_its_length_over_the_ground_speed() {
        // closed form: 8 m/s from the west, 15 m/s airspeed; east 23, west 7, north and south √(225−64)
        let w = Wind { speed_mps: 8.0, from_deg: 270.0, height_m: None }.velocity();
        for (bearing, speed) in [(90.0, 23.0), (270.0, 7.0), (0.0, 161f64.sqrt()), (180.0, 161f64.sqrt())] {
            let g = holding_airspeed(15.0, w, unit(bearing)).ground_speed_mps;
            assert!((g - speed).abs() < 1e-9, "{bearing}: {g}");
            let mut p = FlightPath::default();
            p.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, unit(bearing) * 1000.0], 5.0);
            let air = air_path(&p, w, 15.0);
            assert!((air.length() / 15.0 - 1000.0 / speed).abs() < 1e-9);
        }
    }

    #[test]
    fn the_wind_grows_with_height_by_the_power_law() {
        let w = Wind { speed_mps: 5.0, from_deg: 0.0, height_m: Some(10.0) };
        assert!((w.at_altitude(Some(10.0)).speed_mps - 5.0).abs() < 1e-12);
        assert!((w.at_altitude(Some(80.0)).speed_mps - 5.0 * 8f64.powf(1.0 / 7.0)).abs() < 1e-12);
        assert_eq!(w.at_altitude(None).speed_mps, 5.0);
        // a north wind blows south
        assert!(w.velocity().y < -4.99 && w.velocity().x.abs() < 1e-9);
    }
}
