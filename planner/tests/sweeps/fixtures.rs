//! The fixture fields the service's tests share (`tests/fixtures/` at the repository's root).

use std::path::PathBuf;

use serde_json::Value;

/// The fixtures' folder.
pub fn fixtures_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures")
}

/// A fixture file, parsed; `path` is relative to `tests/fixtures/`.
pub fn fixture(path: &str) -> Value {
    let p = fixtures_dir().join(path);
    serde_json::from_str(&std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).unwrap()
}
