//! The committed OpenAPI document must be the one the code generates.
//! Regenerate with `UPDATE_OPENAPI=1 cargo test --test openapi` (or `coverplan openapi`).

#[test]
fn committed_openapi_document_is_current() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/openapi/openapi.json");
    let generated = coverplan::http::openapi::document();
    if std::env::var_os("UPDATE_OPENAPI").is_some() {
        std::fs::write(path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(committed == generated, "openapi/openapi.json is stale: run `UPDATE_OPENAPI=1 cargo test --test openapi`");
}

#[test]
fn every_route_is_documented() {
    let doc: serde_json::Value = serde_json::from_str(&coverplan::http::openapi::document()).unwrap();
    let paths = doc["paths"].as_object().unwrap();
    for (path, methods) in [
        ("/healthz", vec!["get"]),
        ("/readyz", vec!["get"]),
        ("/api/v1/missions", vec!["get", "post"]),
        ("/api/v1/missions/{id}", vec!["get", "put", "delete"]),
        ("/api/v1/missions/{id}/plans", vec!["get", "post"]),
        ("/api/v1/plans/{id}", vec!["get", "delete"]),
        ("/api/v1/plans/{id}/trajectory", vec!["get"]),
        ("/api/v1/planners", vec!["get"]),
    ] {
        for m in methods {
            assert!(paths[path][m].is_object(), "{m} {path} is not documented");
        }
    }
}
