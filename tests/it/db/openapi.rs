//! The committed OpenAPI document must be the one the code generates.
//! Regenerate with `UPDATE_OPENAPI=1 cargo test --test it openapi` (or `coverplan openapi`).

#[test]
fn committed_openapi_document_is_current() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/openapi/openapi.json");
    let generated = coverplan::http::openapi::document();
    if std::env::var_os("UPDATE_OPENAPI").is_some() {
        std::fs::write(path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(committed == generated, "openapi/openapi.json is stale: run `UPDATE_OPENAPI=1 cargo test --test it openapi`");
}

#[test]
fn operation_ids_are_unique() {
    let doc: serde_json::Value = serde_json::from_str(&coverplan::http::openapi::document()).unwrap();
    let mut ids: Vec<&str> = doc["paths"].as_object().unwrap().values().flat_map(|item| item.as_object().unwrap().values().filter_map(|op| op["operationId"].as_str())).collect();
    let count = ids.len();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), count, "client generators need one name per operation: {ids:?}");
}

#[test]
fn every_schema_reference_resolves() {
    let text = coverplan::http::openapi::document();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let schemas = doc["components"]["schemas"].as_object().unwrap();
    let prefix = "\"#/components/schemas/";
    let mut refs = 0;
    for (at, _) in text.match_indices(prefix) {
        let rest = &text[at + prefix.len()..];
        let name = &rest[..rest.find('"').unwrap()];
        assert!(schemas.contains_key(name), "the document refers to a schema `{name}` it does not define");
        refs += 1;
    }
    assert!(refs > 20, "{refs} references");
}

/// Routes are declared with their documentation (`routes!`), so every route is in the
/// document; this checks the other way: every documented operation is served by the real app
/// (a random id for path parameters, an empty body), never answered "no such route".
#[tokio::test]
async fn every_documented_operation_is_served() {
    let doc: serde_json::Value = serde_json::from_str(&coverplan::http::openapi::document()).unwrap();
    let paths = doc["paths"].as_object().unwrap();
    assert!(paths.len() >= 13, "{:?}", paths.keys());
    let app = crate::common::TestApp::spawn().await;
    let mut operations = 0;
    for (path, item) in paths {
        let url = app.url(&path.replace("{id}", "00000000-0000-4000-8000-000000000000"));
        for method in item.as_object().unwrap().keys().filter(|m| ["get", "post", "put", "delete"].contains(&m.as_str())) {
            let request = app.client.request(method.to_uppercase().parse().unwrap(), &url);
            let request = if method == "post" || method == "put" { request.json(&serde_json::json!({})) } else { request };
            let response = request.send().await.unwrap();
            let status = response.status().as_u16();
            let body = response.text().await.unwrap();
            assert!(status != 405 && !body.contains("\"no_route\""), "{method} {path}: {status} {body}");
            operations += 1;
        }
    }
    assert!(operations >= 21, "{operations} operations");
    app.stop().await;
}

/// The refusals a 422 answer lists as beyond the document are codes the document knows.
#[test]
fn refusals_beyond_the_document_are_known_codes() {
    let doc: serde_json::Value = serde_json::from_str(&coverplan::http::openapi::document()).unwrap();
    let known: Vec<&str> = doc["components"]["schemas"]["ErrorCode"]["enum"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
    let mut listed = 0;
    for item in doc["paths"].as_object().unwrap().values() {
        for answer in item.as_object().unwrap().values().filter_map(|op| op.pointer("/responses/422")) {
            for list in ["x-beyond-schema", "x-beyond-schema-with-profile", "x-stated-in-words"] {
                for code in answer[list].as_array().into_iter().flatten() {
                    assert!(known.contains(&code.as_str().unwrap()), "{list} lists {code}, which ErrorCode does not");
                    listed += 1;
                }
            }
        }
    }
    assert!(listed > 50, "{listed} refusals listed");
}
