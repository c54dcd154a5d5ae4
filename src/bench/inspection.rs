//! `coverplan bench --inspection`: planner `inspection` on seed 001's first scene rebuilt
//! (spec `inspection.md` §11: one 8 × 8 m building of 4 floors, 12 m, points every 0.5 m on
//! its walls and roof, the source's 57° × 44.3° camera and 0.3–5.5 m range, a 0.5 m body with
//! 0.5 m margin) at budgets of 50, 100, 200 and 300 m, with 300 viewpoints and no extension,
//! and with the sphere and the ellipse extensions; and a barn with a silo at 300 m. Each row:
//! the share of points seen (mean and least over the seeds), viewpoints flown and sampled,
//! length, search iterations, time (median) and peak memory.

use std::fmt::Write as _;
use std::time::Instant;

use serde_json::{Value, json};

use super::{peak_mb, quantile, reset_peak};
use crate::planner::frame::LocalFrame;
use crate::planner::geo::Coord;
use crate::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop};

/// A structure of a benchmark scene: a footprint in local metres, or a cylinder's centre and
/// radius.
struct Solid<'a> {
    name: &'a str,
    footprint: &'a [(f64, f64)],
    height_m: f64,
    radius_m: Option<f64>,
}

/// A mission in a square of `half` metres around the origin with these structures.
fn mission(half: f64, structures: &[Solid<'_>], home: (f64, f64)) -> Value {
    let frame = LocalFrame::new(10.0, 52.0);
    let at = |(x, y): (f64, f64)| {
        let [lon, lat] = frame.to_wgs84(Coord { x, y });
        json!([lon, lat])
    };
    let ring = |pts: &[(f64, f64)]| {
        let mut r: Vec<Value> = pts.iter().map(|&p| at(p)).collect();
        r.push(r[0].clone());
        json!([r])
    };
    let features: Vec<Value> = structures
        .iter()
        .map(|s| match s.radius_m {
            Some(r) => {
                json!({"type": "Feature", "properties": {"name": s.name, "height_m": s.height_m, "radius_m": r}, "geometry": {"type": "Point", "coordinates": at(s.footprint[0])}})
            }
            None => json!({"type": "Feature", "properties": {"name": s.name, "height_m": s.height_m}, "geometry": {"type": "Polygon", "coordinates": ring(s.footprint)}}),
        })
        .collect();
    json!({
        "area": {"type": "Polygon", "coordinates": ring(&[(-half, -half), (half, -half), (half, half), (-half, half)])},
        "structures": {"type": "FeatureCollection", "features": features},
        "home": at(home),
    })
}

const HEADER: &str = "| scene | budget m | viewpoints | extension | seen (mean) | seen (least) | flown | sampled | length m | iterations | ms (median) | peak MB |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";

struct Row<'a> {
    scene: &'a str,
    mission: &'a Value,
    budget_m: f64,
    extension: &'a str,
    options: Value,
    camera: Value,
}

fn row(out: &mut String, r: &Row<'_>, seeds: u64) {
    let m = MissionGeometry { no_fly_zones: None, obstacles: None, ..MissionGeometry::of(r.mission) };
    let profiles = planner::vehicle::builtin_profiles();
    let (mut shares, mut times, mut flown, mut sampled, mut lengths, mut iterations) = (Vec::new(), Vec::new(), 0, 0, 0.0, 0);
    let mut options = r.options.clone();
    options["extension"] = json!(r.extension);
    let mut peak: f64 = 0.0;
    for seed in 1..=seeds {
        let params: PlanParams = match serde_json::from_value(json!({
            "planner": "inspection",
            "vehicle": {"profile": "iris"},
            "camera": r.camera,
            "budget": {"max_length_m": r.budget_m},
            "inspection": options,
            "seed": seed,
            "time_limit_s": 300,
        })) {
            Ok(p) => p,
            Err(e) => {
                let _ = writeln!(out, "| {} | {} | refused: {e} |", r.scene, r.budget_m);
                return;
            }
        };
        reset_peak();
        let started = Instant::now();
        let planned = planner::plan(&m, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never());
        times.push(started.elapsed().as_secs_f64() * 1000.0);
        peak = peak.max(peak_mb().unwrap_or(f64::NAN));
        let o = match planned {
            Ok(o) => o,
            Err(e) => {
                let _ = writeln!(out, "| {} | {} | refused: {e} |", r.scene, r.budget_m);
                return;
            }
        };
        let ins = o.stats.inspection.clone().unwrap_or_default();
        shares.push(o.stats.inspection_coverage.unwrap_or(0.0));
        flown += ins.viewpoints;
        sampled += ins.viewpoints_sampled;
        lengths += o.stats.length_m;
        iterations += ins.iterations;
    }
    let n = seeds as f64;
    let mean = shares.iter().sum::<f64>() / n;
    let least = shares.iter().copied().fold(1.0, f64::min);
    let _ = writeln!(
        out,
        "| {} | {:.0} | {} | {} | {:.3} | {:.3} | {:.0} | {:.0} | {:.1} | {:.0} | {:.0} | {:.0} |",
        r.scene,
        r.budget_m,
        r.options["viewpoints"],
        r.extension,
        mean,
        least,
        flown as f64 / n,
        sampled as f64 / n,
        lengths / n,
        iterations as f64 / n,
        quantile(&mut times, 0.5),
        peak
    );
}

pub fn run(repeats: usize) -> String {
    let seeds = repeats.max(1) as u64;
    let mut out = String::new();
    let _ = writeln!(out, "release build, {seeds} seeds a row (1..={seeds}), planning time includes sampling and visibility\n");
    out.push_str(HEADER);
    let building = Solid { name: "scene-1", footprint: &[(0.0, 0.0), (8.0, 0.0), (8.0, 8.0), (0.0, 8.0)], height_m: 12.0, radius_m: None };
    let scene_one = mission(30.0, &[building], (-12.0, 4.0));
    let source_camera = json!({"hfov_deg": 57.0, "image_width_px": 160, "image_height_px": 120});
    let reach = json!({"range_m": [0.3, 5.5], "body_radius_m": 0.5, "safety_margin_m": 0.5, "viewpoints": 300});
    for extension in ["none", "sphere", "ellipse"] {
        for budget_m in [50.0, 100.0, 200.0, 300.0] {
            let r = Row { scene: "scene 1", mission: &scene_one, budget_m, extension, options: reach.clone(), camera: source_camera.clone() };
            row(&mut out, &r, seeds);
        }
    }
    let barn = Solid { name: "barn", footprint: &[(-12.0, -6.0), (12.0, -6.0), (12.0, 6.0), (-12.0, 6.0)], height_m: 8.0, radius_m: None };
    let silo = Solid { name: "silo", footprint: &[(22.0, 0.0)], height_m: 14.0, radius_m: Some(3.0) };
    let barn = mission(60.0, &[barn, silo], (0.0, -25.0));
    let defaults = json!({"viewpoints": 300});
    for extension in ["none", "sphere"] {
        let r = Row {
            scene: "barn + silo (M3E camera, 1–12 m)",
            mission: &barn,
            budget_m: 300.0,
            extension,
            options: defaults.clone(),
            camera: json!({"preset": "dji_mavic3_enterprise"}),
        };
        row(&mut out, &r, seeds);
    }
    out
}
