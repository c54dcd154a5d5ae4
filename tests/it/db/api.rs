//! The HTTP API end to end, against the real server on port 0 with a fresh SQLite file.

use crate::common::{TestApp, fresh_db_url, mission_body};
use serde_json::{Value, json};

fn square(lon: f64, lat: f64, d: f64) -> Value {
    json!([[lon, lat], [lon + d, lat], [lon + d, lat + d], [lon, lat + d], [lon, lat]])
}

fn polygon(rings: Vec<Value>) -> Value {
    json!({"type": "Polygon", "coordinates": rings})
}

#[tokio::test]
async fn a_mission_is_planned_and_its_trajectory_is_geojson() {
    let app = TestApp::spawn().await;
    // the Estonian field's three holes are no-fly zones too: lines stop at their margin
    let id = app.create_mission(&mission_body("real-fields/ee-field-3-holes.json")).await;
    let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"planner": "boustrophedon", "line_spacing_m": 12})).await;
    assert_eq!(status, 202, "{plan}");
    assert_eq!(plan["status"], "queued");
    let plan = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(plan["status"], "succeeded", "{plan}");
    assert_eq!(plan["progress"], 1.0);
    assert_eq!(plan["mission_id"], id.as_str());
    let stats = &plan["stats"];
    for key in ["length_m", "duration_s", "energy_j", "coverage_ratio", "turns", "nfz_intrusion_m"] {
        assert!(stats[key].is_number(), "stats.{key} missing: {stats}");
    }
    assert!(stats["coverage_ratio"].as_f64().unwrap() >= 0.98, "{stats}");
    assert_eq!(stats["nfz_intrusion_m"], 0.0);

    let r = app.client.get(app.url(&format!("/api/v1/plans/{}/trajectory", plan["id"].as_str().unwrap()))).send().await.unwrap();
    assert_eq!(r.status(), 200);
    assert_eq!(r.headers()["content-type"], "application/geo+json");
    let fc: Value = r.json().await.unwrap();
    let parsed: geojson::GeoJson = serde_json::from_value(fc.clone()).expect("valid GeoJSON");
    assert!(matches!(parsed, geojson::GeoJson::FeatureCollection(_)));
    let all = fc["features"].as_array().unwrap();
    // the flown pieces, then what the plan leaves uncovered
    let (features, rest): (Vec<&Value>, Vec<&Value>) = all.iter().partition(|f| f["geometry"]["type"] == "LineString");
    for f in &rest {
        assert_eq!((f["properties"]["kind"].as_str(), f["geometry"]["type"].as_str()), (Some("uncovered"), Some("MultiPolygon")), "{f}");
        assert!(f["properties"]["area_m2"].as_f64().unwrap() > 0.0);
    }
    let mut total = 0.0;
    let mut last_end: Option<Value> = None;
    for f in &features {
        let p = &f["properties"];
        assert!(["sweep", "turn", "transit"].contains(&p["kind"].as_str().unwrap()), "{p}");
        assert_eq!(f["geometry"]["type"], "LineString");
        for key in ["length_m", "duration_s", "energy_j", "speed_mps"] {
            assert!(p[key].as_f64().unwrap() >= 0.0);
        }
        total += p["length_m"].as_f64().unwrap();
        let coords = f["geometry"]["coordinates"].as_array().unwrap();
        if let Some(end) = &last_end {
            assert_eq!(end, &coords[0], "pieces join in flight order");
        }
        last_end = coords.last().cloned();
    }
    assert!((total - stats["length_m"].as_f64().unwrap()).abs() < 0.01 * features.len() as f64);
    assert_eq!(features[0]["properties"]["kind"], "sweep");
    app.stop().await;
}

#[tokio::test]
async fn a_camera_gives_photos_and_altitude() {
    let app = TestApp::spawn().await;
    let mut body = mission_body("real-fields/nl-parcel-b.json");
    body["home"] = json!(body["area"]["coordinates"][0][0]);
    let id = app.create_mission(&body).await;
    let params = json!({
        "camera": {"sensor_width_mm": 13.2, "sensor_height_mm": 8.8, "focal_length_mm": 8.8, "image_width_px": 5472, "image_height_px": 3648},
        "gsd_cm": 2.0, "side_overlap": 0.7, "front_overlap": 0.8, "heading_deg": 45
    });
    let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &params).await;
    assert_eq!(status, 202, "{plan}");
    let plan = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(plan["status"], "succeeded", "{plan}");
    assert!((plan["stats"]["sweep_heading_deg"].as_f64().unwrap() - 45.0).abs() < 1e-6);
    let (_, fc) = app.get(&format!("/api/v1/plans/{}/trajectory", plan["id"].as_str().unwrap())).await;
    let features = fc["features"].as_array().unwrap();
    let photos = features.iter().find(|f| f["properties"]["kind"] == "photos").expect("photos");
    assert_eq!(photos["geometry"]["type"], "MultiPoint");
    assert!(photos["geometry"]["coordinates"].as_array().unwrap().len() > 10);
    // altitude from the ground sample distance: 2 cm/px × 8.8 mm × 5472 px / 13.2 mm = 72.96 m
    let first = &features[0]["geometry"]["coordinates"][0];
    assert!((first[2].as_f64().unwrap() - 72.96).abs() < 0.01, "{first}");
    // home is both start and end
    assert_eq!(features[0]["properties"]["kind"], "transit");
    assert_eq!(features[features.len() - 2]["properties"]["kind"], "transit");
    app.stop().await;
}

#[tokio::test]
async fn bad_input_gets_a_precise_problem_and_nothing_is_stored() {
    let app = TestApp::spawn().await;
    let good = square(5.0, 52.0, 0.01);
    let bowtie = json!([[5.0, 52.0], [5.01, 52.01], [5.01, 52.0], [5.0, 52.01], [5.0, 52.0]]);
    let mut many = Vec::new();
    for k in 0..20_001 {
        let a = k as f64 / 20_001.0 * std::f64::consts::TAU;
        many.push(json!([5.0 + 0.01 * a.cos(), 52.0 + 0.01 * a.sin()]));
    }
    many.push(many[0].clone());
    let cases: Vec<(Value, u16, &str, Option<&str>)> = vec![
        (
            json!({"name": "x", "area": {"type": "Polygon", "coordinates": [[[5.0, 52.0], [5.01, 52.0], [5.01, 52.01], [5.0, 52.01]]]}}),
            422,
            "ring_not_closed",
            Some("/area/coordinates/0"),
        ),
        (json!({"name": "x", "area": polygon(vec![json!([[5.0, 52.0], [5.01, 52.0], [5.0, 52.0]])])}), 422, "ring_too_short", Some("/area/coordinates/0")),
        (json!({"name": "x", "area": polygon(vec![bowtie])}), 422, "self_intersection", Some("/area/coordinates/0")),
        (json!({"name": "x", "area": polygon(vec![good.clone(), square(5.02, 52.0, 0.001)])}), 422, "hole_outside_shell", Some("/area/coordinates/1")),
        (
            json!({"name": "x", "area": polygon(vec![json!([[5.0, 52.0], [5.01, 52.0], [5.01, 91.0], [5.0, 52.0]])])}),
            422,
            "coordinates_look_swapped",
            Some("/area/coordinates/0/2"),
        ),
        (
            json!({"name": "x", "area": polygon(vec![json!([[5.0, 52.0], [190.0, 52.0], [5.01, 52.01], [5.0, 52.0]])])}),
            422,
            "coordinate_out_of_range",
            Some("/area/coordinates/0/1"),
        ),
        (json!({"name": "x", "area": polygon(vec![json!([[5.0, 52.0], ["5.01", 52.0], [5.01, 52.01], [5.0, 52.0]])])}), 422, "invalid_geojson", Some("/area")),
        (json!({"name": "x", "area": polygon(vec![json!([[5.0, 52.0], [5.01, 52.0], [5.02, 52.0], [5.0, 52.0]])])}), 422, "degenerate_ring", Some("/area/coordinates/0")),
        (json!({"name": "x", "area": polygon(vec![square(5.0, 52.0, 0.00001)])}), 422, "area_too_small", Some("/area")),
        (json!({"name": "x", "area": polygon(vec![json!([[5.0, 52.0], [5.01, 52.0], [5.0, 52.0], [5.0, 52.0]])])}), 422, "degenerate_ring", Some("/area/coordinates/0")),
        (json!({"name": "x", "area": polygon(vec![square(5.0, 52.0, 0.2)])}), 422, "area_too_large", Some("/area")),
        (json!({"name": "x", "area": polygon(vec![Value::Array(many)])}), 422, "too_many_vertices", Some("/area")),
        (json!({"name": "x", "area": {"type": "Point", "coordinates": [5.0, 52.0]}}), 422, "unsupported_geometry", Some("/area")),
        (json!({"name": "x", "area": polygon(vec![good.clone()]), "home": [5.0, 95.0]}), 422, "coordinates_look_swapped", Some("/home")),
        (json!({"name": "", "area": polygon(vec![good.clone()])}), 422, "invalid_name", Some("/name")),
        (json!({"area": polygon(vec![good.clone()])}), 422, "invalid_body", None),
        (json!({"name": "x", "area": polygon(vec![good.clone()]), "colour": "red"}), 422, "invalid_body", None),
        (json!({"name": "x", "area": polygon(vec![good.clone()]), "home": "here"}), 422, "invalid_body", Some("/home")),
    ];
    for (body, status, code, pointer) in cases {
        let (s, problem) = app.post("/api/v1/missions", &body).await;
        assert_eq!((s, problem["code"].as_str().unwrap_or_default()), (status, code), "{problem}");
        assert_eq!(problem["status"], status);
        assert_eq!(problem["type"], format!("/problems/{code}"));
        assert!(problem["title"].is_string() && problem["detail"].as_str().unwrap().len() > 5);
        if let Some(p) = pointer {
            assert_eq!(problem["pointer"], p, "{problem}");
        }
    }
    // malformed JSON, NaN, wrong media type, oversized body
    let raw = |body: &'static str, ctype: &'static str| app.client.post(app.url("/api/v1/missions")).header("content-type", ctype).body(body).send();
    for (body, ctype, status) in [
        ("{\"name\": ", "application/json", 400),
        ("{\"name\": \"x\", \"area\": {\"type\": \"Polygon\", \"coordinates\": [[[NaN, 1]]]}}", "application/json", 400),
        ("name=x", "application/x-www-form-urlencoded", 415),
    ] {
        let r = raw(body, ctype).await.unwrap();
        assert_eq!(r.status().as_u16(), status);
        assert_eq!(r.headers()["content-type"], "application/problem+json");
    }
    let huge = format!("{{\"name\": \"{}\"}}", "x".repeat(6 * 1024 * 1024));
    let r = app.client.post(app.url("/api/v1/missions")).header("content-type", "application/json").body(huge).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 413);
    let (_, page) = app.get("/api/v1/missions").await;
    assert_eq!(page["total"], 0, "a refused mission was stored");

    // plan parameters
    let id = app.create_mission(&json!({"name": "ok", "area": polygon(vec![good.clone()])})).await;
    let plan_cases: Vec<(Value, u16, &str, Option<&str>)> = vec![
        (json!({"planner": "teleport", "line_spacing_m": 20}), 422, "unknown_planner", Some("/planner")),
        (json!({"line_spacing_m": -5}), 422, "parameter_out_of_range", Some("/line_spacing_m")),
        (json!({"line_spacing_m": 0}), 422, "parameter_out_of_range", Some("/line_spacing_m")),
        (json!({"line_spacing_m": 1e6}), 422, "parameter_out_of_range", Some("/line_spacing_m")),
        (json!({}), 422, "spacing_missing", Some("/line_spacing_m")),
        (json!({"line_spacing_m": 20, "vehicle": {"cruise_speed_mps": 0}}), 422, "parameter_out_of_range", Some("/vehicle/cruise_speed_mps")),
        (json!({"line_spacing_m": 20, "vehicle": {"kind": "multirotor", "turn_radius_m": 1e7}}), 422, "parameter_out_of_range", Some("/vehicle/turn_radius_m")),
        (json!({"line_spacing_m": 20, "vehicle": {"kind": "submarine"}}), 422, "invalid_body", Some("/vehicle/kind")),
        (json!({"line_spacing_m": 20, "vehicle": {"profile": "nope"}}), 422, "unknown_vehicle_profile", Some("/vehicle/profile")),
        (json!({"line_spacing_m": 20, "heading_deg": "north"}), 422, "invalid_body", Some("/heading_deg")),
        (json!({"line_spacing_m": 20, "start": {"position": [5.0, 100.0]}}), 422, "parameter_out_of_range", Some("/start/position/1")),
        (json!({"line_spacing_m": 20, "side_overlap": 1.5}), 422, "parameter_out_of_range", Some("/side_overlap")),
        (json!({"camera": {"image_width_px": 4000, "image_height_px": 3000}, "altitude_m": 80}), 422, "camera_incomplete", Some("/camera")),
    ];
    for (body, status, code, pointer) in plan_cases {
        let (s, problem) = app.post(&format!("/api/v1/missions/{id}/plans"), &body).await;
        assert_eq!((s, problem["code"].as_str().unwrap_or_default()), (status, code), "{body} → {problem}");
        if let Some(p) = pointer {
            assert_eq!(problem["pointer"], p, "{problem}");
        }
    }
    let big = app.create_mission(&json!({"name": "big", "area": polygon(vec![square(5.0, 52.0, 0.03)])})).await;
    let (s, problem) = app.post(&format!("/api/v1/missions/{big}/plans"), &json!({"line_spacing_m": 0.5})).await;
    assert_eq!((s, problem["code"].as_str().unwrap()), (422, "plan_too_long"));
    let (s, _) = app.post("/api/v1/missions/nope/plans", &json!({"line_spacing_m": 20})).await;
    assert_eq!(s, 404);
    let (_, plans) = app.get(&format!("/api/v1/missions/{id}/plans")).await;
    assert_eq!(plans, json!([]), "a refused plan was stored");
    for path in ["/api/v1/plans/nope", "/api/v1/plans/nope/trajectory", "/api/v1/missions/nope", "/api/v1/nothing"] {
        let (s, problem) = app.get(path).await;
        assert_eq!(s, 404, "{path}");
        assert_eq!(problem["status"], 404);
    }
    let (s, problem) = app.get("/api/v1/missions?limit=1000").await;
    assert_eq!((s, problem["code"].as_str().unwrap()), (422, "parameter_out_of_range"));
    app.stop().await;
}

#[tokio::test]
async fn missions_can_be_listed_updated_and_deleted() {
    let app = TestApp::spawn().await;
    let mut ids = Vec::new();
    for k in 0..5 {
        ids.push(app.create_mission(&json!({"name": format!("field {k}"), "area": polygon(vec![square(5.0 + k as f64 * 0.1, 52.0, 0.01)])})).await);
    }
    let (_, page) = app.get("/api/v1/missions?limit=2&offset=1").await;
    assert_eq!(page["total"], 5);
    assert_eq!(page["items"].as_array().unwrap().len(), 2);
    assert!(page["items"][0]["area"].is_object());
    // the page's picker asks for names only: no geometry crosses the wire
    let (_, names) = app.get("/api/v1/missions?limit=2&offset=1&fields=summary").await;
    assert_eq!(names["total"], 5);
    let first = names["items"][0].as_object().unwrap();
    let mut keys: Vec<&str> = first.keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(keys, ["created_at", "id", "name", "updated_at"]);
    assert_eq!(first["id"], page["items"][0]["id"]);
    let r = app
        .client
        .put(app.url(&format!("/api/v1/missions/{}", ids[0])))
        .json(&json!({"name": "renamed", "area": polygon(vec![square(6.0, 52.0, 0.01)]), "home": [6.0, 52.0]}))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 200);
    let (_, m) = app.get(&format!("/api/v1/missions/{}", ids[0])).await;
    assert_eq!((m["name"].as_str().unwrap(), m["home"].clone()), ("renamed", json!([6.0, 52.0])));
    let r = app.client.put(app.url(&format!("/api/v1/missions/{}", ids[0]))).json(&json!({"name": "bad", "area": polygon(vec![square(6.0, 52.0, 0.3)])})).send().await.unwrap();
    assert_eq!(r.status(), 422);
    let (_, m) = app.get(&format!("/api/v1/missions/{}", ids[0])).await;
    assert_eq!(m["name"], "renamed", "a refused update changed the mission");
    let r = app.client.delete(app.url(&format!("/api/v1/missions/{}", ids[1]))).send().await.unwrap();
    assert_eq!(r.status(), 204);
    let (s, _) = app.get(&format!("/api/v1/missions/{}", ids[1])).await;
    assert_eq!(s, 404);
    app.stop().await;
}

#[tokio::test]
async fn concurrent_writes_never_fail_with_a_locked_database() {
    let app = TestApp::spawn().await;
    let body = json!({"name": "same", "area": polygon(vec![square(5.0, 52.0, 0.005)])});
    let id = app.create_mission(&body).await;
    let mut tasks = Vec::new();
    for k in 0..40 {
        let (client, base, body, id) = (app.client.clone(), app.base.clone(), body.clone(), id.clone());
        tasks.push(tokio::spawn(async move {
            let r = if k % 2 == 0 {
                client.post(format!("{base}/api/v1/missions")).json(&body).send().await.unwrap()
            } else {
                client.post(format!("{base}/api/v1/missions/{id}/plans")).json(&json!({"line_spacing_m": 25})).send().await.unwrap()
            };
            r.status().as_u16()
        }));
    }
    for t in tasks {
        let s = t.await.unwrap();
        assert!(s == 201 || s == 202, "status {s}");
    }
    let (_, plans) = app.get(&format!("/api/v1/missions/{id}/plans")).await;
    for p in plans.as_array().unwrap() {
        let done = app.wait_finished(p["id"].as_str().unwrap()).await;
        assert_eq!(done["status"], "succeeded", "{done}");
    }
    app.stop().await;
}

#[tokio::test]
async fn plans_survive_a_restart() {
    let db = fresh_db_url().await;
    let app = TestApp::spawn_with(db.clone(), |_| {}).await;
    let id = app.create_mission(&mission_body("real-fields/nl-parcel-17ha.json")).await;
    let (_, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"line_spacing_m": 15})).await;
    let plan_id = plan["id"].as_str().unwrap().to_owned();
    let before = app.wait_finished(&plan_id).await;
    let (_, trajectory_before) = app.get(&format!("/api/v1/plans/{plan_id}/trajectory")).await;
    app.stop().await;

    let app = TestApp::spawn_with(db, |_| {}).await;
    let (s, m) = app.get(&format!("/api/v1/missions/{id}")).await;
    assert_eq!((s, m["name"].as_str().unwrap()), (200, "nl-parcel-17ha"));
    let (_, after) = app.get(&format!("/api/v1/plans/{plan_id}")).await;
    assert_eq!(before, after);
    let (_, trajectory_after) = app.get(&format!("/api/v1/plans/{plan_id}/trajectory")).await;
    assert_eq!(trajectory_before, trajectory_after);
    app.stop().await;
}

#[tokio::test]
async fn queued_and_running_plans_can_be_cancelled() {
    let app = TestApp::spawn_with(fresh_db_url().await, |c| {
        c.workers = 1;
        c.queue.start_delay = std::time::Duration::from_secs(60);
    })
    .await;
    let id = app.create_mission(&mission_body("real-fields/nl-parcel-b.json")).await;
    let (_, first) = app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"line_spacing_m": 20})).await;
    let (_, second) = app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"line_spacing_m": 20})).await;
    let first = first["id"].as_str().unwrap().to_owned();
    let second = second["id"].as_str().unwrap().to_owned();
    app.wait_plan(&first, |s| s == "running").await;
    let (_, p) = app.get(&format!("/api/v1/plans/{second}")).await;
    assert_eq!(p["status"], "queued");
    for id in [&second, &first] {
        let r = app.client.delete(app.url(&format!("/api/v1/plans/{id}"))).send().await.unwrap();
        assert_eq!(r.status(), 200);
        let body: Value = r.json().await.unwrap();
        assert_eq!(body["status"], "cancelled");
    }
    // the worker stops the running job and takes nothing else
    tokio::time::sleep(std::time::Duration::from_millis(500)).await;
    for id in [&first, &second] {
        let (_, p) = app.get(&format!("/api/v1/plans/{id}")).await;
        assert_eq!(p["status"], "cancelled");
        let (s, problem) = app.get(&format!("/api/v1/plans/{id}/trajectory")).await;
        assert_eq!((s, problem["code"].as_str().unwrap()), (409, "trajectory_not_available"));
    }
    app.stop().await;
}

#[tokio::test]
async fn service_documents_itself() {
    let app = TestApp::spawn().await;
    let (s, ready) = app.get("/readyz").await;
    assert_eq!((s, ready["status"].as_str().unwrap()), (200, "ready"));
    let (s, _) = app.get("/healthz").await;
    assert_eq!(s, 200);
    let (_, planners) = app.get("/api/v1/planners").await;
    let first = &planners.as_array().unwrap()[0];
    assert_eq!(first["id"], "boustrophedon");
    assert!(first["parameters"].as_array().unwrap().iter().any(|p| p["name"] == "line_spacing_m"));
    let served = app.client.get(app.url("/openapi.json")).send().await.unwrap().text().await.unwrap();
    let served: Value = serde_json::from_str(&served).unwrap();
    let committed: Value = serde_json::from_str(&std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/openapi/openapi.json")).unwrap()).unwrap();
    assert_eq!(served, committed, "the served OpenAPI document differs from openapi/openapi.json");
    let docs = app.client.get(app.url("/docs/")).send().await.unwrap();
    assert_eq!(docs.status(), 200);
    assert!(docs.text().await.unwrap().contains("swagger"));
    let page = app.client.get(app.url("/")).send().await.unwrap();
    assert_eq!(page.status(), 200);
    app.stop().await;
}

#[tokio::test]
async fn planners_and_cameras_are_listed_and_a_camera_plan_searches_every_direction() {
    let app = TestApp::spawn().await;
    let (status, planners) = app.get("/api/v1/planners").await;
    assert_eq!(status, 200);
    let ids: Vec<&str> = planners.as_array().unwrap().iter().map(|p| p["id"].as_str().unwrap()).collect();
    for id in ["boustrophedon", "naive", "eecd", "energy_aware"] {
        assert!(ids.contains(&id), "{id} missing from {ids:?}");
    }
    assert!(planners[0]["direction_rule"].is_string() && planners[0]["parameters"].is_array());
    let (status, cameras) = app.get("/api/v1/cameras").await;
    assert_eq!(status, 200);
    let p4 = cameras.as_array().unwrap().iter().find(|c| c["id"] == "dji_phantom4_pro").expect("preset listed");
    assert_eq!((p4["sensor_width_mm"].as_f64(), p4["image_width_px"].as_u64()), (Some(13.2), Some(5472)));

    let id = app.create_mission(&mission_body("random-fields/h03_00.json")).await;
    // an unknown preset is refused, with where
    let (status, problem) = app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"camera": {"preset": "box_brownie"}, "altitude_m": 60})).await;
    assert_eq!((status, problem["pointer"].as_str()), (422, Some("/camera/preset")), "{problem}");
    let body = json!({"planner": "eecd", "camera": {"preset": "dji_phantom4_pro"}, "altitude_m": 60, "sweep_direction": "optimal"});
    let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &body).await;
    assert_eq!(status, 202, "{plan}");
    let plan = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(plan["status"], "succeeded", "{plan}");
    let stats = &plan["stats"];
    assert!(stats["photos"].as_u64().unwrap() > 0 && stats["photo_coverage_ratio"].as_f64().unwrap() >= 0.98, "{stats}");
    app.stop().await;
}

/// A handler that panics answers 500 with a problem document, and the server goes on.
#[tokio::test]
async fn a_panicking_handler_answers_a_problem() {
    async fn boom() -> &'static str {
        panic!("deliberate failure for the test")
    }
    let router = axum::Router::new().route("/boom", axum::routing::get(boom)).route("/fine", axum::routing::get(|| async { "fine" })).layer(coverplan::http::catch_panics());
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let base = format!("http://{}", listener.local_addr().unwrap());
    tokio::spawn(async move { axum::serve(listener, router).await });
    let r = reqwest::get(format!("{base}/boom")).await.unwrap();
    assert_eq!(r.status(), 500);
    assert_eq!(r.headers()["content-type"], "application/problem+json");
    let problem: Value = r.json().await.unwrap();
    assert_eq!(problem["code"], "internal");
    assert!(!problem["detail"].as_str().unwrap().contains("deliberate"), "internal details stay in the log: {problem}");
    assert_eq!(reqwest::get(format!("{base}/fine")).await.unwrap().text().await.unwrap(), "fine");
}

/// Query-string errors are problems with a pointer to the parameter.
#[tokio::test]
async fn bad_query_parameters_are_named() {
    let app = TestApp::spawn().await;
    for (query, pointer) in [("limit=abc", "/limit"), ("offset=1.5", "/offset"), ("fields=everything", "/fields")] {
        let (s, problem) = app.get(&format!("/api/v1/missions?{query}")).await;
        assert_eq!((s, problem["code"].as_str(), problem["pointer"].as_str()), (400, Some("invalid_query"), Some(pointer)), "{query}: {problem}");
    }
    let (s, problem) = app.get("/api/v1/missions?limit=0").await;
    assert_eq!((s, problem["pointer"].as_str()), (422, Some("/limit")), "{problem}");
    app.stop().await;
}

/// A POST retried with the same `Idempotency-Key` gets the first answer and makes nothing new;
/// the key with another body is refused; each tenant's keys are its own.
#[tokio::test]
async fn retried_posts_with_an_idempotency_key_make_nothing_twice() {
    let app = TestApp::spawn().await;
    let post = |path: &str, key: &str, body: &Value| app.client.post(app.url(path)).header("Idempotency-Key", key).json(body).send();
    let body = mission_body("real-fields/nl-parcel-b.json");
    let first = post("/api/v1/missions", "mission-1", &body).await.unwrap();
    assert_eq!(first.status(), 201);
    assert!(first.headers().get("idempotent-replayed").is_none());
    let first: Value = first.json().await.unwrap();
    let again = post("/api/v1/missions", "mission-1", &body).await.unwrap();
    assert_eq!((again.status().as_u16(), again.headers().get("idempotent-replayed").map(|v| v.to_str().unwrap().to_owned())), (201, Some("true".into())));
    assert_eq!(again.json::<Value>().await.unwrap(), first, "the same answer, the same mission");
    assert_eq!(app.get("/api/v1/missions").await.1["total"], 1);

    let mut other = body.clone();
    other["name"] = json!("another field");
    let reused = post("/api/v1/missions", "mission-1", &other).await.unwrap();
    assert_eq!(reused.status(), 422);
    assert_eq!(reused.json::<Value>().await.unwrap()["code"], "idempotency_key_reused");

    // plans: one queued for two sends
    let id = first["id"].as_str().unwrap();
    let plan_path = format!("/api/v1/missions/{id}/plans");
    let a: Value = post(&plan_path, "plan-1", &json!({"line_spacing_m": 30})).await.unwrap().json().await.unwrap();
    let b: Value = post(&plan_path, "plan-1", &json!({"line_spacing_m": 30})).await.unwrap().json().await.unwrap();
    assert_eq!(a["id"], b["id"]);
    assert_eq!(app.get(&plan_path).await.1.as_array().unwrap().len(), 1);
    // refusals are kept too: the retry of a wrong request is told the same
    let wrong = json!({"line_spacing_m": -1});
    let refused = post(&plan_path, "plan-2", &wrong).await.unwrap();
    let refused_again = post(&plan_path, "plan-2", &wrong).await.unwrap();
    assert_eq!((refused.status(), refused_again.status()), (reqwest::StatusCode::UNPROCESSABLE_ENTITY, reqwest::StatusCode::UNPROCESSABLE_ENTITY));
    assert_eq!(refused_again.headers()["content-type"], "application/problem+json");
    let bad_key = post("/api/v1/missions", &"k".repeat(256), &body).await.unwrap();
    assert_eq!(bad_key.status(), 400);
    app.stop().await;
}

#[tokio::test]
async fn an_idempotency_key_being_answered_is_busy_and_belongs_to_one_tenant() {
    use coverplan::store::idempotency::{self, Begin};
    let db = coverplan::store::connect(&fresh_db_url().await).await.unwrap();
    assert!(matches!(idempotency::begin(&db, "farm-a", "k", "f1").await.unwrap(), Begin::New));
    assert!(matches!(idempotency::begin(&db, "farm-a", "k", "f1").await.unwrap(), Begin::InProgress));
    assert!(matches!(idempotency::begin(&db, "farm-a", "k", "f2").await.unwrap(), Begin::Mismatch));
    assert!(matches!(idempotency::begin(&db, "farm-b", "k", "f2").await.unwrap(), Begin::New), "another tenant's key of the same name");
    idempotency::finish(&db, "farm-a", "k", 201, Some("application/json"), b"{}").await.unwrap();
    match idempotency::begin(&db, "farm-a", "k", "f1").await.unwrap() {
        Begin::Replay { status, content_type, body } => assert_eq!((status, content_type.as_deref(), body.as_slice()), (201, Some("application/json"), &b"{}"[..])),
        _ => panic!("the kept answer is replayed"),
    }
    idempotency::forget(&db, "farm-b", "k").await.unwrap();
    assert!(matches!(idempotency::begin(&db, "farm-b", "k", "f3").await.unwrap(), Begin::New), "a forgotten key is free again");
}

/// Requests that could not finish in reasonable time are refused before queueing, saying why.
#[tokio::test]
async fn plans_too_costly_to_finish_are_refused_before_queueing() {
    let app = TestApp::spawn().await;
    // 100 round no-fly zones of 16 corners in a 3 km square: 1600 corners to route around
    let (lon0, lat0) = (5.0f64, 50.0f64);
    let (mx, my) = (1.0 / (111_320.0 * lat0.to_radians().cos()), 1.0 / 110_574.0);
    let at = |x: f64, y: f64| json!([lon0 + x * mx, lat0 + y * my]);
    let zones: Vec<Value> = (0..100)
        .map(|k| {
            let (cx, cy) = (300.0 + 270.0 * (k % 10) as f64, 300.0 + 270.0 * (k / 10) as f64);
            let mut ring: Vec<Value> = (0..16).map(|t| t as f64 * std::f64::consts::TAU / 16.0).map(|a| at(cx + 25.0 * a.cos(), cy + 25.0 * a.sin())).collect();
            ring.push(ring[0].clone());
            json!({"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [ring]}})
        })
        .collect();
    let square = json!({"type": "Polygon", "coordinates": [[at(0.0, 0.0), at(3000.0, 0.0), at(3000.0, 3000.0), at(0.0, 3000.0), at(0.0, 0.0)]]});
    let many_zones = app.create_mission(&json!({"name": "orchard", "area": square, "no_fly_zones": {"type": "FeatureCollection", "features": zones}})).await;
    let (s, problem) = app.post(&format!("/api/v1/missions/{many_zones}/plans"), &json!({"line_spacing_m": 50})).await;
    assert_eq!((s, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some("too_many_zone_corners"), Some("/no_fly_zones")), "{problem}");

    // a 64 ha field at 0.5 m: over a thousand lines to order one by one
    let field = app.create_mission(&mission_body("random-fields/h00_00.json")).await;
    let (s, problem) = app.post(&format!("/api/v1/missions/{field}/plans"), &json!({"planner": "line_gtsp", "line_spacing_m": 0.5})).await;
    assert_eq!((s, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some("too_many_lines"), Some("/line_spacing_m")), "{problem}");
    let (s, problem) = app.post(&format!("/api/v1/missions/{field}/plans"), &json!({"planner": "line_gtsp", "line_spacing_m": 0.5, "vehicle": {"kind": "fixed_wing"}})).await;
    assert_eq!((s, problem["code"].as_str()), (422, Some("too_many_lines")), "{problem}");
    // the same spacing is fine where lines are joined field by field
    let (s, plan) = app.post(&format!("/api/v1/missions/{field}/plans"), &json!({"planner": "boustrophedon", "line_spacing_m": 0.5})).await;
    assert_eq!(s, 202, "{plan}");
    app.client.delete(app.url(&format!("/api/v1/plans/{}", plan["id"].as_str().unwrap()))).send().await.unwrap();
    app.stop().await;
}
