//! A ground vehicle's connections (docs/methods.md, ground §2–§4). Between two swaths the
//! vehicle turns in the headland: the shortest manoeuvre (Dubins word, or fishtail when it may
//! reverse) that crosses neither the field's edge, a hole, nor the mainland; where none fits,
//! it drives onto a headland pass, along it, and off again (the headland ring as a road).
//! Transits (from the start, between headland rings, to the end) keep off the mainland where
//! the headland joins their ends, and never leave the field. Where no way in the headland joins
//! two swaths, the vehicle crosses in a swath's wheel marks. Swaths of different fields are
//! joined by the road outside, a Dubins path nothing constrains.
//!
//! The order of the swaths is a generalised TSP over their two directions
//! ([`super::gtsp`]), priced lazily: a connection's floor is its length in open ground.

mod switch;

use std::cell::OnceCell;
use std::collections::HashMap;
use std::sync::{OnceLock, RwLock};

use geo::{Coord, MultiPolygon};
use rayon::prelude::*;

use super::gtsp::{Costs, KnownCosts, kept_in, slots};
use super::line_tour::{Line, NO_WAY, entry, exit, line_instance, nearest_entries};
use crate::geom::{EdgeIndex, distance, polyline_length};
use crate::path::TurnShape;
use crate::stop::Stop;
use crate::turn::dubins::Pose;
use crate::turn::ground::{Manoeuvre, Steering};
use crate::turn::turnable_stretch;
use switch::{Lane, Switch, Switches};

/// A headland pass as a road: a closed ring with its arc lengths.
pub struct Road {
    points: Vec<Coord>,
    at: Vec<f64>,
}

impl Road {
    /// The ring with a vertex at least every `step` metres, where ramps may join it.
    fn new(ring: &[Coord], step: f64) -> Self {
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
    /// Where the vehicle turns round or changes pass: found when a way first needs one.
    switches: OnceLock<Switches>,
}

/// What crossing the mainland along a swath's track costs on top of its length, in metres: the
/// route takes it only where no way through the headland joins two swaths (one pond's headland
/// to another's, or to the field's edge).
const TRACK_CROSSING_M: f64 = 1000.0;
/// The same for a crossing off every track, across the crop: only where no track leads.
const MAINLAND_CROSSING_M: f64 = 5000.0;
/// Swaths whose tracks are tried for a crossing: the shortest as the crow flies.
const TRACKS_TRIED: usize = 4;

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

impl Ramp {
    fn lane(&self) -> Lane {
        (self.road, self.forward)
    }
}

/// The lanes `ramps` join, each once.
fn lanes_of(ramps: &[Ramp]) -> Vec<Lane> {
    let mut lanes: Vec<Lane> = ramps.iter().map(Ramp::lane).collect();
    lanes.sort_unstable();
    lanes.dedup();
    lanes
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
    pub fn new(region: &MultiPolygon, mainland: &MultiPolygon, roads: &[Vec<Coord>], steering: Steering, headland_m: f64) -> Self {
        let radius = steering.bounding_radius();
        let spacing = (radius / 2.0).max(1.0);
        let roads: Vec<Road> = roads.iter().filter(|r| r.len() >= 4).map(|r| Road::new(r, spacing)).collect();
        let stops = roads.iter().enumerate().flat_map(|(k, road)| road.stops(spacing).into_iter().map(move |i| (k, i, road.points[i]))).collect();
        let (field, mainland) = (EdgeIndex::new(region), EdgeIndex::new(mainland));
        HeadlandRoutes { field, mainland, roads, stops, steering, reach: 4.0 * radius + 2.0 * headland_m, switches: OnceLock::new() }
    }

    /// The radius of the circle every turn keeps within.
    pub fn bounding_radius(&self) -> f64 {
        self.steering.bounding_radius()
    }

    /// Whether the vehicle may reverse.
    pub fn reverses(&self) -> bool {
        self.steering.reverses()
    }

    /// Below the length in open ground: no way between the poses is shorter.
    pub fn floor(&self, from: Pose, to: Pose) -> f64 {
        0.99 * self.steering.floor(from, to)
    }

    fn clear(&self, points: &[Coord], bounds: Bounds) -> bool {
        !self.field.crossed(points) && (bounds == Bounds::Field || !self.mainland.crossed(points))
    }

    /// The points of `m` when it stays within `bounds`; its straight leg is tried first, before
    /// any arc is drawn.
    fn cleared(&self, m: &Manoeuvre, bounds: Bounds) -> Option<Vec<Coord>> {
        if m.straight().is_some_and(|leg| !self.clear(&leg, bounds)) {
            return None;
        }
        let points = m.points();
        self.clear(&points, bounds).then_some(points)
    }

    /// Whether `points` keep to the headland: they cross neither the field's edges nor the
    /// mainland's.
    pub fn keeps_to_headland(&self, points: &[Coord]) -> bool {
        self.clear(points, Bounds::Headland)
    }

    /// The shortest manoeuvre from `from` to `to` that keeps to the headland (a pass's corner).
    pub fn corner_way(&self, from: Pose, to: Pose) -> Option<Vec<Coord>> {
        self.steering.manoeuvres(from, to).iter().find_map(|m| self.cleared(m, Bounds::Headland))
    }

    /// The stretch of the swath `a → b` whose ends the vehicle can turn at: each end pulled
    /// back (in steps of an eighth of the radius) until a half turn to the left or the right
    /// from it stays in the field; `None` when nothing is left (a swath in an acute corner,
    /// where no turn fits).
    pub fn turnable(&self, a: Coord, b: Coord) -> Option<(Coord, Coord)> {
        turnable_stretch(a, b, self.steering.bounding_radius(), 0.05, |at, out| self.steering.half_turns(at, out).iter().any(|turn| !self.field.crossed(turn)))
    }

    /// Whether a forward half turn from `at` (leaving in the unit direction `out`), to the left
    /// or to the right, stays in the headland: where none does (at an edge slanted to the
    /// swaths, one leaves the field and the other enters the mainland) the swath can only be
    /// left by a long drive or across the crop.
    pub fn turns_back_at(&self, at: Coord, out: Coord) -> bool {
        // a centimetre out: a square end's half turn ends on the mainland's edge, where the
        // neighbouring swath begins
        self.steering.half_turns(at + out * 0.01, out).iter().any(|turn| self.clear(turn, Bounds::Headland))
    }

    /// Between fields, on the road outside them.
    pub fn outside(&self, from: Pose, to: Pose) -> Way {
        let points = self.steering.forward(from, to).points();
        Way { length: polyline_length(&points), points, shape: None }
    }

    /// Anywhere inside the field, off the mainland where the headland joins the two poses: the
    /// shortest manoeuvre that stays in the headland, or else along the headland passes; else
    /// the same across the mainland.
    pub fn transit(&self, from: Pose, to: Pose) -> Option<Way> {
        let manoeuvres = self.steering.manoeuvres(from, to);
        let direct = |bounds: Bounds| manoeuvres.iter().find_map(|m| self.cleared(m, bounds).map(|points| Way { points, length: m.length, shape: None }));
        let by_road = |bounds: Bounds| self.by_road(&self.ramps(from, true, bounds), &self.ramps(to, false, bounds));
        direct(Bounds::Headland).or_else(|| by_road(Bounds::Headland)).or_else(|| direct(Bounds::Field)).or_else(|| by_road(Bounds::Field))
    }

    /// `pose` with its ramps onto the roads (`leaving`: the vehicle sets off from it) or off
    /// them (it arrives at it), inside the headland and inside the field.
    pub fn reach(&self, pose: Pose, leaving: bool) -> Reach {
        let [headland, field] = <[Vec<Ramp>; 2]>::try_from(self.ramps_within(pose, leaving, &[Bounds::Headland, Bounds::Field])).expect("one list per bounds");
        Reach { pose, headland, field }
    }

    /// From `from` to `to` (each a [`Self::reach`]) keeping off the mainland: a manoeuvre in the
    /// headland, else along a headland pass; where neither joins them, across the field
    /// (`true`).
    pub fn drive(&self, from: &Reach, to: &Reach) -> Option<(Way, bool)> {
        let manoeuvres = self.steering.manoeuvres(from.pose, to.pose);
        let direct = |bounds: Bounds| manoeuvres.iter().find_map(|m| self.cleared(m, bounds).map(|points| Way { points, length: m.length, shape: None }));
        let on_headland = direct(Bounds::Headland).or_else(|| self.by_road(&from.headland, &to.headland));
        on_headland.map(|w| (w, false)).or_else(|| direct(Bounds::Field).or_else(|| self.by_road(&from.field, &to.field)).map(|w| (w, true)))
    }

    /// The poses, each way along its road, of the `n` ramp stops nearest `at`.
    pub fn stops_near(&self, at: Coord, n: usize) -> Vec<Pose> {
        let mut near: Vec<(f64, usize, usize)> = self.stops.iter().map(|&(road, vertex, p)| (distance(p, at), road, vertex)).collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        near.into_iter().take(n).flat_map(|(_, road, vertex)| [true, false].map(|forward| ring_pose(&self.roads[road].points, vertex, forward))).collect()
    }

    /// The shortest way onto a road by one of `on`, along it, and off by one of `off`.
    pub fn by_road(&self, on: &[Ramp], off: &[Ramp]) -> Option<Way> {
        self.best_road(on, off).map(|r| self.draw(&r))
    }

    /// [`Self::by_road`]'s choice, not yet drawn: along one lane; where no lane joins the ramps
    /// or its way is a detour ([`Self::is_detour`]), the shortest of that and the ways onto
    /// another lane by a switch (the vehicle turns round, or changes pass).
    fn best_road<'r>(&'r self, on: &'r [Ramp], off: &'r [Ramp]) -> Option<RoadWay<'r>> {
        let shortest = |ways: &mut dyn Iterator<Item = RoadWay<'r>>| ways.min_by(|x, y| x.length.total_cmp(&y.length));
        let along = on.iter().flat_map(|a| off.iter().filter(move |b| b.lane() == a.lane()).map(move |b| (a, b)));
        let direct = shortest(&mut along.map(|(a, b)| RoadWay { length: a.length + self.roads[a.road].along(a.vertex, b.vertex, a.forward) + b.length, on: a, off: b, via: None }));
        let (from_lanes, to_lanes) = (lanes_of(on), lanes_of(off));
        let ends = on.first().zip(off.first()).map(|(a, b)| (a.points[0], *b.points.last().expect("a ramp has points")));
        let detour = |way: &RoadWay<'_>| ends.is_some_and(|(a, b)| self.is_detour(way.length, a, b));
        if direct.as_ref().is_some_and(|w| !detour(w)) || from_lanes.is_empty() || to_lanes.is_empty() {
            return direct;
        }
        let switches = self.switches();
        let lane_pairs = from_lanes.iter().flat_map(|&from| to_lanes.iter().map(move |&to| (from, to)));
        let via = lane_pairs.flat_map(|(from, to)| switches.get(&(from, to)).into_iter().flatten().map(move |s| (from, to, s)));
        shortest(&mut direct.into_iter().chain(via.filter_map(|(from, to, s)| {
            // the best ramp onto the switch's start and off its end, each on its own
            let onto =
                on.iter().filter(|a| a.lane() == from).map(|a| (a.length + self.roads[from.0].along(a.vertex, s.from_vertex, from.1), a)).min_by(|x, y| x.0.total_cmp(&y.0))?;
            let off_it = off.iter().filter(|b| b.lane() == to).map(|b| (self.roads[to.0].along(s.to_vertex, b.vertex, to.1) + b.length, b)).min_by(|x, y| x.0.total_cmp(&y.0))?;
            Some(RoadWay { length: onto.0 + s.length + off_it.0, on: onto.1, off: off_it.1, via: Some(s) })
        })))
    }

    /// The switches, found on first use.
    fn switches(&self) -> &Switches {
        self.switches.get_or_init(|| self.find_switches())
    }

    /// Whether a way of `length` between `a` and `b` is a detour: longer than twice the crow's
    /// distance and 10 turning radii more (room for a loop and its ramps), as a ring driven the
    /// wrong way round.
    pub fn is_detour(&self, length: f64, a: Coord, b: Coord) -> bool {
        length > 2.0 * distance(a, b) + 10.0 * self.steering.bounding_radius()
    }

    fn draw(&self, r: &RoadWay<'_>) -> Way {
        let (a, b) = (r.on, r.off);
        let mut points = a.points.clone();
        let drive = |road: usize, i: usize, j: usize, forward: bool, points: &mut Vec<Coord>| {
            if i != j {
                points.extend(self.roads[road].stretch(i, j, forward).into_iter().skip(1));
            }
        };
        match r.via {
            None => drive(a.road, a.vertex, b.vertex, a.forward, &mut points),
            Some(s) => {
                drive(a.road, a.vertex, s.from_vertex, a.forward, &mut points);
                points.extend(s.points.iter().skip(1));
                drive(b.road, s.to_vertex, b.vertex, b.forward, &mut points);
            }
        }
        points.extend(b.points.iter().skip(1));
        Way { points, length: r.length, shape: None }
    }

    /// Ramps within `bounds` between `pose` and the roads nearby, both directions of travel:
    /// onto a road (`on`) or off it. Per road and direction, the shortest clear ones of the
    /// nearest stops.
    pub fn ramps(&self, pose: Pose, on: bool, bounds: Bounds) -> Vec<Ramp> {
        self.ramps_within(pose, on, &[bounds]).pop().expect("one list per bounds")
    }

    /// [`Self::ramps`] for each of `bounds` at once: the candidates are priced and drawn once.
    fn ramps_within(&self, pose: Pose, on: bool, bounds: &[Bounds]) -> Vec<Vec<Ramp>> {
        let mut near: Vec<(f64, usize)> = self.stops.iter().enumerate().map(|(k, s)| (distance(s.2, pose.coord()), k)).filter(|(d, _)| *d <= self.reach).collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut out = vec![Vec::new(); bounds.len()];
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
            // per bounds and road, the ramps kept so far
            let mut kept = vec![vec![0; self.roads.len()]; bounds.len()];
            for (road, vertex, ramp) in candidates {
                let wanted: Vec<usize> = (0..bounds.len()).filter(|&b| kept[b][road] < RAMPS_KEPT).collect();
                if wanted.is_empty() {
                    continue;
                }
                // each set of edges tested once, whichever bounds ask first, and on the straight
                // leg (one leg of the points) before any arc is drawn
                let leg = ramp.straight();
                let points = OnceCell::new();
                let draw = || points.get_or_init(|| ramp.points());
                let crosses = |edges: &EdgeIndex| leg.is_some_and(|leg| edges.crossed(&leg)) || edges.crossed(draw());
                let (leaves_field, over_mainland) = (OnceCell::new(), OnceCell::new());
                for b in wanted {
                    let clear = !*leaves_field.get_or_init(|| crosses(&self.field)) && (bounds[b] == Bounds::Field || !*over_mainland.get_or_init(|| crosses(&self.mainland)));
                    if clear {
                        kept[b][road] += 1;
                        out[b].push(Ramp { road, vertex, forward, points: draw().clone(), length: ramp.length });
                    }
                }
            }
        }
        out
    }
}

/// A pose and its ramps onto the roads or off them ([`HeadlandRoutes::reach`]).
pub struct Reach {
    pub pose: Pose,
    headland: Vec<Ramp>,
    field: Vec<Ramp>,
}

/// A way along a road chosen by [`HeadlandRoutes::best_road`]: its points are drawn only for
/// the connections driven, the search needs its length only.
struct RoadWay<'r> {
    length: f64,
    on: &'r Ramp,
    off: &'r Ramp,
    /// Where the way turns round or changes pass.
    via: Option<&'r Switch>,
}

/// A connection between two swaths as found: a turn already drawn (its points were needed to
/// clear it), a way along a road still to draw (`true`: for the twin nodes, to reverse), or a
/// crossing along a swath's track (node `x`: from its entry to its exit) between two of these.
enum Link<'r> {
    Drawn(Way),
    Road(RoadWay<'r>, bool),
    Track(Box<Link<'r>>, usize, Box<Link<'r>>),
}

/// How a connection between two swaths crosses the mainland, if it does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Crossing {
    No,
    /// Along a swath's track, in its wheel marks.
    Track,
    /// Off every track, across the crop.
    Crop,
}

/// The connections between swaths, with each swath end's ramps onto the roads, found once.
pub struct SwathLinks<'a> {
    lines: &'a [Line],
    routes: &'a HeadlandRoutes,
    /// Per node: ramps from its exit, and into its entry, inside the headland.
    from_exit: Vec<Vec<Ramp>>,
    to_entry: Vec<Vec<Ramp>>,
    /// The same inside the field, for crossings of the mainland.
    across_from_exit: Vec<Vec<Ramp>>,
    across_to_entry: Vec<Vec<Ramp>>,
    /// Per node, the lanes its entry and its exit reach: found for the first crossing.
    lanes: OnceLock<Vec<(Vec<Lane>, Vec<Lane>)>>,
    /// Lengths of the ways inside the headland asked for by crossings.
    inside: RwLock<HashMap<(usize, usize), Option<f64>>>,
}

impl<'a> SwathLinks<'a> {
    /// Every swath end's ramps, computed side by side: the search needs almost all of them
    /// (a few joins of swath ends that no turn fits bring in most ends).
    pub fn new(lines: &'a [Line], routes: &'a HeadlandRoutes) -> Self {
        let n = 2 * lines.len();
        let both = [Bounds::Headland, Bounds::Field];
        let ramps = |on: bool| -> (Vec<Vec<Ramp>>, Vec<Vec<Ramp>>) {
            (0..n)
                .into_par_iter()
                .map(|v| {
                    let pose = if on { exit(lines, v) } else { entry(lines, v) };
                    let [headland, field] = <[Vec<Ramp>; 2]>::try_from(routes.ramps_within(pose, on, &both)).expect("one list per bounds");
                    (headland, field)
                })
                .unzip()
        };
        let ((from_exit, across_from_exit), (to_entry, across_to_entry)) = rayon::join(|| ramps(true), || ramps(false));
        SwathLinks { lines, routes, from_exit, to_entry, across_from_exit, across_to_entry, lanes: OnceLock::new(), inside: RwLock::default() }
    }

    /// From the exit of node `u` to the entry of node `v`: a turn in the headland; else along
    /// a headland pass (either way round: the twin's ramps may fit where these do not); else,
    /// within a field, a crossing of the mainland along a swath's track, or off the tracks
    /// where none leads; between fields, the road outside.
    pub fn link(&self, u: usize, v: usize) -> Option<(Way, Crossing)> {
        self.find(u, v).map(|(link, crossing)| (self.draw(link), crossing))
    }

    fn draw(&self, link: Link<'_>) -> Way {
        match link {
            Link::Drawn(w) => w,
            Link::Road(r, twin) => {
                let mut w = self.routes.draw(&r);
                if twin {
                    w.points.reverse();
                }
                w
            }
            Link::Track(to, x, from) => {
                let (to, from) = (self.draw(*to), self.draw(*from));
                let mut points = to.points;
                points.extend([entry(self.lines, x).coord(), exit(self.lines, x).coord()]);
                points.extend(from.points.into_iter().skip(1));
                points.dedup();
                Way { length: to.length + self.lines[x / 2].length() + from.length, points, shape: None }
            }
        }
    }

    /// `link`'s length, without drawing it.
    fn length(&self, link: &Link<'_>) -> f64 {
        match link {
            Link::Drawn(w) => w.length,
            Link::Road(r, _) => r.length,
            Link::Track(to, x, from) => self.length(to) + self.lines[x / 2].length() + self.length(from),
        }
    }

    fn find(&self, u: usize, v: usize) -> Option<(Link<'_>, Crossing)> {
        let (from, to) = (exit(self.lines, u), entry(self.lines, v));
        if self.lines[u / 2].region != self.lines[v / 2].region {
            return Some((Link::Drawn(self.routes.outside(from, to)), Crossing::No));
        }
        let (inside, over_mainland) = self.in_headland(u, v);
        if let Some(link) = inside {
            return Some((link, Crossing::No));
        }
        if let Some(link) = self.along_track(u, v) {
            return Some((link, Crossing::Track));
        }
        // the first clear of the field's edges, else by the roads across the mainland
        let routes = self.routes;
        let first_clear = over_mainland.into_iter().find_map(|m| routes.cleared(&m, Bounds::Field).map(|points| Way { points, length: m.length, shape: None }));
        let across = first_clear.map(Link::Drawn).or_else(|| routes.best_road(&self.across_from_exit[u], &self.across_to_entry[v]).map(|r| Link::Road(r, false)));
        across.map(|link| (link, Crossing::Crop))
    }

    /// A way from `u`'s exit to `v`'s entry inside the headland, and the manoeuvres between them
    /// that cross the mainland.
    fn in_headland(&self, u: usize, v: usize) -> (Option<Link<'_>>, Vec<Manoeuvre>) {
        let (from, to) = (exit(self.lines, u), entry(self.lines, v));
        // each manoeuvre tried on the mainland first: between far swath ends most cross it,
        // many by their straight leg alone (found before their arcs are drawn), and only the
        // crossing needs the field's edges
        let routes = self.routes;
        let mut over_mainland: Vec<Manoeuvre> = Vec::new();
        for m in routes.steering.manoeuvres(from, to) {
            if m.straight().is_some_and(|leg| routes.mainland.crossed(&leg)) {
                over_mainland.push(m);
                continue;
            }
            let points = m.points();
            if routes.mainland.crossed(&points) {
                over_mainland.push(m);
            } else if !routes.field.crossed(&points) {
                return (Some(Link::Drawn(Way { points, length: m.length, shape: Some(m.shape) })), over_mainland);
            }
        }
        let (on, off) = (&self.from_exit, &self.to_entry);
        let road = routes.best_road(&on[u], &off[v]).map(|r| Link::Road(r, false)).or_else(|| routes.best_road(&on[v ^ 1], &off[u ^ 1]).map(|r| Link::Road(r, true)));
        (road, over_mainland)
    }

    /// [`Self::in_headland`]'s length, kept.
    fn in_headland_length(&self, u: usize, v: usize) -> Option<f64> {
        let known = self.inside.read().unwrap_or_else(std::sync::PoisonError::into_inner).get(&(u, v)).copied();
        known.unwrap_or_else(|| {
            let length = self.in_headland(u, v).0.map(|l| self.length(&l));
            self.inside.write().unwrap_or_else(std::sync::PoisonError::into_inner).insert((u, v), length);
            length
        })
    }

    /// From `u`'s exit to `v`'s entry across the mainland in swaths' wheel marks: inside the
    /// headland to the entry of a swath `x` (driven, not worked), along it, and inside the
    /// headland from its exit on; where no one swath leads, two. Of the swaths whose entry a
    /// turn from `u` may reach (near it, or on a lane `u`'s ramps join, or one a switch leads
    /// to) and whose exit leads likewise to `v`, the [`TRACKS_TRIED`] shortest as the crow
    /// flies are tried.
    fn along_track(&self, u: usize, v: usize) -> Option<Link<'_>> {
        let lanes = self.lanes.get_or_init(|| self.lanes_reached());
        let switches = self.routes.switches();
        // the lanes `u`'s exit leads to, and those that lead to `v`'s entry, by at most a switch
        let id = |(road, forward): Lane| 2 * road + usize::from(forward);
        let mut after_u = vec![false; 2 * self.routes.roads.len()];
        let mut before_v = after_u.clone();
        for a in &lanes[u].1 {
            after_u[id(*a)] = true;
        }
        for b in &lanes[v].0 {
            before_v[id(*b)] = true;
        }
        for (a, b) in switches.keys() {
            after_u[id(*b)] |= lanes[u].1.contains(a);
            before_v[id(*a)] |= lanes[v].0.contains(b);
        }
        let (from, to) = (exit(self.lines, u).coord(), entry(self.lines, v).coord());
        let near = 4.0 * self.routes.bounding_radius();
        let from_u = |x: usize| distance(from, entry(self.lines, x).coord()) <= near || lanes[x].0.iter().any(|&l| after_u[id(l)]);
        let to_v = |x: usize| distance(exit(self.lines, x).coord(), to) <= near || lanes[x].1.iter().any(|&l| before_v[id(l)]);
        let tracks = |keep: &dyn Fn(usize) -> bool, crow: &dyn Fn(usize) -> f64| {
            let mut tracks: Vec<(f64, usize)> = (0..2 * self.lines.len())
                .filter(|&x| x / 2 != u / 2 && x / 2 != v / 2 && self.lines[x / 2].region == self.lines[u / 2].region && keep(x))
                .map(|x| (crow(x), x))
                .collect();
            tracks.sort_by(|a, b| a.0.total_cmp(&b.0));
            tracks.truncate(TRACKS_TRIED);
            tracks.into_iter().map(|(_, x)| x).collect::<Vec<usize>>()
        };
        let length = |x: usize| self.lines[x / 2].length();
        let (to_track, from_track) = (|x: usize| distance(from, entry(self.lines, x).coord()), |x: usize| distance(exit(self.lines, x).coord(), to));
        // one track; else two, the first from `u`'s side of the field, the second to `v`'s (a
        // vehicle that can turn round nowhere on the headland crosses and comes back)
        let one = tracks(&|x| from_u(x) && to_v(x), &|x| to_track(x) + length(x) + from_track(x));
        let best = one.into_iter().filter_map(|x| Some((self.in_headland_length(u, x)? + length(x) + self.in_headland_length(x, v)?, vec![x]))).min_by(|a, b| a.0.total_cmp(&b.0));
        let best = best.or_else(|| {
            let firsts: Vec<(f64, usize)> =
                tracks(&from_u, &|x| to_track(x) + length(x)).into_iter().filter_map(|x| Some((self.in_headland_length(u, x)? + length(x), x))).collect();
            let lasts: Vec<(f64, usize)> =
                tracks(&to_v, &|y| length(y) + from_track(y)).into_iter().filter_map(|y| Some((length(y) + self.in_headland_length(y, v)?, y))).collect();
            let pairs = firsts.iter().flat_map(|&(a, x)| lasts.iter().filter(move |&&(_, y)| y / 2 != x / 2).map(move |&(b, y)| (a, x, b, y)));
            pairs.filter_map(|(a, x, b, y)| Some((a + self.in_headland_length(x, y)? + b, vec![x, y]))).min_by(|p, q| p.0.total_cmp(&q.0))
        })?;
        // the links inside the headland between `u`, the tracks and `v`
        let stops: Vec<usize> = std::iter::once(u).chain(best.1.iter().copied()).chain([v]).collect();
        let mut legs = stops.windows(2).rev().map(|w| self.in_headland(w[0], w[1]).0);
        let mut link = legs.next()??;
        for (leg, &x) in legs.zip(best.1.iter().rev()) {
            link = Link::Track(Box::new(leg?), x, Box::new(link));
        }
        Some(link)
    }

    /// Per node, the lanes its entry's ramps come off and its exit's go onto.
    fn lanes_reached(&self) -> Vec<(Vec<Lane>, Vec<Lane>)> {
        (0..2 * self.lines.len()).map(|x| (lanes_of(&self.to_entry[x]), lanes_of(&self.from_exit[x]))).collect()
    }

    /// The cost the route search sees: the length, plus [`TRACK_CROSSING_M`] or
    /// [`MAINLAND_CROSSING_M`] for a crossing.
    fn cost(&self, u: usize, v: usize) -> f64 {
        if u / 2 == v / 2 {
            return NO_WAY;
        }
        self.find(u, v).map_or(NO_WAY, |(link, crossing)| {
            self.length(&link)
                + match crossing {
                    Crossing::No => 0.0,
                    Crossing::Track => TRACK_CROSSING_M,
                    Crossing::Crop => MAINLAND_CROSSING_M,
                }
        })
    }
}

/// Nodes up to which the floors are kept in a table (8 n² bytes: 32 MB at 2 000).
const FLOORS_KEPT_UP_TO: usize = 2000;

/// The swaths' order as a node sequence of [`super::line_tour`], from `start` to `end` (each
/// optional, a pose), and what `beside` gives: it runs while the order is searched, on the core
/// the search leaves free.
pub fn order<R: Send>(links: &SwathLinks<'_>, start: Option<Pose>, end: Option<Pose>, stop: &Stop, beside: impl FnOnce() -> R + Send) -> (Vec<usize>, R) {
    let (lines, routes) = (links.lines, links.routes);
    let n = 2 * lines.len();
    if n == 0 {
        return (Vec::new(), beside());
    }
    // the search asks for the same floors many times: each is kept once computed
    let memo = if n <= FLOORS_KEPT_UP_TO { slots(n * n) } else { Vec::new() };
    let floor = |u: usize, v: usize| {
        if u / 2 == v / 2 {
            return NO_WAY;
        }
        kept_in(&memo, u * n + v, || routes.floor(exit(lines, u), entry(lines, v)))
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
    let mut inst = line_instance(lines, Costs::lazy(n, known, |u, v| links.cost(u, v), |u, v| (floor(u, v), false)), terminal(start, true), terminal(end, false), stop.clone());
    inst.candidates = Some(candidates);
    let mut aside = None;
    let seq = rayon::in_place_scope(|s| {
        s.spawn(|_| aside = Some(beside()));
        super::gtsp::solve(&inst)
    });
    (seq, aside.expect("the scope waits for its job"))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decompose::headland::headland;
    use geo::{LineString, Polygon};

    /// A forward sprayer (7 m turns) in a 12 m headland turns back at a swath end square to the
    /// edge, but not where the edge slants at 40° to the swath: the half turn towards the lower
    /// side reaches 7 (1 + sin 50°) = 12.4 m out and leaves the field, the other ends in the
    /// mainland.
    #[test]
    fn half_turns_fit_at_a_square_end_and_not_at_a_slanted_one() {
        let field = |top: Vec<(f64, f64)>| {
            let mut ring = vec![(0.0, 0.0), (400.0, 0.0)];
            ring.extend(top);
            ring.push((0.0, 0.0));
            MultiPolygon(vec![Polygon::new(LineString::from(ring), vec![])])
        };
        // a square top edge, and one slanting up to the right at 50° (40° to north–south swaths)
        let slope = 50f64.to_radians().tan();
        for (top, turns) in [(vec![(400.0, 300.0), (0.0, 300.0)], true), (vec![(400.0, 200.0 + 400.0 * slope), (0.0, 200.0)], false)] {
            let region = field(top);
            let h = headland(&region, 12.0, 2, 7.0);
            let routes = HeadlandRoutes::new(&region, &h.mainland, &h.passes.concat(), Steering::new(7.0, false, None), 12.0);
            // a north–south swath in the middle, ending on the mainland's top edge
            let top_y = if turns { 288.0 } else { 200.0 + 200.0 * slope - 12.0 / 50f64.to_radians().cos() };
            assert_eq!(routes.turns_back_at(Coord { x: 200.0, y: top_y }, Coord { x: 0.0, y: 1.0 }), turns, "top at {top_y}");
        }
    }

    /// The ramps found for the headland and for crossings in one pass are those found for each
    /// on its own: the same stops, directions and lengths, in the same order.
    #[test]
    fn ramps_found_together_are_those_found_one_by_one() {
        let square = |x0: f64, y0: f64, side: f64| LineString::from(vec![(x0, y0), (x0 + side, y0), (x0 + side, y0 + side), (x0, y0 + side), (x0, y0)]);
        let region = MultiPolygon(vec![Polygon::new(square(0.0, 0.0, 120.0), vec![square(50.0, 50.0, 20.0)])]);
        let h = headland(&region, 10.0, 2, 3.0);
        let routes = HeadlandRoutes::new(&region, &h.mainland, &h.passes.concat(), Steering::new(3.0, false, None), 10.0);
        let key = |ramps: &[Ramp]| ramps.iter().map(|r| (r.road, r.vertex, r.forward, r.length)).collect::<Vec<_>>();
        let (mut found, mut differ) = (0, false);
        // swath ends on the mainland's edges (outer and round the pond)
        for (x, y, theta) in [(40.0, 10.0, -1.5), (40.0, 110.0, 1.6), (10.0, 60.0, 3.1), (55.0, 40.0, 1.57), (65.0, 80.0, -1.57), (110.0, 30.0, 0.2)] {
            // facing out of the mainland or into it (a ramp from there must cross it)
            for (on, heading) in [(true, theta), (false, theta + std::f64::consts::PI), (true, theta + std::f64::consts::PI), (false, theta)] {
                let pose = Pose::new(x, y, heading);
                let together = routes.ramps_within(pose, on, &[Bounds::Headland, Bounds::Field]);
                let (headland_only, field_only) = (routes.ramps(pose, on, Bounds::Headland), routes.ramps(pose, on, Bounds::Field));
                assert_eq!(key(&together[0]), key(&headland_only));
                assert_eq!(key(&together[1]), key(&field_only));
                assert!(together[0].iter().all(|r| !routes.field.crossed(&r.points) && !routes.mainland.crossed(&r.points)));
                assert!(together[1].iter().all(|r| !routes.field.crossed(&r.points)));
                found += headland_only.len();
                differ |= key(&together[0]) != key(&together[1]);
            }
        }
        assert!(found > 0, "no ramps at all: the test poses are off the headland");
        assert!(differ, "crossing ramps never differ from headland ones: the two bounds are not exercised");
    }
}
