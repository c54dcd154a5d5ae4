//! `GET /api/v1/planners`, `GET /api/v1/cameras` and `GET /api/v1/formats`: what clients can
//! choose from.

use axum::Json;

use crate::planner;
use crate::planner::camera::{CameraPreset, PRESETS};
use crate::planner::export::{self, Format};
use crate::planner::planners::PlannerInfo;

#[utoipa::path(get, operation_id = "list_planners", path = "/api/v1/planners", tag = "planners", responses((status = 200, body = Vec<PlannerInfo>)))]
pub async fn list() -> Json<Vec<PlannerInfo>> {
    Json(planner::catalogue())
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
