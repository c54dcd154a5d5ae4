//! `/api/v1/missions`: the fields to cover.

use axum::Json;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use utoipa::{IntoParams, ToSchema};

use super::AppState;
use super::auth::Caller;
use super::error::{ApiError, ApiJson, ApiQuery, Problem, off_the_async_threads};
use crate::planner::import::ImportedGuidance;
use crate::planner::{self, MissionGeometry, import};
use crate::store::missions::{self, Mission, MissionSummary, NewMission};
use crate::store::plans::{self, JobKind};

#[derive(Debug, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct MissionRequest {
    /// 1 to 200 characters, not all blank.
    #[schema(min_length = 1, max_length = 200, pattern = "\\S")]
    pub name: String,
    /// GeoJSON Polygon, MultiPolygon, Feature or FeatureCollection of those, WGS84 [lon, lat].
    /// Inner rings are holes: parts not to cover. A LineString (or MultiLineString) Feature with
    /// a `width_m` property (metres, at most 2 000) is a corridor: a road, river or pipeline,
    /// covered as its centre line grown by half its width (planner `corridor` flies along it).
    #[schema(value_type = Object)]
    pub area: Value,
    /// GeoJSON of areas never to be entered.
    #[serde(default)]
    #[schema(value_type = Option<Object>)]
    pub no_fly_zones: Option<Value>,
    /// GeoJSON Feature or FeatureCollection of Polygon features, each with a `height_m`
    /// property (metres above ground): trees, buildings, masts to climb over.
    #[serde(default)]
    #[schema(value_type = Option<Object>)]
    pub obstacles: Option<Value>,
    /// GeoJSON FeatureCollection of structures to inspect (planner `inspection`): Polygon
    /// features, or Point features with `radius_m` (silos, trees), each with `height_m`, and
    /// optionally `base_m` (metres above ground where it starts, default 0) and a unique `name`.
    #[serde(default)]
    #[schema(value_type = Option<Object>)]
    pub structures: Option<Value>,
    /// [longitude, latitude] of the take-off and landing point.
    #[serde(default)]
    #[schema(min_items = 2, max_items = 2)]
    pub home: Option<[f64; 2]>,
}

impl MissionRequest {
    /// Validates everything the planner will need, so that a stored mission can be planned.
    async fn validate(self, state: &AppState) -> Result<NewMission, ApiError> {
        let name = self.name.trim().to_owned();
        if name.is_empty() || name.chars().count() > 200 {
            return Err(ApiError::invalid("invalid_name", "/name", "the name must have 1 to 200 characters"));
        }
        let limits = state.config.limits;
        off_the_async_threads(move || {
            let geometry = MissionGeometry {
                area: &self.area,
                no_fly_zones: self.no_fly_zones.as_ref(),
                obstacles: self.obstacles.as_ref(),
                structures: self.structures.as_ref(),
                home: self.home,
                terrain: None,
            };
            planner::validate_mission(&geometry, &limits)?;
            Ok::<_, ApiError>(NewMission {
                name,
                area: self.area,
                no_fly_zones: self.no_fly_zones.filter(|v| !v.is_null()),
                obstacles: self.obstacles.filter(|v| !v.is_null()),
                structures: self.structures.filter(|v| !v.is_null()),
                home: self.home,
            })
        })
        .await
    }
}

#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct Page {
    /// 1 to 100 (default 20)
    #[param(minimum = 1, maximum = 100)]
    pub limit: Option<i64>,
    /// default 0
    #[param(minimum = 0)]
    pub offset: Option<i64>,
    /// `all` (default): whole missions; `summary`: id, name and times only, for pickers.
    #[param(inline)]
    pub fields: Option<Fields>,
}

#[derive(Debug, Clone, Copy, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum Fields {
    All,
    Summary,
}

/// Whole missions, or their summaries (`fields=summary`).
#[derive(Debug, Serialize, ToSchema)]
#[serde(untagged)]
pub enum MissionItems {
    Missions(Vec<Mission>),
    Summaries(Vec<MissionSummary>),
}

#[derive(Debug, Serialize, ToSchema)]
pub struct MissionPage {
    pub items: MissionItems,
    pub total: i64,
    pub limit: i64,
    pub offset: i64,
}

#[utoipa::path(post, operation_id = "create_mission", path = "/api/v1/missions", tag = "missions", request_body = MissionRequest,
    responses((status = 201, body = Mission), (status = 422, body = Problem, content_type = "application/problem+json"),
              (status = 400, body = Problem), (status = 413, body = Problem)))]
pub async fn create(State(state): State<AppState>, caller: Caller, ApiJson(req): ApiJson<MissionRequest>) -> Result<(StatusCode, Json<Mission>), ApiError> {
    let new = req.validate(&state).await?;
    Ok((StatusCode::CREATED, Json(missions::create(&state.db, &caller.tenant, &new).await?)))
}

/// `POST /api/v1/missions/import` options.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct ImportQuery {
    /// `geojson`, `kml`, `kmz`, `shapefile` (a zip of .shp, .shx, .dbf and .prj), `isoxml`
    /// (TaskData zip or XML) or `plan` (QGroundControl); found from the content when left out.
    pub format: Option<String>,
    /// The mission's name (default: the name the file gives, else "Imported field").
    pub name: Option<String>,
}

/// The mission made from a file, and what of the file was left out and why.
#[derive(Debug, Serialize, ToSchema)]
pub struct ImportedMission {
    #[serde(flatten)]
    pub mission: Mission,
    /// The farm's guidance lines the file holds (ISOXML AB and A+ patterns), each a plan's
    /// `guidance` as it is.
    pub guidance: Vec<ImportedGuidance>,
    pub warnings: Vec<String>,
}

#[utoipa::path(post, operation_id = "import_mission", path = "/api/v1/missions/import", tag = "missions", params(ImportQuery),
    request_body(content = String, content_type = "application/octet-stream", description = "the file, as it is (binary)"),
    responses((status = 201, body = ImportedMission), (status = 400, body = Problem, description = "unknown format, or an unreadable query parameter"),
              (status = 413, body = Problem), (status = 422, body = Problem, description = "the file or a part of it is unreadable or not a valid field")))]
pub async fn import_file(
    State(state): State<AppState>,
    caller: Caller,
    ApiQuery(query): ApiQuery<ImportQuery>,
    body: axum::body::Bytes,
) -> Result<(StatusCode, Json<ImportedMission>), ApiError> {
    if let Some(format) = query.format.as_deref().filter(|f| !import::format_ids().contains(f)) {
        return Err(ApiError::bad_request("unknown_format", "/format", format!("no import format `{format}`; known: {}", import::format_ids().join(", "))));
    }
    // parsing a large file takes a while: off the async runtime
    let format = query.format.clone();
    let imported = off_the_async_threads(move || import::import(format.as_deref(), &body)).await?;
    let name = query.name.or(imported.name).unwrap_or_else(|| "Imported field".to_owned());
    let request = MissionRequest { name, area: imported.area, no_fly_zones: imported.no_fly_zones, obstacles: imported.obstacles, structures: None, home: imported.home };
    let new = request.validate(&state).await?;
    let mission = missions::create(&state.db, &caller.tenant, &new).await?;
    Ok((StatusCode::CREATED, Json(ImportedMission { mission, guidance: imported.guidance, warnings: imported.warnings })))
}

#[utoipa::path(get, operation_id = "list_missions", path = "/api/v1/missions", tag = "missions", params(Page),
    responses((status = 200, body = MissionPage), (status = 400, body = Problem, description = "an unreadable query parameter"), (status = 422, body = Problem)))]
pub async fn list(State(state): State<AppState>, caller: Caller, ApiQuery(page): ApiQuery<Page>) -> Result<Json<MissionPage>, ApiError> {
    let limit = page.limit.unwrap_or(20);
    let offset = page.offset.unwrap_or(0);
    if !(1..=100).contains(&limit) {
        return Err(ApiError::invalid("parameter_out_of_range", "/limit", "limit must be between 1 and 100"));
    }
    if offset < 0 {
        return Err(ApiError::invalid("parameter_out_of_range", "/offset", "offset must not be negative"));
    }
    let (items, total) = match page.fields.unwrap_or(Fields::All) {
        Fields::All => missions::list(&state.db, &caller.tenant, limit, offset).await.map(|(m, n)| (MissionItems::Missions(m), n))?,
        Fields::Summary => missions::list_summaries(&state.db, &caller.tenant, limit, offset).await.map(|(m, n)| (MissionItems::Summaries(m), n))?,
    };
    Ok(Json(MissionPage { items, total, limit, offset }))
}

#[utoipa::path(get, operation_id = "get_mission", path = "/api/v1/missions/{id}", tag = "missions", params(("id" = String, Path)),
    responses((status = 200, body = Mission), (status = 404, body = Problem)))]
pub async fn get(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<Mission>, ApiError> {
    missions::get(&state.db, &caller.tenant, &id).await?.map(Json).ok_or_else(|| ApiError::not_found("mission", &id))
}

#[utoipa::path(put, operation_id = "update_mission", path = "/api/v1/missions/{id}", tag = "missions", params(("id" = String, Path)), request_body = MissionRequest,
    responses((status = 200, body = Mission), (status = 404, body = Problem), (status = 422, body = Problem)))]
pub async fn update(State(state): State<AppState>, caller: Caller, Path(id): Path<String>, ApiJson(req): ApiJson<MissionRequest>) -> Result<Json<Mission>, ApiError> {
    let new = req.validate(&state).await?;
    missions::update(&state.db, &caller.tenant, &id, &new).await?.map(Json).ok_or_else(|| ApiError::not_found("mission", &id))
}

#[utoipa::path(delete, operation_id = "delete_mission", path = "/api/v1/missions/{id}", tag = "missions", params(("id" = String, Path)),
    responses((status = 204, description = "deleted, with its plans"), (status = 404, body = Problem)))]
pub async fn delete(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<StatusCode, ApiError> {
    for kind in [JobKind::Plan, JobKind::Patrol] {
        for job in plans::list_for_mission(&state.db, &caller.tenant, kind, &id).await? {
            state.jobs.cancel(&job.id);
        }
    }
    if missions::delete(&state.db, &caller.tenant, &id).await? { Ok(StatusCode::NO_CONTENT) } else { Err(ApiError::not_found("mission", &id)) }
}
