//! Vehicle profiles and route estimates end to end: `/api/v1/vehicles` and
//! `/api/v1/estimates`, and a plan that names a stored profile and is split into sorties.

use crate::common::{TestApp, mission_body};
use serde_json::{Value, json};

async fn put(app: &TestApp, path: &str, body: &Value) -> (u16, Value) {
    let r = app.client.put(app.url(path)).json(body).send().await.unwrap();
    (r.status().as_u16(), r.json().await.unwrap_or(Value::Null))
}

async fn delete(app: &TestApp, path: &str) -> (u16, Value) {
    let r = app.client.delete(app.url(path)).send().await.unwrap();
    (r.status().as_u16(), r.json().await.unwrap_or(Value::Null))
}

#[tokio::test]
async fn profiles_are_listed_created_edited_and_deleted_except_built_ins() {
    let app = TestApp::spawn().await;
    let (s, list) = app.get("/api/v1/vehicles").await;
    assert_eq!(s, 200);
    let ids: Vec<&str> = list.as_array().unwrap().iter().map(|v| v["profile"].as_str().unwrap()).collect();
    for id in ["iris", "maja", "generic_multirotor", "generic_fixed_wing"] {
        assert!(ids.contains(&id), "{id} missing from {ids:?}");
    }
    let (_, iris) = app.get("/api/v1/vehicles/iris").await;
    assert_eq!((iris["builtin"].as_bool(), iris["energy"]["model"].as_str()), (Some(true), Some("multirotor_iem")));

    // a copy of iris with a smaller battery
    let mut mine = iris.clone();
    for k in ["builtin", "created_at", "updated_at"] {
        mine.as_object_mut().unwrap().remove(k);
    }
    mine["profile"] = json!("iris-small");
    mine["battery"]["energy_wh"] = json!(10.0);
    let (s, created) = app.post("/api/v1/vehicles", &mine).await;
    assert_eq!((s, created["builtin"].as_bool()), (201, Some(false)), "{created}");
    let (s, again) = app.post("/api/v1/vehicles", &mine).await;
    assert_eq!((s, again["code"].as_str()), (409, Some("vehicle_exists")));
    mine["battery"]["energy_wh"] = json!(12.0);
    let (s, updated) = put(&app, "/api/v1/vehicles/iris-small", &mine).await;
    assert_eq!((s, updated["battery"]["energy_wh"].as_f64()), (200, Some(12.0)));
    let (s, p) = put(&app, "/api/v1/vehicles/other", &mine).await;
    assert_eq!((s, p["code"].as_str()), (422, Some("profile_mismatch")));

    // bad figures are refused where they are
    let mut bad = mine.clone();
    bad["battery"]["reserve"] = json!(2.0);
    let (s, p) = app.post("/api/v1/vehicles", &bad).await;
    assert_eq!((s, p["pointer"].as_str()), (422, Some("/battery/reserve")), "{p}");
    let mut bad = mine.clone();
    bad["energy"]["parameters"]["level_power"] = json!([]);
    let (s, p) = app.post("/api/v1/vehicles", &bad).await;
    assert_eq!((s, p["pointer"].as_str()), (422, Some("/energy/parameters/level_power")), "{p}");
    let mut bad = mine.clone();
    bad["profile"] = json!("Bad Name");
    let (s, p) = app.post("/api/v1/vehicles", &bad).await;
    assert_eq!((s, p["code"].as_str()), (422, Some("invalid_profile_id")));

    let (s, p) = delete(&app, "/api/v1/vehicles/iris").await;
    assert_eq!((s, p["code"].as_str()), (409, Some("builtin_vehicle")));
    assert_eq!(delete(&app, "/api/v1/vehicles/iris-small").await.0, 204);
    assert_eq!(app.get("/api/v1/vehicles/iris-small").await.0, 404);
    app.stop().await;
}

#[tokio::test]
async fn routes_made_elsewhere_are_estimated_leg_by_leg() {
    let app = TestApp::spawn().await;
    let d = 100.0 / 111_320.0;
    let body = json!({"route": {"type": "LineString", "coordinates": [[5.0, 0.0, 20.0], [5.0 + d, 0.0, 20.0], [5.0 + d, d, 20.0]]}, "vehicle": {"profile": "iris"}});
    let (s, e) = app.post("/api/v1/estimates", &body).await;
    assert_eq!(s, 200, "{e}");
    let legs = e["legs"].as_array().unwrap();
    assert_eq!(legs.len(), 2);
    let sum: f64 = legs.iter().map(|l| l["energy_j"].as_f64().unwrap()).sum::<f64>() + e["totals"]["takeoff_landing_energy_j"].as_f64().unwrap();
    assert!((sum - e["totals"]["energy_j"].as_f64().unwrap()).abs() < 1e-6);
    // the corner keeps some speed: the second leg starts moving
    assert!(legs[1]["v_in_mps"].as_f64().unwrap() > 0.0);
    let fixed: Value = app.post("/api/v1/estimates", &json!({"waypoints": [[5.0, 0.0, 20.0], [5.0 + d, 0.0, 20.0]], "vehicle": {"profile": "maja"}})).await.1;
    // a fixed wing climbs while it flies the leg: no time beyond it, energy for the climb
    assert!((fixed["totals"]["duration_s"].as_f64().unwrap() - 100.0 / 15.0).abs() < 0.05, "{fixed}");
    assert!(fixed["totals"]["takeoff_landing_energy_j"].as_f64().unwrap() > 0.0);
    for (body, pointer) in [
        (json!({"waypoints": [[5.0, 0.0]]}), "/waypoints"),
        (json!({"waypoints": [[5.0, 0.0], [5.0, f64::MAX]]}), "/waypoints/1"),
        (json!({"route": {"type": "Polygon", "coordinates": []}}), "/route/type"),
        (json!({"waypoints": [[5.0, 0.0], [5.1, 0.0]], "vehicle": {"profile": "nope"}}), "/vehicle/profile"),
    ] {
        let (s, p) = app.post("/api/v1/estimates", &body).await;
        assert_eq!((s, p["pointer"].as_str()), (422, Some(pointer)), "{body}: {p}");
    }
    app.stop().await;
}

#[tokio::test]
async fn a_plan_with_a_small_battery_is_split_into_sorties_from_home() {
    let app = TestApp::spawn().await;
    let mut mission = mission_body("real-fields/nl-parcel-b.json");
    let first = mission["area"]["coordinates"][0][0].clone();
    let (_, iris) = app.get("/api/v1/vehicles/iris").await;
    let mut small = iris.clone();
    for k in ["builtin", "created_at", "updated_at"] {
        small.as_object_mut().unwrap().remove(k);
    }
    small["profile"] = json!("iris-20wh");
    small["battery"]["energy_wh"] = json!(20.0);
    assert_eq!(app.post("/api/v1/vehicles", &small).await.0, 201);
    let params = json!({"line_spacing_m": 20, "altitude_m": 30, "vehicle": {"profile": "iris-20wh"}, "max_sorties": 100});

    // without a home the plan is made as one route, marked where each battery runs out
    let id = app.create_mission(&mission).await;
    let (_, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &params).await;
    let route = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(route["status"], "succeeded", "{route}");
    let warnings = route["stats"]["warnings"].as_array().unwrap();
    assert!(warnings.iter().any(|w| w.as_str().unwrap().contains("home")), "{route}");
    let (_, trajectory) = app.get(&format!("/api/v1/plans/{}/trajectory", plan["id"].as_str().unwrap())).await;
    let swaps = trajectory["features"].as_array().unwrap().iter().filter(|f| f["properties"]["kind"] == "battery_swap").count() as u64;
    assert_eq!(route["stats"]["batteries_needed"].as_u64(), Some(swaps + 1), "{}", route["stats"]);
    assert!(swaps >= 1);

    mission["home"] = first;
    let id = app.create_mission(&mission).await;
    let (_, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &params).await;
    // editing the profile after queueing does not change the plan
    small["battery"]["energy_wh"] = json!(1000.0);
    assert_eq!(put(&app, "/api/v1/vehicles/iris-20wh", &small).await.0, 200);
    let done = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    let stats = &done["stats"];
    let sorties = stats["sorties"].as_u64().unwrap();
    assert!(sorties >= 2, "{stats}");
    for s in stats["sortie_totals"].as_array().unwrap() {
        assert!(s["battery_used"].as_f64().unwrap() <= 1.0, "{s}");
    }
    assert!(stats["coverage_ratio"].as_f64().unwrap() >= 0.98);
    let (_, fc) = app.get(&format!("/api/v1/plans/{}/trajectory", done["id"].as_str().unwrap())).await;
    let last_sortie = fc["features"].as_array().unwrap().iter().filter_map(|f| f["properties"]["sortie"].as_u64()).max();
    assert_eq!(last_sortie, Some(sorties));
    app.stop().await;
}
