//! `docs/configuration.md` lists every setting the binary defines, with its flag and default:
//! the table is checked against `--help` and the variables the code reads itself.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `COVERPLAN_…` names in a text.
fn variables(text: &str) -> BTreeSet<String> {
    text.match_indices("COVERPLAN_")
        .map(|(at, _)| text[at..].chars().take_while(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || *c == '_').collect::<String>())
        .filter(|v| v.len() > "COVERPLAN_".len())
        .collect()
}

/// Each variable of a command's `--help` with its default, when it has one.
fn help_defaults(args: &[&str]) -> BTreeMap<String, Option<String>> {
    let out = Command::new(env!("CARGO_BIN_EXE_coverplan")).args(args).arg("--help").output().unwrap();
    let help = String::from_utf8(out.stdout).unwrap();
    let mut found = BTreeMap::new();
    for line in help.lines() {
        let Some(at) = line.find("[env: ") else { continue };
        let name: String = line[at + 6..].chars().take_while(|c| *c != '=').collect();
        let default = line.split_once("[default: ").map(|(_, d)| d.split(']').next().unwrap().trim_matches('"').to_owned());
        found.insert(name, default);
    }
    found
}

/// The variables the code reads itself (`env::var`, `EnvFilter::try_from_env`) and the hidden flags.
fn read_directly() -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for file in ["src/main.rs", "src/server.rs", "src/telemetry.rs"] {
        let code = std::fs::read_to_string(root().join(file)).unwrap_or_default();
        for pattern in ["env::var(\"", "try_from_env(\"", "env = \""] {
            for (at, _) in code.match_indices(pattern) {
                out.extend(variables(&code[at..at + pattern.len() + 40]).into_iter().take(1));
            }
        }
    }
    out
}

/// The documented table's rows: variable → (flag, default) cells.
fn documented(path: &Path) -> BTreeMap<String, (String, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| l.starts_with("| `COVERPLAN_"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            (cells[1].trim_matches('`').to_owned(), (cells[2].trim_matches('`').to_owned(), cells[3].trim_matches('`').to_owned()))
        })
        .collect()
}

#[test]
fn the_configuration_page_lists_every_setting_with_its_default() {
    let docs = documented(&root().join("docs/configuration.md"));
    let mut helped = BTreeMap::new();
    for command in [&["serve"][..], &["keys"], &["healthcheck"]] {
        helped.extend(help_defaults(command));
    }
    assert!(helped.len() >= 15, "{helped:?}");
    let defined: BTreeSet<String> = helped.keys().cloned().chain(read_directly()).collect();
    let listed: BTreeSet<String> = docs.keys().cloned().collect();
    assert_eq!(listed, defined, "docs/configuration.md against the binary's settings");
    for (name, default) in &helped {
        let (flag, documented_default) = &docs[name];
        assert!(flag.starts_with("--"), "{name}: its flag is not documented");
        if let Some(default) = default {
            assert_eq!(documented_default, default, "{name}'s default");
        }
    }
}
