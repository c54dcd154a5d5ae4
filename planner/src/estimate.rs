//! Estimates for a route made elsewhere: farm software sends its own waypoints and gets the
//! energy and time the vehicle's model predicts, leg by leg (`POST /api/v1/estimates`).

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::energy::PathEstimate;
use super::error::InputError;
use super::field::check_position;
use super::frame::LocalFrame;
use super::path::{FlightPath, PieceKind};
use super::vehicle::{Vehicle, VehicleParams};
use super::wind::{Triangle, Wind};

/// Most waypoints one request may carry.
pub const MAX_WAYPOINTS: usize = 100_000;

#[derive(Debug, Clone, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct EstimateRequest {
    /// A GeoJSON LineString (or a Feature holding one); a third coordinate is the altitude.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(value_type = Option<Object>))]
    pub route: Option<Value>,
    /// Or the waypoints: `[longitude, latitude]` or `[longitude, latitude, altitude_m]`.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 100000))]
    pub waypoints: Option<Vec<Vec<f64>>>,
    #[serde(default)]
    pub vehicle: VehicleParams,
    /// A steady wind the route is flown in (with `height_m`, carried to the route's mean
    /// altitude).
    pub wind: Option<Wind>,
}

#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct LegEstimate {
    /// Index of the waypoint the leg starts at.
    pub from: usize,
    pub length_m: f64,
    pub speed_mps: f64,
    pub v_in_mps: f64,
    pub v_out_mps: f64,
    pub duration_s: f64,
    pub energy_j: f64,
    /// In wind: the leg's ground speed, airspeed and crab angle.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wind: Option<Triangle>,
}

#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct RouteTotals {
    pub length_m: f64,
    /// Flight time and energy, climbing to the first waypoint's altitude and descending from
    /// the last one's included.
    pub duration_s: f64,
    pub energy_j: f64,
    pub energy_wh: f64,
    pub takeoff_landing_energy_j: f64,
    /// Share of one battery's usable energy (above its reserve); over 1 needs more sorties.
    pub battery_used: f64,
}

#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct RouteEstimate {
    pub vehicle: String,
    pub totals: RouteTotals,
    pub legs: Vec<LegEstimate>,
}

/// The waypoints of a request with the JSON pointer of each, before any check.
fn waypoints(req: &EstimateRequest) -> Result<(Vec<Vec<f64>>, String), InputError> {
    match (&req.route, &req.waypoints) {
        (Some(_), Some(_)) => Err(InputError::new("route_twice", "/waypoints", "give either route or waypoints, not both")),
        (None, None) => Err(InputError::new("route_missing", "/route", "give route (a GeoJSON LineString) or waypoints")),
        (None, Some(w)) => Ok((w.clone(), "/waypoints".into())),
        (Some(route), None) => {
            let (geometry, at) = match route.get("type").and_then(Value::as_str) {
                Some("Feature") => (route.get("geometry").unwrap_or(&Value::Null), "/route/geometry"),
                _ => (route, "/route"),
            };
            if geometry.get("type").and_then(Value::as_str) != Some("LineString") {
                return Err(InputError::new("not_a_linestring", format!("{at}/type"), "the route must be a GeoJSON LineString"));
            }
            let coords = geometry
                .get("coordinates")
                .and_then(|c| serde_json::from_value::<Vec<Vec<f64>>>(c.clone()).ok())
                .ok_or_else(|| InputError::new("invalid_geojson", format!("{at}/coordinates"), "coordinates must be an array of [longitude, latitude(, altitude)] numbers"))?;
            Ok((coords, format!("{at}/coordinates")))
        }
    }
}

/// Checks the request and estimates the route with the vehicle resolved from `profiles`.
pub fn estimate_route(req: &EstimateRequest, profiles: &[Vehicle]) -> Result<RouteEstimate, InputError> {
    let vehicle = req.vehicle.resolve(profiles, "/vehicle")?;
    let (points, at) = waypoints(req)?;
    if points.len() < 2 || points.len() > MAX_WAYPOINTS {
        return Err(InputError::new("waypoint_count", at, format!("a route has 2 to {MAX_WAYPOINTS} waypoints; this one has {}", points.len())));
    }
    let mut positions = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let here = format!("{at}/{i}");
        if !(2..=3).contains(&p.len()) {
            return Err(InputError::new("invalid_position", here, "a waypoint is [longitude, latitude] or [longitude, latitude, altitude_m]"));
        }
        check_position(&[p[0], p[1]], &here)?;
        let z = p.get(2).copied().unwrap_or(0.0);
        super::error::check_range(z, -500.0, 10_000.0, &format!("{here}/2"), "m")?;
        positions.push(([p[0], p[1]], z));
    }
    let frame = LocalFrame::centred_on(positions.iter().map(|(p, _)| *p));
    let mut path = FlightPath::default();
    for w in positions.windows(2) {
        let (a, b) = (frame.to_local(w[0].0[0], w[0].0[1]), frame.to_local(w[1].0[0], w[1].0[1]));
        if (b - a).x.hypot((b - a).y) > 1_000_000.0 {
            return Err(InputError::new("leg_too_long", at.clone(), "a leg is longer than 1000 km"));
        }
        // a zero-length leg (a pure climb) is kept as such: FlightPath drops it, so push by hand
        path.pieces.push(super::path::Piece { z: vec![w[0].1, w[1].1], ..super::path::Piece::new(PieceKind::Transit, vec![a, b], 0.0) });
    }
    let wind = match &req.wind {
        Some(w) => {
            w.check("/wind")?;
            let mean_altitude = positions.iter().map(|p| p.1).sum::<f64>() / positions.len() as f64;
            let w = w.at_altitude(Some(mean_altitude));
            vehicle.check_wind(&w, "/wind", "/vehicle")?;
            Some(w)
        }
        None => None,
    };
    let model = vehicle.energy_model_in(wind.as_ref());
    // climb to the first waypoint's altitude, descend from the last one's
    let [takeoff, landing] = model.flight_ends(positions[0].1.max(0.0), positions[positions.len() - 1].1.max(0.0));
    let estimate = PathEstimate { pieces: model.pieces(&path), takeoff, landing };
    let legs = path
        .pieces
        .iter()
        .zip(&estimate.pieces)
        .enumerate()
        .map(|(i, (p, e))| LegEstimate {
            from: i,
            length_m: p.length(),
            speed_mps: e.speed_mps,
            v_in_mps: e.v_in_mps,
            v_out_mps: e.v_out_mps,
            duration_s: e.duration_s,
            energy_j: e.energy_j,
            wind: e.wind,
        })
        .collect();
    let energy_j = estimate.energy_j();
    Ok(RouteEstimate {
        vehicle: vehicle.profile.clone(),
        totals: RouteTotals {
            length_m: path.length(),
            duration_s: estimate.duration_s(),
            energy_j,
            energy_wh: energy_j / 3600.0,
            takeoff_landing_energy_j: estimate.takeoff_landing_j(),
            battery_used: energy_j / vehicle.battery.usable_j(),
        },
        legs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vehicle::builtin_profiles;
    use serde_json::json;

    fn request(v: Value) -> EstimateRequest {
        serde_json::from_value(v).unwrap()
    }

    #[test]
    fn a_square_route_costs_what_its_legs_cost() {
        // about 100 m a side near the equator, at 10 m
        let d = 100.0 / 111_320.0;
        let r = request(json!({"waypoints": [[0, 0, 10], [d, 0, 10], [d, d, 10], [0, d, 10]], "vehicle": {"profile": "iris"}}));
        let e = estimate_route(&r, &builtin_profiles()).unwrap();
        assert_eq!(e.legs.len(), 3);
        let legs: f64 = e.legs.iter().map(|l| l.energy_j).sum();
        assert!((legs + e.totals.takeoff_landing_energy_j - e.totals.energy_j).abs() < 1e-6);
        // climbing 10 m at the measured rate; landing as ArduCopter does, hovering over home and
        // sinking slowly over the last 10 m
        let hover_w = crate::energy::iem::IemCoefficients::iris().hover_power_w();
        let landing_j = (crate::energy::RTL_HOVER_S + 10.0 / crate::energy::LAND_SPEED_MPS) * hover_w;
        assert!((e.totals.takeoff_landing_energy_j - 10.0 * 119.08 - landing_j).abs() < 1.0, "{}", e.totals.takeoff_landing_energy_j);
        assert!(e.legs[1].v_in_mps > 0.0 && e.legs[2].v_out_mps == 0.0);
    }

    #[test]
    fn a_calm_prices_exactly_as_still_air_and_a_wind_by_its_triangle() {
        let profiles = builtin_profiles();
        // 2 km east at 60 m, then 2 km north
        let (dx, dy) = (2000.0 / 111_320.0, 2000.0 / 110_574.0);
        let route = |vehicle: &str, wind: Value| request(json!({"waypoints": [[0, 0, 60], [dx, 0, 60], [dx, dy, 60]], "vehicle": {"profile": vehicle}, "wind": wind}));
        for vehicle in ["iris", "generic_fixed_wing", "generic_multirotor"] {
            let still = estimate_route(&route(vehicle, Value::Null), &profiles).unwrap();
            let calm = estimate_route(&route(vehicle, json!({"speed_mps": 0, "from_deg": 90})), &profiles).unwrap();
            assert_eq!(serde_json::to_value(&still.totals).unwrap(), serde_json::to_value(&calm.totals).unwrap(), "{vehicle}");
        }
        // a fixed wing at 15 m/s in 6 m/s from the west: the leg east at 21 m/s, north at √189
        let windy = estimate_route(&route("generic_fixed_wing", json!({"speed_mps": 6, "from_deg": 270})), &profiles).unwrap();
        let still = estimate_route(&route("generic_fixed_wing", Value::Null), &profiles).unwrap();
        for (leg, ground) in windy.legs.iter().zip([21.0, 189f64.sqrt()]) {
            let w = leg.wind.expect("a leg in wind says its triangle");
            assert!((w.ground_speed_mps - ground).abs() < 1e-6 && (w.airspeed_mps - 15.0).abs() < 1e-12, "{w:?}");
        }
        // the legs take their length over the ground speed, less what the still-air turn adds
        let straight = |legs: &[LegEstimate], k: usize| legs[k].duration_s - legs[k].length_m / 15.0;
        assert!((windy.legs[0].duration_s - windy.legs[0].length_m / 21.0 - straight(&still.legs, 0)).abs() < 0.5, "{:?}", windy.legs[0]);
        // a multirotor holding 7.8 m/s over the ground flies north with a crab into the west wind
        let iris = estimate_route(&route("iris", json!({"speed_mps": 6, "from_deg": 270})), &profiles).unwrap();
        let north = iris.legs[1].wind.unwrap();
        assert!(north.crab_deg < -30.0 && north.airspeed_mps > north.ground_speed_mps, "{north:?}");
    }

    #[test]
    fn bad_routes_are_refused_where_they_are_wrong() {
        let profiles = builtin_profiles();
        let err = |v: Value| estimate_route(&request(v), &profiles).unwrap_err();
        assert_eq!(err(json!({"waypoints": [[0, 0]]})).code, "waypoint_count");
        assert_eq!(err(json!({"waypoints": [[0, 0], [0, 95]]})).pointer, "/waypoints/1");
        assert_eq!(err(json!({"route": {"type": "Point", "coordinates": [0, 0]}})).pointer, "/route/type");
        assert_eq!(err(json!({"route": {"type": "LineString", "coordinates": [[0, 0], [0.001, 0, 1e9]]}})).pointer, "/route/coordinates/1/2");
        assert_eq!(err(json!({})).code, "route_missing");
    }
}
