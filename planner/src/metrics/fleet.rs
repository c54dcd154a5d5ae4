//! A fleet plan's figures: each drone's part, and where two come too close.

use serde::{Deserialize, Serialize};

/// One drone's part of a fleet plan.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct VehicleTotals {
    /// 0-based, as in the request's `fleet` (or the copy of `vehicles`).
    pub vehicle: usize,
    pub profile: String,
    /// Area of its part of the field (0: the drone is not needed).
    pub area_m2: f64,
    pub sweep_lines: usize,
    pub sorties: usize,
    pub length_m: f64,
    pub duration_s: f64,
    pub energy_j: f64,
    /// Seconds after the fleet's start it takes off (drones sharing a home leave in turn).
    pub departure_s: f64,
    /// Seconds after the fleet's start it lands for the last time.
    pub landing_s: f64,
    /// Altitude of its transits, with `altitude_separation_m`.
    pub transit_altitude_m: Option<f64>,
}

/// Two drones of a fleet too close at the same time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Conflict {
    pub vehicles: [usize; 2],
    /// Seconds after the fleet's start.
    pub from_s: f64,
    pub to_s: f64,
    /// Their least horizontal distance.
    pub closest_m: f64,
    /// [longitude, latitude] midway between them at their closest.
    pub position: [f64; 2],
}
