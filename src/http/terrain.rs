//! `/api/v1/missions/{id}/terrain`: the mission's elevation model, for plans flown at a height
//! above the ground (`altitude_reference: terrain`).

use axum::Json;
use axum::body::Body;
use axum::extract::{Path, State};
use axum::http::{HeaderMap, StatusCode, header};
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use super::AppState;
use super::auth::Caller;
use super::error::{ApiError, ApiQuery, Problem, off_the_async_threads};
use crate::planner;
use crate::planner::terrain::{ElevationModel, MAX_MODEL_BYTES, TerrainGrid, TerrainSummary};
use crate::store::{missions, terrain};

/// `PUT /api/v1/missions/{id}/terrain` options.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct TerrainQuery {
    /// The file's name. An SRTM tile's name gives its place (`N36W084.hgt`); default
    /// `terrain.tif`.
    pub name: Option<String>,
}

/// A mission's elevation model: what was read from it.
#[derive(Debug, Serialize, ToSchema)]
pub struct Terrain {
    pub file_name: String,
    #[serde(flatten)]
    pub summary: TerrainSummary,
    pub created_at: String,
}

/// Media types a model may be sent as.
const MEDIA_TYPES: &[&str] = &["image/tiff", "application/octet-stream", "application/zip", "application/x-zip-compressed"];

#[utoipa::path(put, operation_id = "put_terrain", path = "/api/v1/missions/{id}/terrain", tag = "missions", params(("id" = String, Path), TerrainQuery),
    request_body(content = String, content_type = "application/octet-stream", description = "the file as it is: a GeoTIFF (EPSG:4326 or a WGS84 UTM zone; integer or float \
        heights in metres above mean sea level), or an SRTM .hgt tile, plain or zipped; at most 64 MB. Also accepted as image/tiff, application/zip or application/x-zip-compressed"),
    responses((status = 200, body = Terrain, description = "stored, replacing any model the mission had"), (status = 404, body = Problem),
        (status = 413, body = Problem, description = "the file is over the size limit"), (status = 415, body = Problem, description = "another media type"),
        (status = 422, body = Problem, description = "not an elevation model, an unsupported coordinate system, or a model that does not cover the fields and home with a 100 m margin")))]
pub async fn put(
    State(state): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
    ApiQuery(query): ApiQuery<TerrainQuery>,
    headers: HeaderMap,
    body: Body,
) -> Result<Json<Terrain>, ApiError> {
    // another tenant's mission is one that does not exist, whatever the body
    let mission = missions::get(&state.db, &caller.tenant, &id).await?.ok_or_else(|| ApiError::not_found("mission", &id))?;
    let media_type = headers.get(header::CONTENT_TYPE).and_then(|v| v.to_str().ok()).unwrap_or("").split(';').next().unwrap_or("").trim().to_ascii_lowercase();
    if !MEDIA_TYPES.contains(&media_type.as_str()) {
        return Err(ApiError::Client {
            status: StatusCode::UNSUPPORTED_MEDIA_TYPE,
            code: "unsupported_media_type",
            detail: format!("send the elevation model as it is, with Content-Type {} (this request says `{media_type}`)", MEDIA_TYPES.join(", ")),
            pointer: None,
        });
    }
    // the model has its own size limit, larger than the JSON bodies'
    let bytes = axum::body::to_bytes(body, MAX_MODEL_BYTES).await.map_err(|_| ApiError::Client {
        status: StatusCode::PAYLOAD_TOO_LARGE,
        code: "terrain_too_large",
        detail: format!("the elevation model is larger than {} MB: crop it to the fields (for example with gdal_translate -projwin)", MAX_MODEL_BYTES / 1024 / 1024),
        pointer: None,
    })?;
    let file_name = query.name.unwrap_or_else(|| "terrain.tif".to_owned());
    let limits = state.config.limits;
    let (summary, bytes, file_name) = off_the_async_threads(move || {
        let model = ElevationModel::read(&bytes, &file_name)?;
        planner::check_terrain_covers(&mission.geometry(None), &model, &limits)?;
        Ok::<_, ApiError>((model.summary(), bytes, file_name))
    })
    .await?;
    let summary_json = serde_json::to_value(&summary).map_err(|e| ApiError::Internal(format!("terrain summary: {e}")))?;
    let record = terrain::put(&state.db, &caller.tenant, &id, &file_name, &bytes, &summary_json).await?.ok_or_else(|| ApiError::not_found("mission", &id))?;
    Ok(Json(Terrain { file_name: record.file_name, summary, created_at: record.created_at }))
}

#[utoipa::path(get, operation_id = "get_terrain", path = "/api/v1/missions/{id}/terrain", tag = "missions", params(("id" = String, Path)),
    responses((status = 200, body = Terrain), (status = 404, body = Problem, description = "no such mission, or it has no elevation model")))]
pub async fn get(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<Terrain>, ApiError> {
    let record = terrain::get(&state.db, &caller.tenant, &id).await?.ok_or_else(|| missing(&id))?;
    let summary: TerrainSummary = serde_json::from_value(record.summary.0).map_err(|e| ApiError::Internal(format!("stored terrain summary is unreadable: {e}")))?;
    Ok(Json(Terrain { file_name: record.file_name, summary, created_at: record.created_at }))
}

#[utoipa::path(delete, operation_id = "delete_terrain", path = "/api/v1/missions/{id}/terrain", tag = "missions", params(("id" = String, Path)),
    responses((status = 204, description = "deleted"), (status = 404, body = Problem, description = "no such mission, or it has no elevation model")))]
pub async fn delete(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<StatusCode, ApiError> {
    if terrain::delete(&state.db, &caller.tenant, &id).await? { Ok(StatusCode::NO_CONTENT) } else { Err(missing(&id)) }
}

/// `GET /api/v1/missions/{id}/terrain/grid` options.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct GridQuery {
    /// Samples along the longer side, 2 to 512 (default 256).
    #[param(minimum = 2, maximum = 512)]
    pub size: Option<usize>,
}

#[utoipa::path(get, operation_id = "get_terrain_grid", path = "/api/v1/missions/{id}/terrain/grid", tag = "missions", params(("id" = String, Path), GridQuery),
    responses((status = 200, body = TerrainGrid, description = "the model's heights on a regular longitude/latitude grid, for drawing it"),
        (status = 404, body = Problem, description = "no such mission, or it has no elevation model"), (status = 400, body = Problem), (status = 422, body = Problem)))]
pub async fn grid(State(state): State<AppState>, caller: Caller, Path(id): Path<String>, ApiQuery(query): ApiQuery<GridQuery>) -> Result<Json<TerrainGrid>, ApiError> {
    let size = query.size.unwrap_or(256);
    if !(2..=512).contains(&size) {
        return Err(ApiError::invalid("parameter_out_of_range", "/size", format!("{size} is outside the accepted range [2, 512] samples")));
    }
    let (name, bytes) = terrain::model(&state.db, &caller.tenant, &id).await?.ok_or_else(|| missing(&id))?;
    let grid = off_the_async_threads(move || Ok::<_, ApiError>(ElevationModel::read(&bytes, &name)?.grid(size))).await?;
    Ok(Json(grid))
}

fn missing(id: &str) -> ApiError {
    ApiError::Client { status: StatusCode::NOT_FOUND, code: "not_found", detail: format!("mission `{id}` has no elevation model (or there is no such mission)"), pointer: None }
}
