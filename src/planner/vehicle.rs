//! Vehicles: profiles (built-in or stored by the service) and per-plan overrides.

use serde::{Deserialize, Serialize};

use super::energy::constant_power::PowerFigures;
use super::energy::fixed_wing::Airframe;
use super::energy::iem::IemCoefficients;
use super::energy::{EnergyModel, EnergyParams, Motion};
use super::error::{InputError, check_range};
use super::turn::TurnModel;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum VehicleKind {
    Multirotor,
    FixedWing,
}

/// The battery: its energy and the share kept in reserve at landing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Battery {
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 100000.0))]
    pub energy_wh: f64,
    /// Fraction of `energy_wh` that must be left at landing (default 0.25).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 0.9))]
    pub reserve: f64,
}

impl Battery {
    /// Energy a sortie may use, in joules.
    pub fn usable_j(&self) -> f64 {
        self.energy_wh * 3600.0 * (1.0 - self.reserve)
    }
}

/// A vehicle profile with every figure the planner needs.
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
    pub battery: Battery,
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
        },
    ]
}

/// The profile used for a kind when no profile is named.
fn default_profile(kind: Option<VehicleKind>) -> &'static str {
    match kind {
        Some(VehicleKind::FixedWing) => "generic_fixed_wing",
        _ => "generic_multirotor",
    }
}

/// The vehicle part of a plan request: a profile, a kind, or both, with optional overrides.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct VehicleParams {
    /// Name of a profile, as listed by `GET /api/v1/vehicles`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<VehicleKind>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cruise_speed_mps: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_radius_m: Option<f64>,
    /// Battery energy, Wh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub battery_wh: Option<f64>,
    /// Share of the battery kept at landing, 0 to 0.9.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub battery_reserve: Option<f64>,
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
        v.validate(at)?;
        Ok(v)
    }
}

impl Vehicle {
    /// How this vehicle turns: on the spot, or on Dubins paths of its turning radius.
    pub fn turn_model(&self) -> TurnModel {
        match self.kind {
            VehicleKind::Multirotor => TurnModel::Straight,
            VehicleKind::FixedWing => TurnModel::Dubins(self.turn_radius_m),
        }
    }

    /// The energy model of this vehicle: its profile's model, flown at its speed and turns
    /// (a multirotor stops at corners, decelerating and accelerating at `acceleration_mps2`).
    pub fn energy_model(&self) -> Box<dyn EnergyModel + '_> {
        let corner_stop_s = match self.kind {
            VehicleKind::Multirotor => self.cruise_speed_mps / self.acceleration_mps2,
            VehicleKind::FixedWing => 0.0,
        };
        self.energy.model(Motion { cruise_speed_mps: self.cruise_speed_mps, turn_radius_m: self.turn_radius_m, corner_stop_s })
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
        range(self.battery.energy_wh, 1.0, 100_000.0, "battery/energy_wh", "Wh")?;
        range(self.battery.reserve, 0.0, 0.9, "battery/reserve", "")?;
        if self.kind == VehicleKind::FixedWing && self.turn_radius_m < 1.0 {
            return Err(InputError::new("turn_radius_too_small", format!("{at}/turn_radius_m"), "a fixed-wing aircraft needs a turning radius of at least 1 m"));
        }
        self.energy.check(self.cruise_speed_mps, &format!("{at}/energy/parameters"))?;
        let fits = self.energy.for_fixed_wing().is_none_or(|fixed_wing| fixed_wing == (self.kind == VehicleKind::FixedWing));
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
