//! Elevation models on the real app: uploaded to a mission (GeoTIFF, SRTM), refused with a clear
//! problem and nothing stored, planned over at a height above ground, exported in AMSL and
//! terrain frames, deleted with the mission.

use crate::common::{TestApp, fixture};
use serde_json::{Value, json};

fn model_bytes(name: &str) -> Vec<u8> {
    std::fs::read(format!("{}/tests/fixtures/terrain/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

async fn put_model(app: &TestApp, mission: &str, bytes: Vec<u8>, media_type: &str, name: Option<&str>) -> (u16, Value) {
    let query = name.map(|n| format!("?name={n}")).unwrap_or_default();
    let r = app.client.put(app.url(&format!("/api/v1/missions/{mission}/terrain{query}"))).header("content-type", media_type).body(bytes).send().await.unwrap();
    (r.status().as_u16(), r.json().await.unwrap_or(Value::Null))
}

async fn terrain_mission(app: &TestApp, name: &str) -> String {
    let f = fixture(&format!("terrain/{name}.json"));
    app.create_mission(&json!({"name": f["name"], "area": f["area"], "home": f["home"]})).await
}

/// `hills-11.tif` with its CRS changed to the British National Grid (EPSG:27700).
fn in_another_crs() -> Vec<u8> {
    let mut bytes = model_bytes("hills-11.tif");
    let key: Vec<u8> = [3072u16, 0, 1, 32632].iter().flat_map(|v| v.to_le_bytes()).collect();
    let at = bytes.windows(8).position(|w| w == key.as_slice()).expect("the ProjectedCSType key");
    bytes[at + 6..at + 8].copy_from_slice(&27700u16.to_le_bytes());
    bytes
}

#[tokio::test]
async fn a_mission_is_planned_over_its_elevation_model_and_flown_as_planned() {
    let app = TestApp::spawn().await;
    let mission = terrain_mission(&app, "hills-11").await;
    let path = format!("/api/v1/missions/{mission}/terrain");
    assert_eq!(app.get(&path).await.0, 404);

    // refused, with nothing stored: not a model, another CRS, a model elsewhere, a JSON body
    let (s, p) = put_model(&app, &mission, b"not a tiff".to_vec(), "image/tiff", None).await;
    assert_eq!((s, p["code"].as_str()), (422, Some("invalid_terrain")), "{p}");
    let (s, p) = put_model(&app, &mission, in_another_crs(), "image/tiff", None).await;
    assert_eq!((s, p["code"].as_str()), (422, Some("unsupported_crs")), "{p}");
    assert!(p["detail"].as_str().unwrap().contains("EPSG:27700"), "{p}");
    let (s, p) = put_model(&app, &mission, model_bytes("cliff-11.tif"), "image/tiff", None).await;
    assert_eq!((s, p["code"].as_str()), (422, Some("terrain_not_covering")), "{p}");
    let (s, p) = put_model(&app, &mission, model_bytes("hills-11.tif"), "application/json", None).await;
    assert_eq!((s, p["code"].as_str()), (415, Some("unsupported_media_type")), "{p}");
    assert_eq!(app.get(&path).await.0, 404, "nothing was stored");

    let (s, stored) = put_model(&app, &mission, model_bytes("hills-11.tif"), "image/tiff", Some("hills.tif")).await;
    assert_eq!(s, 200, "{stored}");
    assert_eq!((stored["crs"].as_str(), stored["columns"].as_u64(), stored["file_name"].as_str()), (Some("EPSG:32632"), Some(260), Some("hills.tif")));
    let (s, read) = app.get(&path).await;
    assert_eq!((s, read["max_m"].as_f64()), (200, stored["max_m"].as_f64()));
    // the grid the page shades: row by row from the north, within the model's heights
    let (s, grid) = app.get(&format!("{path}/grid?size=64")).await;
    assert_eq!(s, 200, "{grid}");
    let (columns, rows) = (grid["columns"].as_u64().unwrap(), grid["rows"].as_u64().unwrap());
    assert!(columns.max(rows) == 64 && columns.min(rows) >= 2, "{columns} × {rows}");
    let heights: Vec<f64> = grid["heights"].as_array().unwrap().iter().filter_map(Value::as_f64).collect();
    assert!(heights.len() as u64 > columns * rows / 2, "most samples have a height");
    assert!(heights.iter().all(|h| *h >= read["min_m"].as_f64().unwrap() - 0.01 && *h <= read["max_m"].as_f64().unwrap() + 0.01));
    assert_eq!(app.get(&format!("{path}/grid?size=1000")).await.0, 422);

    // a plan over it keeps 60 m ± 5 m above the ground on its sweeps as it reports
    let params = json!({"altitude_m": 60, "line_spacing_m": 60, "altitude_reference": "terrain", "vehicle": {"profile": "generic_multirotor"}});
    let (s, plan) = app.post(&format!("/api/v1/missions/{mission}/plans"), &params).await;
    assert_eq!(s, 202, "{plan}");
    let plan = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(plan["status"], "succeeded", "{plan}");
    let terrain = &plan["stats"]["terrain"];
    assert_eq!(terrain["altitude_reference"], "terrain", "{plan}");
    assert!(terrain["height_above_ground_m"][0].as_f64().unwrap() >= 55.0, "{terrain}");
    let id = plan["id"].as_str().unwrap();
    let (_, trajectory) = app.get(&format!("/api/v1/plans/{id}/trajectory")).await;
    let first = &trajectory["features"][0];
    let (z, ground) = (first["geometry"]["coordinates"][1][2].as_f64().unwrap(), first["properties"]["ground_m"][1].as_f64().unwrap());
    assert!(z - ground >= 55.0 && ground > 250.0, "{first}");

    // QGroundControl: AMSL frame, home on the ground; or the terrain frame on request
    let (_, qgc) = app.get(&format!("/api/v1/plans/{id}/trajectory?format=plan")).await;
    let m = &qgc["mission"];
    assert_eq!(m["globalPlanAltitudeMode"], 2);
    let home_alt = m["plannedHomePosition"][2].as_f64().unwrap();
    assert!((home_alt - first["properties"]["ground_m"][0].as_f64().unwrap()).abs() < 0.01, "{home_alt}");
    let waypoints: Vec<&Value> = m["items"].as_array().unwrap().iter().filter(|i| i["command"] == 16).collect();
    assert!(waypoints.iter().all(|w| w["frame"] == 0 && w["AltitudeMode"] == 2), "{m}");
    let planned: Vec<f64> =
        trajectory["features"].as_array().unwrap().iter().filter_map(|f| f["geometry"]["coordinates"].as_array()).flatten().filter_map(|p| p[2].as_f64()).collect();
    assert!(waypoints.iter().all(|w| planned.iter().any(|z| (z - w["Altitude"].as_f64().unwrap()).abs() < 0.01)), "every waypoint at a planned height");
    let (_, qgc) = app.get(&format!("/api/v1/plans/{id}/trajectory?format=plan&altitude_frame=terrain")).await;
    let items = qgc["mission"]["items"].as_array().unwrap();
    assert!(items.iter().filter(|i| i["command"] == 16).all(|w| w["frame"] == 10 && (w["Altitude"].as_f64().unwrap() - 60.0).abs() <= 30.0), "{qgc}");

    // deleted: the next plan over terrain is refused saying why; the mission takes it along
    let r = app.client.delete(app.url(&path)).send().await.unwrap();
    assert_eq!(r.status(), 204);
    let (s, p) = app.post(&format!("/api/v1/missions/{mission}/plans"), &params).await;
    assert_eq!((s, p["code"].as_str()), (422, Some("terrain_missing")), "{p}");
    assert_eq!(put_model(&app, &mission, model_bytes("hills-11.tif"), "image/tiff", None).await.0, 200);
    assert_eq!(app.client.delete(app.url(&format!("/api/v1/missions/{mission}"))).send().await.unwrap().status(), 204);
    assert_eq!(app.get(&path).await.0, 404);
    app.stop().await;
}

/// The USGS model (geographic, 16-bit integers) and an SRTM tile by its name.
#[tokio::test]
async fn geographic_models_and_srtm_tiles_are_read() {
    let app = TestApp::spawn().await;
    let mission = terrain_mission(&app, "jacksboro").await;
    let (s, stored) = put_model(&app, &mission, model_bytes("jacksboro.tif"), "image/tiff", None).await;
    assert_eq!((s, stored["crs"].as_str(), stored["min_m"].as_f64()), (200, Some("EPSG:4326"), Some(236.0)), "{stored}");
    // a 3″ tile under the same mission (36–37° N, 85–84° W), flat at 400 m, zipped
    let tile: Vec<u8> = (0..1201 * 1201).flat_map(|_| 400i16.to_be_bytes()).collect();
    let zipped = {
        use std::io::Write;
        let mut w = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
        w.start_file("N36W085.hgt", zip::write::SimpleFileOptions::default()).unwrap();
        w.write_all(&tile).unwrap();
        w.finish().unwrap().into_inner()
    };
    let (s, stored) = put_model(&app, &mission, zipped, "application/zip", None).await;
    assert_eq!((s, stored["crs"].as_str(), stored["max_m"].as_f64()), (200, Some("EPSG:4326"), Some(400.0)), "{stored}");
    let (s, p) = put_model(&app, &mission, tile, "application/octet-stream", Some("elevation.hgt")).await;
    assert_eq!((s, p["code"].as_str()), (422, Some("invalid_terrain")), "{p}");
    app.stop().await;
}
