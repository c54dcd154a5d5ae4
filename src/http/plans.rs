//! Plans: `/api/v1/missions/{id}/plans` to queue one, `/api/v1/plans/{id}` to follow it.

use axum::Json;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde_json::json;

use super::AppState;
use super::error::{ApiError, ApiJson, Problem};
use crate::planner::{self, MissionGeometry, PlanParams};
use crate::store::plans::{self, Plan, PlanStatus};
use crate::store::{missions, vehicles};

#[utoipa::path(post, operation_id = "create_plan", path = "/api/v1/missions/{id}/plans", tag = "plans", params(("id" = String, Path)), request_body = PlanParams,
    responses((status = 202, body = Plan, description = "queued"), (status = 404, body = Problem), (status = 422, body = Problem)))]
pub async fn create(State(state): State<AppState>, Path(mission_id): Path<String>, ApiJson(params): ApiJson<PlanParams>) -> Result<(StatusCode, Json<Plan>), ApiError> {
    let mission = missions::get(&state.db, &mission_id).await?.ok_or_else(|| ApiError::not_found("mission", &mission_id))?;
    let geometry = MissionGeometry { area: &mission.area, no_fly_zones: mission.no_fly_zones.as_ref(), obstacles: mission.obstacles.as_ref(), home: mission.home };
    let profiles = vehicles::profiles(&state.db).await?;
    planner::check_plan(&geometry, &params, &profiles, &state.config.limits)?;
    // the named profile as it is now: editing it later does not change a queued plan
    let profile = params.vehicle.resolve(&profiles)?;
    let base = profiles.iter().find(|p| p.profile == profile.profile);
    let snapshot = json!({"area": mission.area, "no_fly_zones": mission.no_fly_zones, "obstacles": mission.obstacles, "home": mission.home, "vehicles": [base]});
    let params = serde_json::to_value(&params).map_err(|e| ApiError::Internal(e.to_string()))?;
    let plan = plans::create(&state.db, &mission_id, &params, &snapshot).await?;
    state.jobs.notify();
    Ok((StatusCode::ACCEPTED, Json(plan)))
}

#[utoipa::path(get, operation_id = "list_plans", path = "/api/v1/missions/{id}/plans", tag = "plans", params(("id" = String, Path)),
    responses((status = 200, body = Vec<Plan>, description = "newest first"), (status = 404, body = Problem)))]
pub async fn list(State(state): State<AppState>, Path(mission_id): Path<String>) -> Result<Json<Vec<Plan>>, ApiError> {
    missions::get(&state.db, &mission_id).await?.ok_or_else(|| ApiError::not_found("mission", &mission_id))?;
    Ok(Json(plans::list_for_mission(&state.db, &mission_id).await?))
}

#[utoipa::path(get, operation_id = "get_plan", path = "/api/v1/plans/{id}", tag = "plans", params(("id" = String, Path)),
    responses((status = 200, body = Plan), (status = 404, body = Problem)))]
pub async fn get(State(state): State<AppState>, Path(id): Path<String>) -> Result<Json<Plan>, ApiError> {
    plans::get(&state.db, &id).await?.map(Json).ok_or_else(|| ApiError::not_found("plan", &id))
}

#[utoipa::path(get, operation_id = "get_trajectory", path = "/api/v1/plans/{id}/trajectory", tag = "plans", params(("id" = String, Path)),
    responses((status = 200, description = "GeoJSON FeatureCollection (RFC 7946) of LineStrings in flight order, \
        `properties.kind` = sweep | turn | transit, with length_m, duration_s, energy_j, speed_mps; a MultiPoint \
        of kind `photos` when a camera was given", content_type = "application/geo+json", body = Object),
        (status = 404, body = Problem), (status = 409, body = Problem, description = "the plan has no trajectory (yet)")))]
pub async fn trajectory(State(state): State<AppState>, Path(id): Path<String>) -> Result<Response, ApiError> {
    match plans::trajectory(&state.db, &id).await? {
        None => Err(ApiError::not_found("plan", &id)),
        Some((PlanStatus::Succeeded, Some(geojson))) => Ok(([(header::CONTENT_TYPE, "application/geo+json")], geojson).into_response()),
        Some((status, _)) => {
            Err(ApiError::conflict("trajectory_not_available", format!("the plan is {}; a trajectory exists only once it has succeeded", json!(status).as_str().unwrap_or("?"))))
        }
    }
}

#[utoipa::path(delete, operation_id = "cancel_plan", path = "/api/v1/plans/{id}", tag = "plans", params(("id" = String, Path)),
    responses((status = 200, body = Plan, description = "cancelled (or already finished: its status says which)"), (status = 404, body = Problem)))]
pub async fn cancel(State(state): State<AppState>, Path(id): Path<String>) -> Result<Json<Plan>, ApiError> {
    plans::cancel(&state.db, &id).await?.ok_or_else(|| ApiError::not_found("plan", &id))?;
    state.jobs.cancel(&id);
    plans::get(&state.db, &id).await?.map(Json).ok_or_else(|| ApiError::not_found("plan", &id))
}
