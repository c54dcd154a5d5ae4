//! The worker pool: a panicking planner fails its plan, and the worker lives on.

use crate::common;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use coverplan::jobs::{self, JobQueue, QueueSettings, Runner};
use coverplan::planner::{FieldLimits, PlanError};
use coverplan::store::keys::OPEN_TENANT;
use coverplan::store::{self, missions, plans};
use serde_json::json;

/// A fresh database holding one mission, and the snapshot of it a plan is queued with.
async fn fresh_mission() -> (store::Db, missions::Mission, serde_json::Value) {
    let db = store::connect(&common::fresh_db_url().await).await.unwrap();
    let body = common::mission_body("real-fields/nl-parcel-b.json");
    let mission = missions::create(
        &db,
        OPEN_TENANT,
        &missions::NewMission { name: "m".into(), area: body["area"].clone(), no_fly_zones: None, obstacles: None, structures: None, home: None },
    )
    .await
    .unwrap();
    let snapshot = json!({"area": mission.area});
    (db, mission, snapshot)
}

/// A stored request this server cannot read (written by another version, or damaged) fails as
/// the server's fault, `internal`, not as the user's `infeasible`.
#[tokio::test]
async fn a_stored_request_that_cannot_be_read_fails_as_internal() {
    let (db, mission, snapshot) = fresh_mission().await;
    let runner: Runner = Arc::new(|job, request, progress, stop| jobs::plan_job(job, request, &FieldLimits::default(), progress, stop));
    let (queue, handles) = JobQueue::start(db.clone(), 1, runner, QueueSettings::default());
    let damaged =
        plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": "twenty"}), &snapshot), i64::MAX).await.unwrap().unwrap();
    queue.notify();
    let mut done = None;
    for _ in 0..600 {
        let p = plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &damaged.id).await.unwrap().unwrap();
        if p.status.is_final() {
            done = Some(p);
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let done = done.expect("the job ended");
    assert_eq!((done.status, done.error_code.as_deref()), (plans::PlanStatus::Failed, Some("internal")), "{:?}", done.error);
    queue.shutdown(handles, Duration::from_secs(1)).await;
}

#[tokio::test]
async fn a_panicking_job_fails_with_a_message_and_the_worker_goes_on() {
    let (db, mission, snapshot) = fresh_mission().await;
    // spacing 13 makes this runner panic; anything else plans for real
    let runner: Runner = Arc::new(|job, request, progress, stop| {
        if job.params["line_spacing_m"] == json!(13.0) {
            panic!("deliberate failure for the test");
        }
        jobs::plan_job(job, request, &FieldLimits::default(), progress, stop)
    });
    let (queue, handles) = JobQueue::start(db.clone(), 1, runner, QueueSettings::default());
    let bad =
        plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 13.0}), &snapshot), i64::MAX).await.unwrap().unwrap();
    let good =
        plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 20.0}), &snapshot), i64::MAX).await.unwrap().unwrap();
    queue.notify();
    let mut finished = None;
    for _ in 0..600 {
        let g = plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &good.id).await.unwrap().unwrap();
        if g.status.is_final() {
            finished = Some(g);
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let bad = plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &bad.id).await.unwrap().unwrap();
    assert_eq!(bad.status, plans::PlanStatus::Failed);
    assert!(bad.error.unwrap().contains("deliberate failure"));
    assert!(bad.stats.is_none());
    let good = finished.expect("the next job ran on the same worker");
    assert_eq!(good.status, plans::PlanStatus::Succeeded);
    assert_eq!(queue.workers_alive(), 1);
    queue.shutdown(handles, Duration::from_secs(1)).await;
}

/// Plans created within the same millisecond (their `created_at` ties) are still claimed
/// first in, first out.
#[tokio::test]
async fn queued_plans_are_claimed_in_the_order_they_were_created() {
    let (db, mission, snapshot) = fresh_mission().await;
    let mut created = Vec::new();
    for k in 0..40 {
        created.push(
            plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 20.0 + k as f64}), &snapshot), i64::MAX)
                .await
                .unwrap()
                .unwrap()
                .id,
        );
    }
    let mut claimed = Vec::new();
    while let Some(job) = plans::claim_next(&db, "test-replica", 30.0).await.unwrap() {
        claimed.push(job.id);
    }
    assert_eq!(claimed, created);
}

/// Polls a plan until it is final; returns it and when it became so.
async fn wait_final(db: &store::Db, id: &str) -> (plans::Plan, Instant) {
    for _ in 0..1000 {
        let p = plans::get(db, OPEN_TENANT, plans::JobKind::Plan, id).await.unwrap().unwrap();
        if p.status.is_final() {
            return (p, Instant::now());
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    panic!("plan {id} did not finish");
}

/// A planner that runs until told to stop, and one that never looks: both plans fail with
/// `time_limit` within a second of the limit, and the single worker then plans the next job.
#[tokio::test]
async fn plans_past_their_time_limit_fail_and_the_worker_takes_the_next_job() {
    let (db, mission, snapshot) = fresh_mission().await;
    let stopped_when_asked = Arc::new(AtomicBool::new(false));
    let runner: Runner = {
        let stopped_when_asked = stopped_when_asked.clone();
        Arc::new(move |job, request, progress, stop| match job.params["line_spacing_m"].as_f64() {
            Some(1.0) => {
                while !stop.requested() {
                    std::thread::sleep(Duration::from_millis(5));
                }
                stopped_when_asked.store(true, Ordering::SeqCst);
                Err(PlanError::Cancelled)
            }
            Some(2.0) => {
                std::thread::sleep(Duration::from_secs(6));
                Err(PlanError::Cancelled)
            }
            _ => jobs::plan_job(job, request, &FieldLimits::default(), progress, stop),
        })
    };
    let limit = Duration::from_secs(1);
    let (queue, handles) = JobQueue::start(db.clone(), 1, runner, QueueSettings { time_limit: limit, ..QueueSettings::default() });
    let polite =
        plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 1.0}), &snapshot), i64::MAX).await.unwrap().unwrap();
    let deaf = plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 2.0, "time_limit_s": 0.5}), &snapshot), i64::MAX)
        .await
        .unwrap()
        .unwrap();
    let good =
        plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 20.0}), &snapshot), i64::MAX).await.unwrap().unwrap();
    let started = Instant::now();
    queue.notify();
    let (polite, polite_done) = wait_final(&db, &polite.id).await;
    assert_eq!((polite.status, polite.error_code.as_deref()), (plans::PlanStatus::Failed, Some("time_limit")), "{polite:?}");
    assert!(polite_done - started < limit + Duration::from_secs(1), "stopped {:?} after the start", polite_done - started);
    assert!(stopped_when_asked.load(Ordering::SeqCst), "the planner saw the stop");
    // the plan's own, shorter limit; the runner ignores it and is left behind
    let (deaf, deaf_done) = wait_final(&db, &deaf.id).await;
    assert_eq!((deaf.status, deaf.error_code.as_deref()), (plans::PlanStatus::Failed, Some("time_limit")), "{deaf:?}");
    assert!(deaf_done - polite_done < Duration::from_millis(1500), "given up {:?} after it started", deaf_done - polite_done);
    assert!(deaf.error.unwrap().contains("0.5 s"));
    let (good, _) = wait_final(&db, &good.id).await;
    assert_eq!(good.status, plans::PlanStatus::Succeeded, "{good:?}");
    queue.shutdown(handles, Duration::from_secs(1)).await;
}

/// Cancelling a running fixed-wing plan around 14 no-fly zones, routed in every sweep direction
/// (18 s of work on a 2-core machine), frees its worker at once: the plan queued behind it
/// starts within moments.
#[tokio::test]
async fn cancelling_a_running_plan_frees_its_worker_at_once() {
    let db = store::connect(&common::fresh_db_url().await).await.unwrap();
    let field = common::fixture("random-fields/h14_00.json");
    let new =
        missions::NewMission { name: "h14".into(), area: field["area"].clone(), no_fly_zones: Some(field["no_fly_zones"].clone()), obstacles: None, structures: None, home: None };
    let mission = missions::create(&db, OPEN_TENANT, &new).await.unwrap();
    let snapshot = json!({"area": mission.area, "no_fly_zones": mission.no_fly_zones});
    let runner: Runner = Arc::new(|job, request, progress, stop| jobs::plan_job(job, request, &FieldLimits::default(), progress, stop));
    let (queue, handles) = JobQueue::start(db.clone(), 1, runner, QueueSettings::default());
    let fixed_wing = json!({"planner": "line_gtsp", "line_spacing_m": 20, "sweep_direction": "optimal", "vehicle": {"kind": "fixed_wing", "turn_radius_m": 10}});
    let long = plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &fixed_wing, &snapshot), i64::MAX).await.unwrap().unwrap();
    let next = plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 40}), &snapshot), i64::MAX).await.unwrap().unwrap();
    queue.notify();
    tokio::time::sleep(Duration::from_secs(2)).await;
    assert_eq!(plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &long.id).await.unwrap().unwrap().status, plans::PlanStatus::Running);
    plans::cancel(&db, OPEN_TENANT, &long.id).await.unwrap();
    queue.cancel(&long.id);
    let cancelled = Instant::now();
    let freed = loop {
        if plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &next.id).await.unwrap().unwrap().status != plans::PlanStatus::Queued {
            break cancelled.elapsed();
        }
        assert!(cancelled.elapsed() < Duration::from_secs(10), "the worker is still busy with the cancelled plan");
        tokio::time::sleep(Duration::from_millis(5)).await;
    };
    assert!(freed < Duration::from_secs(1), "the next plan started {freed:?} after the cancellation");
    let (next, _) = wait_final(&db, &next.id).await;
    assert_eq!(next.status, plans::PlanStatus::Succeeded);
    assert_eq!(plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &long.id).await.unwrap().unwrap().status, plans::PlanStatus::Cancelled);
    queue.shutdown(handles, Duration::from_secs(1)).await;
}

/// A claim reads the queue's index in the claim's own order, however deep the queue: no sort of
/// the queued plans (while it sorted them, one claim took 16 ms with 10 000 plans queued on
/// PostgreSQL and 3.5 ms on SQLite, against 0.7 and 0.2 ms; `coverplan bench --queue`).
#[tokio::test]
async fn a_claim_reads_the_queue_in_its_order_without_sorting() {
    let (db, mission, snapshot) = fresh_mission().await;
    for _ in 0..2000 {
        plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({}), &snapshot), i64::MAX).await.unwrap().unwrap();
    }
    let plan: Vec<String> = match &db {
        store::Db::Sqlite(pool) => {
            let rows: Vec<(i64, i64, i64, String)> =
                sqlx::query_as(sqlx::AssertSqlSafe(format!("EXPLAIN QUERY PLAN {}", plans::CLAIM_NEXT.sqlite))).bind("r").bind(30.0).fetch_all(pool).await.unwrap();
            rows.into_iter().map(|r| r.3).collect()
        }
        store::Db::Postgres(pool) => {
            sqlx::query("ANALYZE plans").execute(pool).await.unwrap();
            let rows: Vec<(String,)> = sqlx::query_as(sqlx::AssertSqlSafe(format!("EXPLAIN {}", plans::CLAIM_NEXT.postgres))).bind("r").bind(30.0).fetch_all(pool).await.unwrap();
            rows.into_iter().map(|r| r.0).collect()
        }
    };
    assert!(plan.iter().any(|line| line.contains("plans_queue")), "the claim does not read the queue's index: {plan:#?}");
    assert!(!plan.iter().any(|line| line.contains("TEMP B-TREE") || line.trim_start_matches([' ', '-', '>']).starts_with("Sort")), "the claim sorts the queue: {plan:#?}");
}
