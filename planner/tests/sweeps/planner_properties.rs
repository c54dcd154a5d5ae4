//! Properties of plans over every fixture field and over generated fields: no error, no
//! panic, coverage, no metre inside a no-fly zone, sweeps near the field, valid GeoJSON,
//! the same output for the same input. Every planner of the registry is checked, so a new
//! planner is checked as soon as it is registered.

use crate::fixtures::{fixture, fixtures_dir};

use coverplan_planner::frame::LocalFrame;
use coverplan_planner::planners::{self, registry};
use coverplan_planner::{self as planner, FieldLimits, MissionGeometry, PlanError, PlanOutput, PlanParams, Stop};
use geo::{Area, BooleanOps, Buffer, Contains, Coord, LineString, MultiPolygon, Point, Polygon};
use proptest::prelude::*;
use serde_json::{Value, json};

fn plan(area: &Value, nfz: Option<&Value>, params: &PlanParams) -> PlanOutput {
    try_plan(area, nfz, params).unwrap_or_else(|| panic!("{} refused the field", params.planner.as_deref().unwrap_or_default()))
}

/// The plan, or `None` when the planner refuses the mission with one of its documented
/// refusals: outside its method (`planner_not_applicable`, such as a spiral around holes) or
/// over its search limit (`instance_too_large`); any other error fails.
fn try_plan(area: &Value, nfz: Option<&Value>, params: &PlanParams) -> Option<PlanOutput> {
    let mission = MissionGeometry { no_fly_zones: nfz, ..MissionGeometry::area(area) };
    match planner::plan(&mission, params, &unlimited_battery(), &FieldLimits::default(), &|_| true, &Stop::never()) {
        Ok(out) => Some(out),
        Err(PlanError::Input(e)) if ["planner_not_applicable", "instance_too_large"].contains(&e.code) => None,
        Err(e) => panic!("{} failed: {e}", params.planner.as_deref().unwrap_or_default()),
    }
}

/// Every planner of the registry but those of ground vehicles (`ground_plans.rs` checks them)
/// and of corridors (`tests/it/corridors.rs`): these fields are areas.
fn planners() -> Vec<&'static str> {
    registry().iter().filter(|p| !p.for_ground_vehicles() && !p.follows_corridors()).map(|p| p.id()).collect()
}

/// The share of the area a planner's plans must cover: its own target, a point less with no-fly
/// zones (the corners at their edges); 0 for a planner whose coverage swaths do not measure.
pub(crate) fn coverage_floor(planner: &str, with_zones: bool) -> f64 {
    let target = planners::find(planner).unwrap_or_else(|| panic!("{planner} is not registered")).coverage_target();
    target.map_or(0.0, |t| if with_zones { t - 0.01 } else { t })
}

pub(crate) fn params(planner: &str, spacing: f64, heading: Option<f64>) -> PlanParams {
    PlanParams { planner: Some(planner.into()), line_spacing_m: Some(spacing), heading_deg: heading, ..PlanParams::default() }
}

/// A plan with a 1-inch camera whose lines are about `spacing` apart (side overlap 70 %).
fn camera_params(planner: &str, spacing: f64, heading: Option<f64>) -> PlanParams {
    let camera = serde_json::from_value(json!({"preset": "dji_phantom4_pro"})).unwrap();
    // this camera images 1.5 m across per metre of altitude
    PlanParams { planner: Some(planner.into()), camera: Some(camera), altitude_m: Some(spacing / 0.45), heading_deg: heading, ..PlanParams::default() }
}

/// The properties every plan must have; false when the planner refused the field.
fn check(area: &Value, nfz: Option<&Value>, p: &PlanParams, name: &str) -> bool {
    check_covering(area, nfz, p, name, coverage_floor(p.planner.as_deref().unwrap_or_default(), nfz.is_some())).is_some()
}

/// Checks the plan of `area` and returns it (`None`: the planner refused the field).
pub(crate) fn check_covering(area: &Value, nfz: Option<&Value>, p: &PlanParams, name: &str, min_coverage: f64) -> Option<PlanOutput> {
    let out = try_plan(area, nfz, p)?;
    let s = &out.stats;
    // with a camera, what the photos image counts (docs/methods.md, multirotor planners §4); its
    // swaths (a line spacing wide, where a photo is 3.3 spacings wide at 70 % side overlap) may
    // differ either way: photos stop flush with a line's ends, and image the square round a bend
    // where a swath turns in a round fan. On a field a few footprints across, a spiral's rings
    // round a star's sharp points leave swaths short where its photos image the ground (0.952
    // swath and 0.998 photo coverage of a seven-pointed star 2.5 km across, rings 530 m apart), so
    // the swaths are only checked to lie over the field
    match s.photo_coverage_ratio {
        Some(photo) => {
            assert!(photo >= min_coverage - 0.01, "{name}: photo coverage {photo}");
            assert!(s.coverage_ratio >= min_coverage - 0.1, "{name}: coverage {}", s.coverage_ratio);
        }
        None => assert!(s.coverage_ratio >= min_coverage, "{name}: coverage {}", s.coverage_ratio),
    }
    // efficiency may pass 1 when one line covers a narrow field, or a camera images wider than
    // the spacing; a plan of one photo (a one-cell grid) has no length, hence no efficiency
    assert!(s.overlap_ratio >= 0.0 && (s.efficiency > 0.0 || s.length_m == 0.0 && s.photos == 1), "{name}: {s:?}");
    assert_eq!(s.nfz_intrusion_m, 0.0, "{name}: path enters a no-fly zone");
    assert!(s.length_m > 0.0 && s.duration_s > 0.0 && s.energy_j > 0.0);
    // valid GeoJSON, and identical on a second run
    let text = serde_json::to_string(&out.trajectory).unwrap();
    let parsed: geojson::GeoJson = text.parse().unwrap_or_else(|e| panic!("{name}: invalid GeoJSON: {e}"));
    assert!(matches!(parsed, geojson::GeoJson::FeatureCollection(_)));
    let again = plan(area, nfz, p);
    assert_eq!(serde_json::to_string(&again.trajectory).unwrap(), text, "{name}: not deterministic");

    // independent checks in a local frame of our own: sweeps stay within one spacing of the
    // field, and no vertex of the path lies inside a no-fly zone
    let ring_points = |v: &Value| -> Vec<[f64; 2]> {
        let mut out = Vec::new();
        collect_positions(v, &mut out);
        out
    };
    let frame = LocalFrame::centred_on(ring_points(area));
    let field = to_local_mp(&frame, area);
    // a camera's lines lie inside its footprint's half width of the edge
    let reach = p.line_spacing_m.unwrap_or_else(|| p.altitude_m.unwrap() * 1.5 / 2.0);
    let near_field = field.buffer(reach + 0.5);
    let zones = nfz.map(|z| to_local_mp(&frame, z)).unwrap_or(MultiPolygon(vec![]));
    // the uncovered ground: outside the zones, within the field, and at least what the coverage
    // ratio says is missing from the area to cover (slivers under 1 m² are left out)
    let kind = |f: &geojson::Feature| f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str).map(str::to_owned);
    let uncovered: Vec<&geojson::Feature> = out.trajectory.features.iter().filter(|f| kind(f).as_deref() == Some("uncovered")).collect();
    assert!(uncovered.len() <= 1, "{name}: one uncovered feature at most");
    let uncovered_mp = uncovered.first().map_or(MultiPolygon(vec![]), |f| to_local_mp(&frame, &serde_json::to_value(f.geometry.as_ref().unwrap()).unwrap()));
    let missing = (1.0 - s.coverage_ratio) * s.area_to_cover_m2;
    let shown = uncovered_mp.unsigned_area();
    assert!(shown >= missing - (5.0f64).max(0.005 * s.area_to_cover_m2), "{name}: {shown:.0} m² shown uncovered, {missing:.0} m² missing");
    // coordinates are written to about a centimetre, so the zones' edges are taken 10 cm in
    assert!(uncovered_mp.intersection(&zones.buffer(-0.1)).unsigned_area() < 1.0, "{name}: uncovered ground drawn inside a no-fly zone");
    assert!(uncovered_mp.difference(&field.buffer(0.5)).unsigned_area() < 1.0, "{name}: uncovered ground drawn outside the field");
    for f in &out.trajectory.features {
        let props = f.properties.as_ref().unwrap();
        let geojson::GeometryValue::LineString { coordinates } = &f.geometry.as_ref().unwrap().value else { continue };
        let pts: Vec<Coord> = coordinates.iter().map(|c| frame.to_local(c[0], c[1])).collect();
        for w in pts.windows(2) {
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let q = Point::new(w[0].x + (w[1].x - w[0].x) * t, w[0].y + (w[1].y - w[0].y) * t);
                assert!(!zones.contains(&q), "{name}: a {} enters a no-fly zone at {q:?}", props["kind"]);
                if props["kind"] == "sweep" {
                    assert!(near_field.contains(&q), "{name}: a sweep leaves the field at {q:?}");
                }
            }
        }
    }
    Some(out)
}

pub(crate) fn collect_positions(v: &Value, out: &mut Vec<[f64; 2]>) {
    match v {
        Value::Array(a) if a.len() >= 2 && a[0].is_number() => out.push([a[0].as_f64().unwrap(), a[1].as_f64().unwrap()]),
        Value::Array(a) => a.iter().for_each(|x| collect_positions(x, out)),
        Value::Object(o) => o.get("coordinates").into_iter().for_each(|x| collect_positions(x, out)),
        _ => {}
    }
}

pub(crate) fn to_local_mp(frame: &LocalFrame, v: &Value) -> MultiPolygon {
    let polys: Vec<Value> = match v["type"].as_str().unwrap() {
        "Polygon" => vec![v["coordinates"].clone()],
        _ => v["coordinates"].as_array().unwrap().clone(),
    };
    MultiPolygon(
        polys
            .iter()
            .map(|rings| {
                let mut rings = rings
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|r| LineString::from(r.as_array().unwrap().iter().map(|c| frame.to_local(c[0].as_f64().unwrap(), c[1].as_f64().unwrap())).collect::<Vec<_>>()));
                let ext = rings.next().unwrap();
                Polygon::new(ext, rings.collect())
            })
            .collect(),
    )
}

fn spacing_for(area_m2: f64) -> f64 {
    (area_m2.sqrt() / 15.0).clamp(4.0, 60.0)
}

#[test]
fn every_fixture_field_is_planned_correctly() {
    let dir = fixtures_dir();
    let mut files: Vec<String> = Vec::new();
    for sub in ["random-fields", "real-fields"] {
        for e in std::fs::read_dir(dir.join(sub)).unwrap() {
            let name = e.unwrap().file_name().into_string().unwrap();
            if name.ends_with(".json") && name != "index.json" {
                files.push(format!("{sub}/{name}"));
            }
        }
    }
    files.sort();
    assert!(files.len() >= 69);
    // each field by the registry's planners in turn: every planner meets seven or eight fields
    // of varied kinds (the files go by hole count, four to a count, and the registry has nine
    // planners), and the suite stays within CI's time: line_gtsp, and auto which runs it, take
    // 8 to 10 s on a field with 15 zones (debug build)
    let all = planners();
    let mut planned = vec![0; all.len()];
    for (i, f) in files.iter().enumerate() {
        let m = fixture(f);
        let frame = LocalFrame::centred_on({
            let mut pts = Vec::new();
            collect_positions(&m["area"], &mut pts);
            pts
        });
        let area = to_local_mp(&frame, &m["area"]).unsigned_area();
        let spacing = spacing_for(area);
        let nfz = m.get("no_fly_zones").filter(|v| !v.is_null());
        // the holes as holes only (overflown), then as no-fly zones too
        let k = i % all.len();
        let planner = all[k];
        let mut ok = check(&m["area"], None, &params(planner, spacing, None), &format!("{f} by {planner}"));
        if nfz.is_some() {
            ok |= check(&m["area"], nfz, &params(planner, spacing, None), &format!("{f} with no-fly zones by {planner}"));
        }
        planned[k] += usize::from(ok);
    }
    for (planner, n) in all.iter().zip(&planned) {
        eprintln!("{planner}: {n} fields planned");
    }
    // eg_cpp refuses fields this large and e_spiral fields with holes; the others plan all
    // they are given
    let total: usize = planned.iter().sum();
    assert!(total >= files.len() * 2 / 3, "{total} plans of {} fields", files.len());
}

#[test]
fn real_fields_are_covered_to_99_percent_in_any_direction() {
    let all = planners();
    let mut k = 0;
    for f in ["ee-field-3-holes", "nl-parcel-17ha", "nl-parcel-b", "us-field-two-cells", "us-field-two-cells-1"] {
        let m = fixture(&format!("real-fields/{f}.json"));
        for heading in [0.0, 33.0, 90.0, 147.0] {
            // two planners of the registry in turn for each field and heading
            for planner in [all[k % all.len()], all[(k + 4) % all.len()]] {
                let Some(out) = try_plan(&m["area"], None, &params(planner, 10.0, Some(heading))) else { continue };
                let floor = coverage_floor(planner, false);
                assert!(out.stats.coverage_ratio >= floor, "{f} at {heading}° by {planner}: {}", out.stats.coverage_ratio);
            }
            k += 1;
        }
    }
}

/// A star-shaped field around (lon, lat) with square holes; see `field_strategy`.
pub(crate) fn star_field(lon: f64, lat: f64, radius: f64, radii: &[f64], jitter: &[f64], holes: usize) -> (Value, Value) {
    let frame = LocalFrame::new(lon, lat);
    let n = radii.len();
    let to_ll = |c: Coord| {
        let p = frame.to_wgs84(c);
        json!([p[0], p[1]])
    };
    let mut ring: Vec<Value> = (0..n)
        .map(|i| {
            let a = (i as f64 + 0.3 * jitter[i]) / n as f64 * std::f64::consts::TAU;
            to_ll(Coord { x: radius * radii[i] * a.cos(), y: radius * radii[i] * a.sin() })
        })
        .collect();
    ring.push(ring[0].clone());
    let mut hole_rings = Vec::new();
    for h in 0..holes {
        let a = h as f64 / 4.0 * std::f64::consts::TAU + 0.4;
        let (cx, cy, d) = (0.18 * radius * a.cos(), 0.18 * radius * a.sin(), 0.05 * radius);
        let sq: Vec<Value> = [(-d, -d), (-d, d), (d, d), (d, -d), (-d, -d)].iter().map(|&(x, y)| to_ll(Coord { x: cx + x, y: cy + y })).collect();
        hole_rings.push(sq);
    }
    let mut rings = vec![Value::Array(ring)];
    rings.extend(hole_rings.iter().cloned().map(Value::Array));
    let area = json!({"type": "Polygon", "coordinates": rings});
    let nfz = json!({"type": "MultiPolygon", "coordinates": hole_rings.iter().map(|r| json!([r])).collect::<Vec<_>>()});
    (area, nfz)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn generated_fields_are_planned_correctly(
        lon in -179.0..179.0f64,
        lat in -70.0..70.0f64,
        radius in 150.0..1500.0f64,
        shape in prop::collection::vec((0.6..1.0f64, -1.0..1.0f64), 5..14),
        holes in 0usize..5,
        lines in 5.0..30.0f64,
        heading in prop::option::of(0.0..180.0f64),
        holes_are_nfz in any::<bool>(),
        planner in prop::sample::select(planners()),
        with_camera in any::<bool>(),
    ) {
        let (radii, jitter): (Vec<f64>, Vec<f64>) = shape.into_iter().unzip();
        let (area, nfz) = star_field(lon, lat, radius, &radii, &jitter, holes);
        let spacing = radius * 2.0 / lines;
        let nfz = (holes_are_nfz && holes > 0).then_some(&nfz);
        let p = if with_camera { camera_params(planner, spacing, heading) } else { params(planner, spacing, heading) };
        check(&area, nfz, &p, &format!("star at {lon},{lat} r={radius} by {planner}"));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Line ends at slanted edges (`swath_ends`): centre-line ends fly the least sweep and cover
    /// the least, full-width ends the most, balanced ones lie between and cover within 1 % of
    /// full width; each plan keeps every property `check_covering` asks.
    #[test]
    fn aircraft_line_ends_trade_sweep_for_coverage_in_order(
        lon in -179.0..179.0f64,
        lat in -70.0..70.0f64,
        radius in 150.0..1500.0f64,
        shape in prop::collection::vec((0.6..1.0f64, -1.0..1.0f64), 5..14),
        holes in 0usize..4,
        lines in 5.0..30.0f64,
        heading in 0.0..180.0f64,
        planner in prop::sample::select(vec!["boustrophedon", "line_gtsp", "eecd"]),
    ) {
        let (radii, jitter): (Vec<f64>, Vec<f64>) = shape.into_iter().unzip();
        let (area, nfz) = star_field(lon, lat, radius, &radii, &jitter, holes);
        let nfz = (holes > 0).then_some(&nfz);
        let name = format!("star at {lon},{lat} r={radius} by {planner}");
        let floor = coverage_floor(planner, nfz.is_some());
        let plan = |ends: &str, min_coverage: f64| {
            let mut p = params(planner, radius * 2.0 / lines, Some(heading));
            p.swath_ends = Some(serde_json::from_value(json!(ends)).unwrap());
            let out = check_covering(&area, nfz, &p, &format!("{name}, {ends} ends"), min_coverage).unwrap_or_else(|| panic!("{name}: refused"));
            (out.stats.sweep_length_m, out.stats.coverage_ratio)
        };
        let full = plan("full_width", floor);
        let balanced = plan("balanced", floor - 0.01);
        let centre = plan("centre_line", 0.0);
        let all = format!("{name}: (sweep m, coverage) centre line {centre:?}, balanced {balanced:?}, full width {full:?}");
        prop_assert!(centre.0 <= balanced.0 + 1e-6 && balanced.0 <= full.0 + 1e-6, "{}", all);
        prop_assert!(centre.1 <= balanced.1 + 1e-4 && balanced.1 <= full.1 + 1e-4, "{}", all);
        prop_assert!(balanced.1 >= full.1 - 0.01, "{}", all);
    }
}

/// Smallest radius of the circle through three points (infinite when they are collinear).
fn circumradius(a: Coord, b: Coord, c: Coord) -> f64 {
    let (ab, bc, ca) = ((b - a).x.hypot((b - a).y), (c - b).x.hypot((c - b).y), (a - c).x.hypot((a - c).y));
    let cross = ((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs();
    if cross < 1e-9 { f64::INFINITY } else { ab * bc * ca / (2.0 * cross) }
}

/// Fixed wing over the generated fields, holes as no-fly zones: every planner that flies a
/// fixed wing covers the field away from the zones, never enters a zone (turn arcs included,
/// checked by sampling in `check`), and never turns tighter than the radius along the whole
/// path. The planners take the fields in turn.
#[test]
fn fixed_wing_plans_respect_zones_and_turning_radius() {
    let index = fixture("random-fields/index.json");
    let fixed_wing = |planner: &str, spacing: f64, radius: f64| -> PlanParams {
        serde_json::from_value(json!({"planner": planner, "line_spacing_m": spacing, "vehicle": {"kind": "fixed_wing", "turn_radius_m": radius}})).unwrap()
    };
    // the planners that fly a fixed wing: the others refuse it, whatever the field
    let (square, _) = star_field(5.0, 45.0, 300.0, &[1.0; 4], &[0.0; 4], 0);
    let flying: Vec<&str> = planners().into_iter().filter(|p| try_plan(&square, None, &fixed_wing(p, 30.0, 36.0)).is_some()).collect();
    eprintln!("planners that fly a fixed wing: {flying:?}");
    assert!(flying.len() >= 5 && flying.contains(&"line_gtsp"), "{flying:?}");
    let mut planned = 0;
    for (k, entry) in index.as_array().unwrap().iter().enumerate().filter(|(k, _)| k % 4 == 0) {
        let f = format!("random-fields/{}", entry["file"].as_str().unwrap());
        let m = fixture(&f);
        let frame = LocalFrame::centred_on({
            let mut pts = Vec::new();
            collect_positions(&m["area"], &mut pts);
            pts
        });
        let field = to_local_mp(&frame, &m["area"]);
        let spacing = spacing_for(field.unsigned_area());
        let radius = spacing * 1.2;
        let nfz = m.get("no_fly_zones").filter(|v| !v.is_null());
        let planner = flying[k / 4 % flying.len()];
        let p = fixed_wing(planner, spacing, radius);
        let name = format!("{f} by {planner}, fixed wing r = {radius:.1} m");
        // near the zones a fixed wing cannot fly what it could not turn back from: coverage is
        // judged away from them below
        let out = check_covering(&m["area"], nfz, &p, &name, if nfz.is_some() { 0.0 } else { 0.99 }).unwrap_or_else(|| panic!("{name}: refused"));
        if let Some(nfz) = nfz {
            // lines stop at the margin (10 m by default), then draw back in steps of r/8 until a
            // half circle (r ahead, 2r aside) fits; their swaths reach half a spacing further
            let reach = 10.0 + 2.0 * radius + radius / 8.0 + spacing / 2.0;
            let away = field.difference(&to_local_mp(&frame, nfz).buffer(reach));
            let away_m2 = away.unsigned_area();
            let covered = away.intersection(&swaths(&out, &frame, spacing)).unsigned_area() / away_m2;
            let share = away_m2 / field.unsigned_area();
            eprintln!("{name}: coverage {:.4}; {covered:.4} of the {share:.2} more than {reach:.0} m from the zones", out.stats.coverage_ratio);
            assert!(away_m2 == 0.0 || covered >= 0.99, "{name}: {covered:.4} covered away from the zones");
        }
        let pts: Vec<Coord> = out
            .trajectory
            .features
            .iter()
            .filter_map(|f| match &f.geometry.as_ref()?.value {
                geojson::GeometryValue::LineString { coordinates } => Some(coordinates.iter().map(|c| frame.to_local(c[0], c[1])).collect::<Vec<_>>()),
                _ => None,
            })
            .flat_map(|piece| piece.into_iter())
            .collect();
        // exported positions are rounded to 1e-7°: judge chords of 5 m and more, within 10 %
        let mut kept: Vec<Coord> = Vec::new();
        for p in pts {
            if kept.last().is_none_or(|q: &Coord| (p - *q).x.hypot((p - *q).y) >= 5.0) {
                kept.push(p);
            }
        }
        for w in kept.windows(3) {
            assert!(circumradius(w[0], w[1], w[2]) >= 0.9 * radius, "{name}: turns with radius {:.1} m at {:?}", circumradius(w[0], w[1], w[2]), w[1]);
        }
        planned += 1;
    }
    assert!(planned >= 16);
}

/// The swaths of the sweeps of `out` in `frame`: a rectangle `spacing` wide along each.
fn swaths(out: &PlanOutput, frame: &LocalFrame, spacing: f64) -> MultiPolygon {
    let mut strips = Vec::new();
    for f in out.trajectory.features.iter().filter(|f| f.properties.as_ref().is_some_and(|p| p["kind"] == "sweep")) {
        let geojson::GeometryValue::LineString { coordinates } = &f.geometry.as_ref().unwrap().value else { continue };
        let pts: Vec<Coord> = coordinates.iter().map(|c| frame.to_local(c[0], c[1])).collect();
        for w in pts.windows(2) {
            let d = w[1] - w[0];
            let len = d.x.hypot(d.y);
            if len > 1e-9 {
                let side = Coord { x: -d.y, y: d.x } * (spacing / 2.0 / len);
                strips.push(Polygon::new(LineString::from(vec![w[0] - side, w[1] - side, w[1] + side, w[0] + side, w[0] - side]), vec![]));
            }
        }
    }
    geo::unary_union(&strips)
}

/// The built-in profiles with a battery no plan here exhausts: these tests are about geometry,
/// not sorties.
pub(crate) fn unlimited_battery() -> Vec<planner::vehicle::Vehicle> {
    let mut profiles = planner::vehicle::builtin_profiles();
    profiles.iter_mut().for_each(|v| v.battery.energy_wh = 1e5);
    profiles
}
