//! One error type for every route, answered as RFC 9457 problem details. Internal errors are
//! logged and answered without their details.

use axum::extract::{FromRequest, FromRequestParts, Request};
use axum::http::request::Parts;
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use serde::de::DeserializeOwned;
use utoipa::ToSchema;

use crate::planner::InputError;

/// Every `code` a client can receive, in a problem document or as a failed plan's `error_code`:
/// the OpenAPI document lists them (schema `ErrorCode`), and `tests/it/registries.rs` checks that
/// every code the sources write is here.
pub const ERROR_CODES: &[&str] = &[
    "admin_only",
    "altitude_missing",
    "archive_too_large",
    "area_too_large",
    "area_too_small",
    "battery_too_large",
    "body_too_large",
    "budget_missing",
    "budget_too_small",
    "budget_twice",
    "builtin_vehicle",
    "camera_altitude_twice",
    "camera_incomplete",
    "camera_missing",
    "camera_needs_altitude",
    "cell_outside_grid",
    "cell_size_out_of_range",
    "cell_size_twice",
    "coordinate_out_of_range",
    "coordinates_look_swapped",
    "corridor_width_missing",
    "crs_not_supported",
    "curvature_rate_too_low",
    "cut_ambiguous",
    "cut_missing",
    "cut_off_path",
    "degenerate_corridor",
    "degenerate_ring",
    "direction_for_fleet",
    "direction_twice",
    "empty_area",
    "empty_file",
    "empty_geometry",
    "empty_polygon",
    "field_too_narrow",
    "field_twice",
    "fields_missing",
    "fields_twice",
    "fleet_mixed",
    "fleet_size",
    "fleet_twice",
    "format_not_applicable",
    "grid_too_large",
    "ground_figures_missing",
    "gsd_out_of_reach",
    "guidance_and_heading",
    "guidance_too_short",
    "guidance_twice",
    "guidance_without_direction",
    "headland_not_covered",
    "headland_too_narrow",
    "hole_outside_shell",
    "home_in_no_fly_zone",
    "home_missing",
    "idempotency_in_progress",
    "idempotency_key_reused",
    "infeasible",
    "instance_too_large",
    "internal",
    "interrupted",
    "invalid_body",
    "invalid_date",
    "invalid_energy_model",
    "invalid_geojson",
    "invalid_idempotency_key",
    "invalid_isoxml",
    "invalid_kml",
    "invalid_model",
    "invalid_name",
    "invalid_plan",
    "invalid_polygon",
    "invalid_position",
    "invalid_profile_id",
    "invalid_query",
    "invalid_shapefile",
    "invalid_terrain",
    "invalid_time",
    "invalid_trajectory",
    "invalid_waypoints",
    "invalid_xml",
    "invalid_zip",
    "landing_sites_for_fleet",
    "leg_too_long",
    "log_off_path",
    "log_other_vehicle",
    "log_unreadable",
    "log_without_position",
    "malformed_json",
    "max_waypoints_too_few",
    "missing_file_part",
    "missing_geometry",
    "mission_too_wide",
    "model_below_ground",
    "model_needs_anchor",
    "no_corridor",
    "no_fields",
    "no_route",
    "no_structures",
    "not_a_fixed_wing",
    "not_a_fleet",
    "not_a_ground_vehicle",
    "not_a_linestring",
    "not_a_multirotor",
    "not_an_inspection",
    "not_for_farm_plans",
    "not_for_fixed_wing",
    "not_for_ground_vehicles",
    "not_for_inspection",
    "not_for_planner",
    "not_found",
    "not_landing",
    "not_over_terrain",
    "not_resumable",
    "not_with_at",
    "nothing_left",
    "nothing_to_cover",
    "nothing_to_inspect",
    "oblique_view_reaches_horizon",
    "obstacle_height_missing",
    "obstacles",
    "options_in_query",
    "overlapping_fields",
    "parameter_out_of_range",
    "patrol_too_long",
    "pattern_not_for_fleets",
    "pitch_without_oblique",
    "plan_too_long",
    "planner_not_applicable",
    "planner_not_for_fleets",
    "planner_vehicle_mismatch",
    "point_in_no_fly_zone",
    "position_missing",
    "position_not_free",
    "profile_mismatch",
    "radius_missing",
    "range_reversed",
    "range_too_short",
    "rate_limited",
    "refill_point_far",
    "ring_not_closed",
    "ring_too_short",
    "rings_intersect",
    "route_missing",
    "route_twice",
    "schedule_not_available",
    "self_intersection",
    "server_time_limit",
    "spacing_missing",
    "spacing_out_of_range",
    "start_missing",
    "start_outside_area",
    "state_mismatch",
    "strategy_not_online",
    "structure_height_missing",
    "structure_name_twice",
    "structure_not_one_polygon",
    "structures_not_a_collection",
    "targets_outside_area",
    "terrain_missing",
    "terrain_not_covering",
    "terrain_too_large",
    "time_limit",
    "too_many_farm_plans",
    "too_many_fields",
    "too_many_lines",
    "too_many_plans",
    "too_many_points",
    "too_many_vertices",
    "too_many_zone_corners",
    "trajectory_not_available",
    "turn_radius_too_small",
    "unauthorised",
    "unknown_camera",
    "unknown_firmware",
    "unknown_format",
    "unknown_planner",
    "unknown_seq",
    "unknown_target",
    "unknown_vehicle_profile",
    "unreadable_body",
    "unsupported_crs",
    "unsupported_geometry",
    "unsupported_media_type",
    "unsupported_projection",
    "vehicle_exists",
    "vehicle_kind_mismatch",
    "vehicle_missing",
    "waypoint_count",
    "wind_too_strong",
    "wrong_winding",
    "xml_entities_refused",
];

/// Refusals that no JSON Schema can state, by what they depend on: a request the OpenAPI
/// document allows may still get one of them. Each operation's 422 answer lists the ones it can
/// give (`x-beyond-schema`, [`super::openapi`]); the fuzz test (`tests/fuzz/`) fails on any other
/// refusal of a request generated as valid, which would be a gap in the document.
pub mod beyond_schema {
    /// Geometry: rings closed, simple and with area, holes inside their shell, fields apart,
    /// the mission's size.
    pub const GEOMETRY: &[&str] = &[
        "area_too_large",
        "area_too_small",
        "corridor_width_missing",
        "crs_not_supported",
        "degenerate_corridor",
        "degenerate_ring",
        "empty_area",
        "hole_outside_shell",
        "home_in_no_fly_zone",
        "invalid_polygon",
        "mission_too_wide",
        "overlapping_fields",
        "ring_not_closed",
        "rings_intersect",
        "self_intersection",
        "structure_name_twice",
        "too_many_vertices",
    ];
    /// A farm plan: its fields (a mission's polygons, each field planned as its parameters say
    /// and in one group at most), its dates and times, and its roads.
    pub const FARM: &[&str] = &[
        "coordinate_out_of_range",
        "coordinates_look_swapped",
        "field_twice",
        "invalid_date",
        "invalid_time",
        "no_fields",
        "not_for_farm_plans",
        "parameter_out_of_range",
        "too_many_fields",
        "too_many_points",
    ];
    /// A route's legs, each at most 1 000 km.
    pub const ROUTE: &[&str] = &["leg_too_long"];
    /// A file's contents (an OBJ model's among them).
    pub const FILE: &[&str] = &[
        "empty_file",
        "invalid_isoxml",
        "invalid_kml",
        "invalid_model",
        "invalid_shapefile",
        "invalid_terrain",
        "invalid_xml",
        "invalid_zip",
        "model_below_ground",
        "unknown_format",
        "xml_entities_refused",
    ];
    /// An imported file's contents, where the request's own members would be described.
    pub const IMPORTED: &[&str] = &[
        "coordinate_out_of_range",
        "coordinates_look_swapped",
        "crs_not_supported",
        "empty_geometry",
        "invalid_geojson",
        "invalid_plan",
        "invalid_position",
        "missing_file_part",
        "missing_geometry",
        "ring_too_short",
        "unsupported_geometry",
        "unsupported_projection",
    ];
    /// Figures that must agree with each other: a relation between two numbers, or between
    /// items of a list.
    pub const RELATIONS: &[&str] = &[
        "cell_outside_grid",
        "fleet_mixed",
        "cell_size_out_of_range",
        "curvature_rate_too_low",
        "grid_too_large",
        "gsd_out_of_reach",
        "guidance_and_heading",
        "guidance_too_short",
        "guidance_twice",
        "guidance_without_direction",
        "headland_not_covered",
        "invalid_energy_model",
        "oblique_view_reaches_horizon",
        "patrol_too_long",
        "pattern_not_for_fleets",
        "pitch_without_oblique",
        "position_not_free",
        "profile_mismatch",
        "range_reversed",
        "spacing_out_of_range",
        "state_mismatch",
    ];
    /// A wind beyond the vehicle: its `max_wind_mps`, a fixed wing's airspeed, a ground
    /// vehicle's (which refuses any).
    pub const WIND: &[&str] = &["not_for_ground_vehicles", "wind_too_strong"];
    /// What a format can say of the plan exported: its kind and vehicle, a waypoint limit only
    /// for the files a controller loads, and one a mission can keep.
    pub const EXPORT: &[&str] = &["format_not_applicable", "max_waypoints_too_few"];
    /// The mission a request plans, and the server's own limits.
    pub const MISSION: &[&str] = &[
        "altitude_missing",
        "budget_too_small",
        "field_too_narrow",
        "home_missing",
        "no_corridor",
        "no_structures",
        "not_for_planner",
        "nothing_to_cover",
        "nothing_to_inspect",
        "plan_too_long",
        "point_in_no_fly_zone",
        "refill_point_far",
        "server_time_limit",
        "start_missing",
        "start_outside_area",
        "targets_outside_area",
        "terrain_missing",
        "terrain_not_covering",
        "too_many_lines",
        "too_many_points",
        "too_many_zone_corners",
        "unknown_target",
    ];
    /// The plan a request resumes (its trajectory, its kind, its no-fly zones), which of the
    /// request's members go together (one cut, `from: position` with a position), and what a
    /// flight log holds.
    pub const RESUMED: &[&str] = &[
        "cut_ambiguous",
        "cut_missing",
        "cut_off_path",
        "log_off_path",
        "log_other_vehicle",
        "log_unreadable",
        "log_without_position",
        "not_resumable",
        "not_with_at",
        "nothing_left",
        "options_in_query",
        "point_in_no_fly_zone",
        "position_missing",
        "too_many_points",
        "unknown_seq",
        "vehicle_missing",
    ];
    /// Given only where the request names a stored vehicle profile (`profile`): its kind and
    /// figures, which the overrides and the other members must suit.
    pub const PROFILE: &[&str] = &[
        "battery_too_large",
        "not_a_fixed_wing",
        "not_a_ground_vehicle",
        "not_a_multirotor",
        "not_for_fixed_wing",
        "not_for_ground_vehicles",
        "planner_not_applicable",
        "planner_vehicle_mismatch",
        "spacing_missing",
        "turn_radius_too_small",
        "unknown_vehicle_profile",
        "vehicle_kind_mismatch",
        "wind_too_strong",
    ];
}

/// RFC 9457 problem details.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Problem {
    /// A URI reference naming the kind of problem, `/problems/{code}`.
    #[serde(rename = "type")]
    pub kind: String,
    pub title: String,
    pub status: u16,
    pub detail: String,
    /// Machine-readable code, also the last part of `type`.
    pub code: String,
    /// JSON pointer to the member of the request that is wrong, where one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pointer: Option<String>,
}

#[derive(Debug)]
pub enum ApiError {
    /// 4xx with a code, a detail and maybe a pointer.
    Client {
        status: StatusCode,
        code: &'static str,
        detail: String,
        pointer: Option<String>,
    },
    /// 429: the caller has too much under way; try again after `retry_after_s`.
    TooMany {
        code: &'static str,
        detail: String,
        retry_after_s: u64,
    },
    Internal(String),
}

impl ApiError {
    pub fn not_found(what: &str, id: &str) -> Self {
        ApiError::Client { status: StatusCode::NOT_FOUND, code: "not_found", detail: format!("no {what} with id `{id}`"), pointer: None }
    }

    pub fn conflict(code: &'static str, detail: impl Into<String>) -> Self {
        ApiError::Client { status: StatusCode::CONFLICT, code, detail: detail.into(), pointer: None }
    }

    pub fn bad_request(code: &'static str, pointer: &str, detail: impl Into<String>) -> Self {
        ApiError::Client { status: StatusCode::BAD_REQUEST, code, detail: detail.into(), pointer: Some(pointer.into()) }
    }

    pub fn invalid(code: &'static str, pointer: &str, detail: impl Into<String>) -> Self {
        ApiError::Client { status: StatusCode::UNPROCESSABLE_ENTITY, code, detail: detail.into(), pointer: Some(pointer.into()) }
    }
}

impl From<InputError> for ApiError {
    fn from(e: InputError) -> Self {
        ApiError::Client { status: StatusCode::UNPROCESSABLE_ENTITY, code: e.code, detail: e.detail, pointer: Some(e.pointer) }
    }
}

impl From<sqlx::Error> for ApiError {
    fn from(e: sqlx::Error) -> Self {
        ApiError::Internal(format!("database: {e}"))
    }
}

fn title(status: StatusCode) -> String {
    status.canonical_reason().unwrap_or("Error").to_owned()
}

pub fn problem_response(status: StatusCode, code: &str, detail: String, pointer: Option<String>) -> Response {
    let body = Problem { kind: format!("/problems/{code}"), title: title(status), status: status.as_u16(), detail, code: code.to_owned(), pointer };
    let mut resp = (status, axum::Json(body)).into_response();
    resp.headers_mut().insert(header::CONTENT_TYPE, header::HeaderValue::from_static("application/problem+json"));
    resp
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        match self {
            ApiError::Client { status, code, detail, pointer } => problem_response(status, code, detail, pointer),
            ApiError::TooMany { code, detail, retry_after_s } => {
                let mut response = problem_response(StatusCode::TOO_MANY_REQUESTS, code, detail, None);
                response.headers_mut().insert(header::RETRY_AFTER, header::HeaderValue::from(retry_after_s));
                response
            }
            ApiError::Internal(message) => {
                tracing::error!(%message, "internal error");
                problem_response(StatusCode::INTERNAL_SERVER_ERROR, "internal", "the server could not complete the request; it has been logged".into(), None)
            }
        }
    }
}

/// A JSON body whose every refusal is a problem: 415 for another media type, 413 over the
/// size limit, 400 for malformed JSON, 422 (with a pointer) for a body of the wrong shape.
pub struct ApiJson<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequest<S> for ApiJson<T> {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, Self::Rejection> {
        if !is_json(req.headers()) {
            return Err(ApiError::Client {
                status: StatusCode::UNSUPPORTED_MEDIA_TYPE,
                code: "unsupported_media_type",
                detail: "send the body as JSON with `Content-Type: application/json`".into(),
                pointer: None,
            });
        }
        let bytes = read_body(req, state).await?;
        // JSON first, then its shape: read in one pass, an array longer than a fixed-size
        // field would be reported as "trailing characters", a syntax error it is not
        let json: serde_json::Value = serde_json::from_slice(&bytes).map_err(|e| ApiError::Client {
            status: StatusCode::BAD_REQUEST,
            code: "malformed_json",
            detail: format!("the body is not valid JSON: {e}"),
            pointer: None,
        })?;
        let mut json = json;
        whole_numbers_as_integers(&mut json);
        let value: T = serde_path_to_error::deserialize(json).map_err(|e| ApiError::Client {
            status: StatusCode::UNPROCESSABLE_ENTITY,
            code: "invalid_body",
            detail: e.inner().to_string(),
            pointer: Some(json_pointer(e.path())),
        })?;
        Ok(ApiJson(value))
    }
}

/// The request's body, within the server's limit.
pub async fn read_body<S: Send + Sync>(req: Request, state: &S) -> Result<axum::body::Bytes, ApiError> {
    axum::body::Bytes::from_request(req, state).await.map_err(|e| {
        let status = e.status();
        if status == StatusCode::PAYLOAD_TOO_LARGE {
            ApiError::Client { status, code: "body_too_large", detail: "the request body is larger than the server accepts".into(), pointer: None }
        } else {
            ApiError::Client { status: StatusCode::BAD_REQUEST, code: "unreadable_body", detail: e.body_text(), pointer: None }
        }
    })
}

/// True when the request says its body is JSON.
pub fn is_json(headers: &axum::http::HeaderMap) -> bool {
    headers.get(header::CONTENT_TYPE).and_then(|v| v.to_str().ok()).is_some_and(|v| v.starts_with("application/json") || v.contains("+json"))
}

/// Writes every whole number of `value` as an integer: JSON has one number type and JSON Schema's
/// `integer` admits `3.0`, which serde would refuse for an integer field.
fn whole_numbers_as_integers(value: &mut serde_json::Value) {
    use serde_json::Value;
    // beyond 2^53 a float is whole but no longer exact
    const EXACT: f64 = 9_007_199_254_740_992.0;
    match value {
        Value::Number(n) if n.is_f64() => {
            if let Some(f) = n.as_f64().filter(|f| f.fract() == 0.0 && f.abs() <= EXACT) {
                *value = Value::from(f as i64);
            }
        }
        Value::Array(items) => items.iter_mut().for_each(whole_numbers_as_integers),
        Value::Object(members) => members.values_mut().for_each(whole_numbers_as_integers),
        _ => {}
    }
}

/// Query parameters whose every refusal is a 400 problem saying which parameter is wrong. The
/// pointer of a query parameter reads the query string as an object: `?limit=abc` is `/limit`.
pub struct ApiQuery<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequestParts<S> for ApiQuery<T> {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, _state: &S) -> Result<Self, Self::Rejection> {
        let query = parts.uri.query().unwrap_or_default();
        let de = serde_urlencoded::Deserializer::new(form_urlencoded::parse(query.as_bytes()));
        serde_path_to_error::deserialize(de).map(ApiQuery).map_err(|e| {
            let pointer = json_pointer(e.path());
            ApiError::Client {
                status: StatusCode::BAD_REQUEST,
                code: "invalid_query",
                detail: format!("query parameter `{}`: {}", pointer.trim_start_matches('/'), e.into_inner()),
                pointer: Some(pointer),
            }
        })
    }
}

fn json_pointer(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    path.iter()
        .filter_map(|s| match s {
            Segment::Seq { index } => Some(index.to_string()),
            Segment::Map { key } => Some(key.replace('~', "~0").replace('/', "~1")),
            Segment::Enum { variant } => Some(variant.clone()),
            Segment::Unknown => None,
        })
        .fold(String::new(), |acc, s| format!("{acc}/{s}"))
}

/// Runs CPU-heavy work (geometry checks, file parsing, exports) on the blocking threads, so
/// that a large request cannot stall the async threads every other request is answered on.
pub async fn off_the_async_threads<T: Send + 'static, E: Into<ApiError> + Send + 'static>(work: impl FnOnce() -> Result<T, E> + Send + 'static) -> Result<T, ApiError> {
    match tokio::task::spawn_blocking(work).await {
        Ok(done) => done.map_err(Into::into),
        Err(e) => Err(ApiError::Internal(format!("a blocking task was lost: {e}"))),
    }
}
