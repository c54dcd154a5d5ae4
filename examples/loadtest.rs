//! A bounded load test on loopback: `cargo run --release --example loadtest -- --binary
//! target/release/coverplan [--clients 64] [--seconds 30]`.
//!
//! Starts the server binary on a fresh database with eight tenants' keys, keeps both workers
//! busy with two long fixed-wing plans around 14 no-fly zones, then runs `--clients` clients for
//! `--seconds`, each looping over a mix of reads (a mission, a plan, the mission list), mission
//! writes (create, update) and plan requests. Prints latency percentiles and errors per kind of
//! request; exits 1 if any request failed. Not a test: its figures depend on the machine.

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde_json::{Value, json};

struct Options {
    binary: PathBuf,
    clients: usize,
    seconds: u64,
}

fn options() -> Options {
    let mut args = std::env::args().skip(1);
    let mut o = Options { binary: PathBuf::from("target/release/coverplan"), clients: 64, seconds: 30 };
    while let Some(flag) = args.next() {
        let value = args.next().unwrap_or_else(|| panic!("{flag} needs a value"));
        match flag.as_str() {
            "--binary" => o.binary = value.into(),
            "--clients" => o.clients = value.parse().expect("--clients N"),
            "--seconds" => o.seconds = value.parse().expect("--seconds N"),
            other => panic!("unknown option {other}; known: --binary, --clients, --seconds"),
        }
    }
    o
}

#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
enum Kind {
    Read,
    MissionWrite,
    PlanRequest,
}

/// One request's outcome: its kind, its latency, and whether it failed.
type Sample = (Kind, Duration, bool);

fn field(name: &str) -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name);
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).expect("a fixture")
}

fn make_key(binary: &PathBuf, db: &PathBuf, tenant: &str) -> String {
    let out = Command::new(binary).args(["keys", "create", "--tenant", tenant, "--database-url"]).arg(db).output().expect("coverplan keys create");
    assert!(out.status.success(), "keys create: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).expect("text").trim().lines().last().expect("the key").to_owned()
}

struct Client {
    http: reqwest::Client,
    base: String,
    key: String,
}

impl Client {
    async fn send(&self, method: reqwest::Method, path: &str, body: Option<&Value>) -> (Duration, Option<Value>) {
        let started = Instant::now();
        let mut request = self.http.request(method, format!("{}{path}", self.base)).bearer_auth(&self.key);
        if let Some(body) = body {
            request = request.json(body);
        }
        let answer = match request.send().await {
            Ok(r) if r.status().is_success() => r.json::<Value>().await.ok(),
            _ => None,
        };
        (started.elapsed(), answer)
    }
}

/// One client's loop until `until`: 8 reads, then a mission write, then (every other round) a
/// plan request.
async fn run_client(client: Client, mission: Value, until: Instant) -> Vec<Sample> {
    let mut samples = Vec::new();
    let (_, created) = client.send(reqwest::Method::POST, "/api/v1/missions", Some(&mission)).await;
    let id = created.and_then(|m| m["id"].as_str().map(str::to_owned)).expect("the client's mission");
    let (_, plan) = client.send(reqwest::Method::POST, &format!("/api/v1/missions/{id}/plans"), Some(&json!({"line_spacing_m": 40}))).await;
    let plan = plan.and_then(|p| p["id"].as_str().map(str::to_owned)).expect("the client's plan");
    let reads = [format!("/api/v1/missions/{id}"), format!("/api/v1/plans/{plan}"), "/api/v1/missions?limit=20&fields=summary".to_string()];
    let mut round = 0usize;
    while Instant::now() < until {
        for k in 0..8 {
            let (took, answer) = client.send(reqwest::Method::GET, &reads[k % reads.len()], None).await;
            samples.push((Kind::Read, took, answer.is_none()));
        }
        let (took, answer) = client.send(reqwest::Method::PUT, &format!("/api/v1/missions/{id}"), Some(&mission)).await;
        samples.push((Kind::MissionWrite, took, answer.is_none()));
        if round.is_multiple_of(2) {
            let (took, answer) = client.send(reqwest::Method::POST, &format!("/api/v1/missions/{id}/plans"), Some(&json!({"line_spacing_m": 40}))).await;
            samples.push((Kind::PlanRequest, took, answer.is_none()));
        }
        round += 1;
    }
    samples
}

fn percentile(sorted: &[Duration], p: f64) -> f64 {
    let at = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted.get(at).map_or(f64::NAN, |d| d.as_secs_f64() * 1000.0)
}

#[tokio::main]
async fn main() {
    let o = options();
    let dir = std::env::temp_dir().join(format!("coverplan-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a folder");
    let db = dir.join("load.db");
    let keys: Vec<String> = (0..8).map(|t| make_key(&o.binary, &db, &format!("farm-{t}"))).collect();
    let port = std::net::TcpListener::bind("127.0.0.1:0").expect("a port").local_addr().expect("an address").port();
    let base = format!("http://127.0.0.1:{port}");
    let mut server = Command::new(&o.binary)
        .arg("serve")
        .env("COVERPLAN_ADDR", format!("127.0.0.1:{port}"))
        .env("COVERPLAN_DATABASE_URL", &db)
        .env("COVERPLAN_WORKERS", "2")
        // the server's capacity is measured, not the per-tenant limits
        .env("COVERPLAN_MAX_QUEUED", "100000")
        .env("COVERPLAN_RATE_PER_S", "100000")
        .env("COVERPLAN_LOG", "warn")
        .stdout(Stdio::null())
        .spawn()
        .expect("the server starts");
    let http = reqwest::Client::builder().pool_max_idle_per_host(o.clients).build().expect("a client");
    let mut ready = false;
    for _ in 0..400 {
        if http.get(format!("{base}/readyz")).send().await.is_ok_and(|r| r.status().is_success()) {
            ready = true;
            break;
        }
        tokio::time::sleep(Duration::from_millis(25)).await;
    }
    assert!(ready, "the server did not start");

    // both workers busy for the whole run: two fixed-wing plans around 14 zones (about a minute each)
    let busy = Client { http: http.clone(), base: base.clone(), key: keys[0].clone() };
    let h14 = field("random-fields/h14_00.json");
    let (_, m) = busy.send(reqwest::Method::POST, "/api/v1/missions", Some(&json!({"name": "h14", "area": h14["area"], "no_fly_zones": h14["no_fly_zones"]}))).await;
    let h14_id = m.and_then(|m| m["id"].as_str().map(str::to_owned)).expect("the busy mission");
    for _ in 0..2 {
        let fixed_wing = json!({"planner": "line_gtsp", "line_spacing_m": 20, "vehicle": {"kind": "fixed_wing", "turn_radius_m": 10}});
        busy.send(reqwest::Method::POST, &format!("/api/v1/missions/{h14_id}/plans"), Some(&fixed_wing)).await.1.expect("a busy plan queued");
    }
    tokio::time::sleep(Duration::from_secs(1)).await;

    let parcel = field("real-fields/nl-parcel-b.json");
    let mission = Arc::new(json!({"name": "load", "area": parcel["area"]}));
    let started = Instant::now();
    let until = started + Duration::from_secs(o.seconds);
    let tasks: Vec<_> = (0..o.clients)
        .map(|c| {
            let client = Client { http: http.clone(), base: base.clone(), key: keys[c % keys.len()].clone() };
            let mission = (*mission).clone();
            tokio::spawn(run_client(client, mission, until))
        })
        .collect();
    let mut samples: Vec<Sample> = Vec::new();
    for t in tasks {
        samples.extend(t.await.expect("a client ran"));
    }
    let elapsed = started.elapsed().as_secs_f64();
    let (_, running) = busy.send(reqwest::Method::GET, &format!("/api/v1/missions/{h14_id}/plans"), None).await;
    let still_busy = running.as_ref().and_then(Value::as_array).map_or(0, |p| p.iter().filter(|p| p["status"] == "running").count());
    let _ = server.kill();
    let _ = server.wait();
    let _ = std::fs::remove_dir_all(&dir);

    println!("{} clients for {elapsed:.0} s on loopback, 8 tenants, 2 workers busy with fixed-wing plans ({still_busy} still running at the end)\n", o.clients);
    println!("| requests | count | per s | p50 ms | p99 ms | max ms | errors |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    let mut failed = 0;
    for (kind, name) in [(Kind::Read, "reads"), (Kind::MissionWrite, "mission writes"), (Kind::PlanRequest, "plan requests")] {
        let mut times: Vec<Duration> = samples.iter().filter(|s| s.0 == kind).map(|s| s.1).collect();
        let errors = samples.iter().filter(|s| s.0 == kind && s.2).count();
        failed += errors;
        times.sort_unstable();
        println!(
            "| {name} | {} | {:.0} | {:.1} | {:.1} | {:.1} | {errors} |",
            times.len(),
            times.len() as f64 / elapsed,
            percentile(&times, 0.5),
            percentile(&times, 0.99),
            times.last().map_or(f64::NAN, |d| d.as_secs_f64() * 1000.0)
        );
    }
    if failed > 0 {
        std::process::exit(1);
    }
}
