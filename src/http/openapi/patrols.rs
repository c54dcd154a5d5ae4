//! What a patrol request's members decide of each other (the validator:
//! `planner::patrol::PatrolParams::resolve`, and `http::patrols::next_moves`).

use serde_json::{Value, json};

use super::{absent, given};
use crate::planner::patrol;

pub fn apply(schemas: &mut Value) {
    let patrol = &mut schemas["PatrolParams"];
    patrol["allOf"] = json!([
        // a camera sets the cells' size from its altitude or GSD, one of them
        {"if": given("camera"), "then": {"allOf": [absent(&["cell_size_m"]), {"oneOf": [given("altitude_m"), given("gsd_cm")]}]}},
        {"if": {"not": given("camera")}, "then": absent(&["altitude_m", "gsd_cm"])},
    ]);
    patrol["properties"]["vehicle"]["allOf"] = json!([{"properties": {"kind": {"enum": ["multirotor", null]}}}]);
    schemas["PatrolState"]["properties"]["headings"]["items"] = json!({"type": "integer", "minimum": 0, "maximum": 3});
    // cells are numbered within the largest grid
    let cell = json!({"type": "integer", "minimum": 0, "maximum": patrol::MAX_CELLS - 1});
    schemas["PatrolState"]["properties"]["at"]["items"] = cell.clone();
    schemas["NextMovesRequest"]["properties"]["blocked"]["items"] = cell;
    // shared_cycle is a fixed walk, not an online decision
    let online: Vec<Value> = schemas["StrategyName"]["enum"].as_array().expect("an enumeration").iter().filter(|s| *s != "shared_cycle").cloned().collect();
    schemas["NextMovesRequest"]["properties"]["strategy"] =
        json!({"anyOf": [{"enum": online}, {"type": "null"}], "description": "Default `nc_drone`; any strategy but `shared_cycle`, a fixed walk."});
}
