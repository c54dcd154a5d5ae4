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

use super::{DEFAULT_HOURS_PER_DAY, DEFAULT_REFILL_S, DEFAULT_ROAD_SPEED_MPS, FieldWork, Machine, Transit, Window};
use crate::error::{InputError, PlanError, check_range};
use crate::stop::Stop;

/// A field is not begun, or taken up again, for less work than this (s) unless that finishes it.
pub const MIN_PIECE_S: f64 = 900.0;
/// Most fields and machines one schedule takes.
pub const MAX_FIELDS: usize = 2_000;
pub const MAX_MACHINES: usize = 100;
/// A day's next field: the weight of its distance from the depot against the drive to it.
const TOWARDS_HOME: f64 = 0.6;
/// Rounds of the local search (each moves one field).
const MOST_MOVES: usize = 20_000;

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
    /// counts each field's nearest arrival and the refills a day needs, s.
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

/// A machine's figures with the defaults filled in.
struct Worker {
    name: String,
    day_s: f64,
    speed: f64,
    endurance_s: f64,
    refill_s: f64,
}

impl Worker {
    /// Work and its refills (from full), s.
    fn with_refills(&self, work_s: f64) -> f64 {
        work_s + ((work_s / self.endurance_s).ceil() - 1.0).max(0.0) * self.refill_s
    }
}

/// The places the transits are priced between: depots first, then each field's entry and exit.
struct Places {
    machines: usize,
    metres: Vec<f64>,
    n: usize,
}

impl Places {
    fn depot(&self, k: usize) -> usize {
        k
    }
    fn entry(&self, i: usize) -> usize {
        self.machines + 2 * i
    }
    fn exit(&self, i: usize) -> usize {
        self.machines + 2 * i + 1
    }
    fn metres(&self, a: usize, b: usize) -> f64 {
        self.metres[a * self.n + b]
    }
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

/// Each machine's fields in order, and the estimates the search compares.
struct Rounds<'a> {
    fields: &'a [FieldWork],
    workers: &'a [Worker],
    places: &'a Places,
}

impl Rounds<'_> {
    fn seconds(&self, k: usize, a: usize, b: usize) -> f64 {
        self.places.metres(a, b) / self.workers[k].speed
    }

    /// Transit seconds of machine `k` to field `i` from where `before` ends (the depot if none)
    /// and from it to where `after` begins.
    fn joins(&self, k: usize, before: Option<usize>, i: usize, after: Option<usize>) -> f64 {
        let p = self.places;
        let from = before.map_or(p.depot(k), |b| p.exit(b));
        let to = after.map_or(p.depot(k), |a| p.entry(a));
        self.seconds(k, from, p.entry(i)) + self.seconds(k, p.exit(i), to)
    }

    /// Transit seconds between `before` and `after` with nothing between.
    fn direct(&self, k: usize, before: Option<usize>, after: Option<usize>) -> f64 {
        let p = self.places;
        let from = before.map_or(p.depot(k), |b| p.exit(b));
        let to = after.map_or(p.depot(k), |a| p.entry(a));
        self.seconds(k, from, to)
    }

    /// The cheapest place for field `i` in round `r` of machine `k`: (index, added transit s).
    fn cheapest_insertion(&self, k: usize, r: &[usize], i: usize) -> (usize, f64) {
        (0..=r.len())
            .map(|at| {
                let before = at.checked_sub(1).map(|b| r[b]);
                let after = r.get(at).copied();
                (at, self.joins(k, before, i, after) - self.direct(k, before, after))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("a round has a place")
    }

    /// Transit saved by taking the field at `at` out of round `r`.
    fn removal_gain(&self, k: usize, r: &[usize], at: usize) -> f64 {
        let before = at.checked_sub(1).map(|b| r[b]);
        let after = r.get(at + 1).copied();
        self.joins(k, before, r[at], after) - self.direct(k, before, after)
    }

    fn work(&self, k: usize, i: usize) -> f64 {
        self.workers[k].with_refills(self.fields[i].work_s)
    }

    /// Estimated working time of a round: its work and transits, a day's return trips left out.
    fn estimate(&self, k: usize, r: &[usize]) -> f64 {
        let transit: f64 = (0..=r.len()).map(|at| self.direct(k, at.checked_sub(1).map(|b| r[b]), r.get(at).copied())).sum();
        transit + r.iter().map(|&i| self.work(k, i)).sum::<f64>()
    }

    /// Whether machine `k` can reach field `i`, work some of it and be home within a day.
    fn reachable(&self, k: usize, i: usize) -> bool {
        let least = self.fields[i].work_s.min(MIN_PIECE_S);
        self.joins(k, None, i, None) + least <= self.workers[k].day_s
    }

    fn first_rounds(&self) -> (Vec<Vec<usize>>, Vec<Unscheduled>) {
        let m = self.workers.len();
        let mut rounds: Vec<Vec<usize>> = vec![Vec::new(); m];
        let mut loads = vec![0.0; m];
        let mut unscheduled = Vec::new();
        let mut order: Vec<usize> = (0..self.fields.len()).collect();
        order.sort_by(|&a, &b| self.fields[b].work_s.total_cmp(&self.fields[a].work_s).then(a.cmp(&b)));
        for i in order {
            let best = (0..m)
                .filter(|&k| self.reachable(k, i))
                .map(|k| {
                    let (at, added) = self.cheapest_insertion(k, &rounds[k], i);
                    (k, at, added, loads[k] + self.work(k, i) + added)
                })
                .min_by(|a, b| a.3.total_cmp(&b.3).then(a.2.total_cmp(&b.2)));
            match best {
                Some((k, at, added, _)) => {
                    rounds[k].insert(at, i);
                    loads[k] += self.work(k, i) + added;
                }
                None => unscheduled
                    .push(Unscheduled { field: i, reason: "no machine can drive from its depot to this field, work on it and drive back within its working day".to_owned() }),
            }
        }
        unscheduled.sort_by_key(|u| u.field);
        (rounds, unscheduled)
    }

    /// Rounds built a day at a time: the machine with the least working time so far goes out
    /// for a day to the unworked field farthest from its depot among those nearer its depot than
    /// any other (else the nearest to its depot), then works the nearest unworked fields that fit
    /// the day, and begins one more if at least [`MIN_PIECE_S`] of it fits (taken up again its
    /// next morning). Far fields are reached with whole days of nearby work around them.
    fn rounds_by_days(&self, unscheduled: &[Unscheduled]) -> Vec<Vec<usize>> {
        let (m, p) = (self.workers.len(), self.places);
        let mut left: Vec<f64> = self.fields.iter().map(|f| f.work_s).collect();
        for u in unscheduled {
            left[u.field] = 0.0;
        }
        let mut rounds: Vec<Vec<usize>> = vec![Vec::new(); m];
        let mut busy = vec![0.0f64; m];
        // a field begun and not finished, per machine: its next day starts there
        let mut carried: Vec<Option<usize>> = vec![None; m];
        let nearest_depot = |i: usize| (0..m).map(|k| p.metres(p.depot(k), p.entry(i))).fold(f64::INFINITY, f64::min);
        while left.iter().any(|&w| w > 0.0) {
            let Some(k) = (0..m).filter(|&k| carried[k].is_some() || (0..left.len()).any(|i| left[i] > 0.0 && self.reachable(k, i))).min_by(|a, b| busy[*a].total_cmp(&busy[*b]))
            else {
                break;
            };
            let w = &self.workers[k];
            let open = |i: usize, left: &[f64], carried: &[Option<usize>]| left[i] > 0.0 && self.reachable(k, i) && !carried.contains(&Some(i));
            let first = carried[k].take().or_else(|| {
                let from_depot = |i: usize| p.metres(p.depot(k), p.entry(i));
                let own = (0..left.len()).filter(|&i| open(i, &left, &carried) && from_depot(i) <= nearest_depot(i) + 1.0).max_by(|a, b| from_depot(*a).total_cmp(&from_depot(*b)));
                own.or_else(|| (0..left.len()).filter(|&i| open(i, &left, &carried)).min_by(|a, b| from_depot(*a).total_cmp(&from_depot(*b))))
            });
            let Some(mut next) = first else { break };
            let (mut t, mut at, mut tank) = (0.0, p.depot(k), w.endurance_s);
            loop {
                let go = self.seconds(k, at, p.entry(next));
                let back = self.seconds(k, p.exit(next), p.depot(k));
                let (done, used, tank_after) = fitting(w, left[next], t + go + back, tank);
                let whole = done + 1e-6 >= left[next];
                if !(whole || done >= MIN_PIECE_S || (t == 0.0 && done > 0.0)) {
                    break;
                }
                rounds[k].push(next);
                t += go + used;
                tank = tank_after;
                left[next] = if whole { 0.0 } else { left[next] - done };
                if !whole {
                    carried[k] = Some(next);
                    break;
                }
                at = p.exit(next);
                // the nearest unworked field from here, nearer still if it is on the way home
                let home = |i: usize| p.metres(p.exit(i), p.depot(k));
                let score = |i: usize| p.metres(at, p.entry(i)) + TOWARDS_HOME * home(i);
                let Some(n) = (0..left.len()).filter(|&i| open(i, &left, &carried)).min_by(|a, b| score(*a).total_cmp(&score(*b))) else {
                    break;
                };
                next = n;
            }
            busy[k] += w.day_s;
        }
        // a field worked over several days is one stop of its round
        for r in &mut rounds {
            r.dedup();
        }
        rounds
    }

    fn improve(&self, rounds: &mut [Vec<usize>], stop: &Stop) -> Result<(), PlanError> {
        let mut loads: Vec<f64> = rounds.iter().enumerate().map(|(k, r)| self.estimate(k, r)).collect();
        for _ in 0..MOST_MOVES {
            if stop.requested() {
                return Err(PlanError::Cancelled);
            }
            let moved = self.move_within(rounds, &mut loads) | self.move_from_last(rounds, &mut loads);
            if !moved {
                break;
            }
        }
        Ok(())
    }

    /// Moves each field to the cheapest place of its own round; true if any moved.
    fn move_within(&self, rounds: &mut [Vec<usize>], loads: &mut [f64]) -> bool {
        let mut moved = false;
        for (k, r) in rounds.iter_mut().enumerate() {
            let mut at = 0;
            while at < r.len() {
                let gain = self.removal_gain(k, r, at);
                let i = r.remove(at);
                let (to, added) = self.cheapest_insertion(k, r, i);
                if added < gain - 1e-6 {
                    r.insert(to, i);
                    loads[k] -= gain - added;
                    moved = true;
                } else {
                    r.insert(at, i);
                }
                at += 1;
            }
        }
        moved
    }

    /// Moves the one field of the latest machine's round whose move to another machine lowers
    /// the later of the two finishes most (ties: saves the most transit); true if one moved.
    fn move_from_last(&self, rounds: &mut [Vec<usize>], loads: &mut [f64]) -> bool {
        let Some(a) = (0..loads.len()).max_by(|x, y| loads[*x].total_cmp(&loads[*y])) else { return false };
        let mut best: Option<(usize, usize, usize, f64, f64)> = None; // (at, to machine, to place, new later finish, transit change)
        for at in 0..rounds[a].len() {
            let i = rounds[a][at];
            let without = loads[a] - self.removal_gain(a, &rounds[a], at) - self.work(a, i);
            for b in (0..loads.len()).filter(|&b| b != a && self.reachable(b, i)) {
                let (to, added) = self.cheapest_insertion(b, &rounds[b], i);
                let with = loads[b] + self.work(b, i) + added;
                let later = without.max(with);
                let change = added - self.removal_gain(a, &rounds[a], at);
                if later < loads[a] - 1.0 && best.is_none_or(|(.., l, c)| (later, change) < (l, c)) {
                    best = Some((at, b, to, later, change));
                }
            }
        }
        let Some((at, b, to, ..)) = best else { return false };
        let i = rounds[a].remove(at);
        rounds[b].insert(to, i);
        loads[a] = self.estimate(a, &rounds[a]);
        loads[b] = self.estimate(b, &rounds[b]);
        true
    }

    /// Lays machine `k`'s round out over its days.
    fn lay_out(&self, k: usize, round: &[usize], first_day: Date, day_start: Time) -> MachineSchedule {
        let w = &self.workers[k];
        let mut days = DayWriter::new(w, Some((first_day, day_start)));
        self.walk(k, round, &mut days);
        MachineSchedule {
            machine: w.name.clone(),
            fields: round.len(),
            working_time_s: days.working_time_s(),
            work_s: days.work_s,
            transit_s: days.transit_s,
            transit_m: days.transit_m,
            refills: days.refills,
            idle_s: days.idle_s(),
            days: days.days,
        }
    }

    /// Machine `k`'s working time over the days its round takes (nothing written down).
    fn working_time(&self, k: usize, round: &[usize]) -> f64 {
        let mut days = DayWriter::new(&self.workers[k], None);
        self.walk(k, round, &mut days);
        days.working_time_s()
    }

    /// Drives machine `k` through its round, day by day, into `days`.
    fn walk(&self, k: usize, round: &[usize], days: &mut DayWriter<'_>) {
        let w = &self.workers[k];
        let p = self.places;
        let mut at = p.depot(k);
        for &i in round {
            let mut left = self.fields[i].work_s;
            while left > 0.0 {
                let go = self.seconds(k, at, p.entry(i));
                let back = self.seconds(k, p.exit(i), p.depot(k));
                let room = w.day_s - days.t - go - back;
                let fits = days.work_fitting(left, room);
                let fresh_day = days.t == 0.0;
                if fits + 1e-6 >= left || fits >= MIN_PIECE_S || (fresh_day && fits > 0.0) {
                    days.transit(Some(i), p.metres(at, p.entry(i)), go);
                    let amount = if fits + 1e-6 >= left { left } else { fits };
                    days.work(i, amount, left);
                    left -= amount;
                    at = p.exit(i);
                    if left > 1e-6 {
                        days.transit(None, p.metres(at, p.depot(k)), back);
                        days.end_day();
                        at = p.depot(k);
                    }
                } else if fresh_day {
                    // reachable() keeps this from happening: a fresh day's room holds some work
                    break;
                } else {
                    // not worth beginning today
                    days.transit(None, p.metres(at, p.depot(k)), self.seconds(k, at, p.depot(k)));
                    days.end_day();
                    at = p.depot(k);
                }
            }
        }
        days.transit(None, p.metres(at, p.depot(k)), self.seconds(k, at, p.depot(k)));
        days.end_day();
    }

    /// Moves fields off the machine that finishes last, judged by the days laid out (a day's
    /// trips home and its unused end included), while that brings the last finish earlier.
    fn balance_days(&self, rounds: &mut [Vec<usize>], stop: &Stop) -> Result<(), PlanError> {
        let mut ends: Vec<f64> = rounds.iter().enumerate().map(|(k, r)| self.working_time(k, r)).collect();
        for _ in 0..MOST_MOVES {
            if stop.requested() {
                return Err(PlanError::Cancelled);
            }
            let Some(a) = (0..ends.len()).max_by(|x, y| ends[*x].total_cmp(&ends[*y])) else { break };
            let mut best: Option<(usize, usize, usize, f64, f64, f64)> = None; // (at, to machine, to place, a's end, b's end, later)
            for at in 0..rounds[a].len() {
                let mut without = rounds[a].clone();
                let i = without.remove(at);
                let end_a = self.working_time(a, &without);
                for b in (0..ends.len()).filter(|&b| b != a && self.reachable(b, i)) {
                    let (to, _) = self.cheapest_insertion(b, &rounds[b], i);
                    let mut with = rounds[b].clone();
                    with.insert(to, i);
                    let end_b = self.working_time(b, &with);
                    let later = end_a.max(end_b);
                    if later < ends[a] - 1.0 && best.is_none_or(|(.., l)| later < l) {
                        best = Some((at, b, to, end_a, end_b, later));
                    }
                }
            }
            let Some((at, b, to, end_a, end_b, _)) = best else { break };
            let i = rounds[a].remove(at);
            rounds[b].insert(to, i);
            (ends[a], ends[b]) = (end_a, end_b);
        }
        Ok(())
    }

    /// A bound that counts what every schedule spends besides work: each field is driven to at
    /// least once, from a depot or another field (at the fastest road speed), and a machine
    /// refills at least `work / endurance − 1` times a day. With `a_k = 1 + R_k / H_k` and
    /// `g_k = 1 + R_k / E_k` (refill time R, day H, endurance E; both 1 without a tank), machine
    /// k's working time T_k satisfies `a_k T_k + R_k ≥ g_k work_k + transit_k`; summed over the
    /// machines, the makespan T ≥ (min g · total work + Σ first arrivals − Σ R) / Σ a.
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
        let a: f64 = (0..w.len()).map(|k| 1.0 + refill(k) / w[k].day_s).sum();
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

/// Writes a machine's legs day by day (or only counts the time, without dates).
struct DayWriter<'a> {
    worker: &'a Worker,
    /// The first day's date and the time each day starts; `None`: count only.
    calendar: Option<(Date, Time)>,
    days: Vec<Day>,
    day_count: usize,
    legs: Vec<Leg>,
    /// Seconds into the current day.
    t: f64,
    /// When the last day written ended, s after its start.
    last_end: f64,
    since_refill: f64,
    refills: usize,
    transit_m: f64,
    transit_s: f64,
    work_s: f64,
}

impl<'a> DayWriter<'a> {
    fn new(worker: &'a Worker, calendar: Option<(Date, Time)>) -> Self {
        DayWriter {
            worker,
            calendar,
            days: Vec::new(),
            day_count: 0,
            legs: Vec::new(),
            t: 0.0,
            last_end: 0.0,
            since_refill: 0.0,
            refills: 0,
            transit_m: 0.0,
            transit_s: 0.0,
            work_s: 0.0,
        }
    }

    /// The days' working time that was neither work, transit nor refill.
    fn idle_s(&self) -> f64 {
        (self.working_time_s() - self.work_s - self.transit_s - self.refills as f64 * self.worker.refill_s).max(0.0)
    }

    /// Working time from the first day's start to the last day's return, nights left out.
    fn working_time_s(&self) -> f64 {
        if self.day_count == 0 { 0.0 } else { (self.day_count - 1) as f64 * self.worker.day_s + self.last_end }
    }

    /// Work (s) that fits in `room` seconds, refills included, of `left` to do.
    fn work_fitting(&self, left: f64, room: f64) -> f64 {
        let w = self.worker;
        fitting(w, left, w.day_s - room, w.endurance_s - self.since_refill).0
    }

    fn push(&mut self, kind: LegKind, field: Option<usize>, seconds: f64, distance_m: Option<f64>, finishes_field: Option<bool>) {
        let (start_s, end_s) = (self.t, self.t + seconds);
        if let Some((_, day_start)) = self.calendar {
            self.legs.push(Leg { kind, field, start: time_of_day(day_start, start_s), end: time_of_day(day_start, end_s), start_s, end_s, distance_m, finishes_field });
        }
        self.t = end_s;
    }

    fn transit(&mut self, field: Option<usize>, metres: f64, seconds: f64) {
        if metres <= 0.0 {
            return;
        }
        self.transit_m += metres;
        self.transit_s += seconds;
        self.push(LegKind::Transit, field, seconds, Some(metres), None);
    }

    /// `amount` of field `i`'s work, with the refills it needs; `left` is what the field had left.
    fn work(&mut self, i: usize, amount: f64, left: f64) {
        let w = self.worker;
        let mut done = 0.0;
        while done < amount - 1e-9 {
            let tank = w.endurance_s - self.since_refill;
            if tank <= 1e-9 {
                self.refills += 1;
                self.push(LegKind::Refill, Some(i), w.refill_s, None, None);
                self.since_refill = 0.0;
                continue;
            }
            let chunk = (amount - done).min(tank);
            done += chunk;
            self.since_refill += chunk;
            self.work_s += chunk;
            let finishes = done >= left - 1e-6;
            self.push(LegKind::Work, Some(i), chunk, None, Some(finishes));
        }
    }

    fn end_day(&mut self) {
        if self.t == 0.0 {
            return;
        }
        let day = self.day_count as u32;
        self.day_count += 1;
        self.last_end = self.t;
        if let Some((first_day, _)) = self.calendar {
            self.days.push(Day { day: day + 1, date: first_day.saturating_add(jiff::Span::new().days(i64::from(day))).to_string(), legs: std::mem::take(&mut self.legs) });
        }
        self.t = 0.0;
        self.since_refill = 0.0;
    }
}

/// Of `left` seconds of work, what a machine with `tank` seconds in its tank can do in a day
/// already `spent` seconds in (its transits to and from the field counted): (work done, time it
/// takes with refills, tank after).
fn fitting(w: &Worker, left: f64, spent: f64, tank: f64) -> (f64, f64, f64) {
    let (mut done, mut used, mut tank) = (0.0, 0.0, tank);
    let mut room = w.day_s - spent;
    while done < left && room > 0.0 {
        let chunk = (left - done).min(tank).min(room);
        done += chunk;
        used += chunk;
        room -= chunk;
        tank -= chunk;
        if tank <= 0.0 && done < left {
            room -= w.refill_s;
            used += w.refill_s;
            tank = w.endurance_s;
        }
    }
    (done, used, tank)
}

/// `HH:MM:SS`, `seconds` after `start` (past midnight it goes on counting: `25:10:00`).
fn time_of_day(start: Time, seconds: f64) -> String {
    let s = (f64::from(start.hour()) * 3600.0 + f64::from(start.minute()) * 60.0 + seconds).round() as i64;
    format!("{:02}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

fn clock_at(first_day: Date, start: Time, day: u32, seconds: f64) -> String {
    let date = first_day.saturating_add(jiff::Span::new().days(i64::from(day)));
    format!("{date}T{}", &time_of_day(start, seconds)[..5])
}
