//! What operators watch: `/metrics` for Prometheus, and JSON logs whose job lines name the plan
//! and the tenant.

use std::process::{Command, Stdio};
use std::time::Duration;

use serde_json::{Value, json};

use crate::common::{TestApp, fresh_db_path, fresh_db_url, mission_body};

/// The value of the sample `name{labels}` in OpenMetrics text (labels in the order written).
fn sample(text: &str, series: &str) -> Option<f64> {
    text.lines().find_map(|l| l.strip_prefix(series).and_then(|rest| rest.trim().split(' ').next()).and_then(|v| v.parse().ok()))
}

#[tokio::test]
async fn metrics_count_requests_by_route_and_jobs_by_planner() {
    let app = TestApp::spawn().await;
    let mission = app.create_mission(&mission_body("real-fields/nl-parcel-b.json")).await;
    for _ in 0..3 {
        assert_eq!(app.get("/api/v1/plans/no-such-plan").await.0, 404);
    }
    let (_, plan) = app.post(&format!("/api/v1/missions/{mission}/plans"), &json!({"line_spacing_m": 30})).await;
    assert_eq!(app.wait_finished(plan["id"].as_str().unwrap()).await["status"], "succeeded");
    let r = app.client.get(app.url("/metrics")).send().await.unwrap();
    assert_eq!(r.status(), 200);
    assert!(r.headers()["content-type"].to_str().unwrap().starts_with("application/openmetrics-text"));
    let text = r.text().await.unwrap();
    assert_eq!(sample(&text, r#"coverplan_http_requests_total{method="GET",route="/api/v1/plans/{id}",status="404"}"#), Some(3.0), "{text}");
    assert_eq!(sample(&text, r#"coverplan_http_requests_total{method="POST",route="/api/v1/missions",status="201"}"#), Some(1.0));
    assert!(sample(&text, r#"coverplan_http_request_duration_seconds_count{method="GET",route="/api/v1/plans/{id}"}"#).is_some_and(|n| n >= 3.0));
    assert_eq!(sample(&text, r#"coverplan_jobs_total{planner="boustrophedon",outcome="succeeded"}"#), Some(1.0));
    assert_eq!(sample(&text, r#"coverplan_job_duration_seconds_count{planner="boustrophedon",outcome="succeeded"}"#), Some(1.0));
    assert_eq!((sample(&text, "coverplan_queue_depth"), sample(&text, "coverplan_jobs_running")), (Some(0.0), Some(0.0)));
    assert!(!text.contains(&mission), "ids make no series");
    app.stop().await;
}

#[tokio::test]
async fn metrics_are_for_admin_keys_once_keys_exist() {
    let app = TestApp::spawn().await;
    let db = coverplan::store::connect(&app.db_url).await.unwrap();
    let (_, user) = coverplan::store::keys::create(&db, "farm-a", false).await.unwrap();
    let (_, admin) = coverplan::store::keys::create(&db, "ops", true).await.unwrap();
    db.close().await;
    let status = |key: Option<&str>| {
        let request = app.client.get(app.url("/metrics"));
        let request = match key {
            Some(k) => request.bearer_auth(k),
            None => request,
        };
        async move { request.send().await.unwrap().status().as_u16() }
    };
    assert_eq!((status(None).await, status(Some(&user)).await, status(Some(&admin)).await), (401, 403, 200));
    app.stop().await;
}

#[tokio::test]
async fn json_logs_name_the_plan_and_tenant_of_every_job_line() {
    let db = fresh_db_path();
    let log = db.with_file_name("server.log");
    let db = fresh_db_url().await;
    let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let mut child = Command::new(env!("CARGO_BIN_EXE_coverplan"))
        .arg("serve")
        .env("COVERPLAN_ADDR", format!("127.0.0.1:{port}"))
        .env("COVERPLAN_DATABASE_URL", &db)
        .env("COVERPLAN_LOG_FORMAT", "json")
        .env("COVERPLAN_LOG", "info")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let base = format!("http://127.0.0.1:{port}");
    let client = reqwest::Client::new();
    let mut ready = false;
    for _ in 0..400 {
        if client.get(format!("{base}/readyz")).send().await.is_ok_and(|r| r.status() == 200) {
            ready = true;
            break;
        }
        tokio::time::sleep(Duration::from_millis(25)).await;
    }
    assert!(ready, "the server did not start");
    let m: Value = client.post(format!("{base}/api/v1/missions")).json(&mission_body("real-fields/nl-parcel-b.json")).send().await.unwrap().json().await.unwrap();
    let p: Value =
        client.post(format!("{base}/api/v1/missions/{}/plans", m["id"].as_str().unwrap())).json(&json!({"line_spacing_m": 30})).send().await.unwrap().json().await.unwrap();
    let plan = p["id"].as_str().unwrap();
    for _ in 0..600 {
        let p: Value = client.get(format!("{base}/api/v1/plans/{plan}")).send().await.unwrap().json().await.unwrap();
        if p["status"] == "succeeded" {
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert!(Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap().success());
    assert!(child.wait().unwrap().success());
    let lines: Vec<Value> = std::fs::read_to_string(&log).unwrap().lines().map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}"))).collect();
    let job_lines: Vec<&Value> = lines.iter().filter(|l| l["span"]["name"] == "job").collect();
    let messages: Vec<&str> = job_lines.iter().filter_map(|l| l["fields"]["message"].as_str()).collect();
    assert!(messages.contains(&"plan started") && messages.contains(&"plan ended"), "{messages:?}");
    for line in job_lines {
        assert_eq!((line["span"]["plan"].as_str(), line["span"]["tenant"].as_str()), (Some(plan), Some("default")), "{line}");
    }
}
