//! Turning round on the headland (docs/methods.md, ground §2): where the headland has room, a
//! turn from one pass onto a pass driven the other way, or onto the next pass. A forward-only
//! vehicle on a ring reaches every point of it, but only in the direction it drives: a way whose
//! ramps join the rings in opposite directions needs one of these, found where the field's
//! corners leave room for a loop.

use std::collections::HashMap;

use rayon::prelude::*;

use super::{Bounds, HeadlandRoutes, ring_pose};
use crate::geom::distance;

/// A road driven one way: `(road, forward)`.
pub type Lane = (usize, bool);

/// A turn from a stop of one lane to a stop of another, inside the headland.
#[derive(Debug, Clone)]
pub struct Switch {
    pub from: Lane,
    pub from_vertex: usize,
    pub to: Lane,
    pub to_vertex: usize,
    pub points: Vec<geo::Coord>,
    pub length: f64,
}

/// The switches by the lanes they join.
pub type Switches = HashMap<(Lane, Lane), Vec<Switch>>;

/// Switches leave from one stop every this many turning radii along a road: a way that turns
/// round drives at most that much further than it would with a switch at every stop.
const SWITCH_EVERY_RADII: f64 = 2.0;
/// How far a switch's end may lie from its start, in turning radii: a loop onto the pass beside.
const SWITCH_REACH_RADII: f64 = 2.5;
/// Stops of each lane tried as a switch's end: the nearest.
const SWITCH_TARGETS: usize = 3;
/// Manoeuvres tried per pair of poses, shortest first.
const SWITCH_WORDS: usize = 4;

impl HeadlandRoutes {
    /// Every switch the headland has room for, from stops [`SWITCH_EVERY_RADII`] apart: per
    /// departure and lane, the shortest manoeuvre onto one of the lane's nearest stops.
    pub(super) fn find_switches(&self) -> Switches {
        let radius = self.steering.bounding_radius();
        let mut departures = Vec::new();
        let mut last: Option<(usize, f64)> = None;
        for (k, &(road, vertex, _)) in self.stops.iter().enumerate() {
            let at = self.roads[road].at[vertex];
            if last.is_none_or(|(r, a)| r != road || at - a >= SWITCH_EVERY_RADII * radius) {
                departures.push(k);
                last = Some((road, at));
            }
        }
        let found: Vec<Switch> = departures.par_iter().flat_map_iter(|&k| self.switches_from(k, SWITCH_REACH_RADII * radius)).collect();
        let mut by_lanes = Switches::new();
        for s in found {
            by_lanes.entry((s.from, s.to)).or_default().push(s);
        }
        by_lanes
    }

    /// The shortest switch from stop `k` (either way along its road) onto each lane nearby.
    fn switches_from(&self, k: usize, reach: f64) -> Vec<Switch> {
        let (road, vertex, at) = self.stops[k];
        let mut near: Vec<(f64, usize)> = self.stops.iter().enumerate().map(|(j, s)| (distance(s.2, at), j)).filter(|(d, _)| *d <= reach).collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut out = Vec::new();
        for forward in [true, false] {
            let from = ring_pose(&self.roads[road].points, vertex, forward);
            let mut tried: HashMap<Lane, usize> = HashMap::new();
            let mut best: HashMap<Lane, Switch> = HashMap::new();
            for &(_, j) in &near {
                let (to_road, to_vertex, _) = self.stops[j];
                for to_forward in [true, false] {
                    let lane = (to_road, to_forward);
                    let count = tried.entry(lane).or_insert(0);
                    if lane == (road, forward) || *count == SWITCH_TARGETS {
                        continue;
                    }
                    *count += 1;
                    let to = ring_pose(&self.roads[to_road].points, to_vertex, to_forward);
                    let clear = self.steering.manoeuvres(from, to).into_iter().take(SWITCH_WORDS).find_map(|m| self.cleared(&m, Bounds::Headland).map(|points| (points, m.length)));
                    if let Some((points, length)) = clear.filter(|(_, length)| best.get(&lane).is_none_or(|s| *length < s.length)) {
                        best.insert(lane, Switch { from: (road, forward), from_vertex: vertex, to: lane, to_vertex, points, length });
                    }
                }
            }
            out.extend(best.into_values());
        }
        out
    }
}
