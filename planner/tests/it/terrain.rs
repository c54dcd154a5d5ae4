//! Plans over terrain keep their height above the ground: checked on the trajectory as written
//! (WGS84, heights above mean sea level), against the elevation model read independently of
//! the planner's own sampling, every metre along every flown piece.

use coverplan_planner::planners::registry;
use coverplan_planner::terrain::ElevationModel;
use coverplan_planner::vehicle::VehicleKind;
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanParams, Stop, plan};
use geojson::GeometryValue;
use proptest::prelude::*;
use serde_json::{Value, json};

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(format!("{}/../tests/fixtures/terrain/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// What the check of one plan found.
#[derive(Debug, Default)]
pub struct Flown {
    /// Least height above ground anywhere, and on sweeps the least and greatest.
    pub lowest: f64,
    pub sweep_range: [f64; 2],
    /// Metres of sweep outside height ± tolerance.
    pub sweep_off_band_m: f64,
    /// Steepest climb and descent, metres per metre, over spans of at least 5 m (the file's
    /// centimetres make shorter spans' slopes noisy).
    pub climb: f64,
    pub descent: f64,
    pub sweep_km: f64,
    pub waypoints: usize,
}

/// Walks every flown piece of `trajectory` every metre (from half a metre in).
pub fn fly(trajectory: &geojson::FeatureCollection, model: &ElevationModel, height_m: f64, tolerance_m: f64) -> Flown {
    let mut f = Flown { lowest: f64::INFINITY, sweep_range: [f64::INFINITY, f64::NEG_INFINITY], ..Flown::default() };
    for feature in &trajectory.features {
        let props = feature.properties.as_ref().unwrap();
        let kind = props.get("kind").and_then(Value::as_str).unwrap_or("");
        if !["sweep", "turn", "transit"].contains(&kind) {
            continue;
        }
        assert_eq!(props.get("altitude_reference").and_then(Value::as_str), Some("terrain"), "{props:?}");
        let Some(GeometryValue::LineString { coordinates }) = feature.geometry.as_ref().map(|g| &g.value) else { panic!("a flown piece is a LineString") };
        f.waypoints += coordinates.len() - 1;
        let metres = |a: &geojson::Position, b: &geojson::Position| {
            let (kx, ky) = (111_412.8 * a[1].to_radians().cos(), 111_132.9 - 559.8 * (2.0 * a[1].to_radians()).cos());
            ((b[0] - a[0]) * kx).hypot((b[1] - a[1]) * ky)
        };
        let (mut from, mut span) = (&coordinates[0], 0.0);
        for w in coordinates.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            let d = metres(a, b);
            span += d;
            if span >= 5.0 {
                f.climb = f.climb.max((b[2] - from[2]) / span);
                f.descent = f.descent.max((from[2] - b[2]) / span);
                (from, span) = (b, 0.0);
            }
            if d < 0.05 {
                continue;
            }
            if kind == "sweep" {
                f.sweep_km += d / 1000.0;
            }
            let mut t = 0.5f64.min(d / 2.0);
            while t < d {
                let s = t / d;
                let (lon, lat, z) = (a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s, a[2] + (b[2] - a[2]) * s);
                let above = z - model.height_at(lon, lat).expect("the path stays on the model");
                f.lowest = f.lowest.min(above);
                if kind == "sweep" {
                    f.sweep_range = [f.sweep_range[0].min(above), f.sweep_range[1].max(above)];
                    if (above - height_m).abs() > tolerance_m {
                        f.sweep_off_band_m += 1.0f64.min(d - t + 0.5);
                    }
                }
                t += 1.0;
            }
        }
    }
    f
}

fn plan_over(mission: &Value, model: &ElevationModel, params: Value) -> coverplan_planner::PlanOutput {
    let geometry = MissionGeometry {
        area: &mission["area"],
        no_fly_zones: None,
        obstacles: None,
        structures: None,
        home: serde_json::from_value(mission["home"].clone()).ok(),
        terrain: Some(model),
    };
    let params: PlanParams = serde_json::from_value(params).unwrap();
    plan(&geometry, &params, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).unwrap()
}

/// Waypoints per km of sweep a plan over the test terrains stays under (hills of up to 35°,
/// 5 m tolerance); measured up to 80, a fixed wing's, whose lead-ins and climb-outs are laid
/// over the ground too.
pub const WAYPOINTS_PER_SWEEP_KM: f64 = 100.0;

/// Over the four public terrains, a multirotor and a fixed wing at 60 m above ground: never
/// below 55 m, within 55–65 m on sweeps except where the ground is steeper than the climb limit
/// (and then as the plan reports), climbs within the limits.
#[test]
fn plans_over_the_test_terrains_keep_their_height_above_ground() {
    for name in ["hills-11", "ridge-11", "cliff-11", "jacksboro"] {
        let mission: Value = serde_json::from_slice(&fixture(&format!("{name}.json"))).unwrap();
        let model = ElevationModel::read(&fixture(&format!("{name}.tif")), "model.tif").unwrap();
        for vehicle in [json!({"profile": "generic_multirotor"}), json!({"kind": "fixed_wing"})] {
            let fixed_wing = vehicle.get("kind").is_some();
            let mut params = json!({"altitude_m": 60, "line_spacing_m": 60, "altitude_reference": "terrain", "vehicle": vehicle, "max_climb_deg": 12});
            if !fixed_wing {
                (params["max_climb_mps"], params["max_descent_mps"]) = (json!(2.5), json!(2.0));
            }
            let out = plan_over(&mission, &model, params);
            let stats = out.stats.terrain.as_ref().expect("terrain figures");
            let f = fly(&out.trajectory, &model, 60.0, 5.0);
            let what = format!("{name}, {}", if fixed_wing { "fixed wing" } else { "multirotor" });
            assert!(f.lowest >= 55.0 - 0.05, "{what}: {:.2} m above ground", f.lowest);
            let (climb, descent) = if fixed_wing { (12f64.to_radians().tan(), 12f64.to_radians().tan()) } else { (2.5 / 8.0, 2.0 / 8.0) };
            // the check's distances are equirectangular: within a few tenths of a per cent
            assert!(f.climb <= climb * 1.01 + 0.005 && f.descent <= descent * 1.01 + 0.005, "{what}: climbs {:.3}, descends {:.3}", f.climb, f.descent);
            assert!(
                (f.sweep_off_band_m - stats.sweep_outside_tolerance_m).abs() <= 2.0 + 0.02 * stats.sweep_outside_tolerance_m,
                "{what}: {:.1} m of sweep outside the band, {:.1} reported",
                f.sweep_off_band_m,
                stats.sweep_outside_tolerance_m
            );
            if stats.sweep_outside_tolerance_m == 0.0 {
                assert!(f.sweep_range[1] <= 65.05, "{what}: {:?}", f.sweep_range);
            }
            assert!(f.waypoints as f64 / f.sweep_km <= WAYPOINTS_PER_SWEEP_KM, "{what}: {} waypoints for {:.2} km of sweep", f.waypoints, f.sweep_km);
            println!("{what}: {:.1} waypoints/km, sweep {:?}, off band {:.0} m", f.waypoints as f64 / f.sweep_km, f.sweep_range, f.sweep_off_band_m);
        }
    }
}

/// Over a flat model the plan is the plan at the same altitude above home, lifted by the
/// ground's height.
#[test]
fn over_flat_ground_the_plan_is_todays_plan() {
    let mission: Value = serde_json::from_slice(&fixture("hills-11.json")).unwrap();
    // a flat model at 312 m over the same place (UTM 32N)
    let model = ElevationModel::from_grid(700, 700, vec![312.0; 490_000], [496_000.0, 5_206_000.0], [10.0, -10.0], 32632).unwrap();
    let params = json!({"altitude_m": 60, "line_spacing_m": 60});
    let flat = plan_over(&mission, &model, params.clone());
    let mut over = params;
    over["altitude_reference"] = json!("terrain");
    let laid = plan_over(&mission, &model, over);
    let flown = |t: &geojson::FeatureCollection| -> Vec<Vec<Vec<f64>>> {
        t.features
            .iter()
            .filter_map(|f| match f.geometry.as_ref().map(|g| &g.value) {
                Some(GeometryValue::LineString { coordinates }) => Some(coordinates.iter().map(|p| p.as_slice().to_vec()).collect()),
                _ => None,
            })
            .collect()
    };
    let (a, b) = (flown(&flat.trajectory), flown(&laid.trajectory));
    assert_eq!(a.len(), b.len());
    for (pa, pb) in a.iter().zip(&b) {
        assert_eq!(pa.len(), pb.len());
        for (p, q) in pa.iter().zip(pb) {
            assert_eq!((p[0], p[1]), (q[0], q[1]));
            assert!((q[2] - (p[2] + 312.0)).abs() < 0.02, "{p:?} {q:?}");
        }
    }
    assert!((laid.stats.length_m - flat.stats.length_m).abs() < 0.01 * flat.stats.length_m);
    assert!((laid.stats.energy_j - flat.stats.energy_j).abs() < 0.001 * flat.stats.energy_j);
}

#[test]
fn refuses_a_model_that_misses_home_or_a_plan_without_one() {
    let mission: Value = serde_json::from_slice(&fixture("hills-11.json")).unwrap();
    let model = ElevationModel::read(&fixture("hills-11.tif"), "m.tif").unwrap();
    let mut far = mission.clone();
    far["home"] = json!([9.2, 46.96]);
    let params: PlanParams = serde_json::from_value(json!({"altitude_m": 60, "line_spacing_m": 60, "altitude_reference": "terrain"})).unwrap();
    let home = serde_json::from_value(far["home"].clone()).ok();
    let geometry = |terrain| MissionGeometry { home, terrain, ..MissionGeometry::area(&far["area"]) };
    let check = |g| coverplan_planner::check_plan(&g, &params, &builtin_profiles(), &FieldLimits::default()).err().unwrap();
    let e = check(geometry(Some(&model)));
    assert_eq!((e.code, e.pointer.as_str()), ("terrain_not_covering", "/home"), "{e:?}");
    assert!(e.detail.contains("does not reach home"), "{}", e.detail);
    assert_eq!(check(geometry(None)).code, "terrain_missing");
}

/// A generated terrain in UTM zone 33N, 3 km a side at 10 m: a tilted plain, Gaussian `hills`
/// (centre x, y, height, width), and a cliff of `cliff` m over a few metres.
fn generated(hills: &[(f64, f64, f64, f64)], tilt: f64, cliff: f64) -> ElevationModel {
    let (n, cell) = (301usize, 10.0);
    let heights = (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f64 * cell, (n - 1 - i / n) as f64 * cell);
            let hill: f64 = hills.iter().map(|&(cx, cy, h, w)| h * (-((x - cx).powi(2) + (y - cy).powi(2)) / (w * w)).exp()).sum();
            (200.0 + tilt * x + hill + cliff / (1.0 + (-(y - 1500.0) / 2.0).exp())) as f32
        })
        .collect();
    ElevationModel::from_grid(n, n, heights, [400_000.0, 5_003_000.0], [cell, -cell], 32633).unwrap()
}

/// A field of about 60 to 80 ha in the middle of the generated terrain, turned by `turn_deg`.
fn generated_mission(model: &ElevationModel, turn_deg: f64) -> Value {
    let b = model.summary().bounds;
    let (lon0, lat0) = ((b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0);
    let (kx, ky) = (111_320.0 * lat0.to_radians().cos(), 110_574.0);
    let (s, c) = turn_deg.to_radians().sin_cos();
    let corner = |x: f64, y: f64| json!([lon0 + (x * c - y * s) / kx, lat0 + (x * s + y * c) / ky]);
    json!({
        "area": {"type": "Polygon", "coordinates": [[corner(-450.0, -350.0), corner(450.0, -350.0), corner(400.0, 380.0), corner(-450.0, 350.0), corner(-450.0, -350.0)]]},
        "home": [lon0 - 600.0 / kx, lat0 - 500.0 / ky],
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 10, ..ProptestConfig::default() })]
    /// Generated terrains (relief up to 300 m, slopes up to 35°, cliffs steeper than any climb
    /// limit), both kinds of aircraft: never below the floor; on sweeps within the band except
    /// the metres the plan reports; climbs within the limits; waypoints per km bounded.
    #[test]
    fn generated_terrains_keep_the_height_above_ground(
        hills in proptest::collection::vec((0.0f64..3000.0, 0.0f64..3000.0, 20.0f64..300.0, 0.05f64..0.8), 0..6),
        tilt in -0.1f64..0.1,
        cliff in prop_oneof![Just(0.0), 20.0f64..80.0],
        turn in 0.0f64..90.0,
        fixed_wing in any::<bool>(),
        height in 40.0f64..120.0,
        pick in any::<prop::sample::Index>(),
    ) {
        // a hill's steepest slope is 0.86 height / width: at most about 35°
        let hills: Vec<(f64, f64, f64, f64)> = hills.iter().map(|&(x, y, h, ratio)| (x, y, h, (h / ratio).max(60.0))).collect();
        let model = generated(&hills, tilt, cliff);
        let mission = generated_mission(&model, turn);
        prop_assume!(model.height_at(mission["home"][0].as_f64().unwrap(), mission["home"][1].as_f64().unwrap()).is_some());
        let vehicle = if fixed_wing { json!({"kind": "fixed_wing"}) } else { json!({"profile": "generic_multirotor"}) };
        // every planner that lays parallel lines for this kind of aircraft
        let kind = if fixed_wing { VehicleKind::FixedWing } else { VehicleKind::Multirotor };
        let planners: Vec<&str> = registry().iter().filter(|p| p.lays_parallel_lines() && p.vehicle_kinds().contains(&kind)).map(|p| p.id()).collect();
        let planner = planners[pick.index(planners.len())];
        let params = json!({"planner": planner, "altitude_m": height, "line_spacing_m": 80, "altitude_reference": "terrain", "vehicle": vehicle, "terrain_tolerance_m": 4});
        let out = plan_over(&mission, &model, params);
        let stats = out.stats.terrain.clone().unwrap();
        let f = fly(&out.trajectory, &model, height, 4.0);
        prop_assert!(f.lowest >= height - 4.0 - 0.05, "{planner}: {:.2} above ground at {height:.1} m", f.lowest);
        // the report counts metre samples, the flight here is looked at between them: each
        // stretch off the band may differ by a metre at either end (steep ground has more of them)
        prop_assert!((f.sweep_off_band_m - stats.sweep_outside_tolerance_m).abs() <= 2.0 + 0.05 * stats.sweep_outside_tolerance_m, "{:.1} against {:.1}", f.sweep_off_band_m, stats.sweep_outside_tolerance_m);
        let steepest = tilt.abs() + hills.iter().map(|h| 0.86 * h.2 / h.3).sum::<f64>();
        if cliff == 0.0 && !fixed_wing && steepest < 0.24 {
            // ground gentler than the climb limit: the band holds everywhere
            prop_assert_eq!(stats.sweep_outside_tolerance_m, 0.0);
        }
        let (climb, descent) = if fixed_wing { (30f64.to_radians().tan(), 30f64.to_radians().tan()) } else { (2.0 / 8.0, 2.0 / 8.0) };
        prop_assert!(f.climb <= climb * 1.01 + 0.005 && f.descent <= descent * 1.01 + 0.005, "climbs {:.4}, descends {:.4}", f.climb, f.descent);
        prop_assert!(f.waypoints as f64 / f.sweep_km <= WAYPOINTS_PER_SWEEP_KM, "{} waypoints for {:.2} km", f.waypoints, f.sweep_km);
    }
}

/// Obstacles stand on the ground: over terrain the path crosses a mast's footprint at least its
/// height plus the clearance above the ground under it.
#[test]
fn obstacles_over_terrain_are_cleared_from_the_ground_up() {
    let mission: Value = serde_json::from_slice(&fixture("hills-11.json")).unwrap();
    let model = ElevationModel::read(&fixture("hills-11.tif"), "m.tif").unwrap();
    // an 80 m block of 120 m × 120 m in the middle of the field
    let (lon, lat, dlon, dlat) = (9.0205, 46.9640, 60.0 / 76_000.0, 60.0 / 111_200.0);
    let block = [[lon - dlon, lat - dlat], [lon + dlon, lat - dlat], [lon + dlon, lat + dlat], [lon - dlon, lat + dlat], [lon - dlon, lat - dlat]];
    let obstacles =
        json!({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"height_m": 80}, "geometry": {"type": "Polygon", "coordinates": [block]}}]});
    let geometry = MissionGeometry {
        area: &mission["area"],
        no_fly_zones: None,
        obstacles: Some(&obstacles),
        structures: None,
        home: serde_json::from_value(mission["home"].clone()).ok(),
        terrain: Some(&model),
    };
    let params: PlanParams = serde_json::from_value(
        json!({"altitude_m": 60, "line_spacing_m": 40, "altitude_reference": "terrain", "vehicle": {"profile": "generic_multirotor"}, "obstacle_clearance_m": 10}),
    )
    .unwrap();
    let out = plan(&geometry, &params, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).unwrap();
    let inside = |p: [f64; 2]| p[0] > lon - dlon && p[0] < lon + dlon && p[1] > lat - dlat && p[1] < lat + dlat;
    let mut crossed = 0;
    for feature in &out.trajectory.features {
        let Some(GeometryValue::LineString { coordinates }) = feature.geometry.as_ref().map(|g| &g.value) else { continue };
        for w in coordinates.windows(2) {
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let p = [w[0][0] + (w[1][0] - w[0][0]) * t, w[0][1] + (w[1][1] - w[0][1]) * t];
                if inside(p) {
                    let above = w[0][2] + (w[1][2] - w[0][2]) * t - model.height_at(p[0], p[1]).unwrap();
                    assert!(above >= 90.0 - 0.05, "{above:.2} m above the ground over the block");
                    crossed += 1;
                }
            }
        }
    }
    assert!(crossed > 20, "the path crosses the block ({crossed} samples)");
}

/// A corridor across the hills and a double grid over them follow the ground like any plan:
/// never below 55 m above it at 60 m, the climbs within the limit.
#[test]
fn corridors_double_grids_and_obliques_keep_their_height_above_ground() {
    let mut mission: Value = serde_json::from_slice(&fixture("hills-11.json")).unwrap();
    let model = ElevationModel::read(&fixture("hills-11.tif"), "model.tif").unwrap();
    let grid = json!({"altitude_m": 60, "line_spacing_m": 60, "altitude_reference": "terrain", "vehicle": {"profile": "generic_multirotor"}, "max_climb_mps": 2.5, "max_descent_mps": 2.0, "pattern": "double_grid"});
    let mut corridor = grid.clone();
    corridor["pattern"] = json!("grid");
    corridor["planner"] = json!("corridor");
    let mut oblique = grid.clone();
    oblique["pattern"] = json!("oblique");
    oblique["camera"] = json!({"preset": "dji_mavic3_enterprise"});
    oblique.as_object_mut().unwrap().remove("line_spacing_m");
    let double = plan_over(&mission, &model, grid);
    let oblique = plan_over(&mission, &model, oblique);
    assert_eq!(oblique.stats.passes.len(), 5);
    // a road over the same hills, with a bend
    mission["area"] = json!({"type": "Feature", "properties": {"width_m": 80},
        "geometry": {"type": "LineString", "coordinates": [[9.0160, 46.9590], [9.0200, 46.9640], [9.0250, 46.9650]]}});
    let road = plan_over(&mission, &model, corridor);
    for (what, out) in [("double grid", double), ("oblique", oblique), ("corridor", road)] {
        let f = fly(&out.trajectory, &model, 60.0, 5.0);
        assert!(f.lowest >= 55.0 - 0.05, "{what}: {:.2} m above ground", f.lowest);
        assert!(f.climb <= 2.5 / 8.0 * 1.01 + 0.005 && f.descent <= 2.0 / 8.0 * 1.01 + 0.005, "{what}: climbs {:.3}, descends {:.3}", f.climb, f.descent);
        assert!(out.stats.coverage_ratio >= 0.99, "{what}: coverage {}", out.stats.coverage_ratio);
    }
}
