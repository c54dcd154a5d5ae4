//! `coverplan bench --terrain`: plans at 60 m above the ground of the public test terrains and of
//! generated ones (25 m cells, a 100 ha field each), beside the same plan at 60 m above home:
//! vertices per km of sweep against one per elevation cell crossed, the planning time the
//! profile adds per 100 ha, the energy over terrain against the flat plan, and the metres of
//! sweep the climb limits keep out of the ±5 m band.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use serde_json::{Value, json};

use super::quantile;
use crate::planner::terrain::ElevationModel;
use crate::planner::{self, FieldLimits, MissionGeometry, PlanOutput, PlanParams, Stop};

/// Generated terrains per class.
const SEEDS: u64 = 5;
const CELL_M: f64 = 25.0;

struct Case {
    class: String,
    mission: Value,
    model: ElevationModel,
}

/// One vehicle's figures on one terrain.
struct Measured {
    vertices_per_km: f64,
    cells_per_km: f64,
    extra_ms_per_100ha: f64,
    energy_ratio: f64,
    off_band_m: f64,
}

fn public_cases(dir: &Path) -> anyhow::Result<Vec<Case>> {
    ["hills-11", "ridge-11", "cliff-11", "jacksboro"]
        .iter()
        .map(|name| {
            let mission: Value = serde_json::from_str(&std::fs::read_to_string(dir.join(format!("{name}.json")))?)?;
            let bytes = std::fs::read(dir.join(format!("{name}.tif")))?;
            let model = ElevationModel::read(&bytes, name).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
            Ok(Case { class: format!("{name} (public)"), mission, model })
        })
        .collect()
}

/// A 5 km square in UTM 33N at 25 m: a tilted plain with Gaussian hills of `height` m and
/// `width` m (seeded), and with `cliff` m a step across the middle; a 1 km × 1 km field in the
/// middle and home 600 m south-west of it.
fn generated(class: &str, seed: u64, hills: usize, height: f64, width: f64, cliff: f64) -> anyhow::Result<Case> {
    let mut state = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
    let mut next = move || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let n = 201usize;
    let centres: Vec<(f64, f64, f64)> = (0..hills).map(|_| (next() * 5000.0, next() * 5000.0, height * (0.5 + next()))).collect();
    let tilt = (next() - 0.5) * 0.1;
    let heights = (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f64 * CELL_M, (n - 1 - i / n) as f64 * CELL_M);
            let hill: f64 = centres.iter().map(|&(cx, cy, h)| h * (-((x - cx).powi(2) + (y - cy).powi(2)) / (width * width)).exp()).sum();
            (300.0 + tilt * x + hill + cliff / (1.0 + (-(y - 2500.0) / 2.0).exp())) as f32
        })
        .collect();
    let model = ElevationModel::from_grid(n, n, heights, [400_000.0, 5_005_000.0], [CELL_M, -CELL_M], 32633).map_err(|e| anyhow::anyhow!("{e}"))?;
    let b = model.summary().bounds;
    let (lon, lat) = ((b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0);
    let (kx, ky) = (111_320.0 * lat.to_radians().cos(), 110_574.0);
    let at = |x: f64, y: f64| json!([lon + x / kx, lat + y / ky]);
    let ring = [at(-500.0, -500.0), at(500.0, -500.0), at(500.0, 500.0), at(-500.0, 500.0), at(-500.0, -500.0)];
    let mission = json!({"area": {"type": "Polygon", "coordinates": [ring]}, "home": [lon - 1100.0 / kx, lat - 1100.0 / ky]});
    Ok(Case { class: class.to_owned(), mission, model })
}

fn plan_once(case: &Case, params: &PlanParams, over_terrain: bool) -> anyhow::Result<(PlanOutput, f64)> {
    let geometry = MissionGeometry { no_fly_zones: None, terrain: over_terrain.then_some(&case.model), ..MissionGeometry::of(&case.mission) };
    let started = Instant::now();
    let out = planner::plan(&geometry, params, &planner::vehicle::builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never())
        .map_err(|e| anyhow::anyhow!("{}: {e}", case.class))?;
    Ok((out, started.elapsed().as_secs_f64() * 1000.0))
}

fn measure(case: &Case, vehicle: &Value, repeats: usize) -> anyhow::Result<Measured> {
    let flat: PlanParams = serde_json::from_value(json!({"altitude_m": 60, "line_spacing_m": 60, "vehicle": vehicle, "max_climb_deg": 12}))?;
    let over = PlanParams { altitude_reference: Some(planner::params::AltitudeReference::Terrain), ..flat.clone() };
    let (mut flat_ms, mut over_ms) = (f64::INFINITY, f64::INFINITY);
    let (mut flat_out, mut over_out) = (None, None);
    for _ in 0..repeats.max(1) {
        let (out, ms) = plan_once(case, &flat, false)?;
        flat_ms = flat_ms.min(ms);
        flat_out = Some(out);
        let (out, ms) = plan_once(case, &over, true)?;
        over_ms = over_ms.min(ms);
        over_out = Some(out);
    }
    let (flat_out, over_out) = (flat_out.context("planned")?, over_out.context("planned")?);
    let terrain = over_out.stats.terrain.as_ref().context("terrain figures")?;
    let hectares = flat_out.stats.area_to_cover_m2 / 10_000.0;
    let cell_m = case.model.summary().cell_size_m;
    Ok(Measured {
        vertices_per_km: terrain.waypoints_per_sweep_km,
        // a path crossing cells of this size diagonally on average
        cells_per_km: 1000.0 / (cell_m[0].min(cell_m[1])),
        extra_ms_per_100ha: (over_ms - flat_ms) / hectares * 100.0,
        energy_ratio: over_out.stats.energy_j / flat_out.stats.energy_j,
        off_band_m: terrain.sweep_outside_tolerance_m,
    })
}

pub fn run(dir: &Path, repeats: usize) -> anyhow::Result<String> {
    let mut cases: Vec<Vec<Case>> = public_cases(dir)?.into_iter().map(|c| vec![c]).collect();
    // (class, hills, height, width, cliff)
    let classes = [("gentle hills (≤ 8°)", 6, 40.0, 500.0, 0.0), ("steep hills (≤ 35°)", 8, 150.0, 220.0, 0.0), ("cliff of 60 m", 3, 30.0, 500.0, 60.0)];
    for (class, hills, height, width, cliff) in classes {
        cases.push((0..SEEDS).map(|seed| generated(class, seed, hills, height, width, cliff)).collect::<anyhow::Result<_>>()?);
    }
    let mut out = String::new();
    writeln!(
        out,
        "| terrain | vehicle | cases | vertices per km of sweep | elevation cells per km | extra planning ms per 100 ha | energy over terrain / flat | sweep outside ±5 m (m) |"
    )?;
    writeln!(out, "|---|---|---:|---:|---:|---:|---:|---:|")?;
    for class in &cases {
        for (name, vehicle) in [("multirotor", json!({"profile": "generic_multirotor"})), ("fixed wing", json!({"kind": "fixed_wing"}))] {
            let measured: Vec<Measured> = class.iter().map(|c| measure(c, &vehicle, repeats)).collect::<anyhow::Result<_>>()?;
            let median = |f: fn(&Measured) -> f64| {
                let mut v: Vec<f64> = measured.iter().map(f).collect();
                quantile(&mut v, 0.5)
            };
            writeln!(
                out,
                "| {} | {name} | {} | {:.1} | {:.0} | {:.1} | {:.2} | {:.0} |",
                class[0].class,
                class.len(),
                median(|m| m.vertices_per_km),
                median(|m| m.cells_per_km),
                median(|m| m.extra_ms_per_100ha),
                median(|m| m.energy_ratio),
                median(|m| m.off_band_m)
            )?;
        }
    }
    writeln!(out, "\nMedians over the cases of each class; plans at 60 m above ground, lines 60 m apart; the fixed wing climbs at most 12°.")?;
    Ok(out)
}
