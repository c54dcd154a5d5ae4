//! `coverplan bench` (built with `--features bench`): the tables it prints, and the command that
//! heads each one in `docs/benchmarks.md`.

use std::process::Command;

#[test]
fn the_routing_benchmark_prints_its_table_headed_by_its_command_in_markdown() {
    let out = Command::new(env!("CARGO_BIN_EXE_coverplan")).args(["bench", "--routing", "--markdown"]).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("```sh\ncargo run --release --features bench -- bench --routing --markdown\n```\n"), "{text}");
    // | lines | matrix ms | solve ms | total ms | length | boustrophedon | saved | Noon–Bean | ms |
    let rows: Vec<Vec<String>> = text
        .lines()
        .filter(|l| l.starts_with("| ") && l[2..].trim_start().starts_with(|c: char| c.is_ascii_digit()))
        .map(|l| l.split('|').map(|c| c.trim().to_string()).collect())
        .collect();
    assert_eq!(rows.iter().map(|r| r[1].as_str()).collect::<Vec<_>>(), ["100", "300", "600"], "{text}");
    for r in &rows {
        let number = |i: usize| r[i].parse::<f64>().unwrap_or_else(|_| panic!("column {i} of {r:?}"));
        assert!(number(5) < number(6), "the routed lines are no shorter than boustrophedon: {r:?}");
        assert!(number(8).is_finite() && number(8) < number(6), "the Noon–Bean route: {r:?}");
    }
}

/// `bench --fields2cover` rows per hole count: (holes, min coverage), and the header.
fn fields2cover_bench(extra: &[&str]) -> (String, Vec<(usize, f64)>) {
    let args = [&["bench", "--fields2cover", "--planner", "boustrophedon", "--fields", "h03_00,h08_00"], extra].concat();
    let out = Command::new(env!("CARGO_BIN_EXE_coverplan")).args(args).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    // | holes | fields | refused | median ms | p95 ms | peak MB | length | vs | efficiency | min coverage | …
    let rows = text
        .lines()
        .filter(|l| l.starts_with("| ") && l[2..].trim_start().starts_with(|c: char| c.is_ascii_digit()))
        .map(|l| l.split('|').map(str::trim).collect::<Vec<_>>())
        // the rows by hole count (the bins beside Fields2Cover read "1–5")
        .filter_map(|r| Some((r[1].parse().ok()?, r[10].parse().unwrap())))
        .collect();
    (text, rows)
}

#[test]
fn the_fields2cover_benchmark_flies_over_holes_only_when_asked() {
    let (zones_text, zones) = fields2cover_bench(&[]);
    let (over_text, over) = fields2cover_bench(&["--overfly-holes"]);
    assert!(zones_text.contains("holes as no-fly zones kept 1 m off"), "{zones_text}");
    assert!(over_text.contains("holes not to cover but free to fly over"), "{over_text}");
    assert_eq!(zones.iter().map(|r| r.0).collect::<Vec<_>>(), [3, 8], "{zones_text}");
    assert_eq!(over.iter().map(|r| r.0).collect::<Vec<_>>(), [3, 8], "{over_text}");
    // beside Fields2Cover's own figures of the same fields: h03_00 in the bin of 1–5 holes, h08_00 in 6–10
    for text in [&zones_text, &over_text] {
        let bins: Vec<&str> = text.lines().filter(|l| l.contains('–') && l.starts_with("| ")).collect();
        assert_eq!(bins.len(), 2, "{text}");
        assert!(bins[0].starts_with("|  1–5  |      1 |") && bins[1].starts_with("|  6–10 |      1 |"), "{text}");
    }
    // lines end at a zone with room to turn before it, so some ground beside each hole is left;
    // over holes that are no zones full-width lines run up to them
    for ((_, with_zones), (_, overflown)) in zones.iter().zip(&over) {
        assert!(*overflown >= 0.999 && with_zones < overflown, "coverage {with_zones} with zones, {overflown} flying over:\n{zones_text}\n{over_text}");
    }
}

#[test]
fn the_fields2cover_benchmark_reports_each_seed_of_the_generated_fields() {
    let run = |fields: &str| {
        let args = ["bench", "--fields2cover", "--planner", "naive", "--overfly-holes", "--fields", fields, "--markdown"];
        let out = Command::new(env!("CARGO_BIN_EXE_coverplan")).args(args).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).unwrap()
    };
    let two = run("h01_00,h01_02,h07_02");
    let table = &two[two.find("ours by seed").unwrap_or_else(|| panic!("no table by seed: {two}"))..];
    let rows: Vec<Vec<&str>> = table.lines().filter(|l| l.starts_with("| 0")).map(|l| l.split('|').map(str::trim).collect()).collect();
    // | seed | 0–0 | 1–5 | 6–10 | 11–15 |: seed 00 has one field of 1 hole, seed 02 one of 1 and one of 7
    assert_eq!(rows.iter().map(|r| r[1]).collect::<Vec<_>>(), ["00", "02"], "{table}");
    assert_eq!(rows[0][2..6].iter().map(|c| *c == "-").collect::<Vec<_>>(), [true, false, true, true], "{table}");
    assert_eq!(rows[1][2..6].iter().map(|c| *c == "-").collect::<Vec<_>>(), [true, false, false, true], "{table}");
    assert!(rows.iter().flat_map(|r| &r[2..6]).filter(|c| **c != "-").all(|c| c.parse::<f64>().is_ok_and(|e| e > 0.3 && e < 1.0)), "{table}");
    // one seed: no table by seed
    assert!(!run("h01_00,h07_00").contains("ours by seed"));
}
