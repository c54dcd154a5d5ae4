//! Fleets: one area flown by several drones at once (docs/methods.md, fleets).
//!
//! The area is cut into bands along the sweep lines, one per drone ([`partition`]); each band
//! is planned for its drone like a plan of its own (by the caller's `plan_part`), and the bands
//! are resized from the drones' planned durations until the last drone lands as early as the
//! cuts allow (the makespan, not the sum). [`timeline`] then finds where two drones come too
//! close at the same time.

pub mod partition;
pub mod timeline;

use geo::{Area, Coord, MultiPolygon};
use rayon::prelude::*;

use crate::error::PlanError;
use partition::{Bands, equal_finish};

/// A drone as the balancing sees it.
#[derive(Debug, Clone, Copy)]
pub struct Drone {
    pub cruise_speed_mps: f64,
    pub home: Option<Coord>,
    /// Seconds after the fleet's start it takes off.
    pub departure_s: f64,
}

/// What balancing needs to know of a drone's planned part.
#[derive(Debug, Clone, Copy)]
pub struct PartTimes {
    /// Take-off to last landing, battery changes excluded.
    pub duration_s: f64,
    /// Of it, the time that does not grow with the part's area: the flights between home and
    /// the part, take-off and landing.
    pub fixed_s: f64,
}

/// Plans one drone's part: what it made, and the times balancing needs.
pub type PlanPart<'a, T> = dyn Fn(usize, &MultiPolygon) -> Result<(T, PartTimes), PlanError> + Sync + 'a;

/// Rounds of resizing: each plans every part once.
pub const ROUNDS: usize = 4;

/// The fleet's parts: for each drone, in the request's order, its part of the region and what
/// `plan_part` made of it (`None`: the drone is not needed).
pub struct Assignment<T> {
    pub parts: Vec<Option<(MultiPolygon, T)>>,
    /// Latest landing, departures included.
    pub makespan_s: f64,
}

/// Splits `region` into bands across direction `angle` (strips `spacing` wide) for `drones`, plans
/// each with `plan_part(drone, part)`, and resizes the bands until the drones land together.
/// Beside it, the fastest drone plans the whole region alone: where cutting costs more than
/// sharing saves (bands strung across holes, each flown out to), it lands first and flies alone.
/// `round_done(k)` is called after each round and may cancel by returning false.
pub fn assign<T: Send>(
    region: &MultiPolygon,
    angle: f64,
    spacing: f64,
    drones: &[Drone],
    plan_part: &PlanPart<'_, T>,
    round_done: &dyn Fn(usize) -> bool,
) -> Result<Assignment<T>, PlanError> {
    let fastest = (0..drones.len())
        .min_by(|&a, &b| drones[b].cruise_speed_mps.total_cmp(&drones[a].cruise_speed_mps).then(drones[a].departure_s.total_cmp(&drones[b].departure_s)))
        .ok_or_else(|| PlanError::Infeasible("a fleet needs a drone".into()))?;
    let mut alone = None;
    let shared = rayon::in_place_scope(|scope| {
        scope.spawn(|_| alone = Some(plan_part(fastest, region)));
        balanced(region, angle, spacing, drones, plan_part, round_done)
    });
    let alone = alone.expect("the scope waits for its tasks");
    // the whole region may be refused where its parts are not (a planner's search limit)
    let alone = match alone {
        Ok((t, times)) => Some((t, drones[fastest].departure_s + times.duration_s)),
        Err(PlanError::Cancelled) => return Err(PlanError::Cancelled),
        Err(_) => None,
    };
    match (shared?, alone) {
        (Some(best), Some((_, alone_s))) if best.makespan_s <= alone_s => Ok(best),
        (Some(best), None) => Ok(best),
        (_, Some((t, makespan_s))) => {
            let mut parts: Vec<Option<(MultiPolygon, T)>> = (0..drones.len()).map(|_| None).collect();
            parts[fastest] = Some((region.clone(), t));
            Ok(Assignment { parts, makespan_s })
        }
        (None, None) => Err(PlanError::Infeasible("the fleet's parts could not be planned".into())),
    }
}

/// The bands resized over [`ROUNDS`]: the assignment that lands first (`None`: no round planned).
fn balanced<T: Send>(
    region: &MultiPolygon,
    angle: f64,
    spacing: f64,
    drones: &[Drone],
    plan_part: &PlanPart<'_, T>,
    round_done: &dyn Fn(usize) -> bool,
) -> Result<Option<Assignment<T>>, PlanError> {
    let bands = Bands::new(region, angle, spacing);
    let total = region.unsigned_area();
    // bands are handed out in the order of the drones' homes across the lines
    let mut order: Vec<usize> = (0..drones.len()).collect();
    order.sort_by(|&a, &b| {
        let across = |k: usize| drones[k].home.map_or(0.0, |h| bands.across(h));
        across(a).total_cmp(&across(b)).then(a.cmp(&b))
    });
    // first guess: area in proportion to speed, no fixed time
    let mut fixed: Vec<f64> = drones.iter().map(|d| d.departure_s).collect();
    let mut rate: Vec<f64> = drones.iter().map(|d| 1.0 / (d.cruise_speed_mps * spacing)).collect();
    let mut best: Option<Assignment<T>> = None;
    let mut tried: Vec<Vec<usize>> = Vec::new();
    for round in 0..ROUNDS {
        let areas = equal_finish(&fixed, &rate, total);
        let in_band_order: Vec<f64> = order.iter().map(|&k| areas[k]).collect();
        let cuts = bands.cuts(&in_band_order);
        if tried.contains(&cuts) {
            break;
        }
        tried.push(cuts.clone());
        let mut strips = vec![(0, 0); drones.len()];
        for (slot, &k) in order.iter().enumerate() {
            strips[k] = (cuts[slot], cuts[slot + 1]);
        }
        let planned: Vec<Option<(MultiPolygon, T, PartTimes)>> = strips
            .par_iter()
            .enumerate()
            .map(|(k, &(from, to))| {
                let part = bands.part(region, from, to);
                if part.unsigned_area() < 1.0 {
                    return Ok(None);
                }
                plan_part(k, &part).map(|(t, times)| Some((part, t, times)))
            })
            .collect::<Result<_, PlanError>>()?;
        if !round_done(round) {
            return Err(PlanError::Cancelled);
        }
        let makespan_s = planned.iter().zip(drones).filter_map(|(p, d)| p.as_ref().map(|(_, _, t)| d.departure_s + t.duration_s)).fold(0.0, f64::max);
        // the model of each drone's duration, refitted on what was planned
        for (k, p) in planned.iter().enumerate() {
            if let Some((part, _, times)) = p {
                let area = part.unsigned_area();
                fixed[k] = drones[k].departure_s + times.fixed_s;
                rate[k] = ((times.duration_s - times.fixed_s) / area).max(1e-9);
            }
        }
        if best.as_ref().is_none_or(|b| makespan_s < b.makespan_s) {
            let parts = planned.into_iter().map(|p| p.map(|(part, t, _)| (part, t))).collect();
            best = Some(Assignment { parts, makespan_s });
        }
    }
    Ok(best)
}
