//! Connections between poses that never enter a no-fly zone, turn arcs included (docs/methods.md, dubins
//! §9): straight transits on the visibility graph for a multirotor; for a fixed-wing aircraft
//! the shortest clear Dubins word, or else Dubins hops along a visibility path laid far
//! enough from the zones to turn in. In wind a fixed wing's words are trochoids over the
//! ground ([`crate::turn::trochoid`]), and what is still drawn as ground arcs (hops, detours,
//! the room to turn at a line's end) uses the radius any ground circle can be flown on in that
//! wind.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Arc, OnceLock, RwLock};

use geo::{Coord, Rect};

use super::visibility::{TransitPlanner, Tree};
use crate::path::FlightPath;
use crate::stop::Stop;
use crate::turn::dubins::{DubinsPath, Pose, all_words, lengths_arriving, lengths_leaving, shortest, to_point_lower_bound};
use crate::turn::trochoid::{Drift, Trochoid};
use crate::turn::{CHORD_TOLERANCE_M, TurnModel, half_circles, turnable_stretch};
use crate::wind::{Tariff, air_length};

pub struct Connector<'a> {
    pub turn: TurnModel,
    /// Straight transits around the zones; its walls are what no connection may enter.
    pub transit: &'a TransitPlanner,
    /// Fixed wing: a visibility graph on the zones grown by the turning radius too.
    pub detour: Option<&'a TransitPlanner>,
    /// Fixed wing around zones: the poses a connection may pass through, each detour corner
    /// in [`VIA_HEADINGS`] headings (pose `i * VIA_HEADINGS + k`: corner `i`, heading `k`).
    via: Vec<Pose>,
    /// The legs from a pose to every via pose, and from every via pose to a pose: a pose's
    /// row serves all its connections.
    legs_out: Legs,
    legs_in: Legs,
    /// Fixed wing around zones: per place, the detour graph's shortest ways from it, and its
    /// corners in sight from it; a line end serves many connections.
    trees: Places<Tree>,
    sights: Places<Vec<(usize, f64)>>,
    /// Once raised, connections cost nothing to find: none is found.
    stop: Option<Stop>,
    /// False: a blocked connection takes the hops along the detour, never a way through one
    /// corner ([`Connector::hops_only`]).
    via_corners: bool,
    /// Fixed wing: the straights flown at the ends of connections ([`Connector::with_ends`]).
    ends: FlightEnds,
    /// Fixed wing in wind ([`Connector::in_wind`]).
    wind: Option<Drift>,
    /// Straight transits in wind: their metres priced by direction ([`Connector::priced_by`]).
    tariff: Option<Arc<Tariff>>,
}

/// The straights a fixed wing flies at the ends of its connections, each left out where it
/// would enter a wall (docs/flight-files.md).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FlightEnds {
    /// Metres flown straight into every pose a connection reaches (a line's start): an
    /// autopilot following waypoints settles on the line over them.
    pub lead_in_m: f64,
    /// From the launch points (home, and the landing sites sorties take off from again),
    /// metres flown straight ahead climbing after take-off.
    pub climb_out: Option<(Vec<Coord>, f64)>,
    /// Into the landing points: the approach's length, and its math heading (`None`: the
    /// heading the connection arrives on).
    pub landing: Option<(Vec<Coord>, f64, Option<f64>)>,
}

type Legs = RwLock<HashMap<[u64; 3], Arc<LegRow>>>;
type Places<T> = RwLock<HashMap<[u64; 2], Arc<T>>>;

/// The legs between one pose and every via pose: their Dubins lengths, computed per corner
/// the first time a connection looks at the corner, and whether each leg stays clear of the
/// walls, found out the first time a connection needs to know.
struct LegRow {
    /// Per corner: no leg between the pose and the corner is shorter.
    bound: Box<[f64]>,
    length: Box<[OnceLock<Box<[f64; VIA_HEADINGS]>>]>,
    clear: Box<[AtomicU8]>,
}

const UNKNOWN: u8 = 0;
const CLEAR: u8 = 1;
const BLOCKED: u8 = 2;

/// `p` moved `metres` along its heading.
fn moved(p: Pose, metres: f64) -> Pose {
    Pose::new(p.x + metres * p.theta.cos(), p.y + metres * p.theta.sin(), p.theta)
}

/// True when `p` stands on `c`.
fn at(c: Coord, p: Pose) -> bool {
    (c - p.coord()).x.hypot((c - p.coord()).y) < 1e-6
}

/// Headings a connection may pass a detour corner in.
const VIA_HEADINGS: usize = 16;

impl<'a> Connector<'a> {
    pub fn new(turn: TurnModel, transit: &'a TransitPlanner, detour: Option<&'a TransitPlanner>) -> Self {
        let via = match (turn, detour) {
            (TurnModel::Dubins(_), Some(d)) => {
                d.corners().iter().flat_map(|&c| (0..VIA_HEADINGS).map(move |k| Pose::at(c, k as f64 * std::f64::consts::TAU / VIA_HEADINGS as f64))).collect()
            }
            _ => Vec::new(),
        };
        Connector {
            turn,
            transit,
            detour,
            via,
            legs_out: Legs::default(),
            legs_in: Legs::default(),
            trees: Places::default(),
            sights: Places::default(),
            stop: None,
            via_corners: true,
            ends: FlightEnds::default(),
            wind: None,
            tariff: None,
        }
    }

    /// The same connections, with empty caches.
    pub fn fresh(&self) -> Self {
        Connector {
            turn: self.turn,
            transit: self.transit,
            detour: self.detour,
            via: self.via.clone(),
            legs_out: Legs::default(),
            legs_in: Legs::default(),
            trees: Places::default(),
            sights: Places::default(),
            stop: self.stop.clone(),
            via_corners: self.via_corners,
            ends: self.ends.clone(),
            wind: self.wind,
            tariff: self.tariff.clone(),
        }
    }

    /// The same connections, with empty caches, except that a blocked one takes the hops
    /// along the detour: a tenth of the time, for estimates (the hops are the longer way where
    /// a way through one corner is found).
    pub fn hops_only(&self) -> Self {
        let mut fresh = self.fresh();
        fresh.via_corners = false;
        fresh
    }

    /// Dubins connections fly `ends`' straights (a fixed wing's lead-ins, climb-out and
    /// landing approach).
    pub fn with_ends(mut self, ends: FlightEnds) -> Self {
        self.ends = ends;
        self
    }

    /// A fixed wing's connections fly in `drift` (none: still air).
    pub fn in_wind(mut self, drift: Option<Drift>) -> Self {
        self.wind = drift;
        self
    }

    /// The wind the connections are flown in.
    pub fn wind(&self) -> Option<Drift> {
        self.wind
    }

    /// Straight connections cost their metres priced by `tariff` (a multirotor in wind:
    /// routes are ranked by what each direction costs it).
    pub fn priced_by(mut self, tariff: Option<Arc<Tariff>>) -> Self {
        self.tariff = tariff;
        self
    }

    /// Flown in `other`'s wind, priced by its tariff.
    pub fn in_wind_of(self, other: &Connector) -> Self {
        self.in_wind(other.wind).priced_by(other.tariff.clone())
    }

    /// True where a connection flown backwards (from the next line's start to the last one's
    /// end, each flown the other way) may cost another length: in wind (upwind against
    /// downwind), and where a fixed wing's lead-ins make the straight into a line's start,
    /// which the way backwards flies out of the other end.
    pub fn directed(&self) -> bool {
        self.wind.is_some() || self.tariff.is_some() || (self.turn != TurnModel::Straight && self.ends.lead_in_m > 0.0)
    }

    /// What flying `path` costs in [`Connector::length`]'s measure: its metres, in wind its
    /// metres of air or its priced metres; plans routed in a wind are compared on it.
    pub fn measure(&self, path: &FlightPath) -> f64 {
        path.pieces.iter().flat_map(|p| p.points.windows(2)).map(|w| self.straight_cost(w[0], w[1])).sum()
    }

    /// What flying the straight `a → b` costs in [`Connector::length`]'s measure: its metres,
    /// in wind its metres of air (fixed wing) or its priced metres (by the tariff).
    pub fn straight_cost(&self, a: Coord, b: Coord) -> f64 {
        match (self.wind, &self.tariff) {
            (Some(d), _) => air_length(&[a, b], d.wind, d.airspeed),
            (None, Some(t)) => t.length(&[a, b]),
            (None, None) => crate::geom::distance(a, b),
        }
    }

    /// The radius of the arcs drawn on the ground: in wind, one any ground circle can be
    /// flown on within the bank of `r`.
    fn ground_radius(&self, r: f64) -> f64 {
        self.wind.map_or(r, |d| d.safe_radius(r))
    }

    /// Where a Dubins connection from `from` may start turning: the ends of the climb-outs
    /// when `from` is the launch point (every heading whose climb-out is clear of the walls, in
    /// 15° steps from the one asked), else `from` itself.
    fn turn_starts(&self, from: Pose) -> impl Iterator<Item = Pose> + '_ {
        let climb_out = self.ends.climb_out.as_ref().filter(|(launches, metres)| *metres > 0.0 && launches.iter().any(|&l| at(l, from)));
        let outs = climb_out.into_iter().flat_map(move |&(_, metres)| {
            (0..=24)
                .map(move |k| from.theta + (if k % 2 == 0 { 1.0 } else { -1.0 }) * (k as f64 / 2.0).ceil() * 15f64.to_radians())
                .map(move |theta| (Pose { theta, ..from }, moved(Pose { theta, ..from }, metres)))
                .filter(|&(launch, end)| self.transit.is_clear(launch.coord(), end.coord()))
                .map(|(_, end)| end)
        });
        let mut outs = outs.peekable();
        let none = outs.peek().is_none();
        outs.chain(none.then_some(from))
    }

    /// Where a Dubins connection to `to` stops turning: short of the landing approach when `to`
    /// is the landing point (on its heading), short of the lead-in otherwise, each shortened
    /// until it is clear of the walls (to a tenth of it at least; else `to` itself).
    fn turn_end(&self, to: Pose) -> Pose {
        let (to, metres) = match &self.ends.landing {
            Some((points, metres, heading)) if points.iter().any(|&p| at(p, to)) => (Pose { theta: heading.unwrap_or(to.theta), ..to }, *metres),
            _ => (to, self.ends.lead_in_m),
        };
        std::iter::successors(Some(metres), |m| Some(m * 0.75))
            .take_while(|&m| m >= metres / 10.0 && m > 0.0)
            .map(|m| moved(to, -m))
            .find(|&p| self.transit.is_clear(p.coord(), to.coord()))
            .unwrap_or(to)
    }

    /// Finds no more connections once `stop` is raised, so that every search built on
    /// connections winds down within moments.
    pub fn stopping_on(mut self, stop: &Stop) -> Self {
        self.stop = Some(stop.clone());
        self
    }
}

impl Drop for Connector<'_> {
    /// Around many zones the leg caches hold millions of small allocations, a few hundred
    /// milliseconds to free (measured after a cancellation: the search had stopped within 50 ms,
    /// the freeing took 200 more); a thread of their own frees them, so that a finished or
    /// stopped plan returns at once.
    fn drop(&mut self) {
        let caches = (std::mem::take(&mut self.legs_out), std::mem::take(&mut self.legs_in));
        let rows = |legs: &Legs| legs.read().map_or(0, |m| m.len());
        if rows(&caches.0) + rows(&caches.1) > 0 {
            std::thread::spawn(move || drop(caches));
        }
    }
}

impl Connector<'_> {
    /// True once the plan is to stop.
    pub fn stopped(&self) -> bool {
        self.stop.as_ref().is_some_and(Stop::requested)
    }

    /// What stops this connector, for another one to stop with it.
    pub fn stop(&self) -> Stop {
        self.stop.clone().unwrap_or_default()
    }

    /// The shortest connection found, as points from `from` to `to` exactly; `None` when there
    /// is none (or the plan is stopping).
    pub fn path(&self, from: Pose, to: Pose) -> Option<Vec<Coord>> {
        if self.stopped() {
            return None;
        }
        match self.turn {
            TurnModel::Straight => self.transit.path(from.coord(), to.coord()),
            TurnModel::Dubins(r) => self.with_straights(from, to, r),
        }
    }

    /// The Dubins connection with its straights ([`Connector::turn_starts`],
    /// [`Connector::turn_end`]): where no clear
    /// way joins them, one with another climb-out, then without the approach, and only then
    /// without the climb-out (a fixed wing cannot turn while it climbs out).
    fn with_straights(&self, from: Pose, to: Pose, r: f64) -> Option<Vec<Coord>> {
        let end = self.turn_end(to);
        let ends = if end.coord() == to.coord() { vec![to] } else { vec![end, to] };
        let tries = self.turn_starts(from).flat_map(|start| ends.iter().map(move |&end| (start, end))).chain([(from, to)]);
        tries.take(12).find_map(|(start, end)| {
            let turn = self.dubins_path(start, end, r)?;
            let points = (start.coord() != from.coord()).then(|| from.coord()).into_iter().chain(turn).chain((end.coord() != to.coord()).then(|| to.coord()));
            Some(points.collect())
        })
    }

    /// The shortest clear Dubins connection, without a lead-in.
    fn dubins_path(&self, from: Pose, to: Pose, r: f64) -> Option<Vec<Coord>> {
        self.clear_dubins(from, to, r).or_else(|| {
            // hops along the detour bound what a way through one corner may cost
            let hops = self.dubins_detour(from, to, r);
            if !self.via_corners {
                return hops;
            }
            let limit = hops.as_deref().map_or(f64::INFINITY, crate::geom::polyline_length);
            self.via_corner(from, to, self.ground_radius(r), limit).or(hops)
        })
    }

    /// Length of [`Connector::path`]; infinite when there is none. In wind, the metres of air
    /// it flies (its time × the airspeed), so that routes are ranked by time.
    pub fn length(&self, from: Pose, to: Pose) -> f64 {
        if self.stopped() {
            return f64::INFINITY;
        }
        match self.turn {
            TurnModel::Straight => match (self.transit.path(from.coord(), to.coord()), &self.tariff) {
                (Some(p), Some(t)) => t.length(&p),
                (Some(p), None) => crate::geom::polyline_length(&p),
                (None, _) => f64::INFINITY,
            },
            TurnModel::Dubins(r) => {
                let (start, end) = (self.turn_starts(from).next().unwrap_or(from), self.turn_end(to));
                if let Some(drift) = self.wind {
                    // in wind, metres of air: the connections are ranked by time
                    if !self.transit.any_wall_in(&self.reach(start, end)) {
                        let quickest = drift.connections(start, end, r).first().map(|t| t.time_s * drift.airspeed);
                        if let Some(turn) = quickest {
                            return turn + self.straight_cost(from.coord(), start.coord()) + self.straight_cost(end.coord(), to.coord());
                        }
                    }
                    return self.with_straights(from, to, r).map_or(f64::INFINITY, |points| air_length(&points, drift.wind, drift.airspeed));
                }
                if !self.transit.any_wall_in(&reach(start, end, r)) {
                    let straights = (start.x - from.x).hypot(start.y - from.y) + (to.x - end.x).hypot(to.y - end.y);
                    return TurnModel::Dubins(r).length(start, end) + straights;
                }
                self.with_straights(from, to, r).map_or(f64::INFINITY, |points| crate::geom::polyline_length(&points))
            }
        }
    }

    /// The stretch of the line `a → b` a fixed-wing aircraft can fly: each end pulled back (in
    /// steps of r/8) until the aircraft can turn there, a half circle to the left or to the
    /// right clear of the no-fly zones; `None` when nothing is left. A line that ends against
    /// a zone could be neither left nor entered there without crossing it. The straight model
    /// turns anywhere: the line is kept whole.
    pub fn turnable(&self, a: Coord, b: Coord) -> Option<(Coord, Coord)> {
        let TurnModel::Dubins(r) = self.turn else { return Some((a, b)) };
        if self.stopped() {
            return None;
        }
        let r = self.ground_radius(r);
        turnable_stretch(a, b, r, 1e-6, |at, out| self.can_turn_at(at, out, r))
    }

    /// True when a half circle of radius `r` turning left or right from `at`, flying `out`
    /// (unit), stays clear of the walls.
    fn can_turn_at(&self, at: Coord, out: Coord, r: f64) -> bool {
        let room = Rect::new(at - Coord { x: 2.0 * r, y: 2.0 * r }, at + Coord { x: 2.0 * r, y: 2.0 * r });
        !self.transit.any_wall_in(&room) || half_circles(at, out, r).iter().any(|arc| self.transit.is_polyline_clear(arc))
    }

    /// A box that holds every connection between the two poses that has no detour.
    pub fn reach(&self, from: Pose, to: Pose) -> Rect {
        let r = match self.turn {
            TurnModel::Dubins(r) => r,
            TurnModel::Straight => 0.0,
        };
        match self.wind {
            // a trochoid is its air path (within 4r of the ends) carried by the wind for at
            // most the longest time a word takes; the ground arcs are within 4 safe radii
            Some(d) => {
                let drifted = d.wind_speed() * d.longest_time(from, to, r);
                let m = (4.0 * r + drifted).max(4.0 * d.safe_radius(r));
                let bb = Rect::new(from.coord(), to.coord());
                Rect::new(bb.min() - Coord { x: m, y: m }, bb.max() + Coord { x: m, y: m })
            }
            None => reach(from, to, r),
        }
    }

    /// No connection from `from` to `to` in open sky is shorter ([`Connector::length`]'s
    /// measure), cheap: the Dubins path in still air; in wind, the time of the straight distance
    /// at the fastest ground speed, V_a + w, in metres of air, or the straight distance at the
    /// tariff's cheapest metre.
    pub fn open_sky_floor(&self, from: Pose, to: Pose) -> f64 {
        match (self.wind, &self.tariff) {
            (Some(d), _) => (to.x - from.x).hypot(to.y - from.y) * d.airspeed / (d.airspeed + d.wind_speed()),
            (None, Some(t)) => self.turn.length(from, to) * t.cheapest(),
            (None, None) => self.turn.length(from, to),
        }
    }

    /// The shortest Dubins word that stays clear of the walls, as points; in wind the quickest
    /// clear trochoid, or else the shortest clear word of the ground radius.
    fn clear_dubins(&self, from: Pose, to: Pose, r: f64) -> Option<Vec<Coord>> {
        if let Some(drift) = self.wind {
            let clear = |t: &Trochoid| {
                let mut points = t.ground_points(CHORD_TOLERANCE_M);
                *points.last_mut().expect("points") = to.coord();
                let bounds = crate::geom::bounding(&points).expect("points");
                self.is_clear_within(&bounds, &points).then_some(points)
            };
            let found = drift.connections(from, to, r).iter().find_map(clear).or_else(|| drift.all_connections(from, to, r).iter().find_map(clear));
            if found.is_some() {
                return found;
            }
        }
        let r = self.ground_radius(r);
        let mut words = all_words(from, to, r);
        words.sort_by(|a, b| a.length().total_cmp(&b.length()));
        words.into_iter().find_map(|w| self.clear_points(w, to))
    }

    /// The points of `word` (ending exactly at `to`) when it stays clear of the walls: a word
    /// whose box meets no wall is clear without testing its points.
    fn clear_points(&self, word: DubinsPath, to: Pose) -> Option<Vec<Coord>> {
        if self.straight_enters(word, to) {
            return None;
        }
        let points = word_points(word, to);
        self.is_clear_within(&word.bounds(), &points).then_some(points)
    }

    /// True when `points`, which lie within `bounds`, stay clear of the walls: points whose box
    /// meets no wall are clear without testing them.
    fn is_clear_within(&self, bounds: &Rect, points: &[Coord]) -> bool {
        !self.transit.any_wall_in(bounds) || self.transit.is_polyline_clear(points)
    }

    /// True when `word` (ending at `to`) stays clear of the walls.
    fn is_word_clear(&self, word: DubinsPath, to: Pose) -> bool {
        self.clear_points(word, to).is_some()
    }

    /// True when the straight part of `word` (ending at `to`), one leg of its points, enters a
    /// wall. Tested first: around zones most words priced are blocked, nine in ten of them
    /// there (h12_00, Fields2Cover's configuration), found without drawing an arc or bounding
    /// the word.
    fn straight_enters(&self, word: DubinsPath, to: Pose) -> bool {
        let straight = word.straight().map(|[a, b]| [a, if word.params[2] > 0.0 { b } else { to.coord() }]);
        straight.is_some_and(|[a, b]| !self.transit.is_clear(a, b))
    }

    /// Two clear Dubins paths through one corner of the detour graph, passed in one of
    /// [`VIA_HEADINGS`] headings: the shortest such pair (the first of equals in corner
    /// order), `None` when none is shorter than `limit`. Best first from a heap: the shortest
    /// ways to a corner and on from it, in any heading ([`to_point_lower_bound`]), bound its
    /// legs from below, so only corners that can still win get their Dubins legs computed
    /// (every leg of every corner for every pose was most of the planning time around many
    /// zones); each leg's clearance is found out once per pose and via pose.
    fn via_corner(&self, from: Pose, to: Pose, r: f64, limit: f64) -> Option<Vec<Coord>> {
        if self.via.is_empty() {
            return None;
        }
        // a leg into `to` is the reverse of one from `to` flown backwards
        let out = self.legs(&self.legs_out, from, r);
        let into = self.legs(&self.legs_in, to.reversed(), r);
        // legs already known to be blocked (rows serve every connection of their pose) are left
        // out; lengths are never negative, so their bits order as they do. Entries: (length
        // bits, 0 for a via pose or 1 for a corner not yet looked at, via pose or corner).
        let open = |row: &LegRow, k: usize| row.clear[k].load(Ordering::Relaxed) != BLOCKED;
        let corners = self.via.len() / VIA_HEADINGS;
        let mut shortest_first: BinaryHeap<Reverse<(u64, u8, usize)>> = (0..corners).map(|i| Reverse(((out.bound[i] + into.bound[i]).to_bits(), 1, i))).collect();
        while let Some(Reverse((bits, corner, at))) = shortest_first.pop() {
            if f64::from_bits(bits) >= limit {
                return None;
            }
            if corner == 1 {
                let poses = at * VIA_HEADINGS..(at + 1) * VIA_HEADINGS;
                let (place, headings) = (self.via[poses.start].coord(), std::array::from_fn(|k| self.via[poses.start + k].theta));
                let legs_out = out.length[at].get_or_init(|| Box::new(lengths_arriving(from, place, &headings, r)));
                let legs_in = into.length[at].get_or_init(|| Box::new(lengths_leaving(place, &headings, to, r)));
                for (k, via) in poses.enumerate().filter(|&(_, via)| open(&out, via) && open(&into, via)) {
                    shortest_first.push(Reverse(((legs_out[k] + legs_in[k]).to_bits(), 0, via)));
                }
                continue;
            }
            let via = self.via[at];
            if self.is_leg_clear(&out, at, || self.is_word_clear(shortest(from, via, r), via)) && self.is_leg_clear(&into, at, || self.is_word_clear(shortest(via, to, r), to)) {
                let mut points = word_points(shortest(from, via, r), via);
                points.extend_from_slice(&word_points(shortest(via, to, r), to)[1..]);
                return Some(points);
            }
        }
        None
    }

    /// The row of `pose` in `legs`, made on first use.
    fn legs(&self, legs: &Legs, pose: Pose, r: f64) -> Arc<LegRow> {
        cached(legs, [pose.x.to_bits(), pose.y.to_bits(), pose.theta.to_bits()], || LegRow {
            bound: self.via.iter().step_by(VIA_HEADINGS).map(|c| to_point_lower_bound(pose, c.coord(), r)).collect(),
            length: (0..self.via.len() / VIA_HEADINGS).map(|_| OnceLock::new()).collect(),
            clear: self.via.iter().map(|_| AtomicU8::new(UNKNOWN)).collect(),
        })
    }

    /// Whether leg `k` of `row` is clear, as `check` tells the first time.
    fn is_leg_clear(&self, row: &LegRow, k: usize, check: impl FnOnce() -> bool) -> bool {
        match row.clear[k].load(Ordering::Relaxed) {
            CLEAR => true,
            BLOCKED => false,
            _ => {
                let clear = check();
                row.clear[k].store(if clear { CLEAR } else { BLOCKED }, Ordering::Relaxed);
                clear
            }
        }
    }

    /// Dubins hops through the corners of a detour, each corner passed heading from the
    /// previous corner towards the next.
    fn dubins_detour(&self, from: Pose, to: Pose, r: f64) -> Option<Vec<Coord>> {
        let detour = self.detour?;
        let (a, b) = (from.coord(), to.coord());
        let corners = if detour.is_clear(a, b) {
            vec![a, b]
        } else {
            let sight = |p: Coord| place(&self.sights, p, || detour.seen_from(p));
            let tree = place(&self.trees, a, || detour.tree_seeing(a, &sight(a)));
            detour.path_between(&tree, b, &sight(b))?
        };
        let k = corners.len();
        let mut poses = vec![from];
        for i in 1..k - 1 {
            let d = corners[i + 1] - corners[i - 1];
            poses.push(Pose::at(corners[i], d.y.atan2(d.x)));
        }
        poses.push(to);
        let mut out = vec![from.coord()];
        for w in poses.windows(2) {
            let hop = self.clear_dubins(w[0], w[1], r)?;
            out.extend_from_slice(&hop[1..]);
        }
        Some(out)
    }
}

/// What `cache` holds for `key`, made by `make` on first use.
fn cached<K: std::hash::Hash + Eq, T>(cache: &RwLock<HashMap<K, Arc<T>>>, key: K, make: impl FnOnce() -> T) -> Arc<T> {
    if let Some(found) = cache.read().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return found.clone();
    }
    let made = Arc::new(make());
    cache.write().unwrap_or_else(|e| e.into_inner()).entry(key).or_insert(made).clone()
}

/// What `places` holds for the place `at`, made by `make` on first use.
fn place<T>(places: &Places<T>, at: Coord, make: impl FnOnce() -> T) -> Arc<T> {
    cached(places, [at.x.to_bits(), at.y.to_bits()], make)
}

/// A box that holds every Dubins word between the two poses: each part stays within 4r of
/// the start or the end, or on the way between them.
fn reach(from: Pose, to: Pose, r: f64) -> Rect {
    let bb = Rect::new(from.coord(), to.coord());
    let m = Coord { x: 4.0 * r, y: 4.0 * r };
    Rect::new(bb.min() - m, bb.max() + m)
}

/// The points of `word`, ending exactly at `to`.
fn word_points(word: DubinsPath, to: Pose) -> Vec<Coord> {
    let mut pts = word.sample(CHORD_TOLERANCE_M);
    *pts.last_mut().expect("points") = to.coord();
    pts
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{MultiPolygon, polygon};

    #[test]
    fn a_turn_avoids_a_zone_beside_the_line_end() {
        // a U-turn from (-200, 0) to (-200, 75) with r = 85 bulges to x = 2.9 around y = 37.5
        let zone = MultiPolygon(vec![polygon![(x: -10., y: 20.), (x: 30., y: 20.), (x: 30., y: 55.), (x: -10., y: 55.)]]);
        let walls = zone.clone();
        let transit = TransitPlanner::new(&zone, &walls);
        let grown = MultiPolygon(vec![polygon![(x: -105., y: -75.), (x: 125., y: -75.), (x: 125., y: 150.), (x: -105., y: 150.)]]);
        let detour = TransitPlanner::new(&grown, &walls);
        let c = Connector::new(TurnModel::Dubins(85.0), &transit, Some(&detour));
        let (a, b) = (Pose::new(-300.0, 0.0, 0.0), Pose::new(-300.0, 75.0, std::f64::consts::PI));
        let free = TurnModel::Dubins(85.0).length(a, b);
        let pts = c.path(a, b).expect("a way round");
        assert!(transit.is_polyline_clear(&pts));
        assert_eq!(pts[0], a.coord());
        assert_eq!(*pts.last().unwrap(), b.coord());
        assert!((c.length(a, b) - crate::geom::polyline_length(&pts)).abs() < 1e-9);
        assert!(c.length(a, b) >= free - 1.0);
        // a zone on the far side of the bulb: another word or a detour is flown
        let (a2, b2) = (Pose::new(-200.0, 0.0, 0.0), Pose::new(-200.0, 75.0, std::f64::consts::PI));
        let pts = c.path(a2, b2).expect("a way round");
        assert!(transit.is_polyline_clear(&pts), "the connection enters the zone");
        assert!(!transit.is_polyline_clear(&TurnModel::Dubins(85.0).points(a2, b2)), "the plain bulb would have entered it");
        // without a way through one corner: the hops along the detour, clear, never shorter
        let hops = c.hops_only();
        for (from, to) in [(a, b), (a2, b2), (Pose::new(-300.0, 37.0, 0.0), Pose::new(300.0, 37.0, 0.0))] {
            let pts = hops.path(from, to).expect("hops round the zone");
            assert!(transit.is_polyline_clear(&pts));
            assert_eq!((pts[0], *pts.last().unwrap()), (from.coord(), to.coord()));
            assert!(hops.length(from, to) >= c.length(from, to) - 1e-9, "{} below {}", hops.length(from, to), c.length(from, to));
        }
    }

    #[test]
    fn a_line_against_a_zone_is_pulled_back_until_the_aircraft_can_turn() {
        let zone = MultiPolygon(vec![polygon![(x: 100., y: -60.), (x: 200., y: -60.), (x: 200., y: 60.), (x: 100., y: 60.)]]);
        let transit = TransitPlanner::new(&zone, &zone);
        let c = Connector::new(TurnModel::Dubins(30.0), &transit, None);
        let (a, b) = (Coord { x: -500.0, y: 0.0 }, Coord { x: 95.0, y: 0.0 });
        let (a2, b2) = c.turnable(a, b).expect("most of the line is left");
        assert_eq!(a2, a, "the far end has room");
        // a half circle reaches r = 30 m ahead: the end must be at x ≤ 70, found in steps of r/8
        assert!(b2.x <= 70.0 && b2.x > 70.0 - 30.0 / 8.0, "pulled back to {b2:?}");
        // from the new end a U-turn to either side is clear
        let turn = TurnModel::Dubins(30.0).points(Pose::at(b2, 0.0), Pose::at(b2 + Coord { x: 0.0, y: 60.0 }, std::f64::consts::PI));
        assert!(transit.is_polyline_clear(&turn));
        // a line shorter than the room it needs is dropped; a multirotor keeps every line whole
        assert_eq!(c.turnable(Coord { x: 80.0, y: 0.0 }, b), None);
        let straight = Connector::new(TurnModel::Straight, &transit, None);
        assert_eq!(straight.turnable(a, b), Some((a, b)));
    }
}
