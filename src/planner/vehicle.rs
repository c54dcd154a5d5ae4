//! Vehicles: built-in profiles and per-plan overrides.

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use super::error::InputError;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum VehicleKind {
    Multirotor,
    FixedWing,
}

/// A resolved vehicle with every figure the planner needs.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct Vehicle {
    pub profile: String,
    pub kind: VehicleKind,
    pub cruise_speed_mps: f64,
    /// Minimum turning radius (0 for a multirotor, which stops and turns on the spot).
    pub turn_radius_m: f64,
    /// Acceleration and deceleration at corners (multirotor).
    pub acceleration_mps2: f64,
    /// Electrical power drawn in cruise, the default energy model's single coefficient.
    pub cruise_power_w: f64,
}

/// Built-in profiles. Figures are typical assumptions, documented in the README, not
/// measurements of a particular airframe.
pub fn builtin_profiles() -> Vec<Vehicle> {
    vec![
        Vehicle {
            profile: "generic_multirotor".into(),
            kind: VehicleKind::Multirotor,
            cruise_speed_mps: 8.0,
            turn_radius_m: 0.0,
            acceleration_mps2: 2.0,
            cruise_power_w: 250.0,
        },
        Vehicle {
            profile: "generic_fixed_wing".into(),
            kind: VehicleKind::FixedWing,
            cruise_speed_mps: 15.0,
            turn_radius_m: 50.0,
            acceleration_mps2: 1.0,
            cruise_power_w: 150.0,
        },
    ]
}

/// The vehicle part of a plan request: a profile, a kind, or both, with optional overrides.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct VehicleParams {
    /// Name of a profile (`generic_multirotor`, `generic_fixed_wing`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<VehicleKind>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cruise_speed_mps: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_radius_m: Option<f64>,
}

impl VehicleParams {
    pub fn resolve(&self) -> Result<Vehicle, InputError> {
        let profiles = builtin_profiles();
        let mut v = match (&self.profile, self.kind) {
            (Some(name), _) => profiles.into_iter().find(|p| &p.profile == name).ok_or_else(|| {
                InputError::new(
                    "unknown_vehicle_profile",
                    "/vehicle/profile",
                    format!("no vehicle profile named `{name}`; known: generic_multirotor, generic_fixed_wing"),
                )
            })?,
            (None, Some(kind)) => profiles.into_iter().find(|p| p.kind == kind).expect("a profile per kind"),
            (None, None) => profiles.into_iter().next().expect("a default profile"),
        };
        if let Some(kind) = self.kind {
            if kind != v.kind {
                return Err(InputError::new("vehicle_kind_mismatch", "/vehicle/kind", format!("profile `{}` is not of this kind", v.profile)));
            }
        }
        if let Some(s) = self.cruise_speed_mps {
            check_range(s, 0.5, 100.0, "/vehicle/cruise_speed_mps", "m/s")?;
            v.cruise_speed_mps = s;
        }
        if let Some(r) = self.turn_radius_m {
            check_range(r, 0.0, 5_000.0, "/vehicle/turn_radius_m", "m")?;
            v.turn_radius_m = r;
        }
        if v.kind == VehicleKind::FixedWing && v.turn_radius_m < 1.0 {
            return Err(InputError::new("turn_radius_too_small", "/vehicle/turn_radius_m", "a fixed-wing aircraft needs a turning radius of at least 1 m"));
        }
        Ok(v)
    }
}

impl Vehicle {
    /// How this vehicle turns: on the spot, or on Dubins paths of its turning radius.
    pub fn turn_model(&self) -> crate::turn::TurnModel {
        match self.kind {
            VehicleKind::Multirotor => crate::turn::TurnModel::Straight,
            VehicleKind::FixedWing => crate::turn::TurnModel::Dubins(self.turn_radius_m),
        }
    }
}

/// Checks that `value` is finite and within `[lo, hi]`.
pub fn check_range(value: f64, lo: f64, hi: f64, pointer: &str, unit: &str) -> Result<(), InputError> {
    if !value.is_finite() || value < lo || value > hi {
        return Err(InputError::new(
            "parameter_out_of_range",
            pointer,
            format!("{value} is outside the accepted range [{lo}, {hi}] {unit}"),
        ));
    }
    Ok(())
}
