//! Vehicles: profiles (built-in or stored by the service) and per-plan overrides.

use serde::{Deserialize, Serialize};

use super::energy::constant_power::PowerFigures;
use super::energy::fixed_wing::Airframe;
use super::energy::ground::GroundPower;
use super::energy::iem::IemCoefficients;
use super::energy::{EnergyModel, EnergyParams, InWind, Motion};
use super::error::{InputError, check_range};
use super::turn::TurnModel;
use super::turn::continuous_curvature::cc_circle_radius;
use super::turn::ground::Steering;
use super::wind::{MAX_WIND_MPS, Wind};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum VehicleKind {
    Multirotor,
    FixedWing,
    /// A tractor, sprayer or mower: works swaths with an implement, turns in the headland.
    Ground,
}

/// What only a ground vehicle has: its implement and how it may turn.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct GroundFigures {
    /// Width the implement works; the swath spacing is this less the plan's `overlap`.
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 100.0))]
    pub working_width_m: f64,
    /// May reverse: Reeds–Shepp turns (with cusps) and three-point (fishtail) turns where they
    /// are shorter or fit where a forward turn does not.
    #[serde(default)]
    pub reverse_allowed: bool,
    /// Steering limit for continuous-curvature turns, 1/m²: how fast the curvature may change
    /// along the path. Absent: the curvature may jump (Dubins turns).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0001, maximum = 10.0))]
    pub max_curvature_rate: Option<f64>,
    /// Speed of turns and transits (the working speed is `cruise_speed_mps`).
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 30.0))]
    pub headland_speed_mps: f64,
}

/// The battery: its energy and the share kept in reserve at landing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Battery {
    /// Wh: at most 100 000 for an aircraft's battery, 20 000 000 for a ground vehicle's tank.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 20000000.0))]
    pub energy_wh: f64,
    /// Fraction of `energy_wh` that must be left at landing (default 0.25).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 0.9))]
    pub reserve: f64,
}

/// ArduPlane's default L1 guidance (`NAVL1_PERIOD`, `NAVL1_DAMPING`): how far ahead it aims.
pub const L1_PERIOD_S: f64 = 17.0;
pub const L1_DAMPING: f64 = 0.75;

/// ArduPlane's L1 distance at `speed_mps` with its default period and damping.
pub fn l1_distance_m(speed_mps: f64) -> f64 {
    (L1_DAMPING * L1_PERIOD_S * speed_mps / std::f64::consts::PI).max(1.0)
}

/// Share of the L1 distance fixed-wing connections keep from zones beyond the margin.
pub const TRACKING_SHARE_OF_L1: f64 = 0.25;

/// A fixed wing's pitch climbing out after take-off (the take-off item's), degrees.
pub const TAKEOFF_PITCH_DEG: f64 = 15.0;

/// A fixed wing's straight climb after take-off to `altitude_m`, metres over the ground.
pub fn climb_out_m(altitude_m: f64) -> f64 {
    altitude_m / TAKEOFF_PITCH_DEG.to_radians().tan()
}

/// Seconds at cruise speed a fixed wing's default lead-in lasts: twice the distance ArduPlane's
/// default L1 guidance looks ahead (period 17 s, damping 0.75: 4.06 s of flight). Our follower
/// reaches a line's start within 0.3 m after it, 9 m off after half of it (docs/flight-files.md).
pub const LEAD_IN_S: f64 = 8.0;

impl Vehicle {
    /// A fixed wing's landing approach from `altitude_m`, metres over the ground: a glide at
    /// cruise speed sinking at its energy model's descent rate.
    pub fn landing_approach_m(&self, altitude_m: f64) -> f64 {
        let (_, sink) = self.vertical_rates_mps();
        altitude_m * self.cruise_speed_mps / sink.max(0.1)
    }

    /// How far an autopilot following waypoints strays from a planned turn: a quarter of its
    /// L1 distance for a fixed wing (15 m at 15 m/s; with half the default margin, 20 m: our
    /// follower strayed up to 19.5 m from the plans of the random fields, and never into a
    /// zone); nothing for vehicles that fly their legs exactly.
    pub fn turn_tracking_m(&self) -> f64 {
        match self.kind {
            VehicleKind::FixedWing => l1_distance_m(self.cruise_speed_mps) * TRACKING_SHARE_OF_L1,
            _ => 0.0,
        }
    }

    /// The straight approach flown before each line: `asked`, or [`LEAD_IN_S`] at cruise speed
    /// for a fixed wing; none for the others, which fly onto a line exactly.
    pub fn lead_in_m(&self, asked: Option<f64>) -> f64 {
        match self.kind {
            VehicleKind::FixedWing => asked.unwrap_or(LEAD_IN_S * self.cruise_speed_mps),
            _ => 0.0,
        }
    }

    /// Climb and descent rates: its energy model's, or 3 and 2 m/s.
    pub fn vertical_rates_mps(&self) -> (f64, f64) {
        match &self.energy {
            EnergyParams::MultirotorIem(c) => (c.climb_rate_mps, c.descent_rate_mps),
            EnergyParams::ConstantPower(p) => (p.vertical_speed_mps, p.vertical_speed_mps),
            EnergyParams::FixedWing(a) => (a.climb_rate_mps, a.climb_rate_mps),
            EnergyParams::Ground(_) => (3.0, 2.0),
        }
    }
}

impl Battery {
    /// Energy a sortie may use, in joules.
    pub fn usable_j(&self) -> f64 {
        self.energy_wh * 3600.0 * (1.0 - self.reserve)
    }
}

/// A vehicle profile with every figure the planner needs.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Vehicle {
    /// Identifier: lower-case letters, digits, `_` and `-`.
    #[cfg_attr(feature = "schema", schema(pattern = "^[a-z0-9_-]{1,64}$"))]
    pub profile: String,
    #[serde(default)]
    pub description: String,
    pub kind: VehicleKind,
    /// Cruise speed; for the multirotor model, the highest speed of any leg.
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 100.0))]
    pub cruise_speed_mps: f64,
    /// Minimum turning radius (0 for a multirotor, which stops and turns on the spot).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 5000.0))]
    pub turn_radius_m: f64,
    /// Acceleration and deceleration at corners (multirotor, constant-power model).
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 20.0))]
    pub acceleration_mps2: f64,
    pub energy: EnergyParams,
    /// For a ground vehicle, its tank: the fuel's energy.
    pub battery: Battery,
    /// Ground vehicles only.
    pub ground: Option<GroundFigures>,
    /// An aircraft's strongest wind to plan in (a fixed wing's is below its airspeed); none:
    /// up to the airspeed.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 60.0))]
    pub max_wind_mps: Option<f64>,
}

/// Built-in profiles. `iris` carries measured coefficients; the others' figures are assumed
/// (documented in the README), not measurements of a particular airframe.
pub fn builtin_profiles() -> Vec<Vehicle> {
    let li_ion = |energy_wh| Battery { energy_wh, reserve: 0.25 };
    vec![
        Vehicle {
            profile: "iris".into(),
            description: "3DR IRIS quadrotor (seed 002): measured energy model, legs at most 7.8 m/s, 3S 5.1 Ah battery; flies through waypoints keeping its heading, \
                          as on the flights that validated the model (a copy with yaw_at_waypoints or waypoint_hold_s models autopilots that turn or stop at each)"
                .into(),
            kind: VehicleKind::Multirotor,
            cruise_speed_mps: 7.8,
            turn_radius_m: 0.0,
            acceleration_mps2: 1.0,
            energy: EnergyParams::MultirotorIem(IemCoefficients::iris()),
            battery: li_ion(56.6),
            ground: None,
            max_wind_mps: Some(10.0),
        },
        Vehicle {
            profile: "maja".into(),
            description: "Fixed-wing survey aircraft of seed 004: 15 m/s, planning turn radius 85 m; energy from an assumed 3 kg airframe, 4S 5 Ah battery".into(),
            kind: VehicleKind::FixedWing,
            cruise_speed_mps: 15.0,
            turn_radius_m: 85.0,
            acceleration_mps2: 1.0,
            energy: EnergyParams::FixedWing(Airframe::default()),
            battery: li_ion(74.0),
            ground: None,
            max_wind_mps: Some(9.0),
        },
        Vehicle {
            profile: "generic_multirotor".into(),
            description: "Assumed large survey multirotor: 8 m/s, 400 W, two 274 Wh batteries (about 55 minutes)".into(),
            kind: VehicleKind::Multirotor,
            cruise_speed_mps: 8.0,
            turn_radius_m: 0.0,
            acceleration_mps2: 2.0,
            energy: EnergyParams::ConstantPower(PowerFigures { cruise_power_w: 400.0, vertical_speed_mps: 2.0 }),
            battery: li_ion(548.0),
            ground: None,
            max_wind_mps: Some(12.0),
        },
        Vehicle {
            profile: "tractor_sprayer".into(),
            description: "Assumed tractor with a 6 m implement: works at 2.5 m/s (9 km/h), turns at 1.5 m/s on a 7 m radius, forward only; \
                          60 kW of fuel power working (40 MJ per hectare, about 1.1 l of diesel), 30 kW turning; 200 l tank"
                .into(),
            kind: VehicleKind::Ground,
            cruise_speed_mps: 2.5,
            turn_radius_m: 7.0,
            acceleration_mps2: 0.5,
            energy: EnergyParams::Ground(GroundPower { working_power_w: 60_000.0, travel_power_w: 30_000.0 }),
            // 200 l of diesel at 10 kWh per litre
            battery: Battery { energy_wh: 2_000_000.0, reserve: 0.1 },
            ground: Some(GroundFigures { working_width_m: 6.0, reverse_allowed: false, max_curvature_rate: None, headland_speed_mps: 1.5 }),
            max_wind_mps: None,
        },
        Vehicle {
            profile: "generic_fixed_wing".into(),
            description: "Assumed small fixed-wing aircraft: 15 m/s, turning radius 50 m, 74 Wh".into(),
            kind: VehicleKind::FixedWing,
            cruise_speed_mps: 15.0,
            turn_radius_m: 50.0,
            acceleration_mps2: 1.0,
            energy: EnergyParams::FixedWing(Airframe::default()),
            battery: li_ion(74.0),
            ground: None,
            max_wind_mps: Some(9.0),
        },
    ]
}

/// The members of a plan's vehicle only a ground vehicle has.
pub const GROUND_OVERRIDES: [&str; 4] = ["working_width_m", "reverse_allowed", "max_curvature_rate", "headland_speed_mps"];

/// Most energy a ground vehicle's tank holds, Wh.
pub const MAX_TANK_WH: f64 = 20_000_000.0;
/// Most energy an aircraft's battery holds, Wh.
pub const MAX_BATTERY_WH: f64 = 100_000.0;

/// The profile used for a kind when no profile is named.
fn default_profile(kind: Option<VehicleKind>) -> &'static str {
    match kind {
        Some(VehicleKind::FixedWing) => "generic_fixed_wing",
        Some(VehicleKind::Ground) => "tractor_sprayer",
        _ => "generic_multirotor",
    }
}

/// The vehicle part of a plan request: a profile, a kind, or both, with optional overrides.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct VehicleParams {
    /// Name of a profile, as listed by `GET /api/v1/vehicles`.
    pub profile: Option<String>,
    pub kind: Option<VehicleKind>,
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 100.0))]
    pub cruise_speed_mps: Option<f64>,
    /// Minimum turning radius (also accepted as `min_turn_radius_m`).
    #[serde(default, skip_serializing_if = "Option::is_none", alias = "min_turn_radius_m")]
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 5000.0))]
    pub turn_radius_m: Option<f64>,
    /// Battery (or, ground vehicle, tank) energy, Wh: at most 100 000 for an aircraft.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 20000000.0))]
    pub battery_wh: Option<f64>,
    /// Share of the battery kept at landing, 0 to 0.9.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 0.9))]
    pub battery_reserve: Option<f64>,
    /// Ground vehicle: width of the implement.
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 100.0))]
    pub working_width_m: Option<f64>,
    /// Ground vehicle: may reverse (Reeds–Shepp turns with cusps, three-point turns).
    pub reverse_allowed: Option<bool>,
    /// Ground vehicle: continuous-curvature turns with this steering limit, 1/m².
    #[cfg_attr(feature = "schema", schema(minimum = 0.0001, maximum = 10.0))]
    pub max_curvature_rate: Option<f64>,
    /// Ground vehicle: speed of turns and transits.
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 30.0))]
    pub headland_speed_mps: Option<f64>,
    /// An aircraft's strongest wind to plan in.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 60.0))]
    pub max_wind_mps: Option<f64>,
}

impl VehicleParams {
    /// The profile named (or the kind's default) from `profiles`, with the overrides applied;
    /// `at` is the JSON pointer of these parameters in the request.
    pub fn resolve(&self, profiles: &[Vehicle], at: &str) -> Result<Vehicle, InputError> {
        let name = self.profile.as_deref().unwrap_or(default_profile(self.kind));
        let mut v = profiles.iter().find(|p| p.profile == name).cloned().ok_or_else(|| {
            let known: Vec<&str> = profiles.iter().map(|p| p.profile.as_str()).collect();
            InputError::new("unknown_vehicle_profile", format!("{at}/profile"), format!("no vehicle profile named `{name}`; known: {}", known.join(", ")))
        })?;
        if let Some(kind) = self.kind
            && kind != v.kind
        {
            return Err(InputError::new("vehicle_kind_mismatch", format!("{at}/kind"), format!("profile `{}` is not of this kind", v.profile)));
        }
        if let Some(s) = self.cruise_speed_mps {
            v.cruise_speed_mps = s;
        }
        if let Some(r) = self.turn_radius_m {
            v.turn_radius_m = r;
        }
        if let Some(e) = self.battery_wh {
            v.battery.energy_wh = e;
        }
        if let Some(r) = self.battery_reserve {
            v.battery.reserve = r;
        }
        if let Some(w) = self.max_wind_mps {
            v.max_wind_mps = Some(w);
        }
        self.apply_ground(&mut v, at)?;
        v.validate(at)?;
        Ok(v)
    }

    /// The ground vehicle's overrides; refused for an aircraft.
    fn apply_ground(&self, v: &mut Vehicle, at: &str) -> Result<(), InputError> {
        let given = [self.working_width_m.is_some(), self.reverse_allowed.is_some(), self.max_curvature_rate.is_some(), self.headland_speed_mps.is_some()];
        let Some(g) = v.ground.as_mut() else {
            return match GROUND_OVERRIDES.iter().zip(given).find(|(_, set)| *set) {
                Some((name, _)) => Err(InputError::new("not_a_ground_vehicle", format!("{at}/{name}"), format!("profile `{}` is not a ground vehicle", v.profile))),
                None => Ok(()),
            };
        };
        if let Some(w) = self.working_width_m {
            g.working_width_m = w;
        }
        if let Some(r) = self.reverse_allowed {
            g.reverse_allowed = r;
        }
        if let Some(k) = self.max_curvature_rate {
            g.max_curvature_rate = Some(k);
        }
        if let Some(s) = self.headland_speed_mps {
            g.headland_speed_mps = s;
        }
        Ok(())
    }
}

impl Vehicle {
    /// How this vehicle turns: on the spot, or on Dubins paths of its turning radius.
    pub fn turn_model(&self) -> TurnModel {
        match self.kind {
            VehicleKind::Multirotor => TurnModel::Straight,
            VehicleKind::FixedWing => TurnModel::Dubins(self.turn_radius_m),
            VehicleKind::Ground => TurnModel::Dubins(self.planning_radius_m()),
        }
    }

    /// The radius turns are planned on: the turning radius, or with a curvature rate the radius
    /// of the circle that bounds the continuous-curvature turn (docs/methods.md, ground §3).
    pub fn planning_radius_m(&self) -> f64 {
        match self.ground.and_then(|g| g.max_curvature_rate) {
            Some(rate) => cc_circle_radius(self.turn_radius_m, rate),
            None => self.turn_radius_m,
        }
    }

    /// How a ground vehicle steers (any other steers forward only, instantly).
    pub fn steering(&self) -> Steering {
        let g = self.ground;
        Steering::new(self.turn_radius_m, g.is_some_and(|g| g.reverse_allowed), g.and_then(|g| g.max_curvature_rate))
    }

    /// A ground vehicle's speed in turns and transits (any other's cruise speed).
    pub fn headland_speed_mps(&self) -> f64 {
        self.ground.map_or(self.cruise_speed_mps, |g| g.headland_speed_mps)
    }

    /// The energy model of this vehicle: its profile's model, flown at its speed and turns
    /// (a multirotor stops at corners, decelerating and accelerating at `acceleration_mps2`).
    pub fn energy_model(&self) -> Box<dyn EnergyModel + '_> {
        let headland_speed_mps = self.headland_speed_mps();
        let corner_stop_s = match self.kind {
            VehicleKind::Multirotor => self.cruise_speed_mps / self.acceleration_mps2,
            VehicleKind::FixedWing => 0.0,
            // a reversal: stop from the turning speed and start again
            VehicleKind::Ground => 2.0 * headland_speed_mps / self.acceleration_mps2,
        };
        self.energy.model(Motion {
            cruise_speed_mps: self.cruise_speed_mps,
            turn_radius_m: self.turn_radius_m,
            corner_stop_s,
            headland_speed_mps,
            multirotor: self.kind == VehicleKind::Multirotor,
        })
    }

    /// [`Self::energy_model`] flown in `wind` (none, or a calm: exactly the still-air model).
    pub fn energy_model_in(&self, wind: Option<&Wind>) -> Box<dyn EnergyModel + '_> {
        match wind.filter(|w| w.speed_mps > 0.0) {
            Some(w) => Box::new(InWind { model: self.energy_model(), wind: w.velocity() }),
            None => self.energy_model(),
        }
    }

    /// Refuses a `wind` (at the flight altitude) this vehicle cannot plan in: a ground vehicle
    /// (wind changes nothing of its work), a wind above its `max_wind_mps`, or, for a fixed
    /// wing, at least its airspeed. `at` is the JSON pointer of the wind, `vehicle_at` the
    /// vehicle's.
    pub fn check_wind(&self, wind: &Wind, at: &str, vehicle_at: &str) -> Result<(), InputError> {
        if self.kind == VehicleKind::Ground {
            return Err(InputError::new("not_for_ground_vehicles", at, "a ground vehicle's work does not change with the wind: leave out wind"));
        }
        let fixed_wing = self.kind == VehicleKind::FixedWing;
        let own = self.max_wind_mps.unwrap_or(self.cruise_speed_mps);
        // a fixed wing makes no headway against a wind as fast as its airspeed
        if wind.speed_mps > own || (fixed_wing && wind.speed_mps >= self.cruise_speed_mps) {
            let limit = if fixed_wing { format!("{:.1} m/s, below its airspeed", own.min(self.cruise_speed_mps)) } else { format!("{own:.1} m/s") };
            return Err(InputError::new(
                "wind_too_strong",
                format!("{at}/speed_mps"),
                format!(
                    "a wind of {:.1} m/s at the flight altitude is beyond what `{}` plans in ({limit}): fly another day, lower, or give the vehicle's own max_wind_mps",
                    wind.speed_mps, self.profile
                ),
            ));
        }
        // a multirotor holding its ground speed into the wind flies at up to both together
        if let EnergyParams::MultirotorIem(c) = &self.energy {
            c.check(self.cruise_speed_mps + wind.speed_mps, &format!("{vehicle_at}/energy/parameters"))
                .map_err(|e| InputError::new("wind_too_strong", format!("{at}/speed_mps"), format!("the energy model cannot price flight into this wind: {}", e.detail)))?;
        }
        Ok(())
    }

    /// Checks every figure; `at` is the JSON pointer of the profile in the request.
    pub fn validate(&self, at: &str) -> Result<(), InputError> {
        let id_ok = !self.profile.is_empty() && self.profile.len() <= 64 && self.profile.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_' || b == b'-');
        if !id_ok {
            return Err(InputError::new("invalid_profile_id", format!("{at}/profile"), "1 to 64 characters: lower-case letters, digits, `_` and `-`"));
        }
        let range = |v: f64, lo: f64, hi: f64, field: &str, unit: &str| check_range(v, lo, hi, &format!("{at}/{field}"), unit);
        range(self.cruise_speed_mps, 0.5, 100.0, "cruise_speed_mps", "m/s")?;
        range(self.turn_radius_m, 0.0, 5_000.0, "turn_radius_m", "m")?;
        range(self.acceleration_mps2, 0.1, 20.0, "acceleration_mps2", "m/s²")?;
        // a tractor's tank holds megawatt-hours of fuel
        range(self.battery.energy_wh, 1.0, MAX_TANK_WH, "battery/energy_wh", "Wh")?;
        if self.kind != VehicleKind::Ground && self.battery.energy_wh > MAX_BATTERY_WH {
            return Err(InputError::new("battery_too_large", format!("{at}/battery/energy_wh"), format!("an aircraft's battery holds at most {MAX_BATTERY_WH} Wh")));
        }
        range(self.battery.reserve, 0.0, 0.9, "battery/reserve", "")?;
        if let Some(w) = self.max_wind_mps {
            range(w, 0.0, MAX_WIND_MPS, "max_wind_mps", "m/s")?;
        }
        if self.kind == VehicleKind::FixedWing && self.turn_radius_m < 1.0 {
            return Err(InputError::new("turn_radius_too_small", format!("{at}/turn_radius_m"), "a fixed-wing aircraft needs a turning radius of at least 1 m"));
        }
        match (self.kind, &self.ground) {
            (VehicleKind::Ground, None) => {
                return Err(InputError::new("ground_figures_missing", format!("{at}/ground"), "a ground vehicle needs its working width and headland speed"));
            }
            (VehicleKind::Ground, Some(g)) => {
                range(g.working_width_m, 0.5, 100.0, "ground/working_width_m", "m")?;
                range(g.headland_speed_mps, 0.1, 30.0, "ground/headland_speed_mps", "m/s")?;
                if let Some(k) = g.max_curvature_rate {
                    range(k, 0.0001, 10.0, "ground/max_curvature_rate", "1/m²")?;
                }
                if self.turn_radius_m < 0.5 {
                    return Err(InputError::new("turn_radius_too_small", format!("{at}/turn_radius_m"), "a ground vehicle needs a turning radius of at least 0.5 m"));
                }
                // continuous-curvature turns are built for steering that reaches full lock within
                // a quarter turn (docs/methods.md, ground §3)
                let least = 2.0 / (std::f64::consts::PI * self.turn_radius_m * self.turn_radius_m);
                if g.max_curvature_rate.is_some_and(|k| k < least) {
                    return Err(InputError::new(
                        "curvature_rate_too_low",
                        format!("{at}/ground/max_curvature_rate"),
                        format!(
                            "steering this slow does not reach the {:.1} m turning radius within a quarter turn: give at least {least:.4} 1/m² (full lock within {:.1} m of travel)",
                            self.turn_radius_m,
                            std::f64::consts::FRAC_PI_2 * self.turn_radius_m
                        ),
                    ));
                }
            }
            (_, Some(_)) => return Err(InputError::new("not_a_ground_vehicle", format!("{at}/ground"), "only a ground vehicle has ground figures")),
            _ => {}
        }
        self.energy.check(self.cruise_speed_mps, &format!("{at}/energy/parameters"))?;
        let fits = matches!(
            (&self.energy, self.kind),
            (EnergyParams::ConstantPower(_), _)
                | (EnergyParams::MultirotorIem(_), VehicleKind::Multirotor)
                | (EnergyParams::FixedWing(_), VehicleKind::FixedWing)
                | (EnergyParams::Ground(_), VehicleKind::Ground)
        );
        if !fits {
            return Err(InputError::new("vehicle_kind_mismatch", format!("{at}/energy/model"), "this energy model is for the other kind of vehicle"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtins_are_valid_and_overrides_are_checked() {
        let all = builtin_profiles();
        for v in &all {
            v.validate("").unwrap_or_else(|e| panic!("{}: {e}", v.profile));
        }
        let fixed = VehicleParams { kind: Some(VehicleKind::FixedWing), ..Default::default() }.resolve(&all, "/vehicle").unwrap();
        assert_eq!(fixed.profile, "generic_fixed_wing");
        let tractor = VehicleParams { kind: Some(VehicleKind::Ground), working_width_m: Some(12.0), ..Default::default() }.resolve(&all, "/vehicle").unwrap();
        assert_eq!(tractor.ground.unwrap().working_width_m, 12.0);
        let drone_with_implement = VehicleParams { working_width_m: Some(6.0), ..Default::default() }.resolve(&all, "/vehicle").unwrap_err();
        assert_eq!((drone_with_implement.code, drone_with_implement.pointer.as_str()), ("not_a_ground_vehicle", "/vehicle/working_width_m"));
        let iris = VehicleParams { profile: Some("iris".into()), battery_wh: Some(20.0), ..Default::default() }.resolve(&all, "/vehicle").unwrap();
        assert_eq!(iris.battery.energy_wh, 20.0);
        let bad = VehicleParams { profile: Some("iris".into()), battery_reserve: Some(1.5), ..Default::default() }.resolve(&all, "/vehicle");
        assert_eq!(bad.unwrap_err().pointer, "/vehicle/battery/reserve");
        let unknown = VehicleParams { profile: Some("zeppelin".into()), ..Default::default() }.resolve(&all, "/vehicle").unwrap_err();
        assert!(unknown.detail.contains("iris"), "{}", unknown.detail);
        let mismatch = VehicleParams { profile: Some("maja".into()), kind: Some(VehicleKind::Multirotor), ..Default::default() }.resolve(&all, "/vehicle");
        assert_eq!(mismatch.unwrap_err().code, "vehicle_kind_mismatch");
    }
}
