//! Plans: rows that are both the job queue and the results. Each belongs to its mission's
//! tenant; every query a request makes is scoped to one.

use serde::Serialize;
use serde_json::Value;
use sqlx::FromRow;
use sqlx::types::Json;
use utoipa::ToSchema;

use super::{Db, Statement, WritePool, new_id};
use crate::on_db;

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
    /// A resumed plan: the plan whose flight it finishes (`POST /api/v1/plans/{id}/resume`).
    pub resumed_from: Option<String>,
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
    resumed_from: Option<String>,
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
            resumed_from: r.resumed_from,
        }
    }
}

macro_rules! columns {
    () => {
        "id, mission_id, status, progress, params, stats, error, error_code, created_at, started_at, finished_at, resumed_from"
    };
}

/// What a job of the queue plans: a plan (coverage or inspection) or a patrol. Each answers
/// only under its own routes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, sqlx::Type)]
#[sqlx(type_name = "TEXT", rename_all = "snake_case")]
pub enum JobKind {
    Plan,
    Patrol,
}

/// The channel on which PostgreSQL announces newly queued plans to every replica.
pub const QUEUED_CHANNEL: &str = "coverplan_queued";

/// What a queued job is: its kind, mission, parameters and the snapshot it runs on, and the
/// plan it resumes.
pub struct NewJob<'a> {
    pub kind: JobKind,
    pub mission_id: &'a str,
    pub params: &'a Value,
    pub mission: &'a Value,
    pub resumed_from: Option<&'a str>,
}

impl<'a> NewJob<'a> {
    pub fn new(kind: JobKind, mission_id: &'a str, params: &'a Value, mission: &'a Value) -> Self {
        NewJob { kind, mission_id, params, mission, resumed_from: None }
    }
}

/// Queues a plan of `tenant`'s mission (a snapshot of its geometry) with `params`; `None` when
/// the tenant has `most_active` plans queued or running already, farm plans' fields left out (counted in the same write
/// transaction, so concurrent requests cannot pass the cap together: SQLite's write lock, or on
/// PostgreSQL a lock on the tenant held to the commit).
pub async fn create(db: &Db, tenant: &str, job: &NewJob<'_>, most_active: i64) -> Result<Option<Plan>, sqlx::Error> {
    let id = new_id();
    let row: Option<PlanRow> = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        if db.is_postgres() {
            sqlx::query("SELECT pg_advisory_xact_lock(hashtext($1))").bind(tenant).execute(&mut *tx).await?;
        }
        let active: i64 = sqlx::query_scalar(sql(Statement {
            sqlite: "SELECT COUNT(*) FROM plans WHERE tenant = ? AND status IN ('queued', 'running') AND farm_plan_id IS NULL",
            postgres: "SELECT COUNT(*) FROM plans WHERE tenant = $1 AND status IN ('queued', 'running') AND farm_plan_id IS NULL",
        }))
        .bind(tenant)
        .fetch_one(&mut *tx)
        .await?;
        if active >= most_active {
            return Ok(None);
        }
        let row = sqlx::query_as(sql(Statement {
            sqlite: concat!(
                "INSERT INTO plans (id, tenant, mission_id, params, mission, kind, resumed_from, status, created_at) VALUES (?, ?, ?, ?, ?, ?, ?, 'queued', ",
                crate::sqlite_now!(),
                ") RETURNING ",
                columns!()
            ),
            postgres: concat!(
                "INSERT INTO plans (id, tenant, mission_id, params, mission, kind, resumed_from, status, created_at) VALUES ($1, $2, $3, $4, $5, $6, $7, 'queued', ",
                crate::postgres_now!(),
                ") RETURNING ",
                columns!()
            ),
        }))
        .bind(&id)
        .bind(tenant)
        .bind(job.mission_id)
        .bind(Json(job.params))
        .bind(Json(job.mission))
        .bind(job.kind)
        .bind(job.resumed_from)
        .fetch_one(&mut *tx)
        .await?;
        if db.is_postgres() {
            // delivered at the commit, to every replica listening
            sqlx::query("SELECT pg_notify($1, '')").bind(QUEUED_CHANNEL).execute(&mut *tx).await?;
        }
        tx.commit().await?;
        Some(row)
    });
    Ok(row.map(Into::into))
}

/// A job of `tenant`'s of this kind; another tenant's, or one of the other kind, is `None`, as
/// one that does not exist.
pub async fn get(db: &Db, tenant: &str, kind: JobKind, id: &str) -> Result<Option<Plan>, sqlx::Error> {
    let row: Option<PlanRow> = on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: concat!("SELECT ", columns!(), " FROM plans WHERE id = ? AND tenant = ? AND kind = ?"),
        postgres: concat!("SELECT ", columns!(), " FROM plans WHERE id = $1 AND tenant = $2 AND kind = $3")
    }))
    .bind(id)
    .bind(tenant)
    .bind(kind)
    .fetch_optional(pool)
    .await?);
    Ok(row.map(Into::into))
}

/// The jobs of this kind of one of `tenant`'s missions, newest first.
pub async fn list_for_mission(db: &Db, tenant: &str, kind: JobKind, mission_id: &str) -> Result<Vec<Plan>, sqlx::Error> {
    let rows: Vec<PlanRow> = on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: concat!("SELECT ", columns!(), " FROM plans WHERE mission_id = ? AND tenant = ? AND kind = ? ORDER BY created_at DESC, rowid DESC"),
        postgres: concat!("SELECT ", columns!(), " FROM plans WHERE mission_id = $1 AND tenant = $2 AND kind = $3 ORDER BY created_at DESC, seq DESC")
    }))
    .bind(mission_id)
    .bind(tenant)
    .bind(kind)
    .fetch_all(pool)
    .await?);
    Ok(rows.into_iter().map(Into::into).collect())
}

/// What a plan's files are written from (and a resumed plan planned from): its status,
/// trajectory (GeoJSON text), parameters, the mission snapshot it was planned on, and the
/// mission's id and name.
#[derive(Debug, Clone, FromRow)]
pub struct ExportSource {
    pub status: PlanStatus,
    pub trajectory: Option<String>,
    #[sqlx(json)]
    pub params: Value,
    #[sqlx(json)]
    pub mission: Value,
    pub mission_id: String,
    pub name: String,
}

pub async fn export_source(db: &Db, tenant: &str, kind: JobKind, id: &str) -> Result<Option<ExportSource>, sqlx::Error> {
    on_db!(db, |pool, sql| {
        sqlx::query_as(sql(Statement {
        sqlite: "SELECT p.status, p.trajectory, p.params, p.mission, p.mission_id, m.name FROM plans p JOIN missions m ON m.id = p.mission_id WHERE p.id = ? AND p.tenant = ? AND p.kind = ?",
        postgres: "SELECT p.status, p.trajectory, p.params, p.mission, p.mission_id, m.name FROM plans p JOIN missions m ON m.id = p.mission_id WHERE p.id = $1 AND p.tenant = $2 AND p.kind = $3"
    }))
    .bind(id)
    .bind(tenant)
    .bind(kind)
    .fetch_optional(pool)
    .await
    })
}

/// A job taken off the queue.
#[derive(Debug, Clone, FromRow)]
pub struct Job {
    pub id: String,
    pub tenant: String,
    pub kind: JobKind,
    #[sqlx(json)]
    pub params: Value,
    #[sqlx(json)]
    pub mission: Value,
    pub mission_id: String,
    /// The mission's elevation model (file name, bytes), read when the request flies over
    /// terrain; not a column of the claim.
    #[sqlx(skip)]
    pub terrain: Option<(String, Vec<u8>)>,
}

/// The claim a replica holds on a running plan: only its holder may write the outcome, and only
/// while its lease is renewed.
#[derive(Debug, Clone, Copy)]
pub struct Claim<'a> {
    pub plan: &'a str,
    pub replica: &'a str,
}

/// Records the end of a claim, in the transaction that ends it.
const CLOSE_CLAIM: Statement = Statement {
    sqlite: concat!("UPDATE plan_claims SET ended_at = ", crate::sqlite_epoch!(), ", outcome = ? WHERE plan_id = ? AND replica = ? AND ended_at IS NULL"),
    postgres: concat!("UPDATE plan_claims SET ended_at = ", crate::postgres_epoch!(), ", outcome = $1 WHERE plan_id = $2 AND replica = $3 AND ended_at IS NULL"),
};

/// The claim of [`claim_next`], the same on both: PostgreSQL locks the row it takes and skips
/// those others hold. The queue's index (`plans_queue`) is in its order, so a claim reads one
/// entry however many plans are queued.
pub const CLAIM_NEXT: Statement = Statement {
    sqlite: concat!(
        "UPDATE plans SET status = 'running', progress = 0, started_at = ",
        crate::sqlite_now!(),
        ", attempts = attempts + 1, claimed_by = ?, lease_until = ",
        crate::sqlite_epoch!(),
        " + ? WHERE id = (SELECT id FROM plans WHERE status = 'queued' ORDER BY farm_plan_id IS NOT NULL, created_at, rowid LIMIT 1) RETURNING id, tenant, kind, params, mission, mission_id"
    ),
    postgres: concat!(
        "UPDATE plans SET status = 'running', progress = 0, started_at = ",
        crate::postgres_now!(),
        ", attempts = attempts + 1, claimed_by = $1, lease_until = ",
        crate::postgres_epoch!(),
        " + $2 WHERE id = (SELECT id FROM plans WHERE status = 'queued' ORDER BY farm_plan_id IS NOT NULL, created_at, seq LIMIT 1 FOR UPDATE SKIP LOCKED) RETURNING id, tenant, kind, params, mission, mission_id"
    ),
};

/// Atomically takes the oldest queued plan for `replica` (a farm plan's fields after every other
/// plan, so that one farm's hundreds of fields do not hold up a single plan), marks it running under a lease of
/// `lease_s` seconds and records the claim. On PostgreSQL the row is locked with `SKIP LOCKED`,
/// so replicas claiming at once take different plans without waiting for each other.
pub async fn claim_next(db: &Db, replica: &str, lease_s: f64) -> Result<Option<Job>, sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let job: Option<Job> = sqlx::query_as(sql(CLAIM_NEXT)).bind(replica).bind(lease_s).fetch_optional(&mut *tx).await?;
        if let Some(job) = &job {
            sqlx::query(sql(Statement {
                sqlite: concat!("INSERT INTO plan_claims (plan_id, replica, claimed_at) VALUES (?, ?, ", crate::sqlite_epoch!(), ")"),
                postgres: concat!("INSERT INTO plan_claims (plan_id, replica, claimed_at) VALUES ($1, $2, ", crate::postgres_epoch!(), ")"),
            }))
            .bind(&job.id)
            .bind(replica)
            .execute(&mut *tx)
            .await?;
        }
        tx.commit().await?;
        Ok(job)
    })
}

/// Renews the lease on a running plan for `lease_s` seconds and saves its progress. False when
/// the plan is no longer this claim's to run (cancelled, or taken over after the lease ran out):
/// its holder should stop.
pub async fn heartbeat(db: &Db, claim: Claim<'_>, progress: f64, lease_s: f64) -> Result<bool, sqlx::Error> {
    let renewed = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let done = sqlx::query(sql(Statement {
            sqlite: concat!("UPDATE plans SET progress = ?, lease_until = ", crate::sqlite_epoch!(), " + ? WHERE id = ? AND claimed_by = ? AND status = 'running'"),
            postgres: concat!("UPDATE plans SET progress = $1, lease_until = ", crate::postgres_epoch!(), " + $2 WHERE id = $3 AND claimed_by = $4 AND status = 'running'"),
        }))
        .bind(progress)
        .bind(lease_s)
        .bind(claim.plan)
        .bind(claim.replica)
        .execute(&mut *tx)
        .await?;
        tx.commit().await?;
        done.rows_affected()
    });
    Ok(renewed > 0)
}

/// Ends `claim` with `outcome` by `update` (which binds its own values, then the plan id and
/// the replica): the plan's row and the claim's record change together or not at all, retried
/// on failures that may pass.
macro_rules! end_claim {
    ($db:expr, $claim:expr, $outcome:expr, $update:expr, |$q:ident| $bind:expr) => {{
        let claim: Claim<'_> = $claim;
        super::retrying(|| async move {
            on_db!($db, |pool, sql| {
                let mut tx = pool.begin_write().await?;
                let $q = sqlx::query(sql($update));
                $bind.bind(claim.plan).bind(claim.replica).execute(&mut *tx).await?;
                sqlx::query(sql(CLOSE_CLAIM)).bind($outcome).bind(claim.plan).bind(claim.replica).execute(&mut *tx).await?;
                tx.commit().await
            })
        })
        .await
    }};
}

/// Stores a finished plan in one statement: stats, trajectory and status together or nothing.
/// A plan cancelled meanwhile stays cancelled; a claim taken over writes nothing.
pub async fn succeed(db: &Db, claim: Claim<'_>, stats: &Value, trajectory: &str) -> Result<(), sqlx::Error> {
    end_claim!(
        db,
        claim,
        "succeeded",
        Statement {
            sqlite: concat!(
                "UPDATE plans SET status = 'succeeded', progress = 1, stats = ?, trajectory = ?, claimed_by = NULL, lease_until = NULL, finished_at = ",
                crate::sqlite_now!(),
                " WHERE id = ? AND claimed_by = ? AND status = 'running'"
            ),
            postgres: concat!(
                "UPDATE plans SET status = 'succeeded', progress = 1, stats = $1, trajectory = $2, claimed_by = NULL, lease_until = NULL, finished_at = ",
                crate::postgres_now!(),
                " WHERE id = $3 AND claimed_by = $4 AND status = 'running'"
            )
        },
        |q| q.bind(Json(stats)).bind(trajectory)
    )
}

/// Fails a running plan with a code for programs and words for people.
pub async fn fail(db: &Db, claim: Claim<'_>, code: &str, error: &str) -> Result<(), sqlx::Error> {
    end_claim!(
        db,
        claim,
        "failed",
        Statement {
            sqlite: concat!(
                "UPDATE plans SET status = 'failed', error_code = ?, error = ?, claimed_by = NULL, lease_until = NULL, finished_at = ",
                crate::sqlite_now!(),
                " WHERE id = ? AND claimed_by = ? AND status = 'running'"
            ),
            postgres: concat!(
                "UPDATE plans SET status = 'failed', error_code = $1, error = $2, claimed_by = NULL, lease_until = NULL, finished_at = ",
                crate::postgres_now!(),
                " WHERE id = $3 AND claimed_by = $4 AND status = 'running'"
            )
        },
        |q| q.bind(code).bind(error)
    )
}

/// Puts a running plan back in the queue (its replica is shutting down), for any replica to
/// take at once.
pub async fn requeue(db: &Db, claim: Claim<'_>) -> Result<(), sqlx::Error> {
    end_claim!(
        db,
        claim,
        "handed_back",
        Statement {
            sqlite: "UPDATE plans SET status = 'queued', progress = 0, started_at = NULL, claimed_by = NULL, lease_until = NULL WHERE id = ? AND claimed_by = ? AND status = 'running'",
            postgres: "UPDATE plans SET status = 'queued', progress = 0, started_at = NULL, claimed_by = NULL, lease_until = NULL WHERE id = $1 AND claimed_by = $2 AND status = 'running'"
        },
        |q| q
    )
}

/// Records the end of a claim whose plan was cancelled by its owner while it ran.
pub async fn release(db: &Db, claim: Claim<'_>, outcome: &str) -> Result<(), sqlx::Error> {
    on_db!(db, |pool, sql| sqlx::query(sql(CLOSE_CLAIM)).bind(outcome).bind(claim.plan).bind(claim.replica).execute(pool).await.map(|_| ()))
}

/// Cancels a queued or running plan of `tenant`'s. Returns its status afterwards (`None`: the
/// tenant has no such plan). A replica running it sees at its next heartbeat that it is no
/// longer running and stops.
pub async fn cancel(db: &Db, tenant: &str, id: &str) -> Result<Option<PlanStatus>, sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        sqlx::query(sql(Statement {
            sqlite: concat!("UPDATE plans SET status = 'cancelled', finished_at = ", crate::sqlite_now!(), " WHERE id = ? AND tenant = ? AND status IN ('queued', 'running')"),
            postgres: concat!(
                "UPDATE plans SET status = 'cancelled', finished_at = ",
                crate::postgres_now!(),
                " WHERE id = $1 AND tenant = $2 AND status IN ('queued', 'running')"
            ),
        }))
        .bind(id)
        .bind(tenant)
        .execute(&mut *tx)
        .await?;
        let status = sqlx::query_scalar(sql(Statement {
            sqlite: "SELECT status FROM plans WHERE id = ? AND tenant = ?",
            postgres: "SELECT status FROM plans WHERE id = $1 AND tenant = $2",
        }))
        .bind(id)
        .bind(tenant)
        .fetch_optional(&mut *tx)
        .await?;
        tx.commit().await?;
        Ok(status)
    })
}

/// Plans whose replica stopped renewing their lease (it died, or lost the database) go back to
/// the queue, unless they were interrupted too often (then they fail, so that a plan that kills
/// its process cannot loop forever). With `every_running`, all running plans count as
/// abandoned: a single SQLite server at start-up holds none. Returns (requeued, failed).
pub async fn requeue_abandoned(db: &Db, every_running: bool) -> Result<(u64, u64), sqlx::Error> {
    // each statement picks the running plans whose lease has run out (or, with the bind
    // `every_running`, any running plan)
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        sqlx::query(sql(Statement {
            sqlite: concat!(
                "UPDATE plan_claims SET ended_at = ",
                crate::sqlite_epoch!(),
                ", outcome = 'abandoned' WHERE ended_at IS NULL AND plan_id IN (SELECT id FROM plans WHERE ",
                "status = 'running' AND (? OR lease_until IS NULL OR lease_until < ",
                crate::sqlite_epoch!(),
                ")",
                ")"
            ),
            postgres: concat!(
                "UPDATE plan_claims SET ended_at = ",
                crate::postgres_epoch!(),
                ", outcome = 'abandoned' WHERE ended_at IS NULL AND plan_id IN (SELECT id FROM plans WHERE ",
                "status = 'running' AND ($1 OR lease_until IS NULL OR lease_until < ",
                crate::postgres_epoch!(),
                ")",
                ")"
            ),
        }))
        .bind(every_running)
        .execute(&mut *tx)
        .await?;
        let failed = sqlx::query(sql(Statement {
            sqlite: concat!(
                "UPDATE plans SET status = 'failed', error_code = 'interrupted', claimed_by = NULL, lease_until = NULL, finished_at = ",
                crate::sqlite_now!(),
                ",
                error = 'the server stopped during this plan ' || attempts || ' times; it was not retried again'
             WHERE attempts >= ? AND ",
                "status = 'running' AND (? OR lease_until IS NULL OR lease_until < ",
                crate::sqlite_epoch!(),
                ")"
            ),
            postgres: concat!(
                "UPDATE plans SET status = 'failed', error_code = 'interrupted', claimed_by = NULL, lease_until = NULL, finished_at = ",
                crate::postgres_now!(),
                ",
                error = 'the server stopped during this plan ' || attempts || ' times; it was not retried again'
             WHERE attempts >= $1 AND ",
                "status = 'running' AND ($2 OR lease_until IS NULL OR lease_until < ",
                crate::postgres_epoch!(),
                ")"
            ),
        }))
        .bind(MAX_ATTEMPTS)
        .bind(every_running)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        let requeued = sqlx::query(sql(Statement {
            sqlite: concat!(
                "UPDATE plans SET status = 'queued', progress = 0, started_at = NULL, claimed_by = NULL, lease_until = NULL WHERE ",
                "status = 'running' AND (? OR lease_until IS NULL OR lease_until < ",
                crate::sqlite_epoch!(),
                ")"
            ),
            postgres: concat!(
                "UPDATE plans SET status = 'queued', progress = 0, started_at = NULL, claimed_by = NULL, lease_until = NULL WHERE ",
                "status = 'running' AND ($1 OR lease_until IS NULL OR lease_until < ",
                crate::postgres_epoch!(),
                ")"
            ),
        }))
        .bind(every_running)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        tx.commit().await?;
        Ok((requeued, failed))
    })
}

/// Plans waiting for a worker, all tenants.
pub async fn queued_count(db: &Db) -> Result<i64, sqlx::Error> {
    on_db!(db, |pool, _sql| sqlx::query_scalar("SELECT COUNT(*) FROM plans WHERE status = 'queued'").fetch_one(pool).await)
}

/// One replica's hold on a plan, as recorded (`plan_claims`): who, when (seconds since 1970),
/// and how it ended (`succeeded`, `failed`, `cancelled`, `handed_back`, `abandoned`; `None`
/// while it runs).
#[derive(Debug, Clone, FromRow)]
pub struct ClaimRecord {
    pub plan_id: String,
    pub replica: String,
    pub claimed_at: f64,
    pub ended_at: Option<f64>,
    pub outcome: Option<String>,
}

/// Every claim ever made, in the order they were made.
pub async fn claims(db: &Db) -> Result<Vec<ClaimRecord>, sqlx::Error> {
    on_db!(db, |pool, _sql| sqlx::query_as("SELECT plan_id, replica, claimed_at, ended_at, outcome FROM plan_claims ORDER BY claimed_at, plan_id").fetch_all(pool).await)
}
