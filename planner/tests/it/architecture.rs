//! The planner's stages form a directed acyclic graph, in the order `lib.rs` documents: every
//! production path (`crate::…`, `super::…`) from one top-level module to another points to a
//! module earlier in [`LAYERS`]. Test modules (`#[cfg(test)]`, at the end of each file) may
//! reach anywhere and are not read.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// The top-level modules, lowest first, as `lib.rs` lists them.
const LAYERS: &[&str] = &[
    "error",
    "archive",
    "geom",
    "frame",
    "path",
    "wind",
    "stop",
    "mesh",
    "terrain",
    "field",
    "sweep",
    "decompose",
    "turn",
    "route",
    "energy",
    "vehicle",
    "camera",
    "params",
    "sortie",
    "metrics",
    "planners",
    "pattern",
    "fleet",
    "farm",
    "patrol",
    "inspection",
    "export",
    "import",
    "estimate",
    "routing_study",
    "compose",
    "report",
    "resume",
];

/// Module path of a source file relative to the crate root (`route/gtsp/mod.rs` → route, gtsp).
fn module_path(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel.with_extension("").iter().map(|p| p.to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// The code of a file without its test module and without comments.
fn production_code(src: &str) -> String {
    let code = src.split("#[cfg(test)]").next().unwrap_or("");
    code.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

fn identifier(s: &str) -> &str {
    let end = s.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(s.len());
    &s[..end]
}

/// The top-level modules a path starting at `rest` (just after `crate::` or enough `super::`
/// to reach the root) names: one, or several for `{a::…, b}`.
fn named_modules(rest: &str) -> Vec<String> {
    let Some(group) = rest.strip_prefix('{') else { return vec![identifier(rest).to_string()] };
    // the items of the group: split at its own commas, not at those of nested groups
    let (mut depth, mut items, mut start) = (0, Vec::new(), 0);
    for (i, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                items.push(&group[start..i]);
                break;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&group[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.into_iter().map(|item| identifier(item.trim()).to_string()).filter(|m| !m.is_empty() && m != "self").collect()
}

/// Edges between top-level modules: module → modules its production code names.
fn dependencies(root: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).expect("readable source folder") {
            let path = entry.expect("entry").path();
            let rel = path.strip_prefix(root).expect("under the root").to_path_buf();
            if path.is_dir() {
                if !["tests", "proptest-regressions"].contains(&rel.to_string_lossy().as_ref()) {
                    stack.push(path);
                }
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") || rel == Path::new("lib.rs") {
                continue;
            }
            let module = module_path(&rel);
            let code = production_code(&fs::read_to_string(&path).expect("readable source"));
            let from = module[0].clone();
            let mut named = Vec::new();
            for (at, _) in code.match_indices("crate::") {
                named.extend(named_modules(&code[at + "crate::".len()..]));
            }
            let mut i = 0;
            while let Some(at) = code[i..].find("super::") {
                let start = i + at;
                let mut rest = &code[start..];
                let mut ups = 0;
                while let Some(r) = rest.strip_prefix("super::") {
                    ups += 1;
                    rest = r;
                }
                // `super` from a module at depth d reaches the root after d ups
                if ups == module.len() {
                    named.extend(named_modules(rest));
                }
                i = start + "super::".len() * ups;
            }
            edges.entry(from.clone()).or_default().extend(named.into_iter().filter(|m| *m != from));
        }
    }
    edges
}

/// A cycle of the graph, if it has one (depth-first search).
fn find_cycle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit<'a>(node: &'a str, edges: &'a BTreeMap<String, BTreeSet<String>>, on_path: &mut Vec<&'a str>, done: &mut BTreeSet<&'a str>) -> Option<Vec<String>> {
        if let Some(k) = on_path.iter().position(|n| *n == node) {
            let mut cycle: Vec<String> = on_path[k..].iter().map(|s| s.to_string()).collect();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if !done.insert(node) {
            return None;
        }
        on_path.push(node);
        for next in edges.get(node).into_iter().flatten() {
            if let Some(c) = visit(next, edges, on_path, done) {
                return Some(c);
            }
        }
        on_path.pop();
        None
    }
    let mut done = BTreeSet::new();
    edges.keys().find_map(|n| visit(n, edges, &mut Vec::new(), &mut done))
}

fn planner_dependencies() -> BTreeMap<String, BTreeSet<String>> {
    dependencies(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"))
}

#[test]
fn the_stages_form_no_cycle() {
    let edges = planner_dependencies();
    for (from, to) in &edges {
        println!("{from} → {}", to.iter().cloned().collect::<Vec<_>>().join(", "));
    }
    assert!(edges.len() >= LAYERS.len() - 2, "the source was not read: {edges:?}");
    if let Some(cycle) = find_cycle(&edges) {
        panic!("import cycle between the planner's modules: {}", cycle.join(" → "));
    }
}

#[test]
fn every_stage_uses_only_the_stages_below_it() {
    let rank = |m: &str| LAYERS.iter().position(|l| *l == m);
    let mut wrong = Vec::new();
    for (from, to) in planner_dependencies() {
        let from_rank = rank(&from).unwrap_or_else(|| panic!("module `{from}` is missing from LAYERS (and from lib.rs's map)"));
        for t in to {
            let to_rank = rank(&t).unwrap_or_else(|| panic!("`{from}` names `{t}`, which is not a stage in LAYERS"));
            if to_rank >= from_rank {
                wrong.push(format!("{from} → {t}"));
            }
        }
    }
    assert!(wrong.is_empty(), "these imports point up the pipeline: {}", wrong.join(", "));
}

#[test]
fn the_check_sees_a_cycle() {
    let edges: BTreeMap<String, BTreeSet<String>> = [("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")].iter().fold(BTreeMap::new(), |mut m, (f, t)| {
        m.entry(f.to_string()).or_insert_with(BTreeSet::new).insert(t.to_string());
        m
    });
    assert_eq!(find_cycle(&edges), Some(vec!["a".into(), "b".into(), "c".into(), "a".into()]));
    assert_eq!(named_modules("{metrics::Stats, planners::{self, registry}}"), vec!["metrics".to_string(), "planners".into()]);
}
