//! What a ground vehicle carries (`payload`): a sprayer's tank or a spreader's hopper that runs
//! empty, or a harvester's grain tank that runs full, and where it is refilled or unloaded.

use serde::{Deserialize, Serialize};

use super::{InputError, check_lon_lat, check_range};

/// A tank, what working a hectare takes from it (or adds to it), and where it is refilled
/// or unloaded.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Payload {
    /// What the tank holds, in litres or kilograms (the unit of `rate_per_ha`), 1 to 100 000.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 100000.0))]
    pub capacity: f64,
    /// What the implement applies per hectare worked (litres or kilograms), or for a harvest
    /// the yield per hectare, 0.01 to 100 000.
    #[cfg_attr(feature = "schema", schema(minimum = 0.01, maximum = 100000.0))]
    pub rate_per_ha: f64,
    /// `true`: the tank fills as the vehicle works (a harvester's grain tank) and is emptied
    /// at the points; default `false`, it empties (a sprayer, a spreader) and is refilled there.
    pub harvest: Option<bool>,
    /// Where the tank is refilled or unloaded, [longitude, latitude] each: points on the field's
    /// boundary or its entrances, at most 100 m from the field; 1 to 20 points.
    #[cfg_attr(feature = "schema", schema(min_items = 1, max_items = 20))]
    pub refill_points: Vec<[f64; 2]>,
    /// Seconds the vehicle stands at a refill point to refill or unload, 0 to 7 200 (default
    /// 900, as a farm plan's machines): counted in the plan's duration.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 7200.0))]
    pub refill_s: Option<f64>,
}

/// Seconds a refill or an unloading takes unless the payload says.
pub const DEFAULT_REFILL_S: f64 = 900.0;

/// Most refill points.
const MAX_REFILL_POINTS: usize = 20;

/// Farthest a refill point may lie from the field, metres.
pub const REFILL_POINT_REACH_M: f64 = 100.0;

impl Payload {
    /// The payload, or what is wrong with it.
    pub fn validate(&self) -> Result<(), InputError> {
        check_range(self.capacity, 1.0, 100_000.0, "/payload/capacity", "")?;
        check_range(self.rate_per_ha, 0.01, 100_000.0, "/payload/rate_per_ha", "per ha")?;
        if let Some(s) = self.refill_s {
            check_range(s, 0.0, 7_200.0, "/payload/refill_s", "s")?;
        }
        let n = self.refill_points.len();
        if !(1..=MAX_REFILL_POINTS).contains(&n) {
            return Err(InputError::new("parameter_out_of_range", "/payload/refill_points", format!("give 1 to {MAX_REFILL_POINTS} refill points, not {n}")));
        }
        for (k, &p) in self.refill_points.iter().enumerate() {
            check_lon_lat(p, &format!("/payload/refill_points/{k}"))?;
        }
        Ok(())
    }

    /// What a square metre worked takes from the tank or adds to it.
    pub fn per_m2(&self) -> f64 {
        self.rate_per_ha / 10_000.0
    }

    /// Seconds stood at a refill point.
    pub fn refill_s(&self) -> f64 {
        self.refill_s.unwrap_or(DEFAULT_REFILL_S)
    }
}
