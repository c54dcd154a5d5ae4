//! The energy planners and the battery through the public entry point: E-Spiral against
//! E-BF (seed 002 §5.1), EG-CPP around a no-fly zone and its limit (its time limit: `tests/time_limit.rs`), `auto`, and sorties.

use coverplan_planner::estimate::{EstimateRequest, estimate_route};
use coverplan_planner::metrics::OptimalityStatus;
use coverplan_planner::vehicle::{Vehicle, builtin_profiles};
use coverplan_planner::{FieldLimits, MissionGeometry, PlanError, PlanOutput, PlanParams, Stop, plan};
use geo::{Buffer, Contains, Coord, LineString, Polygon};
use proptest::prelude::*;
use serde_json::{Value, json};

/// Metres around (10° E, 45° N) to a GeoJSON ring.
fn ring(points: &[(f64, f64)]) -> Value {
    let to = |(x, y): (f64, f64)| json!([10.0 + x / (111_320.0 * 45f64.to_radians().cos()), 45.0 + y / 110_574.0]);
    let mut r: Vec<Value> = points.iter().map(|&p| to(p)).collect();
    r.push(r[0].clone());
    Value::Array(r)
}

fn point(x: f64, y: f64) -> [f64; 2] {
    [10.0 + x / (111_320.0 * 45f64.to_radians().cos()), 45.0 + y / 110_574.0]
}

fn profiles(battery_wh: f64) -> Vec<Vehicle> {
    let mut p = builtin_profiles();
    p.iter_mut().for_each(|v| v.battery.energy_wh = battery_wh);
    p
}

fn run(area: &[(f64, f64)], nfz: Option<&[(f64, f64)]>, home: Option<[f64; 2]>, params: Value, profiles: &[Vehicle]) -> Result<PlanOutput, PlanError> {
    let area = json!({"type": "Polygon", "coordinates": [ring(area)]});
    let nfz = nfz.map(|z| json!({"type": "Polygon", "coordinates": [ring(z)]}));
    let params: PlanParams = serde_json::from_value(params).unwrap();
    let mission = MissionGeometry { no_fly_zones: nfz.as_ref(), home, ..MissionGeometry::area(&area) };
    plan(&mission, &params, profiles, &FieldLimits::default(), &|_| true, &Stop::never())
}

fn regular(n: usize, diameter: f64, turn: f64) -> Vec<(f64, f64)> {
    (0..n).map(|k| (turn + k as f64 * std::f64::consts::TAU / n as f64).sin_cos()).map(|(s, c)| (diameter / 2.0 * c, diameter / 2.0 * s)).collect()
}

fn energy(area: &[(f64, f64)], planner: &str) -> PlanOutput {
    run(area, None, None, json!({"planner": planner, "line_spacing_m": 20, "vehicle": {"profile": "iris"}}), &profiles(1e5)).unwrap_or_else(|e| panic!("{planner}: {e}"))
}

/// Seed 002 §5.1.2's flights: IRIS 10 m up, a 100° lens of 2386 × 2386 px, 10 % side overlap,
/// none in front.
pub(crate) fn flights_camera(planner: &str) -> Value {
    json!({"planner": planner, "vehicle": {"profile": "iris"}, "camera": {"hfov_deg": 100, "image_width_px": 2386, "image_height_px": 2386}, "altitude_m": 10, "side_overlap": 0.1, "front_overlap": 0})
}

/// Consecutive sweeps of which the second flies the first back: a spur into a corner.
fn spurs(out: &PlanOutput) -> usize {
    let sweeps: Vec<&Vec<geojson::Position>> = out
        .trajectory
        .features
        .iter()
        .filter(|f| f.property("kind").and_then(Value::as_str) == Some("sweep"))
        .filter_map(|f| match f.geometry.as_ref().map(|g| &g.value) {
            Some(geojson::GeometryValue::LineString { coordinates }) => Some(coordinates),
            _ => None,
        })
        .collect();
    sweeps.windows(2).filter(|w| w[0].first() == w[1].last() && w[0].last() == w[1].first()).count()
}

/// With the flights' camera, a ring's corner photos image the field's corners: on a heptagon
/// of the flights' size (about five hectares) the spiral covers 99 % with no spur into a corner
/// of 128°, costs less per imaged hectare than the back-and-forth, and `auto` picks it.
#[test]
fn with_the_flights_camera_the_spiral_images_its_corners_and_saves_energy() {
    let heptagon: Vec<(f64, f64)> = regular(7, 270.0, 0.3);
    let area = heptagon.iter().enumerate().map(|(i, &(x, y))| x * heptagon[(i + 1) % 7].1 - heptagon[(i + 1) % 7].0 * y).sum::<f64>() / 2.0;
    let per_imaged_ha = |out: &PlanOutput| out.stats.energy_j / (out.stats.photo_coverage_ratio.unwrap() * area / 1e4);
    let plan = |planner: &str| run(&heptagon, None, None, flights_camera(planner), &profiles(1e5)).unwrap_or_else(|e| panic!("{planner}: {e}"));
    let (spiral, bf) = (plan("e_spiral"), plan("e_bf"));
    eprintln!(
        "heptagon, the flights' camera: e_spiral {:.0} m, {:.0} s, {:.1} kJ, {} sweeps, coverage {:.4}; e_bf {:.0} m, {:.0} s, {:.1} kJ, coverage {:.4}",
        spiral.stats.length_m,
        spiral.stats.duration_s,
        spiral.stats.energy_j / 1000.0,
        spiral.stats.sweep_lines,
        spiral.stats.photo_coverage_ratio.unwrap(),
        bf.stats.length_m,
        bf.stats.duration_s,
        bf.stats.energy_j / 1000.0,
        bf.stats.photo_coverage_ratio.unwrap()
    );
    assert!(spiral.stats.photo_coverage_ratio.unwrap() >= 0.99, "{:?}", spiral.stats.photo_coverage_ratio);
    assert_eq!(spurs(&spiral), 0, "a spur into a corner its ring's photos image");
    assert!(per_imaged_ha(&spiral) < per_imaged_ha(&bf), "the spiral {:.0} J/ha, the back-and-forth {:.0} J/ha", per_imaged_ha(&spiral), per_imaged_ha(&bf));
    let auto = plan("auto");
    assert_eq!(auto.stats.planner, "e_spiral", "{:?}", auto.stats.alternatives);
}

/// Seed 002's polygon near Pisa, flown from its home with the flights' camera (§5.1.2): our
/// spiral costs no more than 5 % over the spiral the authors flew, priced by the same model
/// (from the same home, back to it), and less than our back-and-forth.
#[test]
fn on_the_flights_polygon_the_spiral_costs_what_the_flown_one_does() {
    let fixture: Value = serde_json::from_slice(&std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/fixtures/seed002/pisa-polygon.json")).unwrap()).unwrap();
    let home: [f64; 2] = serde_json::from_value(fixture["home"].clone()).unwrap();
    let mission = MissionGeometry { home: Some(home), ..MissionGeometry::area(&fixture["area"]) };
    let plan_with = |planner: &str| {
        let params: PlanParams = serde_json::from_value(flights_camera(planner)).unwrap();
        plan(&mission, &params, &profiles(1e5), &FieldLimits::default(), &|_| true, &Stop::never()).unwrap_or_else(|e| panic!("{planner}: {e}"))
    };
    let (spiral, bf) = (plan_with("e_spiral"), plan_with("e_bf"));
    // the flown route: from home through the spiral's waypoints and back, 10 m up
    let flown: Vec<Vec<f64>> = serde_json::from_value(fixture["meta"]["flown_spiral"].clone()).unwrap();
    let route: Vec<Vec<f64>> = std::iter::once(&home[..]).chain(flown.iter().map(Vec::as_slice)).chain([&home[..]]).map(|p| vec![p[0], p[1], 10.0]).collect();
    let request: EstimateRequest = serde_json::from_value(json!({"waypoints": route, "vehicle": {"profile": "iris"}})).unwrap();
    let flown = estimate_route(&request, &profiles(1e5)).unwrap().totals;
    eprintln!(
        "Pisa polygon: e_spiral {:.0} m, {:.0} s, {:.1} kJ, coverage {:.4}; e_bf {:.0} m, {:.0} s, {:.1} kJ; the flown spiral {:.0} m, {} points, {:.0} s, {:.1} kJ",
        spiral.stats.length_m,
        spiral.stats.duration_s,
        spiral.stats.energy_j / 1000.0,
        spiral.stats.photo_coverage_ratio.unwrap(),
        bf.stats.length_m,
        bf.stats.duration_s,
        bf.stats.energy_j / 1000.0,
        flown.length_m,
        route.len(),
        flown.duration_s,
        flown.energy_j / 1000.0
    );
    assert!(spiral.stats.photo_coverage_ratio.unwrap() >= 0.99);
    assert!(spiral.stats.energy_j <= 1.05 * flown.energy_j, "our spiral {:.0} J, the flown one {:.0} J", spiral.stats.energy_j, flown.energy_j);
    assert!(spiral.stats.energy_j < bf.stats.energy_j, "our spiral {:.0} J, our back-and-forth {:.0} J", spiral.stats.energy_j, bf.stats.energy_j);
}

#[test]
fn the_spiral_saves_energy_on_regular_polygons_and_does_not_lose_on_rectangles() {
    for n in 6..=10 {
        let field = regular(n, 400.0, 0.3);
        let (spiral, bf) = (energy(&field, "e_spiral"), energy(&field, "e_bf"));
        let saving = 1.0 - spiral.stats.energy_j / bf.stats.energy_j;
        eprintln!(
            "{n} vertices: e_spiral {:.0} J, e_bf {:.0} J, saving {:.1} %, spiral coverage {:.4}",
            spiral.stats.energy_j,
            bf.stats.energy_j,
            100.0 * saving,
            spiral.stats.coverage_ratio
        );
        assert!(saving > 0.0, "{n} vertices: the spiral costs more ({:.1} %)", 100.0 * saving);
        assert!(spiral.stats.coverage_ratio >= 0.99, "{n}: coverage {}", spiral.stats.coverage_ratio);
    }
    let rectangle = [(0.0, 0.0), (300.0, 0.0), (300.0, 200.0), (0.0, 200.0)];
    let (spiral, bf) = (energy(&rectangle, "e_spiral"), energy(&rectangle, "e_bf"));
    eprintln!("rectangle: e_spiral {:.0} J, e_bf {:.0} J", spiral.stats.energy_j, bf.stats.energy_j);
    // measured: the spiral 2.0 % dearer on this 300 × 200 m rectangle (seed 002 reports about 1 % on its shapes)
    assert!(spiral.stats.energy_j <= bf.stats.energy_j * 1.03);
}

#[test]
fn the_spiral_refuses_holes_and_fixed_wing() {
    let square = [(0.0, 0.0), (300.0, 0.0), (300.0, 300.0), (0.0, 300.0)];
    let zone = [(120.0, 120.0), (180.0, 120.0), (180.0, 180.0), (120.0, 180.0)];
    let err = run(&square, Some(&zone), None, json!({"planner": "e_spiral", "line_spacing_m": 20}), &profiles(1e5)).unwrap_err();
    assert!(matches!(&err, PlanError::Input(e) if e.code == "planner_not_applicable"), "{err}");
    let err = run(&square, None, None, json!({"planner": "e_spiral", "line_spacing_m": 20, "vehicle": {"profile": "maja"}}), &profiles(1e5)).unwrap_err();
    assert!(matches!(&err, PlanError::Input(e) if e.pointer == "/vehicle/kind"), "{err}");
}

/// A field notched from above down to 12 m off its lower edge, which bends into a V there (a
/// fleet's band cut past a zone): the rings go round the two sides, and the bent strip under
/// the notch is narrower than a swath, too long and bent for a spur; it gets a pass of its own.
#[test]
fn the_spiral_sweeps_a_bent_strip_no_ring_reaches() {
    let field = [
        (0.0, 0.0),
        (50.0, 0.0),
        (100.0, -30.0),
        (150.0, 0.0),
        (200.0, 0.0),
        (200.0, 100.0),
        (150.0, 100.0),
        (150.0, 12.0),
        (100.0, -18.0),
        (50.0, 12.0),
        (50.0, 100.0),
        (0.0, 100.0),
    ];
    let out = energy(&field, "e_spiral");
    assert!(out.stats.coverage_ratio >= 0.99, "coverage {}", out.stats.coverage_ratio);
}

#[test]
fn eg_cpp_covers_a_grid_around_a_no_fly_zone_and_refuses_what_it_cannot_search() {
    // an L-shaped field of 16 cells of 20 m, a zone over one of them
    let field = [(0.0, 0.0), (100.0, 0.0), (100.0, 40.0), (60.0, 40.0), (60.0, 80.0), (0.0, 80.0)];
    let zone = [(25.0, 45.0), (35.0, 45.0), (35.0, 55.0), (25.0, 55.0)];
    let out = run(&field, Some(&zone), None, json!({"planner": "eg_cpp", "line_spacing_m": 20, "nfz_margin_m": 2, "vehicle": {"profile": "iris"}}), &profiles(1e5)).unwrap();
    eprintln!("eg_cpp: {:.0} J, {} runs, coverage {:.4}, {:.0} ms", out.stats.energy_j, out.stats.sweep_lines, out.stats.coverage_ratio, out.stats.planning_time_ms);
    assert_eq!(out.stats.nfz_intrusion_m, 0.0);
    // runs go from cell centre to cell centre and the swath metric counts no along-track
    // footprint, so the half cell beyond each run's end shows as uncovered (measured 0.853)
    assert!(out.stats.coverage_ratio >= 0.8, "{}", out.stats.coverage_ratio);
    let big = [(0.0, 0.0), (400.0, 0.0), (400.0, 400.0), (0.0, 400.0)];
    let err = run(&big, None, None, json!({"planner": "eg_cpp", "line_spacing_m": 20}), &profiles(1e5)).unwrap_err();
    assert!(matches!(&err, PlanError::Input(e) if e.code == "instance_too_large" && e.detail.contains("100")), "{err}");
    // 16 cells are searched to the end, a square of 100 is not: the plan says which
    let optimality = |w: f64, h: f64| {
        run(&[(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)], None, None, json!({"planner": "eg_cpp", "line_spacing_m": 20}), &profiles(1e5)).unwrap().stats.optimality.unwrap()
    };
    let small = optimality(70.0, 70.0);
    assert_eq!((small.status, small.gap), (OptimalityStatus::Proven, 0.0));
    let large = optimality(190.0, 190.0);
    assert!(large.status == OptimalityStatus::SearchLimited && large.gap > 0.0 && large.gap < 1.0, "{large:?}");
}

#[test]
fn auto_keeps_the_cheapest_plan_that_covers_and_reports_the_others() {
    let field = regular(8, 300.0, 0.1);
    for objective in ["energy", "time", "length"] {
        let out = run(&field, None, None, json!({"planner": "auto", "objective": objective, "line_spacing_m": 25, "vehicle": {"profile": "iris"}}), &profiles(1e5)).unwrap();
        let st = &out.stats;
        assert!(st.alternatives.len() >= 5, "{:?}", st.alternatives);
        assert!(st.alternatives.iter().all(|a| a.planner != st.planner && a.planner != "auto"));
        let mine = match objective {
            "energy" => st.energy_j,
            "time" => st.duration_s,
            _ => st.length_m,
        };
        for a in st.alternatives.iter().filter(|a| a.coverage_ratio.is_some_and(|c| c >= st.coverage_ratio)) {
            let theirs = match objective {
                "energy" => a.energy_j,
                "time" => a.duration_s,
                _ => a.length_m,
            };
            assert!(mine <= theirs.unwrap() + 1e-6, "{objective}: {} chosen at {mine}, {} has {theirs:?}", st.planner, a.planner);
        }
    }
}

#[test]
fn a_field_four_batteries_large_is_flown_in_sorties_within_budget() {
    let field = [(0.0, 0.0), (600.0, 0.0), (600.0, 400.0), (0.0, 400.0)];
    let params = json!({"planner": "boustrophedon", "line_spacing_m": 20, "altitude_m": 30, "vehicle": {"profile": "iris"}});
    let whole = run(&field, None, None, params.clone(), &profiles(1e5)).unwrap();
    // a battery whose usable part is a quarter of the single flight
    let battery_wh = whole.stats.energy_j / 4.0 / 3600.0 / 0.75;
    let small = profiles(battery_wh);
    // without a home: one route, marked where each battery runs out
    let route = run(&field, None, None, params.clone(), &small).unwrap();
    let kind = |f: &geojson::Feature| f.properties.as_ref().and_then(|p| p.get("kind")).and_then(|k| k.as_str()).unwrap_or_default().to_owned();
    let swaps = route.trajectory.features.iter().filter(|f| kind(f) == "battery_swap").count();
    assert_eq!(route.stats.sorties, 1);
    assert!(route.stats.batteries_needed >= 4 && route.stats.batteries_needed == swaps + 1, "{} batteries, {swaps} swaps", route.stats.batteries_needed);
    assert!(route.stats.warnings.iter().any(|w| w.contains("give the mission a home")), "{:?}", route.stats.warnings);
    for f in route.trajectory.features.iter().filter(|f| f.properties.as_ref().is_some_and(|p| p.contains_key("battery_remaining"))) {
        let left = f.properties.as_ref().unwrap()["battery_remaining"].as_f64().unwrap();
        assert!(left >= -1e-9, "piece {} ends with {left} of a battery", f.properties.as_ref().unwrap()["seq"]);
    }
    let out = run(&field, None, Some(point(-20.0, -20.0)), params, &small).unwrap();
    let st = &out.stats;
    assert_eq!(st.warnings, Vec::<String>::new());
    eprintln!("sorties: {} for {:.0} kJ ({:.0} kJ usable each), coverage {:.4}", st.sorties, st.energy_j / 1000.0, battery_wh * 2.7, st.coverage_ratio);
    assert!(st.sorties >= 4 && st.sorties == st.sortie_totals.len());
    assert_eq!(st.batteries_needed, (st.energy_j / (battery_wh * 3600.0 * 0.75)).ceil() as usize);
    for s in &st.sortie_totals {
        assert!(s.battery_used <= 1.0 + 1e-9, "sortie {} uses {:.3} of the battery", s.sortie, s.battery_used);
    }
    assert!(st.coverage_ratio >= 0.99, "{}", st.coverage_ratio);
    assert_eq!(st.sweep_lines, whole.stats.sweep_lines);
    // every sortie starts and ends at home
    let features = &out.trajectory.features;
    for k in 1..=st.sorties {
        let mine: Vec<_> = features.iter().filter(|f| f.properties.as_ref().unwrap()["sortie"] == json!(k)).collect();
        let first = mine.first().unwrap().geometry.as_ref().unwrap();
        let last = mine.last().unwrap().geometry.as_ref().unwrap();
        let ends = |g: &geojson::Geometry, at_end: bool| match &g.value {
            geojson::GeometryValue::LineString { coordinates } => {
                if at_end {
                    coordinates.last().unwrap().clone()
                } else {
                    coordinates[0].clone()
                }
            }
            _ => panic!("a line"),
        };
        let home = point(-20.0, -20.0);
        for p in [ends(first, false), ends(last, true)] {
            assert!((p[0] - home[0]).abs() < 1e-6 && (p[1] - home[1]).abs() < 1e-6, "sortie {k} does not start and end at home");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Generated convex and concave fields as seed 002 §5.1 draws them (6 to 10 vertices, angles
    /// spread by an irregularity of 0 to 1, radii by a spikiness of 0 to 0.4, 200 to 600 m
    /// across): the spiral plans every one, covers 99 %, and no leg leaves the field.
    #[test]
    fn the_spiral_covers_generated_fields(
        n in 6usize..=10,
        diameter in 200.0f64..600.0,
        irregularity in 0.0f64..1.0,
        draws in proptest::collection::vec((0.0f64..1.0, 0.0f64..0.4), 10),
        turn in 0.0f64..std::f64::consts::TAU,
    ) {
        let steps: Vec<f64> = draws[..n].iter().map(|(u, _)| 1.0 + 0.95 * irregularity * (2.0 * u - 1.0)).collect();
        let total: f64 = steps.iter().sum();
        let mut angle = turn;
        let field: Vec<(f64, f64)> = steps
            .iter()
            .zip(&draws)
            .map(|(step, (_, spike))| {
                angle += step / total * std::f64::consts::TAU;
                let r = diameter / 2.0 * (1.0 - spike);
                (r * angle.cos(), r * angle.sin())
            })
            .collect();
        let out = run(&field, None, None, json!({"planner": "e_spiral", "line_spacing_m": 20, "vehicle": {"profile": "iris"}}), &profiles(1e5)).unwrap();
        prop_assert!(out.stats.coverage_ratio >= 0.99, "coverage {}", out.stats.coverage_ratio);
        prop_assert!(out.stats.energy_j > 0.0 && out.stats.sweep_lines > 0);
        // every point of the path within a centimetre of the field
        let inside = Polygon::new(LineString::from(field.iter().map(|&(x, y)| Coord { x, y }).collect::<Vec<_>>()), vec![]).buffer(0.01);
        let to_local = |c: &[f64]| Coord { x: (c[0] - 10.0) * 111_320.0 * 45f64.to_radians().cos(), y: (c[1] - 45.0) * 110_574.0 };
        for f in &out.trajectory.features {
            if let Some(geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) {
                for c in coordinates.iter().map(|c| c.as_slice()) {
                    prop_assert!(inside.contains(&to_local(c)), "{:?} outside the field", to_local(c));
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// With the flights' camera, on generated convex and concave fields of the flights' size,
    /// the spiral's photos image 99 % of the field.
    #[test]
    fn the_spirals_photos_image_generated_fields(
        n in 6usize..=10,
        diameter in 150.0f64..350.0,
        spikes in proptest::collection::vec(0.0f64..0.4, 10),
        turn in 0.0f64..std::f64::consts::TAU,
    ) {
        let field: Vec<(f64, f64)> = regular(n, diameter, turn).iter().zip(&spikes).map(|(&(x, y), s)| (x * (1.0 - s), y * (1.0 - s))).collect();
        let out = run(&field, None, None, flights_camera("e_spiral"), &profiles(1e5)).unwrap();
        let imaged = out.stats.photo_coverage_ratio.unwrap();
        prop_assert!(imaged >= 0.99, "photos image {imaged}");
    }
}

/// For a fixed wing, e_bf's fixed nearest-first order gives way to line-level routing on Dubins
/// costs, which would make it energy_aware's twin: it is refused, with the planner to use.
#[test]
fn e_bf_is_refused_for_a_fixed_wing_and_energy_aware_plans_it() {
    let field = [(0.0, 0.0), (600.0, 0.0), (600.0, 300.0), (0.0, 300.0)];
    let fixed_wing = |planner: &str| json!({"planner": planner, "line_spacing_m": 40, "vehicle": {"kind": "fixed_wing", "turn_radius_m": 30}});
    let Err(PlanError::Input(e)) = run(&field, None, None, fixed_wing("e_bf"), &profiles(1e5)) else { panic!("e_bf planned a fixed wing") };
    assert_eq!((e.code, e.pointer.as_str()), ("planner_not_applicable", "/vehicle/kind"));
    assert!(e.detail.contains("energy_aware"), "{}", e.detail);
    let out = run(&field, None, None, fixed_wing("energy_aware"), &profiles(1e5)).expect("energy_aware flies a fixed wing");
    assert!(out.stats.coverage_ratio >= 0.99, "{}", out.stats.coverage_ratio);
    // for a multirotor both plan, each in its own order
    let multirotor = |planner: &str| json!({"planner": planner, "line_spacing_m": 40, "vehicle": {"profile": "iris"}});
    assert!(run(&field, None, None, multirotor("e_bf"), &profiles(1e5)).is_ok());
}

/// Seed 002 Tables 5 and 6, IEM columns: (path, energy J, time s) of the flown E-Spiral and E-BF
/// routes in the polygonal (P) and rectangular (R) areas.
const SEED002_IEM: [(&str, f64, f64); 4] = [("e_spiral P", 79158.0, 379.35), ("e_bf P", 87945.0, 420.60), ("e_spiral R", 46681.0, 223.91), ("e_bf R", 48182.0, 230.81)];

#[test]
fn the_iris_profile_matches_the_flights_that_validated_it() {
    // the flights' mean power, energy over time: 208.5 to 209.1 W in all four
    let table: Vec<f64> = SEED002_IEM.iter().map(|(_, e, t)| e / t).collect();
    let (low, high) = table.iter().fold((f64::MAX, f64::MIN), |(l, h), &p| (l.min(p), h.max(p)));
    // polygons of the flights' size and kind: an irregular heptagon and a rectangle, each of
    // four to seven minutes of flight at IRIS speeds (the tables: 224 to 421 s)
    let heptagon: Vec<(f64, f64)> = regular(7, 190.0, 0.2).iter().enumerate().map(|(k, &(x, y))| if k % 2 == 0 { (x * 1.1, y * 0.9) } else { (x, y) }).collect();
    let rectangle = [(0.0, 0.0), (140.0, 0.0), (140.0, 80.0), (0.0, 80.0)];
    let params = |planner: &str| json!({"planner": planner, "line_spacing_m": 10, "altitude_m": 20, "vehicle": {"profile": "iris"}, "start": {"position": point(0.0, -120.0)}});
    let mut results = Vec::new();
    for (name, field) in [("P", heptagon.as_slice()), ("R", rectangle.as_slice())] {
        for planner in ["e_spiral", "e_bf"] {
            let out = run(field, None, None, params(planner), &profiles(1e5)).unwrap_or_else(|e| panic!("{planner} {name}: {e}"));
            let st = &out.stats;
            let power = st.energy_j / st.duration_s;
            eprintln!("{planner} {name}: {:.0} J in {:.0} s, mean power {power:.1} W (tables: {low:.1} to {high:.1} W)", st.energy_j, st.duration_s);
            assert!((180.0..=600.0).contains(&st.duration_s), "{planner} {name}: {:.0} s is not a flight of the tables' size", st.duration_s);
            // yaw in place at every waypoint would add 220 W turns and lift time by a fifth
            assert!(power >= low * 0.985 && power <= high * 1.015, "{planner} {name}: mean power {power:.1} W outside the tables' {low:.1}–{high:.1} W ±1.5 %");
            results.push(st.energy_j);
        }
    }
    // the tables' ranking: the spiral saves on the polygon (10.0 % by the IEM), and the two are
    // within a few per cent on the rectangle (3.1 %)
    let polygon_saving = 1.0 - results[0] / results[1];
    let rectangle_gap = (1.0 - results[2] / results[3]).abs();
    assert!(polygon_saving > 0.03, "the spiral saves {:.1} % on the polygon", 100.0 * polygon_saving);
    assert!(rectangle_gap < 0.08, "spiral and back-and-forth differ by {:.1} % on the rectangle", 100.0 * rectangle_gap);
}
