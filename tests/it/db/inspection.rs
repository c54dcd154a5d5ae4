//! Inspection over the API: the barn (draw it with its height, ask for 300 m, get a
//! collision-free path with camera angles and figures), its export to an autopilot, and the
//! refusals with their places.

use coverplan::planner::frame::LocalFrame;
use geo::Coord;
use serde_json::{Value, json};

use crate::common::TestApp;

/// A 24 × 12 m barn, 8 m high, in a 100 m square; a silo beside it; the home 20 m south.
fn barn_mission() -> Value {
    let frame = LocalFrame::new(8.55, 47.37);
    let at = |x: f64, y: f64| {
        let [lon, lat] = frame.to_wgs84(Coord { x, y });
        json!([lon, lat])
    };
    let ring = |pts: &[(f64, f64)]| {
        let mut r: Vec<Value> = pts.iter().map(|&(x, y)| at(x, y)).collect();
        r.push(r[0].clone());
        json!([r])
    };
    json!({
        "name": "farm with a barn",
        "area": {"type": "Polygon", "coordinates": ring(&[(-50.0, -50.0), (50.0, -50.0), (50.0, 50.0), (-50.0, 50.0)])},
        "structures": {"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {"name": "barn", "height_m": 8.0},
             "geometry": {"type": "Polygon", "coordinates": ring(&[(-12.0, -6.0), (12.0, -6.0), (12.0, 6.0), (-12.0, 6.0)])}},
            {"type": "Feature", "properties": {"name": "silo", "height_m": 14.0, "radius_m": 3.0},
             "geometry": {"type": "Point", "coordinates": at(22.0, 0.0)}},
        ]},
        "home": at(0.0, -20.0),
    })
}

#[tokio::test]
async fn a_barn_is_inspected_within_300_m_and_goes_to_the_autopilot() {
    let app = TestApp::spawn().await;
    let id = app.create_mission(&barn_mission()).await;
    let (_, mission) = app.get(&format!("/api/v1/missions/{id}")).await;
    assert_eq!(mission["structures"]["features"].as_array().map(Vec::len), Some(2), "{mission}");
    let params = json!({
        "planner": "inspection",
        "vehicle": {"profile": "iris"},
        "budget": {"max_length_m": 300},
        "targets": [{"name": "barn"}, {"name": "silo", "faces": ["walls"], "priority": 2}],
        "inspection": {"viewpoints": 200, "show_unseen": true},
        "seed": 3,
        "time_limit_s": 10,
    });
    let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &params).await;
    assert_eq!(status, 202, "{plan}");
    let plan_id = plan["id"].as_str().unwrap().to_owned();
    let done = app.wait_finished(&plan_id).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    let stats = &done["stats"];
    assert_eq!(stats["planner"], "inspection");
    let length = stats["length_m"].as_f64().unwrap();
    assert!(length > 50.0 && length <= 300.0, "{stats}");
    let coverage = stats["inspection_coverage"].as_f64().unwrap();
    assert!(coverage > 0.5 && coverage <= 1.0, "{stats}");
    let targets = stats["inspection"]["targets"].as_array().unwrap();
    let names: Vec<(&str, &str)> = targets.iter().map(|t| (t["name"].as_str().unwrap(), t["face"].as_str().unwrap())).collect();
    assert_eq!(names, vec![("barn", "walls"), ("barn", "roof"), ("silo", "walls")]);
    assert!(targets.iter().all(|t| t["seen"].as_u64().unwrap() > 0), "{stats}");

    let (status, trajectory) = app.get(&format!("/api/v1/plans/{plan_id}/trajectory")).await;
    assert_eq!(status, 200);
    let features = trajectory["features"].as_array().unwrap();
    let views: Vec<&Value> = features.iter().filter(|f| f["properties"]["kind"] == "viewpoint").collect();
    assert_eq!(views.len() as u64, stats["inspection"]["viewpoints"].as_u64().unwrap());
    for (k, v) in views.iter().enumerate() {
        let p = &v["properties"];
        assert_eq!(p["order"].as_u64(), Some(k as u64 + 1));
        assert!((0.0..360.0).contains(&p["yaw_deg"].as_f64().unwrap()));
        assert!((-90.0..=30.0).contains(&p["gimbal_pitch_deg"].as_f64().unwrap()));
        assert_eq!(v["geometry"]["coordinates"].as_array().unwrap().len(), 3, "with its height");
    }
    let new_seen: u64 = views.iter().map(|v| v["properties"]["new_pois_seen"].as_u64().unwrap()).sum();
    assert_eq!(new_seen, stats["inspection"]["pois_seen"].as_u64().unwrap());
    let legs = features.iter().filter(|f| f["properties"]["kind"] == "transit").count();
    assert_eq!(legs, views.len() + 1);
    let points = |kind: &str| features.iter().find(|f| f["properties"]["kind"] == kind).unwrap()["geometry"]["coordinates"].as_array().unwrap().len() as u64;
    assert_eq!(points("seen"), new_seen);
    assert_eq!(points("unseen") + new_seen, stats["inspection"]["pois"].as_u64().unwrap());

    // QGroundControl: a hold, the gimbal and a picture at every viewpoint
    let r = app.client.get(app.url(&format!("/api/v1/plans/{plan_id}/trajectory?format=plan&firmware=px4"))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let file: Value = r.json().await.unwrap();
    let items = file["mission"]["items"].as_array().unwrap();
    let count = |command: u64| items.iter().filter(|i| i["command"].as_u64() == Some(command)).count();
    assert_eq!(count(2000), views.len(), "one capture per viewpoint");
    assert_eq!(count(1000), views.len(), "one gimbal command per viewpoint");
    for v in &views {
        let [lon, lat]: [f64; 2] = [v["geometry"]["coordinates"][0].as_f64().unwrap(), v["geometry"]["coordinates"][1].as_f64().unwrap()];
        let item = items
            .iter()
            .find(|i| i["command"].as_u64() == Some(16) && i["params"][4].as_f64() == Some(lat) && i["params"][5].as_f64() == Some(lon))
            .expect("a waypoint at the viewpoint");
        assert_eq!(item["params"][3].as_f64(), v["properties"]["yaw_deg"].as_f64(), "PX4 turns to the viewpoint's yaw");
    }
    // DJI routes and tractor terminals do not take inspections
    let r = app.client.get(app.url(&format!("/api/v1/plans/{plan_id}/trajectory?format=wpml"))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 422);

    // the planners' list offers it
    let (_, planners) = app.get("/api/v1/planners").await;
    assert!(planners.as_array().unwrap().iter().any(|p| p["id"] == "inspection" && p["parameters"].as_array().unwrap().iter().any(|q| q["name"] == "budget")));
    app.stop().await;
}

/// A barn drawn away from every field cannot be seen from inside one: the plan says so, in
/// those words, instead of asking for a wider range.
#[tokio::test]
async fn structures_beyond_the_fields_reach_are_named_as_the_cause() {
    let app = TestApp::spawn().await;
    let mut mission = barn_mission();
    let frame = LocalFrame::new(8.55, 47.37);
    let far = |x: f64, y: f64| {
        let [lon, lat] = frame.to_wgs84(Coord { x: x + 400.0, y });
        json!([lon, lat])
    };
    mission["structures"]["features"][0]["geometry"]["coordinates"] = json!([[far(-12.0, -6.0), far(12.0, -6.0), far(12.0, 6.0), far(-12.0, 6.0), far(-12.0, -6.0)]]);
    mission["structures"]["features"].as_array_mut().unwrap().truncate(1);
    let id = app.create_mission(&mission).await;
    let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"planner": "inspection", "budget": {"max_length_m": 3000}})).await;
    assert_eq!(status, 202, "{plan}");
    let done = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!((done["status"].as_str(), done["error_code"].as_str()), (Some("failed"), Some("targets_outside_area")), "{done}");
    assert!(done["error"].as_str().unwrap().contains("inside a field"), "{done}");
    app.stop().await;
}

#[tokio::test]
async fn inspection_requests_are_refused_with_their_place() {
    let app = TestApp::spawn().await;
    let mission = barn_mission();
    // missions: each structure needs a height, and names are unique
    let mut bad = mission.clone();
    bad["structures"]["features"][0]["properties"].as_object_mut().unwrap().remove("height_m");
    let (status, body) = app.post("/api/v1/missions", &bad).await;
    assert_eq!((status, body["pointer"].as_str()), (422, Some("/structures/features/0/properties/height_m")), "{body}");
    let mut bad = mission.clone();
    bad["structures"]["features"][1]["properties"]["name"] = json!("barn");
    let (status, body) = app.post("/api/v1/missions", &bad).await;
    assert_eq!((status, body["code"].as_str()), (422, Some("structure_name_twice")), "{body}");
    let mut bad = mission.clone();
    bad["structures"]["features"][1]["properties"].as_object_mut().unwrap().remove("radius_m");
    let (status, body) = app.post("/api/v1/missions", &bad).await;
    assert_eq!((status, body["code"].as_str()), (422, Some("radius_missing")), "{body}");

    // a 3D model that does not read names its line
    let mut bad = mission.clone();
    bad["structures"]["features"][1]["properties"] = json!({"name": "silo", "obj": "v 0 0 0\nf 1 2 3\n"});
    let (status, body) = app.post("/api/v1/missions", &bad).await;
    assert_eq!((status, body["code"].as_str(), body["pointer"].as_str()), (422, Some("invalid_model"), Some("/structures/features/1/properties/obj")), "{body}");
    assert!(body["detail"].as_str().unwrap().contains("line 2"), "{body}");

    let id = app.create_mission(&mission).await;
    let mut bare = mission.clone();
    bare.as_object_mut().unwrap().remove("structures");
    let bare_id = app.create_mission(&bare).await;
    let base = json!({"planner": "inspection", "budget": {"max_length_m": 300}});
    let with = |extra: Value| {
        let mut p = base.clone();
        p.as_object_mut().unwrap().extend(extra.as_object().unwrap().clone());
        p
    };
    let frame = LocalFrame::new(8.55, 47.37);
    let inside_the_barn = frame.to_wgs84(Coord { x: 0.0, y: 0.0 });
    let cases: Vec<(&str, Value, &str, &str)> = vec![
        (&bare_id, base.clone(), "no_structures", "/structures"),
        (&id, json!({"planner": "inspection"}), "budget_missing", "/budget"),
        (&id, with(json!({"budget": {"max_length_m": 300, "max_time_s": 100}})), "budget_twice", "/budget"),
        (&id, with(json!({"budget": {"max_length_m": 1}})), "parameter_out_of_range", "/budget/max_length_m"),
        (&id, with(json!({"targets": ["shed"]})), "unknown_target", "/targets/0"),
        (&id, with(json!({"targets": [{"name": "barn", "priority": 0}]})), "parameter_out_of_range", "/targets/0/priority"),
        (&id, with(json!({"vehicle": {"profile": "generic_fixed_wing"}})), "not_a_multirotor", "/vehicle"),
        (&id, with(json!({"line_spacing_m": 20})), "not_for_inspection", "/line_spacing_m"),
        (&id, json!({"line_spacing_m": 20, "budget": {"max_length_m": 300}}), "not_an_inspection", "/budget"),
        (&id, with(json!({"start": {"position": inside_the_barn}})), "position_not_free", "/start"),
        (&id, with(json!({"inspection": {"range_m": [5, 2]}})), "range_reversed", "/inspection/range_m"),
        (&id, with(json!({"inspection": {"viewpoints": 5}})), "parameter_out_of_range", "/inspection/viewpoints"),
        (&id, with(json!({"time_limit_s": 0.01})), "parameter_out_of_range", "/time_limit_s"),
    ];
    for (mission_id, params, code, pointer) in cases {
        let (status, body) = app.post(&format!("/api/v1/missions/{mission_id}/plans"), &params).await;
        assert_eq!((status, body["code"].as_str(), body["pointer"].as_str()), (422, Some(code), Some(pointer)), "{params}: {body}");
    }
    app.stop().await;
}
