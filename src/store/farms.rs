//! Farm plans: a farm's fields, each planned as a job of the queue (`plans.farm_plan_id`), and
//! the schedule written once every field's plan has finished.

use serde::{Deserialize, Serialize};
use serde_json::Value;
use sqlx::FromRow;
use sqlx::types::Json;
use utoipa::ToSchema;

use super::plans::{JobKind, PlanStatus, QUEUED_CHANNEL};
use super::{Db, Statement, WritePool, new_id};
use crate::on_db;

/// A field of a farm plan, as the farm plan was made.
#[derive(Debug, Clone, Serialize, Deserialize, ToSchema)]
pub struct FarmField {
    /// Its index in the farm's fields (what the schedule names it by).
    pub index: usize,
    pub mission_id: String,
    pub name: String,
    /// The job that plans it; none when it was refused.
    pub plan_id: Option<String>,
    /// Why it was refused, in words, with the refusal's code.
    pub refused: Option<String>,
    pub refused_code: Option<String>,
}

/// A field's job: the field's plan to queue.
pub struct FieldJob {
    pub plan_id: String,
    pub mission_id: String,
    pub params: Value,
    pub mission: Value,
}

/// A stored farm plan.
#[derive(Debug, Clone, FromRow)]
pub struct FarmRow {
    pub id: String,
    pub name: String,
    pub request: Json<Value>,
    pub fields: Json<Vec<FarmField>>,
    pub schedule: Option<Json<Value>>,
    pub cancelled: bool,
    pub created_at: String,
    pub finished_at: Option<String>,
}

/// A field's job as the farm plan follows it: its status, and once planned its duration and
/// where its path begins and ends (`[lon, lat]` as JSON text).
#[derive(Debug, Clone, FromRow)]
pub struct FieldPlan {
    pub id: String,
    pub status: PlanStatus,
    pub error: Option<String>,
    pub error_code: Option<String>,
    pub duration_s: Option<f64>,
    pub begins_at: Option<String>,
    pub ends_at: Option<String>,
}

macro_rules! columns {
    () => {
        "id, name, request, fields, schedule, cancelled, created_at, finished_at"
    };
}

/// A new plan id for a field's job (known before the farm plan is written, which lists it).
pub fn new_plan_id() -> String {
    new_id()
}

/// Writes a farm plan and queues its fields' jobs in one transaction; `None` when `tenant` has
/// `most_active` farm plans with fields still queued or running.
pub async fn create(db: &Db, tenant: &str, name: &str, request: &Value, fields: &[FarmField], jobs: &[FieldJob], most_active: i64) -> Result<Option<FarmRow>, sqlx::Error> {
    let id = new_id();
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        if db.is_postgres() {
            sqlx::query("SELECT pg_advisory_xact_lock(hashtext($1))").bind(tenant).execute(&mut *tx).await?;
        }
        let active: i64 = sqlx::query_scalar(sql(Statement {
            sqlite: "SELECT COUNT(DISTINCT farm_plan_id) FROM plans WHERE tenant = ? AND farm_plan_id IS NOT NULL AND status IN ('queued', 'running')",
            postgres: "SELECT COUNT(DISTINCT farm_plan_id) FROM plans WHERE tenant = $1 AND farm_plan_id IS NOT NULL AND status IN ('queued', 'running')",
        }))
        .bind(tenant)
        .fetch_one(&mut *tx)
        .await?;
        if active >= most_active {
            return Ok(None);
        }
        let row: FarmRow = sqlx::query_as(sql(Statement {
            sqlite: concat!("INSERT INTO farm_plans (id, tenant, name, request, fields, created_at) VALUES (?, ?, ?, ?, ?, ", crate::sqlite_now!(), ") RETURNING ", columns!()),
            postgres: concat!(
                "INSERT INTO farm_plans (id, tenant, name, request, fields, created_at) VALUES ($1, $2, $3, $4, $5, ",
                crate::postgres_now!(),
                ") RETURNING ",
                columns!()
            ),
        }))
        .bind(&id)
        .bind(tenant)
        .bind(name)
        .bind(Json(request))
        .bind(Json(fields))
        .fetch_one(&mut *tx)
        .await?;
        for job in jobs {
            sqlx::query(sql(Statement {
                sqlite: concat!(
                    "INSERT INTO plans (id, tenant, mission_id, params, mission, kind, farm_plan_id, status, created_at) VALUES (?, ?, ?, ?, ?, ?, ?, 'queued', ",
                    crate::sqlite_now!(),
                    ")"
                ),
                postgres: concat!(
                    "INSERT INTO plans (id, tenant, mission_id, params, mission, kind, farm_plan_id, status, created_at) VALUES ($1, $2, $3, $4, $5, $6, $7, 'queued', ",
                    crate::postgres_now!(),
                    ")"
                ),
            }))
            .bind(&job.plan_id)
            .bind(tenant)
            .bind(&job.mission_id)
            .bind(Json(&job.params))
            .bind(Json(&job.mission))
            .bind(JobKind::Plan)
            .bind(&id)
            .execute(&mut *tx)
            .await?;
        }
        if db.is_postgres() {
            sqlx::query("SELECT pg_notify($1, '')").bind(QUEUED_CHANNEL).execute(&mut *tx).await?;
        }
        tx.commit().await?;
        Ok(Some(row))
    })
}

pub async fn get(db: &Db, tenant: &str, id: &str) -> Result<Option<FarmRow>, sqlx::Error> {
    on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: concat!("SELECT ", columns!(), " FROM farm_plans WHERE id = ? AND tenant = ?"),
        postgres: concat!("SELECT ", columns!(), " FROM farm_plans WHERE id = $1 AND tenant = $2"),
    }))
    .bind(id)
    .bind(tenant)
    .fetch_optional(pool)
    .await)
}

/// The jobs of a farm plan's fields.
pub async fn field_plans(db: &Db, tenant: &str, id: &str) -> Result<Vec<FieldPlan>, sqlx::Error> {
    on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: "SELECT id, status, error, error_code, stats ->> 'duration_s' AS duration_s, stats -> 'begins_at' AS begins_at, stats -> 'ends_at' AS ends_at \
                 FROM plans WHERE farm_plan_id = ? AND tenant = ?",
        postgres: "SELECT id, status, error, error_code, (stats->>'duration_s')::float8 AS duration_s, (stats->'begins_at')::text AS begins_at, \
                   (stats->'ends_at')::text AS ends_at FROM plans WHERE farm_plan_id = $1 AND tenant = $2",
    }))
    .bind(id)
    .bind(tenant)
    .fetch_all(pool)
    .await)
}

/// Writes the schedule unless another request wrote it first.
pub async fn save_schedule(db: &Db, tenant: &str, id: &str, schedule: &Value) -> Result<(), sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        sqlx::query(sql(Statement {
            sqlite: concat!("UPDATE farm_plans SET schedule = ?, finished_at = ", crate::sqlite_now!(), " WHERE id = ? AND tenant = ? AND schedule IS NULL"),
            postgres: concat!("UPDATE farm_plans SET schedule = $1, finished_at = ", crate::postgres_now!(), " WHERE id = $2 AND tenant = $3 AND schedule IS NULL"),
        }))
        .bind(Json(schedule))
        .bind(id)
        .bind(tenant)
        .execute(&mut *tx)
        .await?;
        tx.commit().await
    })
}

/// Cancels a farm plan and its fields' queued and running jobs; returns the jobs cancelled
/// (`None`: the tenant has no such farm plan).
pub async fn cancel(db: &Db, tenant: &str, id: &str) -> Result<Option<Vec<String>>, sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let found = sqlx::query(sql(Statement {
            sqlite: concat!("UPDATE farm_plans SET cancelled = TRUE, finished_at = COALESCE(finished_at, ", crate::sqlite_now!(), ") WHERE id = ? AND tenant = ?"),
            postgres: concat!("UPDATE farm_plans SET cancelled = TRUE, finished_at = COALESCE(finished_at, ", crate::postgres_now!(), ") WHERE id = $1 AND tenant = $2"),
        }))
        .bind(id)
        .bind(tenant)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        if found == 0 {
            return Ok(None);
        }
        let jobs: Vec<String> = sqlx::query_scalar(sql(Statement {
            sqlite: concat!(
                "UPDATE plans SET status = 'cancelled', finished_at = ",
                crate::sqlite_now!(),
                " WHERE farm_plan_id = ? AND tenant = ? AND status IN ('queued', 'running') RETURNING id"
            ),
            postgres: concat!(
                "UPDATE plans SET status = 'cancelled', finished_at = ",
                crate::postgres_now!(),
                " WHERE farm_plan_id = $1 AND tenant = $2 AND status IN ('queued', 'running') RETURNING id"
            ),
        }))
        .bind(id)
        .bind(tenant)
        .fetch_all(&mut *tx)
        .await?;
        tx.commit().await?;
        Ok(Some(jobs))
    })
}
