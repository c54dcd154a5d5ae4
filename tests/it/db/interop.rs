//! Plans that leave the service and fields that come in: every export format downloaded from
//! the real service, read back by our importers (the geometry within 1 cm) and by independent
//! readers (pymavlink, fastkml, jsonschema, the isoxml library), imports of good and bad files,
//! and a property over the random fields: every format writes, and the flight files visit the
//! trajectory's points in its order.
//!
//! The independent readers are installed by `tests/run_all.sh`; the Python one is found through
//! `COVERPLAN_PYTHON` (default: the virtual environment that script makes).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Command;

use coverplan::planner::export::follower::{self, FollowerSpec};
use coverplan::planner::export::{self, ExportOptions, ExportRequest, Firmware};
use coverplan::planner::geojson::{FeatureCollection, GeometryValue};
use coverplan::planner::vehicle::VehicleKind;
use coverplan::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop, import};
use proptest::prelude::*;
use serde_json::{Value, json};

use crate::common::{self, TestApp};

const ONE_CM_DEG: f64 = 1e-7;
const FLOWN: [&str; 3] = ["sweep", "turn", "transit"];

pub fn python() -> PathBuf {
    let path = std::env::var_os("COVERPLAN_PYTHON").map(PathBuf::from).unwrap_or_else(|| {
        let home = std::env::var_os("HOME").map(PathBuf::from).unwrap_or_default();
        home.join(".cache/coverplan-venv/bin/python")
    });
    assert!(path.exists(), "{} is missing: tests/run_all.sh installs the Python readers (or set COVERPLAN_PYTHON)", path.display());
    path
}

pub fn interop_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/interop")
}

/// Runs a checker and fails with its output unless it succeeds.
pub fn run(command: &mut Command) {
    let out = command.output().unwrap_or_else(|e| panic!("{command:?}: {e}"));
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    println!("{text}");
    assert!(out.status.success(), "{command:?} failed:\n{text}");
}

pub fn temp_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("coverplan-interop-{}", uuid::Uuid::new_v4()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The mission as a GeoJSON file, normalised by our GeoJSON import (exteriors
/// counter-clockwise): what every other format must give back.
fn canonical(mission: &Value) -> import::ImportedMission {
    import::import(Some("geojson"), mission.to_string().as_bytes()).expect("the mission reads as GeoJSON")
}

type Ring = Vec<[f64; 2]>;

/// Polygons of a GeoJSON MultiPolygon, each as rings without the closing point.
/// The polygons of a MultiPolygon, or of a FeatureCollection of Polygons (an import that names
/// its fields).
fn polygons(value: Option<&Value>) -> Vec<Vec<Ring>> {
    let Some(v) = value.filter(|v| !v.is_null()) else { return vec![] };
    let coordinates = match v["type"].as_str() {
        Some("FeatureCollection") => v["features"].as_array().unwrap().iter().map(|f| f["geometry"]["coordinates"].clone()).collect(),
        _ => v["coordinates"].clone(),
    };
    serde_json::from_value::<Vec<Vec<Vec<[f64; 2]>>>>(coordinates)
        .unwrap()
        .into_iter()
        .map(|p| {
            p.into_iter()
                .map(|mut r| {
                    r.pop();
                    r
                })
                .collect()
        })
        .collect()
}

/// Same ring within 1 cm, starting anywhere, same direction.
fn same_ring(a: &Ring, b: &Ring) -> bool {
    let close = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).abs() <= ONE_CM_DEG && (p[1] - q[1]).abs() <= ONE_CM_DEG;
    a.len() == b.len() && (0..b.len()).any(|shift| a.iter().enumerate().all(|(i, &p)| close(p, b[(i + shift) % b.len()])))
}

fn assert_same_polygons(found: &[Vec<Ring>], expected: &[Vec<Ring>], holes: bool, what: &str) {
    assert_eq!(found.len(), expected.len(), "{what}: {} polygons, expected {}", found.len(), expected.len());
    for e in expected {
        let matched = found.iter().any(|f| same_ring(&f[0], &e[0]) && (!holes || (f.len() == e.len() && e[1..].iter().all(|h| f[1..].iter().any(|g| same_ring(g, h))))));
        assert!(matched, "{what}: no polygon matches {:?}…", &e[0][..2]);
    }
}

/// A `.plan`'s inclusion fence holds the fields and the whole flight with a margin: read back,
/// it is one area round every field.
fn assert_fence_holds(found: &[Vec<Ring>], fields: &[Vec<Ring>], what: &str) {
    assert_eq!(found.len(), 1, "{what}: one inclusion fence, {} areas", found.len());
    let fence = &found[0][0];
    assert!(fields.iter().flat_map(|f| &f[0]).all(|&p| inside(p, fence)), "{what}: the fence holds every field");
}

/// Whether `p` lies inside `ring` (not closed): the even-odd rule, on longitudes taken within
/// 180° of `p`'s (a ring may cross the antimeridian).
fn inside(p: [f64; 2], ring: &Ring) -> bool {
    let near = |q: [f64; 2]| [p[0] + (q[0] - p[0] + 540.0).rem_euclid(360.0) - 180.0, q[1]];
    let ring: Vec<[f64; 2]> = ring.iter().map(|&q| near(q)).collect();
    let mut within = false;
    for (i, a) in ring.iter().enumerate() {
        let b = ring[(i + ring.len() - 1) % ring.len()];
        if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0] {
            within = !within;
        }
    }
    within
}

/// The trajectory's flown points in order, each once, `[lat, lon]`.
fn flown_points(trajectory: &FeatureCollection) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::new();
    for f in &trajectory.features {
        let kind = f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str).unwrap_or_default();
        if let (true, Some(GeometryValue::LineString { coordinates })) = (FLOWN.contains(&kind), f.geometry.as_ref().map(|g| &g.value)) {
            for p in coordinates {
                if out.last() != Some(&[p[1], p[0]]) {
                    out.push([p[1], p[0]]);
                }
            }
        }
    }
    out
}

/// Over terrain: each flown point's altitude above mean sea level and the ground's height under
/// it, in the order (and with the repeats left out) of [`flown_points`].
fn flown_heights(trajectory: &FeatureCollection) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut last: Option<[f64; 2]> = None;
    for f in &trajectory.features {
        let props = f.properties.as_ref();
        let kind = props.and_then(|p| p.get("kind")).and_then(Value::as_str).unwrap_or_default();
        if let (true, Some(GeometryValue::LineString { coordinates })) = (FLOWN.contains(&kind), f.geometry.as_ref().map(|g| &g.value)) {
            let ground = props.and_then(|p| p.get("ground_m")).and_then(Value::as_array).expect("a piece over terrain gives its ground");
            for (p, g) in coordinates.iter().zip(ground) {
                if last != Some([p[1], p[0]]) {
                    out.push((p[2], g.as_f64().unwrap()));
                    last = Some([p[1], p[0]]);
                }
            }
        }
    }
    out
}

fn sweeps(trajectory: &FeatureCollection) -> usize {
    trajectory.features.iter().filter(|f| f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str) == Some("sweep")).count()
}

/// The photos the plan shows (its MultiPoint of kind `photos`).
fn photo_count(trajectory: &FeatureCollection) -> usize {
    trajectory
        .features
        .iter()
        .filter(|f| f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str) == Some("photos"))
        .filter_map(|f| match &f.geometry.as_ref()?.value {
            GeometryValue::MultiPoint { coordinates } => Some(coordinates.len()),
            _ => None,
        })
        .sum()
}

fn flown_pieces(trajectory: &FeatureCollection) -> usize {
    trajectory.features.iter().filter(|f| f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str).is_some_and(|k| FLOWN.contains(&k))).count()
}

async fn download(app: &TestApp, plan: &str, query: &str) -> (u16, String, String, Vec<u8>) {
    let r = app.client.get(app.url(&format!("/api/v1/plans/{plan}/trajectory?{query}"))).send().await.unwrap();
    let header = |h: &str| r.headers().get(h).map(|v| v.to_str().unwrap().to_owned()).unwrap_or_default();
    let (status, media, disposition) = (r.status().as_u16(), header("content-type"), header("content-disposition"));
    (status, media, disposition, r.bytes().await.unwrap().to_vec())
}

async fn upload(app: &TestApp, query: &str, bytes: Vec<u8>) -> (u16, Value) {
    let r = app.client.post(app.url(&format!("/api/v1/missions/import?{query}"))).body(bytes).send().await.unwrap();
    (r.status().as_u16(), r.json().await.unwrap_or(Value::Null))
}

async fn mission_count(app: &TestApp) -> i64 {
    app.get("/api/v1/missions?fields=summary").await.1["total"].as_i64().unwrap()
}

/// A succeeded plan of `mission`, with its id and trajectory.
async fn planned(app: &TestApp, mission: &Value, params: &Value) -> (String, FeatureCollection) {
    let id = app.create_mission(mission).await;
    let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), params).await;
    assert_eq!(status, 202, "{plan}");
    let plan_id = plan["id"].as_str().unwrap().to_owned();
    let done = app.wait_finished(&plan_id).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    let (_, _, _, bytes) = download(app, &plan_id, "format=geojson").await;
    (plan_id, serde_json::from_slice(&bytes).unwrap())
}

fn field_mission() -> Value {
    let mut m = common::mission_body("random-fields/h04_00.json");
    m["name"] = json!("North field (h04)");
    m["home"] = m["area"]["coordinates"][0][0].clone();
    m
}

const CAMERA_PLAN: &str = r#"{"planner": "boustrophedon", "camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 80}"#;

#[tokio::test]
async fn every_format_downloads_reads_back_and_passes_independent_readers() {
    let app = TestApp::spawn().await;
    let mission = field_mission();
    let params: Value = serde_json::from_str(CAMERA_PLAN).unwrap();
    let (plan, trajectory) = planned(&app, &mission, &params).await;
    let dir = temp_dir();
    let expected = canonical(&mission);
    let (fields, zones) = (polygons(Some(&expected.area)), polygons(expected.no_fly_zones.as_ref()));
    let holes: usize = fields.iter().map(|f| f.len() - 1).sum();
    let spacing = planner_spacing(&app, &plan).await;
    let mut manifest = Vec::new();
    for (format, media, extension) in [
        ("geojson", "application/geo+json", ".geojson"),
        ("plan", "application/json", ".plan"),
        ("waypoints", "text/plain; charset=utf-8", ".waypoints"),
        ("kml", "application/vnd.google-earth.kml+xml", ".kml"),
        ("kmz", "application/vnd.google-earth.kmz", ".kmz"),
        ("wpml", "application/vnd.google-earth.kmz", ".kmz"),
        ("isoxml", "application/zip", "-taskdata.zip"),
    ] {
        // DJI WPML in one mission, whatever the controller's limit (missions are tested on their own)
        let limit = if format == "wpml" { "&max_waypoints=65535" } else { "" };
        let (status, got_media, disposition, bytes) = download(&app, &plan, &format!("format={format}{limit}")).await;
        assert_eq!(status, 200, "{format}: {}", String::from_utf8_lossy(&bytes));
        assert_eq!(got_media, media, "{format}");
        assert_eq!(disposition, format!("attachment; filename=\"North_field__h04{extension}\""), "{format}");
        let file = format!("{format}{extension}");
        std::fs::write(dir.join(&file), &bytes).unwrap();
        manifest.push(json!({
            "file": file, "format": format, "waypoints": flown_points(&trajectory), "pieces": flown_pieces(&trajectory),
            "fields": fields.len(), "holes": holes, "zones": zones.len(), "photo_lines": sweeps(&trajectory), "photos": photo_count(&trajectory),
            "lines": sweeps(&trajectory), "swath_width_mm": (spacing * 1000.0).round(),
        }));
        // back through the service: fields, holes and zones come back within 1 cm
        if ["kml", "kmz", "isoxml", "plan"].contains(&format) {
            let (status, imported) = upload(&app, &format!("format={format}"), bytes).await;
            assert_eq!(status, 201, "{format}: {imported}");
            if format == "plan" {
                assert_fence_holds(&polygons(Some(&imported["area"])), &fields, format);
            } else {
                assert_same_polygons(&polygons(Some(&imported["area"])), &fields, true, format);
            }
            assert_same_polygons(&polygons(imported.get("no_fly_zones")), &zones, true, format);
            if format != "isoxml" {
                let home = |v: &Value| serde_json::from_value::<[f64; 2]>(v.clone()).unwrap();
                assert!(close(home(&imported["home"]), home(&mission["home"])), "{format}: home at {}", imported["home"]);
            }
        }
    }
    // the mission document itself, as a GeoJSON file
    let (status, imported) = upload(&app, "format=geojson", mission.to_string().into_bytes()).await;
    assert_eq!(status, 201, "{imported}");
    assert_same_polygons(&polygons(Some(&imported["area"])), &fields, true, "geojson");
    assert_same_polygons(&polygons(imported.get("no_fly_zones")), &zones, true, "geojson");
    std::fs::write(dir.join("manifest.json"), json!({"files": manifest}).to_string()).unwrap();
    run(Command::new(python()).arg(interop_dir().join("check_exports.py")).arg(&dir));
    run(Command::new("node").arg(interop_dir().join("check_isoxml.mjs")).arg(&dir));
    app.stop().await;
}

/// A plan over the hills' elevation model, written in the AMSL frame and in the terrain frame, and
/// read by the same independent readers: every waypoint at its planned height, home on the ground.
#[tokio::test]
async fn a_plan_over_terrain_passes_the_independent_readers_in_both_frames() {
    let app = TestApp::spawn().await;
    let f = common::fixture("terrain/hills-11.json");
    let mission = app.create_mission(&json!({"name": "Hills", "area": f["area"], "home": f["home"]})).await;
    let model = std::fs::read(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/terrain/hills-11.tif")).unwrap();
    let r = app.client.put(app.url(&format!("/api/v1/missions/{mission}/terrain"))).header("content-type", "image/tiff").body(model).send().await.unwrap();
    assert_eq!(r.status(), 200);
    let params = json!({"planner": "boustrophedon", "camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 80, "altitude_reference": "terrain", "vehicle": {"profile": "generic_multirotor"}});
    let (status, plan) = app.post(&format!("/api/v1/missions/{mission}/plans"), &params).await;
    assert_eq!(status, 202, "{plan}");
    let plan = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(plan["status"], "succeeded", "{plan}");
    let id = plan["id"].as_str().unwrap();
    let (_, _, _, bytes) = download(&app, id, "format=geojson").await;
    let trajectory: FeatureCollection = serde_json::from_slice(&bytes).unwrap();
    let heights = flown_heights(&trajectory);
    let home_alt = heights[0].1;
    let amsl: Vec<f64> = heights.iter().map(|h| h.0).collect();
    let above_ground: Vec<f64> = heights.iter().map(|h| h.0 - h.1).collect();
    let dir = temp_dir();
    let mut manifest = Vec::new();
    for (format, query, frame, expected) in [
        ("plan", "format=plan", 0, &amsl),
        ("plan", "format=plan&altitude_frame=terrain", 10, &above_ground),
        ("waypoints", "format=waypoints", 0, &amsl),
        ("waypoints", "format=waypoints&altitude_frame=terrain", 10, &above_ground),
        ("kml", "format=kml", 0, &amsl),
        ("wpml", "format=wpml&max_waypoints=65535", 0, &amsl),
    ] {
        let (status, _, _, bytes) = download(&app, id, query).await;
        assert_eq!(status, 200, "{query}: {}", String::from_utf8_lossy(&bytes));
        let file = format!("terrain-{frame}-{format}");
        std::fs::write(dir.join(&file), &bytes).unwrap();
        manifest.push(json!({
            "file": file, "format": format, "waypoints": flown_points(&trajectory), "pieces": flown_pieces(&trajectory),
            "fields": 1, "holes": 0, "zones": 0, "photo_lines": sweeps(&trajectory),
            "frame": frame, "heights": expected, "home_alt": home_alt,
        }));
    }
    std::fs::write(dir.join("manifest.json"), json!({"files": manifest}).to_string()).unwrap();
    run(Command::new(python()).arg(interop_dir().join("check_exports.py")).arg(&dir));
    app.stop().await;
}

/// An oblique plan: the MAVLink files, DJI's WPML and the GeoJSON name each pass's gimbal pitch
/// and heading where the independent readers find them, and the camera triggers take the
/// plan's photos.
#[tokio::test]
async fn an_oblique_plan_passes_the_independent_readers_with_its_camera_poses() {
    let app = TestApp::spawn().await;
    let mission = field_mission();
    let params = json!({
        "planner": "boustrophedon", "camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 100, "side_overlap": 0.3, "front_overlap": 0.5,
        "vehicle": {"profile": "iris", "battery_wh": 5000}, "pattern": "oblique", "oblique_pitch_deg": -50,
    });
    let (plan, trajectory) = planned(&app, &mission, &params).await;
    let stats = app.get(&format!("/api/v1/plans/{plan}")).await.1["stats"].clone();
    assert_eq!(stats["sorties"], 1, "{stats}");
    let passes: Vec<Value> =
        stats["passes"].as_array().expect("each pass's figures").iter().map(|p| json!({"pitch": p["gimbal_pitch_deg"], "heading": p["camera_heading_deg"]})).collect();
    assert_eq!(passes.len(), 5, "{stats}");
    let zones = polygons(canonical(&mission).no_fly_zones.as_ref()).len();
    let dir = temp_dir();
    let mut manifest = Vec::new();
    for (format, query, extension) in [
        ("geojson", "format=geojson", ".geojson"),
        ("plan", "format=plan", ".plan"),
        ("plan", "format=plan&firmware=px4", "-px4.plan"),
        ("waypoints", "format=waypoints", ".waypoints"),
        // one mission, whatever the controller's limit (missions are tested on their own)
        ("wpml", "format=wpml&max_waypoints=65535", ".kmz"),
    ] {
        let (status, _, _, bytes) = download(&app, &plan, query).await;
        assert_eq!(status, 200, "{query}: {}", String::from_utf8_lossy(&bytes));
        let file = format!("oblique-{format}{extension}");
        std::fs::write(dir.join(&file), &bytes).unwrap();
        let mut spec = json!({
            "file": file, "format": format, "waypoints": flown_points(&trajectory), "pieces": flown_pieces(&trajectory),
            "fields": 1, "holes": 0, "zones": zones, "photo_lines": sweeps(&trajectory), "photos": photo_count(&trajectory), "passes": passes,
        });
        // PX4 faces the heading its waypoints give (no CONDITION_YAW to count)
        if query.ends_with("px4") {
            spec["waypoint_headings"] = json!(passes.iter().filter_map(|p| p["heading"].as_f64()).collect::<Vec<_>>());
            spec["passes"] = json!(passes.iter().map(|p| json!({"pitch": p["pitch"], "heading": null})).collect::<Vec<_>>());
        }
        manifest.push(spec);
    }
    std::fs::write(dir.join("manifest.json"), json!({"files": manifest}).to_string()).unwrap();
    run(Command::new(python()).arg(interop_dir().join("check_exports.py")).arg(&dir));
    app.stop().await;
}

/// A flight longer than the controller loads: DJI WPML at its default (99 waypoints) and the
/// MAVLink files at `max_waypoints` 40 come as zips of missions, each read by the independent
/// readers, within the limit, each beginning where the last ended, together taking at least
/// the plan's photos.
#[tokio::test]
async fn a_flight_past_the_controllers_limit_comes_in_missions_within_it() {
    let app = TestApp::spawn().await;
    let mission = field_mission();
    let params = json!({"planner": "boustrophedon", "camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 60, "vehicle": {"profile": "iris", "battery_wh": 5000}});
    let (plan, trajectory) = planned(&app, &mission, &params).await;
    let dir = temp_dir();
    let mut manifest = Vec::new();
    for (format, query, limit) in [("wpml", "format=wpml", 99), ("plan", "format=plan&max_waypoints=40", 40), ("waypoints", "format=waypoints&max_waypoints=40", 40)] {
        let (status, media, disposition, bytes) = download(&app, &plan, query).await;
        assert_eq!(status, 200, "{query}: {}", String::from_utf8_lossy(&bytes));
        assert_eq!(media, "application/zip", "{query}: {disposition}");
        let parts = coverplan::planner::archive::unzip(&bytes).unwrap();
        assert!(parts.len() >= 2, "{query}: {} missions", parts.len());
        let mut files = Vec::new();
        for (k, (name, part)) in parts.iter().enumerate() {
            assert!(
                name.ends_with(&format!(
                    "-part-{}{}",
                    k + 1,
                    if format == "wpml" {
                        ".kmz"
                    } else if format == "plan" {
                        ".plan"
                    } else {
                        ".waypoints"
                    }
                )),
                "{name}"
            );
            let file = format!("limit-{format}-{}", k + 1);
            std::fs::write(dir.join(&file), part).unwrap();
            files.push(file);
        }
        manifest.push(json!({"parts": files, "format": format, "max_waypoints": limit, "photos": photo_count(&trajectory), "zones": polygons(canonical(&mission).no_fly_zones.as_ref()).len()}));
    }
    // a limit only for the files a controller loads, and one a mission can keep
    for (query, code) in [("format=geojson&max_waypoints=100", "format_not_applicable"), ("format=plan&max_waypoints=5", "parameter_out_of_range")] {
        let (status, _, _, body) = download(&app, &plan, query).await;
        let problem: Value = serde_json::from_slice(&body).unwrap();
        assert_eq!((status, problem["code"].as_str()), (422, Some(code)), "{query}: {problem}");
        assert_eq!(problem["pointer"], "/max_waypoints", "{problem}");
    }
    std::fs::write(dir.join("manifest.json"), json!({"files": [], "missions": manifest}).to_string()).unwrap();
    run(Command::new(python()).arg(interop_dir().join("check_exports.py")).arg(&dir));
    app.stop().await;
}

/// A corridor flown in hops between landing sites: each sortie's MAVLink file, read by the
/// independent readers, takes off from its own site and lands at the next; DJI's lands itself.
#[tokio::test]
async fn sorties_between_landing_sites_take_off_and_land_where_the_plan_does() {
    let app = TestApp::spawn().await;
    let line = json!([[5.0, 52.0], [5.03, 52.004], [5.06, 52.0]]);
    let mission =
        json!({"name": "Pipeline", "home": [4.9985, 51.9995], "area": {"type": "Feature", "properties": {"width_m": 60}, "geometry": {"type": "LineString", "coordinates": line}}});
    let sites = json!([[5.012, 52.0022], [5.024, 52.0027], [5.036, 52.0037], [5.048, 52.0024], [5.0605, 51.9996]]);
    let params = json!({"planner": "corridor", "camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 40, "side_overlap": 0.3, "vehicle": {"profile": "iris", "battery_wh": 40}, "landing_sites": sites});
    let (plan, trajectory) = planned(&app, &mission, &params).await;
    // each sortie's first and last point, [lat, lon]
    let mut ends: Vec<([f64; 2], [f64; 2])> = Vec::new();
    for f in &trajectory.features {
        let (Some(k), Some(GeometryValue::LineString { coordinates })) = (f.property("sortie").and_then(Value::as_u64), f.geometry.as_ref().map(|g| &g.value)) else { continue };
        let (first, last) = (coordinates[0].as_slice(), coordinates[coordinates.len() - 1].as_slice());
        if ends.len() < k as usize {
            ends.push(([first[1], first[0]], [last[1], last[0]]));
        }
        ends[k as usize - 1].1 = [last[1], last[0]];
    }
    assert!(ends.len() >= 2, "{} sorties", ends.len());
    let homes: Vec<[f64; 2]> = ends.iter().map(|e| e.0).collect();
    let landings: Vec<Option<[f64; 2]>> = ends.iter().map(|(from, to)| ((from[0] - to[0]).abs() + (from[1] - to[1]).abs() > 1e-7).then_some(*to)).collect();
    assert!(landings.iter().any(Option::is_some), "some sortie lands at a landing site");
    let dir = temp_dir();
    let mut sorties = Vec::new();
    for (format, query) in [("waypoints", "format=waypoints"), ("plan", "format=plan"), ("wpml", "format=wpml&max_waypoints=65535")] {
        let (status, _, _, bytes) = download(&app, &plan, query).await;
        assert_eq!(status, 200, "{query}: {}", String::from_utf8_lossy(&bytes));
        let mut parts = Vec::new();
        for (k, (_, part)) in coverplan::planner::archive::unzip(&bytes).unwrap().iter().enumerate() {
            let file = format!("hops-{format}-{}", k + 1);
            std::fs::write(dir.join(&file), part).unwrap();
            parts.push(file);
        }
        sorties.push(json!({"parts": parts, "format": format, "homes": homes, "landings": landings}));
    }
    std::fs::write(dir.join("manifest.json"), json!({"files": [], "sorties": sorties}).to_string()).unwrap();
    run(Command::new(python()).arg(interop_dir().join("check_exports.py")).arg(&dir));
    app.stop().await;
}

async fn planner_spacing(app: &TestApp, plan: &str) -> f64 {
    app.get(&format!("/api/v1/plans/{plan}")).await.1["stats"]["line_spacing_m"].as_f64().unwrap()
}

#[tokio::test]
async fn fields_come_back_where_they_were_zurich_and_the_antimeridian() {
    let app = TestApp::spawn().await;
    // a vertex exactly at 8.548° E, 47.376° N, and a field 1 km west of the antimeridian
    let zurich = json!({"name": "Zurich", "area": {"type": "Polygon", "coordinates": [[[8.548, 47.376], [8.552, 47.376], [8.552, 47.378], [8.548, 47.378], [8.548, 47.376]]]}});
    let fiji =
        json!({"name": "Taveuni", "area": {"type": "Polygon", "coordinates": [[[179.984, -16.80], [179.990, -16.80], [179.990, -16.795], [179.984, -16.795], [179.984, -16.80]]]}});
    for mission in [zurich, fiji] {
        let (plan, _) = planned(&app, &mission, &json!({"line_spacing_m": 30})).await;
        let expected = polygons(Some(&canonical(&mission).area));
        for format in ["kml", "kmz", "isoxml", "plan"] {
            let (_, _, _, bytes) = download(&app, &plan, &format!("format={format}")).await;
            let (status, imported) = upload(&app, "", bytes).await;
            assert_eq!(status, 201, "{format} (found from the content): {imported}");
            let what = format!("{} {format}", mission["name"]);
            if format == "plan" {
                assert_fence_holds(&polygons(Some(&imported["area"])), &expected, &what);
            } else {
                assert_same_polygons(&polygons(Some(&imported["area"])), &expected, true, &what);
            }
        }
    }
    app.stop().await;
}

#[tokio::test]
async fn exports_say_what_is_wrong() {
    let app = TestApp::spawn_with(common::fresh_db_url().await, |c| c.queue.start_delay = std::time::Duration::from_secs(60)).await;
    let id = app.create_mission(&field_mission()).await;
    let (_, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"line_spacing_m": 20})).await;
    let plan = plan["id"].as_str().unwrap();
    let (status, _, _, body) = download(&app, plan, "format=gpx").await;
    let problem: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!((status, problem["code"].as_str()), (400, Some("unknown_format")));
    for format in export::format_ids() {
        assert!(problem["detail"].as_str().unwrap().contains(format), "{problem}");
    }
    for (query, code) in [("format=plan&firmware=inav", "unknown_firmware"), ("format=plan&altitude_m=high", "invalid_query")] {
        let (status, media, _, body) = download(&app, plan, query).await;
        let problem: Value = serde_json::from_slice(&body).unwrap();
        assert_eq!((status, media.as_str(), problem["code"].as_str()), (400, "application/problem+json", Some(code)), "{query}: {problem}");
    }
    let (status, _, _, body) = download(&app, plan, "format=plan").await;
    let problem: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!((status, problem["code"].as_str()), (409, Some("trajectory_not_available")), "{problem}");
    app.stop().await;
}

#[tokio::test]
async fn a_plan_of_several_sorties_is_a_zip_of_flights() {
    let app = TestApp::spawn().await;
    let mut mission = common::mission_body("random-fields/h00_01.json");
    mission["home"] = mission["area"]["coordinates"][0][0].clone();
    let params = json!({"line_spacing_m": 10, "vehicle": {"profile": "iris", "battery_wh": 15}});
    let (plan, trajectory) = planned(&app, &mission, &params).await;
    let sorties = trajectory.features.iter().filter_map(|f| f.properties.as_ref()?.get("sortie")?.as_u64()).max().unwrap();
    assert!(sorties > 1, "the battery is meant to need several sorties");
    let points = flown_points(&trajectory);
    for (format, extension) in [("plan", ".plan"), ("waypoints", ".waypoints"), ("wpml", ".kmz")] {
        let (status, media, disposition, bytes) = download(&app, &plan, &format!("format={format}&firmware=px4")).await;
        assert_eq!((status, media.as_str()), (200, "application/zip"), "{format}");
        assert!(disposition.contains(&format!("-{format}-sorties.zip")), "{disposition}");
        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        let names: Vec<String> = zip.file_names().map(|n| n.unwrap().into_owned()).collect();
        assert_eq!(names.len() as u64, sorties, "{names:?}");
        assert!(names.iter().all(|n| n.ends_with(extension) && n.contains("-sortie-")), "{names:?}");
        if format == "waypoints" {
            // every sortie's waypoints, one after the other, are the trajectory's points
            let mut visited = Vec::new();
            for k in 1..=sorties {
                let name = names.iter().find(|n| n.contains(&format!("-sortie-{k}."))).unwrap().clone();
                let mut text = String::new();
                zip.by_name(&name).unwrap().read_to_string(&mut text).unwrap();
                visited.extend(wpl_waypoints(&text));
            }
            visited.dedup_by(|a, b| close(*a, *b));
            assert_eq!(visited.len(), points.len());
            assert!(visited.iter().zip(&points).all(|(a, b)| close(*a, *b)));
        }
    }
    app.stop().await;
}

/// A fleet's plan exports as a zip of one flight per drone, each the drone's own waypoints;
/// the GeoJSON trajectory stays one document whose features say their drone.
#[tokio::test]
async fn a_fleet_plan_is_a_zip_of_one_flight_per_drone() {
    let app = TestApp::spawn().await;
    let mission = field_mission();
    let params = json!({"line_spacing_m": 20, "vehicles": 3, "altitude_m": 60, "altitude_separation_m": 10});
    let (plan, trajectory) = planned(&app, &mission, &params).await;
    let drone = |f: &geojson::Feature| f.properties.as_ref()?.get("vehicle")?.as_u64();
    assert!(
        trajectory
            .features
            .iter()
            .filter(|f| flown_pieces(&FeatureCollection { bbox: None, features: vec![(*f).clone()], foreign_members: None }) == 1)
            .all(|f| drone(f).is_some_and(|k| k < 3))
    );
    for (format, extension) in [("waypoints", ".waypoints"), ("plan", ".plan"), ("kml", ".kml")] {
        let (status, media, disposition, bytes) = download(&app, &plan, &format!("format={format}")).await;
        assert_eq!((status, media.as_str()), (200, "application/zip"), "{format}");
        assert!(disposition.contains(&format!("-{format}-fleet.zip")), "{disposition}");
        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        let mut names: Vec<String> = zip.file_names().map(|n| n.unwrap().into_owned()).collect();
        names.sort();
        let expected: Vec<String> = (1..=3).map(|k| format!("North_field__h04-drone-{k}{extension}")).collect();
        assert_eq!(names, expected, "{format}");
        if format == "waypoints" {
            for k in 0..3u64 {
                let own = FeatureCollection { bbox: None, features: trajectory.features.iter().filter(|f| drone(f) == Some(k)).cloned().collect(), foreign_members: None };
                let mut text = String::new();
                zip.by_name(&expected[k as usize]).unwrap().read_to_string(&mut text).unwrap();
                let mut visited = wpl_waypoints(&text);
                visited.dedup_by(|a, b| close(*a, *b));
                let points = flown_points(&own);
                assert_eq!(visited.len(), points.len(), "drone {k}");
                assert!(visited.iter().zip(&points).all(|(a, b)| close(*a, *b)), "drone {k}");
            }
        }
    }
    app.stop().await;
}

fn close(a: [f64; 2], b: [f64; 2]) -> bool {
    (a[0] - b[0]).abs() <= ONE_CM_DEG && (a[1] - b[1]).abs() <= ONE_CM_DEG
}

/// Whether `p` lies on the segment from `a` to `b` (`[lat, lon]`, within about a centimetre).
fn on_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let (d, w) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let length2 = d[0] * d[0] + d[1] * d[1];
    let t = if length2 > 0.0 { (w[0] * d[0] + w[1] * d[1]) / length2 } else { 0.0 };
    (-1e-9..=1.0 + 1e-9).contains(&t) && (w[0] * d[1] - w[1] * d[0]).abs() / length2.sqrt().max(1e-12) <= ONE_CM_DEG
}

/// How many photos an autopilot triggering by distance takes flying a QGC WPL 110 file's legs
/// exactly (the planner's follower, as a multirotor): the camera runs on sweeps only, so a fixed
/// wing's turns change nothing.
fn autopilot_photo_count(text: &str, firmware: Firmware) -> usize {
    let items = export::wpl::read(text).unwrap();
    let spec = FollowerSpec { kind: VehicleKind::Multirotor, firmware, cruise_speed_mps: 8.0, turn_radius_m: 0.0, acceleration_mps2: 2.0, climb_mps: 2.0, descent_mps: 1.5 };
    follower::fly(&items, &spec).photos.len()
}

/// `[lat, lon]` of the NAV_WAYPOINT items of a QGC WPL 110 file, home (item 0) left out.
fn wpl_waypoints(text: &str) -> Vec<[f64; 2]> {
    export::wpl::read(text).unwrap().iter().filter(|i| i.command == 16).filter_map(|i| i.position).map(|p| [p[0], p[1]]).collect()
}

#[tokio::test]
async fn shapefiles_from_pyshp_import_in_wgs84_and_utm_and_bad_ones_are_refused() {
    let app = TestApp::spawn().await;
    let dir = temp_dir();
    run(Command::new(python()).arg(interop_dir().join("make_shapefiles.py")).arg(&dir));
    let expected: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("expected.json")).unwrap()).unwrap();
    let ring = |key: &str| -> Ring { serde_json::from_value(expected[key].clone()).unwrap() };
    let mut field = ring("field");
    let mut hole = ring("hole");
    hole.reverse(); // holes come back clockwise
    for file in ["field-wgs84.zip", "field-utm.zip"] {
        let (status, imported) = upload(&app, "format=shapefile", std::fs::read(dir.join(file)).unwrap()).await;
        assert_eq!(status, 201, "{file}: {imported}");
        assert_same_polygons(&polygons(Some(&imported["area"])), &[vec![field.clone(), hole.clone()]], true, file);
        assert_same_polygons(&polygons(imported.get("no_fly_zones")), &[vec![ring("zone")]], true, file);
    }
    field.reverse();
    let before = mission_count(&app).await;
    for (file, code, pointer) in [
        ("no-prj.zip", "missing_file_part", "/no-prj.prj"),
        ("wrong-winding.zip", "wrong_winding", "/wrong-winding.shp/records/0"),
        ("other-crs.zip", "unsupported_projection", "/other-crs.prj"),
    ] {
        let (status, problem) = upload(&app, "format=shapefile", std::fs::read(dir.join(file)).unwrap()).await;
        assert_eq!((status, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some(code), Some(pointer)), "{file}: {problem}");
    }
    assert_eq!(mission_count(&app).await, before, "nothing is stored on refusal");
    app.stop().await;
}

fn deflated(files: &[(&str, Vec<u8>)]) -> Vec<u8> {
    let mut w = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    for (name, content) in files {
        w.start_file(*name, zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated)).unwrap();
        std::io::Write::write_all(&mut w, content).unwrap();
    }
    w.finish().unwrap().into_inner()
}

#[tokio::test]
async fn bad_files_get_a_problem_naming_the_part_and_nothing_is_stored() {
    let app = TestApp::spawn().await;
    let square = |a: f64, b: f64| format!("{a},{b} {},{b} {},{} {a},{} {a},{b}", a + 0.01, a + 0.01, b + 0.01, b + 0.01);
    let kml = |body: &str| format!(r#"<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document>{body}</Document></kml>"#);
    let placemark = |coords: &str| {
        format!("<Placemark><name>f</name><Polygon><outerBoundaryIs><LinearRing><coordinates>{coords}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>")
    };
    let xxe = r#"<?xml version="1.0"?><!DOCTYPE kml [<!ENTITY x SYSTEM "file:///etc/passwd">]><kml><Document><name>&x;</name></Document></kml>"#;
    let billion = r#"<?xml version="1.0"?><!DOCTYPE d [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]><ISO11783_TaskData>&b;</ISO11783_TaskData>"#;
    let bomb = deflated(&[("doc.kml", vec![b' '; 70 * 1024 * 1024])]);
    let before = mission_count(&app).await;
    let cases: Vec<(&str, Vec<u8>, u16, &str, &str)> = vec![
        ("format=kmz", b"not a zip at all".to_vec(), 422, "invalid_zip", "/"),
        ("format=kmz", bomb, 422, "archive_too_large", "/doc.kml"),
        ("format=kml", xxe.as_bytes().to_vec(), 422, "xml_entities_refused", "/doc.kml"),
        ("format=isoxml", billion.as_bytes().to_vec(), 422, "xml_entities_refused", "/TASKDATA.XML"),
        ("format=kml", kml(&placemark(&square(47.37, 8.54))).into_bytes(), 201, "", ""),
        // latitude 100 with longitudes within ±90: [lat, lon] given as [lon, lat]
        ("format=kml", kml(&placemark("47.37,100 47.38,100 47.38,100.01 47.37,100")).into_bytes(), 422, "coordinates_look_swapped", "/doc.kml/Placemark[f]"),
        ("format=kml", kml("<Placemark><name>p</name><Point><coordinates>8.5,47.3</coordinates></Point></Placemark>").into_bytes(), 422, "empty_geometry", "/"),
        ("format=kml", kml(&placemark("8.5,47.3 8.6,47.3")).into_bytes(), 422, "empty_geometry", "/doc.kml/Placemark[f]"),
        ("format=gpx", b"<gpx/>".to_vec(), 400, "unknown_format", "/format"),
        ("", b"\x00\x01binary".to_vec(), 422, "unknown_format", "/format"),
        (
            "format=plan",
            br#"{"fileType": "Plan", "mission": {"items": []}, "geoFence": {"polygons": [{"inclusion": false, "polygon": [[47.3, 8.5], [47.31, 8.5]]}]}}"#.to_vec(),
            422,
            "empty_geometry",
            "/geoFence/polygons/0/polygon",
        ),
        ("format=isoxml", deflated(&[("TASKDATA/OTHER.XML", b"<x/>".to_vec())]), 422, "missing_file_part", "/TASKDATA/TASKDATA.XML"),
    ];
    for (query, bytes, status, code, pointer) in cases {
        let (got, problem) = upload(&app, query, bytes).await;
        assert_eq!(got, status, "{query}: {problem}");
        if status == 201 {
            assert_eq!(problem["warnings"], json!([]), "{problem}");
            continue;
        }
        assert_eq!((problem["code"].as_str(), problem["pointer"].as_str()), (Some(code), Some(pointer)), "{query}: {problem}");
    }
    assert_eq!(mission_count(&app).await, before + 1, "only the good file made a mission");
    app.stop().await;
}

#[tokio::test]
async fn imports_keep_zones_and_say_what_they_dropped() {
    let app = TestApp::spawn().await;
    let ring = |a: f64, b: f64, d: f64| format!("{a},{b} {},{b} {},{} {a},{} {a},{b}", a + d, a + d, b + d, b + d);
    let doc = format!(
        r#"<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document>
        <Placemark><name>Wheat</name><Polygon><outerBoundaryIs><LinearRing><coordinates>{}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>
        <Placemark><name>Pond</name><Polygon><outerBoundaryIs><LinearRing><coordinates>{}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>
        <Placemark><name>No-fly: mast</name><Polygon><outerBoundaryIs><LinearRing><coordinates>{}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>
        <Placemark><name>Barley</name><Polygon><outerBoundaryIs><LinearRing><coordinates>{}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>
        <Placemark><name>Home</name><Point><coordinates>8.5401,47.3701</coordinates></Point></Placemark>
        <Placemark><name>Track</name><LineString><coordinates>8.54,47.37 8.55,47.38</coordinates></LineString></Placemark>
        </Document></kml>"#,
        ring(8.54, 47.37, 0.01),
        ring(8.542, 47.372, 0.001),
        ring(8.546, 47.376, 0.001),
        ring(8.56, 47.37, 0.005)
    );
    let (status, m) = upload(&app, "name=Farm%20A", doc.into_bytes()).await;
    assert_eq!(status, 201, "{m}");
    assert_eq!(m["name"], "Farm A");
    let area = polygons(Some(&m["area"]));
    assert_eq!(area.len(), 2, "two fields: {m}");
    assert_eq!(area.iter().map(Vec::len).collect::<Vec<_>>(), vec![2, 1], "the pond is a hole of the wheat field: {m}");
    assert_eq!(polygons(m.get("no_fly_zones")).len(), 1, "{m}");
    assert_eq!(m["home"], json!([8.5401, 47.3701]));
    assert!(m["warnings"][0].as_str().unwrap().contains("1 line strings were dropped"), "{m}");
    // the mission is stored and can be planned like any other
    let (status, stored) = app.get(&format!("/api/v1/missions/{}", m["id"].as_str().unwrap())).await;
    assert_eq!((status, &stored["area"]), (200, &m["area"]));
    app.stop().await;
}

/// An imported mission is named by the file: the KML document's name, else its first field's.
#[tokio::test]
async fn kml_imports_are_named_by_the_file() {
    let app = TestApp::spawn().await;
    let square = "8.54,47.37 8.55,47.37 8.55,47.38 8.54,47.38 8.54,47.37";
    let field = |name: &str| {
        format!("<Placemark><name>{name}</name><Polygon><outerBoundaryIs><LinearRing><coordinates>{square}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>")
    };
    let doc = |body: String| format!(r#"<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document>{body}</Document></kml>"#).into_bytes();
    for (body, expected) in [
        (format!("<name>Hoeve De Linde</name>{}", field("Wheat")), "Hoeve De Linde"),
        (field("North parcel"), "North parcel"),
        (format!("<Placemark><name>Home</name><Point><coordinates>8.545,47.375</coordinates></Point></Placemark>{}", field("  ")), "Imported field"),
    ] {
        let (status, m) = upload(&app, "format=kml", doc(body.clone())).await;
        assert_eq!((status, m["name"].as_str()), (201, Some(expected)), "{body}: {m}");
    }
    app.stop().await;
}

/// The property: for random fields, vehicles and cameras, every format writes (DJI's refuses
/// fixed wings, saying so), the flight files visit the trajectory's points in its order (all of
/// them for multirotors; for fixed wings every line end, and each arc by the corners round it),
/// and the ISOXML reads back to the same fields.
fn check_every_format(file: &str, fixed_wing: bool, camera: bool) -> Result<(), TestCaseError> {
    let fixture = common::fixture(&format!("random-fields/{file}"));
    let mission = MissionGeometry { no_fly_zones: fixture.get("no_fly_zones"), ..MissionGeometry::area(&fixture["area"]) };
    let mut params: PlanParams = serde_json::from_value(json!({"planner": "boustrophedon", "vehicle": {"kind": if fixed_wing { "fixed_wing" } else { "multirotor" }}})).unwrap();
    if camera {
        params.camera = serde_json::from_value(json!({"preset": "dji_mavic3_enterprise"})).unwrap();
        params.altitude_m = Some(100.0);
    } else {
        params.line_spacing_m = Some(40.0);
    }
    let mut profiles = planner::vehicle::builtin_profiles();
    profiles.iter_mut().for_each(|v| v.battery.energy_wh = 1e5);
    let out = planner::plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).map_err(|e| TestCaseError::fail(format!("{file}: {e}")))?;
    let request = ExportRequest {
        name: file,
        mission: mission.clone(),
        params: &params,
        profiles: &profiles,
        trajectory: &out.trajectory,
        options: ExportOptions { firmware: Firmware::Px4, altitude_m: None, ..ExportOptions::default() },
    };
    let points = flown_points(&out.trajectory);
    let turn_radius = params.resolve(&profiles).map_err(|e| TestCaseError::fail(e.to_string()))?.vehicle.turn_radius_m;
    let ends: Vec<[f64; 2]> = out
        .trajectory
        .features
        .iter()
        .filter(|f| f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str) == Some("sweep"))
        .filter_map(|f| match &f.geometry.as_ref()?.value {
            GeometryValue::LineString { coordinates } => Some([coordinates[0].clone(), coordinates[coordinates.len() - 1].clone()]),
            _ => None,
        })
        .flatten()
        .map(|p| [p[1], p[0]])
        .collect();
    for format in export::format_ids() {
        let file_out = export::export(format, &request);
        if format == "wpml" && fixed_wing {
            prop_assert_eq!(file_out.unwrap_err().code, "format_not_applicable");
            continue;
        }
        let file_out = file_out.map_err(|e| TestCaseError::fail(format!("{format}: {e}")))?;
        prop_assert!(!file_out.bytes.is_empty());
        if format == "waypoints" {
            let visited = wpl_waypoints(std::str::from_utf8(&file_out.bytes).unwrap());
            // in order, a subsequence of the trajectory's points, and between two of them the
            // places on the leg where a line's photos start and stop
            let mut next = 0;
            let mut on_trajectory = 0;
            for v in &visited {
                match points[next..].iter().position(|p| close(*p, *v)) {
                    Some(found) => {
                        next += found;
                        on_trajectory += 1;
                    }
                    // a fixed wing's arcs are written as the corners round them, a corner per
                    // 90° at most: 0.41 of the radius off the arc (sec 45° - 1), measured up to
                    // 0.44 against the sampled trajectory; photo triggers lie on legs
                    None if fixed_wing => {
                        let metres = |p: [f64; 2]| [p[0] * 111_320.0, p[1] * 111_320.0 * v[0].to_radians().cos()];
                        let off = points
                            .windows(2)
                            .skip(next.saturating_sub(1))
                            .take(400)
                            .map(|w| {
                                let ([ax, ay], [bx, by], [px, py]) = (metres(w[0]), metres(w[1]), metres(*v));
                                let (dx, dy) = (bx - ax, by - ay);
                                let t = (((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy).max(1e-12)).clamp(0.0, 1.0);
                                (px - ax - t * dx).hypot(py - ay - t * dy)
                            })
                            .fold(f64::INFINITY, f64::min);
                        prop_assert!(off <= 0.5 * turn_radius, "{}: waypoint {:?} is {:.1} m off the trajectory", format, v, off);
                    }
                    None => prop_assert!(
                        next + 1 < points.len() && on_segment(*v, points[next], points[next + 1]),
                        "{}: waypoint {:?} is neither on the trajectory after point {} nor on the leg from it",
                        format,
                        v,
                        next
                    ),
                }
            }
            if fixed_wing {
                prop_assert!(ends.iter().all(|e| visited.iter().any(|v| close(*v, *e))), "every line end is a waypoint");
            } else {
                prop_assert_eq!(on_trajectory, points.len(), "a multirotor visits every point");
            }
            if camera {
                // the file triggers where the plan's photos are: an autopilot takes as many
                let taken = autopilot_photo_count(std::str::from_utf8(&file_out.bytes).unwrap(), Firmware::Px4);
                prop_assert_eq!(taken, photo_count(&out.trajectory), "{}: photos an autopilot takes against the plan's", file);
            }
            // the .plan holds the same waypoints
            let plan = export::export("plan", &request).unwrap();
            let plan: Value = serde_json::from_slice(&plan.bytes).unwrap();
            let in_plan: Vec<[f64; 2]> = plan["mission"]["items"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|i| i["command"] == 16)
                .map(|i| [i["params"][4].as_f64().unwrap(), i["params"][5].as_f64().unwrap()])
                .collect();
            prop_assert_eq!(in_plan.len(), visited.len());
            prop_assert!(in_plan.iter().zip(&visited).all(|(a, b)| close(*a, *b)));
        }
        if format == "isoxml" {
            let back = import::import(Some("isoxml"), &file_out.bytes).map_err(|e| TestCaseError::fail(format!("isoxml back: {e}")))?;
            let expected = canonical(&json!({"area": fixture["area"]}));
            prop_assert_eq!(polygons(Some(&back.area)).len(), polygons(Some(&expected.area)).len());
        }
    }
    Ok(())
}

fn random_fields() -> Vec<String> {
    let index = common::fixture("random-fields/index.json");
    index.as_array().unwrap().iter().map(|f| f["file"].as_str().unwrap().to_owned()).filter(|f| f.ends_with("_00.json") || f.ends_with("_01.json")).collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]
    #[test]
    fn any_plan_of_the_random_fields_exports_to_every_format(k in 0usize..64, fixed_wing in any::<bool>(), camera in any::<bool>()) {
        let files = random_fields();
        check_every_format(&files[k % files.len()], fixed_wing, camera)?;
    }
}

#[test]
fn the_readers_and_writers_are_pinned() {
    let requirements = std::fs::read_to_string(interop_dir().join("requirements.txt")).unwrap();
    for line in requirements.lines().filter(|l| !l.trim().is_empty() && !l.starts_with('#')) {
        assert!(line.contains("=="), "{line}: pin every Python package");
    }
    assert!(Path::new(&interop_dir().join("package-lock.json")).exists(), "npm packages are pinned by package-lock.json");
}
