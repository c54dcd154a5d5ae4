//! The repository keeps its promises to readers and tools: the fixtures' README names files
//! that exist, every SQL file of `migrations/` is a migration the binary runs, and every test
//! that starts the application runs on both database backends.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn files_under(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        if path.is_dir() {
            out.extend(files_under(&path, ext));
        } else if path.extension().is_some_and(|e| e == ext) {
            out.push(path);
        }
    }
    out
}

#[test]
fn the_fixtures_readme_describes_files_that_exist() {
    let dir = root().join("tests/fixtures");
    let readme = fs::read_to_string(dir.join("README.md")).unwrap();
    let mut named = 0;
    for quoted in readme.split('`').skip(1).step_by(2) {
        let looks_like_a_file = quoted.ends_with(".json") || quoted.ends_with('/');
        if looks_like_a_file && !quoted.contains('*') && !quoted.contains("NN") && !quoted.starts_with("../") {
            assert!(dir.join(quoted).exists(), "the fixtures README names `{quoted}`, which is not there");
            named += 1;
        }
    }
    assert!(named >= 3, "{named} files named");
}

#[test]
fn every_sql_file_is_a_migration_the_binary_runs() {
    for (folder, migrator) in [("sqlite", &coverplan::store::MIGRATOR), ("postgres", &coverplan::store::POSTGRES_MIGRATOR)] {
        let files: BTreeSet<String> = files_under(&root().join("migrations").join(folder), "sql").iter().map(|f| f.file_name().unwrap().to_string_lossy().into_owned()).collect();
        let embedded: BTreeSet<String> = migrator.iter().map(|m| format!("{:04}_{}.sql", m.version, m.description.replace(' ', "_"))).collect();
        assert_eq!(files, embedded, "{folder}");
    }
}

/// `tests/run_all.sh` runs the tests under `tests/it/db/` a second time on PostgreSQL: a test
/// elsewhere that starts the application (or the server binary) would silently skip it.
#[test]
fn every_test_that_starts_the_app_runs_on_both_backends() {
    let it = root().join("tests/it");
    let mut outside = Vec::new();
    for file in files_under(&it, "rs") {
        let rel = file.strip_prefix(&it).unwrap();
        if rel.starts_with("db") || rel == Path::new("common.rs") || rel == Path::new("repository.rs") {
            continue;
        }
        let code = fs::read_to_string(&file).unwrap();
        // the app in process, a fresh database, or the binary pointed at a database
        if ["TestApp", "fresh_db", ".env(\"COVERPLAN_DATABASE_URL\""].iter().any(|marker| code.contains(marker)) {
            outside.push(rel.display().to_string());
        }
    }
    assert!(outside.is_empty(), "these start the application outside tests/it/db/, so PostgreSQL never sees them: {outside:?}");
    let db_tests = files_under(&it.join("db"), "rs").len();
    assert!(db_tests >= 10, "{db_tests} files under tests/it/db");
    let run_all = fs::read_to_string(root().join("tests/run_all.sh")).unwrap();
    assert!(run_all.contains("-- db::"), "the PostgreSQL pass selects the db module");
}

/// Each backend's statements are written out for it (`store::Statement`): no SQL is rewritten
/// at run time, and each text uses its own backend's bind markers and insertion order.
#[test]
fn every_statement_is_written_in_each_backends_dialect() {
    let mut statements = 0;
    for file in files_under(&root().join("src/store"), "rs") {
        let code = fs::read_to_string(&file).unwrap();
        assert!(!code.contains(".replace("), "{} rewrites text", file.display());
        let code = code.split_whitespace().collect::<Vec<_>>().join(" ");
        for (at, _) in code.match_indices("Statement { sqlite: ") {
            let rest = &code[at..];
            let (sqlite, postgres) = rest.split_once(", postgres: ").unwrap_or_else(|| panic!("{}: a statement without its PostgreSQL text", file.display()));
            let postgres = postgres.split(" }").next().unwrap();
            assert!(!sqlite.contains('$'), "{}: PostgreSQL's bind markers in SQLite's text: {sqlite}", file.display());
            assert!(
                !postgres.contains('?') && !postgres.contains("rowid") && !postgres.contains("strftime"),
                "{}: SQLite's dialect in PostgreSQL's text: {postgres}",
                file.display()
            );
            statements += 1;
        }
    }
    assert!(statements >= 35, "{statements} statements found");
}
