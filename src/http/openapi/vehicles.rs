//! What a vehicle's kind decides of its other members, as `if`/`then` rules the derive cannot
//! write (the validator: `planner::vehicle::Vehicle::validate`).

use serde_json::{Value, json};

use super::absent;
use crate::planner::vehicle::{GROUND_OVERRIDES, MAX_BATTERY_WH};

/// Adds the kind rules to the stored profile (`Vehicle`) and the plan's vehicle
/// (`VehicleParams`, and a fleet's drone).
pub fn apply(schemas: &mut Value) {
    let kind_is = |kinds: &[&str]| json!({"required": ["kind"], "properties": {"kind": {"enum": kinds}}});
    let aircraft = ["multirotor", "fixed_wing"];
    let profile_rules = json!([
        {"if": kind_is(&aircraft), "then": {"properties": {
            "battery": {"properties": {"energy_wh": {"maximum": MAX_BATTERY_WH}}},
            "ground": {"type": "null"}}}},
        {"if": kind_is(&["fixed_wing"]), "then": {"properties": {
            "turn_radius_m": {"minimum": 1},
            "energy": {"properties": {"model": {"enum": ["constant_power", "fixed_wing"]}}}}}},
        {"if": kind_is(&["multirotor"]), "then": {"properties": {
            "energy": {"properties": {"model": {"enum": ["constant_power", "multirotor_iem"]}}}}}},
        {"if": kind_is(&["ground"]), "then": {"required": ["ground"], "properties": {
            "turn_radius_m": {"minimum": 0.5},
            "ground": {"type": "object"},
            "energy": {"properties": {"model": {"enum": ["constant_power", "ground"]}}}}}},
    ]);
    schemas["Vehicle"]["allOf"] = profile_rules;
    // a plan's vehicle: a kind (or, without a profile, the multirotor default) bounds the
    // overrides; a named profile's kind is the stored profile's, beyond the document
    let mut aircraft_overrides = absent(&GROUND_OVERRIDES);
    aircraft_overrides["properties"]["battery_wh"] = json!({"anyOf": [{"type": "null"}, {"maximum": MAX_BATTERY_WH}]});
    let default_kind = json!({"properties": {"kind": {"type": "null"}, "profile": {"type": "null"}}});
    // a fixed wing is also an aircraft: the rule above keeps its ground members out
    let fixed_wing = json!({"properties": {"turn_radius_m": {"anyOf": [{"type": "null"}, {"minimum": 1}]}}});
    let params_rules = json!([
        {"if": kind_is(&aircraft), "then": aircraft_overrides},
        {"if": default_kind, "then": aircraft_overrides},
        {"if": kind_is(&["fixed_wing"]), "then": fixed_wing},
        {"if": kind_is(&["ground"]), "then": {"properties": {"turn_radius_m": {"anyOf": [{"type": "null"}, {"minimum": 0.5}]}}}},
    ]);
    for owner in ["VehicleParams", "FleetMember"] {
        schemas[owner]["allOf"] = params_rules.clone();
    }
}
