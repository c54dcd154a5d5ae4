//! Patrols: `/api/v1/missions/{id}/patrols` to queue one, `/api/v1/patrols/{id}` to follow it,
//! and `/api/v1/patrols/next-moves` for software that runs a patrol online. A patrol is a job
//! in the plans' queue (`kind: "patrol"` beside its parameters), with its own routes.

use axum::Json;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use utoipa::ToSchema;

use super::AppState;
use super::auth::Caller;
use super::error::{ApiError, ApiJson, Problem};
use crate::planner::patrol::{self, CellGrid, Evaporation, PatrolParams, PatrolState, StrategyName, TieRule};
use crate::store::plans::{self, JobKind, Plan, PlanStatus};
use crate::store::{missions, vehicles};

/// A patrol and, once it has run, its figures.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Patrol {
    pub id: String,
    pub mission_id: String,
    pub status: PlanStatus,
    /// The parameters as sent.
    #[schema(value_type = Object)]
    pub params: Value,
    /// The metrics (`qmi`, `sdf`, `ntm`, `reversals`) and each UAV's totals (see `PatrolStats`).
    #[schema(value_type = Option<crate::planner::patrol::PatrolStats>)]
    pub stats: Option<Value>,
    pub error: Option<String>,
    pub error_code: Option<String>,
    pub created_at: String,
    pub started_at: Option<String>,
    pub finished_at: Option<String>,
}

impl From<Plan> for Patrol {
    fn from(p: Plan) -> Self {
        Patrol {
            id: p.id,
            mission_id: p.mission_id,
            status: p.status,
            params: p.params,
            stats: p.stats,
            error: p.error,
            error_code: p.error_code,
            created_at: p.created_at,
            started_at: p.started_at,
            finished_at: p.finished_at,
        }
    }
}

/// A patrol of the caller's.
async fn find(state: &AppState, caller: &Caller, id: &str) -> Result<Plan, ApiError> {
    plans::get(&state.db, &caller.tenant, JobKind::Patrol, id).await?.ok_or_else(|| ApiError::not_found("patrol", id))
}

#[utoipa::path(post, operation_id = "create_patrol", path = "/api/v1/missions/{id}/patrols", tag = "patrols", params(("id" = String, Path)), request_body = PatrolParams,
    responses((status = 202, body = Patrol, description = "queued"), (status = 404, body = Problem), (status = 422, body = Problem),
              (status = 429, body = Problem, description = "too many plans and patrols of this tenant's are queued or running (see `Retry-After`)")))]
pub async fn create(
    State(state): State<AppState>,
    caller: Caller,
    Path(mission_id): Path<String>,
    ApiJson(params): ApiJson<PatrolParams>,
) -> Result<(StatusCode, Json<Patrol>), ApiError> {
    let mission = missions::get(&state.db, &caller.tenant, &mission_id).await?.ok_or_else(|| ApiError::not_found("mission", &mission_id))?;
    let profiles = vehicles::profiles(&state.db, &caller.tenant).await?;
    let (_, vehicle) = params.resolve(&profiles)?;
    let snapshot = super::plans::snapshot(&mission, &profiles, &[&vehicle]);
    let stored = serde_json::to_value(&params).map_err(|e| ApiError::Internal(e.to_string()))?;
    let patrol = super::plans::enqueue(&state, &caller, &crate::store::plans::NewJob::new(JobKind::Patrol, &mission_id, &stored, &snapshot)).await?;
    Ok((StatusCode::ACCEPTED, Json(patrol.into())))
}

#[utoipa::path(get, operation_id = "get_patrol", path = "/api/v1/patrols/{id}", tag = "patrols", params(("id" = String, Path)),
    responses((status = 200, body = Patrol), (status = 404, body = Problem)))]
pub async fn get(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<Patrol>, ApiError> {
    Ok(Json(find(&state, &caller, &id).await?.into()))
}

#[utoipa::path(delete, operation_id = "cancel_patrol", path = "/api/v1/patrols/{id}", tag = "patrols", params(("id" = String, Path)),
    responses((status = 200, body = Patrol, description = "cancelled (or already finished: its status says which)"), (status = 404, body = Problem)))]
pub async fn cancel(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<Patrol>, ApiError> {
    find(&state, &caller, &id).await?;
    plans::cancel(&state.db, &caller.tenant, &id).await?;
    state.jobs.cancel(&id);
    Ok(Json(find(&state, &caller, &id).await?.into()))
}

#[utoipa::path(get, operation_id = "get_patrol_trajectory", path = "/api/v1/patrols/{id}/trajectory", tag = "patrols", params(("id" = String, Path)),
    responses((status = 200, description = "A GeoJSON FeatureCollection: a LineString per UAV (`kind: \"patrol\"`, with `uav`, `turns`, `length_m`, \
        `duration_s`, `energy_j`), then a Polygon per free cell with its `visits` (`kind: \"visits\"`, the heat map)", content_type = "application/geo+json", body = Object),
        (status = 404, body = Problem), (status = 409, body = Problem, description = "the patrol has not finished")))]
pub async fn trajectory(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Response, ApiError> {
    find(&state, &caller, &id).await?;
    let source = plans::export_source(&state.db, &caller.tenant, JobKind::Patrol, &id).await?.ok_or_else(|| ApiError::not_found("patrol", &id))?;
    let (PlanStatus::Succeeded, Some(geojson)) = (source.status, source.trajectory) else {
        return Err(ApiError::conflict("trajectory_not_available", "a patrol's paths exist once it has succeeded"));
    };
    Ok(([(header::CONTENT_TYPE, "application/geo+json")], geojson).into_response())
}

/// One cycle of a centralised patrol, for software that runs it online.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct NextMovesRequest {
    /// The grid: `cols` × `rows` cells, numbered row by row from the south-west corner.
    #[schema(minimum = 1, maximum = 40000)]
    pub cols: usize,
    #[schema(minimum = 1, maximum = 40000)]
    pub rows: usize,
    /// Cells no UAV may enter.
    #[serde(default)]
    pub blocked: Vec<usize>,
    pub state: PatrolState,
    /// Default `nc_drone`.
    #[serde(default)]
    pub strategy: Option<StrategyName>,
    #[serde(default)]
    pub tie_rule: Option<TieRule>,
    #[serde(default)]
    pub time_ties: Option<bool>,
    #[serde(default)]
    pub evaporation: Option<Evaporation>,
    /// Seed of this cycle's random choices (default 0).
    #[serde(default)]
    pub seed: Option<u64>,
}

#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct NextMovesResponse {
    /// Each UAV's next cell, in the order of `state.at` (`null`: every neighbour is taken).
    pub moves: Vec<Option<usize>>,
    /// The state to send with the next cycle.
    pub state: PatrolState,
}

#[utoipa::path(post, operation_id = "patrol_next_moves", path = "/api/v1/patrols/next-moves", tag = "patrols", request_body = NextMovesRequest,
    responses((status = 200, body = NextMovesResponse), (status = 422, body = Problem)))]
pub async fn next_moves(ApiJson(request): ApiJson<NextMovesRequest>) -> Result<Json<NextMovesResponse>, ApiError> {
    if request.strategy == Some(StrategyName::SharedCycle) {
        return Err(ApiError::invalid("strategy_not_online", "/strategy", "shared_cycle is a fixed walk, not a cycle-by-cycle decision: use nc_drone or another online method"));
    }
    let cells = request.cols.saturating_mul(request.rows);
    if cells > patrol::MAX_CELLS {
        return Err(ApiError::invalid("grid_too_large", "/cols", format!("the grid has 1 to {} cells", patrol::MAX_CELLS)));
    }
    let s = &request.state;
    if s.u.len() != cells || s.last_visit.len() != cells {
        return Err(ApiError::invalid("state_mismatch", "/state/u", format!("`u` and `last_visit` have one value per cell: {cells}")));
    }
    if let Some(k) = s.u.iter().position(|v| !v.is_finite()) {
        return Err(ApiError::invalid("parameter_out_of_range", &format!("/state/u/{k}"), "u-values are finite numbers"));
    }
    if s.cycle == 0 {
        return Err(ApiError::invalid("parameter_out_of_range", "/state/cycle", "cycles count from 1"));
    }
    if let Some(k) = s.last_visit.iter().position(|&t| t > s.cycle) {
        return Err(ApiError::invalid("state_mismatch", &format!("/state/last_visit/{k}"), "a last visit cannot be after the cycle about to run"));
    }
    if s.at.is_empty() || s.at.len() > 64 || s.headings.len() != s.at.len() {
        return Err(ApiError::invalid("state_mismatch", "/state/at", "1 to 64 UAVs, each with a heading"));
    }
    let mut grid = CellGrid::open(request.cols, request.rows);
    for (k, &b) in request.blocked.iter().enumerate() {
        let cell = grid.free.get_mut(b).ok_or_else(|| ApiError::invalid("cell_outside_grid", &format!("/blocked/{k}"), "no such cell"))?;
        *cell = false;
    }
    if let Some(k) = s.at.iter().position(|&c| c >= cells || !grid.free[c]) {
        return Err(ApiError::invalid("position_not_free", &format!("/state/at/{k}"), "each UAV is on a free cell of the grid"));
    }
    if let Some(k) = s.headings.iter().position(|&h| h > 3) {
        return Err(ApiError::invalid("parameter_out_of_range", &format!("/state/headings/{k}"), "headings are 0 (north), 1 (east), 2 (south) or 3 (west)"));
    }
    let params = PatrolParams { strategy: request.strategy, tie_rule: request.tie_rule, time_ties: request.time_ties, evaporation: request.evaporation, ..PatrolParams::default() };
    let strategy = params.strategy()?;
    let (moves, state) = patrol::next_moves(&grid, &strategy, request.state, request.seed.unwrap_or(0));
    Ok(Json(NextMovesResponse { moves, state }))
}
