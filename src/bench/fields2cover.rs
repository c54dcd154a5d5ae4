//! `coverplan bench --fields2cover`: each planner beside Fields2Cover 2.1's own plans of the same
//! fields (`tests/fixtures/peers/fields2cover-fixed-wing.json`), by bin of hole counts.

use std::fmt::Write;
use std::path::Path;

use anyhow::Context;
use serde_json::Value;

/// Bins of hole counts.
const BINS: [(usize, usize); 4] = [(0, 0), (1, 5), (6, 10), (11, 15)];

/// One run of a field as a planner planned it: its file name, holes, efficiency per covered
/// area ((covered area / w) / length) and planning time.
pub struct Planned {
    pub field: String,
    pub holes: usize,
    pub efficiency: f64,
    pub ms: f64,
}

/// Fields2Cover's figures of a field: efficiency per covered area and seconds.
fn peer(peers: &Value, field: &str) -> Option<(f64, f64)> {
    let f = peers["fields"].as_array()?.iter().find(|f| f["field"].as_str() == Some(field))?;
    Some((f["efficiency"].as_f64()? * f["swath_coverage"].as_f64()?, f["seconds_excluding_python_start"].as_f64()?))
}

/// The table of one planner beside Fields2Cover: per bin, both efficiencies and the median of
/// Fields2Cover's time over ours.
pub fn beside(data: &Path, planned: &[Planned]) -> anyhow::Result<String> {
    let path = data.join("../peers/fields2cover-fixed-wing.json");
    let peers: Value = serde_json::from_str(&std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?)?;
    let mut out = String::from(
        "beside Fields2Cover, efficiency per covered area ((covered area / w) / length), means by bin of hole counts; speed-up: Fields2Cover's time over ours, per field\n\n\
         | holes | fields | ours | Fields2Cover | median speed-up | least speed-up |\n|------:|-------:|-----:|-------------:|----------------:|---------------:|\n",
    );
    // one row per field: its runs' median time
    let mut fields: Vec<&str> = planned.iter().map(|p| p.field.as_str()).collect();
    fields.dedup();
    let per_field: Vec<(usize, f64, &str, f64)> = fields
        .iter()
        .map(|&f| {
            let runs: Vec<&Planned> = planned.iter().filter(|p| p.field == f).collect();
            let mut ms: Vec<f64> = runs.iter().map(|p| p.ms).collect();
            (runs[0].holes, runs[0].efficiency, f, super::quantile(&mut ms, 0.5))
        })
        .collect();
    for (lo, hi) in BINS {
        let rows: Vec<(f64, f64, f64)> = per_field
            .iter()
            .filter(|p| (lo..=hi).contains(&p.0))
            .filter_map(|&(_, efficiency, field, ms)| peer(&peers, field.trim_end_matches(".json")).map(|(eff, s)| (efficiency, eff, s * 1000.0 / ms)))
            .collect();
        if rows.is_empty() {
            continue;
        }
        let n = rows.len() as f64;
        let mut speed_ups: Vec<f64> = rows.iter().map(|r| r.2).collect();
        let least = speed_ups.iter().copied().fold(f64::INFINITY, f64::min);
        let median = super::quantile(&mut speed_ups, 0.5);
        let (ours, theirs) = (rows.iter().map(|r| r.0).sum::<f64>() / n, rows.iter().map(|r| r.1).sum::<f64>() / n);
        let _ = writeln!(out, "| {lo:>2}–{hi:<2} | {:>6} | {ours:.3} | {theirs:>12.3} | {median:>14.0}× | {least:>13.0}× |", rows.len());
    }
    out.push('\n');
    let seed = |field: &str| field.trim_end_matches(".json").rsplit('_').next().unwrap_or("").to_owned();
    let mut seeds: Vec<String> = per_field.iter().map(|p| seed(p.2)).collect();
    seeds.sort();
    seeds.dedup();
    if seeds.len() > 1 {
        // other seeds of the generator: fields of the same classes that the peers' figures do not cover
        out.push_str("ours by seed of the generated fields (the file name's suffix): mean efficiency per covered area by bin of hole counts\n\n| seed |");
        for (lo, hi) in BINS {
            let _ = write!(out, " {lo}–{hi} |");
        }
        out.push_str("\n|-----:|");
        out.push_str(&"------:|".repeat(BINS.len()));
        out.push('\n');
        for s in &seeds {
            let _ = write!(out, "| {s} |");
            for (lo, hi) in BINS {
                let bin: Vec<f64> = per_field.iter().filter(|p| seed(p.2) == *s && (lo..=hi).contains(&p.0)).map(|p| p.1).collect();
                let _ = if bin.is_empty() { write!(out, " - |") } else { write!(out, " {:.3} |", bin.iter().sum::<f64>() / bin.len() as f64) };
            }
            out.push('\n');
        }
        out.push('\n');
    }
    Ok(out)
}
