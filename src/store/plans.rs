//! Plans: rows that are both the job queue and the results. Each belongs to its mission's
//! tenant; every query a request makes is scoped to one.

use serde::Serialize;
use serde_json::Value;
use sqlx::FromRow;
use sqlx::types::Json;
use utoipa::ToSchema;

use super::{Db, begin_write, new_id};

/// A job that was interrupted this many times is failed instead of requeued again.
pub const MAX_ATTEMPTS: i64 = 3;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema, sqlx::Type)]
#[serde(rename_all = "snake_case")]
#[sqlx(type_name = "TEXT", rename_all = "snake_case")]
pub enum PlanStatus {
    Queued,
    Running,
    Succeeded,
    Failed,
    Cancelled,
}

impl PlanStatus {
    pub fn is_final(self) -> bool {
        matches!(self, PlanStatus::Succeeded | PlanStatus::Failed | PlanStatus::Cancelled)
    }
}

#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Plan {
    pub id: String,
    pub mission_id: String,
    pub status: PlanStatus,
    /// 0 to 1
    pub progress: f64,
    /// The parameters as sent.
    #[schema(value_type = Object)]
    pub params: Value,
    /// Figures of the finished plan (see the `Stats` schema).
    #[schema(value_type = Option<crate::planner::Stats>)]
    pub stats: Option<Value>,
    /// Why the plan failed, in words.
    pub error: Option<String>,
    /// Why the plan failed, for programs: `time_limit`, `infeasible` (no flyable plan
    /// exists), `internal`, `interrupted` (the server stopped during it too often), or the
    /// code of the parameter that is wrong.
    pub error_code: Option<String>,
    pub created_at: String,
    pub started_at: Option<String>,
    pub finished_at: Option<String>,
}

/// A row of `plans`, as listed.
#[derive(FromRow)]
struct PlanRow {
    id: String,
    mission_id: String,
    status: PlanStatus,
    progress: f64,
    params: Json<Value>,
    stats: Option<Json<Value>>,
    error: Option<String>,
    error_code: Option<String>,
    created_at: String,
    started_at: Option<String>,
    finished_at: Option<String>,
}

impl From<PlanRow> for Plan {
    fn from(r: PlanRow) -> Self {
        Plan {
            id: r.id,
            mission_id: r.mission_id,
            status: r.status,
            progress: r.progress,
            params: r.params.0,
            stats: r.stats.map(|j| j.0),
            error: r.error,
            error_code: r.error_code,
            created_at: r.created_at,
            started_at: r.started_at,
            finished_at: r.finished_at,
        }
    }
}

macro_rules! columns {
    () => {
        "id, mission_id, status, progress, params, stats, error, error_code, created_at, started_at, finished_at"
    };
}

/// Queues a plan of `tenant`'s mission (a snapshot of its geometry) with `params`; `None` when
/// the tenant has `most_active` plans queued or running already (counted in the same write
/// transaction, so concurrent requests cannot pass the cap together).
pub async fn create(db: &Db, tenant: &str, mission_id: &str, params: &Value, mission: &Value, most_active: i64) -> Result<Option<Plan>, sqlx::Error> {
    let id = new_id();
    let mut tx = begin_write(db).await?;
    let active: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM plans WHERE tenant = ? AND status IN ('queued', 'running')").bind(tenant).fetch_one(&mut *tx).await?;
    if active >= most_active {
        return Ok(None);
    }
    let row: PlanRow = sqlx::query_as(concat!(
        "INSERT INTO plans (id, tenant, mission_id, params, mission, status, created_at) VALUES (?, ?, ?, ?, ?, 'queued', ",
        crate::sql_now!(),
        ") RETURNING ",
        columns!()
    ))
    .bind(&id)
    .bind(tenant)
    .bind(mission_id)
    .bind(Json(params))
    .bind(Json(mission))
    .fetch_one(&mut *tx)
    .await?;
    tx.commit().await?;
    Ok(Some(row.into()))
}

/// A plan of `tenant`'s; another tenant's is `None`, as one that does not exist.
pub async fn get(db: &Db, tenant: &str, id: &str) -> Result<Option<Plan>, sqlx::Error> {
    let row: Option<PlanRow> = sqlx::query_as(concat!("SELECT ", columns!(), " FROM plans WHERE id = ? AND tenant = ?")).bind(id).bind(tenant).fetch_optional(db).await?;
    Ok(row.map(Into::into))
}

pub async fn list_for_mission(db: &Db, tenant: &str, mission_id: &str) -> Result<Vec<Plan>, sqlx::Error> {
    let rows: Vec<PlanRow> = sqlx::query_as(concat!("SELECT ", columns!(), " FROM plans WHERE mission_id = ? AND tenant = ? ORDER BY created_at DESC, rowid DESC"))
        .bind(mission_id)
        .bind(tenant)
        .fetch_all(db)
        .await?;
    Ok(rows.into_iter().map(Into::into).collect())
}

/// What a plan's files are written from: its status, trajectory (GeoJSON text), parameters,
/// the mission snapshot it was planned on, and the mission's name.
#[derive(Debug, Clone, FromRow)]
pub struct ExportSource {
    pub status: PlanStatus,
    pub trajectory: Option<String>,
    #[sqlx(json)]
    pub params: Value,
    #[sqlx(json)]
    pub mission: Value,
    pub name: String,
}

pub async fn export_source(db: &Db, tenant: &str, id: &str) -> Result<Option<ExportSource>, sqlx::Error> {
    sqlx::query_as("SELECT p.status, p.trajectory, p.params, p.mission, m.name FROM plans p JOIN missions m ON m.id = p.mission_id WHERE p.id = ? AND p.tenant = ?")
        .bind(id)
        .bind(tenant)
        .fetch_optional(db)
        .await
}

/// A job taken off the queue.
#[derive(Debug, Clone, FromRow)]
pub struct Job {
    pub id: String,
    pub tenant: String,
    #[sqlx(json)]
    pub params: Value,
    #[sqlx(json)]
    pub mission: Value,
}

/// Atomically takes the oldest queued plan and marks it running.
pub async fn claim_next(db: &Db) -> Result<Option<Job>, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let job = sqlx::query_as(concat!(
        "UPDATE plans SET status = 'running', progress = 0, started_at = ",
        crate::sql_now!(),
        ", attempts = attempts + 1
         WHERE id = (SELECT id FROM plans WHERE status = 'queued' ORDER BY created_at, rowid LIMIT 1)
         RETURNING id, tenant, params, mission"
    ))
    .fetch_optional(&mut *tx)
    .await?;
    tx.commit().await?;
    Ok(job)
}

pub async fn set_progress(db: &Db, id: &str, progress: f64) -> Result<(), sqlx::Error> {
    let mut tx = begin_write(db).await?;
    sqlx::query("UPDATE plans SET progress = ? WHERE id = ? AND status = 'running'").bind(progress).bind(id).execute(&mut *tx).await?;
    tx.commit().await
}

/// Stores a finished plan in one statement: stats, trajectory and status together or nothing.
/// A plan cancelled meanwhile stays cancelled.
pub async fn succeed(db: &Db, id: &str, stats: &Value, trajectory: &str) -> Result<(), sqlx::Error> {
    let mut tx = begin_write(db).await?;
    sqlx::query(concat!(
        "UPDATE plans SET status = 'succeeded', progress = 1, stats = ?, trajectory = ?, finished_at = ",
        crate::sql_now!(),
        "
         WHERE id = ? AND status = 'running'"
    ))
    .bind(Json(stats))
    .bind(trajectory)
    .bind(id)
    .execute(&mut *tx)
    .await?;
    tx.commit().await
}

/// Fails a running plan with a code for programs and words for people.
pub async fn fail(db: &Db, id: &str, code: &str, error: &str) -> Result<(), sqlx::Error> {
    let mut tx = begin_write(db).await?;
    sqlx::query(concat!("UPDATE plans SET status = 'failed', error_code = ?, error = ?, finished_at = ", crate::sql_now!(), " WHERE id = ? AND status = 'running'"))
        .bind(code)
        .bind(error)
        .bind(id)
        .execute(&mut *tx)
        .await?;
    tx.commit().await
}

/// Cancels a queued or running plan of `tenant`'s. Returns its status afterwards (`None`: the
/// tenant has no such plan).
pub async fn cancel(db: &Db, tenant: &str, id: &str) -> Result<Option<PlanStatus>, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    sqlx::query(concat!("UPDATE plans SET status = 'cancelled', finished_at = ", crate::sql_now!(), " WHERE id = ? AND tenant = ? AND status IN ('queued', 'running')"))
        .bind(id)
        .bind(tenant)
        .execute(&mut *tx)
        .await?;
    let status = sqlx::query_scalar("SELECT status FROM plans WHERE id = ? AND tenant = ?").bind(id).bind(tenant).fetch_optional(&mut *tx).await?;
    tx.commit().await?;
    Ok(status)
}

/// Puts a running plan back in the queue (the worker stopped before finishing it).
pub async fn requeue(db: &Db, id: &str) -> Result<(), sqlx::Error> {
    let mut tx = begin_write(db).await?;
    sqlx::query("UPDATE plans SET status = 'queued', progress = 0, started_at = NULL WHERE id = ? AND status = 'running'").bind(id).execute(&mut *tx).await?;
    tx.commit().await
}

/// At start-up: plans left running by a process that died go back to the queue, unless they
/// were interrupted too often (then they fail, so that a plan that kills the process cannot
/// loop forever). Returns (requeued, failed).
pub async fn recover_interrupted(db: &Db) -> Result<(u64, u64), sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let failed = sqlx::query(concat!(
        "UPDATE plans SET status = 'failed', error_code = 'interrupted', finished_at = ",
        crate::sql_now!(),
        ",
            error = 'the server stopped during this plan ' || attempts || ' times; it was not retried again'
         WHERE status = 'running' AND attempts >= ?"
    ))
    .bind(MAX_ATTEMPTS)
    .execute(&mut *tx)
    .await?
    .rows_affected();
    let requeued = sqlx::query("UPDATE plans SET status = 'queued', progress = 0, started_at = NULL WHERE status = 'running'").execute(&mut *tx).await?.rows_affected();
    tx.commit().await?;
    Ok((requeued, failed))
}

/// Plans waiting for a worker, all tenants.
pub async fn queued_count(db: &Db) -> Result<i64, sqlx::Error> {
    sqlx::query_scalar("SELECT COUNT(*) FROM plans WHERE status = 'queued'").fetch_one(db).await
}
