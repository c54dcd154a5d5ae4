//! Fleets: a field flown by several drones at once. Over generated fields: every property of a
//! single plan holds for the fleet's plan as a whole (coverage, no metre in a zone, sweeps near
//! the field, deterministic), each drone's features are its own numbered flight, the parts do
//! not overlap, and the last landing comes no later than one drone's flight.

use crate::fixtures::fixture;
use crate::planner_properties::{check_covering, coverage_floor, params, star_field, unlimited_battery};

use coverplan_planner::frame::LocalFrame;
use coverplan_planner::planners::registry;
use coverplan_planner::{self as planner, FieldLimits, MissionGeometry, PlanError, PlanOutput, PlanParams, Stop};
use geo::Coord;
use proptest::prelude::*;
use serde_json::{Value, json};

fn plan_with_home(area: &Value, nfz: Option<&Value>, home: [f64; 2], params: &PlanParams) -> PlanOutput {
    try_plan_with_home(area, nfz, home, params).unwrap_or_else(|| panic!("{} refused the field", params.planner.as_deref().unwrap_or_default()))
}

/// The plan, or `None` when the planner refuses the field with a documented refusal (as
/// `planner_properties::try_plan`); any other error fails.
fn try_plan_with_home(area: &Value, nfz: Option<&Value>, home: [f64; 2], params: &PlanParams) -> Option<PlanOutput> {
    let mission = MissionGeometry { no_fly_zones: nfz, home: Some(home), ..MissionGeometry::area(area) };
    match planner::plan(&mission, params, &unlimited_battery(), &FieldLimits::default(), &|_| true, &Stop::never()) {
        Ok(out) => Some(out),
        Err(PlanError::Input(e)) if ["planner_not_applicable", "instance_too_large"].contains(&e.code) => None,
        Err(e) => panic!("{}: {e}", params.planner.as_deref().unwrap_or_default()),
    }
}

fn property<'a>(f: &'a geojson::Feature, name: &str) -> Option<&'a Value> {
    f.properties.as_ref().and_then(|p| p.get(name))
}

/// The fleet's own properties: numbered flights per drone, totals that add up, parts apart.
fn check_fleet(out: &PlanOutput, single: &PlanOutput, drones: usize, spacing: f64, name: &str) {
    let s = &out.stats;
    assert_eq!(s.vehicles.len(), drones, "{name}");
    let makespan = s.makespan_s.expect("a fleet has a makespan");
    let latest = s.vehicles.iter().map(|v| v.landing_s).fold(0.0, f64::max);
    assert!((makespan - latest).abs() < 1e-6, "{name}: makespan {makespan} is not the last landing {latest}");
    let summed: f64 = s.vehicles.iter().map(|v| v.duration_s).sum();
    assert!((summed - s.duration_s).abs() < 1e-6 * summed.max(1.0), "{name}: drones' durations do not add up");
    // no later than one drone alone, but for the turns taken to leave a shared home
    let stagger = s.vehicles.iter().map(|v| v.departure_s).fold(0.0, f64::max);
    assert!(makespan <= single.stats.duration_s + stagger, "{name}: makespan {makespan:.0} s, one drone {:.0} s", single.stats.duration_s);
    // (the spiral and the grid search are not judged on coverage; see coverage_floor)
    let judged = coverage_floor(&single.stats.planner, false) > 0.0;
    assert!(!judged || s.coverage_ratio >= single.stats.coverage_ratio - 0.01, "{name}: coverage {} against one drone's {}", s.coverage_ratio, single.stats.coverage_ratio);
    // every flown feature belongs to a drone, and each drone's seq counts 0, 1, 2, …
    let mut next_seq = vec![0u64; drones];
    for f in &out.trajectory.features {
        let Some(kind) = property(f, "kind").and_then(Value::as_str) else { continue };
        if ["photos", "uncovered"].contains(&kind) {
            continue;
        }
        let v = property(f, "vehicle").and_then(Value::as_u64).unwrap_or_else(|| panic!("{name}: a {kind} without its vehicle")) as usize;
        assert!(v < drones, "{name}");
        assert_eq!(property(f, "seq").and_then(Value::as_u64), Some(next_seq[v]), "{name}: drone {v}'s seq");
        next_seq[v] += 1;
    }
    for (k, v) in s.vehicles.iter().enumerate() {
        assert_eq!(next_seq[k] > 0, v.area_m2 > 0.0, "{name}: drone {k} flies exactly when it has a part");
    }
    // parts are apart: with the planners whose lines follow the bands, each cut between two
    // parts doubles at most one line's worth of swath beyond what one drone's plan doubles
    // (interleaved parts would double far more)
    let doubled = |o: &PlanOutput| o.stats.overlap_ratio * o.stats.sweep_length_m * spacing;
    let longest = out
        .trajectory
        .features
        .iter()
        .filter(|f| property(f, "kind").and_then(Value::as_str) == Some("sweep"))
        .filter_map(|f| property(f, "length_m")?.as_f64())
        .fold(0.0, f64::max);
    let allowed = doubled(single) + (drones - 1) as f64 * longest * spacing;
    assert!(
        !["boustrophedon", "line_gtsp"].contains(&name.split(", ").nth(1).unwrap()) || doubled(out) <= allowed + 1.0,
        "{name}: {:.0} m² swept twice, one drone {:.0} m²",
        doubled(out),
        doubled(single)
    );
}

/// The property test plans on a pool of its own: on the global one its long plans (every planner,
/// debug build) would hold up the timed job tests that run beside it in this binary.
fn own_pool() -> &'static rayon::ThreadPool {
    static POOL: std::sync::OnceLock<rayon::ThreadPool> = std::sync::OnceLock::new();
    POOL.get_or_init(|| rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a thread pool"))
}

/// One generated case of the property test below.
struct Case {
    lon: f64,
    lat: f64,
    radius: f64,
    shape: Vec<(f64, f64)>,
    holes: usize,
    lines: f64,
    heading: Option<f64>,
    drones: usize,
    planner: &'static str,
    home_side: usize,
}

fn check_case(c: Case) {
    let (radii, jitter): (Vec<f64>, Vec<f64>) = c.shape.into_iter().unzip();
    let (area, nfz) = star_field(c.lon, c.lat, c.radius, &radii, &jitter, c.holes);
    let nfz = (c.holes > 0).then_some(&nfz);
    let spacing = c.radius * 2.0 / c.lines;
    // home just outside the field, at one of four sides
    let frame = LocalFrame::new(c.lon, c.lat);
    let side = c.home_side as f64 * std::f64::consts::FRAC_PI_2;
    let home = frame.to_wgs84(Coord { x: 1.2 * c.radius * side.cos(), y: 1.2 * c.radius * side.sin() });
    let single_params = params(c.planner, spacing, c.heading);
    let fleet_params = PlanParams { vehicles: Some(c.drones as u32), ..single_params.clone() };
    let name = format!("{} drones, {}, star at {},{} r={}", c.drones, c.planner, c.lon, c.lat, c.radius);
    // the fleet's plan has every property of a plan (checked without a home) …
    if check_covering(&area, nfz, &fleet_params, &name, coverage_floor(c.planner, nfz.is_some())).is_none() {
        return;
    }
    // … and, flying from a home, those of a fleet (a part may be refused where the whole is not:
    // a spiral's band around a hole)
    let (Some(single), Some(fleet)) = (try_plan_with_home(&area, nfz, home, &single_params), try_plan_with_home(&area, nfz, home, &fleet_params)) else { return };
    check_fleet(&fleet, &single, c.drones, spacing, &name);
}

/// The planners a fleet's parts may be planned with.
fn fleet_planners() -> Vec<&'static str> {
    registry().iter().filter(|p| p.plans_fleet_parts()).map(|p| p.id()).collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn fleets_cover_generated_fields_in_parts_and_finish_sooner(
        lon in -179.0..179.0f64,
        lat in -70.0..70.0f64,
        radius in 200.0..1200.0f64,
        shape in prop::collection::vec((0.6..1.0f64, -1.0..1.0f64), 5..12),
        holes in 0usize..4,
        lines in 8.0..30.0f64,
        heading in prop::option::of(0.0..180.0f64),
        drones in 2usize..6,
        planner in prop::sample::select(fleet_planners()),
        home_side in 0usize..4,
    ) {
        own_pool().install(|| check_case(Case { lon, lat, radius, shape, holes, lines, heading, drones, planner, home_side }));
    }
}

/// Two drones whose bands are strung across three holes land later than one drone alone would
/// (1 199 s against 1 182 s before one drone alone was tried): the fleet then flies one.
#[test]
fn a_fleet_cut_across_holes_lands_no_later_than_one_drone() {
    let shape = vec![
        (0.887022932639707, -0.7301285636349799),
        (0.6751380725045765, 0.24247895303192962),
        (0.9372364091610323, -0.8688603173405077),
        (0.67464109908813, -0.28159261572750327),
        (0.6367593285667722, -0.8714256759385697),
    ];
    own_pool().install(|| check_case(Case { lon: 39.21, lat: 0.045, radius: 649.53, shape, holes: 3, lines: 9.1233, heading: None, drones: 2, planner: "eecd", home_side: 2 }));
}

fn fixture_field(name: &str) -> (Value, Option<Value>, [f64; 2]) {
    let m = fixture(name);
    let home: [f64; 2] = serde_json::from_value(m["area"]["coordinates"][0][0].clone()).unwrap();
    (m["area"].clone(), m.get("no_fly_zones").filter(|v| !v.is_null()).cloned(), home)
}

/// More drones land sooner, within reach of the ideal: one drone's time shared out, plus the
/// flight out to the farthest part.
#[test]
fn more_drones_land_sooner() {
    let (area, nfz, home) = fixture_field("random-fields/h02_00.json");
    let base = PlanParams { line_spacing_m: Some(20.0), ..PlanParams::default() };
    let one = plan_with_home(&area, nfz.as_ref(), home, &base).stats.duration_s;
    let mut previous = one;
    for drones in [2, 4, 8] {
        let out = plan_with_home(&area, nfz.as_ref(), home, &PlanParams { vehicles: Some(drones), ..base.clone() });
        let makespan = out.stats.makespan_s.unwrap();
        assert!(makespan < previous, "{drones} drones: {makespan:.0} s, fewer drones {previous:.0} s");
        let last_off = out.stats.vehicles.iter().map(|v| v.departure_s).fold(0.0, f64::max);
        assert!(makespan < 1.5 * one / drones as f64 + last_off, "{drones} drones: {makespan:.0} s against {one:.0} s for one");
        previous = makespan;
    }
}

/// A faster drone is given more of the field, and the two land at about the same time.
#[test]
fn a_faster_drone_takes_a_larger_part() {
    let (area, nfz, home) = fixture_field("random-fields/h00_00.json");
    let fleet = json!([{"profile": "generic_multirotor", "cruise_speed_mps": 4}, {"profile": "generic_multirotor", "cruise_speed_mps": 12}]);
    let params = PlanParams { line_spacing_m: Some(20.0), fleet: Some(serde_json::from_value(fleet).unwrap()), ..PlanParams::default() };
    let out = plan_with_home(&area, nfz.as_ref(), home, &params);
    let [slow, fast] = [&out.stats.vehicles[0], &out.stats.vehicles[1]];
    assert!(fast.area_m2 > 1.5 * slow.area_m2, "fast {:.0} m², slow {:.0} m²", fast.area_m2, slow.area_m2);
    let (a, b) = (slow.landing_s, fast.landing_s);
    assert!((a - b).abs() < 0.15 * a.max(b), "landings at {a:.0} s and {b:.0} s");
}

/// Altitude layers: each drone's transits climb from the survey altitude to its own layer and
/// back, no steeper than `max_climb_deg`, and the climbs cost energy. Conflicts are left only
/// where the drones climb out of and back into the survey altitude at their shared home.
#[test]
fn altitude_layers_separate_transits() {
    let (area, nfz, home) = fixture_field("random-fields/h02_00.json");
    let level = PlanParams { line_spacing_m: Some(20.0), altitude_m: Some(60.0), vehicles: Some(4), ..PlanParams::default() };
    let params = PlanParams { altitude_separation_m: Some(10.0), ..level.clone() };
    let out = plan_with_home(&area, nfz.as_ref(), home, &params);
    let flat = plan_with_home(&area, nfz.as_ref(), home, &level);
    let layered = out.stats.conflicts.clone().expect("a fleet reports conflicts");
    // the highest layer is 40 m up: its ramp ends 40 / tan 30° = 69 m from where it starts
    let frame = LocalFrame::new(home[0], home[1]);
    for c in &layered {
        let at = frame.to_local(c.position[0], c.position[1]);
        assert!(at.x.hypot(at.y) < 80.0, "a conflict away from the shared home: {c:?}");
    }
    assert!(out.stats.energy_j > flat.stats.energy_j, "climbing to the layers is priced: {} J against {} J", out.stats.energy_j, flat.stats.energy_j);
    let mut reached = 0;
    for f in &out.trajectory.features {
        if property(f, "kind").and_then(Value::as_str) != Some("transit") {
            continue;
        }
        let v = property(f, "vehicle").and_then(Value::as_u64).unwrap() as f64;
        let layer = 60.0 + 10.0 * (v + 1.0);
        let geojson::GeometryValue::LineString { coordinates } = &f.geometry.as_ref().unwrap().value else { panic!("a transit is a line") };
        let (first, last) = (coordinates[0][2], coordinates[coordinates.len() - 1][2]);
        assert!((first - 60.0).abs() < 0.01 && (last - 60.0).abs() < 0.01, "drone {v}'s transit leaves and rejoins the survey altitude: {coordinates:?}");
        assert!(coordinates.iter().all(|c| c[2] <= layer + 0.01), "drone {v} above its layer");
        reached += usize::from(coordinates.iter().any(|c| (c[2] - layer).abs() < 0.01));
        // no ramp steeper than 30°
        let frame = LocalFrame::new(coordinates[0][0], coordinates[0][1]);
        for w in coordinates.windows(2) {
            let (a, b) = (frame.to_local(w[0][0], w[0][1]), frame.to_local(w[1][0], w[1][1]));
            let run = (b.x - a.x).hypot(b.y - a.y);
            assert!((w[1][2] - w[0][2]).abs() <= run * 30f64.to_radians().tan() + 0.05, "drone {v}: a ramp steeper than 30°");
        }
    }
    assert!(reached > 0, "long transits reach their layer");
}

/// What a fleet cannot do is refused with its place.
#[test]
fn fleets_refuse_what_they_cannot_split() {
    let (area, nfz, home) = fixture_field("random-fields/h02_00.json");
    let mission = MissionGeometry { no_fly_zones: nfz.as_ref(), home: Some(home), ..MissionGeometry::area(&area) };
    let refused = |params: PlanParams| match planner::plan(&mission, &params, &unlimited_battery(), &FieldLimits::default(), &|_| true, &Stop::never()) {
        Err(PlanError::Input(e)) => (e.code, e.pointer),
        other => panic!("not refused: {:?}", other.map(|o| o.stats.planner)),
    };
    let fleet = || PlanParams { line_spacing_m: Some(20.0), vehicles: Some(2), ..PlanParams::default() };
    let not_for_fleets = registry().iter().find(|p| !p.plans_fleet_parts() && !p.for_ground_vehicles()).expect("a planner that plans no fleet's parts");
    assert_eq!(refused(PlanParams { planner: Some(not_for_fleets.id().into()), ..fleet() }), ("planner_not_for_fleets", "/planner".into()));
    let optimal = serde_json::from_value(json!("optimal")).unwrap();
    assert_eq!(refused(PlanParams { sweep_direction: Some(optimal), ..fleet() }), ("direction_for_fleet", "/sweep_direction".into()));
    // a drone's home inside a no-fly zone
    let zone = &nfz.as_ref().expect("h02 has zones")["coordinates"][0][0];
    let inside: Vec<[f64; 2]> = zone.as_array().unwrap().iter().map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()]).collect();
    let n = (inside.len() - 1) as f64;
    let centre = inside[..inside.len() - 1].iter().fold([0.0, 0.0], |c, p| [c[0] + p[0] / n, c[1] + p[1] / n]);
    let members = json!([{"profile": "iris"}, {"profile": "iris", "home": centre}]);
    let params = PlanParams { line_spacing_m: Some(20.0), fleet: Some(serde_json::from_value(members).unwrap()), ..PlanParams::default() };
    assert_eq!(refused(params), ("point_in_no_fly_zone", "/fleet/1/home".into()));
}
