//! `GET /api/v1/planners`: the planners and the parameters they take.

use axum::Json;
use serde::Serialize;
use utoipa::ToSchema;

use crate::planner::planners::{ParameterInfo, common_parameters, registry};

#[derive(Debug, Serialize, ToSchema)]
pub struct PlannerInfo {
    pub id: &'static str,
    pub description: &'static str,
    pub parameters: Vec<ParameterInfo>,
}

#[utoipa::path(get, path = "/api/v1/planners", tag = "planners", responses((status = 200, body = Vec<PlannerInfo>)))]
pub async fn list() -> Json<Vec<PlannerInfo>> {
    Json(registry().iter().map(|p| PlannerInfo { id: p.id(), description: p.description(), parameters: common_parameters() }).collect())
}
