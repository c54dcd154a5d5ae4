//! The HTTP layer: one module per resource, one error type, the OpenAPI document.

pub mod error;
pub mod health;
pub mod missions;
pub mod openapi;
pub mod planners;
pub mod plans;
pub mod ui;
pub mod vehicles;

use std::sync::Arc;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::StatusCode;
use axum::routing::get;
use tower_http::services::ServeDir;
use tower_http::trace::TraceLayer;
use utoipa::OpenApi;
use utoipa_swagger_ui::SwaggerUi;

use crate::config::Config;
use crate::jobs::JobQueue;
use crate::store::Db;

#[derive(Clone)]
pub struct AppState {
    pub db: Db,
    pub jobs: Arc<JobQueue>,
    pub config: Arc<Config>,
}

pub fn router(state: AppState) -> Router {
    let api = Router::new()
        .route("/missions", get(missions::list).post(missions::create))
        .route("/missions/{id}", get(missions::get).put(missions::update).delete(missions::delete))
        .route("/missions/{id}/plans", get(plans::list).post(plans::create))
        .route("/plans/{id}", get(plans::get).delete(plans::cancel))
        .route("/plans/{id}/trajectory", get(plans::trajectory))
        .route("/planners", get(planners::list))
        .route("/cameras", get(planners::cameras))
        .route("/vehicles", get(vehicles::list).post(vehicles::create))
        .route("/vehicles/{id}", get(vehicles::get).put(vehicles::update).delete(vehicles::delete))
        .route("/estimates", axum::routing::post(vehicles::estimate))
        .route("/ui-config", get(ui::config))
        .fallback(|| async { error::ApiError::Client { status: StatusCode::NOT_FOUND, code: "no_route", detail: "no such API route".into(), pointer: None } });
    let static_dir = ServeDir::new(&state.config.static_dir);
    Router::new()
        .route("/healthz", get(health::healthz))
        .route("/readyz", get(health::readyz))
        .nest("/api/v1", api)
        .merge(SwaggerUi::new("/docs").url("/openapi.json", openapi::ApiDoc::openapi()))
        .fallback_service(static_dir)
        .layer(DefaultBodyLimit::max(state.config.max_body_bytes))
        .layer(TraceLayer::new_for_http())
        .with_state(state)
}
