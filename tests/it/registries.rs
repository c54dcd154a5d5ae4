//! Each planner and each file format is named in one place: its own file, where the registry
//! finds it. Everywhere else (the service, the page, the other stages) asks the registries, so
//! adding a planner or a format is one file and one registry line. Tests and docs may name ids.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

use coverplan::planner::{self, export, import};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The production sources: Rust of the service and the planner, and the page's own scripts and
/// markup (not the vendored libraries).
fn production_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in fs::read_dir(dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                if path.file_name().is_some_and(|n| n != "vendor" && n != "bench") {
                    walk(&path, out);
                }
            } else if path.extension().is_some_and(|e| e == "rs" || e == "js" || e == "html") {
                out.push(path);
            }
        }
    }
    let mut out = Vec::new();
    for dir in ["src", "planner/src", "static"] {
        walk(&root().join(dir), &mut out);
    }
    out
}

/// A file's code without its inline test module (the last item of a file) and without line
/// comments.
fn code_of(path: &Path) -> String {
    let text = fs::read_to_string(path).unwrap();
    let inline_tests = text.match_indices("#[cfg(test)]").find(|(at, m)| text[at + m.len()..].trim_start().starts_with("mod tests {"));
    let code = inline_tests.map_or(text.as_str(), |(at, _)| &text[..at]);
    code.lines().map(|l| if l.trim_start().starts_with("//") || l.trim_start().starts_with("*") { "" } else { l }).collect::<Vec<_>>().join("\n")
}

/// Where an id is defined: `fn id(&self) -> &'static str { "id" }`, or `id: "id"` in a registry
/// value (the decomposition planners, the export formats).
fn defines(code: &str, id: &str) -> bool {
    let literal = format!("\"{id}\"");
    let compact: String = code.split_whitespace().collect();
    compact.contains(&format!("fnid(&self)->&'staticstr{{{literal}")) || compact.contains(&format!("id:{literal}")) || compact.contains(&format!("PLANNER_ID:&str={literal}"))
}

/// Words that are an id and also something else in a file: (word, file, what it is there).
const OTHER_MEANINGS: &[(&str, &str, &str)] = &[
    ("plan", "src/http/plans.rs", "the resource a 404 names"),
    ("plan", "static/js/plan.js", "the Plan button's element id"),
    ("plan", "static/index.html", "the Plan button's element id"),
    ("inspection", "static/js/plan.js", "a planner's `method` (the kind), not its id"),
    ("kml", "planner/src/export/wpml.rs", "the XML root element of a WPML file"),
    ("waypoints", "src/http/openapi/mod.rs", "the estimate request's member in its example"),
    ("waypoints", "src/http/openapi/geojson.rs", "the estimate request's member"),
    ("inspection", "planner/src/inspection/mod.rs", "the request member holding the inspection's options"),
    ("inspection", "planner/src/params/mod.rs", "the request member holding the inspection's options"),
    ("patrol", "src/http/patrols.rs", "the resource a 404 names"),
    ("auto", "static/index.html", "the value of `landing` that lands at home"),
    ("auto", "static/js/plan.js", "the value of `landing` that lands at home"),
    ("patrol", "static/index.html", "the Patrol button's element id"),
    ("patrol", "static/js/patrol.js", "the Patrol button's element id, and the kind of a patrol's paths"),
    ("patrol", "static/js/plan.js", "a planner's `method` (the kind), not its id"),
];

/// Every production file that writes `id` as a string literal, and the files that define it.
fn uses_and_definitions(files: &[(PathBuf, String)], id: &str) -> (BTreeSet<String>, BTreeSet<String>) {
    let (double, single) = (format!("\"{id}\""), format!("'{id}'"));
    let mut uses = BTreeSet::new();
    let mut definitions = BTreeSet::new();
    for (path, code) in files {
        let rel = path.strip_prefix(root()).unwrap().display().to_string();
        let other_meaning = OTHER_MEANINGS.iter().any(|(word, file, _)| *word == id && *file == rel);
        if (code.contains(&double) || code.contains(&single)) && !other_meaning {
            uses.insert(rel.clone());
        }
        if defines(code, id) {
            definitions.insert(rel);
        }
    }
    (uses, definitions)
}

#[test]
fn planner_and_format_ids_are_named_only_in_their_own_files() {
    let files: Vec<(PathBuf, String)> = production_files().into_iter().map(|p| (p.clone(), code_of(&p))).collect();
    assert!(files.len() > 100, "the sources were not found: {} files", files.len());
    let mut ids: BTreeMap<&str, &str> = BTreeMap::new();
    for p in planner::catalogue() {
        ids.insert(p.id, "planner");
    }
    for id in export::format_ids() {
        ids.insert(id, "export format");
    }
    for id in import::format_ids() {
        ids.insert(id, "import format");
    }
    let mut leaks = Vec::new();
    for (id, what) in &ids {
        let (uses, definitions) = uses_and_definitions(&files, id);
        assert!(!definitions.is_empty(), "the {what} `{id}` is defined nowhere the check can see");
        let outside: Vec<&String> = uses.difference(&definitions).collect();
        if !outside.is_empty() {
            leaks.push(format!("{what} `{id}` (defined in {definitions:?}) is named in {outside:?}"));
        }
    }
    assert!(leaks.is_empty(), "ids matched outside their own files and the registries:\n{}", leaks.join("\n"));
}

/// The check sees a leak: an id written into another file is found.
#[test]
fn the_check_finds_an_id_named_elsewhere() {
    let files = vec![
        (root().join("planner/src/planners/a.rs"), "fn id(&self) -> &'static str {\n        \"a_planner\"\n    }".to_string()),
        (root().join("static/js/plan.js"), "if (planner === 'a_planner') {}".to_string()),
    ];
    let (uses, definitions) = uses_and_definitions(&files, "a_planner");
    assert_eq!(definitions.into_iter().collect::<Vec<_>>(), ["planner/src/planners/a.rs"]);
    assert_eq!(uses.len(), 2);
}

/// The string literal after `marker` once `skip` commas are passed, if the argument there is one.
fn literal_after<'a>(code: &'a str, marker: &str, skip: usize) -> Vec<&'a str> {
    let mut found = Vec::new();
    for (at, _) in code.match_indices(marker) {
        let mut rest = &code[at + marker.len()..];
        for _ in 0..skip {
            let Some(comma) = rest.find(',') else { break };
            rest = &rest[comma + 1..];
        }
        let rest = rest.trim_start();
        if let Some(quoted) = rest.strip_prefix('"').or_else(|| rest.strip_prefix('\'')) {
            let end = quoted.find(['"', '\'']).unwrap_or(0);
            found.push(&quoted[..end]);
        }
    }
    found
}

/// Every error code the sources write (a refusal's, a problem's, a failed plan's) is in the
/// list the OpenAPI document enumerates, and the list holds nothing else.
#[test]
fn every_error_code_is_in_the_documented_list() {
    let markers: &[(&str, usize)] = &[
        ("InputError::new(", 0),
        ("code: ", 0),
        ("ApiError::conflict(", 0),
        ("ApiError::bad_request(", 0),
        ("ApiError::invalid(", 0),
        ("problem_response(", 1),
        ("refuse(", 1),
        ("plans::fail(", 2),
        ("error_code = ", 0),
    ];
    let mut written = BTreeSet::new();
    for (path, code) in production_files().iter().filter(|p| p.extension().is_some_and(|e| e == "rs")).map(|p| (p, code_of(p))) {
        if path.ends_with("http/error.rs") {
            // the list itself, and the helpers that take a code as a parameter
            written.extend(
                ["not_found", "internal", "unsupported_media_type", "body_too_large", "unreadable_body", "malformed_json", "invalid_body", "invalid_query"].map(String::from),
            );
        }
        for (marker, skip) in markers {
            written.extend(literal_after(&code, marker, *skip).into_iter().filter(|c| !c.is_empty() && c.chars().all(|ch| ch.is_ascii_lowercase() || ch == '_')).map(String::from));
        }
    }
    let listed: BTreeSet<String> = coverplan::http::error::ERROR_CODES.iter().map(|c| c.to_string()).collect();
    assert!(written.len() >= 100, "{} codes found", written.len());
    let missing: Vec<&String> = written.difference(&listed).collect();
    let unused: Vec<&String> = listed.difference(&written).collect();
    assert!(missing.is_empty() && unused.is_empty(), "codes written but not listed: {missing:?}; listed but never written: {unused:?}");
    let doc: serde_json::Value = serde_json::from_str(&coverplan::http::openapi::document()).unwrap();
    assert_eq!(doc["components"]["schemas"]["ErrorCode"]["enum"].as_array().map(Vec::len), Some(listed.len()));
    assert_eq!(doc["components"]["schemas"]["Problem"]["properties"]["code"]["$ref"], "#/components/schemas/ErrorCode");
}

/// Every parameter a planner lists is a member of the request's schema with a type and a
/// description there: the planners name their parameters, the schema documents them once.
#[test]
fn every_listed_parameter_is_documented_by_the_request_schema() {
    let mut described = 0;
    for p in planner::catalogue() {
        assert!(!p.parameters.is_empty(), "{} reads no parameter", p.id);
        let (schema, _) = coverplan::http::planners::request_of(p.method);
        for name in p.parameters {
            let info = coverplan::http::planners::describe(schema, name);
            assert!(["number", "integer", "string", "boolean", "array", "object"].contains(&info.kind.as_str()), "{}: `{name}` has type {}", p.id, info.kind);
            assert!(info.description.len() > 15, "{}: `{name}` has no description in {schema} ({:?})", p.id, info.description);
            described += 1;
        }
    }
    assert!(described > 100, "{described}");
}
