//! `/api/v1/vehicles`: vehicle profiles (built-in and the operators' own), and
//! `/api/v1/estimates`: the energy and time of a route made elsewhere.

use axum::Json;
use axum::extract::{Path, State};
use axum::http::StatusCode;

use super::AppState;
use super::auth::Caller;
use super::error::{ApiError, ApiJson, Problem, off_the_async_threads};
use crate::planner::estimate::{EstimateRequest, RouteEstimate, estimate_route};
use crate::planner::vehicle::Vehicle;
use crate::store::vehicles::{self, Deleted, StoredVehicle};

#[utoipa::path(get, operation_id = "list_vehicles", path = "/api/v1/vehicles", tag = "vehicles", responses((status = 200, body = Vec<StoredVehicle>, description = "built-ins first")))]
pub async fn list(State(state): State<AppState>, caller: Caller) -> Result<Json<Vec<StoredVehicle>>, ApiError> {
    Ok(Json(vehicles::list(&state.db, &caller.tenant).await?))
}

#[utoipa::path(get, operation_id = "get_vehicle", path = "/api/v1/vehicles/{id}", tag = "vehicles", params(("id" = String, Path)),
    responses((status = 200, body = StoredVehicle), (status = 404, body = Problem)))]
pub async fn get(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<StoredVehicle>, ApiError> {
    vehicles::get(&state.db, &caller.tenant, &id).await?.map(Json).ok_or_else(|| ApiError::not_found("vehicle profile", &id))
}

#[utoipa::path(post, operation_id = "create_vehicle", path = "/api/v1/vehicles", tag = "vehicles", request_body = Vehicle,
    responses((status = 201, body = StoredVehicle), (status = 409, body = Problem, description = "the id is taken"), (status = 422, body = Problem)))]
pub async fn create(State(state): State<AppState>, caller: Caller, ApiJson(vehicle): ApiJson<Vehicle>) -> Result<(StatusCode, Json<StoredVehicle>), ApiError> {
    vehicle.validate("")?;
    let stored = vehicles::create(&state.db, &caller.tenant, &vehicle)
        .await?
        .ok_or_else(|| ApiError::conflict("vehicle_exists", format!("a vehicle profile named `{}` exists: update it with PUT", vehicle.profile)))?;
    Ok((StatusCode::CREATED, Json(stored)))
}

#[utoipa::path(put, operation_id = "update_vehicle", path = "/api/v1/vehicles/{id}", tag = "vehicles", params(("id" = String, Path)), request_body = Vehicle,
    responses((status = 200, body = StoredVehicle), (status = 403, body = Problem, description = "a built-in profile, without an admin key"), (status = 404, body = Problem), (status = 422, body = Problem)))]
pub async fn update(State(state): State<AppState>, caller: Caller, Path(id): Path<String>, ApiJson(vehicle): ApiJson<Vehicle>) -> Result<Json<StoredVehicle>, ApiError> {
    if vehicle.profile != id {
        return Err(ApiError::invalid("profile_mismatch", "/profile", format!("the body names `{}` but the URL `{id}`; a profile cannot be renamed", vehicle.profile)));
    }
    vehicle.validate("")?;
    let existing = vehicles::get(&state.db, &caller.tenant, &id).await?.ok_or_else(|| ApiError::not_found("vehicle profile", &id))?;
    let owner = match (existing.builtin, caller.admin) {
        (false, _) => Some(caller.tenant.as_str()),
        (true, true) => None,
        (true, false) => {
            return Err(ApiError::Client {
                status: StatusCode::FORBIDDEN,
                code: "builtin_vehicle",
                detail: format!("`{id}` is a built-in profile shared by every tenant: only an admin key may edit it; make your own copy under another id"),
                pointer: None,
            });
        }
    };
    vehicles::update(&state.db, owner, &id, &vehicle).await?.map(Json).ok_or_else(|| ApiError::not_found("vehicle profile", &id))
}

#[utoipa::path(delete, operation_id = "delete_vehicle", path = "/api/v1/vehicles/{id}", tag = "vehicles", params(("id" = String, Path)),
    responses((status = 204, description = "deleted"), (status = 404, body = Problem), (status = 409, body = Problem, description = "a built-in profile")))]
pub async fn delete(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<StatusCode, ApiError> {
    match vehicles::delete(&state.db, &caller.tenant, &id).await? {
        Deleted::Yes => Ok(StatusCode::NO_CONTENT),
        Deleted::NotFound => Err(ApiError::not_found("vehicle profile", &id)),
        Deleted::Builtin => Err(ApiError::conflict("builtin_vehicle", format!("`{id}` is a built-in profile: it can be edited but not deleted"))),
    }
}

#[utoipa::path(post, operation_id = "estimate_route", path = "/api/v1/estimates", tag = "vehicles", request_body = EstimateRequest,
    responses((status = 200, body = RouteEstimate, description = "totals and each leg"), (status = 422, body = Problem)))]
pub async fn estimate(State(state): State<AppState>, caller: Caller, ApiJson(request): ApiJson<EstimateRequest>) -> Result<Json<RouteEstimate>, ApiError> {
    let profiles = vehicles::profiles(&state.db, &caller.tenant).await?;
    // up to 100 000 legs: off the async threads
    let estimate = off_the_async_threads(move || estimate_route(&request, &profiles)).await?;
    Ok(Json(estimate))
}
