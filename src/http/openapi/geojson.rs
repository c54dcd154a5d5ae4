//! The GeoJSON a request may hold, as schemas: what the derive can only call an object. The
//! shapes follow RFC 7946 and the members the server reads (`planner::field`); what a schema
//! cannot say (rings closed and simple, holes inside their shell) is listed under
//! [`crate::http::error::beyond_schema`].

use serde_json::{Value, json};

use crate::planner::estimate::MAX_WAYPOINTS;

/// Tallest obstacle or structure, metres (as `planner::field` reads them).
const MAX_HEIGHT_M: f64 = 1_000.0;

fn reference(name: &str) -> Value {
    json!({"$ref": format!("#/components/schemas/{name}")})
}

/// A position's longitude and latitude, as the first two items of an array.
fn longitude_latitude() -> [Value; 2] {
    [json!({"type": "number", "minimum": -180, "maximum": 180}), json!({"type": "number", "minimum": -90, "maximum": 90})]
}

/// The GeoJSON schemas, to add to the document's components.
pub fn schemas() -> Vec<(&'static str, Value)> {
    let geometry = |kind: &str, coordinates: Value| {
        json!({"type": "object", "required": ["type", "coordinates"], "properties": {
            "type": {"const": kind}, "coordinates": coordinates, "bbox": {"type": ["array", "null"], "items": {"type": "number"}}}})
    };
    // a feature whose properties must hold a member must have them
    let feature = |geometry: Value, properties: Value| {
        let required = if properties["required"].is_array() { json!(["type", "geometry", "properties"]) } else { json!(["type", "geometry"]) };
        json!({"type": "object", "required": required, "properties": {
            "type": {"const": "Feature"}, "geometry": geometry, "properties": properties}})
    };
    let collection = |feature: Value, min_items: u64| {
        json!({"type": "object", "required": ["type", "features"], "properties": {
            "type": {"const": "FeatureCollection"}, "features": {"type": "array", "items": feature, "minItems": min_items}}})
    };
    let polygon_geometry = json!({"oneOf": [reference("GeoPolygon"), reference("GeoMultiPolygon")]});
    let any_properties = json!({"type": ["object", "null"]});
    // RFC 7946 drops `crs`: the server refuses one on an area or no-fly zones rather than guess
    let polygons = |description: &str, min_features: u64| {
        let feature = feature(polygon_geometry.clone(), any_properties.clone());
        json!({"description": description, "not": {"required": ["crs"]},
            "oneOf": [reference("GeoPolygon"), reference("GeoMultiPolygon"), feature.clone(), collection(feature, min_features)]})
    };
    let height = json!({"type": "number", "exclusiveMinimum": 0, "maximum": MAX_HEIGHT_M, "description": "metres above ground"});
    let obstacle = feature(polygon_geometry.clone(), json!({"type": "object", "required": ["height_m"], "properties": {"height_m": height}}));
    let structure_properties = |required: &[&str], extra: Value| {
        let mut properties = json!({
            "height_m": {"type": "number", "minimum": 0.1, "maximum": MAX_HEIGHT_M, "description": "metres, from base_m up"},
            "base_m": {"type": ["number", "null"], "minimum": 0, "maximum": MAX_HEIGHT_M, "description": "metres above ground where it starts (default 0)"},
            "name": {"type": ["string", "null"], "minLength": 1, "maxLength": 200, "pattern": "\\S", "description": "unique in the mission"},
        });
        properties.as_object_mut().expect("an object").extend(extra.as_object().cloned().unwrap_or_default());
        json!({"type": "object", "required": required, "properties": properties})
    };
    vec![
        (
            "GeoPosition",
            json!({"type": "array", "description": "[longitude, latitude], WGS84 degrees (further numbers, such as an altitude, are ignored)",
                "prefixItems": longitude_latitude(), "items": {"type": "number"}, "minItems": 2}),
        ),
        (
            "GeoRing",
            json!({"type": "array", "items": reference("GeoPosition"), "minItems": 4,
                "description": "A closed ring: at least 3 distinct positions, then the first again; the exterior first, then holes"}),
        ),
        ("GeoPolygon", geometry("Polygon", json!({"type": "array", "items": reference("GeoRing"), "minItems": 1}))),
        ("GeoMultiPolygon", geometry("MultiPolygon", json!({"type": "array", "items": {"type": "array", "items": reference("GeoRing"), "minItems": 1}}))),
        ("GeoPolygons", polygons("A Polygon, a MultiPolygon, or a Feature or FeatureCollection of them", 0)),
        ("GeoArea", polygons("A Polygon, a MultiPolygon, or a Feature or FeatureCollection of them, holding at least one polygon", 1)),
        (
            "GeoObstacles",
            json!({"description": "A Feature or FeatureCollection of Polygon (or MultiPolygon) features, each with its `height_m`",
            "oneOf": [obstacle.clone(), collection(obstacle, 0)]}),
        ),
        (
            "GeoStructures",
            collection(
                json!({"oneOf": [
                    feature(reference("GeoPolygon"), structure_properties(&["height_m"], json!({"obj": {"type": "null"}}))),
                    feature(geometry("Point", reference("GeoPosition")), structure_properties(&["height_m", "radius_m"], json!({
                        "obj": {"type": "null"},
                        "radius_m": {"type": "number", "minimum": 0.1, "maximum": 500, "description": "a cylinder (a silo, a tree)"}}))),
                    feature(geometry("Point", reference("GeoPosition")), structure_properties(&["obj"], json!({
                        "obj": {"type": "string", "description": "a Wavefront OBJ model whose origin stands at the point"},
                        "up": {"enum": ["z", "y", null]},
                        "rotation_deg": {"type": ["number", "null"], "minimum": -360, "maximum": 360, "description": "turned clockwise"}}))),
                ]}),
                0,
            ),
        ),
        (
            "GeoRoute",
            json!({"description": "A LineString (or a Feature holding one); a third coordinate is the altitude, metres",
                "oneOf": [reference("GeoLineString"), feature(reference("GeoLineString"), any_properties.clone())]}),
        ),
        ("GeoLineString", geometry("LineString", waypoints())),
        ("GeoRoads", {
            let lines = json!({"oneOf": [geometry("LineString", road()), geometry("MultiLineString", json!({"type": "array", "items": road(), "minItems": 1}))]});
            let feature = feature(lines.clone(), any_properties.clone());
            json!({"description": "Roads: LineStrings or MultiLineStrings, bare, in a Feature or in a FeatureCollection",
                "oneOf": [lines, feature.clone(), collection(feature, 1)]})
        }),
    ]
}

/// A route's waypoints: [longitude, latitude] or [longitude, latitude, altitude_m].
pub fn waypoints() -> Value {
    let [longitude, latitude] = longitude_latitude();
    json!({"type": "array", "minItems": 2, "maxItems": MAX_WAYPOINTS, "items": {"type": "array", "minItems": 2, "maxItems": 3,
        "prefixItems": [longitude, latitude, {"type": "number", "minimum": -500, "maximum": 10_000}]}})
}

/// A road's points, [longitude, latitude] each (further numbers are ignored).
fn road() -> Value {
    json!({"type": "array", "minItems": 2, "maxItems": crate::planner::farm::MAX_ROAD_POINTS, "items": reference("GeoPosition")})
}

/// A point: exactly [longitude, latitude].
fn point() -> Value {
    json!({"type": "array", "minItems": 2, "maxItems": 2, "prefixItems": longitude_latitude()})
}

/// Puts the GeoJSON schemas where the requests hold GeoJSON or points, keeping each member's
/// description and whether it may be null.
pub fn apply(schemas: &mut Value) {
    for (name, schema) in self::schemas() {
        schemas[name] = schema;
    }
    let members = [
        ("MissionRequest", "area", reference("GeoArea")),
        ("MissionRequest", "no_fly_zones", reference("GeoPolygons")),
        ("MissionRequest", "obstacles", reference("GeoObstacles")),
        ("MissionRequest", "structures", reference("GeoStructures")),
        ("MissionRequest", "home", point()),
        ("EstimateRequest", "route", reference("GeoRoute")),
        ("EstimateRequest", "waypoints", waypoints()),
        ("PoseParam", "position", point()),
        ("ResumeParams", "position", point()),
        ("Machine", "depot", point()),
        ("FarmPlanRequest", "roads", reference("GeoRoads")),
    ];
    for (owner, member, schema) in members {
        let old = schemas[owner]["properties"][member].take();
        assert!(old.is_object(), "{owner} has a member {member}");
        let nullable = old["type"].as_array().is_some_and(|t| t.contains(&json!("null"))) || old.to_string().contains(r#"{"type":"null"}"#);
        let mut new = if nullable { json!({"anyOf": [schema, {"type": "null"}]}) } else { schema };
        if let Some(description) = old.get("description") {
            new["description"] = description.clone();
        }
        schemas[owner]["properties"][member] = new;
    }
    // a fleet's drone: a vehicle's members and a home, written out whole (under `allOf`, the
    // vehicle's `additionalProperties: false` would refuse the home)
    let mut member = schemas["VehicleParams"].clone();
    member["properties"]["home"] = json!({"anyOf": [point(), {"type": "null"}],
        "description": "[longitude, latitude] this drone takes off from and lands at; default: the mission's home."});
    member["description"] = schemas["FleetMember"]["description"].clone();
    schemas["FleetMember"] = member;
    // start positions, a flown track and its photos: points
    schemas["PatrolParams"]["properties"]["starts"]["items"] = point();
    schemas["Flown"]["properties"]["track"]["items"] = point();
    schemas["Flown"]["properties"]["photos"]["items"] = point();
    // a route or its waypoints, one of them
    schemas["EstimateRequest"]["oneOf"] = json!([
        {"required": ["route"], "properties": {"route": {"type": "object"}, "waypoints": {"type": "null"}}},
        {"required": ["waypoints"], "properties": {"waypoints": {"type": "array"}, "route": {"type": "null"}}},
    ]);
}
