//! `coverplan bench --queue ADMIN_URL`: the shared job queue on a PostgreSQL server. For 1, 2
//! and 4 replicas (`coverplan serve` processes with one worker each, started by this binary),
//! the plans per minute of one small fixed mission, from the first claim to the last finish as
//! the record of claims shows them (process start left out); then the time one claim takes at
//! a queue of 10 000 plans. Each row runs on a database of its own, created on the server at
//! `ADMIN_URL` and dropped afterwards.

use std::fmt::Write as _;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::Context;
use serde_json::{Value, json};
use sqlx::Connection;

use crate::store::keys::OPEN_TENANT;
use crate::store::{self, missions, plans};

/// Plans queued for each throughput row.
const PLANS: usize = 1000;
/// Plans queued for the claim-latency row, and claims timed there.
const DEEP_QUEUE: usize = 10_000;
const CLAIMS_TIMED: usize = 200;

/// A 200 m × 150 m field in the Netherlands, flown at 20 m spacing.
fn small_field() -> Value {
    let (lon, lat) = (5.0, 52.0);
    let (dx, dy) = (200.0 / (111_320.0 * 52f64.to_radians().cos()), 150.0 / 110_574.0);
    json!({"type": "Polygon", "coordinates": [[[lon, lat], [lon + dx, lat], [lon + dx, lat + dy], [lon, lat + dy], [lon, lat]]]})
}

/// A fresh database on the server, dropped when the bench is done with it.
struct Scratch {
    admin: String,
    name: String,
    url: String,
}

impl Scratch {
    async fn new(admin: &str) -> anyhow::Result<Scratch> {
        let name = format!("coverplan_bench_{}", uuid::Uuid::new_v4().simple());
        let mut conn = sqlx::PgConnection::connect(admin).await.with_context(|| format!("connecting to {admin}"))?;
        sqlx::query(sqlx::AssertSqlSafe(format!("CREATE DATABASE {name}"))).execute(&mut conn).await?;
        conn.close().await?;
        let (server, _) = admin.rsplit_once('/').context("the admin URL names a database")?;
        Ok(Scratch { admin: admin.to_owned(), url: format!("{server}/{name}"), name })
    }

    async fn drop(self) -> anyhow::Result<()> {
        let mut conn = sqlx::PgConnection::connect(&self.admin).await?;
        sqlx::query(sqlx::AssertSqlSafe(format!("DROP DATABASE IF EXISTS {} WITH (FORCE)", self.name))).execute(&mut conn).await?;
        Ok(())
    }
}

/// Queues `n` plans of one small mission.
async fn queue(db: &store::Db, n: usize) -> anyhow::Result<()> {
    let area = small_field();
    let mission =
        missions::create(db, OPEN_TENANT, &missions::NewMission { name: "bench".into(), area: area.clone(), no_fly_zones: None, obstacles: None, structures: None, home: None })
            .await?;
    let snapshot = json!({"area": area});
    for _ in 0..n {
        plans::create(db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 20}), &snapshot), i64::MAX).await?;
    }
    Ok(())
}

fn replica(exe: &std::path::Path, url: &str, k: usize) -> anyhow::Result<Child> {
    Ok(Command::new(exe)
        .arg("serve")
        .env("COVERPLAN_ADDR", "127.0.0.1:0")
        .env("COVERPLAN_DATABASE_URL", url)
        .env("COVERPLAN_WORKERS", "1")
        .env("COVERPLAN_REPLICA", format!("bench-{k}"))
        .env("COVERPLAN_LOG", "warn")
        .stdout(Stdio::null())
        .spawn()?)
}

/// Plans per minute with `replicas` replicas, and how many plans each replica ran.
async fn throughput(admin: &str, exe: &std::path::Path, replicas: usize) -> anyhow::Result<(f64, Vec<usize>)> {
    let scratch = Scratch::new(admin).await?;
    let db = store::connect(&scratch.url).await?;
    queue(&db, PLANS).await?;
    let mut children = (0..replicas).map(|k| replica(exe, &scratch.url, k)).collect::<anyhow::Result<Vec<_>>>()?;
    let started = Instant::now();
    while plans::queued_count(&db).await? > 0 || plans::claims(&db).await?.iter().any(|c| c.ended_at.is_none()) {
        anyhow::ensure!(started.elapsed() < Duration::from_secs(600), "the replicas did not finish {PLANS} plans in 10 minutes");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    for child in &mut children {
        let _ = Command::new("kill").args(["-TERM", &child.id().to_string()]).status();
        let _ = child.wait();
    }
    let claims = plans::claims(&db).await?;
    let first = claims.iter().map(|c| c.claimed_at).fold(f64::INFINITY, f64::min);
    let last = claims.iter().filter_map(|c| c.ended_at).fold(f64::NEG_INFINITY, f64::max);
    let succeeded = claims.iter().filter(|c| c.outcome.as_deref() == Some("succeeded")).count();
    anyhow::ensure!(succeeded == PLANS, "{succeeded} of {PLANS} plans succeeded");
    let per_replica = (0..replicas).map(|k| claims.iter().filter(|c| c.replica == format!("bench-{k}")).count()).collect();
    db.close().await;
    scratch.drop().await?;
    Ok((PLANS as f64 / ((last - first) / 60.0), per_replica))
}

/// Milliseconds one claim takes (median, 95th percentile) with [`DEEP_QUEUE`] plans queued.
async fn claim_latency(url: &str) -> anyhow::Result<(f64, f64)> {
    let db = store::connect(url).await?;
    queue(&db, DEEP_QUEUE).await?;
    let mut ms = Vec::with_capacity(CLAIMS_TIMED);
    for _ in 0..CLAIMS_TIMED {
        let t = Instant::now();
        plans::claim_next(&db, "bench", 30.0).await?.context("a queued plan")?;
        ms.push(t.elapsed().as_secs_f64() * 1000.0);
    }
    db.close().await;
    ms.sort_by(f64::total_cmp);
    Ok((ms[ms.len() / 2], ms[ms.len() * 95 / 100]))
}

pub async fn run(admin: &str) -> anyhow::Result<String> {
    anyhow::ensure!(store::is_postgres(admin), "--queue takes a PostgreSQL admin URL (postgres://user@host:port/postgres)");
    let exe = std::env::current_exe()?;
    let mut out = format!(
        "`ADMIN_URL`: a PostgreSQL server's admin URL (`eval \"$(bash tests/postgres.sh start)\"` starts a throwaway one, fsync off, and sets `$COVERPLAN_TEST_POSTGRES` to it). {PLANS} plans of a 200 m × 150 m field at 20 m spacing, taken by `coverplan serve` replicas of one worker each on this machine, from the first claim to the last finish.\n\n| replicas | plans/min | plans per replica |\n|---:|---:|:---|\n"
    );
    for replicas in [1, 2, 4] {
        let (rate, per_replica) = throughput(admin, &exe, replicas).await?;
        let shares: Vec<String> = per_replica.iter().map(usize::to_string).collect();
        let _ = writeln!(out, "| {replicas} | {rate:.0} | {} |", shares.join(", "));
    }
    out.push_str(&format!("\nOne claim with {DEEP_QUEUE} plans queued ({CLAIMS_TIMED} claims).\n\n| database | median ms | p95 ms |\n|:---|---:|---:|\n"));
    let scratch = Scratch::new(admin).await?;
    let (median, p95) = claim_latency(&scratch.url).await?;
    scratch.drop().await?;
    let _ = writeln!(out, "| PostgreSQL | {median:.2} | {p95:.2} |");
    let sqlite = std::env::temp_dir().join(format!("coverplan-bench-{}.db", uuid::Uuid::new_v4().simple()));
    let (median, p95) = claim_latency(&format!("sqlite://{}", sqlite.display())).await?;
    for suffix in ["", "-wal", "-shm"] {
        let _ = std::fs::remove_file(format!("{}{suffix}", sqlite.display()));
    }
    let _ = writeln!(out, "| SQLite | {median:.2} | {p95:.2} |");
    Ok(out)
}
