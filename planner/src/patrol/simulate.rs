//! The patrol simulator (patrolling spec §2–§5): UAVs move one cell per cycle to the free
//! neighbour with the least value in their matrix, mark the cell they leave by the update
//! rule, break ties by the strategy's rule, and share their matrices as the strategy says.
//! Randomness comes from one seeded ChaCha8 stream, drawn in UAV order, so a run is
//! reproducible from its seed.

use std::collections::VecDeque;

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};
use serde::{Deserialize, Serialize};

use super::grid::CellGrid;
use super::metrics::{PatrolMetrics, Visits};
use super::update_rules::UpdateRule;
use super::watershed::{largest_valley, route};

/// How ties between the least-valued neighbours are broken (spec §3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum TieRule {
    /// Uniformly at random (the classic methods).
    Random,
    /// Straight ahead when it ties, else at random (NC-Drone).
    AheadThenRandom,
    /// As the released NetLogo code: ahead; both sides at random; left, right, back.
    Reference,
}

/// Who shares whose matrix (spec §4, §5.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Sharing {
    /// One matrix for all (a ground station).
    Centralised,
    /// Own matrices; UAVs within `comm_radius_cells` keep the element-wise maximum.
    Max,
    /// Own matrices; UAVs within range keep the rounded element-wise mean.
    Avg,
    /// Own matrices plus copies of the others' from the last meeting, summed when deciding.
    Multi,
    /// Own matrices merged by every UAV every `sync_interval` cycles (CFS).
    Periodic,
}

/// Evaporation (spec §5.3): a cell loses `factor` every `interval` cycles it is not visited.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Evaporation {
    #[cfg_attr(feature = "schema", schema(minimum = 0.0))]
    pub factor: f64,
    #[cfg_attr(feature = "schema", schema(minimum = 1))]
    pub interval: u32,
    /// Lose it continuously (`factor · Δt / interval`) as the released code does, not in steps.
    #[serde(default)]
    pub continuous: bool,
}

/// What Watershed reads as the relief (spec §5.1–§5.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Valleys {
    /// The u-values (WS).
    Visits,
    /// The last-visit times (WSTS).
    LastVisit,
}

/// A patrolling strategy: the update rule and everything around it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strategy {
    pub rule: UpdateRule,
    pub ties: TieRule,
    /// TS: ties go to the least recently visited cell first.
    pub time_ties: bool,
    pub evaporation: Option<Evaporation>,
    pub watershed: Option<Valleys>,
    /// Cycles between two Watershed decisions when the matrix is central.
    pub ws_period: u32,
    pub sharing: Sharing,
    pub comm_radius_cells: usize,
    pub sync_interval: u32,
}

impl Strategy {
    /// Centralised NC-Drone: node counting, ahead first, one shared matrix.
    pub fn nc_drone() -> Strategy {
        Strategy {
            rule: UpdateRule::Nc,
            ties: TieRule::AheadThenRandom,
            time_ties: false,
            evaporation: None,
            watershed: None,
            ws_period: 100,
            sharing: Sharing::Centralised,
            comm_radius_cells: 3,
            sync_interval: 1,
        }
    }

    /// One of the classic real-time search methods on a shared matrix, ties at random.
    pub fn classic(rule: UpdateRule) -> Strategy {
        Strategy { rule, ties: TieRule::Random, ..Strategy::nc_drone() }
    }
}

/// A finished simulation.
#[derive(Debug, Clone)]
pub struct Simulation {
    pub metrics: PatrolMetrics,
    /// Visits per cell (the heat map).
    pub visits: Vec<u32>,
    /// Each UAV's path as the cells where it started, turned and ended.
    pub corners: Vec<Vec<usize>>,
    /// The cycle at which each UAV was on each of its corners.
    pub corner_cycles: Vec<Vec<u32>>,
    /// Heading changes per UAV (NTM's share).
    pub turns: Vec<u64>,
}

#[derive(Debug, Clone)]
struct Matrix {
    u: Vec<f64>,
    tau: Vec<u32>,
}

impl Matrix {
    fn new(cells: usize) -> Matrix {
        Matrix { u: vec![0.0; cells], tau: vec![0; cells] }
    }

    fn evaporated(&self, cell: usize, t: u32, evaporation: Option<Evaporation>) -> f64 {
        let Some(e) = evaporation else { return self.u[cell] };
        let idle = f64::from(t - self.tau[cell]) / f64::from(e.interval.max(1));
        self.u[cell] - e.factor * if e.continuous { idle } else { idle.floor() }
    }
}

/// What a patrol leaves behind as it runs: visits, turns and each UAV's corners.
pub(super) struct Log {
    visits: Visits,
    turns: Vec<u64>,
    reversals: u64,
    /// Per UAV: where it started and every cell it turned on, and when.
    corners: Vec<Vec<usize>>,
    corner_cycles: Vec<Vec<u32>>,
}

impl Log {
    /// UAVs on `starts`, which count as visited at cycle 0.
    pub(super) fn new(cells: usize, starts: &[usize]) -> Log {
        let mut visits = Visits::new(cells);
        let mut first = starts.to_vec();
        first.sort_unstable();
        first.dedup();
        for &s in &first {
            visits.visit(s, 0);
        }
        Log { visits, turns: vec![0; starts.len()], reversals: 0, corners: starts.iter().map(|&s| vec![s]).collect(), corner_cycles: vec![vec![0]; starts.len()] }
    }

    /// UAV `i` flew from `here` to `next` at cycle `t`, heading `before` then `after`.
    pub(super) fn moved(&mut self, i: usize, here: usize, next: usize, t: u32, before: usize, after: usize) {
        let change = (after + 4 - before) % 4;
        if change != 0 {
            self.turns[i] += if change == 2 { 2 } else { 1 };
            self.reversals += u64::from(change == 2);
            self.corners[i].push(here);
            // it reached `here` on the cycle before
            self.corner_cycles[i].push(t - 1);
        }
        self.visits.visit(next, t);
    }

    /// The finished patrol, its UAVs ending on `at` after `cycles` cycles.
    pub(super) fn finish(mut self, free: &[bool], at: &[usize], cycles: u32) -> Simulation {
        for ((corners, times), &end) in self.corners.iter_mut().zip(&mut self.corner_cycles).zip(at) {
            corners.push(end);
            times.push(cycles);
        }
        let ntm = self.turns.iter().sum();
        let metrics = self.visits.metrics(free, cycles, ntm, self.reversals);
        Simulation { metrics, visits: self.visits.count, corners: self.corners, corner_cycles: self.corner_cycles, turns: self.turns }
    }
}

/// The state a patrol runs on: positions, headings and matrices.
struct World<'g> {
    grid: &'g CellGrid,
    strategy: Strategy,
    at: Vec<usize>,
    heading: Vec<usize>,
    /// One matrix (central) or one per UAV.
    mats: Vec<Matrix>,
    /// Periodic sharing: the matrix as of the last synchronisation.
    base: Option<Matrix>,
    /// Multi sharing: `copies[i][j]`, UAV i's copy of UAV j's matrix.
    copies: Vec<Vec<Option<Matrix>>>,
    /// Cells still to fly to a Watershed target, per UAV.
    transit: Vec<VecDeque<usize>>,
    rng: ChaCha8Rng,
}

impl World<'_> {
    fn own(&self, i: usize) -> usize {
        if self.strategy.sharing == Sharing::Centralised { 0 } else { i }
    }

    fn draw(&mut self, k: usize) -> usize {
        (self.rng.next_u64() % k as u64) as usize
    }

    /// The value UAV `i` reads for `cell` at cycle `t`: its own, or with Multi sharing the sum
    /// of its own and its copies of the others', evaporated since the latest visit it knows of.
    fn value(&self, i: usize, cell: usize, t: u32) -> f64 {
        let m = &self.mats[self.own(i)];
        let Some(copies) = self.copies.get(i) else { return m.evaporated(cell, t, self.strategy.evaporation) };
        let mut sum = Matrix { u: vec![m.u[cell]], tau: vec![m.tau[cell]] };
        for c in copies.iter().flatten() {
            sum.u[0] += c.u[cell];
            sum.tau[0] = sum.tau[0].max(c.tau[cell]);
        }
        sum.evaporated(0, t, self.strategy.evaporation)
    }

    /// Where UAV `i` moves at cycle `t`, or `None` when every neighbour is taken.
    fn decide(&mut self, i: usize, t: u32) -> Option<usize> {
        let here = self.at[i];
        let candidates: Vec<(usize, usize, f64)> = (0..4)
            .filter_map(|h| self.grid.step(here, h).map(|c| (h, c)))
            .filter(|&(_, c)| !self.at.iter().enumerate().any(|(j, &p)| j != i && p == c))
            .map(|(h, c)| (h, c, self.value(i, c, t)))
            .collect();
        let least = candidates.iter().map(|c| c.2).fold(f64::INFINITY, f64::min);
        let mut tied: Vec<(usize, usize)> = candidates.iter().filter(|c| c.2 <= least + 1e-9).map(|c| (c.0, c.1)).collect();
        if tied.is_empty() {
            return None;
        }
        if self.strategy.time_ties {
            let m = &self.mats[self.own(i)];
            let oldest = tied.iter().map(|&(_, c)| m.tau[c]).min().expect("non-empty");
            tied.retain(|&(_, c)| m.tau[c] == oldest);
        }
        let h = self.heading[i];
        let has = |d: usize| tied.iter().find(|&&(th, _)| th == d).map(|&(_, c)| c);
        let chosen = match self.strategy.ties {
            TieRule::Random => None,
            TieRule::AheadThenRandom => has(h),
            TieRule::Reference => has(h).or_else(|| {
                let (left, right) = (has((h + 3) % 4), has((h + 1) % 4));
                match (left, right) {
                    (Some(l), Some(r)) => Some(if self.rng.next_u64().is_multiple_of(2) { l } else { r }),
                    (l, r) => l.or(r).or_else(|| has((h + 2) % 4)),
                }
            }),
        };
        Some(chosen.unwrap_or_else(|| {
            let k = self.draw(tied.len());
            tied[k].1
        }))
    }

    /// Moves UAV `i` to `next`, marking the cell it leaves with `rule`.
    fn step(&mut self, i: usize, next: usize, t: u32, rule: UpdateRule, log: &mut Log) {
        let here = self.at[i];
        let next_value = self.value(i, next, t);
        // evaporation is made permanent at a visit (spec §5.3), except with Multi sharing, where
        // the others sum copies of this matrix: there it only weighs decisions
        let evaporation = self.strategy.evaporation.filter(|_| self.strategy.sharing != Sharing::Multi);
        let own = self.own(i);
        let m = &mut self.mats[own];
        m.u[here] = rule.update(m.evaporated(here, t, evaporation), next_value);
        m.tau[here] = t;
        let h = self.grid.heading(here, next).expect("a neighbour");
        log.moved(i, here, next, t, self.heading[i], h);
        self.heading[i] = h;
        self.at[i] = next;
    }

    /// Merges matrices as the sharing mode says, after every UAV moved at cycle `t`; true
    /// when some UAVs synchronised.
    fn share(&mut self, t: u32) -> bool {
        let n = self.at.len();
        match self.strategy.sharing {
            Sharing::Centralised => false,
            Sharing::Periodic => {
                if !t.is_multiple_of(self.strategy.sync_interval.max(1)) {
                    return false;
                }
                let base = self.base.as_mut().expect("periodic sharing has a base");
                let before = base.clone();
                for m in &self.mats {
                    for c in 0..m.u.len() {
                        base.u[c] += m.u[c] - before.u[c];
                        base.tau[c] = base.tau[c].max(m.tau[c]);
                    }
                }
                for m in &mut self.mats {
                    m.clone_from(base);
                }
                true
            }
            Sharing::Max | Sharing::Avg | Sharing::Multi => {
                let r = self.strategy.comm_radius_cells;
                let near = |a: usize, b: usize| {
                    let ((ca, ra), (cb, rb)) = (self.grid.col_row(self.at[a]), self.grid.col_row(self.at[b]));
                    ca.abs_diff(cb).max(ra.abs_diff(rb)) <= r
                };
                // pair by pair, as two radios meet: a mean of two keeps a single visit (½ rounds
                // up), where a mean of four would round it away
                let pairs: Vec<(usize, usize)> = (0..n).flat_map(|a| (a + 1..n).map(move |b| (a, b))).filter(|&(a, b)| near(a, b)).collect();
                for &(a, b) in &pairs {
                    self.merge(&[a, b]);
                }
                !pairs.is_empty()
            }
        }
    }

    fn merge(&mut self, members: &[usize]) {
        let cells = self.grid.len();
        match self.strategy.sharing {
            Sharing::Multi => {
                for &i in members {
                    for &j in members {
                        if i != j {
                            self.copies[i][j] = Some(self.mats[j].clone());
                        }
                    }
                }
            }
            sharing => {
                for c in 0..cells {
                    let values = members.iter().map(|&i| self.mats[i].u[c]);
                    let merged = if sharing == Sharing::Max {
                        values.fold(f64::NEG_INFINITY, f64::max)
                    } else {
                        // halves round up
                        (values.sum::<f64>() / members.len() as f64 + 0.5).floor()
                    };
                    let tau = members.iter().map(|&i| self.mats[i].tau[c]).max().expect("members");
                    for &i in members {
                        self.mats[i].u[c] = merged;
                        self.mats[i].tau[c] = tau;
                    }
                }
            }
        }
    }

    /// Sends the lowest-numbered UAV not already on its way to the largest valley of its
    /// matrix (Watershed), unless another UAV is flying into that valley.
    fn watershed(&mut self, valleys: Valleys) {
        let Some(i) = (0..self.at.len()).find(|&i| self.transit[i].is_empty()) else { return };
        let m = &self.mats[self.own(i)];
        let relief: Vec<f64> = match valleys {
            Valleys::Visits => m.u.clone(),
            Valleys::LastVisit => m.tau.iter().map(|&t| f64::from(t)).collect(),
        };
        let grid = self.grid;
        let rng = &mut self.rng;
        let valley = largest_valley(grid, &relief, |k| (rng.next_u64() % k as u64) as usize);
        let Some(valley) = valley else { return };
        let claimed = self.transit.iter().filter_map(|t| t.back()).any(|target| valley.contains(target));
        if claimed {
            return;
        }
        let target = valley[self.draw(valley.len())];
        self.transit[i] = route(self.grid, self.at[i], target, self.heading[i]).into();
    }
}

/// Runs `strategy` for `cycles` cycles with UAVs starting on `starts` (free cells), all heading
/// north. `None` when `stopped` answers true (asked every 1 024 cycles).
pub fn simulate(grid: &CellGrid, strategy: &Strategy, starts: &[usize], cycles: u32, seed: u64, stopped: &dyn Fn() -> bool) -> Option<Simulation> {
    let n = starts.len();
    let cells = grid.len();
    let own_matrices = if strategy.sharing == Sharing::Centralised { 1 } else { n };
    let mut world = World {
        grid,
        strategy: *strategy,
        at: starts.to_vec(),
        heading: vec![0; n],
        mats: vec![Matrix::new(cells); own_matrices],
        base: (strategy.sharing == Sharing::Periodic).then(|| Matrix::new(cells)),
        copies: if strategy.sharing == Sharing::Multi { vec![vec![None; n]; n] } else { Vec::new() },
        transit: vec![VecDeque::new(); n],
        rng: ChaCha8Rng::seed_from_u64(seed),
    };
    let mut log = Log::new(cells, starts);
    for t in 1..=cycles {
        if t % 1024 == 0 && stopped() {
            return None;
        }
        for i in 0..n {
            if let Some(&next) = world.transit[i].front() {
                // on the way to a valley the move is fixed; a UAV in the way ends the transit
                // (two UAVs could otherwise wait for each other for ever)
                if !world.at.iter().enumerate().any(|(j, &p)| j != i && p == next) {
                    world.transit[i].pop_front();
                    world.step(i, next, t, UpdateRule::Nc, &mut log);
                    continue;
                }
                world.transit[i].clear();
            }
            if let Some(next) = world.decide(i, t) {
                world.step(i, next, t, strategy.rule, &mut log);
            }
        }
        let synced = world.share(t);
        if let Some(valleys) = strategy.watershed {
            let due = if strategy.sharing == Sharing::Centralised { t.is_multiple_of(strategy.ws_period.max(1)) } else { synced };
            if due {
                world.watershed(valleys);
            }
        }
    }
    Some(log.finish(&grid.free, &world.at, cycles))
}

/// A centralised patrol between two cycles, as software that runs it online keeps it: the
/// shared u-values and last-visit times per cell, each UAV's cell and heading (0 N, 1 E, 2 S,
/// 3 W), and the cycle about to run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct PatrolState {
    pub u: Vec<f64>,
    pub last_visit: Vec<u32>,
    /// Each UAV's cell, 1 to 64 UAVs.
    #[cfg_attr(feature = "schema", schema(min_items = 1, max_items = 64))]
    pub at: Vec<usize>,
    /// Each UAV's heading: 0 (north), 1 (east), 2 (south) or 3 (west).
    #[cfg_attr(feature = "schema", schema(value_type = Vec<u8>))]
    pub headings: Vec<usize>,
    /// The cycle about to run, from 1.
    #[cfg_attr(feature = "schema", schema(minimum = 1))]
    pub cycle: u32,
}

/// One cycle of `state`: each UAV's move in UAV order (`None`: every neighbour taken) and the
/// state after them.
pub fn next_moves(grid: &CellGrid, strategy: &Strategy, state: PatrolState, seed: u64) -> (Vec<Option<usize>>, PatrolState) {
    let PatrolState { u, last_visit, at, headings, cycle } = state;
    let mut log = Log::new(grid.len(), &at);
    let mut world = World {
        grid,
        strategy: Strategy { sharing: Sharing::Centralised, watershed: None, ..*strategy },
        transit: vec![VecDeque::new(); at.len()],
        at,
        heading: headings,
        mats: vec![Matrix { u, tau: last_visit }],
        base: None,
        copies: Vec::new(),
        rng: ChaCha8Rng::seed_from_u64(seed),
    };
    let moves = (0..world.at.len())
        .map(|i| {
            let next = world.decide(i, cycle)?;
            world.step(i, next, cycle, strategy.rule, &mut log);
            Some(next)
        })
        .collect();
    let Matrix { u, tau } = world.mats.pop().expect("one matrix");
    (moves, PatrolState { u, last_visit: tau, at: world.at, headings: world.heading, cycle: cycle + 1 })
}

/// The metrics of `strategy` over the seeds `seeds`, simulated in parallel (for statistics).
pub fn metrics_over_seeds(grid: &CellGrid, strategy: &Strategy, starts: &[usize], cycles: u32, seeds: std::ops::Range<u64>) -> Vec<PatrolMetrics> {
    use rayon::prelude::*;
    seeds.into_par_iter().map(|seed| simulate(grid, strategy, starts, cycles, seed, &|| false).expect("never stopped").metrics).collect()
}
