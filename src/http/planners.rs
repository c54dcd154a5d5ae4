//! `GET /api/v1/planners` and `GET /api/v1/cameras`: what clients can choose from.

use axum::Json;
use serde::Serialize;
use utoipa::ToSchema;

use crate::planner;
use crate::planner::camera::{CameraPreset, PRESETS};
use crate::planner::planners::{ParameterInfo, registry};

#[derive(Debug, Serialize, ToSchema)]
pub struct PlannerInfo {
    pub id: &'static str,
    pub description: &'static str,
    /// How the planner chooses the sweep direction when `heading_deg` does not fix it.
    pub direction_rule: &'static str,
    pub parameters: Vec<ParameterInfo>,
}

#[utoipa::path(get, operation_id = "list_planners", path = "/api/v1/planners", tag = "planners", responses((status = 200, body = Vec<PlannerInfo>)))]
pub async fn list() -> Json<Vec<PlannerInfo>> {
    let coverage = registry().iter().map(|p| PlannerInfo { id: p.id(), description: p.description(), direction_rule: p.direction_rule(), parameters: p.parameters() });
    let inspection = PlannerInfo {
        id: planner::INSPECTION,
        description: planner::INSPECTION_DESCRIPTION,
        direction_rule: "none: viewpoints, not sweep lines",
        parameters: planner::inspection::parameters(),
    };
    Json(coverage.chain([inspection]).collect())
}

/// Camera presets, for `camera: {"preset": id}`.
#[utoipa::path(get, operation_id = "list_cameras", path = "/api/v1/cameras", tag = "planners", responses((status = 200, body = Vec<CameraPreset>)))]
pub async fn cameras() -> Json<&'static [CameraPreset]> {
    Json(PRESETS)
}
