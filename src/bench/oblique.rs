//! `coverplan bench --oblique`: pattern `oblique` (the nadir grid and four passes with the
//! gimbal pitched) against the nadir grid alone, on a square field and the generated fields
//! (holes as no-fly zones): length, photos, each oblique pass's share of the area imaged, and
//! planning time; beside MAVLink PR #1508's figures for its one-pass pseudo-oblique survey.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use serde_json::{Value, json};

use crate::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop};

/// The camera and its height: a 1-inch 20 MP camera at 100 m (2.7 cm/px).
const CAMERA: &str = "dji_phantom4_pro";
const ALTITUDE_M: f64 = 100.0;
/// PR #1508's overlaps: front/side 80/70 % for its nadir survey, 80/75 % for its oblique one.
const NADIR_OVERLAPS: (f64, f64) = (0.8, 0.7);
const OBLIQUE_OVERLAPS: (f64, f64) = (0.8, 0.75);

/// A square field `side` metres wide near Zurich.
fn square(side: f64) -> Value {
    let (lon, lat) = (8.5f64, 47.4f64);
    let (dlon, dlat) = (side / (111_320.0 * lat.to_radians().cos()), side / 111_320.0);
    json!({"type": "Polygon", "coordinates": [[[lon, lat], [lon + dlon, lat], [lon + dlon, lat + dlat], [lon, lat + dlat], [lon, lat]]]})
}

pub fn run(dir: &Path, fields: &[String]) -> anyhow::Result<String> {
    let index: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).context("reading index.json")?)?;
    let wanted = |f: &str| if fields.is_empty() { f.ends_with("_00.json") } else { fields.iter().any(|w| f == format!("{w}.json")) };
    let mut missions: Vec<(String, Value)> = vec![("square 900 m".into(), json!({"area": square(900.0)}))];
    for e in index.as_array().context("index.json is a list")?.iter().filter(|e| e["file"].as_str().is_some_and(wanted)) {
        let file = e["file"].as_str().context("file")?;
        missions.push((file.trim_end_matches(".json").to_owned(), serde_json::from_str(&std::fs::read_to_string(dir.join(file))?)?));
    }
    let profiles = planner::vehicle::builtin_profiles();
    let mut out = String::new();
    writeln!(
        out,
        "camera {CAMERA} at {ALTITUDE_M} m, gimbal at −45° on the oblique passes; nadir grid at front/side {:.0}/{:.0} %, oblique plan at {:.0}/{:.0} %; multirotor `iris`, no home\n",
        NADIR_OVERLAPS.0 * 100.0,
        NADIR_OVERLAPS.1 * 100.0,
        OBLIQUE_OVERLAPS.0 * 100.0,
        OBLIQUE_OVERLAPS.1 * 100.0
    )?;
    writeln!(out, "| field | nadir (km) | nadir photos | oblique (km) | oblique photos | per pass (km, photos) | least pass imaged | × length | × photos | plan (ms) |")?;
    writeln!(out, "|---|---|---|---|---|---|---|---|---|---|")?;
    for (name, m) in &missions {
        let mission = MissionGeometry::of(m);
        let params = |pattern: &str, (front, side): (f64, f64)| -> anyhow::Result<PlanParams> {
            Ok(serde_json::from_value(json!({
                "vehicle": {"profile": "iris"}, "camera": {"preset": CAMERA}, "altitude_m": ALTITUDE_M,
                "front_overlap": front, "side_overlap": side, "pattern": pattern,
            }))?)
        };
        let nadir =
            planner::plan(&mission, &params("grid", NADIR_OVERLAPS)?, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).with_context(|| format!("{name}, grid"))?;
        let started = Instant::now();
        let oblique = planner::plan(&mission, &params("oblique", OBLIQUE_OVERLAPS)?, &profiles, &FieldLimits::default(), &|_| true, &Stop::never())
            .with_context(|| format!("{name}, oblique"))?;
        let ms = started.elapsed().as_secs_f64() * 1000.0;
        let (n, o) = (&nadir.stats, &oblique.stats);
        let passes: Vec<String> = o.passes.iter().map(|p| format!("{:.1}, {}", p.length_m / 1000.0, p.photos)).collect();
        let least = o.passes.iter().map(|p| p.photo_coverage_ratio).fold(f64::INFINITY, f64::min);
        writeln!(
            out,
            "| {name} | {:.1} | {} | {:.1} | {} | {} | {least:.4} | {:.2} | {:.2} | {ms:.0} |",
            n.length_m / 1000.0,
            n.photos,
            o.length_m / 1000.0,
            o.photos,
            passes.join("; "),
            o.length_m / n.length_m,
            o.photos as f64 / n.photos as f64
        )?;
    }
    writeln!(out, "| MAVLink PR #1508 (one pass, camera rolled ±20° between shots; its field) | 9.2 | 213 | 6.0 | 338 | (one pass) | | 0.65 | 1.59 | |")?;
    Ok(out)
}
