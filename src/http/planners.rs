//! `GET /api/v1/planners`, `GET /api/v1/cameras` and `GET /api/v1/formats`: what clients can
//! choose from.

use std::sync::LazyLock;

use axum::Json;
use serde::Serialize;
use serde_json::Value;
use utoipa::ToSchema;

use crate::planner;
use crate::planner::camera::{CameraPreset, PRESETS};
use crate::planner::export::{self, Format};
use crate::planner::planners::{MethodKind, PlannerInfo};

/// A planner as clients choose it: what it plans, where to ask for it, and the request members
/// it reads with their types and descriptions.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct PlannerListing {
    #[serde(flatten)]
    pub planner: PlannerInfo,
    /// Where a request for it is sent (`{id}`: the mission's).
    pub request_path: &'static str,
    pub parameters: Vec<ParameterInfo>,
}

/// A request member a planner reads, as the request's schema (`PlanParams`) documents it.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct ParameterInfo {
    pub name: &'static str,
    /// The JSON type: `number`, `integer`, `string`, `boolean`, `array` or `object`.
    #[serde(rename = "type")]
    pub kind: String,
    pub description: String,
}

/// `PlanParams`' members, typed and described by the OpenAPI document (read once).
static DESCRIBED: LazyLock<Value> = LazyLock::new(|| serde_json::from_str(&super::openapi::document()).expect("the OpenAPI document is JSON"));

/// The schema of the request a method is asked for with, and where that request is sent.
pub fn request_of(method: MethodKind) -> (&'static str, &'static str) {
    match method {
        MethodKind::Coverage | MethodKind::Inspection => ("PlanParams", "/api/v1/missions/{id}/plans"),
        MethodKind::Patrol => ("PatrolParams", "/api/v1/missions/{id}/patrols"),
    }
}

/// A member of the request schema `schema` as the schema says it: its JSON type and description
/// (the member's own, else the type's).
pub fn describe(schema: &str, name: &'static str) -> ParameterInfo {
    let schemas = &DESCRIBED["components"]["schemas"];
    let member = &schemas[schema]["properties"][name];
    // `T | null` is a oneOf of the type and null; its description sits on the type's branch
    let alternatives = member["oneOf"].as_array().or(member["anyOf"].as_array()).cloned().unwrap_or_else(|| vec![member.clone()]);
    let own = alternatives.into_iter().find(|a| a["type"] != "null").unwrap_or_default();
    let referenced = own["$ref"].as_str().and_then(|r| r.rsplit('/').next()).map_or(&Value::Null, |t| &schemas[t]);
    let text = |v: &Value| v["description"].as_str().map(str::to_owned);
    let description = text(member).or_else(|| text(&own)).or_else(|| text(referenced)).unwrap_or_default();
    let kind_of = |v: &Value| match &v["type"] {
        Value::String(t) => Some(t.clone()),
        Value::Array(ts) => ts.iter().filter_map(Value::as_str).find(|t| *t != "null").map(str::to_owned),
        _ if v["properties"].is_object() || v["oneOf"].is_array() || v["allOf"].is_array() => Some("object".to_owned()),
        _ => None,
    };
    let kind = kind_of(&own).or_else(|| kind_of(referenced)).unwrap_or_else(|| "object".to_owned());
    ParameterInfo { name, kind, description: description.split_whitespace().collect::<Vec<_>>().join(" ") }
}

#[utoipa::path(get, operation_id = "list_planners", path = "/api/v1/planners", tag = "planners", responses((status = 200, body = Vec<PlannerListing>)))]
pub async fn list() -> Json<Vec<PlannerListing>> {
    Json(planner::catalogue().into_iter().map(listing).collect())
}

fn listing(planner: PlannerInfo) -> PlannerListing {
    let (schema, request_path) = request_of(planner.method);
    let parameters = planner.parameters.iter().map(|name| describe(schema, name)).collect();
    PlannerListing { planner, request_path, parameters }
}

/// Camera presets, for `camera: {"preset": id}`.
#[utoipa::path(get, operation_id = "list_cameras", path = "/api/v1/cameras", tag = "planners", responses((status = 200, body = Vec<CameraPreset>)))]
pub async fn cameras() -> Json<&'static [CameraPreset]> {
    Json(PRESETS)
}

/// The formats a finished plan can be downloaded in (`GET /api/v1/plans/{id}/trajectory?format=id`),
/// in the order menus list them; the first is the default.
#[utoipa::path(get, operation_id = "list_formats", path = "/api/v1/formats", tag = "planners", responses((status = 200, body = Vec<Format>)))]
pub async fn formats() -> Json<Vec<&'static Format>> {
    Json(export::formats())
}
