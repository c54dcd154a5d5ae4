//! The HTTP layer: one module per resource, one error type, the OpenAPI document.
//!
//! Every API route is declared with its OpenAPI entry (`routes!` reads the handler's
//! `#[utoipa::path]`), so no route can go undocumented.

pub mod assets;
pub mod auth;
pub mod error;
pub mod farms;
pub mod health;
pub mod idempotency;
pub mod metrics;
pub mod missions;
pub mod openapi;
pub mod patrols;
pub mod planners;
pub mod plans;
pub mod resume;
pub mod terrain;
pub mod ui;
pub mod vehicles;

use std::sync::Arc;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::routing::any;
use tower_http::catch_panic::CatchPanicLayer;
use tower_http::services::ServeDir;
use tower_http::trace::TraceLayer;
use utoipa::OpenApi;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;
use utoipa_swagger_ui::SwaggerUi;

use crate::config::Config;
use crate::jobs::JobQueue;
use crate::store::Db;

#[derive(Clone)]
pub struct AppState {
    pub db: Db,
    pub jobs: Arc<JobQueue>,
    pub config: Arc<Config>,
    pub limiter: Arc<auth::KeyLimiter>,
}

/// Every documented route, with the document they make.
pub fn api() -> OpenApiRouter<AppState> {
    OpenApiRouter::with_openapi(openapi::ApiDoc::openapi())
        .routes(routes!(health::healthz))
        .routes(routes!(health::readyz))
        .routes(routes!(metrics::metrics))
        .routes(routes!(missions::list, missions::create))
        .routes(routes!(missions::import_file))
        .routes(routes!(missions::get, missions::update, missions::delete))
        .routes(routes!(terrain::put, terrain::get, terrain::delete))
        .routes(routes!(terrain::grid))
        .routes(routes!(plans::list, plans::create))
        .routes(routes!(plans::get, plans::cancel))
        .routes(routes!(plans::trajectory))
        .routes(routes!(resume::resume))
        .routes(routes!(farms::create))
        .routes(routes!(farms::get, farms::cancel))
        .routes(routes!(farms::schedule_csv))
        .routes(routes!(farms::taskdata))
        .routes(routes!(farms::flights))
        .routes(routes!(patrols::create))
        .routes(routes!(patrols::get, patrols::cancel))
        .routes(routes!(patrols::trajectory))
        .routes(routes!(patrols::next_moves))
        .routes(routes!(planners::list))
        .routes(routes!(planners::cameras))
        .routes(routes!(planners::formats))
        .routes(routes!(vehicles::list, vehicles::create))
        .routes(routes!(vehicles::get, vehicles::update, vehicles::delete))
        .routes(routes!(vehicles::estimate))
        .routes(routes!(ui::config))
}

pub fn router(state: AppState) -> Router {
    let (api, document) = api().split_for_parts();
    let document = openapi::complete(document);
    let no_route = || async { error::ApiError::Client { status: StatusCode::NOT_FOUND, code: "no_route", detail: "no such API route".into(), pointer: None } };
    let router = Router::new().merge(api).route("/api/v1/{*rest}", any(no_route)).merge(SwaggerUi::new("/docs").external_url_unchecked("/openapi.json", document));
    // the page: embedded in the binary, or from a folder while developing it
    let router = match &state.config.static_dir {
        Some(dir) => router.fallback_service(ServeDir::new(dir)),
        None => router.fallback(assets::embedded),
    };
    router
        // inner layers run last: the idempotency key is the caller's, known once authenticated
        .layer(axum::middleware::from_fn_with_state(state.clone(), idempotency::idempotent))
        .layer(axum::middleware::from_fn_with_state(state.clone(), auth::authenticate))
        .layer(DefaultBodyLimit::max(state.config.max_body_bytes))
        .layer(catch_panics())
        // per route (so that the route's template is known), outside every refusal above
        .layer(axum::middleware::from_fn_with_state(state.clone(), metrics::track))
        .layer(TraceLayer::new_for_http())
        .with_state(state)
}

/// A handler that panics answers 500 with a problem document (and the panic is logged), instead
/// of a dropped connection.
pub fn catch_panics() -> CatchPanicLayer<fn(Box<dyn std::any::Any + Send>) -> Response> {
    CatchPanicLayer::custom(|panic: Box<dyn std::any::Any + Send>| error::ApiError::Internal(format!("a handler panicked: {}", crate::panic_message(&*panic))).into_response())
}
