//! The worker pool: a panicking planner fails its plan, and the worker lives on.

use crate::common;

use std::sync::Arc;
use std::time::Duration;

use coverplan::jobs::{self, JobQueue, Runner};
use coverplan::planner::FieldLimits;
use coverplan::store::{self, missions, plans};
use serde_json::json;

/// A fresh database holding one mission, and the snapshot of it a plan is queued with.
async fn fresh_mission() -> (store::Db, missions::Mission, serde_json::Value) {
    let db = store::connect(&format!("sqlite://{}", common::fresh_db_path().display())).await.unwrap();
    let body = common::mission_body("real-fields/nl-parcel-b.json");
    let mission = missions::create(&db, &missions::NewMission { name: "m".into(), area: body["area"].clone(), no_fly_zones: None, obstacles: None, home: None }).await.unwrap();
    let snapshot = json!({"area": mission.area});
    (db, mission, snapshot)
}

#[tokio::test]
async fn a_panicking_job_fails_with_a_message_and_the_worker_goes_on() {
    let (db, mission, snapshot) = fresh_mission().await;
    // spacing 13 makes this runner panic; anything else plans for real
    let runner: Runner = Arc::new(|job, progress| {
        if job.params["line_spacing_m"] == json!(13.0) {
            panic!("deliberate failure for the test");
        }
        jobs::plan_job(job, &FieldLimits::default(), progress)
    });
    let (queue, handles) = JobQueue::start(db.clone(), 1, runner, Duration::ZERO);
    let bad = plans::create(&db, &mission.id, &json!({"line_spacing_m": 13.0}), &snapshot).await.unwrap();
    let good = plans::create(&db, &mission.id, &json!({"line_spacing_m": 20.0}), &snapshot).await.unwrap();
    queue.notify();
    let mut finished = None;
    for _ in 0..600 {
        let g = plans::get(&db, &good.id).await.unwrap().unwrap();
        if g.status.is_final() {
            finished = Some(g);
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let bad = plans::get(&db, &bad.id).await.unwrap().unwrap();
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
        created.push(plans::create(&db, &mission.id, &json!({"line_spacing_m": 20.0 + k as f64}), &snapshot).await.unwrap().id);
    }
    let mut claimed = Vec::new();
    while let Some(job) = plans::claim_next(&db).await.unwrap() {
        claimed.push(job.id);
    }
    assert_eq!(claimed, created);
}
