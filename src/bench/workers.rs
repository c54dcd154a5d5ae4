//! `coverplan bench --workers 1,2,4,8,16`: one server's worker pool on SQLite. For each count, a
//! batch of plans is queued in a fresh database (a multirotor `boustrophedon` plan of every
//! generated field `--repeats` times at different spacings, and a fixed-wing `line_gtsp` plan of
//! every field with four holes or more), then one `coverplan serve` with that many workers plans
//! them: plans per minute, the speed-up over the first count, the cores the server kept busy (its
//! CPU seconds over the wall seconds) and its peak memory.

use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::Context;
use serde_json::{Value, json};

use super::peak_mb_of;
use crate::store::keys::OPEN_TENANT;
use crate::store::{self, missions, plans};

/// The batch: (mission area and zones, parameters).
fn batch(dir: &Path, repeats: usize) -> anyhow::Result<Vec<(Value, Value)>> {
    let mut fields: Vec<(String, Value)> = Vec::new();
    for entry in std::fs::read_dir(dir).with_context(|| format!("reading {}", dir.display()))? {
        let path = entry?.path();
        let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default().to_owned();
        if name.starts_with('h') && path.extension().is_some_and(|e| e == "json") {
            fields.push((name, serde_json::from_str(&std::fs::read_to_string(&path)?)?));
        }
    }
    fields.sort_by(|a, b| a.0.cmp(&b.0));
    let multirotor = |spacing: f64| json!({"planner": "boustrophedon", "line_spacing_m": spacing, "vehicle": {"kind": "multirotor", "cruise_speed_mps": 8, "battery_wh": 100000}});
    let fixed_wing = json!({"planner": "line_gtsp", "line_spacing_m": 20, "vehicle": {"kind": "fixed_wing", "cruise_speed_mps": 15, "turn_radius_m": 10, "battery_wh": 100000}});
    let mut jobs = Vec::new();
    for k in 0..repeats {
        for (_, f) in &fields {
            jobs.push((f.clone(), multirotor(8.0 + k as f64)));
        }
    }
    for (name, f) in &fields {
        if name.get(1..3).and_then(|h| h.parse::<u32>().ok()).is_some_and(|holes| holes >= 4) {
            jobs.push((f.clone(), fixed_wing.clone()));
        }
    }
    Ok(jobs)
}

/// Seconds of CPU a process has used (user and system), from `/proc`.
fn cpu_seconds(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

struct Row {
    workers: usize,
    plans: usize,
    seconds: f64,
    cores_busy: f64,
    peak_mb: f64,
}

async fn row(exe: &Path, jobs: &[(Value, Value)], workers: usize) -> anyhow::Result<Row> {
    let dir = std::env::temp_dir().join(format!("coverplan-bench-workers-{}-{workers}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let url = format!("sqlite://{}?mode=rwc", dir.join("bench.db").display());
    let db = store::connect(&url).await?;
    for (field, params) in jobs {
        let new = missions::NewMission {
            name: "bench".into(),
            area: field["area"].clone(),
            no_fly_zones: field.get("no_fly_zones").cloned().filter(|z| !z.is_null()),
            obstacles: None,
            structures: None,
            home: None,
        };
        let mission = missions::create(&db, OPEN_TENANT, &new).await?;
        let snapshot = json!({"area": new.area, "no_fly_zones": new.no_fly_zones});
        plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, params, &snapshot), i64::MAX).await?;
    }
    let mut server = Command::new(exe)
        .arg("serve")
        .env("COVERPLAN_ADDR", "127.0.0.1:0")
        .env("COVERPLAN_DATABASE_URL", &url)
        .env("COVERPLAN_WORKERS", workers.to_string())
        .env("COVERPLAN_JOB_TIMEOUT_S", "600")
        .env("COVERPLAN_LOG", "warn")
        .stdout(Stdio::null())
        .spawn()?;
    let started = Instant::now();
    while plans::queued_count(&db).await? > 0 || plans::claims(&db).await?.iter().any(|c| c.ended_at.is_none()) {
        anyhow::ensure!(started.elapsed() < Duration::from_secs(1_800), "{workers} workers did not finish {} plans in 30 minutes", jobs.len());
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let seconds = started.elapsed().as_secs_f64();
    let (cpu, peak) = (cpu_seconds(server.id()).unwrap_or(f64::NAN), peak_mb_of(&server.id().to_string()).unwrap_or(f64::NAN));
    let _ = Command::new("kill").args(["-TERM", &server.id().to_string()]).status();
    let _ = server.wait();
    let plans = plans::claims(&db).await?.iter().filter(|c| c.outcome.as_deref() == Some("succeeded")).count();
    db.close().await;
    let _ = std::fs::remove_dir_all(&dir);
    Ok(Row { workers, plans, seconds, cores_busy: cpu / seconds, peak_mb: peak })
}

pub async fn run(dir: &Path, repeats: usize, counts: &[usize]) -> anyhow::Result<String> {
    let exe = std::env::current_exe()?;
    let jobs = batch(dir, repeats)?;
    let mut out = String::new();
    writeln!(
        out,
        "{} plans (a multirotor boustrophedon plan of each of {}'s fields {repeats} times, a fixed-wing line_gtsp plan of each with 4 holes or more), \
         queued in a fresh SQLite database, then planned by one `coverplan serve`; {} cores here.\n",
        jobs.len(),
        dir.display(),
        std::thread::available_parallelism().map_or(0, |n| n.get())
    )?;
    writeln!(out, "| workers | plans | s | plans/min | speed-up | cores busy | peak MB |")?;
    writeln!(out, "|---:|---:|---:|---:|---:|---:|---:|")?;
    let mut first = None;
    for &workers in counts {
        let r = row(&exe, &jobs, workers).await?;
        let rate = r.plans as f64 / r.seconds * 60.0;
        let base = *first.get_or_insert(rate);
        writeln!(out, "| {} | {} | {:.1} | {rate:.0} | {:.2} | {:.2} | {:.0} |", r.workers, r.plans, r.seconds, rate / base, r.cores_busy, r.peak_mb)?;
    }
    Ok(out)
}
