//! Exact solution by dynamic programming over cluster subsets (Held–Karp): 2^m · n states,
//! for instances of a dozen clusters or fewer.

use super::Instance;

/// The optimal sequence: one node per cluster, in flight order.
pub fn held_karp(inst: &Instance) -> Vec<usize> {
    let (m, n) = (inst.clusters.len(), inst.n());
    assert!(m < usize::BITS as usize && n < u16::MAX as usize, "an instance far too large for Held–Karp");
    let bit: Vec<usize> = inst.cluster_of().iter().map(|&k| 1 << k).collect();
    // each step's cost (the connection and the node entered) read once: the loop below runs
    // 2^m · n² times
    let step: Vec<f64> = (0..n * n).map(|i| inst.c(i / n, i % n) + inst.node_cost[i % n]).collect();
    let full = (1usize << m) - 1;
    let mut dp = vec![f64::INFINITY; (full + 1) * n];
    let mut parent = vec![u16::MAX; (full + 1) * n];
    for v in 0..n {
        dp[bit[v] * n + v] = inst.start(v) + inst.node_cost[v];
    }
    for set in 1..=full {
        for v in 0..n {
            let here = dp[set * n + v];
            if set & bit[v] == 0 || !here.is_finite() {
                continue;
            }
            let row = &step[v * n..(v + 1) * n];
            for w in 0..n {
                if set & bit[w] != 0 {
                    continue;
                }
                let at = (set | bit[w]) * n + w;
                let cost = here + row[w];
                if cost < dp[at] {
                    dp[at] = cost;
                    parent[at] = v as u16;
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
    loop {
        seq.push(v);
        let p = parent[set * n + v];
        set &= !bit[v];
        if p == u16::MAX {
            break;
        }
        v = p as usize;
    }
    seq.reverse();
    seq
}
