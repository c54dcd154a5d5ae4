//! `coverplan bench --fleet`: the last landing of 1, 2, 4 and 8 drones on the generated fields,
//! against the ideal: one drone's flight time shared out evenly, plus the longest flight out
//! from home to a part (which no split can shorten).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use serde_json::Value;

use super::{bench_spacing, home_south_west_of, quantile};
use crate::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop};

const FLEETS: [u32; 4] = [1, 2, 4, 8];

/// One fleet size's results over the fields.
#[derive(Default)]
struct Row {
    /// Last landing over the ideal.
    to_ideal: Vec<f64>,
    /// Last landing over one drone's flight time.
    to_one: Vec<f64>,
    ms: Vec<f64>,
    conflicts: usize,
}

/// The duration of the first piece each drone flies (its flight out from home), by drone.
fn flights_out(trajectory: &planner::geojson::FeatureCollection) -> f64 {
    let mut seen = std::collections::HashSet::new();
    let mut longest: f64 = 0.0;
    for f in &trajectory.features {
        let Some(p) = f.properties.as_ref() else { continue };
        let drone = p.get("vehicle").and_then(Value::as_u64).unwrap_or(0);
        if p.get("kind").and_then(Value::as_str) == Some("transit") && seen.insert(drone) {
            longest = longest.max(p.get("duration_s").and_then(Value::as_f64).unwrap_or(0.0));
        } else {
            seen.insert(drone);
        }
    }
    longest
}

pub fn run(dir: &Path, fields: &[String]) -> anyhow::Result<String> {
    let index: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).context("reading index.json")?)?;
    let entries: Vec<&Value> = index
        .as_array()
        .context("index.json is a list")?
        .iter()
        .filter(|e| {
            if fields.is_empty() { e["file"].as_str().is_some_and(|f| f.ends_with("_00.json")) } else { fields.iter().any(|f| e["file"].as_str() == Some(&format!("{f}.json"))) }
        })
        .collect();
    let mut rows: Vec<Row> = FLEETS.iter().map(|_| Row::default()).collect();
    let profiles = planner::vehicle::builtin_profiles();
    for e in &entries {
        let file = e["file"].as_str().context("file")?;
        let m: Value = serde_json::from_str(&std::fs::read_to_string(dir.join(file))?)?;
        let spacing = bench_spacing(e["area_m2"].as_f64().context("area_m2")?);
        let mission = MissionGeometry { home: Some(home_south_west_of(&m)?), ..MissionGeometry::of(&m) };
        let mut one = None;
        for (k, &n) in FLEETS.iter().enumerate() {
            let params = PlanParams { line_spacing_m: Some(spacing), vehicles: (n > 1).then_some(n), ..PlanParams::default() };
            let started = Instant::now();
            let Ok(out) = planner::plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()) else { continue };
            let ms = started.elapsed().as_secs_f64() * 1000.0;
            let makespan = out.stats.makespan_s.unwrap_or(out.stats.duration_s);
            let single = *one.get_or_insert(out.stats.duration_s);
            let ideal = single / n as f64 + flights_out(&out.trajectory);
            rows[k].to_ideal.push(makespan / ideal);
            rows[k].ms.push(ms);
            rows[k].conflicts += out.stats.conflicts.as_ref().map_or(0, Vec::len);
            rows[k].to_one.push(makespan / single);
        }
    }
    let mut out = String::new();
    writeln!(
        out,
        "fields: {} from {}; spacing sqrt(area)/20 within 5..60 m; generic_multirotor (548 Wh), home 50 m off the south-west corner; holes as no-fly zones\n",
        entries.len(),
        dir.display()
    )?;
    writeln!(out, "| drones | plans | last landing / one drone (median) | / ideal median | / ideal worst | conflicts | median ms | p95 ms |")?;
    writeln!(out, "|-------:|------:|----------------------------------:|---------------:|--------------:|----------:|----------:|-------:|")?;
    for (k, Row { to_ideal: ratio, ms, conflicts, to_one: share }) in rows.iter_mut().enumerate() {
        let worst = ratio.iter().copied().fold(f64::NAN, f64::max);
        writeln!(
            out,
            "| {:>6} | {:>5} | {:>34.3} | {:>14.3} | {:>13.3} | {:>9} | {:>9.1} | {:>6.1} |",
            FLEETS[k],
            ratio.len(),
            quantile(share, 0.5),
            quantile(ratio, 0.5),
            worst,
            conflicts,
            quantile(ms, 0.5),
            quantile(ms, 0.95)
        )?;
    }
    Ok(out)
}
