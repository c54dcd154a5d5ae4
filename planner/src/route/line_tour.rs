//! Line-level routing (docs/methods.md, routing §1, §6; seed 004): every sweep line is a cluster of its two
//! flight directions, connections cost the length of the flyable path from the end of one line
//! to the start of the next (Dubins for a fixed-wing aircraft), and the order is a generalised
//! TSP solved by [`super::gtsp`]. Lines carry the region (field or cell) they belong to; without
//! re-entries each region is flown in one block.

use geo::Coord;
use rayon::prelude::*;

use super::connect::Connector;
use super::gtsp::{self, Costs, Instance, KnownCosts, solve};
use crate::stop::Stop;
use crate::turn::climb::Obstacles;
use crate::turn::dubins::Pose;

/// A sweep line, flown `a → b` (node `2k`) or `b → a` (node `2k + 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    pub a: Coord,
    pub b: Coord,
    pub region: usize,
}

impl Line {
    pub fn length(&self) -> f64 {
        crate::geom::distance(self.a, self.b)
    }
}

/// Entry pose of node `v`.
pub fn entry(lines: &[Line], v: usize) -> Pose {
    let l = &lines[v / 2];
    let (p, q) = if v.is_multiple_of(2) { (l.a, l.b) } else { (l.b, l.a) };
    Pose::at(p, (q.y - p.y).atan2(q.x - p.x))
}

/// Exit pose of node `v`.
pub fn exit(lines: &[Line], v: usize) -> Pose {
    let e = entry(lines, v);
    let l = &lines[v / 2];
    let q = if v.is_multiple_of(2) { l.b } else { l.a };
    Pose::at(q, e.theta)
}

/// A start or end position; without a heading the aircraft faces where it goes (start) or
/// arrives as it comes (end).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Terminal {
    pub at: Coord,
    pub heading: Option<f64>,
}

impl Terminal {
    fn towards(&self, p: Coord) -> Pose {
        Pose::at(self.at, self.heading.unwrap_or_else(|| (p.y - self.at.y).atan2(p.x - self.at.x)))
    }

    fn from(&self, p: Coord) -> Pose {
        Pose::at(self.at, self.heading.unwrap_or_else(|| (self.at.y - p.y).atan2(self.at.x - p.x)))
    }
}

pub struct LineProblem<'a> {
    pub lines: &'a [Line],
    pub connector: &'a Connector<'a>,
    pub start: Option<Terminal>,
    pub end: Option<Terminal>,
    pub allow_reentry: bool,
    /// Obstacles to climb over: connections cost their raised length plus the lost coverage.
    pub obstacles: Option<&'a Obstacles>,
    /// Each node's entry and exit pose, found once: their arc tangents were a tenth of
    /// pricing connections. Made by [`LineProblem::new`] from `lines`.
    pub(crate) poses: Vec<[Pose; 2]>,
}

/// Added to every connection between regions when re-entries are not allowed: larger than any
/// tour, so the best tour leaves each region once.
const REGION_CHANGE: f64 = 1e8;

/// Cost of an impossible connection: large enough never to be chosen when there is a way.
pub const NO_WAY: f64 = 1e12;

fn finite(c: f64) -> f64 {
    if c.is_finite() { c } else { NO_WAY }
}

/// A 10° chord is 0.99873 of its arc.
const CHORDS_AT_LEAST: f64 = 0.998;

/// Entries nearest each exit whose connections are priced before the search.
pub const CANDIDATES: usize = 24;

/// For each node, the [`CANDIDATES`] nodes whose entry is nearest its exit in a straight line:
/// where the cheap connections are (no turning path is shorter than the straight line). By
/// brute force, O(n²) distances, a few milliseconds for thousands of lines.
pub fn nearest_entries(lines: &[Line]) -> Vec<Vec<usize>> {
    let n = 2 * lines.len();
    let entries: Vec<Coord> = (0..n).map(|v| entry(lines, v).coord()).collect();
    (0..n)
        .into_par_iter()
        .map(|u| {
            let from = exit(lines, u).coord();
            // squared distances order as distances do, without a square root each
            let mut near: Vec<(f64, usize)> = (0..n).filter(|&v| v / 2 != u / 2).map(|v| ((entries[v].x - from.x).powi(2) + (entries[v].y - from.y).powi(2), v)).collect();
            if near.len() > CANDIDATES {
                near.select_nth_unstable_by(CANDIDATES, |a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                near.truncate(CANDIDATES);
            }
            near.into_iter().map(|(_, v)| v).collect()
        })
        .collect()
}

/// The GTSP instance of `lines`: clusters of each line's two directions, each node costing its
/// line's length, connections by `cost`, start and end costs where there is a start or end
/// (impossible ones at [`NO_WAY`]).
pub fn line_instance<'c>(lines: &[Line], cost: Costs<'c>, from_start: Option<Vec<f64>>, to_end: Option<Vec<f64>>, stop: Stop) -> Instance<'c> {
    let n = 2 * lines.len();
    Instance {
        clusters: (0..lines.len()).map(|k| vec![2 * k, 2 * k + 1]).collect(),
        reverse: (0..n).map(|v| v ^ 1).collect(),
        cost,
        node_cost: (0..n).map(|v| lines[v / 2].length()).collect(),
        from_start: from_start.map(|r| r.into_iter().map(finite).collect()),
        to_end: to_end.map(|r| r.into_iter().map(finite).collect()),
        candidates: None,
        stop,
    }
}

impl<'a> LineProblem<'a> {
    /// The routing of `lines` by `connector`, with no start, end nor obstacles, re-entering
    /// regions allowed.
    pub fn new(lines: &'a [Line], connector: &'a Connector<'a>) -> Self {
        let poses = (0..2 * lines.len()).map(|v| [entry(lines, v), exit(lines, v)]).collect();
        LineProblem { lines, connector, start: None, end: None, allow_reentry: true, obstacles: None, poses }
    }

    fn entry(&self, v: usize) -> Pose {
        self.poses[v][0]
    }

    fn exit(&self, v: usize) -> Pose {
        self.poses[v][1]
    }

    /// Cost of the connection from the exit of node `u` to the entry of node `v`: its length,
    /// or with obstacles its raised 3D length plus the penalty for the coverage it loses;
    /// infinite when there is no way.
    pub fn connection(&self, u: usize, v: usize) -> f64 {
        if u / 2 == v / 2 {
            return f64::INFINITY;
        }
        let (from, to) = (self.exit(u), self.entry(v));
        let plain = self.connector.length(from, to);
        match self.obstacles {
            Some(obs) if plain.is_finite() && obs.near(&self.connector.reach(from, to)) => {
                let Some(points) = self.connector.path(from, to) else { return f64::INFINITY };
                let (length_3d, lost) = obs.connection((self.entry(u).coord(), from.coord()), &points, (to.coord(), self.exit(v).coord()));
                length_3d + obs.penalty * lost
            }
            _ => plain,
        }
    }

    /// A lower bound of [`Self::connection`], cheap: the connection in open sky (no zone
    /// makes a connection shorter, nor climbing over an obstacle), less the most that
    /// sampling arcs into chords (10° at most) takes off a flown path's length. The flag
    /// says the bound is the connection itself: with no zone within the turn's reach and no
    /// obstacle, the connection is the open-sky one, as cheap to price as its bound, and
    /// bounding it first priced it twice (most connections while ranking headings).
    pub fn connection_floor(&self, u: usize, v: usize) -> (f64, bool) {
        if u / 2 == v / 2 {
            return (f64::INFINITY, false);
        }
        let (from, to) = (self.exit(u), self.entry(v));
        if self.obstacles.is_none() && !self.connector.transit.any_wall_in(&self.connector.reach(from, to)) {
            return (self.connection(u, v), true);
        }
        (CHORDS_AT_LEAST * self.connector.open_sky_floor(from, to), false)
    }

    /// From the start to the entry of each node (`None` without a start).
    pub fn start_costs(&self) -> Option<Vec<f64>> {
        self.start.map(|s| {
            (0..2 * self.lines.len())
                .map(|v| {
                    let e = self.entry(v);
                    self.connector.length(s.towards(e.coord()), e)
                })
                .collect()
        })
    }

    /// From the exit of each node to the end (`None` without an end).
    pub fn end_costs(&self) -> Option<Vec<f64>> {
        self.end.map(|t| {
            (0..2 * self.lines.len())
                .map(|v| {
                    let x = self.exit(v);
                    self.connector.length(x, t.from(x.coord()))
                })
                .collect()
        })
    }

    /// The GTSP instance: clusters of two directed nodes, node costs, connection costs, and
    /// for each exit the entries where the local search looks for moves. Up to
    /// [`gtsp::ALL_NEIGHBOURS_UP_TO`] lines every connection is computed in advance, in
    /// parallel (the search would ask for most of them, one at a time), and every entry is a
    /// candidate. On more, each exit's [`gtsp::NEIGHBOURS`] cheapest connections to its
    /// [`CANDIDATES`] nearest entries are (see [`Self::cheapest`]), those priced on the way
    /// are its candidates, and the rest are priced when the search first needs them.
    pub fn instance(&self) -> Instance<'_> {
        let n = 2 * self.lines.len();
        if self.lines.len() <= gtsp::ALL_NEIGHBOURS_UP_TO {
            let raw: Vec<f64> = (0..n * n).into_par_iter().map(|i| self.connection(i / n, i % n)).collect();
            let mut inst = self.assemble(raw, self.start_costs(), self.end_costs());
            inst.candidates = Some(nearest_entries(self.lines));
            return inst;
        }
        let priced: Vec<Vec<(usize, f64)>> = nearest_entries(self.lines).par_iter().enumerate().map(|(u, near)| self.cheapest(u, near, gtsp::NEIGHBOURS)).collect();
        let candidates = priced.iter().map(|row| row.iter().map(|&(v, _)| v).collect()).collect();
        let known: KnownCosts = priced.into_iter().enumerate().flat_map(|(u, row)| row.into_iter().map(move |(v, c)| ((u, v), c))).collect();
        let mut inst = self.instance_with(self.lazy_costs(known), self.start_costs(), self.end_costs());
        inst.candidates = Some(candidates);
        inst
    }

    /// `seq` improved by one local search ([`gtsp::improve`]) on connections priced when the
    /// search first needs one, none in advance: what the real connections change in a route
    /// found on others, at a fraction of a full solve's cost. Returns the sequence and its
    /// total (as on [`Self::instance`]).
    pub fn improve(&self, seq: &[usize]) -> (Vec<usize>, f64) {
        let mut inst = self.instance_with(self.lazy_costs(Vec::new()), self.start_costs(), self.end_costs());
        inst.candidates = Some(nearest_entries(self.lines));
        let better = gtsp::improve(&inst, seq);
        let total = inst.total(&better);
        (better, total)
    }

    /// Connections priced when the search first asks for one (`known` ones kept), moves
    /// weighed on their floors first.
    fn lazy_costs(&self, known: KnownCosts) -> Costs<'_> {
        let price = |u: usize, v: usize| self.priced(u, v, self.connection(u, v));
        let floor = |u: usize, v: usize| {
            let (floor, exact) = self.connection_floor(u, v);
            (self.priced(u, v, floor), exact)
        };
        let costs = Costs::lazy(2 * self.lines.len(), known, price, floor);
        if self.connector.directed() { costs.directed() } else { costs }
    }

    /// The `k` cheapest connections from the exit of `u` to the entries of `near`, without
    /// pricing them all: in the order of their floors, until the next floor is above the
    /// `k`-th cheapest cost found. Around no-fly zones most of a plan's time is pricing
    /// connections, and the far candidates rarely make the cut. Returns every connection
    /// priced, with its cost.
    fn cheapest(&self, u: usize, near: &[usize], k: usize) -> Vec<(usize, f64)> {
        let mut by_floor: Vec<(f64, usize, bool)> = near
            .iter()
            .map(|&v| {
                let (floor, exact) = self.connection_floor(u, v);
                (self.priced(u, v, floor), v, exact)
            })
            .collect();
        by_floor.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut priced: Vec<(usize, f64)> = Vec::with_capacity(near.len());
        let mut costs: Vec<f64> = Vec::with_capacity(near.len());
        for (floor, v, exact) in by_floor {
            if costs.len() >= k && costs[k - 1] < floor {
                break;
            }
            let c = if exact { floor } else { self.priced(u, v, self.connection(u, v)) };
            costs.insert(costs.partition_point(|&x| x <= c), c);
            priced.push((v, c));
        }
        priced
    }

    /// The cost the solver sees: impossible connections get [`NO_WAY`], changes of region the
    /// surcharge when re-entries are not allowed.
    fn priced(&self, u: usize, v: usize, raw: f64) -> f64 {
        let surcharge = if !self.allow_reentry && self.lines[u / 2].region != self.lines[v / 2].region { REGION_CHANGE } else { 0.0 };
        finite(raw) + surcharge
    }

    /// The instance from all connection costs (`raw[u * n + v]`, infinite where there is no
    /// way), priced as [`Self::instance`] does.
    pub fn assemble(&self, mut raw: Vec<f64>, from_start: Option<Vec<f64>>, to_end: Option<Vec<f64>>) -> Instance<'static> {
        let n = 2 * self.lines.len();
        for (i, c) in raw.iter_mut().enumerate() {
            *c = self.priced(i / n, i % n, *c);
        }
        self.instance_with(Costs::Dense(raw), from_start, to_end)
    }

    /// The instance on `cost`, each node costing its line flown in its direction as the
    /// connections are measured: in wind a line flown upwind costs more than downwind.
    fn instance_with<'c>(&self, cost: Costs<'c>, from_start: Option<Vec<f64>>, to_end: Option<Vec<f64>>) -> Instance<'c> {
        let mut inst = line_instance(self.lines, cost, from_start, to_end, self.connector.stop());
        inst.node_cost = self.poses.iter().map(|[entry, exit]| self.connector.straight_cost(entry.coord(), exit.coord())).collect();
        inst
    }

    /// The best node sequence found and its cost (without the region-change surcharge).
    pub fn solve(&self) -> (Vec<usize>, f64) {
        let inst = self.instance();
        let seq = solve(&inst);
        let cost = self.cost_of(&inst, &seq);
        (seq, cost)
    }

    /// True when the sequence flies a connection that does not exist.
    pub fn impossible(&self, inst: &Instance, seq: &[usize]) -> bool {
        self.cost_of(inst, seq) >= NO_WAY
    }

    /// The cost of a sequence, without the region-change surcharge.
    pub fn cost_of(&self, inst: &Instance, seq: &[usize]) -> f64 {
        let changes = seq.windows(2).filter(|w| self.lines[w[0] / 2].region != self.lines[w[1] / 2].region).count();
        let surcharge = if self.allow_reentry { 0.0 } else { changes as f64 * REGION_CHANGE };
        inst.total(seq) - surcharge
    }

    /// A lower bound of `inst.total` (an instance of this problem's) over every tour. Without
    /// re-entries every tour changes region at least once per region after the first: the
    /// bound of the instance without the surcharges, plus that many.
    pub fn lower_bound(&self, inst: &Instance) -> f64 {
        if self.allow_reentry {
            return gtsp::lower_bound(inst);
        }
        let n = inst.n();
        let other_region = |u: usize, v: usize| self.lines[u / 2].region != self.lines[v / 2].region;
        let plain = Instance {
            clusters: inst.clusters.clone(),
            reverse: inst.reverse.clone(),
            cost: Costs::Dense((0..n * n).map(|i| inst.c(i / n, i % n) - if other_region(i / n, i % n) { REGION_CHANGE } else { 0.0 }).collect()),
            node_cost: inst.node_cost.clone(),
            from_start: inst.from_start.clone(),
            to_end: inst.to_end.clone(),
            candidates: None,
            stop: Stop::never(),
        };
        let mut regions: Vec<usize> = self.lines.iter().map(|l| l.region).collect();
        regions.sort_unstable();
        regions.dedup();
        gtsp::lower_bound(&plain) + regions.len().saturating_sub(1) as f64 * REGION_CHANGE
    }

    /// Flight legs of a node sequence: `(entry, exit)` poses.
    pub fn legs(&self, seq: &[usize]) -> Vec<(Pose, Pose)> {
        seq.iter().map(|&v| (self.entry(v), self.exit(v))).collect()
    }

    /// Start pose for a first leg entering at `p`, end pose for a last leg leaving at `p`.
    pub fn terminals(&self, first: Pose, last: Pose) -> (Option<Pose>, Option<Pose>) {
        (self.start.map(|s| s.towards(first.coord())), self.end.map(|e| e.from(last.coord())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::route::connect::FlightEnds;
    use crate::route::visibility::TransitPlanner;
    use crate::turn::TurnModel;
    use geo::MultiPolygon;

    /// Spec §6 vector: 6 lines × 500 m, spacing 75 m, r = 85 m, free start and end: the best
    /// order's turns sum to 1 734.6 m.
    #[test]
    fn finds_the_best_skip_order() {
        let lines: Vec<Line> = (0..6).map(|i| Line { a: Coord { x: 0.0, y: 75.0 * i as f64 }, b: Coord { x: 500.0, y: 75.0 * i as f64 }, region: 0 }).collect();
        let none = MultiPolygon(vec![]);
        let transit = TransitPlanner::new(&none, &none);
        let connector = Connector::new(TurnModel::Dubins(85.0), &transit, None);
        let problem = LineProblem::new(&lines, &connector);
        let (seq, cost) = problem.solve();
        assert_eq!(seq.len(), 6);
        assert!((cost - 3000.0 - 1734.6).abs() < 0.1, "{cost}");
        let inst = problem.instance();
        assert!(problem.lower_bound(&inst) <= cost + 1e-9);
        // every connection priced up front gives the same optimum as lazy pricing
        let n = 2 * lines.len();
        let dense = problem.assemble((0..n * n).map(|i| problem.connection(i / n, i % n)).collect(), None, None);
        assert!((dense.total(&solve(&dense)) - cost).abs() < 1e-9);
        // the standard route of seeds 003 and 004, the ATSP search on the Noon–Bean
        // transformation, finds the same turns
        let standard = crate::routing_study::noon_bean::solve(&inst, 100).expect("clusters kept together");
        assert!((problem.cost_of(&inst, &standard) - cost).abs() < 1e-6, "{}", problem.cost_of(&inst, &standard));
        // boustrophedon order for comparison: 5 bulbs of 527.5 m
        let bous: Vec<usize> = (0..6).map(|k| 2 * k + k % 2).collect();
        assert!((problem.cost_of(&inst, &bous) - 3000.0 - 2637.6).abs() < 0.1);
    }

    /// In a wind that makes a metre east cost twice one west, each line's two directions cost
    /// what they do, and three lines are flown two westward, one eastward; in a fixed wing's
    /// wind, a line flown upwind costs more metres of air than downwind.
    #[test]
    fn lines_cost_what_their_direction_costs_in_wind() {
        let lines: Vec<Line> = (0..3).map(|i| Line { a: Coord { x: 0.0, y: 10.0 * i as f64 }, b: Coord { x: 100.0, y: 10.0 * i as f64 }, region: 0 }).collect();
        let none = MultiPolygon(vec![]);
        let transit = TransitPlanner::new(&none, &none);
        let tariff = crate::wind::Tariff::sampled(|u| 1.5 + 0.5 * u.x);
        let connector = Connector::new(TurnModel::Straight, &transit, None).priced_by(Some(std::sync::Arc::new(tariff)));
        let problem = LineProblem::new(&lines, &connector);
        let inst = problem.instance();
        for k in 0..3 {
            assert!((inst.node_cost[2 * k] - 200.0).abs() < 1e-9 && (inst.node_cost[2 * k + 1] - 100.0).abs() < 1e-9, "{:?}", inst.node_cost);
        }
        let (seq, cost) = problem.solve();
        assert_eq!(seq.iter().filter(|&&v| v % 2 == 1).count(), 2, "{seq:?}");
        assert!((cost - 400.0 - 2.0 * 15.0).abs() < 1e-6, "{cost}");
        // 5 m/s from the west, 15 m/s airspeed: east at 20 m/s over the ground, west at 10
        let drift = crate::turn::trochoid::Drift { wind: Coord { x: 5.0, y: 0.0 }, airspeed: 15.0 };
        let connector = Connector::new(TurnModel::Dubins(20.0), &transit, None).in_wind(Some(drift));
        let problem = LineProblem::new(&lines, &connector);
        let inst = problem.instance();
        assert!((inst.node_cost[0] - 75.0).abs() < 1e-9 && (inst.node_cost[1] - 150.0).abs() < 1e-9, "{:?}", inst.node_cost);
    }

    /// A connection flown backwards (its twin) costs another length in wind (upwind against
    /// downwind), and with lead-ins between staggered line ends: priced lazily, each costs its
    /// own, whichever the search asks for first.
    #[test]
    fn a_connection_and_its_twin_are_priced_each_on_its_own_where_they_differ() {
        let none = MultiPolygon(vec![]);
        let transit = TransitPlanner::new(&none, &none);
        let drift = crate::turn::trochoid::Drift { wind: Coord { x: 6.0, y: 2.0 }, airspeed: 15.0 };
        let in_wind = Connector::new(TurnModel::Dubins(40.0), &transit, None).in_wind(Some(drift));
        let led_in = Connector::new(TurnModel::Dubins(40.0), &transit, None).with_ends(FlightEnds { lead_in_m: 120.0, ..FlightEnds::default() });
        for (what, connector) in [("in wind", &in_wind), ("with lead-ins", &led_in)] {
            // line ends staggered by up to 74 m
            let lines: Vec<Line> = (0..24)
                .map(|i| Line { a: Coord { x: 37.0 * (i % 3) as f64, y: 30.0 * i as f64 }, b: Coord { x: 400.0 - 37.0 * (i % 2) as f64, y: 30.0 * i as f64 }, region: 0 })
                .collect();
            let problem = LineProblem::new(&lines, connector);
            let inst = problem.instance();
            assert!(matches!(inst.cost, Costs::Lazy(_)), "more lines than are priced in advance");
            let mut differ = 0;
            for (u, v) in [(0, 2), (1, 3), (4, 9), (10, 30), (7, 40), (13, 15)] {
                let (tu, tv) = (v ^ 1, u ^ 1);
                let twin = inst.c(tu, tv);
                let cost = inst.c(u, v);
                assert!((cost - problem.connection(u, v)).abs() < 1e-9 && (twin - problem.connection(tu, tv)).abs() < 1e-9, "{what}, {u} → {v}: {cost}, twin {twin}");
                differ += usize::from((cost - twin).abs() > 1.0);
            }
            assert!(differ > 0, "{what}: no twin differs");
        }
    }

    /// Pricing candidates in the order of their floors finds the neighbours pricing them all
    /// finds, around a zone that blocks many of the connections.
    #[test]
    fn the_cheapest_connections_are_found_without_pricing_every_candidate() {
        use geo::polygon;
        // 30 lines 20 m apart, cut by a zone in the middle
        let lines: Vec<Line> = (0..30)
            .flat_map(|i| {
                let y = 20.0 * i as f64;
                [Line { a: Coord { x: 0.0, y }, b: Coord { x: 250.0, y }, region: 0 }, Line { a: Coord { x: 350.0, y }, b: Coord { x: 600.0, y }, region: 0 }]
            })
            .collect();
        let zone = MultiPolygon(vec![polygon![(x: 270., y: -50.), (x: 330., y: -50.), (x: 330., y: 650.), (x: 270., y: 650.)]]);
        let grown = MultiPolygon(vec![polygon![(x: 255., y: -65.), (x: 345., y: -65.), (x: 345., y: 665.), (x: 255., y: 665.)]]);
        let (transit, detour) = (TransitPlanner::new(&zone, &zone), TransitPlanner::new(&grown, &zone));
        let connector = Connector::new(TurnModel::Dubins(10.0), &transit, Some(&detour));
        let problem = LineProblem::new(&lines, &connector);
        let mut priced_fewer = false;
        for (u, near) in nearest_entries(&lines).iter().enumerate() {
            let mut all: Vec<(f64, usize)> = near.iter().map(|&v| (problem.priced(u, v, problem.connection(u, v)), v)).collect();
            all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let found = problem.cheapest(u, near, gtsp::NEIGHBOURS);
            let mut best: Vec<(f64, usize)> = found.iter().map(|&(v, c)| (c, v)).collect();
            best.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            assert_eq!(best[..gtsp::NEIGHBOURS], all[..gtsp::NEIGHBOURS], "exit {u}");
            priced_fewer |= found.len() < near.len();
        }
        assert!(priced_fewer, "every candidate was priced");
        // floors never exceed their connections, and those flagged exact are them: the
        // connections no zone is within reach of, and only those
        let (mut exact_seen, mut bounds_seen) = (false, false);
        for u in 0..2 * lines.len() {
            for v in (0..2 * lines.len()).filter(|v| v / 2 != u / 2) {
                let ((floor, exact), cost) = (problem.connection_floor(u, v), problem.connection(u, v));
                assert!(floor <= cost + 1e-9, "floor {floor} above {cost} from {u} to {v}");
                let zone_near = transit.any_wall_in(&connector.reach(exit(&lines, u), entry(&lines, v)));
                assert_eq!(exact, !zone_near, "from {u} to {v}");
                if exact {
                    assert_eq!(floor, cost, "from {u} to {v}");
                }
                (exact_seen, bounds_seen) = (exact_seen || exact, bounds_seen || !exact);
            }
        }
        assert!(exact_seen && bounds_seen);
    }

    #[test]
    fn the_bound_counts_the_region_changes_a_tour_without_reentries_makes() {
        // three lines in each of two fields side by side, flown without re-entries
        let lines: Vec<Line> = (0..6)
            .map(|i| Line {
                a: Coord { x: 600.0 * (i / 3) as f64, y: 75.0 * (i % 3) as f64 },
                b: Coord { x: 600.0 * (i / 3) as f64 + 400.0, y: 75.0 * (i % 3) as f64 },
                region: i / 3,
            })
            .collect();
        let none = MultiPolygon(vec![]);
        let transit = TransitPlanner::new(&none, &none);
        let connector = Connector::new(TurnModel::Dubins(85.0), &transit, None);
        let problem = LineProblem { allow_reentry: false, ..LineProblem::new(&lines, &connector) };
        let inst = problem.instance();
        let seq = solve(&inst);
        let bound = problem.lower_bound(&inst);
        assert!(bound <= inst.total(&seq) + 1e-6, "{bound} above {}", inst.total(&seq));
        assert!(bound >= REGION_CHANGE + 2400.0, "{bound} misses the region change");
    }
}
