//! The local search of the GTSP heuristic: 2-opt (reverse a stretch of the sequence, flying
//! each of its nodes the other way) and Or-opt (move a chain of 1–3 clusters elsewhere, maybe
//! reversed; a single cluster may also change node), then the best node per cluster.
//!
//! Moves are only tried where a new link goes to one of a node's nearest neighbours, and only
//! around clusters whose links changed (a queue, the "don't look bits" of Bentley): a full
//! pass costs O(m·K) and the repair after a kick stays local. Moves are found on the reversal
//! symmetry `c(u → v) = c(rev v → rev u)` (true for straight transits and Dubins paths) and
//! kept only when their exact change of the total is negative, so an asymmetric cost can only
//! make the search weaker, never wrong.

use std::collections::VecDeque;

use super::{Instance, optimise_clusters};

/// The cheapest successors of each node, and the cheapest first and last nodes.
pub struct Neighbours {
    pub out: Vec<Vec<usize>>,
    /// Cheapest to enter from the start.
    pub first: Vec<usize>,
    /// Nodes whose reverse is cheapest to leave for the end.
    last_reversed: Vec<usize>,
}

impl Neighbours {
    /// `k` neighbours per node among the instance's candidates (or every node).
    pub fn new(inst: &Instance, of: &[usize], k: usize) -> Self {
        let n = inst.n();
        let ranked = |nodes: &mut dyn Iterator<Item = usize>, key: &dyn Fn(usize) -> f64| -> Vec<usize> {
            let mut keyed: Vec<(f64, usize)> = nodes.map(|v| (key(v), v)).collect();
            keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            keyed.into_iter().take(k).map(|(_, v)| v).collect()
        };
        let out = (0..n)
            .map(|u| {
                let mut others: Box<dyn Iterator<Item = usize>> = match &inst.candidates {
                    Some(c) => Box::new(c[u].iter().copied().filter(|&v| of[v] != of[u])),
                    None => Box::new((0..n).filter(|&v| of[v] != of[u])),
                };
                ranked(&mut others, &|v| inst.floor(u, v))
            })
            .collect();
        let first = ranked(&mut (0..n), &|v| inst.start(v) + inst.node_cost[v]);
        let last_reversed = ranked(&mut (0..n), &|v| inst.end(v)).into_iter().map(|v| inst.reverse[v]).collect();
        Self { out, first, last_reversed }
    }
}

/// A sequence with the position of each cluster in it and its total.
struct Tour<'i, 'a> {
    inst: &'i Instance<'a>,
    of: &'i [usize],
    seq: Vec<usize>,
    pos: Vec<usize>,
    total: f64,
}

/// Improves `seq` (of cost `total`) by moves around the `active` clusters and those the moves
/// touch, until none improves; with `whole`, then the best node of every cluster, and again.
/// Returns the sequence and its total.
pub fn local_search(inst: &Instance, nb: &Neighbours, of: &[usize], (seq, total): (Vec<usize>, f64), active: impl IntoIterator<Item = usize>, whole: bool) -> (Vec<usize>, f64) {
    let mut tour = Tour { inst, of, pos: vec![0; inst.clusters.len()], total, seq };
    tour.reindex();
    if tour.seq.len() < 2 {
        return (tour.seq, tour.total);
    }
    let mut queue = Queue { queued: vec![false; inst.clusters.len()], order: VecDeque::new() };
    active.into_iter().for_each(|k| queue.push(k));
    loop {
        while let Some(k) = queue.pop() {
            if let Some(touched) = tour.improve(k, nb) {
                touched.into_iter().chain([k]).for_each(|c| queue.push(c));
            }
            // a stopped plan's connections all cost "no way": every move would look like a gain
            if inst.stop.requested() {
                return (tour.seq, tour.total);
            }
        }
        if !whole {
            return (tour.seq, tour.total);
        }
        let optimised = optimise_clusters(inst, &tour.seq);
        let changed: Vec<usize> = optimised.iter().zip(&tour.seq).filter(|(a, b)| a != b).map(|(&a, _)| of[a]).collect();
        if changed.is_empty() || !tour.accept(optimised) {
            return (tour.seq, tour.total);
        }
        changed.into_iter().for_each(|c| queue.push(c));
    }
}

/// Clusters to look at, each queued at most once.
struct Queue {
    queued: Vec<bool>,
    order: VecDeque<usize>,
}

impl Queue {
    fn push(&mut self, k: usize) {
        if !std::mem::replace(&mut self.queued[k], true) {
            self.order.push_back(k);
        }
    }

    fn pop(&mut self) -> Option<usize> {
        let k = self.order.pop_front()?;
        self.queued[k] = false;
        Some(k)
    }
}

/// Smallest improvement taken, in cost units (metres): well above the rounding of sums over
/// thousands of links, so that rounding noise never passes for an improvement and moves
/// cannot cycle.
pub const EPS: f64 = 1e-3;

impl Tour<'_, '_> {
    fn reindex(&mut self) {
        for (i, &v) in self.seq.iter().enumerate() {
            self.pos[self.of[v]] = i;
        }
    }

    fn at(&self, i: isize) -> Option<usize> {
        usize::try_from(i).ok().and_then(|i| self.seq.get(i).copied())
    }

    /// Takes `cand` if its total is lower.
    fn accept(&mut self, cand: Vec<usize>) -> bool {
        let total = self.inst.total(&cand);
        let better = total < self.total - EPS;
        if better {
            self.seq = cand;
            self.total = total;
            self.reindex();
        }
        better
    }

    fn clusters(&self, nodes: &[Option<usize>]) -> Vec<usize> {
        nodes.iter().flatten().map(|&v| self.of[v]).collect()
    }

    /// The first improving move around cluster `k`, made; the clusters whose links changed.
    fn improve(&mut self, k: usize, nb: &Neighbours) -> Option<Vec<usize>> {
        let i = self.pos[k];
        self.reverse_from(i, nb).or_else(|| self.reverse_to(i, nb)).or_else(|| self.move_chain(i, nb))
    }

    /// 2-opt with the stretch starting at `i`: the new first link goes to a neighbour.
    fn reverse_from(&mut self, i: usize, nb: &Neighbours) -> Option<Vec<usize>> {
        let near = match self.at(i as isize - 1) {
            Some(p) => &nb.out[p],
            None => &nb.first,
        };
        for &w in near {
            let j = self.pos[self.of[w]];
            if j >= i
                && self.seq[j] == self.inst.reverse[w]
                && let Some(t) = self.reverse(i, j)
            {
                return Some(t);
            }
        }
        None
    }

    /// 2-opt with the stretch ending at `j`: the new last link is cheap, found by symmetry
    /// among the neighbours of the reversed successor.
    fn reverse_to(&mut self, j: usize, nb: &Neighbours) -> Option<Vec<usize>> {
        let near = match self.at(j as isize + 1) {
            Some(q) => &nb.out[self.inst.reverse[q]],
            None => &nb.last_reversed,
        };
        for &y in near {
            let i = self.pos[self.of[y]];
            if i <= j
                && self.seq[i] == y
                && let Some(t) = self.reverse(i, j)
            {
                return Some(t);
            }
        }
        None
    }

    /// Reverses `seq[i..=j]` if that improves the total: priced on the floors of its two new
    /// links first, then of all its new links, then exactly.
    fn reverse(&mut self, i: usize, j: usize) -> Option<Vec<usize>> {
        let inst = self.inst;
        let rev = &inst.reverse;
        let (p, q) = (self.at(i as isize - 1), self.at(j as isize + 1));
        let (a, b) = (self.seq[i], self.seq[j]);
        let gone = inst.link(p, Some(a)) + inst.link(Some(b), q);
        let ends_floor = inst.link_floor(p, Some(rev[b])) + inst.link_floor(Some(rev[a]), q) - gone;
        // written so that a move priced NaN (links of infinite cost on both sides: no way at
        // all) is never taken, which would loop for ever
        if ends_floor.is_nan() || ends_floor >= -EPS {
            return None;
        }
        let stretch = &self.seq[i..=j];
        let flown: f64 = stretch.iter().map(|&v| inst.node_cost[rev[v]] - inst.node_cost[v]).sum::<f64>() - stretch.windows(2).map(|w| inst.c(w[0], w[1])).sum::<f64>();
        let reversed = |link: &dyn Fn(usize, usize) -> f64| stretch.windows(2).map(|w| link(rev[w[1]], rev[w[0]])).sum::<f64>();
        let floor = ends_floor + flown + reversed(&|u, v| inst.floor(u, v));
        if floor.is_nan() || floor >= -EPS {
            return None;
        }
        let ends = inst.link(p, Some(rev[b])) + inst.link(Some(rev[a]), q) - gone;
        let delta = ends + flown + reversed(&|u, v| inst.c(u, v));
        if delta.is_nan() || delta >= -EPS {
            return None;
        }
        self.seq[i..=j].reverse();
        for t in i..=j {
            self.seq[t] = rev[self.seq[t]];
            self.pos[self.of[self.seq[t]]] = t;
        }
        self.total += delta;
        Some(self.clusters(&[p, Some(a), Some(b), q]))
    }

    /// Or-opt: the chain of 1–3 clusters starting at `i` moved next to a neighbour of its
    /// first node (by symmetry) or of its last, or to either end.
    fn move_chain(&mut self, i: usize, nb: &Neighbours) -> Option<Vec<usize>> {
        let inst = self.inst;
        let rev = &inst.reverse;
        let m = self.seq.len();
        for len in 1..=3 {
            if i + len > m || len >= m {
                break;
            }
            let chain: Vec<usize> = self.seq[i..i + len].to_vec();
            let (p, q) = (self.at(i as isize - 1), self.at((i + len) as isize));
            let inner_on =
                |c: &[usize], link: &dyn Fn(usize, usize) -> f64| c.iter().map(|&v| inst.node_cost[v]).sum::<f64>() + c.windows(2).map(|x| link(x[0], x[1])).sum::<f64>();
            let inner = |c: &[usize]| inner_on(c, &|u, v| inst.c(u, v));
            let inner_floor = |c: &[usize]| inner_on(c, &|u, v| inst.floor(u, v));
            // what taking the chain out saves, at most (the new link p → q on its floor), and exactly
            let kept = inst.link(p, Some(chain[0])) + inst.link(Some(chain[len - 1]), q) + inner(&chain);
            let removed_at_most = kept - inst.link_floor(p, q);
            let mut removed = None;
            let options: Vec<Vec<usize>> =
                if len == 1 { inst.clusters[self.of[chain[0]]].iter().map(|&v| vec![v]).collect() } else { vec![chain.clone(), chain.iter().rev().map(|&v| rev[v]).collect()] };
            // the rest of the sequence without the chain, by index
            let rest_len = m - len;
            let rest_at = |k: isize| -> Option<usize> {
                let k = usize::try_from(k).ok().filter(|&k| k < rest_len)?;
                Some(if k < i { self.seq[k] } else { self.seq[k + len] })
            };
            let rest_index = |v: usize| -> Option<usize> {
                let at = self.pos[self.of[v]];
                (self.seq[at] == v && !(i..i + len).contains(&at)).then(|| if at < i { at } else { at - len })
            };
            for moved in &options {
                let (f, l) = (moved[0], moved[len - 1]);
                let spots = [0, rest_len]
                    .into_iter()
                    .chain(nb.out[rev[f]].iter().filter_map(|&y| rest_index(rev[y]).map(|k| k + 1)))
                    .chain(nb.out[l].iter().filter_map(|&w| rest_index(w)));
                let added_inner_floor = inner_floor(moved);
                let mut added_inner = None;
                for k in spots {
                    if k == i && moved == &chain {
                        continue;
                    }
                    let (u, w) = (rest_at(k as isize - 1), rest_at(k as isize));
                    let split = inst.link(u, w);
                    let floor = inst.link_floor(u, Some(f)) + inst.link_floor(Some(l), w) - split + added_inner_floor - removed_at_most;
                    if floor.is_nan() || floor >= -EPS {
                        continue;
                    }
                    // the new links exactly before the one that closes the gap: p → q often
                    // spans the field (a turn's other end), costly to price and seldom worth it
                    let added_inner = *added_inner.get_or_insert_with(|| inner(moved));
                    let added = inst.link(u, Some(f)) + inst.link(Some(l), w) - split + added_inner;
                    if (added - removed_at_most).is_nan() || added - removed_at_most >= -EPS {
                        continue;
                    }
                    let removed = *removed.get_or_insert_with(|| kept - inst.link(p, q));
                    let delta = added - removed;
                    if delta < -EPS {
                        let rest = (0..rest_len).map(|x| rest_at(x as isize).expect("in range"));
                        let cand: Vec<usize> = rest.clone().take(k).chain(moved.iter().copied()).chain(rest.skip(k)).collect();
                        let mut around = vec![p, q, u, w];
                        around.extend(chain.iter().map(|&v| Some(v)));
                        let touched = self.clusters(&around);
                        self.seq = cand;
                        self.total += delta;
                        self.reindex();
                        return Some(touched);
                    }
                }
            }
        }
        None
    }
}
