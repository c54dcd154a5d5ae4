//! A camera: a preset of the list, or enough figures to price a pixel (the validator:
//! `planner::camera::Camera`).

use serde_json::{Value, json};

use super::{absent, given};
use crate::planner::camera::PRESETS;

pub fn apply(schemas: &mut Value) {
    let camera = &mut schemas["Camera"];
    let presets: Vec<&str> = PRESETS.iter().map(|p| p.id).collect();
    camera["properties"]["preset"] = json!({"anyOf": [{"enum": presets}, {"type": "null"}], "description": "A camera from `GET /api/v1/cameras`."});
    camera["allOf"] = json!([
        // without a preset, the image size
        {"if": {"not": given("preset")}, "then": {"allOf": [given("image_width_px"), given("image_height_px")]}},
        // the lens one way: a sensor width with a focal length (or the preset's), a horizontal
        // field of view, or a diagonal one
        {"anyOf": [
            {"allOf": [absent(&["hfov_deg", "dfov_deg"]), {"anyOf": [given("preset"), {"allOf": [given("sensor_width_mm"), given("focal_length_mm")]}]}]},
            {"allOf": [given("hfov_deg"), absent(&["sensor_width_mm", "focal_length_mm", "dfov_deg"])]},
            {"allOf": [given("dfov_deg"), absent(&["sensor_width_mm", "focal_length_mm", "hfov_deg"])]},
        ]},
    ]);
    // the IEM's corner knots: [interior angle, fraction of the speed kept]
    schemas["IemCoefficients"]["properties"]["exit_speed_fraction"]["items"] = json!({"type": "array", "minItems": 2, "maxItems": 2,
        "prefixItems": [{"type": "number", "minimum": 0, "maximum": 180}, {"type": "number", "minimum": 0, "maximum": 1}]});
}
