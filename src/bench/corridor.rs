//! `coverplan bench --corridor`: planner `corridor` on generated corridors 220 km long and 60 m
//! wide (a pipeline, QGroundControl #5695), winding in rows with wiggles and turns sharper than
//! a fixed wing's turning radius: planning time, length, time, batteries and coverage, for a
//! multirotor and a fixed wing, per seed.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Context;
use serde_json::{Value, json};

use super::Stream;
use crate::planner::frame::LocalFrame;
use crate::planner::geo::Coord;
use crate::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop};

const LENGTH_M: f64 = 220_000.0;
const WIDTH_M: f64 = 60.0;
/// Rows of the winding line, and the distance between them.
const ROW_M: f64 = 36_000.0;
const ROW_GAP_M: f64 = 3_000.0;
/// A vertex every this many metres.
const STEP_M: f64 = 100.0;

/// The centre line of seed `seed`: rows east and west joined by half turns, the heading
/// wandering ±25° about each row's, with a sharp kink (90° to 140° out and back) every 10 km.
pub fn centre_line(seed: u64) -> Vec<Coord> {
    let mut rng = Stream(seed.wrapping_mul(7919).wrapping_add(17));
    let (mut at, mut s, mut wander) = (Coord { x: -ROW_M / 2.0, y: 0.0 }, 0.0, 0.0f64);
    let mut points = vec![at];
    let mut row = 0usize;
    while s < LENGTH_M {
        let base = if row.is_multiple_of(2) { 0.0 } else { std::f64::consts::PI };
        let along_row = if row.is_multiple_of(2) { at.x + ROW_M / 2.0 } else { ROW_M / 2.0 - at.x };
        if along_row >= ROW_M {
            // a half turn of radius half the gap to the next row
            let r = ROW_GAP_M / 2.0;
            let centre = Coord { x: at.x, y: at.y + r };
            let side = if row.is_multiple_of(2) { 1.0 } else { -1.0 };
            let steps = (std::f64::consts::PI * r / STEP_M).ceil() as usize;
            for k in 1..=steps {
                let a = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * k as f64 / steps as f64;
                points.push(Coord { x: centre.x + side * r * a.cos(), y: centre.y + r * a.sin() });
            }
            at = *points.last().expect("a point");
            s += std::f64::consts::PI * r;
            row += 1;
            wander = 0.0;
            continue;
        }
        wander = (wander + (rng.next() - 0.5) * 0.2).clamp(-0.45, 0.45);
        let mut heading = base + wander;
        if (s / 10_000.0).fract() < STEP_M / 10_000.0 && s > 1_000.0 {
            // a kink: out at a sharp angle and back
            let kink = (90.0 + 50.0 * rng.next()).to_radians();
            let out = Coord { x: (heading + kink).cos(), y: (heading + kink).sin() } * 150.0;
            points.push(at + out);
            points.push(at + out + Coord { x: heading.cos(), y: heading.sin() } * 150.0);
            at = *points.last().expect("a point");
            s += 300.0;
            heading = base;
        }
        at = at + Coord { x: heading.cos(), y: heading.sin() } * STEP_M;
        points.push(at);
        s += STEP_M;
    }
    points
}

pub fn run(seeds: usize) -> anyhow::Result<String> {
    let profiles = planner::vehicle::builtin_profiles();
    let frame = LocalFrame::new(8.0, 47.0);
    let mut out = String::new();
    writeln!(
        out,
        "corridor: {LENGTH_M:.0} m long, {WIDTH_M} m wide, winding in rows {ROW_M:.0} m long with kinks of 90–140° every 10 km; no home (batteries are changed where they run out)\n"
    )?;
    writeln!(out, "| seed | vehicle | spacing (m) | plan (ms) | sweeps | flown (km) | time (h) | batteries | coverage |")?;
    writeln!(out, "|---|---|---|---|---|---|---|---|---|")?;
    for seed in 0..seeds as u64 {
        let line = centre_line(seed);
        let coordinates: Vec<Value> = line.iter().map(|c| json!(frame.to_wgs84(*c))).collect();
        let area = json!({"type": "Feature", "properties": {"width_m": WIDTH_M}, "geometry": {"type": "LineString", "coordinates": coordinates}});
        let mission = MissionGeometry::area(&area);
        for (vehicle, spacing) in [("iris", 25.0), ("generic_fixed_wing", 40.0)] {
            let params: PlanParams = serde_json::from_value(json!({"planner": "corridor", "line_spacing_m": spacing, "altitude_m": 80, "vehicle": {"profile": vehicle}}))?;
            let started = Instant::now();
            let plan = planner::plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).with_context(|| format!("seed {seed}, {vehicle}"))?;
            let ms = started.elapsed().as_secs_f64() * 1000.0;
            let s = &plan.stats;
            writeln!(
                out,
                "| {seed} | {vehicle} | {spacing} | {ms:.0} | {} | {:.1} | {:.1} | {} | {:.4} |",
                s.sweep_lines,
                s.length_m / 1000.0,
                s.duration_s / 3600.0,
                s.batteries_needed,
                s.coverage_ratio
            )?;
        }
    }
    Ok(out)
}
