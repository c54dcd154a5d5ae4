//! Exact solution by dynamic programming over cluster subsets (Held–Karp): 2^m · n states,
//! for instances of a dozen clusters or fewer.

use super::Instance;

/// The optimal sequence: one node per cluster, in flight order.
pub fn held_karp(inst: &Instance) -> Vec<usize> {
    let (m, n) = (inst.clusters.len(), inst.n());
    let of = inst.cluster_of();
    let full = (1usize << m) - 1;
    let mut dp = vec![f64::INFINITY; (full + 1) * n];
    let mut parent = vec![usize::MAX; (full + 1) * n];
    for v in 0..n {
        dp[(1 << of[v]) * n + v] = inst.start(v) + inst.node_cost[v];
    }
    for set in 1..=full {
        for v in 0..n {
            let here = dp[set * n + v];
            if !here.is_finite() || set & (1 << of[v]) == 0 {
                continue;
            }
            for (k, cluster) in inst.clusters.iter().enumerate() {
                if set & (1 << k) != 0 {
                    continue;
                }
                let next_set = set | (1 << k);
                for &w in cluster {
                    let cost = here + inst.c(v, w) + inst.node_cost[w];
                    if cost < dp[next_set * n + w] {
                        dp[next_set * n + w] = cost;
                        parent[next_set * n + w] = v;
                    }
                }
            }
        }
    }
    let mut best = (f64::INFINITY, usize::MAX);
    for v in 0..n {
        let total = dp[full * n + v] + inst.end(v);
        if total < best.0 {
            best = (total, v);
        }
    }
    if best.1 == usize::MAX {
        // every order is infeasible: any order will do, the caller reports the gap
        return inst.clusters.iter().map(|c| c[0]).collect();
    }
    let (mut set, mut v) = (full, best.1);
    let mut seq = Vec::with_capacity(m);
    while v != usize::MAX {
        seq.push(v);
        let p = parent[set * n + v];
        set &= !(1 << of[v]);
        v = p;
    }
    seq.reverse();
    seq
}
