//! Several fields flown by `line_gtsp` at headings of their own (docs/methods.md, routing §6):
//! the combinations are screened by the sum of each field's own quick route, and the screen
//! must still let through each field's best heading.

use coverplan_planner::frame::LocalFrame;
use coverplan_planner::geom::axial_difference;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanParams, Stop, plan};
use geo::Coord;
use proptest::prelude::*;
use serde_json::{Value, json};

/// A `length` × `width` rectangle centred on `centre`, its long side at `deg` (math angle).
fn rectangle(frame: &LocalFrame, centre: (f64, f64), length: f64, width: f64, deg: f64) -> Value {
    let (sin, cos) = deg.to_radians().sin_cos();
    let corner = |u: f64, v: f64| {
        let (x, y) = (u * length / 2.0, v * width / 2.0);
        json!(frame.to_wgs84(Coord { x: centre.0 + x * cos - y * sin, y: centre.1 + x * sin + y * cos }))
    };
    json!([[corner(-1., -1.), corner(1., -1.), corner(1., 1.), corner(-1., 1.), corner(-1., -1.)]])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]
    /// Two long rectangles 700 m apart at any two headings: each is swept along its long side
    /// (a quarter of the turns of sweeping across), and both are covered.
    #[test]
    fn each_field_is_swept_along_its_long_side(west_deg in 0.0..180.0f64, east_deg in 0.0..180.0f64) {
        let frame = LocalFrame::new(5.0, 52.0);
        let area = json!({"type": "MultiPolygon", "coordinates": [
            rectangle(&frame, (0.0, 0.0), 400.0, 100.0, west_deg),
            rectangle(&frame, (700.0, 0.0), 300.0, 90.0, east_deg),
        ]});
        let params: PlanParams =
            serde_json::from_value(json!({"planner": "line_gtsp", "line_spacing_m": 20, "vehicle": {"profile": "iris"}})).unwrap();
        let mission = MissionGeometry::area(&area);
        let out = plan(&mission, &params, &coverplan_planner::vehicle::builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect("planned");
        prop_assert!(out.stats.coverage_ratio >= 0.99, "coverage {}", out.stats.coverage_ratio);
        let mut sweeps = [0, 0];
        for f in &out.trajectory.features {
            let kind = f.properties.as_ref().and_then(|p| p.get("kind")).and_then(Value::as_str);
            let Some(geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { continue };
            if kind != Some("sweep") || coordinates.len() < 2 {
                continue;
            }
            let a = frame.to_local(coordinates[0][0], coordinates[0][1]);
            let b = frame.to_local(coordinates[coordinates.len() - 1][0], coordinates[coordinates.len() - 1][1]);
            let (field, long_side) = if (a.x + b.x) / 2.0 < 350.0 { (0, west_deg) } else { (1, east_deg) };
            let heading = (b.y - a.y).atan2(b.x - a.x);
            prop_assert!(
                axial_difference(heading, long_side.to_radians()) <= 2f64.to_radians(),
                "field {field}: a sweep at {:.1}°, its long side at {long_side:.1}°",
                heading.to_degrees()
            );
            sweeps[field] += 1;
        }
        prop_assert!(sweeps[0] >= 5 && sweeps[1] >= 4, "sweeps per field {sweeps:?}");
    }
}
