//! What a plan request's members decide of each other, as `if`/`then` rules the derive cannot
//! write (the validator: `planner::params::PlanParams::resolve` and `planner::check_plan`).
//! Generators give up on more than a few such rules in one schema, so the document writes the
//! ones a client meets first and states the others in the members' descriptions, listing
//! their refusals ([`IN_WORDS`]).

use serde_json::{Value, json};

use super::{absent, given};
use crate::planner::INSPECTION;
use crate::planner::params::{COVERAGE_ONLY_MEMBERS, INSPECTION_ONLY_MEMBERS, TERRAIN_MEMBERS};

/// Most cross-member rules one schema holds: with more (or with a seventh in `Budget`'s
/// choice), schemathesis 4.32's generator, which expands them into every combination, gives
/// up on the operation.
const MOST_RULES: usize = 6;

/// The refusals of rules the members' descriptions state in words, past [`MOST_RULES`]: a
/// line spacing or a camera for an aircraft; a fleet instead of `vehicle` and `vehicles`; the
/// sweep direction `optimal` without a heading or a fleet; a landing heading only with landing
/// `auto`; a lead-in and a landing heading for a fixed wing, headland members for a ground
/// vehicle, which has no line spacing, camera, fleet, terrain or landing; a fixed wing over
/// terrain climbs at `max_climb_deg`; pattern `oblique` for a multirotor with a camera;
/// landing sites for one aircraft (a fixed wing's with landing `auto`); each planner's vehicle
/// kinds, fleets and line ends (`GET /api/v1/planners`).
pub const IN_WORDS: &[&str] = &[
    "camera_missing",
    "direction_for_fleet",
    "direction_twice",
    "fleet_twice",
    "landing_sites_for_fleet",
    "not_a_fixed_wing",
    "not_a_ground_vehicle",
    "not_a_multirotor",
    "not_for_fixed_wing",
    "not_for_ground_vehicles",
    "not_for_planner",
    "not_landing",
    "planner_not_applicable",
    "planner_not_for_fleets",
    "planner_vehicle_mismatch",
    "spacing_missing",
];

fn rule(condition: Value, then: Value) -> Value {
    json!({"if": condition, "then": then})
}

/// A rule with its converse in one: generators expand it into two branches, where two rules
/// would make four combinations (a 42nd member took the schema past what they model).
fn rule_or_else(condition: Value, then: Value, otherwise: Value) -> Value {
    json!({"if": condition, "then": then, "else": otherwise})
}

/// Adds the rules to `PlanParams`.
pub fn apply(schemas: &mut Value) {
    let is_inspection = json!({"required": ["planner"], "properties": {"planner": {"const": INSPECTION}}});
    let not_inspection = json!({"properties": {"planner": {"not": {"const": INSPECTION}}}});
    let over_terrain = json!({"required": ["altitude_reference"], "properties": {"altitude_reference": {"const": "terrain"}}});
    let start_end_altitude = json!({"properties": {"altitude_m": {"type": "null"}}});
    let rules = vec![
        // members of one kind of planner
        rule(not_inspection.clone(), {
            let mut then = absent(&INSPECTION_ONLY_MEMBERS);
            then["properties"]["start"] = json!({"anyOf": [{"type": "null"}, start_end_altitude]});
            then["properties"]["end"] = then["properties"]["start"].clone();
            then
        }),
        rule(is_inspection, json!({"allOf": [absent(&COVERAGE_ONLY_MEMBERS), given("budget")]})),
        // plans over terrain, and what they need; the terrain's members only for them
        rule_or_else(over_terrain, json!({"anyOf": [given("altitude_m"), {"allOf": [given("camera"), given("gsd_cm")]}]}), absent(&TERRAIN_MEMBERS)),
        // a camera's altitude: one way
        rule(given("camera"), json!({"oneOf": [given("altitude_m"), given("gsd_cm")]})),
        // fleets
        rule(given("altitude_separation_m"), json!({"anyOf": [given("fleet"), given("vehicles")]})),
    ];
    assert!(rules.len() <= MOST_RULES, "generators model at most {MOST_RULES} rules of one schema");
    // an inspection's ranges: [low, high] within their bounds (low below high is beyond a schema)
    let pair = |lo: f64, hi: f64| {
        json!({"anyOf": [{"type": "array", "minItems": 2, "maxItems": 2,
            "prefixItems": [{"type": "number", "minimum": lo, "maximum": hi}, {"type": "number", "minimum": lo, "maximum": hi}]}, {"type": "null"}]})
    };
    for (member, lo, hi) in [("range_m", 0.1, 500.0), ("gimbal_pitch_deg", -90.0, 90.0), ("altitude_range_m", 0.5, 1_000.0)] {
        let description = schemas["InspectionOptions"]["properties"][member]["description"].clone();
        schemas["InspectionOptions"]["properties"][member] = pair(lo, hi);
        schemas["InspectionOptions"]["properties"][member]["description"] = description;
    }
    // `guidance` (a `Guidance`, as the import answer gives it) is described in the API guide,
    // not here: with it, schemathesis 4.32's generator gives up on the operation, as with a
    // seventh rule (tried: without its null choice, with its points as bounded pairs)
    if let Some(members) = schemas["PlanParams"]["properties"].as_object_mut() {
        members.remove("guidance");
    }
    // a landing site and a refill point are `[lon, lat]`: the derive writes a fixed-length array inside a list
    // without its length (CI's fuzz sent `[]`)
    let site = &mut schemas["PlanParams"]["properties"]["landing_sites"]["items"];
    site["minItems"] = json!(2);
    site["maxItems"] = json!(2);
    let lon_lat = [json!({"type": "number", "minimum": -180.0, "maximum": 180.0}), json!({"type": "number", "minimum": -90.0, "maximum": 90.0})];
    schemas["Payload"]["properties"]["refill_points"]["items"] = json!({"type": "array", "minItems": 2, "maxItems": 2, "prefixItems": lon_lat});
    // a planner of the registry (CI's fuzz sent a name no planner has)
    let planner = &mut schemas["PlanParams"]["properties"]["planner"];
    let ids: Vec<&str> = crate::planner::planners::registry().iter().map(|p| p.id()).chain([INSPECTION]).collect();
    *planner = json!({"anyOf": [{"enum": ids}, {"type": "null"}], "description": planner["description"].clone()});
    // a budget is one of its three limits
    schemas["Budget"]["oneOf"] = json!([given("max_length_m"), given("max_time_s"), given("max_energy_j")]);
    schemas["PlanParams"]["allOf"] = json!(rules);
}
