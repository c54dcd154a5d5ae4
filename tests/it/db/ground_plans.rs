//! A farm system's request for a ground vehicle end to end over the API (a field with a pond,
//! a 6 m sprayer, 7 m turns, two headland passes) down to the tractor terminal's ISOXML. The
//! ground planner's own properties are the planner crate's `tests/it/ground_plans.rs`.

use coverplan::planner::frame::LocalFrame;
use geo::{Centroid, Coord, LineString, Polygon};
use serde_json::{Value, json};

use crate::common::{self, TestApp};

/// The local frame of a polygon's outer ring, and the ring in it.
fn outer_ring_in_local_frame(area: &Value) -> (LocalFrame, Polygon) {
    let ring: Vec<[f64; 2]> = area["coordinates"][0].as_array().unwrap().iter().map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()]).collect();
    let frame = LocalFrame::centred_on(ring.iter().copied());
    let local: LineString = ring.iter().map(|&[lon, lat]| frame.to_local(lon, lat)).collect();
    (frame, Polygon::new(local, vec![]))
}

/// The issue's farm system: a field with a pond, a 6 m sprayer turning on 7 m, two headland
/// passes, over the API; the plan stays in the field and goes to the tractor terminal.
#[tokio::test]
async fn a_sprayer_plan_with_a_pond_goes_to_the_tractor_terminal() {
    let app = TestApp::spawn().await;
    let mut mission = common::mission_body("real-fields/nl-parcel-b.json");
    // a pond of about 40 × 30 m near the middle of the field
    let (frame, field) = outer_ring_in_local_frame(&mission["area"]);
    let centre = field.centroid().unwrap().0;
    let pond: Vec<Value> = [(-20.0, -15.0), (20.0, -15.0), (20.0, 15.0), (-20.0, 15.0), (-20.0, -15.0)]
        .iter()
        .map(|&(x, y)| {
            let p = frame.to_wgs84(Coord { x: centre.x + x, y: centre.y + y });
            json!([p[0], p[1]])
        })
        .collect();
    mission["area"]["coordinates"].as_array_mut().unwrap().push(Value::Array(pond));
    let id = app.create_mission(&mission).await;
    let (status, plan) = app
        .post(&format!("/api/v1/missions/{id}/plans"), &json!({"vehicle": {"profile": "tractor_sprayer", "working_width_m": 6, "min_turn_radius_m": 7}, "headland_passes": 2}))
        .await;
    assert_eq!(status, 202, "{plan}");
    let plan_id = plan["id"].as_str().unwrap().to_owned();
    let done = app.wait_finished(&plan_id).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    let stats = &done["stats"];
    assert_eq!(stats["planner"], "headland");
    assert_eq!((stats["ground"]["turns_leaving_field"].as_u64(), stats["ground"]["turns_crossing_holes"].as_u64()), (Some(0), Some(0)), "{stats}");
    assert!(stats["ground"]["mainland_coverage"].as_f64().unwrap() >= 0.99, "{stats}");
    let r = app.client.get(app.url(&format!("/api/v1/plans/{plan_id}/trajectory?format=isoxml"))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let bytes = r.bytes().await.unwrap();
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes.to_vec())).unwrap();
    let mut xml = String::new();
    std::io::Read::read_to_string(&mut zip.by_name("TASKDATA/TASKDATA.XML").unwrap(), &mut xml).unwrap();
    let swaths = stats["sweep_lines"].as_u64().unwrap() as usize;
    // every swath an AB line, every headland pass a curve, the pond an interior ring
    assert_eq!(xml.matches(r#"C="1" E="4""#).count(), swaths, "AB lines");
    assert!(xml.matches(r#"C="3" E="4""#).count() >= 3, "headland curves round the edge and the pond");
    assert_eq!(xml.matches(r#"<LSG A="2""#).count(), 1, "the pond");
    app.stop().await;
}

/// The farm's guidance line goes to the terminal and comes back: a plan along an AB line and
/// one along an A+ line, with a tramline every four swaths, are exported as ISOXML (the
/// tramlines as tram lines), read by the isoxml library and imported again,
/// and the line read back is
/// the line given (point A and B to a centimetre, the bearing to 0.01°); planned again along
/// the line read back, the swaths are the same.
#[tokio::test]
async fn guidance_lines_round_trip_through_the_tractor_terminal() {
    let app = TestApp::spawn().await;
    let mission = common::mission_body("real-fields/nl-parcel-b.json");
    let (frame, field) = outer_ring_in_local_frame(&mission["area"]);
    let centre = field.centroid().unwrap().0;
    let a = frame.to_wgs84(Coord { x: centre.x - 13.7, y: centre.y + 4.2 });
    let b = frame.to_wgs84(Coord { x: centre.x + 180.0, y: centre.y + 61.0 });
    let id = app.create_mission(&mission).await;
    let metres_between = |p: [f64; 2], q: &Value| {
        let q = frame.to_local(q[0].as_f64().unwrap(), q[1].as_f64().unwrap());
        let p = frame.to_local(p[0], p[1]);
        (p.x - q.x).hypot(p.y - q.y)
    };
    let plan = |guidance: Value| {
        let app = &app;
        let id = id.clone();
        async move {
            let params = json!({"vehicle": {"profile": "tractor_sprayer", "working_width_m": 6, "min_turn_radius_m": 7}, "guidance": guidance, "tramline_every": 4});
            let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &params).await;
            assert_eq!(status, 202, "{plan}");
            let plan_id = plan["id"].as_str().unwrap().to_owned();
            let done = app.wait_finished(&plan_id).await;
            assert_eq!(done["status"], "succeeded", "{done}");
            (plan_id, done["stats"].clone())
        }
    };
    for guidance in [json!({"a": a, "b": b}), json!({"a": a, "bearing_deg": 71.234567})] {
        let (plan_id, stats) = plan(guidance.clone()).await;
        let r = app.client.get(app.url(&format!("/api/v1/plans/{plan_id}/trajectory?format=isoxml"))).send().await.unwrap();
        assert_eq!(r.status().as_u16(), 200);
        let bytes = r.bytes().await.unwrap().to_vec();
        // the isoxml library reads the same line (installed by tests/run_all.sh)
        let dir = crate::db::interop::temp_dir();
        std::fs::write(dir.join("plan-taskdata.zip"), &bytes).unwrap();
        let spec = json!({"file": "plan-taskdata.zip", "format": "isoxml", "fields": 1, "holes": 0, "zones": 0, "swath_width_mm": 6000.0,
            "lines": stats["sweep_lines"], "headland_passes": stats["ground"]["headland_passes"], "guidance": guidance, "tramlines": stats["ground"]["tramlines"]});
        let tramlines = stats["ground"]["tramlines"].as_u64().unwrap();
        assert!(tramlines >= 5, "{tramlines} tramlines of {} swaths", stats["sweep_lines"]);
        std::fs::write(dir.join("manifest.json"), json!({"files": [spec]}).to_string()).unwrap();
        let checker = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop/check_isoxml.mjs");
        let out = std::process::Command::new("node").arg(checker).arg(&dir).output().unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert!(out.status.success(), "{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        let r = app.client.post(app.url("/api/v1/missions/import?format=isoxml")).body(bytes).send().await.unwrap();
        assert_eq!(r.status().as_u16(), 201);
        let imported: Value = r.json().await.unwrap();
        let lines = imported["guidance"].as_array().unwrap();
        let line = lines.iter().find(|g| g["name"] == "AB line" || g["name"] == "A+ line").unwrap_or_else(|| panic!("no guidance line in {lines:?}"))["guidance"].clone();
        assert!(metres_between(a, &line["a"]) < 0.01, "{line} for {guidance}");
        match guidance.get("b") {
            Some(_) => assert!(metres_between(b, &line["b"]) < 0.01, "{line}"),
            None => assert!((line["bearing_deg"].as_f64().unwrap() - 71.234567).abs() < 0.01, "{line}"),
        }
        // the line read back lays the same swaths
        let (_, again) = plan(line).await;
        assert_eq!(
            (again["sweep_lines"].clone(), again["sweep_heading_deg"].as_f64().map(|h| (h * 100.0).round())),
            (stats["sweep_lines"].clone(), stats["sweep_heading_deg"].as_f64().map(|h| (h * 100.0).round()))
        );
        // (the order searched over them may differ: their ends move by a fraction of a millimetre)
        assert!((again["sweep_length_m"].as_f64().unwrap() - stats["sweep_length_m"].as_f64().unwrap()).abs() < 0.1, "{again} against {stats}");
    }
    app.stop().await;
}

/// The issue's sprayer with a 3 000 l tank: its route breaks off where the tank runs dry and
/// drives to the refill point at the field's corner; a refill point far from the field and a
/// payload on a drone are refused with the member to change.
#[tokio::test]
async fn a_sprayer_with_a_3000_l_tank_plans_its_refill_trips() {
    let app = TestApp::spawn().await;
    let mission = common::mission_body("real-fields/nl-parcel-b.json");
    let corner = mission["area"]["coordinates"][0][0].clone();
    let id = app.create_mission(&mission).await;
    let sprayer = |refill: Value| {
        json!({"vehicle": {"profile": "tractor_sprayer", "working_width_m": 6, "min_turn_radius_m": 7}, "headland_passes": 2,
            "payload": {"capacity": 3000, "rate_per_ha": 1500, "refill_points": [refill]}})
    };
    let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &sprayer(corner.clone())).await;
    assert_eq!(status, 202, "{plan}");
    let plan_id = plan["id"].as_str().unwrap().to_owned();
    let done = app.wait_finished(&plan_id).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    let payload = &done["stats"]["ground"]["payload"];
    let (amount, trips) = (payload["amount"].as_f64().unwrap(), payload["trips"].as_u64().unwrap());
    assert!(trips as f64 >= (amount / 3000.0).ceil() - 1.0 && trips >= 1, "{payload}");
    assert!(payload["trip_distance_m"].as_f64().unwrap() <= payload["rule_trip_distance_m"].as_f64().unwrap_or(f64::INFINITY) + 1e-6, "{payload}");
    // each trip stands a quarter of an hour at the point unless the payload says
    assert!((payload["refill_stops_s"].as_f64().unwrap() - 900.0 * trips as f64).abs() < 1e-6, "{payload}");
    // every trip ends at the corner
    let r = app.client.get(app.url(&format!("/api/v1/plans/{plan_id}/trajectory"))).send().await.unwrap();
    let trajectory: Value = r.json().await.unwrap();
    let ends: Vec<Value> = trajectory["features"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["properties"]["refill"] == true)
        .map(|f| f["geometry"]["coordinates"].as_array().unwrap().last().unwrap().clone())
        .collect();
    assert_eq!(ends.len() as u64, trips);
    let (frame, _) = outer_ring_in_local_frame(&mission["area"]);
    let at = |p: &Value| frame.to_local(p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
    assert!(ends.iter().all(|e| { (at(e) - at(&corner)).x.hypot((at(e) - at(&corner)).y) < 0.05 }), "{ends:?}");
    // resuming it is refused in words (the tank's level at the cut is not carried)
    let (status, problem) = app.post(&format!("/api/v1/plans/{plan_id}/resume"), &json!({"at": {"seq": 3, "fraction": 0.5}})).await;
    assert_eq!((status, problem["code"].as_str()), (422, Some("not_resumable")), "{problem}");
    // a kilometre east of the corner: too far
    let far = frame.to_wgs84(at(&corner) + Coord { x: 1000.0, y: 0.0 });
    let (status, problem) = app.post(&format!("/api/v1/missions/{id}/plans"), &sprayer(json!(far))).await;
    assert_eq!((status, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some("refill_point_far"), Some("/payload/refill_points/0")), "{problem}");
    let mut too_long = sprayer(corner.clone());
    too_long["payload"]["refill_s"] = json!(86_400);
    let (status, problem) = app.post(&format!("/api/v1/missions/{id}/plans"), &too_long).await;
    assert_eq!((status, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some("parameter_out_of_range"), Some("/payload/refill_s")), "{problem}");
    let drone = json!({"line_spacing_m": 20, "payload": {"capacity": 10, "rate_per_ha": 10, "refill_points": [corner]}});
    let (status, problem) = app.post(&format!("/api/v1/missions/{id}/plans"), &drone).await;
    assert_eq!((status, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some("not_a_ground_vehicle"), Some("/payload")), "{problem}");
    app.stop().await;
}

/// Two tractors share a field: each works a band of it (the first the headland passes too), the
/// whole field is worked, they never come within the working width of each other at the same
/// time, and the last is done well before one tractor alone; a tractor and a drone do not share
/// a field.
#[tokio::test]
async fn two_tractors_share_a_field() {
    let app = TestApp::spawn().await;
    let mission = common::mission_body("real-fields/nl-parcel-17ha.json");
    let id = app.create_mission(&mission).await;
    let tractor = json!({"profile": "tractor_sprayer", "working_width_m": 6, "min_turn_radius_m": 7});
    let mut done = Vec::new();
    for params in [json!({"vehicle": tractor, "headland_passes": 2}), json!({"fleet": [tractor, tractor], "headland_passes": 2})] {
        let (status, plan) = app.post(&format!("/api/v1/missions/{id}/plans"), &params).await;
        assert_eq!(status, 202, "{plan}");
        let finished = app.wait_finished(plan["id"].as_str().unwrap()).await;
        assert_eq!(finished["status"], "succeeded", "{finished}");
        done.push(finished["stats"].clone());
    }
    let (alone, shared) = (&done[0], &done[1]);
    assert_eq!(shared["vehicles"].as_array().unwrap().len(), 2, "{shared}");
    assert!(shared["vehicles"].as_array().unwrap().iter().all(|v| v["length_m"].as_f64().unwrap() > 0.0), "{shared}");
    assert_eq!(shared["conflicts"].as_array().map(Vec::len), Some(0), "{shared}");
    assert!(shared["ground"]["mainland_coverage"].as_f64().unwrap() >= 0.99, "{shared}");
    let makespan = shared["makespan_s"].as_f64().unwrap();
    assert!(makespan < 0.65 * alone["duration_s"].as_f64().unwrap(), "two tractors done at {makespan} s, one alone at {}", alone["duration_s"]);
    let mixed = json!({"fleet": [tractor, {"profile": "iris"}]});
    let (status, problem) = app.post(&format!("/api/v1/missions/{id}/plans"), &mixed).await;
    assert_eq!((status, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some("fleet_mixed"), Some("/fleet/1")), "{problem}");
    app.stop().await;
}
