//! `coverplan bench --wind`: plans made for the wind against the plan made as in still air,
//! flown in the same wind, on the generated fields (holes as no-fly zones) for a multirotor
//! (energy) and a fixed wing (time), at 0.3 and 0.5 of the airspeed from 8 directions; and how
//! far the still-air estimate is from the flight in wind.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use serde_json::{Value, json};

use super::{bench_spacing, home_south_west_of, quantile};
use crate::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop};

/// Wind speeds as shares of the airspeed, and the directions it blows from.
const STRENGTHS: [f64; 2] = [0.3, 0.5];
const DIRECTIONS: usize = 8;

#[derive(Default)]
struct Row {
    /// 1 − wind-aware figure / still-air plan's figure in the same wind.
    saving: Vec<f64>,
    /// The still-air plan's figure in wind over its still-air estimate, less 1.
    still_air_error: Vec<f64>,
    /// Plans where the wind-aware choice differs from the still-air plan.
    changed: usize,
    /// Plans whose still-air lines a fixed wing could not turn between in this wind (another
    /// direction's plan was given).
    unflyable: usize,
    ms: Vec<f64>,
}

pub fn run(dir: &Path, fields: &[String]) -> anyhow::Result<String> {
    let index: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).context("reading index.json")?)?;
    let wanted = |f: &str| if fields.is_empty() { f.ends_with("_00.json") || f.ends_with("_01.json") } else { fields.iter().any(|w| f == format!("{w}.json")) };
    let entries: Vec<&Value> = index.as_array().context("index.json is a list")?.iter().filter(|e| e["file"].as_str().is_some_and(wanted)).collect();
    let profiles = planner::vehicle::builtin_profiles();
    // (profile, objective, what the row compares)
    let vehicles = [("iris", "energy"), ("generic_fixed_wing", "time")];
    let mut rows: Vec<Vec<Row>> = vehicles.iter().map(|_| STRENGTHS.iter().map(|_| Row::default()).collect()).collect();
    for e in &entries {
        let file = e["file"].as_str().context("file")?;
        let m: Value = serde_json::from_str(&std::fs::read_to_string(dir.join(file))?)?;
        let spacing = bench_spacing(e["area_m2"].as_f64().context("area_m2")?);
        let mission = MissionGeometry { home: Some(home_south_west_of(&m)?), ..MissionGeometry::of(&m) };
        for (vehicle_rows, (vehicle, objective)) in rows.iter_mut().zip(vehicles) {
            let cruise = profiles.iter().find(|p| p.profile == vehicle).context("a built-in profile")?.cruise_speed_mps;
            let params = |wind: Option<Value>| -> anyhow::Result<PlanParams> {
                Ok(serde_json::from_value(json!({"vehicle": {"profile": vehicle}, "line_spacing_m": spacing, "altitude_m": 60, "objective": objective, "wind": wind}))?)
            };
            let pick = |s: &planner::metrics::Stats| if objective == "time" { s.duration_s } else { s.energy_j };
            let Ok(still) = planner::plan(&mission, &params(None)?, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()) else { continue };
            for (row, strength) in vehicle_rows.iter_mut().zip(STRENGTHS) {
                for d in 0..DIRECTIONS {
                    let wind = json!({"speed_mps": strength * cruise, "from_deg": d as f64 * 360.0 / DIRECTIONS as f64});
                    let started = Instant::now();
                    let windy = planner::plan(&mission, &params(Some(wind))?, &profiles, &FieldLimits::default(), &|_| true, &Stop::never())
                        .with_context(|| format!("{file}, {vehicle}, wind {strength} of the airspeed from {d}/8"))?;
                    row.ms.push(started.elapsed().as_secs_f64() * 1000.0);
                    if (windy.stats.sweep_heading_deg - still.stats.sweep_heading_deg).abs() > 0.01 {
                        row.changed += 1;
                    }
                    let w = windy.stats.wind.as_ref().context("the wind in the stats")?;
                    let Some(today) = (if objective == "time" { w.still_air_plan_duration_s } else { w.still_air_plan_energy_j }) else {
                        row.unflyable += 1;
                        continue;
                    };
                    row.saving.push(1.0 - pick(&windy.stats) / today);
                    row.still_air_error.push(today / pick(&still.stats) - 1.0);
                }
            }
        }
    }
    let mut out = String::new();
    writeln!(
        out,
        "fields: {} from {}; spacing sqrt(area)/20 within 5..60 m, 60 m up, home 50 m off the south-west corner, holes as no-fly zones; winds from {DIRECTIONS} directions; \
         saving: 1 − the wind-aware plan's figure / the still-air plan's flown in the same wind (multirotor: energy, holding its ground speed; fixed wing: time, holding its airspeed); \
         still-air error: how much more the still-air plan costs in the wind than its still-air estimate says; \
         still-air lines unflyable: a fixed wing found no turn clear of the zones between them in this wind (another direction's plan was given)\n",
        entries.len(),
        dir.display()
    )?;
    writeln!(
        out,
        "| vehicle | figure | wind / airspeed | plans | heading changed | still-air lines unflyable | saving median | saving worst | saving best | still-air error median | (max) | median ms |"
    )?;
    writeln!(
        out,
        "|---------|--------|----------------:|------:|----------------:|--------------------------:|--------------:|-------------:|------------:|-----------------------:|------:|----------:|"
    )?;
    for ((vehicle, objective), vehicle_rows) in vehicles.iter().zip(rows.iter_mut()) {
        for (strength, row) in STRENGTHS.iter().zip(vehicle_rows.iter_mut()) {
            let worst = row.saving.iter().copied().fold(f64::INFINITY, f64::min);
            let best = row.saving.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let error_max = row.still_air_error.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            writeln!(
                out,
                "| {vehicle} | {objective} | {strength:.1} | {} | {} | {} | {:.2} % | {:.2} % | {:.2} % | {:+.1} % | {:+.1} % | {:.0} |",
                row.ms.len(),
                row.changed,
                row.unflyable,
                100.0 * quantile(&mut row.saving, 0.5),
                100.0 * worst,
                100.0 * best,
                100.0 * quantile(&mut row.still_air_error, 0.5),
                100.0 * error_max,
                quantile(&mut row.ms, 0.5)
            )?;
        }
    }
    Ok(out)
}
