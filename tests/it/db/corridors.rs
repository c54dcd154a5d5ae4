//! A corridor over the API: a road drawn as a LineString with its width, planned with planner
//! `corridor` and written as a QGroundControl plan. The planner's own properties are the
//! planner crate's `tests/it/corridors.rs`.

use coverplan::planner::frame::LocalFrame;
use geo::Coord;
use serde_json::{Value, json};

use crate::common::TestApp;

/// A road 2 km long with a bend, in WGS84.
fn road(frame: &LocalFrame) -> Vec<Value> {
    [(0.0, 0.0), (900.0, 0.0), (1400.0, 600.0), (1900.0, 650.0)].iter().map(|&(x, y)| json!(frame.to_wgs84(Coord { x, y }))).collect()
}

#[tokio::test]
async fn a_road_with_its_width_is_planned_along_its_centre_line() {
    let app = TestApp::spawn().await;
    let frame = LocalFrame::new(5.2, 52.1);
    let mission = json!({"name": "road", "area": {"type": "Feature", "properties": {"width_m": 40}, "geometry": {"type": "LineString", "coordinates": road(&frame)}}});
    let id = app.create_mission(&mission).await;
    let (status, plan) =
        app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"planner": "corridor", "line_spacing_m": 15, "altitude_m": 60, "vehicle": {"profile": "iris"}})).await;
    assert_eq!(status, 202, "{plan}");
    let plan = app.wait_finished(plan["id"].as_str().unwrap()).await;
    assert_eq!(plan["status"], "succeeded", "{plan}");
    let stats = &plan["stats"];
    assert!(stats["coverage_ratio"].as_f64().unwrap() >= 0.995, "{stats}");
    // three lines 2 km long, back and forth
    let length = stats["length_m"].as_f64().unwrap();
    assert!((3.0 * 2000.0..3.0 * 2200.0 + 1000.0).contains(&length), "{length} m flown");
    let r = app.client.get(app.url(&format!("/api/v1/plans/{}/trajectory?format=plan", plan["id"].as_str().unwrap()))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let qgc: Value = r.json().await.unwrap();
    assert!(qgc["mission"]["items"].as_array().is_some_and(|items| items.len() > 6), "{qgc}");

    // a polygon mission has no corridor for the planner
    let field = json!({"name": "field", "area": {"type": "Polygon", "coordinates": [[[5.2, 52.1], [5.21, 52.1], [5.21, 52.11], [5.2, 52.1]]]}});
    let id = app.create_mission(&field).await;
    let (status, problem) = app.post(&format!("/api/v1/missions/{id}/plans"), &json!({"planner": "corridor", "line_spacing_m": 15, "vehicle": {"profile": "iris"}})).await;
    assert_eq!((status, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some("no_corridor"), Some("/planner")), "{problem}");
    // a line without its width is refused where it is
    let no_width = json!({"name": "x", "area": {"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": road(&frame)}}]}});
    let (status, problem) = app.post("/api/v1/missions", &no_width).await;
    assert_eq!((status, problem["code"].as_str(), problem["pointer"].as_str()), (422, Some("corridor_width_missing"), Some("/area/features/0/properties/width_m")), "{problem}");
    app.stop().await;
}
