//! Refill and unloading trips (`payload`): where a ground vehicle's tank runs empty (or, for a
//! harvest, full), the route breaks off, drives to a refill point along the headland, comes
//! back and resumes.
//!
//! A trip may leave between two working pieces (after a swath, instead of the turn to the
//! next) or inside one where the tank runs out: the vehicle drives on along the swath's own
//! track to its end, makes the trip, re-enters the swath at its start and drives along its
//! track to where it stopped. Which breaks to take is a shortest path over the breaks each tank
//! can reach (exact for these two kinds of break); the operator's rule it is compared with goes
//! back only at a swath's end, when what is left cannot finish the next swath.

use geo::Coord;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::headland_route::{HeadlandRoutes, Reach, Way};
use crate::geom::distance;
use crate::path::{FlightPath, Piece, PieceKind};
use crate::turn::dubins::Pose;

/// A tank and where it is refilled, in the plan's frame.
#[derive(Debug, Clone)]
pub struct Tank {
    pub capacity: f64,
    /// What a square metre worked takes from the tank (or adds to it).
    pub per_m2: f64,
    pub stations: Vec<Coord>,
    /// Seconds stood at a station.
    pub stand_s: f64,
    /// That stand as the metres driven on the headland in its time: what a trip more costs
    /// besides its legs, when the breaks are chosen.
    pub stand_m: f64,
}

/// What the trips cost (`stats.ground.payload`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct PayloadStats {
    pub capacity: f64,
    /// What the plan applies (or harvests), in the tank's unit.
    pub amount: f64,
    pub trips: usize,
    /// Trips that break off inside a swath or headland pass.
    pub trips_inside_pieces: usize,
    /// The non-working distance the trips add: their legs, and the drives along a broken
    /// piece's own track, less the turns they replace.
    pub trip_distance_m: f64,
    /// Trip legs that cross the mainland (where no way along the headland reaches the point).
    pub trip_crossings: usize,
    /// Seconds stood at refill points, in the plan's duration (`payload.refill_s` a trip).
    #[serde(default)]
    pub refill_stops_s: f64,
    /// The operator's rule (back only at a swath's end, when what is left cannot finish the
    /// next one): its trips and their non-working distance, and what ours save on it (a share).
    pub rule_trips: usize,
    /// `None` where the rule goes back from a place no trip leaves from.
    pub rule_trip_distance_m: Option<f64>,
    pub rule_trip_crossings: usize,
    pub saving: f64,
}

impl PayloadStats {
    /// The figures of several machines' trips together (machines sharing a field).
    pub fn together<'a>(parts: impl IntoIterator<Item = &'a PayloadStats>) -> Option<PayloadStats> {
        let mut all: Option<PayloadStats> = None;
        for p in parts {
            let t = all.get_or_insert_with(|| PayloadStats { capacity: p.capacity, rule_trip_distance_m: Some(0.0), ..PayloadStats::default() });
            t.amount += p.amount;
            t.trips += p.trips;
            t.trips_inside_pieces += p.trips_inside_pieces;
            t.trip_distance_m += p.trip_distance_m;
            t.trip_crossings += p.trip_crossings;
            t.refill_stops_s += p.refill_stops_s;
            t.rule_trips += p.rule_trips;
            t.rule_trip_distance_m = t.rule_trip_distance_m.zip(p.rule_trip_distance_m).map(|(a, b)| a + b);
            t.rule_trip_crossings += p.rule_trip_crossings;
        }
        all.map(|t| PayloadStats { saving: saving(t.trip_distance_m, t.rule_trip_distance_m), ..t })
    }
}

/// What `ours` saves on `rule` (a share; 0 where the rule makes no trips or cannot be driven).
fn saving(ours: f64, rule: Option<f64>) -> f64 {
    match rule {
        Some(rule) if rule > 0.0 => 1.0 - ours / rule,
        _ => 0.0,
    }
}

/// What a leg that crosses the mainland costs the search on top of its length, metres: more
/// than any trip saves, so that the fewest crossings come first.
const CROSSING_PENALTY_M: f64 = 1.0e6;
/// Headland stops a refill point is reached from, the nearest: at a sharp corner of the
/// headland no ramp reaches the nearest one.
const STOPS_PER_POINT: usize = 4;
/// Shortest stretch of a piece a break inside it leaves on either side, metres: a break nearer
/// an end is one at that end.
const SHORTEST_STRETCH_M: f64 = 0.5;

/// Where a trip leaves the route.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Break {
    /// Before working piece `k` (after piece `k − 1`).
    Before(usize),
    /// Inside working piece `k`, this many metres along it.
    Inside(usize, f64),
}

/// The route's working pieces (swaths and headland passes) and the non-working ones between.
struct Work<'a> {
    pieces: &'a [Piece],
    /// Indices of the working pieces in `pieces`.
    at: Vec<usize>,
    /// Each working piece's length and what it takes from the tank.
    length: Vec<f64>,
    amount: Vec<f64>,
}

impl<'a> Work<'a> {
    fn new(path: &'a FlightPath, per_m2: f64) -> Self {
        let at: Vec<usize> = path.pieces.iter().enumerate().filter(|(_, p)| matches!(p.kind, PieceKind::Sweep | PieceKind::Headland)).map(|(i, _)| i).collect();
        let length: Vec<f64> = at.iter().map(|&i| path.pieces[i].length()).collect();
        let amount = at.iter().zip(&length).map(|(&i, l)| l * 2.0 * path.pieces[i].half_swath_m * per_m2).collect();
        Work { pieces: &path.pieces, at, length, amount }
    }

    /// The non-working pieces between working pieces `k − 1` and `k`.
    fn gap(&self, k: usize) -> &'a [Piece] {
        &self.pieces[self.at[k - 1] + 1..self.at[k]]
    }
}

fn entry(p: &Piece) -> Pose {
    let (a, b) = (p.points[0], p.points[1]);
    Pose::at(a, (b.y - a.y).atan2(b.x - a.x))
}

fn exit(p: &Piece) -> Pose {
    let n = p.points.len();
    let (a, b) = (p.points[n - 2], p.points[n - 1]);
    Pose::at(b, (b.y - a.y).atan2(b.x - a.x))
}

/// A trip's leg from a piece to a refill point or back.
#[derive(Debug, Clone)]
struct Leg {
    points: Vec<Coord>,
    length: f64,
    crossing: bool,
}

impl Leg {
    fn cost(&self) -> f64 {
        self.length + if self.crossing { CROSSING_PENALTY_M } else { 0.0 }
    }
}

/// The legs between each working piece and each refill point: from its exit (`out`) and to its
/// entry (`back`), per point; the point is reached from one of the headland stops nearest it,
/// either way along its road, by a straight stretch (where the vehicle turns round off the
/// field).
struct Legs {
    out: Vec<Vec<Option<Leg>>>,
    back: Vec<Vec<Option<Leg>>>,
}

impl Legs {
    fn new(work: &Work<'_>, routes: &HeadlandRoutes, stations: &[Coord]) -> Self {
        let at_station: Vec<Vec<(Reach, Reach)>> =
            stations.iter().map(|&s| routes.stops_near(s, STOPS_PER_POINT).into_iter().map(|pose| (routes.reach(pose, false), routes.reach(pose, true))).collect()).collect();
        // the shortest of `ways`, each with its stretch to or from the refill point `at`
        let best = |ways: Vec<Option<(Way, bool)>>, at: Coord, leaving: bool| {
            let legs = ways.into_iter().flatten().map(|(w, crossing)| with_stub(Leg { length: w.length, points: w.points, crossing }, at, leaving));
            legs.min_by(|a, b| a.cost().total_cmp(&b.cost()))
        };
        let (out, back) = work
            .at
            .par_iter()
            .map(|&i| {
                let piece = &work.pieces[i];
                let (from, to) = (routes.reach(exit(piece), true), routes.reach(entry(piece), false));
                let per_station = |leaving: bool| -> Vec<Option<Leg>> {
                    stations
                        .iter()
                        .zip(&at_station)
                        .map(|(&s, poses)| {
                            let ways = poses.iter().map(|(arrive, depart)| if leaving { routes.drive(&from, arrive) } else { routes.drive(depart, &to) }).collect();
                            best(ways, s, leaving)
                        })
                        .collect()
                };
                (per_station(true), per_station(false))
            })
            .unzip();
        Legs { out, back }
    }

    /// The cheapest trip from working piece `from`'s exit to piece `to`'s entry: its refill
    /// point and its cost.
    fn trip(&self, from: usize, to: usize) -> Option<(usize, f64)> {
        let pairs = self.out[from].iter().zip(&self.back[to]).enumerate();
        pairs.filter_map(|(s, (o, b))| Some((s, o.as_ref()?.cost() + b.as_ref()?.cost()))).min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// `leg` extended by the straight stretch between the road and the refill point `at`, at its
/// end when `leaving` the route, else at its start.
fn with_stub(mut leg: Leg, at: Coord, leaving: bool) -> Leg {
    let end = if leaving { *leg.points.last().expect("a way has points") } else { leg.points[0] };
    let stub = distance(end, at);
    if stub > 0.01 {
        if leaving {
            leg.points.push(at);
        } else {
            leg.points.insert(0, at);
        }
        leg.length += stub;
    }
    leg
}

/// What each break costs the search (non-working metres, crossings priced), and the best
/// refill point for it.
struct Costs {
    /// A trip's stand at the refill point, in metres.
    stand_m: f64,
    /// Per working piece `k` ≥ 1: a trip before it, less the gap it replaces.
    before: Vec<Option<(usize, f64)>>,
    /// Per working piece: a trip from inside it (its length driven along its track, plus the
    /// trip from its exit to its entry).
    inside: Vec<Option<(usize, f64)>>,
}

impl Costs {
    fn new(work: &Work<'_>, legs: &Legs, stand_m: f64) -> Self {
        let n = work.at.len();
        let gap = |k: usize| work.gap(k).iter().map(Piece::length).sum::<f64>();
        let before = (0..n).map(|k| if k == 0 { None } else { legs.trip(k - 1, k).map(|(s, c)| (s, c - gap(k))) }).collect();
        let inside = (0..n).map(|k| legs.trip(k, k).map(|(s, c)| (s, c + work.length[k]))).collect();
        Costs { stand_m, before, inside }
    }

    /// Break `b`'s refill point and its cost: its legs less what they replace, and the stand.
    fn of(&self, b: Break) -> Option<(usize, f64)> {
        let trip = match b {
            Break::Before(k) => self.before[k],
            Break::Inside(k, _) => self.inside[k],
        };
        trip.map(|(s, c)| (s, c + self.stand_m))
    }
}

/// The breaks of least total cost that keep the tank from running dry: a shortest path over
/// the places the tank is full again, in the order they are worked. `start[k]`: what is worked
/// before piece `k`.
fn cheapest_breaks(work: &Work<'_>, costs: &Costs, capacity: f64) -> Option<Vec<Break>> {
    use std::collections::BTreeMap;
    let n = work.at.len();
    let start: Vec<f64> = std::iter::once(0.0)
        .chain(work.amount.iter().scan(0.0, |s, a| {
            *s += a;
            Some(*s)
        }))
        .collect();
    let total = start[n];
    let eps = 1e-9 * capacity.max(1.0);
    // a full tank at (piece, amount into it); its cost and the break before it
    #[derive(Clone, Copy)]
    struct Full {
        cost: f64,
        came: Option<(Break, (usize, u64))>,
    }
    let key = |piece: usize, into: f64| (piece, into.max(0.0).to_bits());
    let mut open: BTreeMap<(usize, u64), Full> = BTreeMap::from([(key(0, 0.0), Full { cost: 0.0, came: None })]);
    let mut done: BTreeMap<(usize, u64), Full> = BTreeMap::new();
    let mut finish: Option<(f64, (usize, u64))> = None;
    while let Some((here, full)) = open.pop_first() {
        done.insert(here, full);
        let (piece, into) = (here.0, f64::from_bits(here.1));
        let reach = start[piece] + into + capacity + eps;
        let mut relax = |to: (usize, u64), b: Break| {
            let Some((_, c)) = costs.of(b) else { return };
            let cost = full.cost + c;
            let better = open.get(&to).is_none_or(|f| cost < f.cost);
            if better {
                open.insert(to, Full { cost, came: Some((b, here)) });
            }
        };
        if total <= reach {
            if finish.is_none_or(|(c, _)| full.cost < c) {
                finish = Some((full.cost, here));
            }
            continue;
        }
        for (k, _) in start.iter().enumerate().take(n).skip(piece + 1).take_while(|(_, s)| **s <= reach) {
            relax(key(k, 0.0), Break::Before(k));
        }
        // where the tank runs dry inside a piece: as late as it can
        let dry = reach - eps;
        let j = start.partition_point(|&s| s <= dry).saturating_sub(1).min(n - 1);
        // (a stretch too short to leave before the piece's end: left earlier)
        let (amount, length) = (work.amount[j].max(f64::MIN_POSITIVE), work.length[j]);
        let metres = ((dry - start[j]) / amount * length).min(length - SHORTEST_STRETCH_M);
        let into_j = metres / length * amount;
        if metres >= SHORTEST_STRETCH_M && (j > piece || into_j > into) {
            relax(key(j, into_j), Break::Inside(j, metres));
        }
    }
    let (_, mut at) = finish?;
    let mut breaks = Vec::new();
    while let Some((b, from)) = done[&at].came {
        breaks.push(b);
        at = from;
    }
    breaks.reverse();
    Some(breaks)
}

/// The operator's rule: back only at a swath's end, when what is left cannot finish the next
/// piece (from the latest end since the last trip that a trip leaves from: `priced`); inside a
/// piece only where a full tank cannot finish it.
fn rule_breaks(work: &Work<'_>, capacity: f64, priced: impl Fn(usize) -> bool) -> Vec<Break> {
    let mut left = capacity;
    // the last piece a trip left before or inside
    let mut last = 0;
    let mut out = Vec::new();
    for k in 0..work.at.len() {
        let need = work.amount[k];
        if need > left + 1e-9 && k > 0 && left < capacity {
            let j = (last + 1..=k).rev().find(|&j| priced(j)).unwrap_or(k);
            out.push(Break::Before(j));
            left = capacity - work.amount[j..k].iter().sum::<f64>();
            last = j;
        }
        let mut worked = 0.0;
        while need - worked > left + 1e-9 {
            worked += left;
            out.push(Break::Inside(k, worked / need * work.length[k]));
            left = capacity;
            last = k;
        }
        left -= need - worked;
    }
    out
}

/// `points` cut `at` metres along: the stretch before and the stretch after.
fn split(points: &[Coord], at: f64) -> (Vec<Coord>, Vec<Coord>) {
    let mut walked = 0.0;
    for (i, w) in points.windows(2).enumerate() {
        let d = distance(w[0], w[1]);
        if walked + d >= at && d > 0.0 {
            let cut = w[0] + (w[1] - w[0]) * ((at - walked) / d);
            let mut before = points[..=i].to_vec();
            before.push(cut);
            let mut after = vec![cut];
            after.extend_from_slice(&points[i + 1..]);
            return (before, after);
        }
        walked += d;
    }
    (points.to_vec(), vec![*points.last().expect("a piece has points"); 2])
}

/// Appends a drive along `points` where it has a length (as [`FlightPath::push`] drops a
/// connection of none); `refill_s`: the tank is refilled where it ends, standing so long.
fn push_transit(pieces: &mut Vec<Piece>, points: Vec<Coord>, refill_s: Option<f64>) {
    if crate::geom::polyline_length(&points) > 0.0 {
        pieces.push(Piece { refill_s, ..Piece::new(PieceKind::Transit, points, 0.0) });
    }
}

/// Appends the trip from `out` to `back` (the refill point's legs), standing `stand_s` there.
fn push_trip(pieces: &mut Vec<Piece>, out: &Leg, back: &Leg, stand_s: f64) {
    push_transit(pieces, out.points.clone(), Some(stand_s));
    push_transit(pieces, back.points.clone(), None);
}

/// `path` with its refill trips: the breaks of least non-working distance, and what they cost
/// beside the operator's rule. `None` when some tank cannot reach a refill point.
pub fn plan_trips(path: &FlightPath, tank: &Tank, routes: &HeadlandRoutes) -> Option<(FlightPath, PayloadStats)> {
    let work = Work::new(path, tank.per_m2);
    let amount: f64 = work.amount.iter().sum();
    let mut stats = PayloadStats { capacity: tank.capacity, amount, rule_trip_distance_m: Some(0.0), ..PayloadStats::default() };
    if amount <= tank.capacity || work.at.is_empty() {
        return Some((path.clone(), stats));
    }
    let legs = Legs::new(&work, routes, &tank.stations);
    let costs = Costs::new(&work, &legs, tank.stand_m);
    let breaks = cheapest_breaks(&work, &costs, tank.capacity)?;
    // the non-working metres of `breaks`, and their legs across the mainland
    let measure = |breaks: &[Break]| -> (f64, usize) {
        let crossings: usize = breaks.iter().filter_map(|&b| costs.of(b).map(|(s, _)| crossings(&legs, b, s))).sum();
        let cost: f64 = breaks.iter().map(|&b| costs.of(b).map_or(f64::INFINITY, |(_, c)| c)).sum();
        (cost - crossings as f64 * CROSSING_PENALTY_M - breaks.len() as f64 * tank.stand_m, crossings)
    };
    let rule = rule_breaks(&work, tank.capacity, |k| costs.before[k].is_some());
    stats.trips = breaks.len();
    stats.refill_stops_s = breaks.len() as f64 * tank.stand_s;
    stats.trips_inside_pieces = breaks.iter().filter(|b| matches!(b, Break::Inside(..))).count();
    (stats.trip_distance_m, stats.trip_crossings) = measure(&breaks);
    stats.rule_trips = rule.len();
    let (rule_m, rule_crossings) = measure(&rule);
    (stats.rule_trip_distance_m, stats.rule_trip_crossings) = (rule_m.is_finite().then_some(rule_m), rule_crossings);
    stats.saving = saving(stats.trip_distance_m, stats.rule_trip_distance_m);
    let mut pieces: Vec<Piece> = path.pieces[..work.at[0]].to_vec();
    for k in 0..work.at.len() {
        if k > 0 {
            match breaks.iter().find(|&&b| b == Break::Before(k)) {
                Some(&b) => {
                    let (s, _) = costs.of(b).expect("a chosen break has a cost");
                    let (out, back) = (legs.out[k - 1][s].as_ref().expect("priced"), legs.back[k][s].as_ref().expect("priced"));
                    push_trip(&mut pieces, out, back, tank.stand_s);
                }
                None => pieces.extend_from_slice(work.gap(k)),
            }
        }
        // the piece, cut where trips leave it
        let piece = &work.pieces[work.at[k]];
        let mut rest = piece.points.clone();
        let mut done_m = 0.0;
        for &b in &breaks {
            let Break::Inside(j, at) = b else { continue };
            if j != k {
                continue;
            }
            let (s, _) = costs.of(b).expect("a chosen break has a cost");
            let (out, back) = (legs.out[k][s].as_ref().expect("priced"), legs.back[k][s].as_ref().expect("priced"));
            let (worked, ahead) = split(&rest, at - done_m);
            let (_, track) = split(&piece.points, 0.0);
            let (to_here, _) = split(&track, at);
            pieces.push(Piece { points: worked, ..piece.clone() });
            push_transit(&mut pieces, ahead.clone(), None);
            push_trip(&mut pieces, out, back, tank.stand_s);
            push_transit(&mut pieces, to_here, None);
            rest = ahead;
            done_m = at;
        }
        pieces.push(Piece { points: rest, ..piece.clone() });
    }
    pieces.extend_from_slice(&path.pieces[work.at[work.at.len() - 1] + 1..]);
    Some((FlightPath { pieces }, stats))
}

/// How many of break `b`'s legs by refill point `s` cross the mainland.
fn crossings(legs: &Legs, b: Break, s: usize) -> usize {
    let (from, to) = match b {
        Break::Before(k) => (k - 1, k),
        Break::Inside(k, _) => (k, k),
    };
    let crossing = |l: &Option<Leg>| l.as_ref().is_some_and(|l| l.crossing);
    usize::from(crossing(&legs.out[from][s])) + usize::from(crossing(&legs.back[to][s]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Swaths of `lengths` metres, 1 m wide (half 0.5), one after another with 10 m gaps.
    fn route(lengths: &[f64]) -> FlightPath {
        let mut pieces = Vec::new();
        for (k, &l) in lengths.iter().enumerate() {
            let y = k as f64 * 10.0;
            if k > 0 {
                pieces.push(Piece::new(PieceKind::Transit, vec![Coord { x: 0.0, y: y - 10.0 }, Coord { x: 0.0, y }], 0.0));
            }
            pieces.push(Piece::new(PieceKind::Sweep, vec![Coord { x: 0.0, y }, Coord { x: l, y }], 0.5));
        }
        FlightPath { pieces }
    }

    /// Break costs: `before[k]` for each piece boundary, `inside[k]` for a break in piece `k`,
    /// each trip standing `stand_m` at the refill point.
    fn costs_standing(before: &[f64], inside: &[f64], stand_m: f64) -> Costs {
        Costs { stand_m, before: before.iter().map(|&c| Some((0, c))).collect(), inside: inside.iter().map(|&c| Some((0, c))).collect() }
    }

    fn costs(before: &[f64], inside: &[f64]) -> Costs {
        costs_standing(before, inside, 0.0)
    }

    /// What is worked between one full tank and the next along `breaks`.
    fn worked_per_tank(work: &Work<'_>, breaks: &[Break]) -> Vec<f64> {
        let mut out = vec![0.0];
        let mut done = vec![0.0; work.at.len()];
        let mut at = 0;
        for &b in breaks.iter().chain([&Break::Before(work.at.len())]) {
            let (k, upto) = match b {
                Break::Before(k) => (k, 0.0),
                Break::Inside(k, m) => (k, work.amount[k] * m / work.length[k]),
            };
            while at < k {
                *out.last_mut().expect("one") += work.amount[at] - done[at];
                done[at] = work.amount[at];
                at += 1;
            }
            if k < work.at.len() {
                *out.last_mut().expect("one") += upto - done[k];
                done[k] = upto;
            }
            out.push(0.0);
        }
        out
    }

    #[test]
    fn the_cheapest_breaks_go_back_early_where_the_trip_is_short() {
        // four 100 m swaths (100 units each), a tank of 250: going back before the 2nd costs
        // 10 but leaves 300 to work, so a second trip follows (100): one trip before the 3rd
        // (100) is cheaper
        let path = route(&[100.0, 100.0, 100.0, 100.0]);
        let work = Work::new(&path, 1.0);
        let c = costs(&[f64::NAN, 10.0, 100.0, 100.0], &[500.0; 4]);
        assert_eq!(cheapest_breaks(&work, &c, 250.0).expect("reachable"), vec![Break::Before(2)]);
        // with a trip before the 4th at 20, two cheap trips beat one dear one
        let c = costs(&[f64::NAN, 10.0, 100.0, 20.0], &[500.0; 4]);
        assert_eq!(cheapest_breaks(&work, &c, 250.0).expect("reachable"), vec![Break::Before(1), Break::Before(3)]);
        // ... unless each trip stands longer than the 70 m they save: then one trip
        let c = costs_standing(&[f64::NAN, 10.0, 100.0, 20.0], &[500.0; 4], 80.0);
        assert_eq!(cheapest_breaks(&work, &c, 250.0).expect("reachable"), vec![Break::Before(2)]);
        // the rule goes back before the 3rd (the tank holds 50 after two swaths)
        assert_eq!(rule_breaks(&work, 250.0, |_| true), vec![Break::Before(2)]);
    }

    #[test]
    fn a_break_inside_a_swath_is_taken_where_the_tank_runs_dry_when_it_is_cheaper() {
        // two 100 m swaths, a tank of 150: inside the 2nd (cost 30) beats before it (cost 80)
        let path = route(&[100.0, 100.0]);
        let work = Work::new(&path, 1.0);
        let c = costs(&[f64::NAN, 80.0], &[500.0, 30.0]);
        let breaks = cheapest_breaks(&work, &c, 150.0).expect("reachable");
        assert_eq!(breaks.len(), 1);
        let Break::Inside(1, at) = breaks[0] else { panic!("{breaks:?}") };
        assert!((at - 50.0).abs() < 1e-6, "{at}");
        // a swath longer than the tank is broken inside by the rule too
        assert_eq!(rule_breaks(&Work::new(&route(&[400.0]), 1.0), 150.0, |_| true), vec![Break::Inside(0, 150.0), Break::Inside(0, 300.0)]);
    }

    #[test]
    fn no_tank_runs_dry_and_the_cheapest_breaks_cost_no_more_than_the_rule() {
        use proptest::prelude::*;
        let mut runner = proptest::test_runner::TestRunner::default();
        let case = (proptest::collection::vec(5.0f64..200.0, 1..30), proptest::collection::vec(0.0f64..300.0, 60), 50.0f64..400.0);
        runner
            .run(&case, |(lengths, prices, capacity)| {
                let path = route(&lengths);
                let work = Work::new(&path, 1.0);
                let n = lengths.len();
                // a sixth of the breaks have no trip (no way from there to a refill point)
                let priced = |p: &[f64]| p.iter().map(|&c| (c < 250.0).then_some((0, c))).collect();
                let c = Costs { stand_m: 0.0, before: priced(&prices[..n]), inside: priced(&prices[30..30 + n]) };
                let rule = rule_breaks(&work, capacity, |k| c.before[k].is_some());
                let total = |b: &[Break]| b.iter().map(|&b| c.of(b).map_or(f64::INFINITY, |(_, x)| x)).sum::<f64>();
                let Some(breaks) = cheapest_breaks(&work, &c, capacity) else {
                    // only where the rule finds no trips either
                    prop_assert!(total(&rule).is_infinite(), "{:?}", rule);
                    return Ok(());
                };
                prop_assert!(total(&breaks) <= total(&rule) + 1e-6, "{:?} {:?}", breaks, rule);
                for b in [&breaks, &rule] {
                    let tanks = worked_per_tank(&work, b);
                    prop_assert!(tanks.iter().all(|&t| t <= capacity + 1e-6), "{:?}: {:?}", b, tanks);
                    prop_assert!((tanks.iter().sum::<f64>() - lengths.iter().sum::<f64>()).abs() < 1e-6);
                }
                Ok(())
            })
            .expect("property holds");
    }

    #[test]
    fn split_cuts_a_polyline_at_a_distance_along_it() {
        let points = vec![Coord { x: 0.0, y: 0.0 }, Coord { x: 10.0, y: 0.0 }, Coord { x: 10.0, y: 10.0 }];
        let (a, b) = split(&points, 15.0);
        assert_eq!(a, vec![points[0], points[1], Coord { x: 10.0, y: 5.0 }]);
        assert_eq!(b, vec![Coord { x: 10.0, y: 5.0 }, points[2]]);
    }
}
