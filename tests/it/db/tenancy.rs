//! Tenants and API keys on the real app: a tenant reaches nothing of another's through any
//! documented route, keys are checked, and the per-tenant and per-key limits answer 429.

use std::time::Duration;

use reqwest::Method;
use serde_json::{Value, json};

use crate::common::{TestApp, fresh_db_url, mission_body};
use coverplan::store::{self, keys};

/// A client sending one key (or none).
struct As {
    http: reqwest::Client,
    base: String,
    key: Option<String>,
}

impl As {
    fn new(app: &TestApp, key: Option<&str>) -> As {
        As { http: reqwest::Client::new(), base: app.base.clone(), key: key.map(str::to_owned) }
    }

    async fn send(&self, method: Method, path: &str, body: Option<&Value>) -> (u16, Value, reqwest::header::HeaderMap) {
        let mut request = self.http.request(method, format!("{}{path}", self.base));
        if let Some(key) = &self.key {
            request = request.bearer_auth(key);
        }
        if let Some(body) = body {
            request = request.json(body);
        }
        let response = request.send().await.unwrap();
        let (status, headers) = (response.status().as_u16(), response.headers().clone());
        (status, response.json().await.unwrap_or(Value::Null), headers)
    }

    async fn get(&self, path: &str) -> (u16, Value) {
        let (s, v, _) = self.send(Method::GET, path, None).await;
        (s, v)
    }

    async fn post(&self, path: &str, body: &Value) -> (u16, Value) {
        let (s, v, _) = self.send(Method::POST, path, Some(body)).await;
        (s, v)
    }

    async fn wait_finished(&self, plan: &str) -> Value {
        for _ in 0..1200 {
            let (_, p) = self.get(&format!("/api/v1/plans/{plan}")).await;
            if matches!(p["status"].as_str(), Some("succeeded" | "failed" | "cancelled")) {
                return p;
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
        panic!("plan {plan} did not finish");
    }
}

/// Keys made in the app's database, as an operator would with `coverplan keys create`.
async fn make_key(app: &TestApp, tenant: &str, admin: bool) -> String {
    let db = store::connect(&app.db_url).await.unwrap();
    let (_, key) = keys::create(&db, tenant, admin).await.unwrap();
    db.close().await;
    key
}

/// Everything tenant A can read, to compare before and after B's attempts.
async fn snapshot(a: &As, mission: &str, plan: &str) -> Vec<Value> {
    let mut seen = Vec::new();
    for path in [
        format!("/api/v1/missions/{mission}"),
        format!("/api/v1/missions/{mission}/plans"),
        format!("/api/v1/plans/{plan}"),
        format!("/api/v1/plans/{plan}/trajectory"),
        "/api/v1/missions".to_string(),
        "/api/v1/vehicles/farm-a-drone".to_string(),
    ] {
        let (s, v) = a.get(&path).await;
        assert_eq!(s, 200, "{path}: {v}");
        seen.push(v);
    }
    seen
}

#[tokio::test]
async fn a_tenant_reaches_nothing_of_another_through_any_route() {
    let app = TestApp::spawn().await;
    let a = As::new(&app, Some(&make_key(&app, "farm-a", false).await));
    let b = As::new(&app, Some(&make_key(&app, "farm-b", false).await));

    // A's mission, plan and vehicle profile
    let (s, mission) = a.post("/api/v1/missions", &mission_body("real-fields/nl-parcel-b.json")).await;
    assert_eq!(s, 201, "{mission}");
    let mission = mission["id"].as_str().unwrap().to_owned();
    let (_, plan) = a.post(&format!("/api/v1/missions/{mission}/plans"), &json!({"line_spacing_m": 30})).await;
    let plan = plan["id"].as_str().unwrap().to_owned();
    assert_eq!(a.wait_finished(&plan).await["status"], "succeeded");
    let (_, mut vehicle) = a.get("/api/v1/vehicles/iris").await;
    for k in ["builtin", "created_at", "updated_at"] {
        vehicle.as_object_mut().unwrap().remove(k);
    }
    vehicle["profile"] = json!("farm-a-drone");
    assert_eq!(a.post("/api/v1/vehicles", &vehicle).await.0, 201);
    let (_, patrol) = a.post(&format!("/api/v1/missions/{mission}/patrols"), &json!({"cycles": 100})).await;
    let patrol = patrol["id"].as_str().unwrap().to_owned();
    let before = snapshot(&a, &mission, &plan).await;

    // every documented operation on A's ids, as B: 404, as for an id that does not exist
    let doc: Value = serde_json::from_str(&coverplan::http::openapi::document()).unwrap();
    let mut tried = 0;
    for (path, item) in doc["paths"].as_object().unwrap().iter().filter(|(p, _)| p.contains("{id}")) {
        let (id, body) = if path.starts_with("/api/v1/missions/") {
            let body = if path.ends_with("/plans") {
                json!({"line_spacing_m": 30})
            } else if path.ends_with("/patrols") {
                json!({"cycles": 100})
            } else {
                mission_body("real-fields/nl-parcel-b.json")
            };
            (&mission, body)
        } else if path.starts_with("/api/v1/plans/") {
            (&plan, json!({}))
        } else if path.starts_with("/api/v1/patrols/") {
            (&patrol, json!({}))
        } else {
            (&"farm-a-drone".to_string(), vehicle.clone())
        };
        for method in item.as_object().unwrap().keys() {
            let method: Method = method.to_uppercase().parse().unwrap();
            let with_body = (method == Method::POST || method == Method::PUT).then_some(&body);
            let (status, problem, _) = b.send(method.clone(), &path.replace("{id}", id), with_body).await;
            let mut absent_body = body.clone();
            if absent_body.get("profile").is_some() {
                absent_body["profile"] = json!("no-such-id");
            }
            let (_, absent, _) = b.send(method.clone(), &path.replace("{id}", "no-such-id"), with_body.map(|_| &absent_body)).await;
            assert_eq!(status, 404, "{method} {path} as another tenant: {problem}");
            assert_eq!(problem["code"], absent["code"], "{method} {path}: another tenant's id must look like one that does not exist");
            tried += 1;
        }
    }
    assert!(tried >= 11, "{tried} operations with an id");

    // lists show only one's own; B may use the name of A's profile for its own
    let (_, listed) = b.get("/api/v1/missions").await;
    assert_eq!((listed["total"].as_i64(), listed["items"].as_array().map(Vec::len)), (Some(0), Some(0)), "{listed}");
    let (_, profiles) = b.get("/api/v1/vehicles").await;
    assert!(profiles.as_array().unwrap().iter().all(|v| v["profile"] != "farm-a-drone"));
    let estimate = json!({"vehicle": {"profile": "farm-a-drone"}, "route": {"type": "LineString", "coordinates": [[4.0, 52.0], [4.001, 52.0]]}});
    let (s, problem) = b.post("/api/v1/estimates", &estimate).await;
    assert_eq!(s, 422, "B priced a route with A's profile: {problem}");
    assert_eq!(b.post("/api/v1/vehicles", &vehicle).await.0, 201);

    assert_eq!(snapshot(&a, &mission, &plan).await, before, "B's attempts changed A's data");
    app.stop().await;
}

#[tokio::test]
async fn keys_are_required_once_one_exists_and_checked() {
    let app = TestApp::spawn().await;
    let open = As::new(&app, None);
    // no key yet: open, as on a laptop
    assert_eq!(open.get("/api/v1/missions").await.0, 200);
    let key = make_key(&app, "farm-a", false).await;
    let (s, problem, headers) = open.send(Method::GET, "/api/v1/missions", None).await;
    assert_eq!((s, problem["code"].as_str()), (401, Some("unauthorised")), "{problem}");
    assert_eq!(headers.get("www-authenticate").and_then(|v| v.to_str().ok()), Some("Bearer"));
    let id = key.split('_').nth(1).unwrap();
    for wrong in [format!("cpk_{id}_{}", "0".repeat(64)), "cpk_nope_nope".into(), "not-a-key".into(), key[..key.len() - 1].to_owned()] {
        assert_eq!(As::new(&app, Some(&wrong)).get("/api/v1/missions").await.0, 401, "{wrong}");
    }
    let a = As::new(&app, Some(&key));
    assert_eq!(a.get("/api/v1/missions").await.0, 200);
    // what the page and probes need stays open
    for path in ["/healthz", "/readyz", "/api/v1/ui-config", "/openapi.json", "/"] {
        assert_eq!(open.get(path).await.0, 200, "{path}");
    }
    // revoking the last key does not open the server again
    let db = store::connect(&app.db_url).await.unwrap();
    assert!(keys::revoke(&db, id).await.unwrap());
    db.close().await;
    assert_eq!(a.get("/api/v1/missions").await.0, 401);
    assert_eq!(open.get("/api/v1/missions").await.0, 401);
    app.stop().await;
}

#[tokio::test]
async fn built_in_profiles_are_edited_by_admin_keys_only() {
    let app = TestApp::spawn().await;
    let user = As::new(&app, Some(&make_key(&app, "farm-a", false).await));
    let admin = As::new(&app, Some(&make_key(&app, "operator", true).await));
    let (_, mut iris) = user.get("/api/v1/vehicles/iris").await;
    for k in ["builtin", "created_at", "updated_at"] {
        iris.as_object_mut().unwrap().remove(k);
    }
    iris["battery"]["energy_wh"] = json!(50.0);
    let (s, problem, _) = user.send(Method::PUT, "/api/v1/vehicles/iris", Some(&iris)).await;
    assert_eq!((s, problem["code"].as_str()), (403, Some("builtin_vehicle")), "{problem}");
    assert_eq!(user.get("/api/v1/vehicles/iris").await.1["battery"]["energy_wh"].as_f64().map(|w| w != 50.0), Some(true));
    let (s, edited, _) = admin.send(Method::PUT, "/api/v1/vehicles/iris", Some(&iris)).await;
    assert_eq!((s, edited["battery"]["energy_wh"].as_f64()), (200, Some(50.0)), "{edited}");
    // shared: every tenant sees the edit
    assert_eq!(user.get("/api/v1/vehicles/iris").await.1["battery"]["energy_wh"].as_f64(), Some(50.0));
    app.stop().await;
}

#[tokio::test]
async fn each_tenant_may_queue_a_bounded_number_of_plans() {
    let app = TestApp::spawn_with(fresh_db_url().await, |c| {
        c.workers = 1;
        c.max_queued = 2;
        c.queue.start_delay = Duration::from_secs(60);
    })
    .await;
    let a = As::new(&app, Some(&make_key(&app, "farm-a", false).await));
    let b = As::new(&app, Some(&make_key(&app, "farm-b", false).await));
    let body = mission_body("real-fields/nl-parcel-b.json");
    let mission_a = a.post("/api/v1/missions", &body).await.1["id"].as_str().unwrap().to_owned();
    let mission_b = b.post("/api/v1/missions", &body).await.1["id"].as_str().unwrap().to_owned();
    let params = json!({"line_spacing_m": 30});
    let mut queued = Vec::new();
    for _ in 0..2 {
        let (s, p) = a.post(&format!("/api/v1/missions/{mission_a}/plans"), &params).await;
        assert_eq!(s, 202, "{p}");
        queued.push(p["id"].as_str().unwrap().to_owned());
    }
    let (s, problem, headers) = a.send(Method::POST, &format!("/api/v1/missions/{mission_a}/plans"), Some(&params)).await;
    assert_eq!((s, problem["code"].as_str()), (429, Some("too_many_plans")), "{problem}");
    assert!(headers.get("retry-after").is_some());
    // another tenant is not held back by A's queue
    assert_eq!(b.post(&format!("/api/v1/missions/{mission_b}/plans"), &params).await.0, 202);
    // a cancelled plan frees its place
    assert_eq!(a.send(Method::DELETE, &format!("/api/v1/plans/{}", queued[1]), None).await.0, 200);
    assert_eq!(a.post(&format!("/api/v1/missions/{mission_a}/plans"), &params).await.0, 202);
    app.stop().await;
}

#[tokio::test]
async fn each_key_is_rate_limited_apart() {
    let app = TestApp::spawn_with(fresh_db_url().await, |c| c.rate_limit = coverplan::http::auth::RateLimit { per_second: 2, burst: 5 }).await;
    let a = As::new(&app, Some(&make_key(&app, "farm-a", false).await));
    let b = As::new(&app, Some(&make_key(&app, "farm-b", false).await));
    let mut statuses = Vec::new();
    for _ in 0..8 {
        let (s, _, headers) = a.send(Method::GET, "/api/v1/missions", None).await;
        if s == 429 {
            assert!(headers.get("retry-after").and_then(|v| v.to_str().ok()).and_then(|v| v.parse::<u64>().ok()).is_some_and(|s| s >= 1));
        }
        statuses.push(s);
    }
    assert_eq!(statuses.iter().filter(|&&s| s == 200).count(), 5, "a burst of 5, then refusals: {statuses:?}");
    assert!(statuses[5..].iter().all(|&s| s == 429), "{statuses:?}");
    assert_eq!(b.get("/api/v1/missions").await.0, 200, "another key has its own allowance");
    app.stop().await;
}

#[tokio::test]
async fn a_server_that_requires_keys_refuses_to_start_without_one() {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let mut config = coverplan::config::Config::new(listener.local_addr().unwrap(), fresh_db_url().await);
    config.require_auth = true;
    let refused = coverplan::server::serve(listener, config, async {}).await;
    let message = format!("{:#}", refused.expect_err("refused to start"));
    assert!(message.contains("coverplan keys create"), "{message}");
}
