//! Plans: `/api/v1/missions/{id}/plans` to queue one, `/api/v1/plans/{id}` to follow it.

use axum::Json;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Deserialize;
use serde_json::json;
use utoipa::IntoParams;

use super::AppState;
use super::auth::Caller;
use super::error::{ApiError, ApiJson, ApiQuery, Problem, off_the_async_threads};
use crate::jobs;
use crate::planner::export::{self, AltitudeFrame, ExportFile, ExportOptions, ExportRequest, Exporter, Firmware};
use crate::planner::geojson::FeatureCollection;
use crate::planner::params::AltitudeReference;
use crate::planner::terrain::ElevationModel;
use crate::planner::vehicle::Vehicle;
use crate::planner::{self, MissionGeometry, PlanParams};
use crate::store::plans::{self, JobKind, Plan, PlanStatus};
use crate::store::{missions, terrain, vehicles};

#[utoipa::path(post, operation_id = "create_plan", path = "/api/v1/missions/{id}/plans", tag = "plans", params(("id" = String, Path)), request_body = PlanParams,
    responses((status = 202, body = Plan, description = "queued"), (status = 404, body = Problem), (status = 422, body = Problem),
              (status = 429, body = Problem, description = "too many plans of this tenant's are queued or running (see `Retry-After`)")))]
pub async fn create(
    State(state): State<AppState>,
    caller: Caller,
    Path(mission_id): Path<String>,
    ApiJson(params): ApiJson<PlanParams>,
) -> Result<(StatusCode, Json<Plan>), ApiError> {
    let mission = missions::get(&state.db, &caller.tenant, &mission_id).await?.ok_or_else(|| ApiError::not_found("mission", &mission_id))?;
    let profiles = vehicles::profiles(&state.db, &caller.tenant).await?;
    let limits = state.config.limits;
    // over terrain the model must cover the plan's start and end too
    let model = match params.altitude_reference {
        Some(AltitudeReference::Terrain) => terrain::model(&state.db, &caller.tenant, &mission_id).await?,
        _ => None,
    };
    let (mission, params, profiles) = off_the_async_threads(move || {
        let model = model.map(|(name, bytes)| ElevationModel::read(&bytes, &name)).transpose()?;
        let geometry = mission.geometry(model.as_ref());
        planner::check_plan(&geometry, &params, &profiles, &limits)?;
        Ok::<_, ApiError>((mission, params, profiles))
    })
    .await?;
    let most = state.config.queue.time_limit.as_secs_f64();
    if params.time_limit_s.is_some_and(|s| s > most) {
        return Err(ApiError::invalid("server_time_limit", "/time_limit_s", format!("this server plans for at most {most} s; ask for that or less")));
    }
    let flown = planner::vehicles_flown(&params, &profiles)?;
    let snapshot = snapshot(&mission, &profiles, &flown.iter().collect::<Vec<_>>());
    let params = serde_json::to_value(&params).map_err(|e| ApiError::Internal(e.to_string()))?;
    Ok((StatusCode::ACCEPTED, Json(enqueue(&state, &caller, &plans::NewJob::new(JobKind::Plan, &mission_id, &params, &snapshot)).await?)))
}

/// A plan that is not the caller's, or not there.
pub(super) fn not_found(id: &str) -> ApiError {
    ApiError::not_found("plan", id)
}

/// What a job runs on: the mission's geometry and the stored profiles of its vehicles as they
/// are now, so that editing either later does not change a queued job.
pub(super) fn snapshot(mission: &missions::Mission, profiles: &[Vehicle], flown: &[&Vehicle]) -> serde_json::Value {
    let base: Vec<&Vehicle> = profiles.iter().filter(|p| flown.iter().any(|v| v.profile == p.profile)).collect();
    json!({"area": mission.area, "no_fly_zones": mission.no_fly_zones, "obstacles": mission.obstacles, "structures": mission.structures, "home": mission.home, "vehicles": base})
}

/// Queues a job (a plan or a patrol) of the caller's, within the tenant's cap, and wakes a worker.
pub(super) async fn enqueue(state: &AppState, caller: &Caller, job: &plans::NewJob<'_>) -> Result<Plan, ApiError> {
    let most = state.config.max_queued;
    let plan = plans::create(&state.db, &caller.tenant, job, most).await?.ok_or_else(|| ApiError::TooMany {
        code: "too_many_plans",
        detail: format!("{most} plans and patrols of yours are queued or running, the most this server takes at once: wait for one to finish or cancel one"),
        retry_after_s: 10,
    })?;
    state.jobs.notify();
    Ok(plan)
}

#[utoipa::path(get, operation_id = "list_plans", path = "/api/v1/missions/{id}/plans", tag = "plans", params(("id" = String, Path)),
    responses((status = 200, body = Vec<Plan>, description = "newest first"), (status = 404, body = Problem)))]
pub async fn list(State(state): State<AppState>, caller: Caller, Path(mission_id): Path<String>) -> Result<Json<Vec<Plan>>, ApiError> {
    missions::get(&state.db, &caller.tenant, &mission_id).await?.ok_or_else(|| ApiError::not_found("mission", &mission_id))?;
    Ok(Json(plans::list_for_mission(&state.db, &caller.tenant, JobKind::Plan, &mission_id).await?))
}

#[utoipa::path(get, operation_id = "get_plan", path = "/api/v1/plans/{id}", tag = "plans", params(("id" = String, Path)),
    responses((status = 200, body = Plan), (status = 404, body = Problem)))]
pub async fn get(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<Plan>, ApiError> {
    find(&state, &caller, &id).await.map(Json)
}

/// A plan of the caller's (patrols share the queue, not these routes).
async fn find(state: &AppState, caller: &Caller, id: &str) -> Result<Plan, ApiError> {
    plans::get(&state.db, &caller.tenant, JobKind::Plan, id).await?.ok_or_else(|| ApiError::not_found("plan", id))
}

/// `GET /api/v1/plans/{id}/trajectory` options.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct TrajectoryQuery {
    /// An export format's id, as `GET /api/v1/formats` lists them (default: the first). A plan
    /// of several sorties comes as a zip of one file per sortie in the formats that describe one
    /// flight (`one_flight_per_file`).
    pub format: Option<String>,
    /// `ardupilot` (default) or `px4`: the autopilot of the formats with `firmware_commands`.
    pub firmware: Option<String>,
    /// Altitude above home for flight files of plans made without one, 1 to 10 000 m (default:
    /// the plan's, else 50 m).
    #[param(minimum = 1, maximum = 10000)]
    pub altitude_m: Option<f64>,
    /// Plans over terrain: `amsl` (default) writes each waypoint's altitude above mean sea
    /// level as planned; `terrain` writes its height above the ground under it, in the terrain
    /// frame, for vehicles with a rangefinder or terrain data.
    #[param(inline)]
    pub altitude_frame: Option<AltitudeFrame>,
    /// The formats with a `waypoint_limit`: most waypoints the controller loads (mission items
    /// for the MAVLink files, home left out), 10 to 65 535 (default: the format's
    /// `default_max_waypoints`, 99 for DJI WPML, else none). Past it the lines are written as
    /// their two ends, and a flight that still has more is cut into missions (a zip), each
    /// beginning where the last ended.
    #[param(minimum = 10, maximum = 65535)]
    pub max_waypoints: Option<usize>,
}

impl TrajectoryQuery {
    /// The exporter asked for and the options it writes with; unknown formats and firmware and
    /// altitudes out of range are refused.
    pub(super) fn choice(&self) -> Result<(&'static dyn Exporter, ExportOptions), ApiError> {
        let format = self.format.as_deref().unwrap_or(export::default_format().id);
        let exporter = export::find(format)
            .ok_or_else(|| ApiError::bad_request("unknown_format", "/format", format!("no export format `{format}`; known: {}", export::format_ids().join(", "))))?;
        if let Some(a) = self.altitude_m.filter(|a| !(1.0..=10_000.0).contains(a)) {
            return Err(ApiError::invalid("parameter_out_of_range", "/altitude_m", format!("{a} m is outside the accepted range [1, 10000] m above home")));
        }
        let (least, most) = export::MAX_WAYPOINTS_RANGE;
        if let Some(n) = self.max_waypoints.filter(|n| !(least..=most).contains(n)) {
            return Err(ApiError::invalid("parameter_out_of_range", "/max_waypoints", format!("{n} waypoints is outside the accepted range [{least}, {most}]")));
        }
        let firmware = match self.firmware.as_deref() {
            None | Some("ardupilot") => Firmware::Ardupilot,
            Some("px4") => Firmware::Px4,
            Some(other) => return Err(ApiError::bad_request("unknown_firmware", "/firmware", format!("no firmware `{other}`; known: ardupilot, px4"))),
        };
        let options = ExportOptions { firmware, altitude_m: self.altitude_m, altitude_frame: self.altitude_frame.unwrap_or_default(), max_waypoints: self.max_waypoints };
        Ok((exporter, options))
    }
}

#[utoipa::path(get, operation_id = "get_trajectory", path = "/api/v1/plans/{id}/trajectory", tag = "plans", params(("id" = String, Path), TrajectoryQuery),
    responses((status = 200, description = "The trajectory in the asked format, as an attachment named after the mission. GeoJSON: a FeatureCollection \
        (RFC 7946) of LineStrings in flight order, `properties.kind` = sweep | headland | turn | transit (a ground vehicle's turns with turn_type u | omega | fishtail), with length_m, duration_s, energy_j, speed_mps, sortie; \
        a MultiPoint of kind `photos` when a camera was given", content_type = "application/geo+json", body = Object),
        (status = 400, body = Problem, description = "unknown format or firmware, or an unreadable query parameter"), (status = 404, body = Problem),
        (status = 409, body = Problem, description = "the plan has no trajectory (yet)"), (status = 422, body = Problem, description = "the format cannot say this plan, takes no max_waypoints, or cannot keep a line's photos within it")))]
pub async fn trajectory(State(state): State<AppState>, caller: Caller, Path(id): Path<String>, ApiQuery(query): ApiQuery<TrajectoryQuery>) -> Result<Response, ApiError> {
    let (exporter, options) = query.choice()?;
    let format = exporter.format().id;
    let mut source = plans::export_source(&state.db, &caller.tenant, JobKind::Plan, &id).await?.ok_or_else(|| ApiError::not_found("plan", &id))?;
    let (PlanStatus::Succeeded, Some(geojson)) = (source.status, source.trajectory.take()) else {
        let status = json!(source.status);
        return Err(ApiError::conflict("trajectory_not_available", format!("the plan is {}; a trajectory exists only once it has succeeded", status.as_str().unwrap_or("?"))));
    };
    let as_stored = exporter.format();
    let file = if as_stored.verbatim && query.max_waypoints.is_none() {
        // no need to read it
        ExportFile { file_name: format!("{}{}", export::file_stem(&source.name), as_stored.extension), media_type: as_stored.media_type, bytes: geojson.into_bytes() }
    } else {
        // reading and writing a large trajectory takes a while: off the async runtime
        off_the_async_threads(move || export_file(&id, format, &source, &geojson, options)).await?
    };
    let disposition = format!("attachment; filename=\"{}\"", file.file_name);
    Ok(([(header::CONTENT_TYPE, file.media_type.to_owned()), (header::CONTENT_DISPOSITION, disposition)], file.bytes).into_response())
}

/// Writes a stored plan in `format`.
fn export_file(id: &str, format: &str, source: &plans::ExportSource, geojson: &str, options: ExportOptions) -> Result<ExportFile, ApiError> {
    let stored = StoredExport::read(id, source, geojson)?;
    Ok(export::export(format, &stored.request(&source.name, source, options))?)
}

/// What a stored plan is exported from besides its mission: its trajectory, parameters and the
/// vehicles of its snapshot, read once.
pub(super) struct StoredExport {
    trajectory: FeatureCollection,
    params: PlanParams,
    profiles: Vec<Vehicle>,
}

impl StoredExport {
    /// Reads stored plan `id` (its trajectory `geojson`).
    pub(super) fn read(id: &str, source: &plans::ExportSource, geojson: &str) -> Result<StoredExport, ApiError> {
        let internal = |e: &dyn std::fmt::Display| ApiError::Internal(format!("plan {id}: {e}"));
        Ok(StoredExport {
            trajectory: serde_json::from_str(geojson).map_err(|e| internal(&e))?,
            params: serde_json::from_value(source.params.clone()).map_err(|e| internal(&e))?,
            profiles: jobs::snapshot_profiles(&source.mission).map_err(|e| internal(&e))?,
        })
    }

    /// The export request of the plan, named `name`, on the geometry of its snapshot.
    pub(super) fn request<'a>(&'a self, name: &'a str, source: &'a plans::ExportSource, options: ExportOptions) -> ExportRequest<'a> {
        ExportRequest { name, mission: MissionGeometry::of(&source.mission), params: &self.params, profiles: &self.profiles, trajectory: &self.trajectory, options }
    }
}

#[utoipa::path(delete, operation_id = "cancel_plan", path = "/api/v1/plans/{id}", tag = "plans", params(("id" = String, Path)),
    responses((status = 200, body = Plan, description = "cancelled (or already finished: its status says which)"), (status = 404, body = Problem)))]
pub async fn cancel(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<Plan>, ApiError> {
    find(&state, &caller, &id).await?;
    plans::cancel(&state.db, &caller.tenant, &id).await?.ok_or_else(|| ApiError::not_found("plan", &id))?;
    state.jobs.cancel(&id);
    find(&state, &caller, &id).await.map(Json)
}
