//! The shared job queue: leases that a dead replica's plans outlive, a cap on attempts,
//! cancellation that reaches the replica running a plan, and an upgrade of a database made by
//! the previous release. These run on both backends (`tests/run_all.sh` runs them a second
//! time on PostgreSQL); the test with several processes is in `process.rs`.

use std::time::{Duration, Instant};

use coverplan::store::keys::OPEN_TENANT;
use coverplan::store::plans::{self, Claim, PlanStatus};
use coverplan::store::{self, keys, missions};
use serde_json::json;

use crate::common::{self, TestApp, mission_body};

async fn db_with_a_plan() -> (store::Db, String) {
    let db = store::connect(&common::fresh_db_url().await).await.unwrap();
    let body = mission_body("real-fields/nl-parcel-b.json");
    let mission = missions::create(
        &db,
        OPEN_TENANT,
        &missions::NewMission { name: "m".into(), area: body["area"].clone(), no_fly_zones: None, obstacles: None, structures: None, home: None },
    )
    .await
    .unwrap();
    let plan = plans::create(&db, OPEN_TENANT, &plans::NewJob::new(plans::JobKind::Plan, &mission.id, &json!({"line_spacing_m": 20}), &json!({"area": mission.area})), 100)
        .await
        .unwrap()
        .unwrap();
    (db, plan.id)
}

/// A replica that stops renewing its lease loses the plan to the next replica once the lease
/// has run out, and can write nothing for it afterwards (not even when it wakes up).
#[tokio::test]
async fn a_plan_whose_replica_went_silent_is_taken_again_and_its_old_holder_writes_nothing() {
    let (db, id) = db_with_a_plan().await;
    let first = plans::claim_next(&db, "a", 0.4).await.unwrap().expect("queued");
    assert_eq!(first.id, id);
    assert!(plans::claim_next(&db, "b", 0.4).await.unwrap().is_none(), "one plan, one claim");
    assert_eq!(plans::requeue_abandoned(&db, false).await.unwrap(), (0, 0), "the lease still holds");
    assert!(plans::heartbeat(&db, Claim { plan: &id, replica: "a" }, 0.5, 0.4).await.unwrap());
    tokio::time::sleep(Duration::from_millis(700)).await;
    assert_eq!(plans::requeue_abandoned(&db, false).await.unwrap(), (1, 0));
    let again = plans::claim_next(&db, "b", 30.0).await.unwrap().expect("requeued");
    assert_eq!(again.id, id);
    // the old holder comes back: its heartbeat is refused and its outcome is not stored
    assert!(!plans::heartbeat(&db, Claim { plan: &id, replica: "a" }, 0.9, 30.0).await.unwrap());
    plans::fail(&db, Claim { plan: &id, replica: "a" }, "internal", "stale").await.unwrap();
    assert_eq!(plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &id).await.unwrap().unwrap().status, PlanStatus::Running);
    plans::succeed(&db, Claim { plan: &id, replica: "b" }, &json!({"length_m": 1.0}), "{}").await.unwrap();
    assert_eq!(plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &id).await.unwrap().unwrap().status, PlanStatus::Succeeded);
    let claims = plans::claims(&db).await.unwrap();
    let summary: Vec<(&str, Option<&str>)> = claims.iter().map(|c| (c.replica.as_str(), c.outcome.as_deref())).collect();
    assert_eq!(summary, [("a", Some("abandoned")), ("b", Some("succeeded"))]);
    assert!(claims[1].claimed_at >= claims[0].ended_at.unwrap(), "{claims:?}");
}

/// A plan whose replicas keep dying is not run forever: after three claims it fails as
/// `interrupted`.
#[tokio::test]
async fn a_plan_that_keeps_losing_its_replica_fails_after_three_attempts() {
    let (db, id) = db_with_a_plan().await;
    for attempt in 1..=plans::MAX_ATTEMPTS {
        assert!(plans::claim_next(&db, &format!("r{attempt}"), 0.0).await.unwrap().is_some(), "attempt {attempt}");
        tokio::time::sleep(Duration::from_millis(20)).await;
        let (requeued, failed) = plans::requeue_abandoned(&db, false).await.unwrap();
        assert_eq!((requeued, failed), if attempt < plans::MAX_ATTEMPTS { (1, 0) } else { (0, 1) }, "attempt {attempt}");
    }
    let plan = plans::get(&db, OPEN_TENANT, plans::JobKind::Plan, &id).await.unwrap().unwrap();
    assert_eq!((plan.status, plan.error_code.as_deref()), (PlanStatus::Failed, Some("interrupted")), "{plan:?}");
    assert!(plans::claim_next(&db, "r4", 30.0).await.unwrap().is_none());
}

/// Two servers on one database: a plan cancelled through one stops on the other, which is
/// running it, within a heartbeat or two.
#[tokio::test]
async fn cancelling_on_one_replica_stops_the_plan_running_on_another() {
    let url = common::fresh_db_url().await;
    let hold = |name: &'static str| {
        move |c: &mut coverplan::config::Config| {
            c.queue.start_delay = Duration::from_secs(60);
            c.queue.replica = Some(name.into());
            c.workers = 1;
        }
    };
    let a = TestApp::spawn_with(url.clone(), hold("a")).await;
    let b = TestApp::spawn_with(url.clone(), hold("b")).await;
    let mission = a.create_mission(&mission_body("real-fields/nl-parcel-b.json")).await;
    let (_, plan) = a.post(&format!("/api/v1/missions/{mission}/plans"), &json!({"line_spacing_m": 20})).await;
    let id = plan["id"].as_str().unwrap().to_owned();
    a.wait_plan(&id, |s| s == "running").await;
    let db = store::connect(&url).await.unwrap();
    let runner = plans::claims(&db).await.unwrap().into_iter().find(|c| c.plan_id == id).expect("claimed").replica;
    let other = if runner == "a" { &b } else { &a };
    let asked = Instant::now();
    let r = other.client.delete(other.url(&format!("/api/v1/plans/{id}"))).send().await.unwrap();
    assert!(r.status().is_success(), "{}", r.status());
    let ended = loop {
        let claim = plans::claims(&db).await.unwrap().into_iter().find(|c| c.plan_id == id).unwrap();
        if claim.outcome.is_some() {
            break claim;
        }
        assert!(asked.elapsed() < Duration::from_secs(5), "replica {runner} still runs the cancelled plan");
        tokio::time::sleep(Duration::from_millis(20)).await;
    };
    assert_eq!(ended.outcome.as_deref(), Some("cancelled"));
    assert!(asked.elapsed() < Duration::from_secs(2), "stopped {:?} after the cancel", asked.elapsed());
    a.stop().await;
    b.stop().await;
}

/// A SQLite database made by the previous release (migrations 0001–0006), with a mission, a
/// finished plan, a plan left running, a patrol and a key, opens with this release: the new migrations
/// apply, nothing is lost, and the interrupted plan is queued again.
#[tokio::test]
async fn a_database_of_the_previous_release_upgrades_cleanly() {
    let old = tempdir_with_migrations("sqlite", 6);
    let path = common::fresh_db_path();
    let url = format!("sqlite://{}", path.display());
    {
        use sqlx::sqlite::SqliteConnectOptions;
        let options: SqliteConnectOptions = url.parse::<SqliteConnectOptions>().unwrap().create_if_missing(true);
        let pool = sqlx::SqlitePool::connect_with(options).await.unwrap();
        sqlx::migrate::Migrator::new(old.as_path()).await.unwrap().run(&pool).await.unwrap();
        let area = mission_body("real-fields/nl-parcel-b.json")["area"].to_string();
        sqlx::query(
            "INSERT INTO missions (id, tenant, name, area, created_at, updated_at) VALUES ('m1', 'farm', 'old field', ?, '2026-01-01T00:00:00.000Z', '2026-01-01T00:00:00.000Z')",
        )
        .bind(&area)
        .execute(&pool)
        .await
        .unwrap();
        for (id, status) in [("p-done", "succeeded"), ("p-running", "running")] {
            sqlx::query("INSERT INTO plans (id, tenant, mission_id, params, mission, status, attempts, stats, created_at) VALUES (?, 'farm', 'm1', '{\"line_spacing_m\": 20}', ?, ?, 1, '{\"length_m\": 5.0}', '2026-01-01T00:00:01.000Z')")
                .bind(id)
                .bind(format!("{{\"area\": {area}}}"))
                .bind(status)
                .execute(&pool)
                .await
                .unwrap();
        }
        // a patrol, told apart then by a `kind` member in its parameters
        sqlx::query("INSERT INTO plans (id, tenant, mission_id, params, mission, status, created_at) VALUES ('p-patrol', 'farm', 'm1', '{\"kind\": \"patrol\", \"uavs\": 2}', ?, 'queued', '2026-01-01T00:00:02.000Z')")
            .bind(format!("{{\"area\": {area}}}"))
            .execute(&pool)
            .await
            .unwrap();
        pool.close().await;
    }
    let db = store::connect(&url).await.unwrap();
    let patrol = plans::get(&db, "farm", plans::JobKind::Patrol, "p-patrol").await.unwrap().expect("the patrol, by its kind column");
    assert_eq!(patrol.params, json!({"uavs": 2}), "the kind moved out of the parameters");
    assert!(plans::get(&db, "farm", plans::JobKind::Plan, "p-patrol").await.unwrap().is_none(), "a patrol is no plan");
    assert!(plans::get(&db, "farm", plans::JobKind::Patrol, "p-done").await.unwrap().is_none(), "a plan is no patrol");
    assert!(plans::cancel(&db, "farm", "p-patrol").await.unwrap().is_some());
    assert_eq!(missions::get(&db, "farm", "m1").await.unwrap().unwrap().name, "old field");
    let done = plans::get(&db, "farm", plans::JobKind::Plan, "p-done").await.unwrap().unwrap();
    assert_eq!((done.status, done.stats), (PlanStatus::Succeeded, Some(json!({"length_m": 5.0}))));
    assert_eq!(plans::requeue_abandoned(&db, true).await.unwrap(), (1, 0));
    let job = plans::claim_next(&db, "new", 30.0).await.unwrap().expect("the interrupted plan is queued again");
    assert_eq!(job.id, "p-running");
    assert!(!keys::required(&db).await.unwrap());
}

/// A PostgreSQL database made before patrols had a column of their own (migrations 0001–0002),
/// with a plan and a patrol told apart by a `kind` member of its parameters, opens with this
/// release: the patrol is found by its kind, its parameters lose the member, the plan stays a plan.
#[tokio::test]
async fn a_postgres_database_with_patrols_in_parameters_upgrades_cleanly() {
    if common::test_postgres().is_none() {
        eprintln!("SQLite pass: the PostgreSQL pass runs this test");
        return;
    }
    let old = tempdir_with_migrations("postgres", 2);
    let url = common::fresh_db_url().await;
    {
        let pool = sqlx::PgPool::connect(&url).await.unwrap();
        sqlx::migrate::Migrator::new(old.as_path()).await.unwrap().run(&pool).await.unwrap();
        let area = mission_body("real-fields/nl-parcel-b.json")["area"].clone();
        sqlx::query(
            "INSERT INTO missions (id, tenant, name, area, created_at, updated_at) VALUES ('m1', 'farm', 'old field', $1, '2026-01-01T00:00:00.000Z', '2026-01-01T00:00:00.000Z')",
        )
        .bind(&area)
        .execute(&pool)
        .await
        .unwrap();
        for (id, params) in [("p-plan", json!({"line_spacing_m": 20})), ("p-patrol", json!({"kind": "patrol", "uavs": 2}))] {
            sqlx::query("INSERT INTO plans (id, tenant, mission_id, params, mission, status, created_at) VALUES ($1, 'farm', 'm1', $2, $3, 'queued', '2026-01-01T00:00:01.000Z')")
                .bind(id)
                .bind(params)
                .bind(json!({"area": area}))
                .execute(&pool)
                .await
                .unwrap();
        }
        pool.close().await;
    }
    let db = store::connect(&url).await.unwrap();
    let patrol = plans::get(&db, "farm", plans::JobKind::Patrol, "p-patrol").await.unwrap().expect("the patrol, by its kind column");
    assert_eq!(patrol.params, json!({"uavs": 2}), "the kind moved out of the parameters");
    assert!(plans::get(&db, "farm", plans::JobKind::Plan, "p-patrol").await.unwrap().is_none(), "a patrol is no plan");
    let plan = plans::get(&db, "farm", plans::JobKind::Plan, "p-plan").await.unwrap().expect("the plan stays a plan");
    assert_eq!(plan.params, json!({"line_spacing_m": 20}));
    assert!(plans::get(&db, "farm", plans::JobKind::Patrol, "p-plan").await.unwrap().is_none(), "a plan is no patrol");
}

/// A folder holding the first `n` migrations of `backend`, as the release that had them shipped.
fn tempdir_with_migrations(backend: &str, n: usize) -> std::path::PathBuf {
    let dir = common::fresh_db_path().with_file_name("migrations");
    std::fs::create_dir_all(&dir).unwrap();
    let source = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("migrations").join(backend);
    let mut files: Vec<_> = std::fs::read_dir(&source).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    assert!(files.len() > n, "this release adds migrations after the first {n}");
    for f in &files[..n] {
        std::fs::copy(f, dir.join(f.file_name().unwrap())).unwrap();
    }
    dir
}

/// An outcome write that fails in a way that may pass is tried again; one that cannot pass is
/// not.
#[tokio::test]
async fn outcome_writes_are_retried_only_on_failures_that_may_pass() {
    let calls = std::sync::atomic::AtomicUsize::new(0);
    let flaky = store::retrying(|| async {
        let n = calls.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        if n < 2 { Err(sqlx::Error::PoolTimedOut) } else { Ok(n) }
    })
    .await;
    assert_eq!(flaky.unwrap(), 2);
    calls.store(0, std::sync::atomic::Ordering::SeqCst);
    let broken: Result<(), _> = store::retrying(|| async {
        calls.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        Err(sqlx::Error::RowNotFound)
    })
    .await;
    assert!(broken.is_err());
    assert_eq!(calls.load(std::sync::atomic::Ordering::SeqCst), 1);
}
