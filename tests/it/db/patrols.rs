//! Patrols through the API: queued and followed like plans, paths and heat map as GeoJSON on
//! the mission's area, reproducible from the seed; bad parameters answer 422; the online
//! next-moves route.

use serde_json::{Value, json};

use crate::common::{TestApp, mission_body};

async fn wait_patrol(app: &TestApp, id: &str) -> Value {
    for _ in 0..1200 {
        let (_, p) = app.get(&format!("/api/v1/patrols/{id}")).await;
        if matches!(p["status"].as_str(), Some("succeeded" | "failed" | "cancelled")) {
            return p;
        }
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
    }
    panic!("patrol {id} did not finish");
}

#[tokio::test]
async fn a_patrol_of_three_uavs_gives_paths_metrics_and_a_heat_map() {
    let app = TestApp::spawn().await;
    let mission = app.create_mission(&mission_body("real-fields/nl-parcel-b.json")).await;
    let params = json!({"uavs": 3, "cycles": 2000, "cell_size_m": 25.0, "seed": 5});
    let (status, queued) = app.post(&format!("/api/v1/missions/{mission}/patrols"), &params).await;
    assert_eq!(status, 202, "{queued}");
    let id = queued["id"].as_str().unwrap().to_owned();
    let done = wait_patrol(&app, &id).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    assert_eq!(done["params"], params);
    let stats = &done["stats"];
    assert!(stats["qmi"].as_f64().unwrap() > 0.0 && stats["ntm"].as_u64().unwrap() > 0, "{stats}");
    assert_eq!(stats["uavs"].as_array().unwrap().len(), 3);
    assert!(stats["energy_j"].as_f64().unwrap() > 0.0);
    let r = app.client.get(app.url(&format!("/api/v1/patrols/{id}/trajectory"))).send().await.unwrap();
    assert_eq!(r.headers()["content-type"], "application/geo+json");
    let trajectory: Value = r.json().await.unwrap();
    let features = trajectory["features"].as_array().unwrap();
    let paths: Vec<&Value> = features.iter().filter(|f| f["properties"]["kind"] == "patrol").collect();
    let cells: Vec<&Value> = features.iter().filter(|f| f["properties"]["kind"] == "visits").collect();
    assert_eq!(paths.len(), 3);
    // each corner carries its cycle: from 0 to the last, at most one cell per cycle between
    // corners (a UAV whose neighbours are all taken waits)
    for path in &paths {
        let coords = path["geometry"]["coordinates"].as_array().unwrap();
        let cycles: Vec<u64> = path["properties"]["cycles"].as_array().unwrap().iter().map(|c| c.as_u64().unwrap()).collect();
        assert_eq!((cycles.len(), cycles.first(), cycles.last()), (coords.len(), Some(&0), Some(&2000)));
        let metres = |a: &Value, b: &Value| {
            let (dx, dy) = (b[0].as_f64().unwrap() - a[0].as_f64().unwrap(), b[1].as_f64().unwrap() - a[1].as_f64().unwrap());
            let lat = a[1].as_f64().unwrap().to_radians();
            (dx * 111_320.0 * lat.cos()).hypot(dy * 110_574.0)
        };
        for (w, c) in coords.windows(2).zip(cycles.windows(2)) {
            let cells = metres(&w[0], &w[1]) / 25.0;
            let took = (c[1] - c[0]) as f64;
            assert!(cells <= took * 1.01 + 0.05, "{cells} cells in {took} cycles");
        }
    }
    assert_eq!(cells.len() as u64, stats["free_cells"].as_u64().unwrap());
    // every cell was visited in 2 000 cycles, and the visits add up to the moves and starts
    let visits: u64 = cells.iter().map(|c| c["properties"]["visits"].as_u64().unwrap()).sum();
    assert!(cells.iter().all(|c| c["properties"]["visits"].as_u64().unwrap() > 0));
    assert!((2 * 2000..=3 * 2000 + 1).contains(&visits), "{visits} visits");
    // the same seed gives the same patrol; the plans' routes do not serve it
    let (_, again) = app.post(&format!("/api/v1/missions/{mission}/patrols"), &params).await;
    let again = wait_patrol(&app, again["id"].as_str().unwrap()).await;
    for k in ["qmi", "sdf", "ntm"] {
        assert_eq!(again["stats"][k], stats[k], "{k}");
    }
    assert_eq!(app.get(&format!("/api/v1/plans/{id}")).await.0, 404);
    let (_, listed) = app.get(&format!("/api/v1/missions/{mission}/plans")).await;
    assert!(listed.as_array().unwrap().is_empty(), "{listed}");
    app.stop().await;
}

/// A camera sets the cells: the square its footprint covers at the patrol altitude.
#[tokio::test]
async fn a_camera_sets_the_patrol_cells() {
    let app = TestApp::spawn().await;
    let mission = app.create_mission(&mission_body("real-fields/nl-parcel-b.json")).await;
    let camera = json!({"preset": "dji_phantom4_pro"});
    let footprint = serde_json::from_value::<coverplan::planner::camera::Camera>(camera.clone()).unwrap().plan(Some(40.0), None, 0.0, 0.0).unwrap();
    let side = footprint.footprint_across_m.min(footprint.footprint_along_m);
    let mut cells = Vec::new();
    for params in [json!({"camera": camera, "altitude_m": 40, "cycles": 200}), json!({"cell_size_m": side, "cycles": 200})] {
        let (status, queued) = app.post(&format!("/api/v1/missions/{mission}/patrols"), &params).await;
        assert_eq!(status, 202, "{queued}");
        let done = wait_patrol(&app, queued["id"].as_str().unwrap()).await;
        assert_eq!(done["status"], "succeeded", "{done}");
        assert!((done["stats"]["cell_size_m"].as_f64().unwrap() - side).abs() < 1e-9, "{}", done["stats"]);
        cells.push(done["stats"]["free_cells"].clone());
    }
    assert_eq!(cells[0], cells[1], "the same grid as the same cell size given directly");
    app.stop().await;
}

#[tokio::test]
async fn bad_patrol_parameters_are_refused_with_where() {
    let app = TestApp::spawn().await;
    let mission = app.create_mission(&mission_body("real-fields/nl-parcel-b.json")).await;
    for (params, pointer) in [
        (json!({"cycles": 0}), "/cycles"),
        (json!({"cell_size_m": 0.5}), "/cell_size_m"),
        (json!({"uavs": 65}), "/uavs"),
        // uavs × cycles would overflow: refused as out of range, never a panic
        (json!({"uavs": 4_611_686_018_427_387_904u64, "cycles": 10}), "/uavs"),
        (json!({"uavs": 8, "cycles": 300_000}), "/cycles"),
        (json!({"sync_interval": 0}), "/sync_interval"),
        (json!({"vehicle": {"profile": "no-such-drone"}}), "/vehicle/profile"),
        (json!({"vehicle": {"profile": "generic_fixed_wing"}}), "/vehicle"),
        (json!({"camera": {"preset": "dji_phantom4_pro"}, "altitude_m": 40, "cell_size_m": 20}), "/cell_size_m"),
        (json!({"altitude_m": 40}), "/altitude_m"),
        (json!({"camera": {"preset": "dji_phantom4_pro"}}), "/altitude_m"),
        (json!({"camera": {"preset": "dji_phantom4_pro"}, "altitude_m": 0.2}), "/altitude_m"),
    ] {
        let (status, problem) = app.post(&format!("/api/v1/missions/{mission}/patrols"), &params).await;
        assert_eq!((status, problem["pointer"].as_str()), (422, Some(pointer)), "{params}: {problem}");
    }
    let (status, _) = app.post(&format!("/api/v1/missions/{mission}/patrols"), &json!({"strategy": "ant_colony"})).await;
    assert_eq!(status, 422);
    let (status, _) = app.post("/api/v1/missions/no-such-mission/patrols", &json!({})).await;
    assert_eq!(status, 404);
    app.stop().await;
}

#[tokio::test]
async fn next_moves_runs_a_patrol_one_cycle_at_a_time() {
    let app = TestApp::spawn().await;
    let cells = 6 * 5;
    let mut state = json!({"u": vec![0.0; cells], "last_visit": vec![0; cells], "at": [0, 29], "headings": [0, 2], "cycle": 1});
    for _ in 0..20 {
        let (status, answer) = app.post("/api/v1/patrols/next-moves", &json!({"cols": 6, "rows": 5, "blocked": [7, 8], "state": state, "seed": 3})).await;
        assert_eq!(status, 200, "{answer}");
        for (k, m) in answer["moves"].as_array().unwrap().iter().enumerate() {
            let (from, to) = (state["at"][k].as_u64().unwrap() as i64, m.as_u64().unwrap() as i64);
            assert!(to != 7 && to != 8, "into a blocked cell");
            let ((c0, r0), (c1, r1)) = ((from % 6, from / 6), (to % 6, to / 6));
            assert_eq!((c0 - c1).abs() + (r0 - r1).abs(), 1);
        }
        state = answer["state"].clone();
    }
    assert_eq!(state["cycle"], 21);
    let fixed = json!({"cols": 6, "rows": 5, "state": state, "strategy": "shared_cycle"});
    let (status, problem) = app.post("/api/v1/patrols/next-moves", &fixed).await;
    assert_eq!((status, problem["code"].as_str()), (422, Some("strategy_not_online")), "{problem}");
    let short = json!({"cols": 6, "rows": 5, "state": {"u": [0.0], "last_visit": [0], "at": [0], "headings": [0], "cycle": 1}});
    let (status, problem) = app.post("/api/v1/patrols/next-moves", &short).await;
    assert_eq!((status, problem["code"].as_str()), (422, Some("state_mismatch")), "{problem}");
    let mut late = json!({"cols": 2, "rows": 1, "state": {"u": [0.0, 0.0], "last_visit": [0, 9], "at": [0], "headings": [0], "cycle": 3}});
    let (status, problem) = app.post("/api/v1/patrols/next-moves", &late).await;
    assert_eq!((status, problem["pointer"].as_str()), (422, Some("/state/last_visit/1")), "{problem}");
    late["state"]["last_visit"] = json!([0, 0]);
    late["blocked"] = json!([0]);
    let (status, problem) = app.post("/api/v1/patrols/next-moves", &late).await;
    assert_eq!((status, problem["pointer"].as_str()), (422, Some("/state/at/0")), "{problem}");
    app.stop().await;
}

/// The predictable baseline through the API, on a real field (a tree tour: no Hamiltonian cycle
/// is built there): every cell visited, and the same walk on every run.
#[tokio::test]
async fn a_shared_cycle_patrol_visits_every_cell() {
    let app = TestApp::spawn().await;
    let mission = app.create_mission(&mission_body("real-fields/nl-parcel-b.json")).await;
    let (status, queued) = app.post(&format!("/api/v1/missions/{mission}/patrols"), &json!({"strategy": "shared_cycle", "uavs": 2, "cycles": 1000, "cell_size_m": 25.0})).await;
    assert_eq!(status, 202, "{queued}");
    let done = wait_patrol(&app, queued["id"].as_str().unwrap()).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    let trajectory = app.get(&format!("/api/v1/patrols/{}/trajectory", done["id"].as_str().unwrap())).await.1;
    let cells: Vec<&Value> = trajectory["features"].as_array().unwrap().iter().filter(|f| f["properties"]["kind"] == "visits").collect();
    assert!(!cells.is_empty() && cells.iter().all(|c| c["properties"]["visits"].as_u64().unwrap() > 0));
    let (_, again) =
        app.post(&format!("/api/v1/missions/{mission}/patrols"), &json!({"strategy": "shared_cycle", "uavs": 2, "cycles": 1000, "cell_size_m": 25.0, "seed": 9})).await;
    let again = wait_patrol(&app, again["id"].as_str().unwrap()).await;
    assert_eq!(again["stats"]["qmi"], done["stats"]["qmi"], "no randomness, whatever the seed");
    app.stop().await;
}
