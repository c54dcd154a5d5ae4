//! Each machine's round (its fields in order): built by insertion or a day at a time, and
//! improved by moving fields (docs/methods.md, farms §2).

use super::FieldWork;
use super::days::fitting;
use super::schedule::{MIN_PIECE_S, Unscheduled};
use crate::error::PlanError;
use crate::stop::Stop;

/// A day's next field: the weight of its distance from the depot against the drive to it.
const TOWARDS_HOME: f64 = 0.6;
/// Rounds of the local search (each moves one field).
const MOST_MOVES: usize = 20_000;

/// A machine's figures with the defaults filled in.
pub(super) struct Worker {
    pub(super) name: String,
    pub(super) day_s: f64,
    pub(super) speed: f64,
    pub(super) endurance_s: f64,
    pub(super) refill_s: f64,
}

impl Worker {
    /// Work and its refills (from full), s.
    pub(super) fn with_refills(&self, work_s: f64) -> f64 {
        work_s + ((work_s / self.endurance_s).ceil() - 1.0).max(0.0) * self.refill_s
    }
}

/// The places the transits are priced between: depots first, then each field's entry and exit.
pub(super) struct Places {
    pub(super) machines: usize,
    pub(super) metres: Vec<f64>,
    pub(super) n: usize,
}

impl Places {
    pub(super) fn depot(&self, k: usize) -> usize {
        k
    }
    pub(super) fn entry(&self, i: usize) -> usize {
        self.machines + 2 * i
    }
    pub(super) fn exit(&self, i: usize) -> usize {
        self.machines + 2 * i + 1
    }
    pub(super) fn metres(&self, a: usize, b: usize) -> f64 {
        self.metres[a * self.n + b]
    }
}

/// Each machine's fields in order, and the estimates the search compares.
pub(super) struct Rounds<'a> {
    pub(super) fields: &'a [FieldWork],
    pub(super) workers: &'a [Worker],
    pub(super) places: &'a Places,
}

impl Rounds<'_> {
    pub(super) fn seconds(&self, k: usize, a: usize, b: usize) -> f64 {
        self.places.metres(a, b) / self.workers[k].speed
    }

    /// Transit seconds of machine `k` to field `i` from where `before` ends (the depot if none)
    /// and from it to where `after` begins.
    pub(super) fn joins(&self, k: usize, before: Option<usize>, i: usize, after: Option<usize>) -> f64 {
        let p = self.places;
        let from = before.map_or(p.depot(k), |b| p.exit(b));
        let to = after.map_or(p.depot(k), |a| p.entry(a));
        self.seconds(k, from, p.entry(i)) + self.seconds(k, p.exit(i), to)
    }

    /// Transit seconds between `before` and `after` with nothing between.
    pub(super) fn direct(&self, k: usize, before: Option<usize>, after: Option<usize>) -> f64 {
        let p = self.places;
        let from = before.map_or(p.depot(k), |b| p.exit(b));
        let to = after.map_or(p.depot(k), |a| p.entry(a));
        self.seconds(k, from, to)
    }

    /// The cheapest place for field `i` in round `r` of machine `k`: (index, added transit s).
    pub(super) fn cheapest_insertion(&self, k: usize, r: &[usize], i: usize) -> (usize, f64) {
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
    pub(super) fn removal_gain(&self, k: usize, r: &[usize], at: usize) -> f64 {
        let before = at.checked_sub(1).map(|b| r[b]);
        let after = r.get(at + 1).copied();
        self.joins(k, before, r[at], after) - self.direct(k, before, after)
    }

    pub(super) fn work(&self, k: usize, i: usize) -> f64 {
        self.workers[k].with_refills(self.fields[i].work_s)
    }

    /// Estimated working time of a round: its work and transits, a day's return trips left out.
    pub(super) fn estimate(&self, k: usize, r: &[usize]) -> f64 {
        let transit: f64 = (0..=r.len()).map(|at| self.direct(k, at.checked_sub(1).map(|b| r[b]), r.get(at).copied())).sum();
        transit + r.iter().map(|&i| self.work(k, i)).sum::<f64>()
    }

    /// Whether machine `k` can reach field `i`, work some of it and be home within a day.
    pub(super) fn reachable(&self, k: usize, i: usize) -> bool {
        let least = self.fields[i].work_s.min(MIN_PIECE_S);
        self.joins(k, None, i, None) + least <= self.workers[k].day_s
    }

    pub(super) fn first_rounds(&self) -> (Vec<Vec<usize>>, Vec<Unscheduled>) {
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
    pub(super) fn rounds_by_days(&self, unscheduled: &[Unscheduled]) -> Vec<Vec<usize>> {
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

    pub(super) fn improve(&self, rounds: &mut [Vec<usize>], stop: &Stop) -> Result<(), PlanError> {
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
    pub(super) fn move_within(&self, rounds: &mut [Vec<usize>], loads: &mut [f64]) -> bool {
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
    pub(super) fn move_from_last(&self, rounds: &mut [Vec<usize>], loads: &mut [f64]) -> bool {
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

    /// Moves fields off the machine that finishes last, judged by the days laid out (a day's
    /// trips home and its unused end included), while that brings the last finish earlier.
    pub(super) fn balance_days(&self, rounds: &mut [Vec<usize>], stop: &Stop) -> Result<(), PlanError> {
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
}
