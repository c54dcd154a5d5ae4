//! Resuming a plan whose flight stopped: `POST /api/v1/plans/{id}/resume` with where it stopped
//! as JSON, or with the flight's log as the body (docs/api.md, "Resume a plan").

use axum::Json;
use axum::extract::{FromRequest, Path, Request, State};
use axum::http::StatusCode;
use serde::Deserialize;
use serde_json::json;
use utoipa::IntoParams;

use super::AppState;
use super::auth::Caller;
use super::error::{ApiError, ApiJson, ApiQuery, Problem, is_json, off_the_async_threads, read_body};
use super::plans::{enqueue, not_found};
use crate::jobs;
use crate::planner::geojson::FeatureCollection;
use crate::planner::import::flight_log;
use crate::planner::params::AltitudeReference;
use crate::planner::params::resume::{Flown, ResumeFrom, ResumeParams};
use crate::planner::terrain::ElevationModel;
use crate::planner::vehicle::VehicleKind;
use crate::planner::{self, MissionGeometry, PlanParams};
use crate::store::plans::{self, JobKind, Plan, PlanStatus};
use crate::store::terrain;

/// With a flight log as the body: how to go on (as the JSON request's members of those names).
#[derive(Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct LogOptions {
    /// Trigger distances flown again before the cut, 0 to 20 (default 2).
    #[param(minimum = 0, maximum = 20)]
    photos_back: Option<u32>,
    /// `home` (default) or `position` (the track's last point, the aircraft still in the air).
    from: Option<ResumeFrom>,
    /// The battery left for the first sortie, 0 to 1 (default: a fresh one; from `position`, what
    /// the log says).
    #[param(minimum = 0.0, maximum = 1.0)]
    battery_remaining: Option<f64>,
    /// Farthest across a line a photo (or the track) counts as the line's, 0.1 to 100 m.
    #[param(minimum = 0.1, maximum = 100.0)]
    tolerance_m: Option<f64>,
}

impl LogOptions {
    fn given(&self) -> bool {
        self.photos_back.is_some() || self.from.is_some() || self.battery_remaining.is_some() || self.tolerance_m.is_some()
    }
}

#[utoipa::path(post, operation_id = "resume_plan", path = "/api/v1/plans/{id}/resume", tag = "plans", params(("id" = String, Path), LogOptions),
    request_body(content(
        (ResumeParams = "application/json"),
        (Vec<u8> = "application/octet-stream")
    ), description = "where the flight stopped, as JSON; or the flight's log: MAVLink telemetry (.tlog), PX4 (.ulg) or ArduPilot DataFlash (.bin), told by its first bytes, with the options in the query"),
    responses((status = 202, body = Plan, description = "the plan of what is left, queued; `resumed_from` names this plan"), (status = 404, body = Problem),
              (status = 409, body = Problem, description = "the plan has not succeeded"),
              (status = 415, body = Problem, description = "the body is neither JSON nor a flight log (`application/octet-stream`)"),
              (status = 422, body = Problem, description = "the cut is not on this plan, the log is not readable or not this plan's flight, or the plan is not resumed"),
              (status = 429, body = Problem, description = "too many plans of this tenant's are queued or running (see `Retry-After`)")))]
pub async fn resume(
    State(state): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
    ApiQuery(options): ApiQuery<LogOptions>,
    body: Request,
) -> Result<(StatusCode, Json<Plan>), ApiError> {
    // another tenant's plan is one that does not exist, whatever the body says
    let mut source = plans::export_source(&state.db, &caller.tenant, JobKind::Plan, &id).await?.ok_or_else(|| not_found(&id))?;
    let request = if is_json(body.headers()) {
        if options.given() {
            return Err(ApiError::invalid("options_in_query", "/photos_back", "with a JSON body the options are its members, not query parameters"));
        }
        Sent::Json(ApiJson::<ResumeParams>::from_request(body, &state).await?.0)
    } else if body.headers().get(axum::http::header::CONTENT_TYPE).is_none_or(|v| v == "application/octet-stream") {
        Sent::Log(read_body(body, &state).await?)
    } else {
        return Err(ApiError::Client {
            status: StatusCode::UNSUPPORTED_MEDIA_TYPE,
            code: "unsupported_media_type",
            detail: "send where the flight stopped as JSON (`Content-Type: application/json`) or its log as `application/octet-stream`".into(),
            pointer: None,
        });
    };
    let (PlanStatus::Succeeded, Some(geojson)) = (source.status, source.trajectory.take()) else {
        let status = json!(source.status);
        return Err(ApiError::conflict("trajectory_not_available", format!("the plan is {}; a plan is resumed once it has succeeded", status.as_str().unwrap_or("?"))));
    };
    let internal = |e: &dyn std::fmt::Display| ApiError::Internal(format!("plan {id}: {e}"));
    let params: PlanParams = serde_json::from_value(source.params.clone()).map_err(|e| internal(&e))?;
    let model = match params.altitude_reference {
        Some(AltitudeReference::Terrain) => terrain::model(&state.db, &caller.tenant, &source.mission_id).await?,
        _ => None,
    };
    let limits = state.config.limits;
    let profiles = jobs::snapshot_profiles(&source.mission).map_err(|e| internal(&e))?;
    // the log and the trajectory are read once, off the async threads; the cut is found on it
    // now, so that a wrong one is refused here
    let (request, trajectory, source) = off_the_async_threads(move || {
        let request = match request {
            Sent::Json(r) => r,
            Sent::Log(bytes) => {
                let log = flight_log::read(&bytes)?;
                let flown_by = planner::vehicles_flown(&params, &profiles)?.first().map(|v| v.kind);
                if let Some((logged, planned)) = log.vehicle.zip(flown_by).filter(|(l, p)| l != p) {
                    let said = |k| match k {
                        VehicleKind::Multirotor => "multirotor",
                        VehicleKind::FixedWing => "fixed wing",
                        VehicleKind::Ground => "ground vehicle",
                    };
                    let why = format!("the log is a {}'s; this plan is a {}'s: is it this plan's flight?", said(logged), said(planned));
                    return Err(ApiError::invalid("log_other_vehicle", "/flown", why));
                }
                let flown = Flown { tolerance_m: options.tolerance_m, ..log.flown };
                ResumeParams { flown: Some(flown), photos_back: options.photos_back, from: options.from, battery_remaining: options.battery_remaining, ..ResumeParams::default() }
            }
        };
        let checked = request.check()?;
        let unreadable = |e: serde_json::Error| ApiError::Internal(format!("stored trajectory: {e}"));
        let trajectory: serde_json::Value = serde_json::from_str(&geojson).map_err(unreadable)?;
        let collection = FeatureCollection::deserialize(&trajectory).map_err(unreadable)?;
        let model = model.map(|(name, bytes)| ElevationModel::read(&bytes, &name)).transpose()?;
        let geometry = MissionGeometry { terrain: model.as_ref(), ..MissionGeometry::of(&source.mission) };
        planner::check_resume(&geometry, &params, &profiles, &limits, &collection, &checked)?;
        Ok::<_, ApiError>((request, trajectory, source))
    })
    .await?;
    let mut snapshot = source.mission;
    snapshot["resume"] = json!({"request": request, "trajectory": trajectory});
    let job = plans::NewJob { resumed_from: Some(&id), ..plans::NewJob::new(JobKind::Plan, &source.mission_id, &source.params, &snapshot) };
    Ok((StatusCode::ACCEPTED, Json(enqueue(&state, &caller, &job).await?)))
}

/// Where the flight stopped, as sent.
enum Sent {
    Json(ResumeParams),
    Log(axum::body::Bytes),
}
