//! Farm plans over the API: a farm's fields planned as jobs of the queue and scheduled over
//! machines and days; refusals in words; cancelling; and single plans not held up by a farm.

use std::time::Duration;

use serde_json::{Value, json};

use super::interop;
use crate::common::{self, TestApp};

/// A `w` × `h` m rectangle whose south-west corner is `east` and `north` metres from (5.66°E,
/// 51.98°N).
fn rectangle(east: f64, north: f64, w: f64, h: f64) -> Value {
    let corners = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h), (0.0, 0.0)].map(|(x, y)| point(east + x, north + y));
    json!({"type": "Polygon", "coordinates": [corners]})
}

/// `[lon, lat]` `east` and `north` metres from (5.66°E, 51.98°N).
fn point(east: f64, north: f64) -> [f64; 2] {
    [5.66 + east / (111_320.0 * 51.98f64.to_radians().cos()), 51.98 + north / 111_195.0]
}

/// A farm of `n` fields 600 m apart in rows of four, of different sizes, as one mission.
fn farm_mission(n: usize) -> Value {
    let features: Vec<Value> = (0..n)
        .map(|k| {
            let (east, north) = ((k % 4) as f64 * 600.0, (k / 4) as f64 * 600.0);
            json!({"type": "Feature", "properties": {"name": format!("field {k}")}, "geometry": rectangle(east, north, 150.0 + 40.0 * (k % 3) as f64, 120.0 + 30.0 * (k % 5) as f64)})
        })
        .collect();
    json!({"name": "farm", "area": {"type": "FeatureCollection", "features": features}})
}

fn drone() -> Value {
    json!({"vehicle": {"profile": "iris"}, "line_spacing_m": 10, "altitude_m": 40})
}

fn machines() -> Value {
    json!([{"name": "north", "depot": point(-70.0, -110.0), "hours_per_day": 0.5, "road_speed_mps": 12},
           {"name": "south", "depot": point(1_700.0, 1_700.0), "hours_per_day": 0.5}])
}

/// Polls a farm plan until it is no longer planning.
async fn wait_farm(app: &TestApp, id: &str) -> Value {
    for _ in 0..2400 {
        let (status, farm) = app.get(&format!("/api/v1/farm-plans/{id}")).await;
        assert_eq!(status, 200, "{farm}");
        if farm["status"] != "planning" {
            return farm;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    panic!("farm plan {id} did not finish planning");
}

#[tokio::test]
async fn a_farm_is_planned_field_by_field_and_scheduled_over_machines_and_days() {
    let app = TestApp::spawn().await;
    let mission = app.create_mission(&farm_mission(10)).await;
    // the last field over terrain the mission has none of: refused, listed, and the farm goes on
    let request = json!({"name": "spring", "mission_id": mission, "machines": machines(),
        "window": {"start_date": "2027-04-12", "days": 3, "day_start": "08:00"}, "params": drone(),
        "groups": [{"fields": [9], "params": {"vehicle": {"profile": "iris"}, "line_spacing_m": 10, "altitude_m": 40, "altitude_reference": "terrain"}}]});
    let (status, farm) = app.post("/api/v1/farm-plans", &request).await;
    assert_eq!(status, 202, "{farm}");
    assert_eq!((farm["fields_total"].as_u64(), farm["fields"][9]["error_code"].as_str()), (Some(10), Some("terrain_missing")), "{farm}");
    assert_eq!(farm["fields"][3]["name"], "field 3");
    let farm = wait_farm(&app, farm["id"].as_str().unwrap()).await;
    assert_eq!(farm["status"], "scheduled", "{farm}");
    assert_eq!(farm["fields_done"], 10);
    let schedule = &farm["schedule"];
    assert_eq!(schedule["unscheduled"].as_array().unwrap().iter().map(|u| u["field"].as_u64().unwrap()).collect::<Vec<_>>(), [9], "{schedule}");
    // each planned field worked for its plan's duration, by one machine
    let mut worked = [0.0; 10];
    let mut by = [None; 10];
    for (k, machine) in schedule["machines"].as_array().unwrap().iter().enumerate() {
        for day in machine["days"].as_array().unwrap() {
            for leg in day["legs"].as_array().unwrap().iter().filter(|l| l["kind"] == "work") {
                let i = leg["field"].as_u64().unwrap() as usize;
                worked[i] += leg["end_s"].as_f64().unwrap() - leg["start_s"].as_f64().unwrap();
                assert!(by[i].is_none_or(|m| m == k), "field {i} worked by two machines");
                by[i] = Some(k);
            }
        }
    }
    for field in &farm["fields"].as_array().unwrap()[..9] {
        let i = field["index"].as_u64().unwrap() as usize;
        assert_eq!(field["status"], "succeeded", "{field}");
        let (_, plan) = app.get(field["plan_url"].as_str().unwrap()).await;
        let duration = plan["stats"]["duration_s"].as_f64().unwrap();
        assert!((worked[i] - duration).abs() < 0.01, "field {i}: worked {} s, its plan takes {duration} s", worked[i]);
    }
    // half an hour a day: the work takes days, each from the depot and back
    assert!(schedule["days_used"].as_u64().unwrap() >= 2, "{schedule}");
    assert!(schedule["makespan_s"].as_f64().unwrap() >= schedule["lower_bound_s"].as_f64().unwrap());
    assert_eq!(schedule["machines"][0]["days"][0]["date"], "2027-04-12");
    assert!(schedule["machines"][0]["days"][0]["legs"][0]["start"].as_str().unwrap().starts_with("08:00"));
    // the CSV: a row per leg
    let legs: usize = schedule["machines"].as_array().unwrap().iter().flat_map(|m| m["days"].as_array().unwrap()).map(|d| d["legs"].as_array().unwrap().len()).sum();
    let r = app.client.get(app.url(farm["schedule_csv_url"].as_str().unwrap())).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    assert!(r.headers()["content-type"].to_str().unwrap().starts_with("text/csv"));
    let csv = r.text().await.unwrap();
    assert!(csv.starts_with("machine,day,date,start,end,kind,field_index,field,distance_m,finishes_field\n"), "{csv}");
    assert_eq!(csv.lines().count(), legs + 1);
    assert!(csv.contains(",work,3,field 3,"), "{csv}");
    // the farm's TaskData, read by the isoxml library: each planned field a partfield with its
    // swaths, a task for each stretch of a machine's day on one field
    let r = app.client.get(app.url(&format!("/api/v1/farm-plans/{}/taskdata", farm["id"].as_str().unwrap()))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let dir = interop::temp_dir();
    std::fs::write(dir.join("farm-taskdata.zip"), r.bytes().await.unwrap()).unwrap();
    let mut lines = 0;
    for field in &farm["fields"].as_array().unwrap()[..9] {
        lines += app.get(field["plan_url"].as_str().unwrap()).await.1["stats"]["sweep_lines"].as_u64().unwrap();
    }
    let tasks: usize = schedule["machines"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|m| m["days"].as_array().unwrap())
        .map(|d| {
            let mut worked: Vec<u64> = d["legs"].as_array().unwrap().iter().filter(|l| l["kind"] == "work").map(|l| l["field"].as_u64().unwrap()).collect();
            worked.dedup();
            worked.len()
        })
        .sum();
    let manifest =
        json!({"files": [{"file": "farm-taskdata.zip", "format": "isoxml", "fields": 9, "holes": 0, "zones": 0, "swath_width_mm": 10_000.0, "lines": lines, "tasks": tasks}]});
    std::fs::write(dir.join("manifest.json"), manifest.to_string()).unwrap();
    interop::run(std::process::Command::new("node").arg(interop::interop_dir().join("check_isoxml.mjs")).arg(&dir));
    // a flight plan per machine and day: every sweep of every field's plan flown on one day
    let farm_id = farm["id"].as_str().unwrap();
    let mut sweeps_planned = 0;
    for field in &farm["fields"].as_array().unwrap()[..9] {
        let (_, trajectory) = app.get(&format!("{}/trajectory", field["plan_url"].as_str().unwrap())).await;
        sweeps_planned += trajectory["features"].as_array().unwrap().iter().filter(|f| f["properties"]["kind"] == "sweep").count();
    }
    let days_worked: Vec<String> = schedule["machines"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|m| {
            let machine = m["machine"].as_str().unwrap().to_owned();
            m["days"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|d| d["legs"].as_array().unwrap().iter().any(|l| l["kind"] == "work"))
                .map(move |d| format!("{machine}-day-{}-{}", d["day"], d["date"].as_str().unwrap()))
        })
        .collect();
    let r = app.client.get(app.url(&format!("/api/v1/farm-plans/{farm_id}/flights?format=geojson"))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let files = coverplan::planner::archive::unzip(&r.bytes().await.unwrap()).unwrap();
    let mut names: Vec<String> = files.iter().map(|(name, _)| name.trim_end_matches(".geojson").to_owned()).collect();
    names.sort();
    let mut expected = days_worked.clone();
    expected.sort();
    assert_eq!(names, expected);
    let mut sweeps_flown = 0;
    for (name, bytes) in &files {
        let day: Value = serde_json::from_slice(bytes).unwrap();
        let features = day["features"].as_array().unwrap();
        sweeps_flown += features.iter().filter(|f| f["properties"]["kind"] == "sweep").count();
        let sorties: Vec<u64> = features.iter().filter_map(|f| f["properties"]["sortie"].as_u64()).collect();
        assert!(sorties.first() == Some(&1) && sorties.windows(2).all(|w| w[1] == w[0] || w[1] == w[0] + 1), "{name}: sorties {sorties:?}");
    }
    assert_eq!(sweeps_flown, sweeps_planned);
    // in a format of one flight a file, each sortie is a file QGroundControl loads
    let r = app.client.get(app.url(&format!("/api/v1/farm-plans/{farm_id}/flights?format=plan&firmware=px4"))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    for (name, bytes) in coverplan::planner::archive::unzip(&r.bytes().await.unwrap()).unwrap() {
        let plan: Value = serde_json::from_slice(&bytes).unwrap();
        assert!(name.ends_with(".plan") && plan["fileType"] == "Plan" && !plan["mission"]["items"].as_array().unwrap().is_empty(), "{name}");
    }
    let (status, problem) = app.get(&format!("/api/v1/farm-plans/{farm_id}/flights?format=nope")).await;
    assert_eq!((status, problem["code"].as_str()), (400, Some("unknown_format")));
    // imported back, the TaskData is a farm whose fields keep their partfields' names
    let bytes = std::fs::read(dir.join("farm-taskdata.zip")).unwrap();
    let r = app.client.post(app.url("/api/v1/missions/import?format=isoxml")).body(bytes).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 201);
    let imported: Value = r.json().await.unwrap();
    let again = json!({"mission_id": imported["id"], "machines": machines(), "window": {"start_date": "2027-04-12", "days": 3}, "params": drone()});
    let (status, farm) = app.post("/api/v1/farm-plans", &again).await;
    assert_eq!(status, 202, "{farm}");
    let mut names: Vec<&str> = farm["fields"].as_array().unwrap().iter().map(|f| f["name"].as_str().unwrap()).collect();
    names.sort_unstable();
    assert_eq!(names, (0..9).map(|k| format!("field {k}")).collect::<Vec<_>>(), "{farm}");
    let r = app.client.delete(app.url(&format!("/api/v1/farm-plans/{}", farm["id"].as_str().unwrap()))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let _ = std::fs::remove_dir_all(&dir);
    app.stop().await;
}

#[tokio::test]
async fn a_farm_of_missions_with_roads_drives_along_them() {
    let app = TestApp::spawn().await;
    let mut ids = Vec::new();
    for k in 0..3 {
        ids.push(app.create_mission(&json!({"name": format!("m{k}"), "area": rectangle(k as f64 * 800.0, 0.0, 150.0, 120.0)})).await);
    }
    // a road that comes by each field between long detours north
    let depot = point(-70.0, -110.0);
    let mut road = vec![depot];
    for k in 0..3 {
        road.extend([point(k as f64 * 800.0 - 400.0, 1_500.0), point(k as f64 * 800.0 + 75.0, 60.0)]);
    }
    let road = json!({"type": "LineString", "coordinates": road});
    let body =
        |roads: Option<&Value>| json!({"missions": ids, "machines": [{"depot": depot}], "window": {"start_date": "2027-04-12", "days": 2}, "params": drone(), "roads": roads});
    let mut transit = Vec::new();
    for roads in [None, Some(&road)] {
        let (status, farm) = app.post("/api/v1/farm-plans", &body(roads)).await;
        assert_eq!(status, 202, "{farm}");
        let farm = wait_farm(&app, farm["id"].as_str().unwrap()).await;
        assert_eq!(farm["status"], "scheduled", "{farm}");
        assert_eq!(farm["schedule"]["machines"][0]["fields"], 3);
        transit.push(farm["schedule"]["transit_m"].as_f64().unwrap());
    }
    assert!(transit[1] > transit[0] + 2_000.0, "by road {} m, straight {} m", transit[1], transit[0]);
    app.stop().await;
}

#[tokio::test]
async fn farm_requests_are_refused_in_words_where_they_are_wrong() {
    let app = TestApp::spawn().await;
    let mission = app.create_mission(&farm_mission(2)).await;
    let base = json!({"mission_id": mission, "machines": machines(), "window": {"start_date": "2027-04-12", "days": 3}, "params": drone()});
    let with = |edit: &dyn Fn(&mut Value)| {
        let mut b = base.clone();
        edit(&mut b);
        b
    };
    let cases: Vec<(Value, u16, &str, &str)> = vec![
        (with(&|b| b["missions"] = json!([mission])), 422, "fields_twice", "/mission_id"),
        (with(&|b| b["window"]["start_date"] = json!("2027-02-30")), 422, "invalid_date", "/window/start_date"),
        (with(&|b| b["machines"][1]["depot"] = json!([5.0, 95.0])), 422, "coordinates_look_swapped", "/machines/1/depot"),
        (with(&|b| b["params"]["vehicles"] = json!(2)), 422, "not_for_farm_plans", "/params/vehicles"),
        (with(&|b| b["groups"] = json!([{"fields": [2], "params": drone()}])), 422, "parameter_out_of_range", "/groups/0/fields/0"),
        (with(&|b| b["groups"] = json!([{"fields": [0], "params": drone()}, {"fields": [0], "params": drone()}])), 422, "field_twice", "/groups/1/fields/0"),
        (with(&|b| b["roads"] = json!({"type": "Point", "coordinates": [5.0, 52.0]})), 422, "invalid_geojson", "/roads"),
        (with(&|b| b["mission_id"] = json!("no-such-mission")), 404, "not_found", ""),
    ];
    for (body, status, code, pointer) in cases {
        let (got, problem) = app.post("/api/v1/farm-plans", &body).await;
        assert_eq!((got, problem["code"].as_str().unwrap_or_default()), (status, code), "{problem}");
        if !pointer.is_empty() {
            assert_eq!(problem["pointer"], pointer, "{problem}");
        }
    }
    app.stop().await;
}

#[tokio::test]
async fn a_cancelled_farm_cancels_its_fields_and_a_single_plan_is_not_held_up_by_a_farm() {
    // one worker and a cap of 3 plans: a farm's 16 fields count against neither
    let app = TestApp::spawn_with(common::fresh_db_url().await, |c| {
        c.workers = 1;
        c.max_queued = 3;
    })
    .await;
    let mission = app.create_mission(&farm_mission(16)).await;
    // fields that take a while each (every sweep direction tried), so that the farm is still
    // planning when it is cancelled however fast the machine
    let slow = json!({"vehicle": {"profile": "iris"}, "line_spacing_m": 2, "altitude_m": 40, "sweep_direction": "optimal"});
    let (status, farm) =
        app.post("/api/v1/farm-plans", &json!({"mission_id": mission, "machines": machines(), "window": {"start_date": "2027-04-12", "days": 3}, "params": slow})).await;
    assert_eq!(status, 202, "{farm}");
    let single = app.create_mission(&json!({"name": "one", "area": rectangle(0.0, 0.0, 150.0, 120.0)})).await;
    let (status, plan) = app.post(&format!("/api/v1/missions/{single}/plans"), &drone()).await;
    assert_eq!(status, 202, "{plan}");
    // the fields queued still once the single plan was (its answer comes after its commit; its
    // `created_at` is when its transaction began, which a loaded database may hold a while)
    let id = farm["id"].as_str().unwrap();
    let (_, then) = app.get(&format!("/api/v1/farm-plans/{id}")).await;
    let queued_then: Vec<&str> = then["fields"].as_array().unwrap().iter().filter(|f| f["status"] == "queued").filter_map(|f| f["plan_id"].as_str()).collect();
    let done = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(done["status"], "succeeded");
    // of those, at most one started before the single plan: the one a claim in flight as the
    // single plan was committed may have taken; a queue that left it behind the farm would
    // start every field left
    let single_started = done["started_at"].as_str().unwrap();
    let (_, now) = app.get(&format!("/api/v1/farm-plans/{id}")).await;
    assert_eq!(now["fields"].as_array().unwrap().iter().filter(|f| f["plan_id"].is_string()).count(), 16, "{now}");
    let mut started_before_it = Vec::new();
    for plan_id in queued_then {
        let (_, job) = app.get(&format!("/api/v1/plans/{plan_id}")).await;
        if let Some(started) = job["started_at"].as_str().filter(|&s| s < single_started) {
            started_before_it.push((plan_id.to_owned(), started.to_owned()));
        }
    }
    assert!(started_before_it.len() <= 1, "fields queued with the single plan started before it ({single_started}): {started_before_it:?}");
    let r = app.client.delete(app.url(&format!("/api/v1/farm-plans/{id}"))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let cancelled: Value = r.json().await.unwrap();
    assert_eq!(cancelled["status"], "cancelled", "{cancelled}");
    assert!(cancelled["fields"].as_array().unwrap().iter().all(|f| ["succeeded", "cancelled"].contains(&f["status"].as_str().unwrap())), "{cancelled}");
    let r = app.client.get(app.url(&format!("/api/v1/farm-plans/{id}/schedule.csv"))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 409);
    app.stop().await;
}
