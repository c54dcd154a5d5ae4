//! Liveness and readiness.

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use serde::Serialize;
use utoipa::ToSchema;

use super::AppState;

#[derive(Debug, Serialize, ToSchema)]
pub struct Health {
    pub status: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub workers: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub database: Option<&'static str>,
}

#[utoipa::path(get, path = "/healthz", tag = "health", responses((status = 200, body = Health, description = "the process answers")))]
pub async fn healthz() -> Json<Health> {
    Json(Health { status: "ok", workers: None, database: None })
}

#[utoipa::path(get, path = "/readyz", tag = "health",
    responses((status = 200, body = Health, description = "database reachable and workers running"), (status = 503, body = Health)))]
pub async fn readyz(State(state): State<AppState>) -> (StatusCode, Json<Health>) {
    let db_ok = state.db.ping().await;
    let workers = state.jobs.workers_alive();
    let ready = db_ok && workers > 0;
    let status = if ready { StatusCode::OK } else { StatusCode::SERVICE_UNAVAILABLE };
    (status, Json(Health { status: if ready { "ready" } else { "not_ready" }, workers: Some(workers), database: Some(if db_ok { "ok" } else { "unreachable" }) }))
}
