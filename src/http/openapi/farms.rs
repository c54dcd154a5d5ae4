//! A farm plan request: its fields one way (the validator: `http::farms::create`).

use serde_json::{Value, json};

use crate::planner::farm::MAX_FIELDS;

/// Adds to `FarmPlanRequest` and `FieldGroup` what the derive cannot write.
pub fn apply(schemas: &mut Value) {
    // missions, or one mission's polygons
    schemas["FarmPlanRequest"]["oneOf"] = json!([
        {"required": ["missions"], "properties": {"missions": {"type": "array"}, "mission_id": {"type": "null"}}},
        {"required": ["mission_id"], "properties": {"mission_id": {"type": "string"}, "missions": {"type": "null"}}},
    ]);
    // a field's index: below the most fields a farm takes (CI's fuzz sent 9.4e21)
    schemas["FieldGroup"]["properties"]["fields"]["items"]["maximum"] = json!(MAX_FIELDS - 1);
}
