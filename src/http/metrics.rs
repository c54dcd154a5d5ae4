//! `GET /metrics` for Prometheus, and the layer that counts and times every request.

use std::time::Instant;

use axum::extract::{MatchedPath, Request, State};
use axum::http::{StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use super::AppState;
use super::auth::Caller;
use super::error::{ApiError, Problem};
use crate::store::plans;

/// Counts and times a request under its route's template (`other` for the page's files and
/// unknown paths, so that no path makes a series of its own).
pub async fn track(State(state): State<AppState>, request: Request, next: Next) -> Response {
    let route = request.extensions().get::<MatchedPath>().map_or("other", |p| p.as_str()).to_owned();
    let method = request.method().as_str().to_owned();
    let started = Instant::now();
    let response = next.run(request).await;
    state.jobs.telemetry.request(&method, &route, response.status().as_u16(), started.elapsed());
    response
}

#[utoipa::path(get, operation_id = "get_metrics", path = "/metrics", tag = "health",
    responses((status = 200, description = "OpenMetrics text: coverplan_http_requests_total and coverplan_http_request_duration_seconds by route, \
        coverplan_queue_depth, coverplan_jobs_running, coverplan_jobs_total and coverplan_job_duration_seconds by planner and outcome",
        content_type = "application/openmetrics-text", body = String),
        (status = 403, body = Problem, description = "a key that is not an admin's")))]
pub async fn metrics(State(state): State<AppState>, caller: Caller) -> Result<Response, ApiError> {
    if !caller.admin {
        return Err(ApiError::Client { status: StatusCode::FORBIDDEN, code: "admin_only", detail: "the metrics are for the operator: use an admin key".into(), pointer: None });
    }
    let queued = plans::queued_count(&state.db).await?;
    let text = state.jobs.telemetry.render(queued, state.jobs.running_count() as i64);
    Ok(([(header::CONTENT_TYPE, "application/openmetrics-text; version=1.0.0; charset=utf-8")], text).into_response())
}
