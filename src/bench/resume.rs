//! `coverplan bench --resume`: how long resuming a plan takes, on the generated fields (holes as
//! no-fly zones) for a multirotor and a fixed wing, cut at ten places along each plan's path,
//! and how much longer the resumed plan is than what the original had left; and how long the
//! same cuts take from a flight log (the path flown up to the cut, a position every 2 m).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use serde_json::{Value, json};

use super::{bench_spacing, home_south_west_of, quantile};
use crate::planner::params::resume::ResumeParams;
use crate::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop};

/// Cuts per plan, evenly along its pieces (each halfway along its piece).
const CUTS: usize = 10;

#[derive(Default)]
struct Row {
    plans: usize,
    ms: Vec<f64>,
    /// The resumed plan's length over the original's after the cut.
    to_left: Vec<f64>,
    /// Cuts after the last line (nothing left).
    nothing_left: usize,
    /// The same cuts from the track flown up to them.
    log_ms: Vec<f64>,
}

/// The plan's path `[lon, lat]` up to halfway along the piece `seq`, a point every 2 m: what a
/// log of the flight stopped there holds.
fn track_to(trajectory: &crate::planner::geojson::FeatureCollection, seq: u64) -> Vec<[f64; 2]> {
    let mut path: Vec<[f64; 2]> = Vec::new();
    for f in &trajectory.features {
        let Some(p) = f.properties.as_ref() else { continue };
        let Some(crate::planner::geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { continue };
        if !matches!(p.get("kind").and_then(Value::as_str), Some("sweep" | "turn" | "transit")) {
            continue;
        }
        let at = p.get("seq").and_then(Value::as_u64).unwrap_or(0);
        let points: Vec<[f64; 2]> = coordinates.iter().map(|c| [c[0], c[1]]).collect();
        let keep = if at == seq { points.len().div_ceil(2).max(1) } else { points.len() };
        path.extend_from_slice(&points[..keep]);
        if at == seq {
            break;
        }
    }
    let mut track = Vec::new();
    for w in path.windows(2) {
        let k = w[0][1].to_radians().cos();
        let metres = ((w[1][0] - w[0][0]) * k).hypot(w[1][1] - w[0][1]) * 111_320.0;
        let n = (metres / 2.0).ceil().max(1.0) as usize;
        track.extend((0..n).map(|i| {
            let t = i as f64 / n as f64;
            [w[0][0] + (w[1][0] - w[0][0]) * t, w[0][1] + (w[1][1] - w[0][1]) * t]
        }));
    }
    track.extend(path.last().copied());
    track
}

pub fn run(dir: &Path, fields: &[String]) -> anyhow::Result<String> {
    let index: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).context("reading index.json")?)?;
    let wanted = |f: &str| if fields.is_empty() { f.ends_with("_00.json") || f.ends_with("_01.json") } else { fields.iter().any(|w| f == format!("{w}.json")) };
    let entries: Vec<&Value> = index.as_array().context("index.json is a list")?.iter().filter(|e| e["file"].as_str().is_some_and(wanted)).collect();
    let profiles = planner::vehicle::builtin_profiles();
    let vehicles = ["iris", "generic_fixed_wing"];
    let mut rows: Vec<Row> = vehicles.iter().map(|_| Row::default()).collect();
    for e in &entries {
        let file = e["file"].as_str().context("file")?;
        let m: Value = serde_json::from_str(&std::fs::read_to_string(dir.join(file))?)?;
        let spacing = bench_spacing(e["area_m2"].as_f64().context("area_m2")?);
        let mission = MissionGeometry { home: Some(home_south_west_of(&m)?), ..MissionGeometry::of(&m) };
        for (row, vehicle) in rows.iter_mut().zip(vehicles) {
            let params: PlanParams = serde_json::from_value(json!({"vehicle": {"profile": vehicle}, "line_spacing_m": spacing, "altitude_m": 60}))?;
            let Ok(original) = planner::plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()) else { continue };
            row.plans += 1;
            let seqs: Vec<u64> = original
                .trajectory
                .features
                .iter()
                .filter_map(|f| f.properties.as_ref())
                .filter(|p| matches!(p.get("kind").and_then(Value::as_str), Some("sweep" | "turn" | "transit")))
                .filter_map(|p| p.get("seq").and_then(Value::as_u64))
                .collect();
            for k in 0..CUTS {
                let seq = seqs[k * seqs.len() / CUTS];
                let request: ResumeParams = serde_json::from_value(json!({"at": {"seq": seq, "fraction": 0.5}}))?;
                let request = request.check().map_err(|e| anyhow::anyhow!("{e}"))?;
                let started = Instant::now();
                match planner::resume(&mission, &params, &profiles, &FieldLimits::default(), &original.trajectory, &request, &|_| true, &Stop::never()) {
                    Ok(resumed) => {
                        row.ms.push(started.elapsed().as_secs_f64() * 1000.0);
                        let left = resumed.stats.resume.as_ref().map_or(f64::NAN, |r| r.original_left_m);
                        row.to_left.push(resumed.stats.length_m / left);
                    }
                    Err(e) if e.to_string().contains("nothing is left") => row.nothing_left += 1,
                    Err(e) => anyhow::bail!("{file}, {vehicle}, cut at seq {seq}: {e}"),
                }
                // a log stopped halfway along the way to the first line holds one position: none
                let flown: ResumeParams = serde_json::from_value(json!({"flown": {"track": track_to(&original.trajectory, seq)}}))?;
                let Ok(flown) = flown.check() else { continue };
                let started = Instant::now();
                planner::resume(&mission, &params, &profiles, &FieldLimits::default(), &original.trajectory, &flown, &|_| true, &Stop::never())
                    .with_context(|| format!("{file}, {vehicle}, from a log stopped at seq {seq}"))?;
                row.log_ms.push(started.elapsed().as_secs_f64() * 1000.0);
            }
        }
    }
    let mut out = String::new();
    writeln!(
        out,
        "fields: {} from {}; spacing sqrt(area)/20 within 5..60 m, 60 m up, home 50 m off the south-west corner, holes as no-fly zones; {CUTS} cuts a plan, each halfway along a piece spread evenly over the path; from a log: the path flown to the same cuts, a position every 2 m (a cut on the way to the first line gives a log of one position, left out)\n",
        entries.len(),
        dir.display()
    )?;
    writeln!(
        out,
        "| vehicle | plans | resumes | nothing left | median ms | p95 ms | max ms | length / original's rest (median) | (p95) | from a log: resumes | median ms | p95 ms |"
    )?;
    writeln!(
        out,
        "|---------|------:|--------:|-------------:|----------:|-------:|-------:|-----------------------------------:|------:|--------------------:|----------:|-------:|"
    )?;
    for (vehicle, row) in vehicles.iter().zip(rows.iter_mut()) {
        let max = row.ms.iter().copied().fold(0.0, f64::max);
        writeln!(
            out,
            "| {vehicle} | {} | {} | {} | {:.1} | {:.1} | {:.1} | {:.3} | {:.3} | {} | {:.1} | {:.1} |",
            row.plans,
            row.ms.len(),
            row.nothing_left,
            quantile(&mut row.ms, 0.5),
            quantile(&mut row.ms, 0.95),
            max,
            quantile(&mut row.to_left, 0.5),
            quantile(&mut row.to_left, 0.95),
            row.log_ms.len(),
            quantile(&mut row.log_ms, 0.5),
            quantile(&mut row.log_ms, 0.95)
        )?;
    }
    Ok(out)
}
