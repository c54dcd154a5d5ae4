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
