//! The OpenAPI document: what is not a route (title, shared schemas, tags). The routes add
//! themselves in [`super::api`]. The committed copy lives in `openapi/openapi.json`.

use serde_json::{Value, json};
use utoipa::OpenApi;

use super::error;

mod camera;
mod farms;
mod geojson;
mod patrols;
mod plans;
mod vehicles;

#[derive(OpenApi)]
#[openapi(
    info(title = "coverplan", description = "Coverage path planning for drones and farm vehicles: \
        store fields as missions, queue plans, fetch GeoJSON trajectories with length, time and energy. \
        Every error is an RFC 9457 problem (application/problem+json).", license(name = "MIT")),
    components(schemas(error::Problem, crate::planner::Stats, crate::planner::path::PieceKind)),
    tags((name = "missions"), (name = "plans"), (name = "patrols"), (name = "farms"), (name = "planners"), (name = "vehicles"), (name = "health"))
)]
pub struct ApiDoc;

/// The document as the server serves it, pretty-printed.
pub fn document() -> String {
    serde_json::to_string_pretty(&complete(super::api().into_openapi())).expect("the OpenAPI document serialises") + "\n"
}

/// A schema: these members absent (or null).
fn absent(members: &[&str]) -> Value {
    let nulls: serde_json::Map<String, Value> = members.iter().map(|m| (m.to_string(), json!({"type": "null"}))).collect();
    json!({"properties": nulls})
}

/// A schema: the member given (not null).
fn given(member: &str) -> Value {
    json!({"required": [member], "properties": {member: {"not": {"type": "null"}}}})
}

/// A problem answer of the document.
fn problem(description: &str) -> Value {
    json!({"description": description, "content": {PROBLEM_TYPE: {"schema": {"$ref": "#/components/schemas/Problem"}}}})
}

const PROBLEM_TYPE: &str = "application/problem+json";

/// What the routes' own entries cannot say, added to the whole document (edited as JSON):
/// - the API key (`api_key`) and its answers (401, 429) on every tenant's route;
/// - `Idempotency-Key` and its answers (400, 409, 422) on every POST;
/// - the refusals of every JSON body (400 malformed, 413 too large, 415 not JSON);
/// - problems under their own media type, `application/problem+json`, as they are sent;
/// - links from what a request makes to what can be done with it next, and working examples;
/// - two schemas the derive gets wrong: `MissionItems` (two array forms, which an empty list
///   matches both: `anyOf`, not `oneOf`) and `StoredVehicle` (a `Vehicle`, which allows no
///   other member, plus three: written out whole instead of `allOf`);
/// - what the derive cannot write of the requests: GeoJSON ([`geojson`]), the rules between
///   members ([`vehicles`], [`plans`], [`patrols`], [`camera`]), and each operation's refusals
///   beyond what the document can state.
///
/// The result is JSON: utoipa's types cannot hold all of JSON Schema 2020-12 (`prefixItems`,
/// `const` without a type).
pub fn complete(doc: utoipa::openapi::OpenApi) -> Value {
    let mut doc = serde_json::to_value(&doc).expect("the OpenAPI document serialises");
    doc["components"]["securitySchemes"]["api_key"] = json!({
        "type": "http", "scheme": "bearer",
        "description": "`Authorization: Bearer KEY`, a key from `coverplan keys create`; needed once the server has any key"
    });
    let paths = doc["paths"].as_object_mut().expect("paths");
    for (path, item) in paths.iter_mut() {
        let protected = super::auth::protected(path);
        for (method, operation) in item.as_object_mut().expect("a path item").iter_mut().filter(|(m, _)| ["get", "put", "post", "delete"].contains(&m.as_str())) {
            let json_body = operation.pointer("/requestBody/content/application~1json").is_some();
            let post = method == "post";
            let responses = operation["responses"].as_object_mut().expect("responses");
            let mut add = |status: &str, description: &str| {
                responses.entry(status).or_insert_with(|| problem(description));
            };
            if protected {
                add("401", "no API key, or an unknown or revoked one (the server has keys)");
                add("429", "the key sends requests faster than the server allows (see `Retry-After`)");
            }
            if json_body {
                add("400", "the body is not valid JSON");
                add("413", "the body is larger than the server accepts");
                add("415", "the body is not sent as `application/json`");
            }
            if post {
                add("400", "a malformed Idempotency-Key");
                add("409", "the first request with this Idempotency-Key is still being answered");
                add("422", "the Idempotency-Key was sent with another request");
            }
            for (status, response) in responses.iter_mut() {
                if response.get("description").is_none() {
                    let reason = status.parse().ok().and_then(|s| axum::http::StatusCode::from_u16(s).ok()).and_then(|s| s.canonical_reason()).unwrap_or("answer");
                    response["description"] = json!(reason);
                }
                if let Some(content) = response.get_mut("content").and_then(Value::as_object_mut)
                    && content.get("application/json").is_some_and(|c| c["schema"]["$ref"] == "#/components/schemas/Problem")
                {
                    let problem = content.remove("application/json").expect("present");
                    content.insert(PROBLEM_TYPE.into(), problem);
                }
            }
            if protected {
                operation["security"] = json!([{"api_key": []}]);
            }
            if post {
                let parameters = operation.as_object_mut().expect("an operation").entry("parameters").or_insert_with(|| json!([]));
                parameters.as_array_mut().expect("parameters").push(json!({
                    "name": "Idempotency-Key", "in": "header", "required": false,
                    "description": "Any 1 to 255 characters unique to this request: a retry with the same key and body gets the first answer again (kept a day)",
                    "schema": {"type": "string", "minLength": 1, "maxLength": 255}
                }));
            }
        }
    }
    // the refusals each operation can give to a request this document allows
    for r in refusals() {
        let answer = &mut paths[r.path][r.method]["responses"]["422"];
        assert!(answer.is_object(), "{} {} documents its 422 answer", r.method, r.path);
        let listed = |codes: &[&str]| codes.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(", ");
        let mut description = format!("{}; beyond what this document can state: {}", answer["description"].as_str().unwrap_or_default(), listed(&r.beyond));
        if !r.with_profile.is_empty() {
            description += &format!("; with a stored profile named, also {}", listed(&r.with_profile));
        }
        if !r.in_words.is_empty() {
            description += &format!("; of rules the members' descriptions state: {}", listed(r.in_words));
        }
        answer["description"] = json!(description);
        answer["x-beyond-schema"] = json!(r.beyond);
        answer["x-beyond-schema-with-profile"] = json!(r.with_profile);
        answer["x-stated-in-words"] = json!(r.in_words);
    }
    // the formats and autopilots the registries know, as the only values the query takes
    let choices = [
        ("/api/v1/missions/import", "format", crate::planner::import::format_ids().to_vec()),
        ("/api/v1/plans/{id}/trajectory", "format", crate::planner::export::format_ids()),
        ("/api/v1/plans/{id}/trajectory", "firmware", vec!["ardupilot", "px4"]),
        ("/api/v1/farm-plans/{id}/flights", "format", crate::planner::export::format_ids()),
        ("/api/v1/farm-plans/{id}/flights", "firmware", vec!["ardupilot", "px4"]),
    ];
    for (path, name, values) in choices {
        for operation in paths[path].as_object_mut().expect("a path item").values_mut() {
            for parameter in operation["parameters"].as_array_mut().into_iter().flatten().filter(|p| p["name"] == name && p["in"] == "query") {
                parameter["schema"] = json!({"type": "string", "enum": values});
            }
        }
    }
    // a trajectory comes in every export format's media type, and as a zip of one file per
    // sortie for the flight formats
    let trajectory = &mut paths["/api/v1/plans/{id}/trajectory"]["get"]["responses"]["200"]["content"];
    for exporter in crate::planner::export::EXPORTERS {
        let media_type = exporter.format().media_type.split(';').next().expect("a media type").trim();
        let schema = if media_type.ends_with("json") { json!({"type": "object"}) } else { json!({"type": "string", "format": "binary"}) };
        trajectory.as_object_mut().expect("content").entry(media_type).or_insert_with(|| json!({ "schema": schema }));
    }
    trajectory["application/zip"] = json!({"schema": {"type": "string", "format": "binary"}});
    // what a client does next with what it made (OpenAPI links; generators and fuzzers follow them)
    let follow = |made: &str, status: &str, id: &str, next: &[&str]| {
        let links: serde_json::Map<String, Value> =
            next.iter().map(|op| (op.to_string(), json!({"operationId": op, "parameters": {"id": format!("$response.body#/{id}")}}))).collect();
        (made.to_owned(), status.to_owned(), Value::Object(links))
    };
    let mission_next = ["get_mission", "update_mission", "delete_mission", "list_plans", "create_plan"];
    for (made, status, links) in [
        follow("create_mission", "201", "id", &mission_next),
        follow("import_mission", "201", "id", &mission_next),
        follow("create_plan", "202", "id", &["get_plan", "cancel_plan", "get_trajectory"]),
        follow("create_vehicle", "201", "profile", &["get_vehicle", "update_vehicle", "delete_vehicle"]),
    ] {
        let operation = paths
            .values_mut()
            .flat_map(|item| item.as_object_mut().expect("a path item").values_mut())
            .find(|op| op["operationId"] == made.as_str())
            .expect("the operation exists");
        operation["responses"][status.as_str()]["links"] = links;
    }
    let schemas = &mut doc["components"]["schemas"];
    // requests that work as they are, for readers and for the generators' first tries
    let field = json!({"type": "Polygon", "coordinates": [[[5.6600, 51.9850], [5.6629, 51.9850], [5.6629, 51.9864], [5.6600, 51.9864], [5.6600, 51.9850]]]});
    schemas["MissionRequest"]["example"] = json!({"name": "North field", "area": field, "home": [5.6598, 51.9849]});
    let default_planner = crate::planner::planners::default_for(crate::planner::vehicle::VehicleKind::Multirotor).map(|p| p.id());
    schemas["PlanParams"]["example"] = json!({"planner": default_planner, "line_spacing_m": 25, "vehicle": {"profile": "iris"}});
    schemas["EstimateRequest"]["example"] = json!({"waypoints": [[5.66, 51.985], [5.6629, 51.985], [5.6629, 51.9864]], "vehicle": {"profile": "iris"}});
    geojson::apply(schemas);
    vehicles::apply(schemas);
    plans::apply(schemas);
    patrols::apply(schemas);
    camera::apply(schemas);
    farms::apply(schemas);
    if let Some(items) = schemas["MissionItems"].as_object_mut()
        && let Some(forms) = items.remove("oneOf")
    {
        items.insert("anyOf".into(), forms);
    }
    // every code a client can receive, as one enumeration
    schemas["ErrorCode"] = json!({"type": "string", "enum": super::error::ERROR_CODES, "description": "What went wrong, for programs: the last part of a problem's `type`, or why a plan or patrol failed."});
    schemas["Problem"]["properties"]["code"] = json!({"$ref": "#/components/schemas/ErrorCode"});
    for failed in ["Plan", "Patrol"] {
        schemas[failed]["properties"]["error_code"] = json!({"anyOf": [{"$ref": "#/components/schemas/ErrorCode"}, {"type": "null"}]});
    }
    let mut stored = schemas["Vehicle"].clone();
    for (name, schema) in schemas["StoredVehicle"]["allOf"][1]["properties"].as_object().cloned().unwrap_or_default() {
        stored["properties"][&name] = schema;
        stored["required"].as_array_mut().expect("required").push(json!(name));
    }
    stored["description"] = json!("A stored profile: the vehicle's figures, whether it is built in, and when it was made and changed.");
    schemas["StoredVehicle"] = stored;
    doc
}

/// The refusals an operation can give to a request the document allows.
struct Refusals {
    path: &'static str,
    method: &'static str,
    /// Beyond what a schema can state (see [`super::error::beyond_schema`]).
    beyond: Vec<&'static str>,
    /// Also these where the request names a stored vehicle profile, whose kind decides them.
    with_profile: Vec<&'static str>,
    /// Of rules the members' descriptions state in words (see [`plans::IN_WORDS`]).
    in_words: &'static [&'static str],
}

/// The refusals of each operation that has some.
fn refusals() -> Vec<Refusals> {
    use super::error::beyond_schema::{EXPORT, FARM, FILE, GEOMETRY, IMPORTED, MISSION, PROFILE, RELATIONS, RESUMED, ROUTE, WIND};
    let of = |groups: &[&[&'static str]]| -> Vec<&'static str> {
        let mut codes: Vec<_> = groups.concat();
        codes.sort_unstable();
        codes.dedup();
        codes
    };
    let refusals = |path, method, beyond, with_profile| Refusals { path, method, beyond, with_profile, in_words: &[] };
    vec![
        refusals("/api/v1/missions", "post", of(&[GEOMETRY, FILE]), vec![]),
        refusals("/api/v1/missions/{id}", "put", of(&[GEOMETRY, FILE]), vec![]),
        refusals("/api/v1/missions/import", "post", of(&[GEOMETRY, FILE, IMPORTED]), vec![]),
        refusals("/api/v1/missions/{id}/terrain", "put", of(&[FILE]), vec![]),
        Refusals { in_words: plans::IN_WORDS, ..refusals("/api/v1/missions/{id}/plans", "post", of(&[MISSION, RELATIONS, WIND]), of(&[PROFILE])) },
        Refusals { in_words: plans::IN_WORDS, ..refusals("/api/v1/farm-plans", "post", of(&[MISSION, RELATIONS, WIND, GEOMETRY, FARM]), of(&[PROFILE])) },
        refusals("/api/v1/missions/{id}/patrols", "post", of(&[MISSION, RELATIONS]), of(&[PROFILE])),
        refusals("/api/v1/patrols/next-moves", "post", of(&[RELATIONS]), vec![]),
        refusals("/api/v1/plans/{id}/resume", "post", of(&[RESUMED]), vec![]),
        refusals("/api/v1/plans/{id}/trajectory", "get", of(&[EXPORT]), vec![]),
        refusals("/api/v1/farm-plans/{id}/flights", "get", of(&[EXPORT]), vec![]),
        refusals("/api/v1/estimates", "post", of(&[ROUTE, WIND]), of(&[PROFILE])),
        refusals("/api/v1/vehicles", "post", of(&[RELATIONS]), vec![]),
        refusals("/api/v1/vehicles/{id}", "put", of(&[RELATIONS]), vec![]),
    ]
}
