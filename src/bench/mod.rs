//! `coverplan bench`: planning time and plan quality per planner and per hole count, over the
//! generated fields (`tests/fixtures/random-fields` by default), printed as a table;
//! `--routing`, `--energy`, `--patrol`, `--fleet`, `--ground`, `--inspection`, `--terrain`,
//! `--resume`, `--wind`, `--corridor`, `--oblique`, `--farm`, `--workers` and `--queue` run the
//! routing, energy, patrolling, fleet, ground-vehicle, inspection, terrain, resume, wind,
//! corridor, oblique, farm, worker-pool and shared-queue benchmarks instead.

mod command;
pub mod corridor;
pub mod energy;
pub mod farm;
mod fields2cover;
pub mod fleet;
pub mod ground;
pub mod inspection;
pub mod oblique;
pub mod patrol;
pub mod queue;
pub mod resume;
pub mod terrain;
pub mod wind;
pub mod workers;

pub use command::{BenchArgs, run_command};

use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use serde_json::Value;

use crate::planner::params::SwathEnds;
use crate::planner::planners::registry;
use crate::planner::vehicle::{VehicleKind, VehicleParams};
use crate::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop};

struct Row {
    holes: usize,
    times_ms: Vec<f64>,
    /// Peak resident memory of each run, MB (Linux).
    peak_mb: Vec<f64>,
    /// Fields the planner refused (not applicable, or over its limits).
    refused: usize,
    lengths_m: Vec<f64>,
    efficiency: Vec<f64>,
    coverage: Vec<f64>,
    /// Length over the boustrophedon planner's on the same field.
    vs_reference: Vec<f64>,
    /// Where the length goes: sweep over the lower bound (area / spacing), turns, transits.
    sweep_over_bound: Vec<f64>,
    turns_m: Vec<f64>,
    transits_m: Vec<f64>,
}

/// A reproducible stream of numbers in [0, 1) (SplitMix64): generated corridors and farms.
pub(crate) struct Stream(pub u64);

impl Stream {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) as f64 / u64::MAX as f64
    }
}

fn quantile(v: &mut [f64], q: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    let idx = ((v.len() - 1) as f64 * q).round() as usize;
    v[idx]
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// A home 50 m outside the south-west corner of the bounding box of a field file's first
/// polygon, `[lon, lat]`.
pub fn home_south_west_of(field: &serde_json::Value) -> anyhow::Result<[f64; 2]> {
    use anyhow::Context;
    let ring = field["area"]["coordinates"][0].as_array().context("a polygon")?;
    let (lon, lat) = ring.iter().fold((f64::INFINITY, f64::INFINITY), |(x, y), p| (x.min(p[0].as_f64().unwrap_or(x)), y.min(p[1].as_f64().unwrap_or(y))));
    Ok([lon - 50.0 / (111_320.0 * lat.to_radians().cos()), lat - 50.0 / 110_574.0])
}

/// Line spacing for a field: a twentieth of the square root of its area, 5 to 60 m (about 20
/// lines across a square field), so that fields of 1 to 200 ha get comparable plans.
pub fn bench_spacing(area_m2: f64) -> f64 {
    (area_m2.sqrt() / 20.0).clamp(5.0, 60.0)
}

/// Fields2Cover's configuration for fixed wings (issue 19): width max(8, √area / 25), turning
/// radius half of it, zones kept 1 m off, on the fields `h*_00`.
pub fn fields2cover_spacing(area_m2: f64) -> f64 {
    (area_m2.sqrt() / 25.0).max(8.0)
}

/// Fields2Cover 2.1's figures in that configuration (its route planner, Dubins turns, no
/// headland), measured on this machine when issue 19 was filed.
const FIELDS2COVER_FIXED_WING: &str = "Fields2Cover 2.1 (route planner, Dubins r = w/2, no headland, centre-line swath ends), measured here: median efficiency 0.840 over the 16 fields, 0.884 on h00_00 (no holes), 2.7–3.8 s a field with process start (the times below leave it out); its turns cross holes 149 times";

/// What to benchmark.
pub struct Options<'a> {
    pub planner: Option<&'a str>,
    pub repeats: usize,
    /// `multirotor` (default) or `fixed_wing`.
    pub vehicle: Option<&'a str>,
    /// Line spacing for every field instead of the area rule; a fixed wing turns at half of it.
    pub spacing_m: Option<f64>,
    /// Only these field files (without `.json`).
    pub fields: &'a [String],
    /// Where lines end at slanted edges (`swath_ends`); `None`: the planners' default.
    pub ends: Option<&'a str>,
    /// Fields2Cover's fixed-wing configuration ([`fields2cover_spacing`]) on the fields `h*_00`.
    pub fields2cover: bool,
    /// With `fields2cover`: the fields of every seed of the generator, not only `h*_00`.
    pub every_seed: bool,
    /// The fields' holes are only not to be covered, free to fly over (as Fields2Cover treats
    /// them), instead of also being no-fly zones.
    pub overfly_holes: bool,
}

/// Resets the process's peak resident memory (Linux: `/proc/self/clear_refs`), so that the next
/// [`peak_mb`] reads the peak of what runs in between.
fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// The process's peak resident memory since [`reset_peak`], MB; `None` where `/proc` has none.
fn peak_mb() -> Option<f64> {
    peak_mb_of("self")
}

/// Process `process`'s (a pid, or `self`) peak resident memory, MB.
fn peak_mb_of(process: &str) -> Option<f64> {
    let status = std::fs::read_to_string(format!("/proc/{process}/status")).ok()?;
    let kb: f64 = status.lines().find(|l| l.starts_with("VmHWM:"))?.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Runs the benchmark and returns the table as text.
pub fn run(dir: &Path, options: &Options<'_>) -> anyhow::Result<String> {
    let index: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).context("reading index.json")?)?;
    let entries: Vec<&Value> = index
        .as_array()
        .context("index.json is a list")?
        .iter()
        .filter(|e| match (options.fields.is_empty(), e["file"].as_str()) {
            (true, Some(file)) => !options.fields2cover || options.every_seed || file.ends_with("_00.json"),
            (_, file) => options.fields.iter().any(|f| file == Some(&format!("{f}.json"))),
        })
        .collect();
    anyhow::ensure!(!entries.is_empty(), "no field of {} matches {:?}", dir.display(), options.fields);
    let fixed_wing = match options.vehicle.unwrap_or(if options.fields2cover { "fixed_wing" } else { "multirotor" }) {
        "multirotor" => false,
        "fixed_wing" => true,
        other => anyhow::bail!("--vehicle is multirotor or fixed_wing, not {other}"),
    };
    let ends: Option<SwathEnds> = options.ends.map(|e| serde_json::from_value(Value::from(e))).transpose().context("--ends is full_width, balanced or centre_line")?;
    let repeats = options.repeats.max(1);
    let spacing_rule = match (options.spacing_m, options.fields2cover) {
        (Some(s), _) => format!("{s} m"),
        (None, true) => "max(8, sqrt(area)/25) m".to_owned(),
        (None, false) => "sqrt(area)/20 within 5..60 m".to_owned(),
    };
    let vehicle = if fixed_wing { "fixed wing turning at half the spacing" } else { "multirotor" };
    let holes = match (options.overfly_holes, options.fields2cover) {
        (true, _) => "holes not to cover but free to fly over",
        (false, true) => "holes as no-fly zones kept 1 m off",
        (false, false) => "holes as no-fly zones kept 10 m off",
    };
    let ends_rule = options.ends.unwrap_or("the planners' default");
    let mut out = String::new();
    out.push_str(&format!("fields: {} from {}; {repeats} runs each; spacing {spacing_rule}; {vehicle}; {holes}; line ends {ends_rule}\n", entries.len(), dir.display()));
    if options.fields2cover {
        out.push_str(&format!("beside: {FIELDS2COVER_FIXED_WING}\n"));
    }
    out.push('\n');
    // lengths of the reference planner (the first one, `boustrophedon`) per field
    let mut reference: std::collections::HashMap<String, f64> = std::collections::HashMap::new();
    // a battery large enough that no plan is split into sorties
    let mut profiles = planner::vehicle::builtin_profiles();
    profiles.iter_mut().for_each(|v| v.battery.energy_wh = 1e5);
    for p in registry().iter().filter(|p| !p.for_ground_vehicles() && !p.follows_corridors() && options.planner.is_none_or(|f| f == p.id())) {
        let mut rows: Vec<Row> = (0..=15)
            .map(|holes| Row {
                holes,
                refused: 0,
                times_ms: vec![],
                peak_mb: vec![],
                lengths_m: vec![],
                efficiency: vec![],
                coverage: vec![],
                vs_reference: vec![],
                sweep_over_bound: vec![],
                turns_m: vec![],
                transits_m: vec![],
            })
            .collect();
        let mut beside: Vec<fields2cover::Planned> = Vec::new();
        for &e in &entries {
            let file = e["file"].as_str().context("file")?;
            let holes = e["holes"].as_u64().context("holes")? as usize;
            let m: Value = serde_json::from_str(&std::fs::read_to_string(dir.join(file))?)?;
            let area_m2 = e["area_m2"].as_f64().context("area_m2")?;
            let spacing = options.spacing_m.unwrap_or_else(|| if options.fields2cover { fields2cover_spacing(area_m2) } else { bench_spacing(area_m2) });
            let mut params = PlanParams {
                planner: Some(p.id().into()),
                line_spacing_m: Some(spacing),
                swath_ends: ends.filter(|_| p.lays_parallel_lines()),
                nfz_margin_m: options.fields2cover.then_some(1.0),
                ..PlanParams::default()
            };
            if fixed_wing {
                params.vehicle = VehicleParams { kind: Some(VehicleKind::FixedWing), turn_radius_m: Some(spacing / 2.0), ..VehicleParams::default() };
                // Fields2Cover's paths enter each swath from its turn
                params.lead_in_m = options.fields2cover.then_some(0.0);
            }
            let mut mission = MissionGeometry::area(&m["area"]);
            if !options.overfly_holes {
                mission.no_fly_zones = m.get("no_fly_zones").filter(|v| !v.is_null());
            }
            for _ in 0..repeats {
                reset_peak();
                let t = Instant::now();
                let row = &mut rows[holes.min(15)];
                let Ok(plan) = planner::plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()) else {
                    row.refused += 1;
                    continue;
                };
                let ms = t.elapsed().as_secs_f64() * 1000.0;
                row.times_ms.push(ms);
                let s = &plan.stats;
                beside.push(fields2cover::Planned { field: file.to_string(), holes, efficiency: s.coverage_ratio * s.area_to_cover_m2 / spacing / s.length_m, ms });
                row.peak_mb.extend(peak_mb());
                row.lengths_m.push(plan.stats.length_m);
                if p.id() == registry()[0].id() {
                    reference.insert(file.to_string(), plan.stats.length_m);
                }
                if let Some(r) = reference.get(file) {
                    row.vs_reference.push(plan.stats.length_m / r);
                }
                row.efficiency.push(plan.stats.efficiency);
                row.coverage.push(plan.stats.coverage_ratio);
                row.sweep_over_bound.push(plan.stats.sweep_length_m / plan.stats.lower_bound_m);
                row.turns_m.push(plan.stats.turn_length_m);
                row.transits_m.push(plan.stats.transit_length_m);
            }
        }
        out.push_str(&format!("planner {}\n", p.id()));
        out.push_str(&format!(
            "| holes | fields | refused | median ms | p95 ms | peak MB | mean length m | length / {} | mean efficiency | min coverage | sweep / bound | turns m | transits m |\n",
            registry()[0].id()
        ));
        out.push_str(
            "|------:|-------:|--------:|----------:|-------:|--------:|--------------:|----------:|----------------:|-------------:|--------------:|--------:|-----------:|\n",
        );
        for r in rows.iter_mut().filter(|r| !r.times_ms.is_empty() || r.refused > 0) {
            let n = r.times_ms.len() / repeats;
            if n == 0 {
                // every field of the row refused: no figures to show
                out.push_str(&format!("| {:>5} | {:>6} | {:>7} | - | - | - | - | - | - | - | - | - | - |\n", r.holes, 0, r.refused / repeats));
                continue;
            }
            let median = quantile(&mut r.times_ms, 0.5);
            let p95 = quantile(&mut r.times_ms, 0.95);
            out.push_str(&format!(
                "| {:>5} | {:>6} | {:>7} | {:>9.2} | {:>6.2} | {:>7.0} | {:>13.0} | {:>9} | {:>15.3} | {:>12.4} | {:>13.3} | {:>7.0} | {:>10.0} |\n",
                r.holes,
                n,
                r.refused / repeats,
                median,
                p95,
                r.peak_mb.iter().copied().fold(f64::NAN, f64::max),
                mean(&r.lengths_m),
                if r.vs_reference.is_empty() { "-".to_string() } else { format!("{:.3}", mean(&r.vs_reference)) },
                mean(&r.efficiency),
                r.coverage.iter().copied().fold(f64::INFINITY, f64::min),
                mean(&r.sweep_over_bound),
                mean(&r.turns_m),
                mean(&r.transits_m)
            ));
        }
        out.push('\n');
        if options.fields2cover && !beside.is_empty() {
            out.push_str(&fields2cover::beside(dir, &beside)?);
        }
    }
    Ok(out)
}

/// `coverplan bench --routing`: line-level routing of 100, 300 and 600 parallel 1 km lines,
/// 20 m apart, with Dubins turns of radius 50 m (so the best order skips lines), against the
/// plain boustrophedon order 1, 2, 3, … of the same lines, and against the standard route of
/// seeds 003 and 004: the Noon–Bean transformation to an asymmetric TSP, solved by Or-opt and
/// as many kicks.
pub fn routing() -> String {
    use std::fmt::Write;
    let mut out = String::from("routing: parallel lines 1000 m long, 20 m apart, Dubins radius 50 m, free start and end\n\n");
    out.push_str("| lines | cost matrix ms | solve ms | total ms | length m | boustrophedon m | saved | Noon–Bean ATSP m | its solve ms |\n|------:|--------------:|---------:|---------:|---------:|----------------:|------:|-----------------:|-------------:|\n");
    for n in [100, 300, 600] {
        let r = planner::routing_study::parallel_lines(n);
        let _ = writeln!(
            out,
            "| {n:5} | {:13.1} | {:8.1} | {:8.1} | {:8.0} | {:15.0} | {:4.1} % | {:16.0} | {:12.1} |",
            r.cost_matrix_ms,
            r.solve_ms,
            r.cost_matrix_ms + r.solve_ms,
            r.length_m,
            r.boustrophedon_m,
            100.0 * (1.0 - r.length_m / r.boustrophedon_m),
            r.noon_bean_m,
            r.noon_bean_ms
        );
    }
    out
}
