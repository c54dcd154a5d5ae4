//! `pattern: double_grid` over the random fields (holes as no-fly zones): a second set of lines
//! across the first, flown after it. Both sets cover the area on their own, the second at 90°
//! to the first, and the flight enters no zone.

use coverplan_planner::geom::axial_difference;
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanOutput, PlanParams, Stop, plan};
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
        let params = |pattern: &str, heading: f64| -> PlanParams {
            serde_json::from_value(json!({"planner": planner, "vehicle": {"profile": profile, "battery_wh": 90000}, "line_spacing_m": 30, "altitude_m": 60, "heading_deg": heading, "pattern": pattern})).unwrap()
        };
        let run = |params: PlanParams| plan(&mission, &params, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never());
        let (grid, across_grid) = (run(params("grid", bearing)), run(params("grid", bearing + 90.0)));
        let double = run(params("double_grid", bearing));
        let (Ok(grid), Ok(across_grid), Ok(double)) = (grid, across_grid, double) else { return Ok(()) };
        prop_assert!(double.stats.coverage_ratio >= grid.stats.coverage_ratio - 1e-9, "{} against {}", double.stats.coverage_ratio, grid.stats.coverage_ratio);
        let walls = zones(&field);
        for f in &double.trajectory.features {
            let Some(geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { continue };
            let line = LineString::new(coordinates.iter().map(|p| Coord { x: p[0], y: p[1] }).collect());
            prop_assert!(!walls.intersects(&line), "a {:?} enters a no-fly zone", f.properties.as_ref().and_then(|p| p.get("kind")));
        }
        // each set of lines flies about as much sweep as the grid on its heading alone (a fixed
        // wing drops the lines it has no Dubins way onto, in either plan alike)
        let first = (90.0 - bearing).to_radians();
        let second = first + std::f64::consts::FRAC_PI_2;
        let (along, across) = (sweep_along(&double, first), sweep_along(&double, second));
        let (alone, across_alone) = (sweep_along(&grid, first), sweep_along(&across_grid, second));
        prop_assert!(along > 0.5 * alone && across > 0.5 * across_alone, "sweep along the first heading {along:.0} m (alone {alone:.0} m), across it {across:.0} m (alone {across_alone:.0} m)");
    }
}

/// The sweep metres of `plan` flown along the math angle `heading` either way.
fn sweep_along(plan: &PlanOutput, heading: f64) -> f64 {
    let mut total = 0.0;
    for f in &plan.trajectory.features {
        let kind = f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str);
        let Some(geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { continue };
        if kind != Some("sweep") || coordinates.len() < 2 {
            continue;
        }
        let end = metres([coordinates[0][0], coordinates[0][1]], &coordinates[coordinates.len() - 1][..]);
        let (dx, dy) = (end.x, end.y);
        if axial_difference(dy.atan2(dx), heading) < 0.05 {
            total += dx.hypot(dy);
        }
    }
    total
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

/// East and north metres of `[lon, lat]` from `origin`, on a sphere's tangent plane (the
/// fields span a kilometre: the flatness error is millimetres).
fn metres(origin: [f64; 2], p: &[f64]) -> Coord {
    const METRES_PER_DEGREE: f64 = 111_319.49;
    Coord { x: (p[0] - origin[0]) * METRES_PER_DEGREE * origin[1].to_radians().cos(), y: (p[1] - origin[1]) * METRES_PER_DEGREE }
}

/// The ground a pinhole camera `h` above it images, pitched `pitch_deg` below the horizon and
/// facing the compass `bearing_deg`, with half fields of view `half` (across, along the image's
/// height): each image corner's ray rotated into the world and cut with the ground, written
/// here from the rotations rather than from the planner's formulas.
fn imaged(at: Coord, h: f64, pitch_deg: f64, bearing_deg: f64, half: (f64, f64)) -> geo::Polygon {
    let (p, b) = (pitch_deg.to_radians(), bearing_deg.to_radians());
    // camera axes in (east, north, up): forward, right, image up
    let forward = [b.sin() * p.cos(), b.cos() * p.cos(), -p.sin()];
    let right = [b.cos(), -b.sin(), 0.0];
    let up = [b.sin() * p.sin(), b.cos() * p.sin(), p.cos()];
    let corner = |x: f64, y: f64| {
        let ray: Vec<f64> = (0..3).map(|i| forward[i] + x * half.0.tan() * right[i] + y * half.1.tan() * up[i]).collect();
        let t = h / -ray[2];
        Coord { x: at.x + t * ray[0], y: at.y + t * ray[1] }
    };
    geo::Polygon::new(LineString::from(vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0), corner(-1.0, -1.0)]), vec![])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10))]
    /// Five passes, each of which images the area on its own as the camera sees it (every
    /// photo's trapezoid, from the photos and camera poses the trajectory gives) but for the
    /// ground only a photo taken inside a zone's margin would image; no flight in a zone.
    #[test]
    fn an_oblique_plan_sees_the_area_from_five_directions(
        k in 0usize..64,
        altitude in 70.0..120.0f64,
        pitch in -60.0..-35.0f64,
        bearing in 0.0..180.0f64,
        side in 0.2..0.5f64,
    ) {
        use geo::{Area, BooleanOps, Buffer, Translate};
        let field = field(k);
        let mission = MissionGeometry { no_fly_zones: Some(&field["no_fly_zones"]), ..MissionGeometry::area(&field["area"]) };
        let margin = 10.0;
        let params: PlanParams = serde_json::from_value(json!({
            "planner": "boustrophedon", "vehicle": {"profile": "iris", "battery_wh": 90000}, "camera": {"preset": "dji_mavic3_enterprise"},
            "altitude_m": altitude, "side_overlap": side, "front_overlap": 0.5, "heading_deg": bearing, "nfz_margin_m": margin,
            "pattern": "oblique", "oblique_pitch_deg": pitch,
        })).unwrap();
        let result = plan(&mission, &params, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never());
        let Ok(result) = result else { return Ok(()) };
        prop_assert_eq!(result.stats.passes.len(), 5);
        let walls = zones(&field);
        let area: geojson::Geometry = serde_json::from_value(field["area"].clone()).unwrap();
        let area: MultiPolygon = match geo::Geometry::try_from(area).unwrap() {
            geo::Geometry::Polygon(p) => MultiPolygon(vec![p]),
            geo::Geometry::MultiPolygon(m) => m,
            other => panic!("not polygons: {other:?}"),
        };
        let origin = { let c = area.0[0].exterior().0[0]; [c.x, c.y] };
        let local = |m: &MultiPolygon| -> MultiPolygon { geo::MapCoords::map_coords(m, |c| metres(origin, &[c.x, c.y])) };
        let keep_out = local(&walls).buffer(margin);
        let region = local(&area).difference(&keep_out);
        // the camera's half fields of view: 17.3 × 13.0 mm behind 12.29 mm, the image 5280 × 3956 px
        let half = ((17.3f64 / 2.0 / 12.29).atan(), (17.3f64 * 3956.0 / 5280.0 / 2.0 / 12.29).atan());
        let mut passes = std::collections::BTreeMap::<u64, (f64, Vec<geo::Polygon>)>::new();
        for f in &result.trajectory.features {
            let props = f.properties.as_ref().unwrap();
            let Some(geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else {
                if props.get("kind").and_then(Value::as_str) != Some("photos") { continue }
                let Some(geojson::GeometryValue::MultiPoint { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { continue };
                let pass = props["pass"].as_u64().expect("an oblique plan's photos name their pass");
                let pitch = -props["gimbal_pitch_deg"].as_f64().unwrap();
                // the nadir pass faces the lines, which all lie at the bearing asked
                let facing = props.get("camera_heading_deg").and_then(Value::as_f64).unwrap_or(bearing);
                let (_, photos) = passes.entry(pass).or_insert((facing, Vec::new()));
                photos.extend(coordinates.iter().map(|p| imaged(metres(origin, p.as_slice()), altitude, pitch, facing, half)));
                continue;
            };
            let degrees: Vec<Coord> = coordinates.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
            prop_assert!(!walls.intersects(&LineString::new(degrees)), "a flown piece enters a no-fly zone");
        }
        prop_assert_eq!(passes.keys().copied().collect::<Vec<_>>(), vec![1, 2, 3, 4, 5]);
        let centre = altitude / (-pitch).to_radians().tan();
        for (pass, (facing, photos)) in &passes {
            let seen = geo::unary_union(photos);
            // a pass looking along compass bearing b images from `centre` behind what it sees:
            // ground whose photo would be taken in a zone's margin is out of its reach
            let facing = facing.to_radians();
            let out_of_reach = if *pass == 1 { MultiPolygon(vec![]) } else { keep_out.translate(centre * facing.sin(), centre * facing.cos()) };
            let target = region.difference(&out_of_reach);
            let share = target.intersection(&seen).unsigned_area() / target.unsigned_area();
            prop_assert!(share >= 0.995, "pass {pass}: {share:.4} of the area it can reach is imaged");
            let stats = &result.stats.passes[(*pass - 1) as usize];
            prop_assert_eq!(stats.photos, photos.len());
        }
    }
}

#[test]
fn an_oblique_plan_is_refused_where_it_cannot_be_flown() {
    let field = field(0);
    let mission = MissionGeometry::area(&field["area"]);
    let refused = |body: Value| {
        let params: PlanParams = serde_json::from_value(body).unwrap();
        let err = plan(&mission, &params, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect_err("refused");
        format!("{err:?}")
    };
    let camera = json!({"preset": "dji_mavic3_enterprise"});
    assert!(refused(json!({"line_spacing_m": 30, "altitude_m": 80, "vehicle": {"profile": "iris"}, "pattern": "oblique"})).contains("camera_missing"));
    assert!(refused(json!({"camera": camera, "altitude_m": 80, "vehicle": {"profile": "generic_fixed_wing"}, "pattern": "oblique"})).contains("not_a_multirotor"));
    assert!(refused(json!({"camera": camera, "altitude_m": 80, "vehicle": {"profile": "iris"}, "oblique_pitch_deg": -40})).contains("pitch_without_oblique"));
    assert!(refused(json!({"camera": camera, "altitude_m": 80, "vehicle": {"profile": "iris"}, "pattern": "oblique", "planner": "e_spiral"})).contains("not_for_planner"));
    // the camera's image reaches 27.8° above and below its centre (17.3 mm × 3956 / 5280 behind
    // 12.29 mm): at −25° its top is 2.8° above the horizon, at −32.8° 5° under it
    let horizon = refused(json!({"camera": camera, "altitude_m": 80, "vehicle": {"profile": "iris"}, "pattern": "oblique", "oblique_pitch_deg": -25}));
    assert!(horizon.contains("oblique_view_reaches_horizon") && horizon.contains("-32.8"), "{horizon}");
}
