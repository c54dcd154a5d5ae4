//! The farm's schedule: fields shared among machines, ordered, and laid out over working days
//! (docs/methods.md, farms).
//!
//! Two constructions of each machine's round (its fields in order), each improved, the one that
//! finishes first kept:
//! - by insertion: each field, the longest first, to the machine whose estimated working time it
//!   raises least, at the cheapest place of its round; then local search on the estimates;
//! - by days: the least busy machine goes out for a day to its farthest unworked field, then
//!   works the nearest ones (on the way home) that fit the day.
//!
//! Both are improved on the days laid out: a day leaves the depot and comes back within the
//! machine's hours; a field that does not fit the rest of a day is begun if at least
//! [`MIN_PIECE_S`] of it fits and taken up again the next morning; a machine refills after
//! `endurance_s` of work. The lower bound counts the work, the refills a day needs and each
//! field's nearest arrival.

use jiff::civil::{Date, Time};
use serde::{Deserialize, Serialize};
use serde_with::skip_serializing_none;

use super::days::clock_at;
use super::rounds::{Places, Rounds, Worker};
use super::{DEFAULT_HOURS_PER_DAY, DEFAULT_REFILL_S, DEFAULT_ROAD_SPEED_MPS, FieldWork, Machine, Transit, Window};
use crate::error::{InputError, PlanError, check_range};
use crate::stop::Stop;

/// A field is not begun, or taken up again, for less work than this (s) unless that finishes it.
pub const MIN_PIECE_S: f64 = 900.0;
/// Most fields and machines one schedule takes.
pub const MAX_FIELDS: usize = 2_000;
pub const MAX_MACHINES: usize = 100;

/// Which machine works which field when, and the figures to judge it by.
#[skip_serializing_none]
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Schedule {
    /// Each machine's days, in the request's order.
    pub machines: Vec<MachineSchedule>,
    /// Working time (transits and refills included, nights left out) of the machine that
    /// finishes last, s.
    pub makespan_s: f64,
    /// No schedule finishes earlier: the greatest of the total work over the machines, the
    /// longest field with its transits from and to the nearest depot, and the bound that also
    /// counts each field's nearest arrival, each day's drive home and the refills a day needs, s.
    pub lower_bound_s: f64,
    /// `makespan_s / lower_bound_s` (1 = no schedule can do better).
    pub makespan_over_bound: f64,
    /// When the last machine is home: local date and time, `YYYY-MM-DDTHH:MM`.
    pub ends_at: String,
    /// Working days from the first to the last machine home.
    pub days_used: u32,
    /// Whether the work fits the window's days.
    pub fits_window: bool,
    pub work_s: f64,
    pub transit_s: f64,
    pub transit_m: f64,
    /// Of the machines' working time, the share spent in transit.
    pub transit_share: f64,
    pub refills: usize,
    /// Working hours left unused at the ends of days (a field that did not fit), s.
    pub idle_s: f64,
    /// Fields no machine can work, with the reason.
    pub unscheduled: Vec<Unscheduled>,
    pub warnings: Vec<String>,
}

/// A machine's part of the schedule.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct MachineSchedule {
    pub machine: String,
    /// Fields it works (a field over several days counted once).
    pub fields: usize,
    /// Its working time, transits and refills included, s.
    pub working_time_s: f64,
    pub work_s: f64,
    pub transit_s: f64,
    pub transit_m: f64,
    pub refills: usize,
    /// Its working hours left unused at the ends of days, s.
    pub idle_s: f64,
    pub days: Vec<Day>,
}

/// A machine's working day, from the depot and back.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Day {
    /// 1 for the window's first day.
    pub day: u32,
    /// `YYYY-MM-DD`.
    pub date: String,
    pub legs: Vec<Leg>,
}

/// A stretch of a machine's day.
#[skip_serializing_none]
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Leg {
    pub kind: LegKind,
    /// The field worked, or driven to (its index in the farm's fields); none for the way home.
    pub field: Option<usize>,
    /// Local time, `HH:MM:SS`.
    pub start: String,
    pub end: String,
    /// Seconds after the day's start.
    pub start_s: f64,
    pub end_s: f64,
    /// Transits: metres driven.
    pub distance_m: Option<f64>,
    /// Work: whether it finishes the field (false: the field is taken up again later).
    pub finishes_field: Option<bool>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum LegKind {
    Transit,
    Work,
    Refill,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Unscheduled {
    pub field: usize,
    pub reason: String,
}

/// Checks the machines and the window, as [`schedule`] does before it begins.
pub fn check_setup(machines: &[Machine], window: &Window) -> Result<(), InputError> {
    check_window(window)?;
    workers(machines, window).map(drop)
}

impl Schedule {
    /// Names the fields by `index[i]` instead of `i` (the schedule was made of some of a
    /// farm's fields) and adds `not_scheduled`, fields left out before scheduling.
    pub fn renumber(&mut self, index: &[usize], not_scheduled: Vec<Unscheduled>) {
        for leg in self.machines.iter_mut().flat_map(|m| m.days.iter_mut()).flat_map(|d| d.legs.iter_mut()) {
            leg.field = leg.field.map(|i| index[i]);
        }
        for u in &mut self.unscheduled {
            u.field = index[u.field];
        }
        self.unscheduled.extend(not_scheduled);
        self.unscheduled.sort_by_key(|u| u.field);
        self.warnings.retain(|w| !w.ends_with(UNSCHEDULED_WARNING));
        if !self.unscheduled.is_empty() {
            self.warnings.push(format!("{} fields{UNSCHEDULED_WARNING}", self.unscheduled.len()));
        }
    }
}

const UNSCHEDULED_WARNING: &str = " are not in the schedule (see `unscheduled`)";

/// A stretch of a machine's day on one field: the share of the field's work done in it, from
/// `from` to `to` (0 to 1; a field worked in one go is 0 to 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stretch {
    pub field: usize,
    pub from: f64,
    pub to: f64,
}

impl Schedule {
    /// Each machine's days (as `machines[k].days`) as the stretches of work on each field, in
    /// order: a field's work legs of one day, refills between them, make one stretch.
    pub fn stretches(&self) -> Vec<Vec<Vec<Stretch>>> {
        let work = |leg: &&Leg| leg.kind == LegKind::Work && leg.field.is_some();
        let mut total: std::collections::HashMap<usize, f64> = std::collections::HashMap::new();
        for leg in self.machines.iter().flat_map(|m| &m.days).flat_map(|d| &d.legs).filter(work) {
            *total.entry(leg.field.expect("worked field")).or_default() += leg.end_s - leg.start_s;
        }
        let mut done: std::collections::HashMap<usize, f64> = std::collections::HashMap::new();
        let mut share = |field: usize, seconds: f64| {
            let whole = total[&field];
            let so_far = done.entry(field).or_default();
            let from = if whole > 0.0 { *so_far / whole } else { 0.0 };
            *so_far += seconds;
            // the last stretch ends at 1 exactly, whatever the sum's rounding
            let to = if whole > 0.0 && *so_far / whole < 1.0 - 1e-9 { *so_far / whole } else { 1.0 };
            (from, to)
        };
        self.machines
            .iter()
            .map(|m| {
                m.days
                    .iter()
                    .map(|day| {
                        let mut stretches: Vec<Stretch> = Vec::new();
                        for leg in day.legs.iter().filter(work) {
                            let field = leg.field.expect("worked field");
                            let (from, to) = share(field, leg.end_s - leg.start_s);
                            match stretches.last_mut() {
                                Some(last) if last.field == field => last.to = to,
                                _ => stretches.push(Stretch { field, from, to }),
                            }
                        }
                        stretches
                    })
                    .collect()
            })
            .collect()
    }
}

/// Schedules `fields` over `machines` within `window`, with transits priced by `transit`.
pub fn schedule(fields: &[FieldWork], machines: &[Machine], window: &Window, transit: &dyn Transit, stop: &Stop) -> Result<Schedule, PlanError> {
    let (first_day, day_start) = check_window(window)?;
    let workers = workers(machines, window)?;
    if fields.len() > MAX_FIELDS {
        return Err(InputError::new("too_many_fields", "/fields", format!("{} fields; one farm plan takes at most {MAX_FIELDS}", fields.len())).into());
    }
    let mut places: Vec<[f64; 2]> = machines.iter().map(|m| m.depot).collect();
    places.extend(fields.iter().flat_map(|f| [f.entry, f.exit]));
    let places = Places { machines: machines.len(), n: places.len(), metres: transit.distances(&places) };
    let plan = Rounds { fields, workers: &workers, places: &places };
    // two constructions, each improved on the days laid out; the one that finishes first is kept
    let (mut by_insertion, unscheduled) = plan.first_rounds();
    plan.improve(&mut by_insertion, stop)?;
    plan.balance_days(&mut by_insertion, stop)?;
    let mut by_days = plan.rounds_by_days(&unscheduled);
    plan.balance_days(&mut by_days, stop)?;
    let finish = |rounds: &[Vec<usize>]| rounds.iter().enumerate().map(|(k, r)| plan.working_time(k, r)).fold(0.0, f64::max);
    let rounds = if finish(&by_days) <= finish(&by_insertion) { by_days } else { by_insertion };
    if stop.requested() {
        return Err(PlanError::Cancelled);
    }
    let laid_out: Vec<MachineSchedule> = rounds.iter().enumerate().map(|(k, r)| plan.lay_out(k, r, first_day, day_start)).collect();
    Ok(plan.summary(laid_out, unscheduled, window, first_day, day_start))
}

fn check_window(window: &Window) -> Result<(Date, Time), InputError> {
    let date: Date =
        window.start_date.parse().map_err(|_| InputError::new("invalid_date", "/window/start_date", format!("`{}` is not a date written YYYY-MM-DD", window.start_date)))?;
    check_range(f64::from(window.days), 1.0, 366.0, "/window/days", "days")?;
    if let Some(h) = window.hours_per_day {
        check_range(h, 0.5, 24.0, "/window/hours_per_day", "h")?;
    }
    let start = match &window.day_start {
        None => Time::constant(7, 0, 0, 0),
        Some(s) => s.parse().map_err(|_| InputError::new("invalid_time", "/window/day_start", format!("`{s}` is not a time of day written HH:MM")))?,
    };
    Ok((date, start))
}

fn workers(machines: &[Machine], window: &Window) -> Result<Vec<Worker>, InputError> {
    if machines.is_empty() || machines.len() > MAX_MACHINES {
        return Err(InputError::new("parameter_out_of_range", "/machines", format!("{} machines; a farm plan takes 1 to {MAX_MACHINES}", machines.len())));
    }
    machines
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let at = |member: &str| format!("/machines/{k}/{member}");
            crate::field::check_position(&m.depot, &at("depot"))?;
            let hours = m.hours_per_day.or(window.hours_per_day).unwrap_or(DEFAULT_HOURS_PER_DAY);
            check_range(hours, 0.5, 24.0, &at("hours_per_day"), "h")?;
            let speed = m.road_speed_mps.unwrap_or(DEFAULT_ROAD_SPEED_MPS);
            check_range(speed, 0.5, 60.0, &at("road_speed_mps"), "m/s")?;
            let endurance_s = m.endurance_s.unwrap_or(f64::INFINITY);
            if m.endurance_s.is_some() {
                check_range(endurance_s, 60.0, 1e7, &at("endurance_s"), "s")?;
            }
            let refill_s = m.refill_s.unwrap_or(DEFAULT_REFILL_S);
            check_range(refill_s, 0.0, 86_400.0, &at("refill_s"), "s")?;
            Ok(Worker { name: m.name.clone().unwrap_or_else(|| format!("machine {}", k + 1)), day_s: hours * 3600.0, speed, endurance_s, refill_s })
        })
        .collect()
}

impl Rounds<'_> {
    /// A bound that counts what every schedule spends besides work: each field is driven to at
    /// least once, from a depot or another field (at the fastest road speed), each working day
    /// ends with the drive home from some field's exit (at least `b_k`, the nearest one), and a
    /// machine refills at least `work / endurance − 1` times a day. With `a_k = 1 + R_k / H_k`
    /// and `g_k = 1 + R_k / E_k` (refill time R, day H, endurance E; both 1 without a tank),
    /// machine k's working time T_k over its n_k ≥ T_k / H_k days satisfies
    /// `a_k T_k + R_k ≥ g_k work_k + arrivals_k + n_k b_k`; summed over the machines, the
    /// makespan T ≥ (min g · total work + Σ first arrivals − Σ R) / Σ max(0, a_k − b_k / H_k).
    fn bound_with_transits_and_refills(&self, scheduled: &[usize]) -> f64 {
        let (p, w) = (self.places, self.workers);
        let refill = |k: usize| if w[k].endurance_s.is_finite() { w[k].refill_s } else { 0.0 };
        let fastest = w.iter().map(|w| w.speed).fold(0.0, f64::max);
        let arrivals: f64 = scheduled
            .iter()
            .map(|&i| {
                let from_fields = scheduled.iter().filter(|&&j| j != i).map(|&j| p.metres(p.exit(j), p.entry(i)));
                let from_depots = (0..w.len()).map(|k| p.metres(p.depot(k), p.entry(i)));
                from_fields.chain(from_depots).fold(f64::INFINITY, f64::min) / fastest
            })
            .sum();
        let work: f64 = scheduled.iter().map(|&i| self.fields[i].work_s).sum();
        let g = (0..w.len()).map(|k| 1.0 + refill(k) / w[k].endurance_s).fold(f64::INFINITY, f64::min);
        let home = |k: usize| scheduled.iter().map(|&i| self.seconds(k, p.exit(i), p.depot(k))).fold(f64::INFINITY, f64::min);
        let a: f64 = (0..w.len()).map(|k| (1.0 + (refill(k) - home(k)) / w[k].day_s).max(0.0)).sum();
        if a <= 0.0 {
            // no machine has a working day (nothing scheduled)
            return 0.0;
        }
        let refills: f64 = (0..w.len()).map(refill).sum();
        ((g * work + arrivals - refills) / a).max(0.0)
    }

    fn summary(&self, machines: Vec<MachineSchedule>, unscheduled: Vec<Unscheduled>, window: &Window, first_day: Date, day_start: Time) -> Schedule {
        let m = self.workers.len();
        let scheduled: Vec<usize> = (0..self.fields.len()).filter(|i| !unscheduled.iter().any(|u| u.field == *i)).collect();
        // refills left out here (a night refills too); the third bound counts them
        let total: f64 = scheduled.iter().map(|&i| self.fields[i].work_s).sum();
        let longest = scheduled
            .iter()
            .map(|&i| (0..m).filter(|&k| self.reachable(k, i)).map(|k| self.fields[i].work_s + self.joins(k, None, i, None)).fold(f64::INFINITY, f64::min))
            .fold(0.0, f64::max);
        let lower_bound_s = (total / m as f64).max(longest).max(self.bound_with_transits_and_refills(&scheduled));
        let makespan_s = machines.iter().map(|s| s.working_time_s).fold(0.0, f64::max);
        let days_used = machines.iter().map(|s| s.days.last().map_or(0, |d| d.day)).max().unwrap_or(0);
        let last_home =
            machines.iter().filter_map(|s| s.days.last().and_then(|d| d.legs.last()).map(|l| (s.days.len(), l.end_s))).max_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let ends_at = last_home.map_or_else(|| clock_at(first_day, day_start, 0, 0.0), |(d, s)| clock_at(first_day, day_start, d as u32 - 1, s));
        let work_s: f64 = machines.iter().map(|s| s.work_s).sum();
        let transit_s: f64 = machines.iter().map(|s| s.transit_s).sum();
        let busy: f64 = machines.iter().map(|s| s.working_time_s).sum();
        let fits_window = days_used <= window.days;
        let mut warnings = Vec::new();
        if !fits_window {
            warnings.push(format!("the work takes {days_used} working days, more than the window's {}", window.days));
        }
        if !unscheduled.is_empty() {
            warnings.push(format!("{} fields{UNSCHEDULED_WARNING}", unscheduled.len()));
        }
        Schedule {
            makespan_s,
            lower_bound_s,
            makespan_over_bound: if lower_bound_s > 0.0 { makespan_s / lower_bound_s } else { 1.0 },
            ends_at,
            days_used,
            fits_window,
            work_s,
            transit_s,
            transit_m: machines.iter().map(|s| s.transit_m).sum(),
            transit_share: if busy > 0.0 { transit_s / busy } else { 0.0 },
            refills: machines.iter().map(|s| s.refills).sum(),
            idle_s: machines.iter().map(|s| s.idle_s).sum(),
            machines,
            unscheduled,
            warnings,
        }
    }
}
