//! The orienteering problem with a union reward (spec `inspection.md` §7): choose and order
//! viewpoints from the start to the end within the budget so that the weighted union of what
//! they see is largest. Variable neighbourhood search as in seed 001 (Algorithms 5 and 7):
//! greedy insertion, then shake (insert a run of unused viewpoints, or exchange a run of the
//! path for one), repair back into the budget, local search by single insertions and
//! exchanges each followed by 2-opt; better paths are kept.
//!
//! Rewards are kept with a counter per point (O(|seen|) to add or remove a viewpoint), and a
//! path's cost is updated by the change of its neighbouring legs only.

use std::cell::Cell;

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};
use rayon::prelude::*;

/// Node 0 is the start, node 1 the end; viewpoint k is node k + 2.
pub const START: usize = 0;
pub const END: usize = 1;

/// Attempts of one local search: seed 001 made |V|² of them, which is why its runs hit their
/// three-hour cap.
const LOCAL_SEARCH_ATTEMPTS: usize = 400;

/// Prices legs on demand: the search asks for a small part of all pairs.
pub trait Pricer: Sync {
    /// Costs of the legs from node `u` to node `v` and back (`u < v`; infinite where there is
    /// none).
    fn pair(&self, u: usize, v: usize) -> (f64, f64);
}

/// The problem: what each viewpoint sees, the points' weights, the legs' costs (directed:
/// climbing costs more than descending, priced when first asked for) and each viewpoint's own
/// cost (its capture).
pub struct Instance<'a> {
    pub sees: Vec<Vec<u32>>,
    pub weights: Vec<f64>,
    pub node_cost: Vec<f64>,
    pub budget: f64,
    pricer: &'a dyn Pricer,
    /// `costs[u * stride + v]`: the leg from node u to node v; NaN until priced.
    costs: Vec<Cell<f64>>,
    stride: usize,
}

impl<'a> Instance<'a> {
    /// Room for `max_viewpoints` viewpoints (the table is allocated once).
    pub fn new(pricer: &'a dyn Pricer, weights: Vec<f64>, budget: f64, max_viewpoints: usize) -> Self {
        let stride = max_viewpoints + 2;
        Instance { sees: Vec::new(), weights, node_cost: Vec::new(), budget, pricer, costs: (0..stride * stride).map(|_| Cell::new(f64::NAN)).collect(), stride }
    }

    /// Adds a viewpoint; false when the table is full.
    pub fn add_viewpoint(&mut self, sees: Vec<u32>, node_cost: f64) -> bool {
        if self.sees.len() + 2 >= self.stride {
            return false;
        }
        self.sees.push(sees);
        self.node_cost.push(node_cost);
        true
    }

    pub fn edge(&self, u: usize, v: usize) -> f64 {
        let known = self.costs[u * self.stride + v].get();
        if !known.is_nan() {
            return known;
        }
        let (lo, hi) = (u.min(v), u.max(v));
        let (there, back) = self.pricer.pair(lo, hi);
        self.store(lo, hi, there, back);
        if u < v { there } else { back }
    }

    fn store(&self, lo: usize, hi: usize, there: f64, back: f64) {
        self.costs[lo * self.stride + hi].set(there);
        self.costs[hi * self.stride + lo].set(back);
    }

    /// Prices the pairs not yet priced, in parallel.
    fn prefetch(&self, pairs: impl Iterator<Item = (usize, usize)>) {
        let mut missing: Vec<(usize, usize)> = pairs.filter(|&(u, v)| u != v && self.costs[u * self.stride + v].get().is_nan()).map(|(u, v)| (u.min(v), u.max(v))).collect();
        missing.sort_unstable();
        missing.dedup();
        let priced: Vec<(f64, f64)> = missing.par_iter().map(|&(u, v)| self.pricer.pair(u, v)).collect();
        for ((u, v), (there, back)) in missing.into_iter().zip(priced) {
            self.store(u, v, there, back);
        }
    }

    pub fn viewpoints(&self) -> usize {
        self.sees.len()
    }

    /// Cost of flying `tour` (viewpoint indices) from the start to the end.
    pub fn tour_cost(&self, tour: &[usize]) -> f64 {
        let mut prev = START;
        let mut total = 0.0;
        for &k in tour {
            total += self.edge(prev, k + 2) + self.node_cost[k];
            prev = k + 2;
        }
        total + self.edge(prev, END)
    }

    /// The weighted union of what `tour` sees, computed afresh.
    pub fn tour_reward(&self, tour: &[usize]) -> f64 {
        let mut seen = vec![false; self.weights.len()];
        for &k in tour {
            for &p in &self.sees[k] {
                seen[p as usize] = true;
            }
        }
        seen.iter().zip(&self.weights).filter(|(s, _)| **s).map(|(_, w)| w).sum()
    }
}

/// A path with its bookkeeping.
#[derive(Debug, Clone)]
pub struct Solution {
    pub tour: Vec<usize>,
    pub cost: f64,
    pub reward: f64,
    /// How many viewpoints of the tour see each point.
    count: Vec<u16>,
    member: Vec<bool>,
}

impl Solution {
    fn empty(inst: &Instance) -> Solution {
        Solution { tour: Vec::new(), cost: inst.edge(START, END), reward: 0.0, count: vec![0; inst.weights.len()], member: vec![false; inst.viewpoints()] }
    }

    fn node(&self, pos: usize) -> usize {
        self.tour[pos] + 2
    }

    /// Nodes before and after a gap at `pos` (before the tour's `pos`-th viewpoint).
    fn around_gap(&self, pos: usize) -> (usize, usize) {
        let prev = if pos == 0 { START } else { self.node(pos - 1) };
        let next = if pos == self.tour.len() { END } else { self.node(pos) };
        (prev, next)
    }

    fn gain(&self, inst: &Instance, k: usize) -> f64 {
        inst.sees[k].iter().filter(|&&p| self.count[p as usize] == 0).map(|&p| inst.weights[p as usize]).sum()
    }

    fn loss(&self, inst: &Instance, k: usize) -> f64 {
        inst.sees[k].iter().filter(|&&p| self.count[p as usize] == 1).map(|&p| inst.weights[p as usize]).sum()
    }

    /// The cheapest place to insert `k`, and what it adds to the cost.
    fn best_insertion(&self, inst: &Instance, k: usize) -> (usize, f64) {
        let v = k + 2;
        (0..=self.tour.len())
            .map(|pos| {
                let (a, b) = self.around_gap(pos);
                (pos, inst.edge(a, v) + inst.edge(v, b) - inst.edge(a, b) + inst.node_cost[k])
            })
            .fold((0, f64::INFINITY), |best, x| if x.1 < best.1 { x } else { best })
    }

    /// What removing the viewpoint at `pos` saves.
    fn removal_saving(&self, inst: &Instance, pos: usize) -> f64 {
        let v = self.node(pos);
        let prev = if pos == 0 { START } else { self.node(pos - 1) };
        let next = if pos + 1 == self.tour.len() { END } else { self.node(pos + 1) };
        inst.edge(prev, v) + inst.edge(v, next) - inst.edge(prev, next) + inst.node_cost[self.tour[pos]]
    }

    fn insert(&mut self, inst: &Instance, k: usize, pos: usize) {
        let (a, b) = self.around_gap(pos);
        self.cost += inst.edge(a, k + 2) + inst.edge(k + 2, b) - inst.edge(a, b) + inst.node_cost[k];
        for &p in &inst.sees[k] {
            let c = &mut self.count[p as usize];
            if *c == 0 {
                self.reward += inst.weights[p as usize];
            }
            *c += 1;
        }
        self.tour.insert(pos, k);
        self.member[k] = true;
    }

    fn remove(&mut self, inst: &Instance, pos: usize) -> usize {
        self.cost -= self.removal_saving(inst, pos);
        let k = self.tour.remove(pos);
        for &p in &inst.sees[k] {
            let c = &mut self.count[p as usize];
            *c -= 1;
            if *c == 0 {
                self.reward -= inst.weights[p as usize];
            }
        }
        self.member[k] = false;
        k
    }

    /// Better: more reward within the budget, or as much for less.
    fn beats(&self, other: &Solution, budget: f64) -> bool {
        self.cost <= budget && (self.reward > other.reward + 1e-9 || (self.reward >= other.reward - 1e-9 && self.cost < other.cost - 1e-9))
    }

    /// Room for viewpoints added to the instance since this solution was made.
    fn grow(&mut self, viewpoints: usize) {
        self.member.resize(viewpoints, false);
    }
}

pub struct Search {
    rng: ChaCha8Rng,
    pub best: Solution,
    pub iterations: usize,
    pub since_improvement: usize,
}

impl Search {
    /// Starts from the greedy path.
    pub fn new(inst: &Instance, seed: u64) -> Search {
        let mut best = Solution::empty(inst);
        fill(inst, &mut best);
        two_opt(inst, &mut best);
        fill(inst, &mut best);
        Search { rng: ChaCha8Rng::seed_from_u64(seed ^ 0x005e_ed0f_1a5e), best, iterations: 0, since_improvement: 0 }
    }

    fn below(&mut self, n: usize) -> usize {
        (self.rng.next_u64() % n.max(1) as u64) as usize
    }

    /// One round of the neighbourhoods; true when it improved the best path.
    pub fn iterate(&mut self, inst: &Instance) -> bool {
        self.best.grow(inst.viewpoints());
        self.iterations += 1;
        let mut improved = false;
        let mut neighbourhood = 1;
        while neighbourhood <= 2 {
            let mut candidate = self.best.clone();
            self.shake(inst, &mut candidate, neighbourhood);
            repair(inst, &mut candidate);
            self.local_search(inst, &mut candidate, neighbourhood);
            if candidate.beats(&self.best, inst.budget) {
                self.best = candidate;
                improved = true;
                neighbourhood = 1;
            } else {
                neighbourhood += 1;
            }
        }
        self.since_improvement = if improved { 0 } else { self.since_improvement + 1 };
        improved
    }

    /// Unused viewpoints that would add something.
    fn useful_unused(&self, inst: &Instance, s: &Solution) -> Vec<usize> {
        (0..inst.viewpoints()).filter(|&k| !s.member[k] && s.gain(inst, k) > 0.0).collect()
    }

    /// Neighbourhood 1: a run of unused viewpoints inserted at a random place; 2: a run of the
    /// path exchanged for a run of unused viewpoints.
    fn shake(&mut self, inst: &Instance, s: &mut Solution, neighbourhood: usize) {
        let unused = self.useful_unused(inst, s);
        if unused.is_empty() {
            return;
        }
        let run = 1 + self.below(3);
        let mut pos = self.below(s.tour.len() + 1);
        if neighbourhood == 2 && !s.tour.is_empty() {
            pos = self.below(s.tour.len());
            for _ in 0..(1 + self.below(3)).min(s.tour.len() - pos) {
                s.remove(inst, pos);
            }
        }
        let start = self.below(unused.len());
        for &k in unused.iter().cycle().skip(start).take(run.min(unused.len())) {
            if !s.member[k] {
                s.insert(inst, k, pos.min(s.tour.len()));
            }
        }
    }

    fn local_search(&mut self, inst: &Instance, s: &mut Solution, neighbourhood: usize) {
        let unused = self.useful_unused(inst, s);
        if unused.is_empty() {
            return;
        }
        for _ in 0..LOCAL_SEARCH_ATTEMPTS.min(unused.len() * unused.len().max(1)) {
            let k = unused[self.below(unused.len())];
            if s.member[k] {
                continue;
            }
            let gain = s.gain(inst, k);
            if gain <= 0.0 {
                continue;
            }
            if neighbourhood == 1 {
                let (pos, extra) = s.best_insertion(inst, k);
                if s.cost + extra <= inst.budget {
                    s.insert(inst, k, pos);
                    two_opt(inst, s);
                }
            } else if !s.tour.is_empty() {
                // exchange: one viewpoint of the path for k, where that pays
                let j = self.below(s.tour.len());
                let before = (s.reward, s.cost);
                let out = s.remove(inst, j);
                let (pos, _) = s.best_insertion(inst, k);
                s.insert(inst, k, pos);
                if s.cost > inst.budget || s.reward < before.0 - 1e-9 || (s.reward <= before.0 + 1e-9 && s.cost >= before.1) {
                    // undo
                    s.remove(inst, pos);
                    s.insert(inst, out, j);
                } else {
                    two_opt(inst, s);
                }
            }
        }
        fill(inst, s);
    }
}

/// Greedy insertion by added weight per added cost, while anything fits.
fn fill(inst: &Instance, s: &mut Solution) {
    loop {
        let stops: Vec<usize> = [START, END].into_iter().chain(s.tour.iter().map(|&k| k + 2)).collect();
        inst.prefetch((0..inst.viewpoints()).filter(|&k| !s.member[k]).flat_map(|k| stops.iter().map(move |&n| (n, k + 2))));
        let mut best: Option<(f64, usize, usize)> = None;
        for k in 0..inst.viewpoints() {
            if s.member[k] {
                continue;
            }
            let gain = s.gain(inst, k);
            if gain <= 0.0 {
                continue;
            }
            let (pos, extra) = s.best_insertion(inst, k);
            if s.cost + extra > inst.budget {
                continue;
            }
            let ratio = gain / extra.max(1e-9);
            if best.is_none_or(|b| ratio > b.0) {
                best = Some((ratio, k, pos));
            }
        }
        let Some((_, k, pos)) = best else { return };
        s.insert(inst, k, pos);
    }
}

/// Drops the viewpoint that loses the least weight per cost saved until the path fits.
fn repair(inst: &Instance, s: &mut Solution) {
    while s.cost > inst.budget && !s.tour.is_empty() {
        let worst = (0..s.tour.len())
            .map(|pos| (pos, s.loss(inst, s.tour[pos]) / s.removal_saving(inst, pos).max(1e-9)))
            .fold((0, f64::INFINITY), |best, x| if x.1 < best.1 { x } else { best })
            .0;
        s.remove(inst, worst);
    }
}

/// Reverses stretches of the path while that makes it cheaper (costs are directed, so the
/// reversed stretch is priced leg by leg).
fn two_opt(inst: &Instance, s: &mut Solution) {
    let n = s.tour.len();
    if n < 2 {
        return;
    }
    let mut improved = true;
    while improved {
        improved = false;
        for i in 0..n - 1 {
            for j in i + 1..n {
                let prev = if i == 0 { START } else { s.node(i - 1) };
                let next = if j + 1 == n { END } else { s.node(j + 1) };
                let inner: f64 = (i..j).map(|k| inst.edge(s.node(k), s.node(k + 1))).sum();
                let inner_rev: f64 = (i..j).map(|k| inst.edge(s.node(k + 1), s.node(k))).sum();
                let before = inst.edge(prev, s.node(i)) + inner + inst.edge(s.node(j), next);
                let after = inst.edge(prev, s.node(j)) + inner_rev + inst.edge(s.node(i), next);
                if after < before - 1e-9 {
                    s.tour[i..=j].reverse();
                    s.cost += after - before;
                    improved = true;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Viewpoints on a line at x = 1..=n, start and end at 0; each sees points {k, k+1}.
    struct OnALine;

    impl Pricer for OnALine {
        fn pair(&self, u: usize, v: usize) -> (f64, f64) {
            let x = |node: usize| if node < 2 { 0.0 } else { (node - 1) as f64 };
            let d = (x(u) - x(v)).abs();
            (d, d)
        }
    }

    fn line(n: usize, budget: f64) -> Instance<'static> {
        let mut inst = Instance::new(&OnALine, vec![1.0; n + 1], budget, n);
        for k in 0..n as u32 {
            assert!(inst.add_viewpoint(vec![k, k + 1], 0.0));
        }
        inst
    }

    #[test]
    fn the_reward_kept_is_the_union_and_the_budget_holds() {
        for budget in [0.0, 3.0, 8.0, 100.0] {
            let inst = line(10, budget);
            let mut search = Search::new(&inst, 7);
            for _ in 0..50 {
                search.iterate(&inst);
            }
            let best = &search.best;
            assert!(best.cost <= budget + 1e-9);
            assert!((best.cost - inst.tour_cost(&best.tour)).abs() < 1e-9);
            assert_eq!(best.reward, inst.tour_reward(&best.tour));
            // going out to x and back costs 2x and sees points 0..=x: the search finds the most
            let reach = (budget / 2.0).floor().min(10.0);
            let expected = if reach >= 1.0 { reach + 1.0 } else { 0.0 };
            assert_eq!(best.reward, expected, "budget {budget}: {:?}", best.tour);
        }
    }

    #[test]
    fn two_opt_untangles_a_path() {
        let inst = line(6, 100.0);
        let mut s = Solution::empty(&inst);
        for (pos, k) in [3, 0, 5, 1, 4, 2].into_iter().enumerate() {
            s.insert(&inst, k, pos);
        }
        two_opt(&inst, &mut s);
        assert!((s.cost - 12.0).abs() < 1e-9, "{:?} {}", s.tour, s.cost);
        assert!((s.cost - inst.tour_cost(&s.tour)).abs() < 1e-9);
    }
}
