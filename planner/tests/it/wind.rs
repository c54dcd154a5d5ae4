//! Plans in wind over the random fields (holes as no-fly zones), for a multirotor and a fixed
//! wing, in winds of 0.3 and 0.5 of the airspeed from 8 directions: a calm changes nothing; the
//! wind-aware plan never predicts more energy (multirotor) or time (fixed wing) than the plan
//! made as in still air, flown in the same wind (for a multirotor, checked against its
//! trajectory priced here; a fixed wing flies that plan's lines with the turns the wind lets
//! it fly, so only the plan knows that flight); no ground
//! track enters a no-fly zone; a fixed wing's path, as the air sees it, bends no tighter than
//! its turning radius (its bank limit).

use coverplan_planner::frame::LocalFrame;
use coverplan_planner::geojson::{FeatureCollection, GeometryValue};
use coverplan_planner::path::{FlightPath, Piece, PieceKind};
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::wind::{Wind, air_path};
use coverplan_planner::{FieldLimits, MissionGeometry, PlanOutput, PlanParams, Stop, plan};
use geo::{Coord, Intersects, LineString, MapCoords, MultiPolygon};
use proptest::prelude::*;
use serde::Deserialize;
use serde_json::{Value, json};

fn field(k: usize) -> Value {
    let read = |path: &str| -> Value { serde_json::from_slice(&std::fs::read(format!("{}/../tests/fixtures/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()).unwrap() };
    let index = read("random-fields/index.json");
    let names: Vec<&str> = index.as_array().unwrap().iter().map(|e| e["file"].as_str().unwrap()).collect();
    read(&format!("random-fields/{}", names[k % names.len()]))
}

/// One sortie (a battery far larger than the plan), so that the plan's path is its flight.
fn params(fixed_wing: bool, wind: Option<Value>) -> PlanParams {
    let (profile, objective) = if fixed_wing { ("generic_fixed_wing", "time") } else { ("iris", "energy") };
    serde_json::from_value(json!({"vehicle": {"profile": profile, "battery_wh": 90000}, "line_spacing_m": 30, "altitude_m": 60, "objective": objective, "wind": wind})).unwrap()
}

fn run(field: &Value, p: &PlanParams) -> Result<PlanOutput, String> {
    let mission = MissionGeometry { no_fly_zones: Some(&field["no_fly_zones"]), ..MissionGeometry::area(&field["area"]) };
    plan(&mission, p, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).map_err(|e| e.to_string())
}

/// The trajectory's pieces in `frame`, in order.
fn path_of(trajectory: &FeatureCollection, frame: &LocalFrame) -> FlightPath {
    let pieces = trajectory.features.iter().filter_map(|f| {
        let props = f.properties.as_ref()?;
        let kind = PieceKind::deserialize(props.get("kind")?).ok()?;
        let GeometryValue::LineString { coordinates } = &f.geometry.as_ref()?.value else { return None };
        let points = coordinates.iter().map(|p| frame.to_local(p[0], p[1])).collect();
        Some(Piece::new(kind, points, 15.0))
    });
    FlightPath { pieces: pieces.collect() }
}

fn zones(field: &Value, frame: &LocalFrame) -> MultiPolygon {
    let geometry: geojson::Geometry = serde_json::from_value(field["no_fly_zones"].clone()).unwrap();
    let zones = match geo::Geometry::try_from(geometry).unwrap() {
        geo::Geometry::Polygon(p) => MultiPolygon(vec![p]),
        geo::Geometry::MultiPolygon(m) => m,
        other => panic!("not polygons: {other:?}"),
    };
    zones.map_coords(|c| frame.to_local(c.x, c.y))
}

#[test]
fn a_calm_plans_and_prices_exactly_as_still_air() {
    for k in [0, 5, 11] {
        let f = field(k);
        for fixed_wing in [false, true] {
            let still = run(&f, &params(fixed_wing, None)).unwrap();
            let calm = run(&f, &params(fixed_wing, Some(json!({"speed_mps": 0, "from_deg": 270})))).unwrap();
            let figures = |o: &PlanOutput| {
                let mut s = serde_json::to_value(&o.stats).unwrap();
                s.as_object_mut().unwrap().retain(|k, _| k != "planning_time_ms" && k != "wind");
                s
            };
            assert_eq!(figures(&still), figures(&calm), "field {k}, fixed wing {fixed_wing}");
            assert_eq!(still.trajectory, calm.trajectory, "field {k}, fixed wing {fixed_wing}");
            assert_eq!(calm.stats.wind.as_ref().map(|w| w.speed_mps), Some(0.0));
        }
    }
}

fn check_wind(k: usize, fixed_wing: bool, strength: f64, from_deg: f64) -> Result<(), TestCaseError> {
    let f = field(k);
    let profiles = builtin_profiles();
    let still = run(&f, &params(fixed_wing, None)).map_err(TestCaseError::fail)?;
    let vehicle = params(fixed_wing, None).vehicle.resolve(&profiles, "/vehicle").unwrap();
    let wind = Wind { speed_mps: strength * vehicle.cruise_speed_mps, from_deg, height_m: None };
    let windy = run(&f, &params(fixed_wing, Some(serde_json::to_value(wind).unwrap()))).map_err(TestCaseError::fail)?;
    let what = format!("field {k}, fixed wing {fixed_wing}, {:.1} m/s from {from_deg}°", wind.speed_mps);
    prop_assert_eq!(windy.stats.sorties, 1, "{}", what);
    let ring = f["area"]["coordinates"][0].as_array().unwrap();
    let frame = LocalFrame::centred_on(ring.iter().map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()]));
    let pick = |duration_s: f64, energy_j: f64| if fixed_wing { duration_s } else { energy_j };
    let figure = pick(windy.stats.duration_s, windy.stats.energy_j);
    let reported = windy.stats.wind.as_ref().and_then(|w| pick_reported(w, fixed_wing));
    // absent: the still-air plan's lines cannot be flown in this wind (a fixed wing finds no
    // turn clear of the zones), and the plan is another direction's
    prop_assert!(reported.is_some() || fixed_wing, "{what}: no still-air figure");
    if let Some(reported) = reported {
        prop_assert!(figure <= reported * (1.0 + 1e-12), "{what}: {figure:.1} against the still-air plan's {reported:.1} in the same wind");
    }
    if let (false, Some(reported)) = (fixed_wing, reported) {
        // a multirotor flies the still-air plan's path as drawn: priced here from its trajectory
        // in the wind, it is what the plan reports (its positions are rounded, which moves the
        // estimate by up to about 1e-4, as much as in still air)
        let path = path_of(&still.trajectory, &frame);
        let today = vehicle.energy_model_in(Some(&wind)).estimate(&path, Some(60.0)).energy_j();
        let rounding = (vehicle.energy_model().estimate(&path, Some(60.0)).energy_j() - still.stats.energy_j).abs();
        prop_assert!((reported - today).abs() <= 2.0 * rounding + 1e-6 * today, "{what}: reported {reported:.1} against {today:.1} priced here (rounding {rounding:.1})");
    }
    // the ground track stays out of the zones
    let zones = zones(&f, &frame);
    for (i, piece) in path_of(&windy.trajectory, &frame).pieces.iter().enumerate() {
        prop_assert!(!zones.intersects(&LineString::from(piece.points.clone())), "{what}: piece {i} enters a no-fly zone");
    }
    // a fixed wing's turns stay within its bank: the path as the air sees it bends no tighter
    // than the turning radius (circumradius of each three points a few metres apart)
    if fixed_wing {
        let air = air_path(&path_of(&windy.trajectory, &frame), wind.velocity(), vehicle.cruise_speed_mps);
        let points: Vec<Coord> = air.pieces.iter().flat_map(|p| p.points.iter().copied()).collect();
        let tightest = tightest_bend(&points);
        prop_assert!(tightest >= 0.85 * vehicle.turn_radius_m, "{what}: the air path bends on {tightest:.1} m, tighter than the {} m radius", vehicle.turn_radius_m);
    }
    // every piece says how it is flown in this wind
    for feature in windy.trajectory.features.iter().filter(|f| f.property("duration_s").is_some()) {
        let ground = feature.property("ground_speed_mps").and_then(Value::as_f64);
        prop_assert!(ground.is_some_and(|g| g > 0.0), "{what}: a piece without its ground speed: {:?}", feature.properties);
    }
    Ok(())
}

/// The still-air plan's figure in the wind the plan reports: a fixed wing's time (its lines,
/// order and directions, its connections flown as the wind lets it), a multirotor's energy.
fn pick_reported(w: &coverplan_planner::metrics::WindStats, fixed_wing: bool) -> Option<f64> {
    if fixed_wing { w.still_air_plan_duration_s } else { w.still_air_plan_energy_j }
}

/// The smallest circumradius of three points of `points`, each pair at least 2 m apart along it.
fn tightest_bend(points: &[Coord]) -> f64 {
    let mut spaced: Vec<Coord> = Vec::new();
    for &p in points {
        if spaced.last().is_none_or(|&q: &Coord| (p - q).x.hypot((p - q).y) >= 2.0) {
            spaced.push(p);
        }
    }
    spaced
        .windows(3)
        .map(|w| {
            let (a, b, c) = ((w[1] - w[0]).x.hypot((w[1] - w[0]).y), (w[2] - w[1]).x.hypot((w[2] - w[1]).y), (w[2] - w[0]).x.hypot((w[2] - w[0]).y));
            let twice_area = ((w[1] - w[0]).x * (w[2] - w[0]).y - (w[1] - w[0]).y * (w[2] - w[0]).x).abs();
            if twice_area < 1e-9 { f64::INFINITY } else { a * b * c / (2.0 * twice_area) }
        })
        .fold(f64::INFINITY, f64::min)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]
    #[test]
    fn wind_aware_plans_cost_no_more_than_still_air_plans_in_the_same_wind(k in 0usize..64, fixed_wing in any::<bool>(), strong in any::<bool>(), direction in 0u32..8) {
        check_wind(k, fixed_wing, if strong { 0.5 } else { 0.3 }, direction as f64 * 45.0)?;
    }
}

#[test]
fn winds_an_aircraft_cannot_fly_in_are_refused_where_they_are_given() {
    let f = field(0);
    let refused = |fixed_wing: bool, wind: Value| run(&f, &params(fixed_wing, Some(wind))).unwrap_err();
    // a fixed wing at 15 m/s may plan in at most its 9 m/s; the multirotor its 10 m/s
    assert!(refused(true, json!({"speed_mps": 9.5, "from_deg": 90})).contains("9.0 m/s"));
    assert!(refused(false, json!({"speed_mps": 10.5, "from_deg": 90})).contains("10.0 m/s"));
    // measured at 10 m, a 9 m/s wind is stronger at 60 m
    assert!(refused(false, json!({"speed_mps": 9.0, "from_deg": 90, "height_m": 10})).contains("beyond"));
}
