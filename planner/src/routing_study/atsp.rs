//! Asymmetric TSP by iterated local search, for the tours of a Noon–Bean instance
//! ([`super::noon_bean`]): Or-opt moves (a chain of one to three nodes taken out and put back
//! elsewhere, in the same direction, the only 2- and 3-exchanges that keep every arc's
//! direction) towards each node's cheapest successors and predecessors, and segment-limited
//! double-bridge kicks. Deterministic: a fixed-seed generator drives the kicks.

use std::collections::VecDeque;

use crate::route::gtsp::Rng;

/// Cheapest successors and predecessors kept per node.
const NEIGHBOURS: usize = 10;
/// Longest chain an Or-opt move carries.
const CHAIN: usize = 3;
/// Longest segment a double-bridge kick moves.
const KICK_SEGMENT: usize = 50;
/// Smallest gain worth a move.
const EPS: f64 = 1e-7;

/// A dense ATSP: `cost[i * size + j]`, `f64::INFINITY` where there is no arc.
pub struct Matrix {
    pub size: usize,
    pub cost: Vec<f64>,
}

impl Matrix {
    fn c(&self, i: usize, j: usize) -> f64 {
        self.cost[i * self.size + j]
    }

    /// Cost of the closed tour.
    pub fn tour_cost(&self, tour: &[usize]) -> f64 {
        (0..tour.len()).map(|i| self.c(tour[i], tour[(i + 1) % tour.len()])).sum()
    }

    /// The `k` cheapest finite arcs out of (or into) each node.
    fn nearest(&self, k: usize, out: bool) -> Vec<Vec<usize>> {
        (0..self.size)
            .map(|u| {
                let arc = |v: usize| if out { self.c(u, v) } else { self.c(v, u) };
                let mut near: Vec<(f64, usize)> = (0..self.size).filter(|&v| v != u && arc(v).is_finite()).map(|v| (arc(v), v)).collect();
                near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                near.into_iter().take(k).map(|(_, v)| v).collect()
            })
            .collect()
    }
}

/// A closed tour starting at node `first`, from the nearest-neighbour tour, improved by Or-opt
/// and `kicks` double-bridge kicks.
pub fn solve(m: &Matrix, first: usize, kicks: usize) -> Vec<usize> {
    let succ = m.nearest(NEIGHBOURS, true);
    let pred = m.nearest(NEIGHBOURS, false);
    let mut tour = nearest_neighbour(m, first);
    let mut total = m.tour_cost(&tour);
    or_opt(m, &succ, &pred, &mut tour, &mut total, (0..m.size).collect());
    let n = m.size;
    if n < 8 {
        return tour;
    }
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for _ in 0..kicks {
        // A B C D → A C B D with B and C short; the first node stays first
        let x = 1 + rng.below(n - 3);
        let y = x + 1 + rng.below(KICK_SEGMENT.min(n - 2 - x));
        let z = y + 1 + rng.below(KICK_SEGMENT.min(n - 1 - y));
        let mut kicked: Vec<usize> = tour[..x].iter().chain(&tour[y..z]).chain(&tour[x..y]).chain(&tour[z..]).copied().collect();
        let mut cost = m.tour_cost(&kicked);
        let touched = [x - 1, x, y - 1, y, z - 1, z % n].into_iter().map(|p| tour[p]).collect();
        or_opt(m, &succ, &pred, &mut kicked, &mut cost, touched);
        if cost < total - EPS {
            tour = kicked;
            total = cost;
        }
    }
    tour
}

fn nearest_neighbour(m: &Matrix, first: usize) -> Vec<usize> {
    let mut seen = vec![false; m.size];
    let mut tour = vec![first];
    seen[first] = true;
    while tour.len() < m.size {
        let u = *tour.last().expect("not empty");
        let next = (0..m.size).filter(|&v| !seen[v]).min_by(|&a, &b| m.c(u, a).total_cmp(&m.c(u, b))).expect("a node is left");
        seen[next] = true;
        tour.push(next);
    }
    tour
}

/// Or-opt until no move improves, starting from the chains at the `active` nodes and
/// revisiting the nodes each move touches. Moves are tried where a new arc is one of the
/// cheapest out of or into a node, and kept when their exact change is negative.
fn or_opt(m: &Matrix, succ: &[Vec<usize>], pred: &[Vec<usize>], tour: &mut Vec<usize>, total: &mut f64, active: Vec<usize>) {
    let n = tour.len();
    let mut pos = vec![0; n];
    let index = |tour: &[usize], pos: &mut [usize]| tour.iter().enumerate().for_each(|(i, &v)| pos[v] = i);
    index(tour, &mut pos);
    let mut queued = vec![false; n];
    let mut queue: VecDeque<usize> = VecDeque::new();
    for v in active {
        enqueue(&mut queue, &mut queued, v);
    }
    while let Some(f) = queue.pop_front() {
        queued[f] = false;
        'chains: for len in 1..=CHAIN {
            // the chain f … l, between p and q; the first node of the tour never moves
            let i = pos[f];
            if i == 0 || i + len > n || len + 2 > n {
                break;
            }
            let l = tour[i + len - 1];
            let (p, q) = (tour[i - 1], tour[(i + len) % n]);
            let removed = m.c(p, q) - m.c(p, f) - m.c(l, q);
            let in_chain = |v: usize| pos[v] >= i && pos[v] < i + len;
            // insert between a and b = next(a): a → f cheap, or l → b cheap
            let spots = pred[f].iter().map(|&a| (a, tour[(pos[a] + 1) % n])).chain(succ[l].iter().map(|&b| (tour[(pos[b] + n - 1) % n], b)));
            for (a, b) in spots {
                if in_chain(a) || in_chain(b) {
                    continue;
                }
                let delta = removed + m.c(a, f) + m.c(l, b) - m.c(a, b);
                if delta < -EPS {
                    let chain: Vec<usize> = tour.drain(i..i + len).collect();
                    // before b, or last when b is the first node
                    let at = if b == tour[0] { tour.len() } else { tour.iter().position(|&v| v == b).expect("b is in the tour") };
                    tour.splice(at..at, chain);
                    index(tour, &mut pos);
                    *total += delta;
                    for v in [p, q, a, b, f, l] {
                        enqueue(&mut queue, &mut queued, v);
                    }
                    break 'chains;
                }
            }
        }
    }
}

fn enqueue(queue: &mut VecDeque<usize>, queued: &mut [bool], v: usize) {
    if !queued[v] {
        queued[v] = true;
        queue.push_back(v);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on a circle visited in any order: the best tour goes round the circle, and the
    /// search finds it from its nearest-neighbour start on an asymmetric variant too.
    #[test]
    fn finds_the_round_trip_on_a_circle() {
        let n = 40;
        let pts: Vec<(f64, f64)> = (0..n)
            .map(|k| {
                let a = (k * 17 % n) as f64 * std::f64::consts::TAU / n as f64;
                (a.cos() * 100.0, a.sin() * 100.0)
            })
            .collect();
        // going counter-clockwise is cheap, clockwise twice as dear
        let cost: Vec<f64> = (0..n * n)
            .map(|i| {
                let (u, v) = (i / n, i % n);
                if u == v {
                    return f64::INFINITY;
                }
                let d = (pts[u].0 - pts[v].0).hypot(pts[u].1 - pts[v].1);
                let ccw = pts[u].0 * pts[v].1 - pts[u].1 * pts[v].0 > 0.0;
                if ccw { d } else { 2.0 * d }
            })
            .collect();
        let m = Matrix { size: n, cost };
        let tour = solve(&m, 0, 200);
        let mut sorted = tour.clone();
        sorted.sort();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        assert_eq!(tour[0], 0);
        let chord = 2.0 * 100.0 * (std::f64::consts::PI / n as f64).sin();
        assert!((m.tour_cost(&tour) - n as f64 * chord).abs() < 1e-6, "{} for {}", m.tour_cost(&tour), n as f64 * chord);
    }
}
