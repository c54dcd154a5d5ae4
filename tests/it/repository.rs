//! The repository keeps its promises to readers and tools: proptest's saved failing cases sit
//! where proptest reads them, the fixtures' README names files that exist, and every SQL file
//! of `migrations/` is a migration the binary runs.

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

/// proptest saves a test file's failing cases beside the source tree of its crate root (the
/// nearest folder with a `lib.rs` or `main.rs`): `<parent>/proptest-regressions/<path>.txt`.
/// A saved file whose test file moved is never read again.
#[test]
fn saved_proptest_cases_sit_where_proptest_reads_them() {
    // (folder of saved cases, the crate root it mirrors)
    let mirrors = [("src/proptest-regressions", "src/planner"), ("src/planner/tests/proptest-regressions", "src/planner/tests/it"), ("tests/proptest-regressions", "tests/it")];
    let mut saved = 0;
    for (cases, crate_root) in mirrors {
        for file in files_under(&root().join(cases), "txt") {
            let rel = file.strip_prefix(root().join(cases)).unwrap().with_extension("rs");
            let source = root().join(crate_root).join(&rel);
            let text = fs::read_to_string(&source).unwrap_or_else(|_| panic!("{} has no test file {}", file.display(), source.display()));
            assert!(text.contains("proptest!"), "{} holds no property test", source.display());
            saved += 1;
        }
    }
    assert!(saved >= 4, "{saved} saved files found");
    // no saved cases anywhere else
    let everywhere: usize = ["src", "tests"].iter().map(|d| files_under(&root().join(d), "txt").iter().filter(|f| f.to_string_lossy().contains("proptest")).count()).sum();
    assert_eq!(everywhere, saved, "saved cases outside the folders proptest reads");
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
