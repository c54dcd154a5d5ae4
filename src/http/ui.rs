//! `GET /api/v1/ui-config`: what the map page needs from the server's configuration.

use axum::Json;
use axum::extract::State;
use serde::Serialize;
use utoipa::ToSchema;

use super::AppState;

#[derive(Debug, Serialize, ToSchema)]
pub struct UiConfig {
    /// Leaflet tile URL template (`COVERPLAN_TILE_URL`); absent: the page draws without tiles.
    pub tile_url: Option<String>,
    pub tile_attribution: Option<String>,
}

#[utoipa::path(get, operation_id = "get_ui_config", path = "/api/v1/ui-config", tag = "planners", responses((status = 200, body = UiConfig)))]
pub async fn config(State(state): State<AppState>) -> Json<UiConfig> {
    Json(UiConfig { tile_url: state.config.tile_url.clone(), tile_attribution: state.config.tile_attribution.clone() })
}
