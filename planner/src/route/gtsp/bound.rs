//! Lower bounds of the cost of every path through an instance, for pruning a search over
//! many instances (the heading combinations of `line_gtsp`).

use super::Instance;

/// Instances of at most this many clusters get the assignment bound: the Hungarian method's
/// O(m³) steps stay well below the cost of solving them.
const ASSIGNMENT_UP_TO: usize = 48;

/// No path through `inst` costs less. Every cluster is entered by its cheapest way in, and
/// left by its cheapest way out (the larger sum counts); on small instances, the assignment
/// relaxation, which is never lower: each cluster, and the start and end joined into one
/// place, gets a distinct successor at the least total cost.
pub fn lower_bound(inst: &Instance) -> f64 {
    let m = inst.clusters.len();
    if m == 0 {
        return 0.0;
    }
    let steps = cluster_steps(inst);
    if m <= ASSIGNMENT_UP_TO {
        return assignment(&steps);
    }
    let size = m + 1;
    let entered: f64 = (0..m).map(|j| (0..size).map(|i| steps[i * size + j]).fold(f64::INFINITY, f64::min)).sum();
    let left: f64 = (0..m).map(|i| (0..size).map(|j| steps[i * size + j]).fold(f64::INFINITY, f64::min)).sum();
    // entering a cluster also flies it; leaving one does not: add the cheapest flights
    let flown: f64 = inst.clusters.iter().map(|c| c.iter().map(|&v| inst.node_cost[v]).fold(f64::INFINITY, f64::min)).sum();
    entered.max(left + flown)
}

/// Cheapest step between clusters, `(m + 1)²` row-major, index `m` standing for the start
/// (as a row) and the end (as a column): from cluster `i` to cluster `j`, the cheapest
/// connection between their nodes (on its floor: a bound need not price every pair) plus
/// flying the node entered.
fn cluster_steps(inst: &Instance) -> Vec<f64> {
    let m = inst.clusters.len();
    let size = m + 1;
    let mut steps = vec![f64::INFINITY; size * size];
    for (j, to) in inst.clusters.iter().enumerate() {
        steps[m * size + j] = to.iter().map(|&v| inst.start(v) + inst.node_cost[v]).fold(f64::INFINITY, f64::min);
        for (i, from) in inst.clusters.iter().enumerate().filter(|&(i, _)| i != j) {
            steps[i * size + j] = from.iter().flat_map(|&u| to.iter().map(move |&v| (u, v))).map(|(u, v)| inst.floor(u, v) + inst.node_cost[v]).fold(f64::INFINITY, f64::min);
        }
    }
    for (i, from) in inst.clusters.iter().enumerate() {
        steps[i * size + m] = from.iter().map(|&u| inst.end(u)).fold(f64::INFINITY, f64::min);
    }
    steps
}

/// Least total of a permutation without fixed points of the square matrix `a` (the
/// Hungarian method with potentials, O(size³)).
fn assignment(a: &[f64]) -> f64 {
    let size = (a.len() as f64).sqrt().round() as usize;
    // the diagonal is forbidden: a finite stand-in far above any real cost keeps the
    // potentials' arithmetic free of infinities
    const FORBIDDEN: f64 = 1e15;
    let at = |i: usize, j: usize| if i == j || !a[i * size + j].is_finite() { FORBIDDEN } else { a[i * size + j] };
    // 1-based rows and columns; column 0 is the free one the search starts from
    let (mut u, mut v) = (vec![0.0; size + 1], vec![0.0; size + 1]);
    let (mut row_of, mut way) = (vec![0usize; size + 1], vec![0usize; size + 1]);
    for i in 1..=size {
        row_of[0] = i;
        let mut j0 = 0;
        let mut min_to = vec![f64::INFINITY; size + 1];
        let mut used = vec![false; size + 1];
        loop {
            used[j0] = true;
            let i0 = row_of[j0];
            let (mut delta, mut j1) = (f64::INFINITY, 0);
            for j in 1..=size {
                if used[j] {
                    continue;
                }
                let reduced = at(i0 - 1, j - 1) - u[i0] - v[j];
                if reduced < min_to[j] {
                    min_to[j] = reduced;
                    way[j] = j0;
                }
                if min_to[j] < delta {
                    delta = min_to[j];
                    j1 = j;
                }
            }
            for j in 0..=size {
                if used[j] {
                    u[row_of[j]] += delta;
                    v[j] -= delta;
                } else {
                    min_to[j] -= delta;
                }
            }
            j0 = j1;
            if row_of[j0] == 0 {
                break;
            }
        }
        loop {
            let j1 = way[j0];
            row_of[j0] = row_of[j1];
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    // the total of the entries chosen, not of the potentials: no rounding in the bound's favour
    (1..=size).map(|j| at(row_of[j] - 1, j - 1)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assignment_finds_the_cheapest_derangement() {
        // brute force over every permutation without fixed points of random 5 × 5 matrices
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) as f64 / (1u64 << 31) as f64 * 100.0
        };
        fn permutations(rest: &mut Vec<usize>, out: &mut Vec<Vec<usize>>, now: &mut Vec<usize>) {
            if rest.is_empty() {
                out.push(now.clone());
                return;
            }
            for i in 0..rest.len() {
                let x = rest.remove(i);
                now.push(x);
                permutations(rest, out, now);
                now.pop();
                rest.insert(i, x);
            }
        }
        let mut perms = Vec::new();
        permutations(&mut (0..5).collect(), &mut perms, &mut Vec::new());
        for _ in 0..50 {
            let a: Vec<f64> = (0..25).map(|_| next()).collect();
            let best = perms
                .iter()
                .filter(|p| p.iter().enumerate().all(|(i, &j)| i != j))
                .map(|p| p.iter().enumerate().map(|(i, &j)| a[i * 5 + j]).sum::<f64>())
                .fold(f64::INFINITY, f64::min);
            assert!((assignment(&a) - best).abs() < 1e-9, "{} vs {best}", assignment(&a));
        }
    }
}
