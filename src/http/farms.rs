//! Farm plans: `/api/v1/farm-plans` plans each of a farm's fields as a job of the queue (any
//! worker of any replica takes them), then schedules the fields over the machines and days.
//! The schedule is made by the first request that finds every field's plan finished.

use std::collections::HashMap;
use std::time::{Duration, Instant};

use axum::Json;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use utoipa::ToSchema;

use super::AppState;
use super::auth::Caller;
use super::error::{ApiError, ApiJson, ApiQuery, Problem, off_the_async_threads};
use super::plans::{StoredExport, TrajectoryQuery, snapshot};
use crate::planner::export::{DayStretch, ExportOptions, FarmTask, FarmTaskData};
use crate::planner::farm::{self, FieldWork, LegKind, Machine, RoadNetwork, Schedule, StraightLine, Stretch, Unscheduled, Window};
use crate::planner::params::AltitudeReference;
use crate::planner::terrain::ElevationModel;
use crate::planner::vehicle::Vehicle;
use crate::planner::{self, PlanError, PlanParams, Stop};
use crate::store::farms::{self, FarmField, FarmRow, FieldJob, FieldPlan};
use crate::store::plans::{self, JobKind, PlanStatus};
use crate::store::{Db, missions, terrain, vehicles};

/// Farm plans of one tenant's whose fields may be queued or running at once.
pub const MOST_FARM_PLANS_AT_ONCE: i64 = 3;

/// A farm's fields, its machines and working days, and how to plan each field.
#[derive(Debug, Clone, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct FarmPlanRequest {
    /// A name for the farm plan (default `farm plan`).
    #[schema(max_length = 200)]
    pub name: Option<String>,
    /// The fields: missions, each one field (its holes and no-fly zones with it). Give this or
    /// `mission_id`.
    #[schema(min_items = 1, max_items = 2000)]
    pub missions: Option<Vec<String>>,
    /// Or one mission whose area holds the farm's fields (as an import of a farm file makes
    /// it): each of its polygons is a field, named by its feature's `name` property. Its no-fly
    /// zones apply to every field.
    pub mission_id: Option<String>,
    /// The machines that work the fields, each from its depot.
    #[schema(min_items = 1, max_items = 100)]
    pub machines: Vec<Machine>,
    pub window: Window,
    /// Roads the machines drive on between fields: GeoJSON LineStrings (a FeatureCollection,
    /// Feature or geometry). Default: straight lines.
    #[schema(value_type = Option<Object>)]
    pub roads: Option<Value>,
    /// How each field is planned, as `POST /api/v1/missions/{id}/plans` takes it, for one
    /// vehicle (not a fleet: the farm's machines are `machines`).
    pub params: PlanParams,
    /// Other parameters for some fields.
    #[schema(max_items = 100)]
    pub groups: Option<Vec<FieldGroup>>,
}

/// Parameters for some of the farm's fields.
#[derive(Debug, Clone, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldGroup {
    /// The fields' indices in the farm (the order of `missions`, or of the mission's polygons).
    #[schema(min_items = 1)]
    pub fields: Vec<usize>,
    pub params: PlanParams,
}

/// What the farm plan keeps of the request for its schedule.
#[derive(Debug, Clone, Deserialize, Serialize)]
struct ScheduleRequest {
    machines: Vec<Machine>,
    window: Window,
    roads: Option<Value>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum FarmStatus {
    /// Fields are being planned.
    Planning,
    /// Every field's plan has finished and the schedule is made.
    Scheduled,
    /// No field could be planned.
    Failed,
    Cancelled,
}

/// A farm plan: its fields' plans as they progress and, once all have finished, the schedule.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct FarmPlan {
    pub id: String,
    pub name: String,
    pub status: FarmStatus,
    /// Fields whose plan has finished (succeeded, failed or cancelled), and all of them.
    pub fields_done: usize,
    pub fields_total: usize,
    pub fields: Vec<FieldState>,
    pub machines: Vec<Machine>,
    pub window: Window,
    /// Once scheduled.
    pub schedule: Option<Schedule>,
    /// The schedule as CSV, once scheduled.
    pub schedule_csv_url: Option<String>,
    pub created_at: String,
    pub finished_at: Option<String>,
}

/// A field of the farm and its plan.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct FieldState {
    pub index: usize,
    pub mission_id: String,
    pub name: String,
    pub plan_id: Option<String>,
    /// `/api/v1/plans/{id}`: the plan, its trajectory under `/trajectory`.
    pub plan_url: Option<String>,
    /// None when the field was refused.
    pub status: Option<PlanStatus>,
    /// Its plan's working time, s.
    pub work_s: Option<f64>,
    /// Why it was refused or its plan failed, in words, and the code.
    pub error: Option<String>,
    pub error_code: Option<String>,
}

#[utoipa::path(post, operation_id = "create_farm_plan", path = "/api/v1/farm-plans", tag = "farms", request_body = FarmPlanRequest,
    responses((status = 202, body = FarmPlan, description = "its fields queued"), (status = 404, body = Problem, description = "a mission named is not there"),
              (status = 422, body = Problem), (status = 429, body = Problem, description = "three farm plans of this tenant's are still planning (see `Retry-After`)")))]
pub async fn create(State(state): State<AppState>, caller: Caller, ApiJson(request): ApiJson<FarmPlanRequest>) -> Result<(StatusCode, Json<FarmPlan>), ApiError> {
    farm::check_setup(&request.machines, &request.window)?;
    if request.params.fleet.is_some() || request.params.vehicles.is_some() {
        let member = if request.params.fleet.is_some() { "fleet" } else { "vehicles" };
        return Err(ApiError::invalid("not_for_farm_plans", &format!("/params/{member}"), "a farm plan plans each field for one vehicle: its machines are `machines`"));
    }
    let most = state.config.queue.time_limit.as_secs_f64();
    if request.params.time_limit_s.is_some_and(|s| s > most) {
        return Err(ApiError::invalid("server_time_limit", "/params/time_limit_s", format!("this server plans for at most {most} s; ask for that or less")));
    }
    if let Some(roads) = &request.roads {
        let roads = roads.clone();
        off_the_async_threads(move || RoadNetwork::from_geojson(&roads, "/roads").map(drop)).await?;
    }
    let fields = fields_of(&state, &caller, &request).await?;
    let params = params_by_field(&request, fields.len())?;
    let profiles = vehicles::profiles(&state.db, &caller.tenant).await?;
    let models = terrain_models(&state, &caller, &fields, &params).await?;
    let limits = state.config.limits;
    let checked = off_the_async_threads(move || {
        let checked: Vec<Result<FieldJob, (String, &'static str)>> = fields
            .par_iter()
            .zip(&params)
            .map(|(field, params)| {
                let model = models.get(&field.mission.id).map(|(name, bytes)| ElevationModel::read(bytes, name)).transpose().map_err(refusal)?;
                planner::check_plan(&field.mission.geometry(model.as_ref()), params, &profiles, &limits).map_err(refusal)?;
                let flown: Vec<Vehicle> = planner::vehicles_flown(params, &profiles).map_err(refusal)?;
                Ok(FieldJob {
                    plan_id: farms::new_plan_id(),
                    mission_id: field.mission.id.clone(),
                    params: serde_json::to_value(params).expect("parameters serialise"),
                    mission: snapshot(&field.mission, &profiles, &flown.iter().collect::<Vec<_>>()),
                })
            })
            .collect();
        Ok::<_, ApiError>((fields, checked))
    });
    let (fields, checked) = checked.await?;
    if let Some(Err((detail, code))) = checked.iter().find(|c| c.is_err()).filter(|_| checked.iter().all(Result::is_err)) {
        return Err(ApiError::invalid("no_fields", "/", format!("no field of the farm can be planned; the first: {detail} ({code})")));
    }
    let listed: Vec<FarmField> = fields
        .iter()
        .zip(&checked)
        .enumerate()
        .map(|(index, (f, c))| FarmField {
            index,
            mission_id: f.mission.id.clone(),
            name: f.name.clone(),
            plan_id: c.as_ref().ok().map(|j| j.plan_id.clone()),
            refused: c.as_ref().err().map(|e| e.0.clone()),
            refused_code: c.as_ref().err().map(|e| e.1.to_owned()),
        })
        .collect();
    let jobs: Vec<FieldJob> = checked.into_iter().flatten().collect();
    let kept = ScheduleRequest { machines: request.machines.clone(), window: request.window.clone(), roads: request.roads.clone() };
    let name = request.name.clone().unwrap_or_else(|| "farm plan".to_owned());
    let stored = serde_json::to_value(&kept).map_err(|e| ApiError::Internal(e.to_string()))?;
    let row = farms::create(&state.db, &caller.tenant, &name, &stored, &listed, &jobs, MOST_FARM_PLANS_AT_ONCE).await?.ok_or_else(|| ApiError::TooMany {
        code: "too_many_farm_plans",
        detail: format!("{MOST_FARM_PLANS_AT_ONCE} farm plans of yours are still planning their fields: wait for one to finish or cancel one"),
        retry_after_s: 30,
    })?;
    state.jobs.notify();
    Ok((StatusCode::ACCEPTED, Json(view(&state, &caller, row).await?)))
}

fn refusal(e: impl Into<ApiError>) -> (String, &'static str) {
    match e.into() {
        ApiError::Client { code, detail, pointer, .. } => (pointer.map_or(detail.clone(), |p| format!("{detail} (at {p})")), code),
        ApiError::TooMany { code, detail, .. } => (detail, code),
        ApiError::Internal(detail) => (detail, "internal"),
    }
}

/// A field of the farm: the mission it is planned on (its area that field alone) and its name.
struct Field {
    mission: missions::Mission,
    name: String,
}

async fn fields_of(state: &AppState, caller: &Caller, request: &FarmPlanRequest) -> Result<Vec<Field>, ApiError> {
    let get = |id: String| async move { missions::get(&state.db, &caller.tenant, &id).await?.ok_or_else(|| ApiError::not_found("mission", &id)) };
    match (&request.missions, &request.mission_id) {
        (Some(ids), None) => {
            let mut fields = Vec::with_capacity(ids.len());
            for id in ids {
                let mission = get(id.clone()).await?;
                fields.push(Field { name: mission.name.clone(), mission });
            }
            Ok(fields)
        }
        (None, Some(id)) => {
            let mission = get(id.clone()).await?;
            let polygons = polygons_of(&mission.area);
            if polygons.is_empty() {
                return Err(ApiError::invalid("no_fields", "/mission_id", "the mission's area has no polygon: its fields are the polygons of its area"));
            }
            if polygons.len() > farm::MAX_FIELDS {
                return Err(ApiError::invalid(
                    "too_many_fields",
                    "/mission_id",
                    format!("the mission has {} fields; a farm plan takes at most {}", polygons.len(), farm::MAX_FIELDS),
                ));
            }
            // each field's mission: the mission without its whole area, and the field as its area
            let rest = missions::Mission { area: Value::Null, ..mission };
            Ok(polygons
                .into_iter()
                .enumerate()
                .map(|(k, (area, name))| Field { name: name.unwrap_or_else(|| format!("{} #{}", rest.name, k + 1)), mission: missions::Mission { area, ..rest.clone() } })
                .collect())
        }
        (Some(_), Some(_)) => Err(ApiError::invalid("fields_twice", "/mission_id", "give the fields as `missions` or as one `mission_id`, not both")),
        (None, None) => {
            Err(ApiError::invalid("fields_missing", "/missions", "give the farm's fields: `missions` (each one field) or `mission_id` (a mission whose polygons are the fields)"))
        }
    }
}

/// Each polygon of a mission's area (a Polygon, MultiPolygon, Feature or FeatureCollection) as
/// a Polygon geometry, with its feature's `name`.
fn polygons_of(area: &Value) -> Vec<(Value, Option<String>)> {
    let name_of = |feature: &Value| feature["properties"]["name"].as_str().map(str::to_owned);
    let of_geometry = |g: &Value, name: Option<String>| -> Vec<(Value, Option<String>)> {
        match g["type"].as_str() {
            Some("Polygon") => vec![(json!({"type": "Polygon", "coordinates": g["coordinates"]}), name)],
            Some("MultiPolygon") => {
                let parts = g["coordinates"].as_array().cloned().unwrap_or_default();
                let several = parts.len() > 1;
                parts
                    .into_iter()
                    .enumerate()
                    .map(|(k, c)| (json!({"type": "Polygon", "coordinates": c}), name.clone().map(|n| if several { format!("{n} #{}", k + 1) } else { n })))
                    .collect()
            }
            _ => Vec::new(),
        }
    };
    match area["type"].as_str() {
        Some("FeatureCollection") => area["features"].as_array().into_iter().flatten().flat_map(|f| of_geometry(&f["geometry"], name_of(f))).collect(),
        Some("Feature") => of_geometry(&area["geometry"], name_of(area)),
        _ => of_geometry(area, None),
    }
}

/// Each field's parameters: its group's, else the farm's.
fn params_by_field(request: &FarmPlanRequest, fields: usize) -> Result<Vec<PlanParams>, ApiError> {
    let mut chosen: Vec<Option<usize>> = vec![None; fields];
    for (g, group) in request.groups.iter().flatten().enumerate() {
        if group.params.fleet.is_some() || group.params.vehicles.is_some() {
            return Err(ApiError::invalid("not_for_farm_plans", &format!("/groups/{g}/params"), "a farm plan plans each field for one vehicle: its machines are `machines`"));
        }
        for (k, &i) in group.fields.iter().enumerate() {
            let at = format!("/groups/{g}/fields/{k}");
            let slot = chosen
                .get_mut(i)
                .ok_or_else(|| ApiError::invalid("parameter_out_of_range", &at, format!("the farm has {fields} fields, numbered from 0; there is no field {i}")))?;
            if let Some(other) = slot.replace(g) {
                return Err(ApiError::invalid("field_twice", &at, format!("field {i} is in group {other} already")));
            }
        }
    }
    Ok(chosen.into_iter().map(|g| g.map_or_else(|| request.params.clone(), |g| request.groups.as_ref().expect("a group")[g].params.clone())).collect())
}

/// The elevation models of the missions whose fields fly over terrain.
async fn terrain_models(state: &AppState, caller: &Caller, fields: &[Field], params: &[PlanParams]) -> Result<HashMap<String, (String, Vec<u8>)>, ApiError> {
    let mut models = HashMap::new();
    for (field, params) in fields.iter().zip(params) {
        if params.altitude_reference == Some(AltitudeReference::Terrain)
            && !models.contains_key(&field.mission.id)
            && let Some(model) = terrain::model(&state.db, &caller.tenant, &field.mission.id).await?
        {
            models.insert(field.mission.id.clone(), model);
        }
    }
    Ok(models)
}

#[utoipa::path(get, operation_id = "get_farm_plan", path = "/api/v1/farm-plans/{id}", tag = "farms", params(("id" = String, Path)),
    responses((status = 200, body = FarmPlan), (status = 404, body = Problem)))]
pub async fn get(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<FarmPlan>, ApiError> {
    let row = find(&state, &caller, &id).await?;
    Ok(Json(view(&state, &caller, row).await?))
}

async fn find(state: &AppState, caller: &Caller, id: &str) -> Result<FarmRow, ApiError> {
    farms::get(&state.db, &caller.tenant, id).await?.ok_or_else(|| ApiError::not_found("farm plan", id))
}

/// The farm plan as the API shows it; schedules it first when every field's plan has finished.
async fn view(state: &AppState, caller: &Caller, mut row: FarmRow) -> Result<FarmPlan, ApiError> {
    let plans: HashMap<String, FieldPlan> = farms::field_plans(&state.db, &caller.tenant, &row.id).await?.into_iter().map(|p| (p.id.clone(), p)).collect();
    let all_done = plans.values().all(|p| p.status.is_final());
    if all_done && row.schedule.is_none() && !row.cancelled {
        let kept: ScheduleRequest = serde_json::from_value(row.request.0.clone()).map_err(|e| ApiError::Internal(format!("farm plan {}: {e}", row.id)))?;
        let fields = row.fields.0.clone();
        let works = plans.clone();
        let deadline = Instant::now() + state.config.queue.time_limit.min(Duration::from_secs(600));
        let made = off_the_async_threads(move || make_schedule(&kept, &fields, &works, &Stop::until(deadline))).await?;
        let made = serde_json::to_value(&made).map_err(|e| ApiError::Internal(e.to_string()))?;
        farms::save_schedule(&state.db, &caller.tenant, &row.id, &made).await?;
        row = find(state, caller, &row.id).await?;
    }
    let kept: ScheduleRequest = serde_json::from_value(row.request.0).map_err(|e| ApiError::Internal(format!("farm plan {}: {e}", row.id)))?;
    let fields: Vec<FieldState> = row
        .fields
        .0
        .into_iter()
        .map(|f| {
            let plan = f.plan_id.as_ref().and_then(|id| plans.get(id));
            FieldState {
                index: f.index,
                plan_url: f.plan_id.as_ref().map(|id| format!("/api/v1/plans/{id}")),
                status: plan.map(|p| p.status),
                work_s: plan.and_then(|p| p.duration_s),
                error: f.refused.or_else(|| plan.and_then(|p| p.error.clone())),
                error_code: f.refused_code.or_else(|| plan.and_then(|p| p.error_code.clone())),
                mission_id: f.mission_id,
                name: f.name,
                plan_id: f.plan_id,
            }
        })
        .collect();
    let schedule: Option<Schedule> = row.schedule.map(|s| serde_json::from_value(s.0)).transpose().map_err(|e| ApiError::Internal(format!("farm plan {}: {e}", row.id)))?;
    let status = match (&schedule, row.cancelled) {
        (_, true) => FarmStatus::Cancelled,
        (Some(s), _) if s.machines.iter().all(|m| m.fields == 0) => FarmStatus::Failed,
        (Some(_), _) => FarmStatus::Scheduled,
        (None, _) => FarmStatus::Planning,
    };
    Ok(FarmPlan {
        schedule_csv_url: schedule.as_ref().map(|_| format!("/api/v1/farm-plans/{}/schedule.csv", row.id)),
        id: row.id,
        name: row.name,
        status,
        fields_done: fields.iter().filter(|f| f.status.is_none_or(PlanStatus::is_final)).count(),
        fields_total: fields.len(),
        fields,
        machines: kept.machines,
        window: kept.window,
        schedule,
        created_at: row.created_at,
        finished_at: row.finished_at,
    })
}

/// The schedule of the fields whose plans succeeded; the others are listed as unscheduled.
fn make_schedule(kept: &ScheduleRequest, fields: &[FarmField], plans: &HashMap<String, FieldPlan>, stop: &Stop) -> Result<Schedule, ApiError> {
    let point = |s: &Option<String>| s.as_deref().and_then(|s| serde_json::from_str::<[f64; 2]>(s).ok());
    let mut works = Vec::new();
    let mut index = Vec::new();
    let mut unscheduled = Vec::new();
    for f in fields {
        let plan = f.plan_id.as_ref().and_then(|id| plans.get(id));
        match plan.map(|p| (p.status, p.duration_s, point(&p.begins_at), point(&p.ends_at))) {
            Some((PlanStatus::Succeeded, Some(work_s), Some(entry), Some(exit))) => {
                works.push(FieldWork { entry, exit, work_s });
                index.push(f.index);
            }
            _ => {
                let why = f.refused.clone().or_else(|| plan.and_then(|p| p.error.clone())).unwrap_or_else(|| "its plan did not succeed".to_owned());
                unscheduled.push(Unscheduled { field: f.index, reason: format!("not planned: {why}") });
            }
        }
    }
    let transit: Box<dyn farm::Transit> = match &kept.roads {
        Some(roads) => Box::new(RoadNetwork::from_geojson(roads, "/roads")?),
        None => Box::new(StraightLine),
    };
    let mut made = farm::schedule(&works, &kept.machines, &kept.window, transit.as_ref(), stop).map_err(|e| match e {
        PlanError::Input(e) => e.into(),
        other => ApiError::Internal(format!("scheduling the farm: {other}")),
    })?;
    made.renumber(&index, unscheduled);
    Ok(made)
}

#[utoipa::path(get, operation_id = "get_farm_schedule_csv", path = "/api/v1/farm-plans/{id}/schedule.csv", tag = "farms", params(("id" = String, Path)),
    responses((status = 200, content_type = "text/csv", body = String, description = "a row per leg of every machine's days: machine, day, date, start, end, kind, field_index, field, distance_m, finishes_field"),
              (status = 404, body = Problem), (status = 409, body = Problem, description = "the farm plan is not scheduled yet")))]
pub async fn schedule_csv(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Response, ApiError> {
    let row = find(&state, &caller, &id).await?;
    let farm = view(&state, &caller, row).await?;
    let Some(schedule) = &farm.schedule else {
        return Err(not_scheduled(&farm));
    };
    let labels: Vec<String> = farm.fields.iter().map(|f| f.name.clone()).collect();
    let disposition = format!("attachment; filename=\"{}.csv\"", planner::export::file_stem(&farm.name));
    Ok(([(header::CONTENT_TYPE, "text/csv; charset=utf-8".to_owned()), (header::CONTENT_DISPOSITION, disposition)], farm::schedule_csv(schedule, &labels)).into_response())
}

#[utoipa::path(get, operation_id = "get_farm_taskdata", path = "/api/v1/farm-plans/{id}/taskdata", tag = "farms", params(("id" = String, Path)),
    responses((status = 200, content_type = "application/zip", body = Vec<u8>, description = "ISOXML TaskData (a zip with TASKDATA/TASKDATA.XML): every planned field's partfields with their guidance, \
        as each plan's own file has them, and a task for each stretch of a machine's day on one field, named by the machine, the day and the field, in the schedule's order"),
              (status = 404, body = Problem), (status = 409, body = Problem, description = "the farm plan is not scheduled yet")))]
pub async fn taskdata(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Response, ApiError> {
    let row = find(&state, &caller, &id).await?;
    let farm = view(&state, &caller, row).await?;
    let Some(schedule) = &farm.schedule else {
        return Err(not_scheduled(&farm));
    };
    let tasks = farm_tasks(schedule, &farm.fields);
    let planned: Vec<(usize, String, String)> =
        farm.fields.iter().filter(|f| f.status == Some(PlanStatus::Succeeded)).filter_map(|f| f.plan_id.clone().map(|p| (f.index, f.name.clone(), p))).collect();
    let (db, tenant) = (state.db.clone(), caller.tenant.clone());
    // one field's trajectory in memory at a time
    let bytes = off_the_async_threads(move || {
        let runtime = tokio::runtime::Handle::current();
        let mut file = FarmTaskData::default();
        for (index, name, plan_id) in planned {
            let Some((source, stored)) = runtime.block_on(stored_export(&db, &tenant, &plan_id))? else { continue };
            file.add(index, &name, &stored.request(&name, &source, ExportOptions::default()))?;
        }
        Ok::<_, ApiError>(file.finish(&tasks))
    })
    .await?;
    let disposition = format!("attachment; filename=\"{}-taskdata.zip\"", planner::export::file_stem(&farm.name));
    Ok(([(header::CONTENT_TYPE, "application/zip".to_owned()), (header::CONTENT_DISPOSITION, disposition)], bytes).into_response())
}

/// A stored plan and what it is exported from (`None`: it is gone).
async fn stored_export(db: &Db, tenant: &str, plan_id: &str) -> Result<Option<(plans::ExportSource, StoredExport)>, ApiError> {
    let Some(mut source) = plans::export_source(db, tenant, JobKind::Plan, plan_id).await? else { return Ok(None) };
    let geojson = source.trajectory.take().unwrap_or_default();
    let stored = StoredExport::read(plan_id, &source, &geojson)?;
    Ok(Some((source, stored)))
}

#[utoipa::path(get, operation_id = "get_farm_flights", path = "/api/v1/farm-plans/{id}/flights", tag = "farms", params(("id" = String, Path), TrajectoryQuery),
    responses((status = 200, content_type = "application/zip", body = Vec<u8>, description = "a zip of one flight plan per machine and working day in `format` (as a plan's \
        trajectory takes it): the sorties its fields' plans fly that day, in the schedule's order, a field worked over several days flown sortie by sortie; a file per sortie in the formats \
        that describe one flight; named `{machine}-day-{day}-{date}`"),
              (status = 400, body = Problem, description = "unknown format or firmware"), (status = 404, body = Problem),
              (status = 409, body = Problem, description = "the farm plan is not scheduled yet"), (status = 422, body = Problem, description = "the format cannot say these plans")))]
pub async fn flights(State(state): State<AppState>, caller: Caller, Path(id): Path<String>, ApiQuery(query): ApiQuery<TrajectoryQuery>) -> Result<Response, ApiError> {
    let (exporter, options) = query.choice()?;
    let row = find(&state, &caller, &id).await?;
    let farm = view(&state, &caller, row).await?;
    let Some(schedule) = &farm.schedule else {
        return Err(not_scheduled(&farm));
    };
    let plan_of: HashMap<usize, String> = farm.fields.iter().filter(|f| f.status == Some(PlanStatus::Succeeded)).filter_map(|f| f.plan_id.clone().map(|p| (f.index, p))).collect();
    let mut days: Vec<(String, Vec<Stretch>)> = Vec::new();
    for (k, (machine, stretches)) in schedule.machines.iter().zip(schedule.stretches()).enumerate() {
        // machines of one name are told apart by their number
        let named = schedule.machines.iter().filter(|m| m.machine == machine.machine).count() > 1;
        let name = if named { format!("{} {}", machine.machine, k + 1) } else { machine.machine.clone() };
        for (day, worked) in machine.days.iter().zip(stretches).filter(|(_, w)| !w.is_empty()) {
            days.push((format!("{name}-day-{}-{}", day.day, day.date), worked));
        }
    }
    let (db, tenant) = (state.db.clone(), caller.tenant.clone());
    let format = exporter.format().id;
    // one day's trajectories in memory at a time
    let files = off_the_async_threads(move || {
        let runtime = tokio::runtime::Handle::current();
        let mut files = Vec::new();
        for (stem, worked) in days {
            let mut loaded = Vec::new();
            for stretch in worked {
                let Some(plan_id) = plan_of.get(&stretch.field) else { continue };
                if let Some((source, stored)) = runtime.block_on(stored_export(&db, &tenant, plan_id))? {
                    loaded.push((stretch, source, stored));
                }
            }
            let stretches: Vec<DayStretch<'_>> =
                loaded.iter().map(|(share, source, stored)| DayStretch { request: stored.request(&source.name, source, options), share: *share }).collect();
            files.extend(planner::export::export_day(format, &stem, &stretches)?);
        }
        Ok::<_, ApiError>(files)
    })
    .await?;
    let disposition = format!("attachment; filename=\"{}-flights-{format}.zip\"", planner::export::file_stem(&farm.name));
    Ok(([(header::CONTENT_TYPE, "application/zip".to_owned()), (header::CONTENT_DISPOSITION, disposition)], planner::archive::zip(&files)).into_response())
}

/// A task for each stretch of a machine's day on one field: `sprayer 1 · day 3 (2027-04-14) · 2. North field`.
fn farm_tasks(schedule: &Schedule, fields: &[FieldState]) -> Vec<FarmTask> {
    let mut tasks = Vec::new();
    for machine in &schedule.machines {
        for day in &machine.days {
            let mut worked: Vec<usize> = day.legs.iter().filter(|l| l.kind == LegKind::Work).filter_map(|l| l.field).collect();
            worked.dedup();
            for (order, field) in worked.into_iter().enumerate() {
                let designator = format!("{} · day {} ({}) · {}. {}", machine.machine, day.day, day.date, order + 1, fields[field].name);
                tasks.push(FarmTask { designator, field });
            }
        }
    }
    tasks
}

fn not_scheduled(farm: &FarmPlan) -> ApiError {
    ApiError::conflict(
        "schedule_not_available",
        format!("the farm plan is {}: {} of its {} fields are planned", json!(farm.status).as_str().unwrap_or("?"), farm.fields_done, farm.fields_total),
    )
}

#[utoipa::path(delete, operation_id = "cancel_farm_plan", path = "/api/v1/farm-plans/{id}", tag = "farms", params(("id" = String, Path)),
    responses((status = 200, body = FarmPlan, description = "cancelled, its fields' queued and running plans with it"), (status = 404, body = Problem)))]
pub async fn cancel(State(state): State<AppState>, caller: Caller, Path(id): Path<String>) -> Result<Json<FarmPlan>, ApiError> {
    let cancelled = farms::cancel(&state.db, &caller.tenant, &id).await?.ok_or_else(|| ApiError::not_found("farm plan", &id))?;
    for plan in &cancelled {
        state.jobs.cancel(plan);
    }
    let row = find(&state, &caller, &id).await?;
    Ok(Json(view(&state, &caller, row).await?))
}
