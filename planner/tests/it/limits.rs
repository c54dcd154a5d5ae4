//! A controller's waypoint limit (`max_waypoints`) over the random fields, every pattern: each
//! mission of a MAVLink file and of DJI WPML holds at most the limit, begins where the one
//! before ended, and together they fly every line end of the flight written without a limit.

use coverplan_planner::export::{self, AltitudeFrame, ExportOptions, ExportRequest, Firmware};
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanParams, Stop, archive, plan};
use proptest::prelude::*;
use serde_json::{Value, json};

fn field(k: usize) -> Value {
    let read = |path: &str| -> Value { serde_json::from_slice(&std::fs::read(format!("{}/../tests/fixtures/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()).unwrap() };
    let index = read("random-fields/index.json");
    let names: Vec<&str> = index.as_array().unwrap().iter().map(|e| e["file"].as_str().unwrap()).collect();
    read(&format!("random-fields/{}", names[k % names.len()]))
}

/// The files of an export: the missions of a zip of them, or the one file (a KMZ is a zip
/// itself).
fn files(bytes: Vec<u8>) -> Vec<Vec<u8>> {
    if !archive::is_zip(&bytes) {
        return vec![bytes];
    }
    let entries = archive::unzip(&bytes).unwrap();
    if entries.iter().any(|e| e.0.starts_with("wpmz/")) { vec![bytes] } else { entries.into_iter().map(|f| f.1).collect() }
}

/// The waypoints (`[lat, lon]`) and the item count of a `QGC WPL 110` file.
fn waypoints(text: &[u8]) -> (Vec<[f64; 2]>, usize) {
    let items = export::wpl::read(std::str::from_utf8(text).unwrap()).unwrap();
    let points = items.iter().filter(|i| i.command == 16).filter_map(|i| i.position).map(|p| [p[0], p[1]]).collect();
    (points, items.len())
}

/// The waypoints (`[lon, lat]`) of a DJI WPML file, in order.
fn placemarks(kmz: &[u8]) -> Vec<[f64; 2]> {
    let parts = archive::unzip(kmz).unwrap();
    let waylines = String::from_utf8(parts.into_iter().find(|p| p.0 == "wpmz/waylines.wpml").unwrap().1).unwrap();
    waylines
        .split("<coordinates>")
        .skip(1)
        .map(|s| {
            let text = s.split("</coordinates>").next().unwrap();
            let v: Vec<f64> = text.split(',').map(|x| x.trim().parse().unwrap()).collect();
            [v[0], v[1]]
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10))]
    #[test]
    fn missions_keep_within_the_controllers_limit(k in 0usize..64, pattern in prop::sample::select(vec!["grid", "double_grid", "oblique"]), limit in 12usize..120, fixed_wing in any::<bool>()) {
        let field = field(k);
        let mission = MissionGeometry { home: Some([field["area"]["coordinates"][0][0][0].as_f64().unwrap(), field["area"]["coordinates"][0][0][1].as_f64().unwrap()]), no_fly_zones: Some(&field["no_fly_zones"]), ..MissionGeometry::area(&field["area"]) };
        let fixed_wing = fixed_wing && pattern != "oblique";
        let profile = if fixed_wing { "generic_fixed_wing" } else { "iris" };
        let params: PlanParams = serde_json::from_value(json!({
            "vehicle": {"profile": profile, "battery_wh": 90000}, "camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 90, "side_overlap": 0.4, "front_overlap": 0.6, "pattern": pattern,
        })).unwrap();
        let profiles = builtin_profiles();
        let Ok(out) = plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()) else { return Ok(()) };

        let export = |format: &str, max_waypoints: Option<usize>| {
            let options = ExportOptions { firmware: Firmware::Ardupilot, altitude_frame: AltitudeFrame::Amsl, altitude_m: None, max_waypoints };
            let request = ExportRequest { name: "limit", mission: mission.clone(), params: &params, profiles: &profiles, trajectory: &out.trajectory, options };
            files(export::export(format, &request).unwrap().bytes)
        };
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-7 && (a[1] - b[1]).abs() < 1e-7;
        // MAVLink: every part within the limit, each beginning where the last ended
        let whole: Vec<[f64; 2]> = export("waypoints", None).iter().flat_map(|f| waypoints(f).0).collect();
        let parts: Vec<(Vec<[f64; 2]>, usize)> = export("waypoints", Some(limit)).iter().map(|f| waypoints(f)).collect();
        for (k, (points, count)) in parts.iter().enumerate() {
            prop_assert!(*count <= limit, "mission {k}: {count} items, the limit {limit}");
            if k > 0 {
                let before = parts[k - 1].0.last().copied().unwrap();
                prop_assert!(close(points[0], before), "mission {k} begins at {:?}, the one before ended at {before:?}", points[0]);
            }
        }
        // the limited missions fly the whole flight's waypoints but the trigger points, in order
        let flown: Vec<[f64; 2]> = parts.iter().flat_map(|p| p.0.clone()).collect();
        let mut at = 0;
        for p in &flown {
            while at < whole.len() && !close(whole[at], *p) {
                at += 1;
            }
            prop_assert!(at < whole.len(), "a mission flies {p:?}, which the whole flight does not (or not in this order)");
        }
        prop_assert!(flown.len() >= whole.len() / 3, "{} of {} waypoints flown", flown.len(), whole.len());
        // DJI WPML (multirotors): at most `limit` placemarks each, continuing
        if !fixed_wing {
            let parts: Vec<Vec<[f64; 2]>> = export("wpml", Some(limit)).iter().map(|f| placemarks(f)).collect();
            for (k, points) in parts.iter().enumerate() {
                prop_assert!(points.len() <= limit, "WPML mission {k}: {} waypoints, the limit {limit}", points.len());
                if k > 0 {
                    prop_assert!(close(points[0], *parts[k - 1].last().unwrap()), "WPML mission {k} does not begin where the one before ended");
                }
            }
        }
    }
}
