//! The `coverplan` binary as operators run it: started outside the repository, killed
//! mid-job, stopped with SIGTERM, benchmarking.

use std::process::{Child, Command, Stdio};
use std::time::Duration;

use crate::common::{self, fresh_db_path, fresh_db_url, mission_body};
use coverplan::store::plans;
use serde_json::{Value, json};

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

struct Server {
    child: Child,
    base: String,
}

impl Server {
    /// SIGKILL: no chance to clean up.
    fn kill(&mut self) {
        self.child.kill().unwrap();
        self.child.wait().unwrap();
    }
}

fn start(db: &str, port: u16, delay_ms: u64) -> Server {
    start_replica(db, port, delay_ms, "solo")
}

fn start_replica(db: &str, port: u16, delay_ms: u64, replica: &str) -> Server {
    // started away from the repository: the binary carries its page
    let away = fresh_db_path();
    let child = Command::new(env!("CARGO_BIN_EXE_coverplan"))
        .arg("serve")
        .current_dir(away.parent().expect("a fresh folder"))
        .env("COVERPLAN_ADDR", format!("127.0.0.1:{port}"))
        .env("COVERPLAN_DATABASE_URL", db)
        .env("COVERPLAN_WORKERS", "1")
        // a killed replica's plans are taken again 3 s after its last heartbeat
        .env("COVERPLAN_LEASE_S", "3")
        .env("COVERPLAN_REPLICA", replica)
        .env("COVERPLAN_MAX_QUEUED", "100")
        .env("COVERPLAN_SHUTDOWN_GRACE_S", "1")
        .env("COVERPLAN_JOB_START_DELAY_MS", delay_ms.to_string())
        .env("COVERPLAN_LOG", "warn")
        .stdout(Stdio::null())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let server = Server { child, base: format!("http://127.0.0.1:{port}") };
    for _ in 0..400 {
        let ok = Command::new(env!("CARGO_BIN_EXE_coverplan")).args(["healthcheck", "--addr", &format!("127.0.0.1:{port}")]).stderr(Stdio::null()).status().unwrap().success();
        if ok {
            return server;
        }
        std::thread::sleep(Duration::from_millis(25));
    }
    panic!("the server did not start");
}

async fn status(client: &reqwest::Client, base: &str, plan: &str) -> String {
    let p: Value = client.get(format!("{base}/api/v1/plans/{plan}")).send().await.unwrap().json().await.unwrap();
    p["status"].as_str().unwrap().to_owned()
}

async fn wait_status(client: &reqwest::Client, base: &str, plan: &str, want: &str) {
    for _ in 0..1200 {
        if status(client, base, plan).await == want {
            return;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    panic!("plan {plan} never became {want}");
}

async fn queue_plan(client: &reqwest::Client, base: &str) -> String {
    let m: Value = client.post(format!("{base}/api/v1/missions")).json(&mission_body("real-fields/nl-parcel-b.json")).send().await.unwrap().json().await.unwrap();
    let p: Value =
        client.post(format!("{base}/api/v1/missions/{}/plans", m["id"].as_str().unwrap())).json(&json!({"line_spacing_m": 20})).send().await.unwrap().json().await.unwrap();
    p["id"].as_str().unwrap().to_owned()
}

#[tokio::test]
async fn the_binary_serves_its_page_from_any_working_directory() {
    let db = fresh_db_url().await;
    let mut server = start(&db, free_port(), 0);
    let client = reqwest::Client::new();
    for (path, kind, needle) in [("/", "text/html", "<html"), ("/app.js", "javascript", "import"), ("/vendor/leaflet/leaflet.js", "javascript", "Leaflet")] {
        let r = client.get(format!("{}{path}", server.base)).send().await.unwrap();
        assert_eq!(r.status(), 200, "{path}");
        let content_type = r.headers()["content-type"].to_str().unwrap().to_owned();
        let etag = r.headers()["etag"].clone();
        assert!(content_type.contains(kind), "{path}: {content_type}");
        assert!(r.text().await.unwrap().contains(needle), "{path}");
        // a browser that has the file revalidates it without downloading it again
        let again = client.get(format!("{}{path}", server.base)).header("if-none-match", etag).send().await.unwrap();
        assert_eq!(again.status(), 304, "{path}");
    }
    let missing = client.get(format!("{}/no-such-page.html", server.base)).send().await.unwrap();
    assert_eq!(missing.status(), 404);
    server.kill();
}

/// A server (on a fresh database) whose only worker holds a plan running for a minute.
async fn a_server_with_a_running_plan() -> (String, u16, Server, String) {
    let db = fresh_db_url().await;
    let port = free_port();
    let server = start(&db, port, 60_000);
    let client = reqwest::Client::new();
    let plan = queue_plan(&client, &server.base).await;
    wait_status(&client, &server.base, &plan, "running").await;
    (db, port, server, plan)
}

#[tokio::test]
async fn a_job_running_when_the_process_is_killed_completes_after_restart() {
    let (db, port, mut server, plan) = a_server_with_a_running_plan().await;
    server.kill();

    let mut server = start(&db, port, 0);
    let client = reqwest::Client::new(); // the old one pools a connection to the dead process
    wait_status(&client, &server.base, &plan, "succeeded").await;
    let r = client.get(format!("{}/api/v1/plans/{plan}/trajectory", server.base)).send().await.unwrap();
    assert_eq!(r.status(), 200);
    server.kill();
}

#[tokio::test]
async fn sigterm_requeues_unfinished_work_and_exits_cleanly() {
    let (db, port, mut server, plan) = a_server_with_a_running_plan().await;
    let pid = server.child.id().to_string();
    assert!(Command::new("kill").args(["-TERM", &pid]).status().unwrap().success());
    let exit = tokio::task::spawn_blocking(move || server.child.wait().unwrap()).await.unwrap();
    assert!(exit.success(), "exit status {exit:?}");

    let mut server = start(&db, port, 0);
    let client = reqwest::Client::new(); // the old one pools a connection to the dead process
    wait_status(&client, &server.base, &plan, "succeeded").await;
    server.kill();
}

/// Two `coverplan serve` processes on one PostgreSQL database take 40 plans queued through both;
/// one is killed with SIGKILL while it runs a plan. Every plan succeeds exactly once, both
/// replicas took plans, and the record of claims shows no plan held by two replicas at once.
#[tokio::test]
async fn replicas_on_postgres_share_the_queue_and_a_killed_one_loses_no_plan() {
    if common::test_postgres().is_none() {
        eprintln!("skipped: needs COVERPLAN_TEST_POSTGRES (tests/run_all.sh runs it on PostgreSQL)");
        return;
    }
    let db = fresh_db_url().await;
    let mut a = start_replica(&db, free_port(), 400, "a");
    let mut b = start_replica(&db, free_port(), 400, "b");
    let client = reqwest::Client::new();
    let m: Value = client.post(format!("{}/api/v1/missions", a.base)).json(&mission_body("real-fields/nl-parcel-b.json")).send().await.unwrap().json().await.unwrap();
    let mut ids = Vec::new();
    for k in 0..40 {
        let base = if k % 2 == 0 { &a.base } else { &b.base };
        let r = client.post(format!("{base}/api/v1/missions/{}/plans", m["id"].as_str().unwrap())).json(&json!({"line_spacing_m": 20})).send().await.unwrap();
        assert_eq!(r.status(), 202);
        ids.push(r.json::<Value>().await.unwrap()["id"].as_str().unwrap().to_owned());
    }
    let store = coverplan::store::connect(&db).await.unwrap();
    let started = std::time::Instant::now();
    loop {
        let claims = plans::claims(&store).await.unwrap();
        let of_a: Vec<_> = claims.iter().filter(|c| c.replica == "a").collect();
        if of_a.len() >= 3 && of_a.iter().any(|c| c.ended_at.is_none()) {
            break;
        }
        assert!(started.elapsed() < Duration::from_secs(60), "replica a took {} plans", of_a.len());
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    a.kill();
    for id in &ids {
        wait_status(&client, &b.base, id, "succeeded").await;
    }
    let claims = plans::claims(&store).await.unwrap();
    for id in &ids {
        let of_plan: Vec<_> = claims.iter().filter(|c| &c.plan_id == id).collect();
        assert_eq!(of_plan.iter().filter(|c| c.outcome.as_deref() == Some("succeeded")).count(), 1, "{of_plan:?}");
        for pair in of_plan.windows(2) {
            let ended = pair[0].ended_at.expect("an earlier claim ended");
            assert!(pair[1].claimed_at >= ended, "two replicas held {id} at once: {of_plan:?}");
        }
    }
    let by = |r: &str| claims.iter().filter(|c| c.replica == r).count();
    assert!(by("a") >= 3 && by("b") >= 1, "a took {}, b took {}", by("a"), by("b"));
    assert!(claims.iter().any(|c| c.replica == "a" && c.outcome.as_deref() == Some("abandoned")), "the killed replica's plan was taken over");
    b.kill();
}

#[test]
fn plan_reads_a_kml_field_and_writes_a_flight_file() {
    let dir = std::env::temp_dir().join(format!("coverplan-cli-{}", uuid::Uuid::new_v4()));
    std::fs::create_dir_all(&dir).unwrap();
    let ring = "8.540,47.370 8.544,47.370 8.544,47.373 8.540,47.373 8.540,47.370";
    let kml = format!(
        r#"<kml xmlns="http://www.opengis.net/kml/2.2"><Document><Placemark><name>Home</name><Point><coordinates>8.5401,47.3701</coordinates></Point></Placemark><Placemark><name>Field</name><Polygon><outerBoundaryIs><LinearRing><coordinates>{ring}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark></Document></kml>"#
    );
    std::fs::write(dir.join("field.kml"), kml).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_coverplan"))
        .args(["plan", "--mission"])
        .arg(dir.join("field.kml"))
        .args(["--format", "plan", "--firmware", "px4", "--out"])
        .arg(dir.join("field.plan"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let plan: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("field.plan")).unwrap()).unwrap();
    assert_eq!((plan["fileType"].as_str(), plan["mission"]["firmwareType"].as_u64()), (Some("Plan"), Some(12)));
    assert_eq!(plan["mission"]["plannedHomePosition"][0], 47.3701, "home, [lat, lon]");
    let unknown = Command::new(env!("CARGO_BIN_EXE_coverplan")).args(["plan", "--mission"]).arg(dir.join("field.kml")).args(["--format", "gpx"]).output().unwrap();
    // refused with the registry's formats, as `--help` lists them
    let said = String::from_utf8_lossy(&unknown.stderr);
    assert!(!unknown.status.success() && said.contains(&format!("possible values: {}", coverplan::planner::export::format_ids().join(", "))), "{said}");
}
