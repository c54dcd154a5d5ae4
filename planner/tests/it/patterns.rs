//! `pattern: double_grid` over the random fields (holes as no-fly zones): a second set of lines
//! across the first, flown after it. Both sets cover the area on their own, the second at 90°
//! to the first, and the flight enters no zone.

use coverplan_planner::geom::axial_difference;
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanParams, Stop, plan};
use geo::{Coord, Intersects, LineString, MultiPolygon};
use proptest::prelude::*;
use serde_json::{Value, json};

fn field(k: usize) -> Value {
    let read = |path: &str| -> Value { serde_json::from_slice(&std::fs::read(format!("{}/../tests/fixtures/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()).unwrap() };
    let index = read("random-fields/index.json");
    let names: Vec<&str> = index.as_array().unwrap().iter().map(|e| e["file"].as_str().unwrap()).collect();
    read(&format!("random-fields/{}", names[k % names.len()]))
}

/// The zones in longitude and latitude (a straight segment meets them there where it does in
/// metres, to the flatness of a few hundred metres of the Earth).
fn zones(field: &Value) -> MultiPolygon {
    let geometry: geojson::Geometry = serde_json::from_value(field["no_fly_zones"].clone()).unwrap();
    match geo::Geometry::try_from(geometry).unwrap() {
        geo::Geometry::Polygon(p) => MultiPolygon(vec![p]),
        geo::Geometry::MultiPolygon(m) => m,
        other => panic!("not polygons: {other:?}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    #[test]
    fn a_double_grid_flies_a_second_set_of_lines_across_the_first(k in 0usize..64, fixed_wing in any::<bool>(), planner in prop::sample::select(vec!["boustrophedon", "line_gtsp"]), bearing in 0.0..180.0f64) {
        let field = field(k);
        let mission = MissionGeometry { no_fly_zones: Some(&field["no_fly_zones"]), ..MissionGeometry::area(&field["area"]) };
        let profile = if fixed_wing { "generic_fixed_wing" } else { "iris" };
        let params = |pattern: &str| -> PlanParams {
            serde_json::from_value(json!({"planner": planner, "vehicle": {"profile": profile, "battery_wh": 90000}, "line_spacing_m": 30, "altitude_m": 60, "heading_deg": bearing, "pattern": pattern})).unwrap()
        };
        let grid = plan(&mission, &params("grid"), &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never());
        let double = plan(&mission, &params("double_grid"), &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never());
        let (Ok(grid), Ok(double)) = (grid, double) else { return Ok(()) };
        prop_assert!(double.stats.coverage_ratio >= grid.stats.coverage_ratio - 1e-9, "{} against {}", double.stats.coverage_ratio, grid.stats.coverage_ratio);
        // the sweeps' headings: two families 90° apart, each about as long as the grid's sweep
        let walls = zones(&field);
        let mut sweeps: Vec<(f64, f64)> = Vec::new();
        for f in &double.trajectory.features {
            let kind = f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str).unwrap_or_default().to_owned();
            let Some(geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { continue };
            let degrees: Vec<Coord> = coordinates.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
            prop_assert!(!walls.intersects(&LineString::new(degrees.clone())), "a {kind} enters a no-fly zone");
            // east and north in degrees of latitude, near enough for a heading
            let scale = degrees[0].y.to_radians().cos();
            let points: Vec<Coord> = degrees.iter().map(|c| Coord { x: (c.x - degrees[0].x) * scale, y: c.y }).collect();
            if kind == "sweep" && points.len() >= 2 {
                let (a, b) = (points[0], points[points.len() - 1]);
                sweeps.push(((b.y - a.y).atan2(b.x - a.x), ((b.x - a.x).hypot(b.y - a.y))));
            }
        }
        // the bearing as a math angle
        let first = (90.0 - bearing).to_radians();
        let across: f64 = sweeps.iter().filter(|(h, _)| axial_difference(*h, first + std::f64::consts::FRAC_PI_2) < 0.05).map(|(_, l)| l).sum();
        let along: f64 = sweeps.iter().filter(|(h, _)| axial_difference(*h, first) < 0.05).map(|(_, l)| l).sum();
        let total: f64 = sweeps.iter().map(|(_, l)| l).sum();
        prop_assert!(across > 0.3 * total && along > 0.3 * total, "sweep along the first heading {along:.0} m, across it {across:.0} m, of {total:.0} m");
    }
}

#[test]
fn a_double_grid_is_refused_where_it_means_nothing() {
    let field = field(0);
    let mission = MissionGeometry::area(&field["area"]);
    let refused = |extra: Value| {
        let mut body = json!({"line_spacing_m": 30, "vehicle": {"profile": "iris"}, "pattern": "double_grid"});
        body.as_object_mut().unwrap().extend(extra.as_object().unwrap().clone());
        // a fleet names its drones' vehicles itself
        if body.get("fleet").is_some() {
            body.as_object_mut().unwrap().remove("vehicle");
        }
        let params: PlanParams = serde_json::from_value(body).unwrap();
        let err = plan(&mission, &params, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect_err("refused");
        format!("{err:?}")
    };
    assert!(refused(json!({"planner": "e_spiral"})).contains("not_for_planner"));
    let fleet = refused(json!({"fleet": [{"profile": "iris"}, {"profile": "iris"}]}));
    assert!(fleet.contains("pattern_not_for_fleets"), "{fleet}");
}
