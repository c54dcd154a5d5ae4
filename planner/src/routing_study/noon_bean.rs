//! Noon–Bean transformation (Noon and Bean 1993; seed 004 §4.2.2): a GTSP over two-node clusters becomes an
//! asymmetric TSP whose optimal tours are the GTSP's optimal paths plus `(clusters − 1)·M`,
//! for external ATSP solvers such as LKH (seeds 003 and 004 solve their instances this way)
//! and for [`solve`], the built-in ATSP search on it, which `coverplan bench --routing`
//! compares with the direct search of [`crate::route::gtsp`]. No planner uses it: the direct
//! search is shorter and, from 300 lines on, faster (README, "Routing").
//!
//! Row-shift convention: the flown node is the one through which the tour enters its
//! cluster; the tour then steps to the partner for free and leaves from it, paying the cost
//! of leaving the entry node plus `M`. Seed 004's Table 4.2 mixes this with the column-shift
//! convention and is not exact; the tests below check this one against brute force.

use super::atsp::{self, Matrix};
use crate::route::gtsp::Instance;

/// An ATSP over the instance's nodes plus a start node `n` and an end node `n + 1`.
pub struct Atsp {
    pub matrix: Matrix,
    /// Added to every arc between clusters.
    pub big_m: f64,
}

/// Transforms an instance whose clusters are pairs `{u, reverse[u]}`. Node costs go on the
/// arcs entering their node.
pub fn to_atsp(inst: &Instance) -> Atsp {
    let n = inst.node_cost.len();
    debug_assert!(inst.clusters.iter().all(|c| c.len() == 2));
    let (s, e, size) = (n, n + 1, n + 2);
    let d = |u: usize, w: usize| inst.c(u, w) + inst.node_cost[w];
    let start = |w: usize| inst.from_start.as_ref().map_or(0.0, |f| f[w]) + inst.node_cost[w];
    let end = |u: usize| inst.to_end.as_ref().map_or(0.0, |t| t[u]);
    let largest = (0..n)
        .flat_map(|u| (0..n).map(move |w| (u, w)))
        .filter(|&(u, w)| u != w && inst.reverse[u] != w)
        .map(|(u, w)| d(u, w))
        .chain((0..n).map(start))
        .chain((0..n).map(end))
        .fold(0.0f64, f64::max);
    let big_m = (inst.clusters.len() as f64 + 2.0) * largest.max(1.0);
    let mut cost = vec![f64::INFINITY; size * size];
    for u in 0..n {
        let partner = inst.reverse[u];
        cost[u * size + partner] = 0.0;
        for w in 0..n {
            if w != u && w != partner {
                cost[u * size + w] = d(partner, w) + big_m;
            }
        }
        cost[u * size + e] = end(partner);
        cost[s * size + u] = start(u);
    }
    cost[e * size + s] = 0.0;
    Atsp { matrix: Matrix { size, cost }, big_m }
}

/// The GTSP sequence that the ATSP search ([`atsp::solve`], with `kicks` kicks) finds on the
/// transformed instance; `None` if its tour splits a cluster (it never should: that costs an
/// extra `M`).
pub fn solve(inst: &Instance, kicks: usize) -> Option<Vec<usize>> {
    let atsp = to_atsp(inst);
    let tour = atsp::solve(&atsp.matrix, inst.node_cost.len(), kicks);
    from_atsp_tour(inst, &tour)
}

/// The GTSP sequence flown by an ATSP tour (a cyclic order of all nodes), or `None` when the
/// tour splits a cluster.
pub fn from_atsp_tour(inst: &Instance, tour: &[usize]) -> Option<Vec<usize>> {
    let n = inst.node_cost.len();
    let at = tour.iter().position(|&v| v == n)?;
    let rotated: Vec<usize> = tour[at..].iter().chain(&tour[..at]).copied().collect();
    if rotated.len() != n + 2 || rotated[n + 1] != n + 1 {
        return None;
    }
    let body = &rotated[1..=n];
    body.chunks(2).map(|pair| (inst.reverse[pair[0]] == pair[1]).then_some(pair[0])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::route::gtsp::{Costs, held_karp};

    struct Rng(u64);
    impl Rng {
        fn below(&mut self, n: u64) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0 % n
        }
    }

    fn permutations(items: Vec<usize>) -> Vec<Vec<usize>> {
        if items.len() <= 1 {
            return vec![items];
        }
        let mut out = Vec::new();
        for i in 0..items.len() {
            let mut rest = items.clone();
            let first = rest.remove(i);
            for mut p in permutations(rest) {
                p.insert(0, first);
                out.push(p);
            }
        }
        out
    }

    /// the Noon–Bean check (docs/methods.md, routing §5): 200 random 3-cluster instances with integer costs
    /// 1–100; the brute-force ATSP optimum minus `2·M` is the brute-force GTSP optimum, and
    /// the optimal ATSP tour reads back as an optimal GTSP sequence.
    #[test]
    fn atsp_optimum_is_the_gtsp_optimum() {
        let mut rng = Rng(0x2545_F491_4F6C_DD1D);
        for _ in 0..200 {
            let n = 6;
            let mut int = |k: usize| (0..k).map(|_| 1.0 + rng.below(100) as f64).collect::<Vec<f64>>();
            let inst = Instance {
                clusters: vec![vec![0, 1], vec![2, 3], vec![4, 5]],
                reverse: (0..n).map(|v| v ^ 1).collect(),
                cost: Costs::Dense(int(n * n)),
                node_cost: int(n),
                from_start: Some(int(n)),
                to_end: Some(int(n)),
                candidates: None,
                stop: crate::stop::Stop::never(),
            };
            // GTSP by brute force: every cluster order and node choice
            let mut gtsp = f64::INFINITY;
            for order in permutations(vec![0, 1, 2]) {
                for pick in 0..8 {
                    let seq: Vec<usize> = order.iter().enumerate().map(|(i, &c)| 2 * c + ((pick >> i) & 1)).collect();
                    gtsp = gtsp.min(inst.total(&seq));
                }
            }
            assert_eq!(gtsp, inst.total(&held_karp(&inst)));
            let atsp = to_atsp(&inst);
            let (mut best, mut best_tour) = (f64::INFINITY, Vec::new());
            for p in permutations((0..n + 2).filter(|&v| v != n).collect()) {
                let tour: Vec<usize> = std::iter::once(n).chain(p).collect();
                let c = atsp.matrix.tour_cost(&tour);
                if c < best {
                    (best, best_tour) = (c, tour);
                }
            }
            assert!((best - 2.0 * atsp.big_m - gtsp).abs() < 1e-6, "ATSP {best} − 2M ≠ GTSP {gtsp}");
            let seq = from_atsp_tour(&inst, &best_tour).expect("clusters kept together");
            assert_eq!(inst.total(&seq), gtsp);
        }
    }
}
