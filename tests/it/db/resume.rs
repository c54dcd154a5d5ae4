//! `POST /api/v1/plans/{id}/resume`: the plan of what a stopped flight left, from a piece of
//! the trajectory or the aircraft's position, queued like a plan and linked to its original;
//! wrong cuts are refused with the place that is wrong, and nothing is stored.

use crate::common::{TestApp, mission_body};
use serde_json::{Value, json};

async fn trajectory(app: &TestApp, plan: &str, format: &str) -> (u16, Vec<u8>) {
    let r = app.client.get(app.url(&format!("/api/v1/plans/{plan}/trajectory?format={format}"))).send().await.unwrap();
    (r.status().as_u16(), r.bytes().await.unwrap().to_vec())
}

/// The sweeps of a trajectory: seq, first and last point.
fn sweeps(fc: &Value) -> Vec<(u64, [f64; 2], [f64; 2])> {
    fc["features"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["properties"]["kind"] == "sweep")
        .map(|f| {
            let c = f["geometry"]["coordinates"].as_array().unwrap();
            let at = |p: &Value| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()];
            (f["properties"]["seq"].as_u64().unwrap(), at(&c[0]), at(&c[c.len() - 1]))
        })
        .collect()
}

/// A succeeded plan with `params` of the real field `nl-parcel-b` (its home at its first corner):
/// the mission's id, the plan, and its trajectory as GeoJSON.
async fn planned(app: &TestApp, params: Value) -> (String, Value, Value) {
    let mut body = mission_body("real-fields/nl-parcel-b.json");
    body["home"] = json!(body["area"]["coordinates"][0][0]);
    let mission = app.create_mission(&body).await;
    let (status, plan) = app.post(&format!("/api/v1/missions/{mission}/plans"), &params).await;
    assert_eq!(status, 202, "{plan}");
    let original = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(original["status"], "succeeded", "{original}");
    let fc: Value = serde_json::from_slice(&trajectory(app, original["id"].as_str().unwrap(), "geojson").await.1).unwrap();
    (mission, original, fc)
}

#[tokio::test]
async fn a_stopped_flight_is_resumed_from_a_piece_or_a_position() {
    let app = TestApp::spawn().await;
    let (mission, original, fc) = planned(&app, json!({"camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 60})).await;
    let id = original["id"].as_str().unwrap();
    let lines = sweeps(&fc);
    assert!(lines.len() >= 4, "{} lines", lines.len());
    let (seq, a, b) = lines[lines.len() / 2];
    let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    // the compass heading the line is flown on
    let heading = ((b[0] - a[0]) * a[1].to_radians().cos()).atan2(b[1] - a[1]).to_degrees().rem_euclid(360.0);
    for request in [json!({"at": {"seq": seq, "fraction": 0.5}}), json!({"position": mid, "heading_deg": heading})] {
        let (status, queued) = app.post(&format!("/api/v1/plans/{id}/resume"), &request).await;
        assert_eq!(status, 202, "{request}: {queued}");
        assert_eq!((queued["resumed_from"].as_str(), queued["mission_id"].as_str()), (Some(id), Some(mission.as_str())));
        let resumed = app.wait_finished(queued["id"].as_str().unwrap()).await;
        assert_eq!(resumed["status"], "succeeded", "{request}: {resumed}");
        let (stats, before) = (&resumed["stats"], &original["stats"]);
        let cut = &stats["resume"];
        assert_eq!(cut["seq"].as_u64(), Some(seq), "{request}: {cut}");
        assert!((cut["fraction"].as_f64().unwrap() - 0.5).abs() < 0.01, "{request}: {cut}");
        // two photos back on the cut line, then the lines after it
        assert!(cut["overlap_m"].as_f64().unwrap() > 0.0, "{cut}");
        let left = cut["original_sweep_left_m"].as_f64().unwrap() + cut["overlap_m"].as_f64().unwrap();
        assert!((stats["sweep_length_m"].as_f64().unwrap() - left).abs() < 1.0, "{stats}");
        assert!(stats["photos"].as_u64().unwrap() < before["photos"].as_u64().unwrap());
        let resumed_id = resumed["id"].as_str().unwrap();
        let again: Value = serde_json::from_slice(&trajectory(&app, resumed_id, "geojson").await.1).unwrap();
        let first = sweeps(&again)[0];
        assert!((first.2[0] - b[0]).abs() < 1e-6 && (first.2[1] - b[1]).abs() < 1e-6, "the first line flown is the cut one, to its end: {first:?}");
        // and it exports like any plan
        for format in ["waypoints", "plan", "kml", "wpml", "isoxml"] {
            let (status, bytes) = trajectory(&app, resumed_id, format).await;
            assert_eq!(status, 200, "{format}: {}", String::from_utf8_lossy(&bytes));
        }
    }
    let plans_before = app.get(&format!("/api/v1/missions/{mission}/plans")).await.1.as_array().unwrap().len();
    let far = [mid[0] + 0.05, mid[1]];
    for (request, status, code, pointer) in [
        (json!({"at": {"seq": 100_000, "fraction": 0.5}}), 422, "unknown_seq", "/at/seq"),
        (json!({"position": far}), 422, "cut_off_path", "/position"),
        (json!({}), 422, "cut_missing", "/at"),
        (json!({"at": {"seq": seq, "fraction": 0.5}, "position": mid}), 422, "cut_ambiguous", "/position"),
        (json!({"at": {"seq": seq, "fraction": 0.5}, "from": "position"}), 422, "position_missing", "/from"),
        (json!({"at": {"seq": seq, "fraction": 2}}), 422, "parameter_out_of_range", "/at/fraction"),
        (json!({"at": {"seq": lines[lines.len() - 1].0, "fraction": 1}}), 422, "nothing_left", "/at"),
    ] {
        let (got, problem) = app.post(&format!("/api/v1/plans/{id}/resume"), &request).await;
        assert_eq!((got, problem["code"].as_str(), problem["pointer"].as_str()), (status, Some(code), Some(pointer)), "{request}: {problem}");
    }
    let (status, problem) = app.post("/api/v1/plans/no-such-plan/resume", &json!({"at": {"seq": 1, "fraction": 0.5}})).await;
    assert_eq!((status, problem["code"].as_str()), (404, Some("not_found")), "{problem}");
    let plans_after = app.get(&format!("/api/v1/missions/{mission}/plans")).await.1.as_array().unwrap().len();
    assert_eq!(plans_after, plans_before, "nothing is queued on refusal");
    app.stop().await;
}

/// A tractor stopped in a swath resumes with the swaths it had left, their tramlines marked,
/// and its ISOXML task carries them to the terminal.
#[tokio::test]
async fn a_stopped_tractor_is_resumed_with_the_swaths_left() {
    let app = TestApp::spawn().await;
    let (_, original, fc) = planned(&app, json!({"vehicle": {"profile": "tractor_sprayer"}, "tramline_every": 3})).await;
    let id = original["id"].as_str().unwrap();
    let lines = sweeps(&fc);
    let (seq, _, b) = lines[lines.len() / 2];
    let (status, queued) = app.post(&format!("/api/v1/plans/{id}/resume"), &json!({"at": {"seq": seq, "fraction": 0.5}})).await;
    assert_eq!(status, 202, "{queued}");
    let resumed = app.wait_finished(queued["id"].as_str().unwrap()).await;
    assert_eq!(resumed["status"], "succeeded", "{resumed}");
    let resumed_id = resumed["id"].as_str().unwrap();
    let again: Value = serde_json::from_slice(&trajectory(&app, resumed_id, "geojson").await.1).unwrap();
    let left = sweeps(&again);
    assert_eq!(left.len(), lines.len() - lines.len() / 2, "the cut swath and every one after it");
    assert!((left[0].2[0] - b[0]).abs() < 1e-6 && (left[0].2[1] - b[1]).abs() < 1e-6, "the cut swath to its end: {:?}", left[0]);
    let tramlines =
        |fc: &Value, from: u64| fc["features"].as_array().unwrap().iter().filter(|f| f["properties"]["tramline"] == true && f["properties"]["seq"].as_u64() >= Some(from)).count();
    assert_eq!(resumed["stats"]["ground"]["tramlines"].as_u64(), Some(tramlines(&fc, seq) as u64), "{}", resumed["stats"]);
    let (status, bytes) = trajectory(&app, resumed_id, "isoxml").await;
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&bytes));
    app.stop().await;
}

/// An aircraft still in the air resumes from where it is, on the battery it has left: its first
/// sortie starts there and takes no take-off; a battery too low to fly the next line and back
/// is refused by the job in words.
#[tokio::test]
async fn an_aircraft_in_the_air_resumes_from_its_position_on_its_battery() {
    let app = TestApp::spawn().await;
    let mut body = mission_body("real-fields/nl-parcel-b.json");
    body["home"] = json!(body["area"]["coordinates"][0][0]);
    let mission = app.create_mission(&body).await;
    let (_, plan) = app.post(&format!("/api/v1/missions/{mission}/plans"), &json!({"line_spacing_m": 25, "altitude_m": 50})).await;
    let original = app.wait_finished(plan["id"].as_str().unwrap()).await;
    let id = original["id"].as_str().unwrap();
    let fc: Value = serde_json::from_slice(&trajectory(&app, id, "geojson").await.1).unwrap();
    let lines = sweeps(&fc);
    let (_, a, b) = lines[1];
    let aircraft = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    let (status, queued) = app.post(&format!("/api/v1/plans/{id}/resume"), &json!({"position": aircraft, "from": "position", "battery_remaining": 0.9})).await;
    assert_eq!(status, 202, "{queued}");
    let resumed = app.wait_finished(queued["id"].as_str().unwrap()).await;
    assert_eq!(resumed["status"], "succeeded", "{resumed}");
    let again: Value = serde_json::from_slice(&trajectory(&app, resumed["id"].as_str().unwrap(), "geojson").await.1).unwrap();
    let first = &again["features"][0]["geometry"]["coordinates"][0];
    let off = ((first[0].as_f64().unwrap() - aircraft[0]).abs(), (first[1].as_f64().unwrap() - aircraft[1]).abs());
    assert!(off.0 < 1e-6 && off.1 < 1e-6, "the flight starts where the aircraft is: {first} against {aircraft:?}");
    let (status, queued) = app.post(&format!("/api/v1/plans/{id}/resume"), &json!({"position": aircraft, "from": "position", "battery_remaining": 0.26})).await;
    assert_eq!(status, 202, "{queued}");
    let low = app.wait_finished(queued["id"].as_str().unwrap()).await;
    assert_eq!((low["status"].as_str(), low["error_code"].as_str()), (Some("failed"), Some("infeasible")), "{low}");
    assert!(low["error"].as_str().unwrap().contains("battery left"), "{low}");
    app.stop().await;
}

/// Writes a telemetry log of `plan` flown up to `seq` × `fraction` with pymavlink
/// (tests/interop/make_tlog.py), with the script's other options.
fn flown_log(plan: &Value, seq: u64, fraction: f64, options: &[&str]) -> Vec<u8> {
    let dir = crate::db::interop::temp_dir();
    let (geojson, tlog) = (dir.join("plan.geojson"), dir.join("flight.tlog"));
    std::fs::write(&geojson, plan.to_string()).unwrap();
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop/make_tlog.py");
    let out = std::process::Command::new(crate::db::interop::python())
        .arg(script)
        .arg(&geojson)
        .arg(&tlog)
        .args(["--seq", &seq.to_string(), "--fraction", &fraction.to_string()])
        .args(options)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let log = std::fs::read(tlog).unwrap();
    std::fs::remove_dir_all(dir).ok();
    log
}

async fn post_log(app: &TestApp, plan: &str, query: &str, log: Vec<u8>) -> (u16, Value) {
    let url = app.url(&format!("/api/v1/plans/{plan}/resume{query}"));
    let r = app.client.post(url).header("content-type", "application/octet-stream").body(log).send().await.unwrap();
    (r.status().as_u16(), r.json().await.unwrap_or(Value::Null))
}

/// A flight's own log as the body: the cut is where its photos stop, a line it flew off its
/// track is flown again, and logs that are not this plan's flight are refused in words.
#[tokio::test]
async fn a_flight_log_resumes_what_the_flight_did_not_image() {
    let app = TestApp::spawn().await;
    let mut body = mission_body("real-fields/nl-parcel-b.json");
    body["home"] = json!(body["area"]["coordinates"][0][0]);
    let mission = app.create_mission(&body).await;
    let (_, plan) = app.post(&format!("/api/v1/missions/{mission}/plans"), &json!({"camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 60})).await;
    let original = app.wait_finished(plan["id"].as_str().unwrap()).await;
    let id = original["id"].as_str().unwrap();
    let fc: Value = serde_json::from_slice(&trajectory(&app, id, "geojson").await.1).unwrap();
    let lines = sweeps(&fc);
    let (seq, a, b) = lines[lines.len() / 2];
    let line_m = ((b[0] - a[0]) * 111_320.0 * a[1].to_radians().cos()).hypot((b[1] - a[1]) * 111_320.0);
    let spacing = original["stats"]["line_spacing_m"].as_f64().unwrap();
    // stopped halfway along a line: resumed at its last photo there, two photos back
    let (status, queued) = post_log(&app, id, "", flown_log(&fc, seq, 0.5, &[])).await;
    assert_eq!(status, 202, "{queued}");
    let resumed = app.wait_finished(queued["id"].as_str().unwrap()).await;
    assert_eq!(resumed["status"], "succeeded", "{resumed}");
    let cut = &resumed["stats"]["resume"];
    assert_eq!(cut["seq"].as_u64(), Some(seq), "{cut}");
    let fraction = cut["fraction"].as_f64().unwrap();
    assert!(fraction <= 0.5 + 1e-6 && fraction > 0.5 - 30.0 / line_m, "the last photo before the stop: {cut}");
    assert!(cut.get("redone_m").is_none(), "every line before the cut was imaged: {cut}");
    // the track the log flew comes with the plan, and the plan exports like any other
    let resumed_id = resumed["id"].as_str().unwrap();
    let again: Value = serde_json::from_slice(&trajectory(&app, resumed_id, "geojson").await.1).unwrap();
    let flown = again["features"].as_array().unwrap().iter().find(|f| f["properties"]["kind"] == "flown").expect("the track flown");
    assert_eq!(flown["geometry"]["type"], "MultiLineString");
    for format in ["waypoints", "plan", "kml", "wpml", "isoxml"] {
        let (status, bytes) = trajectory(&app, resumed_id, format).await;
        assert_eq!(status, 200, "{format}: {}", String::from_utf8_lossy(&bytes));
    }
    // a line flown half a spacing off its track is flown again
    let (first_seq, ..) = lines[1];
    let offset = format!("{}", spacing / 2.0);
    let (status, queued) = post_log(&app, id, "?photos_back=1", flown_log(&fc, seq, 0.5, &["--offset-seq", &first_seq.to_string(), "--offset-m", &offset])).await;
    assert_eq!(status, 202, "{queued}");
    let resumed = app.wait_finished(queued["id"].as_str().unwrap()).await;
    let cut = &resumed["stats"]["resume"];
    assert_eq!(cut["seq"].as_u64(), Some(seq), "{cut}");
    assert!(
        cut["redone_m"]
            .as_f64()
            .is_some_and(|m| m > 0.9 * ((lines[1].2[0] - lines[1].1[0]) * 111_320.0 * a[1].to_radians().cos()).hypot((lines[1].2[1] - lines[1].1[1]) * 111_320.0)),
        "{cut}"
    );
    // the same log without photos: the track stands for them
    let (status, queued) = post_log(&app, id, "", flown_log(&fc, seq, 0.5, &["--no-photos"])).await;
    assert_eq!(status, 202, "{queued}");
    let resumed = app.wait_finished(queued["id"].as_str().unwrap()).await;
    assert_eq!(resumed["stats"]["resume"]["seq"].as_u64(), Some(seq), "{resumed}");
    // logs that are not this plan's flight, or not readable
    let plans_before = app.get(&format!("/api/v1/missions/{mission}/plans")).await.1.as_array().unwrap().len();
    for (options, code) in [
        (&["--truncate"][..], "log_unreadable"),
        (&["--vehicle", "plane"][..], "log_other_vehicle"),
        (&["--no-position"][..], "log_without_position"),
        (&["--shift-m", "5000"][..], "log_off_path"),
    ] {
        let (status, problem) = post_log(&app, id, "", flown_log(&fc, seq, 0.5, options)).await;
        assert_eq!((status, problem["code"].as_str()), (422, Some(code)), "{options:?}: {problem}");
        assert!(problem["detail"].as_str().is_some_and(|d| d.len() > 20), "{problem}");
    }
    let (status, problem) = post_log(&app, id, "", b"this is not a flight log at all".to_vec()).await;
    assert_eq!((status, problem["code"].as_str()), (422, Some("log_unreadable")), "{problem}");
    let r = app.client.post(app.url(&format!("/api/v1/plans/{id}/resume"))).header("content-type", "text/plain").body("hello").send().await.unwrap();
    assert_eq!(r.status().as_u16(), 415);
    let plans_after = app.get(&format!("/api/v1/missions/{mission}/plans")).await.1.as_array().unwrap().len();
    assert_eq!(plans_after, plans_before, "nothing is queued on refusal");
    app.stop().await;
}
