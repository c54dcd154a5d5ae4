//! A ground vehicle's connections (docs/methods.md, ground §2–§4). Between two swaths the
//! vehicle turns in the headland: the shortest manoeuvre (Dubins word, or fishtail when it may
//! reverse) that crosses neither the field's edge, a hole, nor the mainland; where none fits,
//! it drives onto a headland pass, along it, and off again (the headland ring as a road).
//! Transits (from the start, between headland rings, to the end) may cross the mainland but
//! never leave the field. Swaths of different fields are joined by the road outside, a Dubins
//! path nothing constrains.
//!
//! The order of the swaths is a generalised TSP over their two directions
//! ([`super::gtsp`]), priced lazily: a connection's floor is its length in open ground.

use std::sync::OnceLock;

use geo::{Coord, MultiPolygon};
use rayon::prelude::*;

use super::gtsp::{Costs, KnownCosts};
use super::line_tour::{Line, NO_WAY, entry, exit, line_instance, nearest_entries};
use crate::geom::{EdgeIndex, distance, polyline_length};
use crate::path::TurnShape;
use crate::stop::Stop;
use crate::turn::dubins::Pose;
use crate::turn::ground::{Manoeuvre, Steering};
use crate::turn::turnable_stretch;

/// A headland pass as a road: a closed ring with its arc lengths.
pub struct Road {
    points: Vec<Coord>,
    at: Vec<f64>,
}

impl Road {
    /// The ring with a vertex at least every `step` metres, where ramps may join it.
    fn new(ring: Vec<Coord>, step: f64) -> Self {
        let mut points = vec![ring[0]];
        for w in ring.windows(2) {
            let k = (distance(w[0], w[1]) / step).ceil().max(1.0) as usize;
            points.extend((1..=k).map(|i| w[0] + (w[1] - w[0]) * (i as f64 / k as f64)));
        }
        let mut at = vec![0.0];
        for w in points.windows(2) {
            at.push(at.last().expect("one") + distance(w[0], w[1]));
        }
        Road { points, at }
    }

    fn length(&self) -> f64 {
        *self.at.last().expect("a road has points")
    }

    /// Metres from vertex `i` to vertex `j` in the direction of travel.
    fn along(&self, i: usize, j: usize, forward: bool) -> f64 {
        let d = self.at[j] - self.at[i];
        let d = if forward { d } else { -d };
        d.rem_euclid(self.length())
    }

    /// The ring's points from vertex `i` to vertex `j` in the direction of travel.
    fn stretch(&self, i: usize, j: usize, forward: bool) -> Vec<Coord> {
        let n = self.points.len() - 1;
        let mut out = vec![self.points[i]];
        let mut k = i;
        loop {
            k = if forward { (k + 1) % n } else { (k + n - 1) % n };
            out.push(self.points[k]);
            if k == j {
                break;
            }
        }
        out
    }

    /// Vertices at least `spacing` apart along the ring, where ramps join it.
    fn stops(&self, spacing: f64) -> Vec<usize> {
        let mut out = vec![0];
        for i in 1..self.points.len() - 1 {
            if self.at[i] - self.at[*out.last().expect("one")] >= spacing {
                out.push(i);
            }
        }
        out
    }
}

/// The pose at vertex `i` (not the last) of a closed ring (first vertex repeated last), facing
/// along the ring (`forward`) or back.
pub fn ring_pose(ring: &[Coord], i: usize, forward: bool) -> Pose {
    let n = ring.len() - 1;
    let next = if forward { ring[i + 1] } else { ring[(i + n - 1) % n] };
    Pose::at(ring[i], (next.y - ring[i].y).atan2(next.x - ring[i].x))
}

/// A way found between two poses.
#[derive(Debug, Clone)]
pub struct Way {
    pub points: Vec<Coord>,
    pub length: f64,
    /// `Some` for a turn in the headland, `None` for a transit.
    pub shape: Option<TurnShape>,
}

/// Where the vehicle may go, and how it turns.
pub struct HeadlandRoutes {
    field: EdgeIndex,
    mainland: EdgeIndex,
    roads: Vec<Road>,
    /// Each road's ramp stops: `(road, vertex, position)`.
    stops: Vec<(usize, usize, Coord)>,
    steering: Steering,
    /// How far from a pose ramps onto a road are looked for.
    reach: f64,
}

/// What crossing the mainland between two swaths costs on top of its length, in metres: the
/// route takes it only where no way through the headland joins them.
const MAINLAND_CROSSING_M: f64 = 1000.0;

/// Stops tried per road and direction of travel for ramps from or to a pose: the nearest.
const RAMP_STOPS: usize = 12;
/// Clear ramps kept per road and direction: the shortest.
const RAMPS_KEPT: usize = 4;

/// A Dubins ramp between a pose and a road's vertex, driven along the road `forward` or back.
#[derive(Debug, Clone)]
pub struct Ramp {
    road: usize,
    vertex: usize,
    forward: bool,
    points: Vec<Coord>,
    length: f64,
}

/// What a connection may not cross: the field's edges, and for a turn the mainland's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bounds {
    /// Inside the headland.
    Headland,
    /// Inside the field, across the mainland if need be.
    Field,
}

impl HeadlandRoutes {
    /// `region`: the field less its holes and zones; `mainland`: where turns may not go;
    /// `roads`: the headland passes' rings.
    pub fn new(region: &MultiPolygon, mainland: &MultiPolygon, roads: Vec<Vec<Coord>>, steering: Steering, headland_m: f64) -> Self {
        let radius = steering.bounding_radius();
        let spacing = (radius / 2.0).max(1.0);
        let roads: Vec<Road> = roads.into_iter().filter(|r| r.len() >= 4).map(|r| Road::new(r, spacing)).collect();
        let stops = roads.iter().enumerate().flat_map(|(k, road)| road.stops(spacing).into_iter().map(move |i| (k, i, road.points[i]))).collect();
        HeadlandRoutes { field: EdgeIndex::new(region), mainland: EdgeIndex::new(mainland), roads, stops, steering, reach: 4.0 * radius + 2.0 * headland_m }
    }

    /// Below the length in open ground: no way between the poses is shorter.
    pub fn floor(&self, from: Pose, to: Pose) -> f64 {
        0.99 * self.steering.floor(from, to)
    }

    fn clear(&self, points: &[Coord], bounds: Bounds) -> bool {
        !self.field.crossed(points) && (bounds == Bounds::Field || !self.mainland.crossed(points))
    }

    /// The stretch of the swath `a → b` whose ends the vehicle can turn at: each end pulled
    /// back (in steps of an eighth of the radius) until a half turn to the left or the right
    /// from it stays in the field; `None` when nothing is left (a swath in an acute corner,
    /// where no turn fits).
    pub fn turnable(&self, a: Coord, b: Coord) -> Option<(Coord, Coord)> {
        turnable_stretch(a, b, self.steering.bounding_radius(), 0.05, |at, out| self.steering.half_turns(at, out).iter().any(|turn| !self.field.crossed(turn)))
    }

    /// Between fields, on the road outside them.
    pub fn outside(&self, from: Pose, to: Pose) -> Way {
        let points = self.steering.forward(from, to).points();
        Way { length: polyline_length(&points), points, shape: None }
    }

    /// Anywhere inside the field: the shortest manoeuvre that stays in it, or else along a
    /// headland pass.
    pub fn transit(&self, from: Pose, to: Pose) -> Option<Way> {
        let direct = self.steering.manoeuvres(from, to).into_iter().find_map(|m| {
            let points = m.points();
            self.clear(&points, Bounds::Field).then_some(Way { points, length: m.length, shape: None })
        });
        direct.or_else(|| {
            let (on, off) = (self.ramps(from, true, Bounds::Field), self.ramps(to, false, Bounds::Field));
            self.by_road(&on, &off)
        })
    }

    /// The shortest way onto a road by one of `on`, along it, and off by one of `off`.
    pub fn by_road(&self, on: &[Ramp], off: &[Ramp]) -> Option<Way> {
        let mut best: Option<(f64, &Ramp, &Ramp)> = None;
        for a in on {
            for b in off.iter().filter(|b| b.road == a.road && b.forward == a.forward) {
                let total = a.length + self.roads[a.road].along(a.vertex, b.vertex, a.forward) + b.length;
                if best.is_none_or(|x| total < x.0) {
                    best = Some((total, a, b));
                }
            }
        }
        let (length, a, b) = best?;
        let mut points = a.points.clone();
        if a.vertex != b.vertex {
            points.extend(self.roads[a.road].stretch(a.vertex, b.vertex, a.forward).into_iter().skip(1));
        }
        points.extend(b.points.iter().skip(1));
        Some(Way { points, length, shape: None })
    }

    /// Ramps within `bounds` between `pose` and the roads nearby, both directions of travel:
    /// onto a road (`on`) or off it. Per road and direction, the shortest clear ones of the
    /// nearest stops.
    pub fn ramps(&self, pose: Pose, on: bool, bounds: Bounds) -> Vec<Ramp> {
        let mut near: Vec<(f64, usize)> = self.stops.iter().enumerate().map(|(k, s)| (distance(s.2, pose.coord()), k)).filter(|(d, _)| *d <= self.reach).collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut out = Vec::new();
        for forward in [true, false] {
            let mut tried = vec![0; self.roads.len()];
            let mut candidates: Vec<(usize, usize, Manoeuvre)> = Vec::new();
            for &(_, k) in &near {
                let (road, vertex, _) = self.stops[k];
                if tried[road] == RAMP_STOPS {
                    continue;
                }
                tried[road] += 1;
                let at = ring_pose(&self.roads[road].points, vertex, forward);
                let (a, b) = if on { (pose, at) } else { (at, pose) };
                candidates.push((road, vertex, self.steering.forward(a, b)));
            }
            candidates.sort_by(|x, y| x.2.length.total_cmp(&y.2.length));
            let mut kept = vec![0; self.roads.len()];
            for (road, vertex, ramp) in candidates {
                if kept[road] == RAMPS_KEPT {
                    continue;
                }
                let points = ramp.points();
                if self.clear(&points, bounds) {
                    kept[road] += 1;
                    out.push(Ramp { road, vertex, forward, points, length: ramp.length });
                }
            }
        }
        out
    }
}

/// The connections between swaths: each swath end's ramps onto the roads, found once.
pub struct SwathLinks<'a> {
    lines: &'a [Line],
    routes: &'a HeadlandRoutes,
    /// Per node: ramps from its exit, and into its entry, inside the headland.
    from_exit: Vec<Vec<Ramp>>,
    to_entry: Vec<Vec<Ramp>>,
    /// The same inside the field, for crossings of the mainland: found when first needed.
    across_from_exit: Vec<OnceLock<Vec<Ramp>>>,
    across_to_entry: Vec<OnceLock<Vec<Ramp>>>,
}

impl<'a> SwathLinks<'a> {
    pub fn new(lines: &'a [Line], routes: &'a HeadlandRoutes) -> Self {
        let n = 2 * lines.len();
        let from_exit = (0..n).into_par_iter().map(|v| routes.ramps(exit(lines, v), true, Bounds::Headland)).collect();
        let to_entry = (0..n).into_par_iter().map(|v| routes.ramps(entry(lines, v), false, Bounds::Headland)).collect();
        let unknown = || (0..n).map(|_| OnceLock::new()).collect();
        SwathLinks { lines, routes, from_exit, to_entry, across_from_exit: unknown(), across_to_entry: unknown() }
    }

    /// From the exit of node `u` to the entry of node `v`: a turn in the headland; else along
    /// a headland pass (either way round: the twin's ramps may fit where these do not); else,
    /// within a field, a transit across the mainland (`crossing` true); between fields, the
    /// road outside.
    pub fn link(&self, u: usize, v: usize) -> Option<(Way, bool)> {
        let (from, to) = (exit(self.lines, u), entry(self.lines, v));
        if self.lines[u / 2].region != self.lines[v / 2].region {
            return Some((self.routes.outside(from, to), false));
        }
        // each manoeuvre drawn once and tried on the mainland first: between far swath ends
        // most cross it, found at their first stretch, and only the crossing needs the edges
        let mut over_mainland: Vec<(Vec<Coord>, f64)> = Vec::new();
        for m in self.routes.steering.manoeuvres(from, to) {
            let points = m.points();
            if self.routes.mainland.crossed(&points) {
                over_mainland.push((points, m.length));
            } else if !self.routes.field.crossed(&points) {
                return Some((Way { points, length: m.length, shape: Some(m.shape) }, false));
            }
        }
        let road = self.routes.by_road(&self.from_exit[u], &self.to_entry[v]).or_else(|| {
            self.routes.by_road(&self.from_exit[v ^ 1], &self.to_entry[u ^ 1]).map(|mut w| {
                w.points.reverse();
                w
            })
        });
        if let Some(w) = road {
            return Some((w, false));
        }
        // the first clear of the field's edges, else by the roads across the mainland
        let first_clear = over_mainland.into_iter().find(|(points, _)| !self.routes.field.crossed(points));
        let across = first_clear.map(|(points, length)| Way { points, length, shape: None }).or_else(|| {
            let on = self.across_from_exit[u].get_or_init(|| self.routes.ramps(from, true, Bounds::Field));
            let off = self.across_to_entry[v].get_or_init(|| self.routes.ramps(to, false, Bounds::Field));
            self.routes.by_road(on, off)
        });
        across.map(|w| (w, true))
    }

    /// The cost the route search sees: the length, plus [`MAINLAND_CROSSING_M`] for a crossing.
    fn cost(&self, u: usize, v: usize) -> f64 {
        if u / 2 == v / 2 {
            return NO_WAY;
        }
        self.link(u, v).map_or(NO_WAY, |(w, crossing)| w.length + if crossing { MAINLAND_CROSSING_M } else { 0.0 })
    }
}

/// Nodes up to which the floors are kept in a table (8 n² bytes: 32 MB at 2 000).
const FLOORS_KEPT_UP_TO: usize = 2000;

/// The swaths' order as a node sequence of [`super::line_tour`], from `start` to `end` (each
/// optional, a pose).
pub fn order(links: &SwathLinks<'_>, start: Option<Pose>, end: Option<Pose>, stop: &Stop) -> Vec<usize> {
    let (lines, routes) = (links.lines, links.routes);
    let n = 2 * lines.len();
    if n == 0 {
        return Vec::new();
    }
    // the search asks for the same floors many times: each is kept once computed (NaN: not yet)
    let memo: Vec<std::cell::Cell<f64>> = if n <= FLOORS_KEPT_UP_TO { vec![std::cell::Cell::new(f64::NAN); n * n] } else { Vec::new() };
    let floor = |u: usize, v: usize| {
        if u / 2 == v / 2 {
            return NO_WAY;
        }
        let kept = memo.get(u * n + v).map(std::cell::Cell::get).filter(|f| !f.is_nan());
        kept.unwrap_or_else(|| {
            let f = routes.floor(exit(lines, u), entry(lines, v));
            if let Some(cell) = memo.get(u * n + v) {
                cell.set(f);
            }
            f
        })
    };
    let candidates = nearest_entries(lines);
    let known: KnownCosts = candidates.par_iter().enumerate().flat_map_iter(|(u, c)| c.iter().map(move |&v| ((u, v), links.cost(u, v)))).collect();
    let terminal = |p: Option<Pose>, to_line: bool| {
        p.map(|p| {
            (0..n)
                .into_par_iter()
                .map(|v| {
                    let (a, b) = if to_line { (p, entry(lines, v)) } else { (exit(lines, v), p) };
                    let (way, inside) = connect_anywhere(routes, a, b);
                    way.length + if inside { 0.0 } else { LEAVING_FIELD_M }
                })
                .collect()
        })
    };
    let mut inst = line_instance(lines, Costs::lazy(n, known, |u, v| links.cost(u, v), floor), terminal(start, true), terminal(end, false), stop.clone());
    inst.candidates = Some(candidates);
    super::gtsp::solve(&inst)
}

/// A transit inside the field when one is found (`true`), else by the road outside (a start or
/// end beyond the field's edge, or a part of the field cut off from the rest).
pub fn connect_anywhere(routes: &HeadlandRoutes, from: Pose, to: Pose) -> (Way, bool) {
    match routes.transit(from, to) {
        Some(w) => (w, true),
        None => (routes.outside(from, to), false),
    }
}

/// What leaving the field costs on top of a transit's length: every way inside is preferred.
pub const LEAVING_FIELD_M: f64 = 10_000.0;
