//! The query KEDA's PostgreSQL scaler asks (deploy/kubernetes/keda.yaml) counts the plans queued
//! and running, on the test database: the replicas scale on what is waiting or being planned.

use std::time::Duration;

use coverplan::store::{self, Db};
use serde_json::json;

use crate::common::{self, TestApp};

/// The scaler's query, as the manifest writes it.
fn scaler_query() -> String {
    let manifest = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/deploy/kubernetes/keda.yaml")).unwrap();
    let line = manifest.lines().find_map(|l| l.trim().strip_prefix("query:")).expect("keda.yaml has a query");
    line.trim().trim_matches('"').to_owned()
}

async fn count(db: &Db, query: &str) -> i64 {
    match db {
        Db::Sqlite(pool) => sqlx::query_scalar(sqlx::AssertSqlSafe(query.to_owned())).fetch_one(pool).await.unwrap(),
        Db::Postgres(pool) => sqlx::query_scalar(sqlx::AssertSqlSafe(query.to_owned())).fetch_one(pool).await.unwrap(),
    }
}

#[tokio::test]
async fn the_autoscalers_query_counts_the_plans_queued_and_running() {
    // one worker that holds each plan a minute: one running, the others queued
    let app = TestApp::spawn_with(common::fresh_db_url().await, |c| {
        c.workers = 1;
        c.queue.start_delay = Duration::from_secs(60);
    })
    .await;
    let db = store::connect(&app.db_url).await.unwrap();
    let query = scaler_query();
    assert_eq!(count(&db, &query).await, 0);
    let mission = app.create_mission(&common::mission_body("real-fields/nl-parcel-b.json")).await;
    let mut plans = Vec::new();
    for _ in 0..3 {
        let (status, plan) = app.post(&format!("/api/v1/missions/{mission}/plans"), &json!({"vehicle": {"profile": "iris"}, "line_spacing_m": 20})).await;
        assert_eq!(status, 202, "{plan}");
        plans.push(plan["id"].as_str().unwrap().to_owned());
    }
    app.wait_plan(&plans[0], |s| s == "running").await;
    assert_eq!(count(&db, &query).await, 3);
    let r = app.client.delete(app.url(&format!("/api/v1/plans/{}", plans[2]))).send().await.unwrap();
    assert_eq!(r.status().as_u16(), 200);
    assert_eq!(count(&db, &query).await, 2, "a cancelled plan no longer counts");
    db.close().await;
    app.stop().await;
}
