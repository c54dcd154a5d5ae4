//! A machine's round laid out over working days, from the depot and back within its hours
//! (docs/methods.md, farms §3).

use jiff::civil::{Date, Time};

use super::rounds::{Rounds, Worker};
use super::schedule::{Day, Leg, LegKind, MIN_PIECE_S, MachineSchedule};

impl Rounds<'_> {
    /// Lays machine `k`'s round out over its days.
    pub(super) fn lay_out(&self, k: usize, round: &[usize], first_day: Date, day_start: Time) -> MachineSchedule {
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
    pub(super) fn working_time(&self, k: usize, round: &[usize]) -> f64 {
        let mut days = DayWriter::new(&self.workers[k], None);
        self.walk(k, round, &mut days);
        days.working_time_s()
    }

    /// Drives machine `k` through its round, day by day, into `days`.
    pub(super) fn walk(&self, k: usize, round: &[usize], days: &mut DayWriter<'_>) {
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
}

/// Writes a machine's legs day by day (or only counts the time, without dates).
pub(super) struct DayWriter<'a> {
    pub(super) worker: &'a Worker,
    /// The first day's date and the time each day starts; `None`: count only.
    pub(super) calendar: Option<(Date, Time)>,
    pub(super) days: Vec<Day>,
    pub(super) day_count: usize,
    pub(super) legs: Vec<Leg>,
    /// Seconds into the current day.
    pub(super) t: f64,
    /// When the last day written ended, s after its start.
    pub(super) last_end: f64,
    pub(super) since_refill: f64,
    pub(super) refills: usize,
    pub(super) transit_m: f64,
    pub(super) transit_s: f64,
    pub(super) work_s: f64,
}

impl<'a> DayWriter<'a> {
    pub(super) fn new(worker: &'a Worker, calendar: Option<(Date, Time)>) -> Self {
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
    pub(super) fn idle_s(&self) -> f64 {
        (self.working_time_s() - self.work_s - self.transit_s - self.refills as f64 * self.worker.refill_s).max(0.0)
    }

    /// Working time from the first day's start to the last day's return, nights left out.
    pub(super) fn working_time_s(&self) -> f64 {
        if self.day_count == 0 { 0.0 } else { (self.day_count - 1) as f64 * self.worker.day_s + self.last_end }
    }

    /// Work (s) that fits in `room` seconds, refills included, of `left` to do.
    pub(super) fn work_fitting(&self, left: f64, room: f64) -> f64 {
        let w = self.worker;
        fitting(w, left, w.day_s - room, w.endurance_s - self.since_refill).0
    }

    pub(super) fn push(&mut self, kind: LegKind, field: Option<usize>, seconds: f64, distance_m: Option<f64>, finishes_field: Option<bool>) {
        let (start_s, end_s) = (self.t, self.t + seconds);
        if let Some((_, day_start)) = self.calendar {
            self.legs.push(Leg { kind, field, start: time_of_day(day_start, start_s), end: time_of_day(day_start, end_s), start_s, end_s, distance_m, finishes_field });
        }
        self.t = end_s;
    }

    pub(super) fn transit(&mut self, field: Option<usize>, metres: f64, seconds: f64) {
        if metres <= 0.0 {
            return;
        }
        self.transit_m += metres;
        self.transit_s += seconds;
        self.push(LegKind::Transit, field, seconds, Some(metres), None);
    }

    /// `amount` of field `i`'s work, with the refills it needs; `left` is what the field had left.
    pub(super) fn work(&mut self, i: usize, amount: f64, left: f64) {
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

    pub(super) fn end_day(&mut self) {
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
pub(super) fn fitting(w: &Worker, left: f64, spent: f64, tank: f64) -> (f64, f64, f64) {
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
pub(super) fn time_of_day(start: Time, seconds: f64) -> String {
    let s = (f64::from(start.hour()) * 3600.0 + f64::from(start.minute()) * 60.0 + seconds).round() as i64;
    format!("{:02}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

pub(super) fn clock_at(first_day: Date, start: Time, day: u32, seconds: f64) -> String {
    let date = first_day.saturating_add(jiff::Span::new().days(i64::from(day)));
    format!("{date}T{}", &time_of_day(start, seconds)[..5])
}
