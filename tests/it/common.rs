//! Starts the real application on port 0 with a fresh database: a new SQLite file, or with
//! `COVERPLAN_TEST_POSTGRES` (a PostgreSQL server's admin URL, as `tests/run_all.sh` sets it for
//! its second pass) a new database on that server.
#![allow(dead_code)]

use std::path::PathBuf;
use std::time::Duration;

use coverplan::config::Config;
use serde_json::{Value, json};
use tokio::sync::oneshot;

pub struct TestApp {
    pub base: String,
    pub client: reqwest::Client,
    pub db_url: String,
    stop: Option<oneshot::Sender<()>>,
    handle: Option<tokio::task::JoinHandle<()>>,
}

pub fn fresh_db_path() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("coverplan-test-{}", uuid::Uuid::new_v4()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join("test.db")
}

/// The admin URL of the PostgreSQL server the tests run on, when they do.
pub fn test_postgres() -> Option<String> {
    std::env::var("COVERPLAN_TEST_POSTGRES").ok().filter(|u| !u.is_empty())
}

/// A URL of a new, empty database of the backend under test.
pub async fn fresh_db_url() -> String {
    match test_postgres() {
        Some(admin) => {
            use sqlx::Connection;
            let name = format!("coverplan_test_{}", uuid::Uuid::new_v4().simple());
            let mut conn = sqlx::PgConnection::connect(&admin).await.unwrap_or_else(|e| panic!("{admin}: {e}"));
            sqlx::query(sqlx::AssertSqlSafe(format!("CREATE DATABASE {name}"))).execute(&mut conn).await.unwrap();
            conn.close().await.unwrap();
            let (server, _) = admin.rsplit_once('/').expect("the admin URL names a database");
            format!("{server}/{name}")
        }
        None => format!("sqlite://{}", fresh_db_path().display()),
    }
}

pub fn fixture(path: &str) -> Value {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(path);
    serde_json::from_str(&std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).unwrap()
}

/// A mission body from a fixture file (drops its `meta`).
pub fn mission_body(path: &str) -> Value {
    let f = fixture(path);
    json!({"name": f["name"], "area": f["area"], "no_fly_zones": f.get("no_fly_zones").cloned().unwrap_or(Value::Null)})
}

impl TestApp {
    pub async fn spawn() -> TestApp {
        Self::spawn_with(fresh_db_url().await, |_| {}).await
    }

    pub async fn spawn_with(db_url: String, adjust: impl FnOnce(&mut Config)) -> TestApp {
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let addr = listener.local_addr().unwrap();
        let mut config = Config::new(addr, db_url.clone());
        config.workers = 2;
        config.shutdown_grace = Duration::from_secs(5);
        adjust(&mut config);
        let (stop, stopped) = oneshot::channel::<()>();
        let (ready_tx, ready_rx) = oneshot::channel();
        let handle = tokio::spawn(async move {
            let shutdown = async move {
                let _ = stopped.await;
            };
            let result = coverplan::server::serve(listener, config, shutdown);
            let _ = ready_tx.send(());
            let (_, served) = result.await.expect("server starts");
            served.expect("server runs");
        });
        let _ = ready_rx.await;
        let app = TestApp { base: format!("http://{addr}"), client: reqwest::Client::new(), db_url, stop: Some(stop), handle: Some(handle) };
        app.wait_ready().await;
        app
    }

    pub async fn wait_ready(&self) {
        for _ in 0..200 {
            if let Ok(r) = self.client.get(format!("{}/readyz", self.base)).send().await
                && r.status() == 200
            {
                return;
            }
            tokio::time::sleep(Duration::from_millis(25)).await;
        }
        panic!("the server did not become ready");
    }

    pub async fn stop(mut self) {
        if let Some(s) = self.stop.take() {
            let _ = s.send(());
        }
        if let Some(h) = self.handle.take() {
            h.await.unwrap();
        }
    }

    pub fn url(&self, path: &str) -> String {
        format!("{}{}", self.base, path)
    }

    pub async fn post(&self, path: &str, body: &Value) -> (u16, Value) {
        let r = self.client.post(self.url(path)).json(body).send().await.unwrap();
        let status = r.status().as_u16();
        (status, r.json().await.unwrap_or(Value::Null))
    }

    pub async fn get(&self, path: &str) -> (u16, Value) {
        let r = self.client.get(self.url(path)).send().await.unwrap();
        let status = r.status().as_u16();
        (status, r.json().await.unwrap_or(Value::Null))
    }

    pub async fn create_mission(&self, body: &Value) -> String {
        let (status, m) = self.post("/api/v1/missions", body).await;
        assert_eq!(status, 201, "{m}");
        m["id"].as_str().unwrap().to_owned()
    }

    /// Polls a plan until `done` says so (or 120 s pass).
    pub async fn wait_plan(&self, id: &str, done: impl Fn(&str) -> bool) -> Value {
        for _ in 0..2400 {
            let (_, p) = self.get(&format!("/api/v1/plans/{id}")).await;
            if done(p["status"].as_str().unwrap_or_default()) {
                return p;
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
        panic!("plan {id} did not reach the expected status");
    }

    pub async fn wait_finished(&self, id: &str) -> Value {
        self.wait_plan(id, |s| matches!(s, "succeeded" | "failed" | "cancelled")).await
    }
}
