//! `line_gtsp` (seed 004, docs/methods.md, routing §6): every sweep line of every field is a cluster of its
//! two directions, connections are Dubins paths for a fixed-wing aircraft (straight transits
//! for a multirotor), and one generalised TSP over all lines gives the order, from the start
//! pose to the end pose. With `allow_reentry` the route may leave a field and come back.
//!
//! Each field's sweep heading is searched on a 2° grid (plus its hull's edge directions),
//! keeping headings whose line count is within δ of the field's fewest (δ: every heading for
//! one field, 3 for two, 1 for more). When that makes more than 5 000 combinations, a coarser
//! grid (4°, 6°, …) is searched first, then the 2° neighbourhoods of its best five, then one
//! field's heading at a time over its whole 2° list from the best five combinations, until
//! the best stands. Combinations are evaluated in parallel, each by a quick solve: exact
//! (Held–Karp) up to ten lines, else greedy and one local search. Connection costs are computed
//! once per pair of fields and headings and kept for the whole search, and combinations are
//! taken cheapest lower bound first, skipping those whose bound exceeds the best route found;
//! around no-fly zones, one field (or fields sharing a heading) prices only the connections its
//! quick solve asks for instead. After each stage the best [`FINALISTS`] are solved in full and
//! re-ranked; the best three are refined on a 0.5° grid. Around no-fly zones, where a
//! connection a zone blocks is dear, the ranking ignores the zones, the best
//! [`FINALISTS_AROUND_ZONES`] of each stage are settled instead ([`Search::settle`]: the quick
//! route improved on connections that pass zones by their detour hops), unsettled combinations
//! are raised as the zones raised settled ones, and only the best [`FINAL_SOLVES`] are solved in
//! full on the real connections, at the end. A fixed-wing aircraft cannot fly the end of a line
//! that stops against a no-fly zone (no room to turn): each metre of sweep a heading loses that
//! way costs `coverage_penalty` metres of route, or the shortest route would be the one that
//! flies least.

use std::collections::{HashMap, HashSet};

use geo::{Area, ConvexHull, Coord, MultiPolygon};
use rayon::prelude::*;

use super::{PlannedPath, Planner, Problem, Progress, no_sweep_lines};
use crate::error::PlanError;
use crate::path::{FlightPath, PieceKind};
use crate::route::connect::Connector;
use crate::route::gtsp::{self, Instance};
use crate::route::line_tour::{Line, LineProblem};
use crate::route::visibility::TransitPlanner;
use crate::sweep::ends::end_lines;
use crate::sweep::{candidate_directions, from_sweep_frame, sweep, width_across};

pub struct LineGtsp;

/// A combination solved in full: its node sequence and its total cost.
type Solved = (Vec<usize>, f64);

/// Grid of the heading search, degrees.
const GRID_DEG: f64 = 2.0;
/// Refinement around the best combinations: ±1.5° in 0.5° steps.
const REFINE_DEG: [f64; 7] = [-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5];
const REFINED_COMBINATIONS: usize = 3;
/// A single field with more lines than this keeps headings within 2 lines of the fewest.
const ALL_HEADINGS_UP_TO_LINES: usize = 30;
/// Combinations evaluated between two progress reports (and cancellation checks).
const CHUNK: usize = 64;
/// More fields than this share one heading.
const SEPARATE_HEADINGS_UP_TO: usize = 3;
/// Above this many combinations on the 2° grid, the search starts on a coarser grid.
const MAX_COARSE_COMBINATIONS: usize = 5_000;
/// Combinations ranked best by quick solves that are solved in full at each stage.
const FINALISTS: usize = 48;
/// The same around no-fly zones, where each is settled instead ([`Search::settle`]).
const FINALISTS_AROUND_ZONES: usize = 4;
/// Combinations settled side by side: a round with one fewer takes the next in the ranking.
const SETTLED_TOGETHER: usize = 2;
/// Around no-fly zones, the settled combinations solved in full on the real connections at the
/// end of the search, each from its settled route. Until 2026-11-27 the finalists of every
/// stage were: 15–42 full solves of 0.1–0.4 s each, most of a plan's time.
const FINAL_SOLVES: usize = 2;
/// Around no-fly zones, settled combinations whose headings are all within this of an
/// unsettled one's tell what the zones add to its cost (degrees).
const NEAR_DEG: f64 = 4.0;
/// Coarse combinations whose neighbourhood is searched on the 2° grid.
const COARSE_KEPT: usize = 5;
/// After a coarse search: rounds of changing one group's heading at a time, from the best
/// few combinations.
const DESCENT_ROUNDS: usize = 4;
const DESCENT_STARTS: usize = 5;
/// With fields flown at headings of their own, combinations are solved quickly in the order of
/// the sum of each field's own quick route, and only while that sum is less than the best
/// combination's cost divided by this. On `h14_01` (two fields, 3 196 combinations) the quick
/// solves of the fields together cost 0.957–1.056 times that sum.
const SUM_OF_FIELDS_SLACK: f64 = 0.95;

impl Planner for LineGtsp {
    fn id(&self) -> &'static str {
        "line_gtsp"
    }

    fn name(&self) -> &'static str {
        "Lines in the shortest order (line GTSP)"
    }

    fn description(&self) -> &'static str {
        "Line-level generalised TSP (seed 004): every line of every field a cluster of its two directions, Dubins \
         connections for fixed-wing aircraft, one optimal route over all fields from the start pose to the end pose \
         (Held–Karp when small, iterated local search otherwise); allow_reentry lets the route leave a field and \
         come back. Built for fixed-wing survey of one to a few fields."
    }

    fn orders_lines_one_by_one(&self) -> bool {
        true
    }

    fn direction_rule(&self) -> &'static str {
        "per field, every heading on a 2° grid with a line count near the fewest, combinations searched for the shortest route, refined to 0.5°"
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        let fields: Vec<MultiPolygon> = problem.region.0.iter().map(|p| MultiPolygon(vec![p.clone()])).collect();
        let open_sky = TransitPlanner::new(&MultiPolygon(vec![]), &MultiPolygon(vec![]));
        let around_zones = problem.transit.has_walls();
        let ranking_connector = Connector::new(problem.connector.turn, &open_sky, None).in_wind_of(problem.connector).stopping_on(&problem.connector.stop());
        let search = Search {
            problem,
            fields: &fields,
            shared: fields.len() > SEPARATE_HEADINGS_UP_TO,
            ranking_connector: if around_zones { &ranking_connector } else { problem.connector },
            finalists: if around_zones { FINALISTS_AROUND_ZONES } else { FINALISTS },
        };
        // a searched heading comes with its route; a fixed one is routed here
        let (best, searched) = match problem.sweep_angle {
            Some(a) => (vec![a; fields.len()], None),
            None => {
                let (choice, seq) = search.best_choice(progress)?;
                (search.per_field(&choice), Some(seq))
            }
        };
        let lines = search.lines(&best);
        if lines.is_empty() {
            return Err(no_sweep_lines());
        }
        let route = search.route(&lines);
        let seq = searched.unwrap_or_else(|| route.solve().0);
        let path = fly_lines(&route, &seq, problem.layout.half_swath())?;
        let main = (0..fields.len()).max_by(|&a, &b| fields[a].unsigned_area().total_cmp(&fields[b].unsigned_area())).unwrap_or(0);
        Ok(PlannedPath::new(path, best.get(main).copied().unwrap_or(0.0), fields.len()))
    }
}

/// Every combination of one heading per group.
fn combinations(candidates: &[Vec<f64>]) -> Vec<Vec<f64>> {
    candidates.iter().fold(vec![Vec::new()], |acc, options| acc.iter().flat_map(|c| options.iter().map(move |&h| [c.clone(), vec![h]].concat())).collect())
}

/// The combinations that differ from `choice` in one group's heading, taken from `grid`.
fn one_group_changed(choice: &[f64], grid: &[Vec<f64>]) -> Vec<Vec<f64>> {
    (0..choice.len())
        .flat_map(|g| {
            grid[g].iter().map(move |&h| {
                let mut moved = choice.to_vec();
                moved[g] = h;
                moved
            })
        })
        .collect()
}

/// A heading per group and its cost: the solver's total of its route (with the region-change
/// surcharge when re-entries are not allowed, the same for every combination) plus the
/// penalty for the sweep it loses before no-fly zones; once settled (solved
/// exactly or by the full solver, on the real connections) the route's node sequence.
/// Around no-fly zones an unsettled combination's cost is its quick cost (on connections
/// that ignore the zones) raised as the zones raised those of settled neighbours.
struct Ranked {
    cost: f64,
    /// The quick solve's cost and node sequence, on the connections combinations are ranked on.
    quick: f64,
    quick_seq: Vec<usize>,
    choice: Vec<f64>,
    seq: Option<Vec<usize>>,
}

/// The combinations evaluated so far, best first, and every one looked at.
#[derive(Default)]
struct Ranking {
    ranked: Vec<Ranked>,
    seen: HashSet<Vec<i64>>,
}

impl Ranking {
    /// True the first time a combination is looked at. Headings are compared to the
    /// micro-degree, modulo 180°: one reached by two ways (44° − 0.5° and 42° + 1.5°, in
    /// radians) can differ in its last bits, and was ranked twice, so that both final solves
    /// went to one combination (`h11_00`).
    fn first_look(&mut self, choice: &[f64]) -> bool {
        self.seen.insert(choice.iter().map(|h| ((h.to_degrees() * 1e6).round() as i64).rem_euclid(180_000_000)).collect())
    }

    fn best_cost(&self) -> f64 {
        self.ranked.first().map_or(f64::INFINITY, |r| r.cost)
    }

    fn sort(&mut self) {
        self.ranked.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    }

    /// Each unsettled combination's cost: its quick cost times the least ratio of settled to
    /// quick cost among the settled combinations whose headings are all within [`NEAR_DEG`]
    /// of its own, or without one among all settled combinations (1 without any, never below
    /// 1). Neighbouring headings meet the zones alike (real routes round nine zones cost 3–6 %
    /// more than quick ones); without this, every combination whose quick cost was below the
    /// best real cost was settled, most of a plan's time. Headings with no settled neighbour
    /// were settled at ratio 1, before anything better was known: 42 settles on `h12_00`
    /// where 15 now give the same route.
    fn expect_as_neighbours(&mut self) {
        let settled: Vec<(Vec<f64>, f64)> = self.ranked.iter().filter(|r| r.seq.is_some() && r.cost.is_finite()).map(|r| (r.choice.clone(), (r.cost / r.quick).max(1.0))).collect();
        let apart = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| crate::geom::axial_difference(*x, *y)).fold(0.0, f64::max);
        for r in self.ranked.iter_mut().filter(|r| r.seq.is_none()) {
            let least = settled.iter().filter(|(choice, _)| apart(choice, &r.choice) <= NEAR_DEG.to_radians() + 1e-9).map(|(_, raise)| *raise).reduce(f64::min);
            r.cost = r.quick * least.or(settled.iter().map(|(_, raise)| *raise).reduce(f64::min)).unwrap_or(1.0);
        }
        self.sort();
    }

    /// The combinations around the best `keep`: each heading moved by every offset (degrees).
    fn around(&self, keep: usize, offsets: &[f64]) -> Vec<Vec<f64>> {
        self.ranked
            .iter()
            .take(keep)
            .flat_map(|r| {
                let options: Vec<Vec<f64>> = r.choice.iter().map(|&h| offsets.iter().map(|&d| (h + d.to_radians()).rem_euclid(std::f64::consts::PI)).collect()).collect();
                combinations(&options)
            })
            .collect()
    }
}

/// Lines of one field at one heading.
type Key = (usize, u64);

/// One field swept at one heading: its flyable lines, the metres of sweep cut off them to
/// leave room to turn before no-fly zones, and, where blocks are tabulated
/// ([`Search::tabulates_blocks`]), the costs from the start to each node's entry and from each
/// node's exit to the end.
struct Swept {
    lines: Vec<Line>,
    lost_m: f64,
    from_start: Option<Vec<f64>>,
    to_end: Option<Vec<f64>>,
}

/// Every field's lines at every heading looked at, and the connection costs between the lines
/// of two fields at their headings (or of one field): each computed once, whatever the other
/// fields do, and kept from one stage of the search to the next.
#[derive(Default)]
struct Tables {
    swept: HashMap<Key, Swept>,
    blocks: HashMap<(Key, Key), Vec<f64>>,
    /// With fields at headings of their own: each field's quick route cost at each heading,
    /// with free ends, plus the penalty of its lost sweep.
    alone: HashMap<Key, f64>,
}

impl Tables {
    /// Metres of sweep a combination loses to turning room before no-fly zones.
    fn lost_m(&self, combo: &[f64]) -> f64 {
        keys(combo).iter().map(|k| self.swept[k].lost_m).sum()
    }
}

fn keys(combo: &[f64]) -> Vec<Key> {
    combo.iter().enumerate().map(|(r, h)| (r, h.to_bits())).collect()
}

struct Search<'a> {
    problem: &'a Problem<'a>,
    fields: &'a [MultiPolygon],
    /// One heading shared by every field (more than a few fields: their combinations would
    /// explode); otherwise one per field.
    shared: bool,
    /// The connections combinations are ranked on. Around no-fly zones, connections that
    /// ignore them: a fixed-wing connection blocked by a zone costs a search through the
    /// zones' corners, too much for every pair of lines at every heading. The finalists are
    /// then solved on the real connections.
    ranking_connector: &'a Connector<'a>,
    /// Combinations solved in full after each stage.
    finalists: usize,
}

impl Search<'_> {
    /// The groups whose headings are chosen: every field, or all fields as one.
    fn groups(&self) -> Vec<MultiPolygon> {
        if self.shared { vec![MultiPolygon(self.fields.iter().flat_map(|f| f.0.clone()).collect())] } else { self.fields.to_vec() }
    }

    /// A heading per field from a heading per group.
    fn per_field(&self, choice: &[f64]) -> Vec<f64> {
        if self.shared { vec![choice[0]; self.fields.len()] } else { choice.to_vec() }
    }

    /// The candidate headings of every group on a grid of `step_deg`.
    fn grid(&self, step_deg: f64) -> Vec<Vec<f64>> {
        let groups = self.groups();
        groups.iter().map(|g| self.headings(g, groups.len(), step_deg)).collect()
    }

    /// The best heading per group: every combination on the 2° grid when they are few;
    /// otherwise a coarser grid first (docs/methods.md, routing §6), the 2° neighbours of its best, then one
    /// group at a time over its whole 2° list until the best combination stands. Last, 0.5°
    /// around the best three.
    fn best_choice(&self, progress: &dyn Progress) -> Result<(Vec<f64>, Vec<usize>), PlanError> {
        let mut ranking = Ranking::default();
        let tables = &mut Tables::default();
        let mut step_deg = GRID_DEG;
        let mut candidates = self.grid(step_deg);
        while candidates.iter().map(Vec::len).product::<usize>() > MAX_COARSE_COMBINATIONS && step_deg < 12.0 {
            step_deg += GRID_DEG;
            candidates = self.grid(step_deg);
        }
        self.evaluate(tables, &mut ranking, combinations(&candidates), progress, (0.1, 0.5))?;
        if step_deg > GRID_DEG {
            let reach = ((step_deg - GRID_DEG) / GRID_DEG).round() as i32;
            let offsets: Vec<f64> = (-reach..=reach).map(|j| j as f64 * GRID_DEG).collect();
            let finer = ranking.around(COARSE_KEPT, &offsets);
            self.evaluate(tables, &mut ranking, finer, progress, (0.5, 0.6))?;
            let grid = self.grid(GRID_DEG);
            for round in 0..DESCENT_ROUNDS {
                let leader = ranking.ranked.first().map(|r| r.choice.clone());
                let moves: Vec<Vec<f64>> = ranking.ranked.iter().take(DESCENT_STARTS).flat_map(|r| one_group_changed(&r.choice, &grid)).collect();
                let at = 0.6 + 0.2 * round as f64 / DESCENT_ROUNDS as f64;
                self.evaluate(tables, &mut ranking, moves, progress, (at, at + 0.2 / DESCENT_ROUNDS as f64))?;
                if ranking.ranked.first().map(|r| &r.choice) == leader.as_ref() {
                    break;
                }
            }
        }
        let refined = ranking.around(REFINED_COMBINATIONS, &REFINE_DEG);
        self.evaluate(tables, &mut ranking, refined, progress, (0.8, 0.9))?;
        self.final_route(tables, ranking)
    }

    /// The best combination and its route. Around no-fly zones the best [`FINAL_SOLVES`]
    /// settled combinations are solved in full on the real connections (in parallel), each
    /// from its settled route, and the cheapest kept.
    fn final_route(&self, tables: &Tables, ranking: Ranking) -> Result<(Vec<f64>, Vec<usize>), PlanError> {
        let mut settled = ranking.ranked.into_iter().filter(|r| r.cost.is_finite()).filter_map(|r| Some((r.choice, r.seq?)));
        if self.ranks_on_real_connections() {
            return settled.next().ok_or_else(no_sweep_lines);
        }
        let finalists: Vec<(Vec<f64>, Vec<usize>)> = settled.take(FINAL_SOLVES).collect();
        let solved: Vec<(Vec<f64>, Vec<usize>, f64)> = finalists
            .into_par_iter()
            .filter_map(|(choice, seq)| self.solve_in_full(tables, &self.per_field(&choice), Some(&seq)).map(|(full, cost)| (choice, full, cost)))
            .collect();
        if self.problem.connector.stopped() {
            return Err(PlanError::Cancelled);
        }
        let (choice, seq, _) = solved.into_iter().min_by(|a, b| a.2.total_cmp(&b.2)).ok_or_else(no_sweep_lines)?;
        Ok((choice, seq))
    }

    /// Candidate headings of one group (math radians in [0, π)).
    fn headings(&self, field: &MultiPolygon, group_count: usize, step_deg: f64) -> Vec<f64> {
        let hull: Vec<Coord> = field.convex_hull().exterior().0.clone();
        let mut grid: Vec<f64> = (0..(180.0 / step_deg).ceil() as usize).map(|k| (k as f64 * step_deg).to_radians()).collect();
        let edges: Vec<f64> = candidate_directions(&hull).into_iter().take(hull.len().saturating_sub(1)).collect();
        grid.extend(edges.iter().copied());
        let count = |h: f64| self.problem.layout.count(width_across(&hull, h));
        let fewest = grid.iter().map(|&h| count(h)).min().unwrap_or(1);
        let delta = match group_count {
            1 if fewest <= ALL_HEADINGS_UP_TO_LINES => usize::MAX,
            1 => 2,
            2 => 3,
            _ => 1,
        };
        let mut kept: Vec<f64> = grid.into_iter().filter(|&h| count(h) <= fewest.saturating_add(delta) || edges.contains(&h)).collect();
        kept.sort_by(f64::total_cmp);
        kept.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        kept
    }

    /// The flyable lines of field `region` at heading `h`, and the metres of sweep lost.
    fn field_lines(&self, region: usize, h: f64) -> (Vec<Line>, f64) {
        field_lines(self.problem, &self.fields[region], region, h)
    }

    /// The lines of every field at its heading.
    fn lines(&self, combo: &[f64]) -> Vec<Line> {
        combo.iter().enumerate().flat_map(|(region, &h)| self.field_lines(region, h).0).collect()
    }

    /// What a combination's lost sweep adds to its cost: `coverage_penalty` metres of path
    /// per metre, so that a heading does not win by leaving more of the field unflown.
    fn penalty(&self, tables: &Tables, combo: &[f64]) -> f64 {
        self.problem.coverage_penalty * tables.lost_m(combo)
    }

    fn route<'l>(&'l self, lines: &'l [Line]) -> LineProblem<'l> {
        self.problem.line_problem(lines, self.problem.allow_reentry)
    }

    /// `f` of the route of `lines` on the real connections, with caches of their own: one
    /// heading's poses are no other's, and caches kept from heading to heading grew to
    /// hundreds of MB around many zones.
    fn on_real_connections<T>(&self, lines: &[Line], f: impl FnOnce(&LineProblem) -> T) -> T {
        let connector = self.problem.connector.fresh();
        f(&LineProblem { connector: &connector, ..self.route(lines) })
    }

    /// The route of `lines` on the connections combinations are ranked on.
    fn ranking_route<'l>(&'l self, lines: &'l [Line]) -> LineProblem<'l> {
        LineProblem { connector: self.ranking_connector, ..self.route(lines) }
    }

    /// The combination (a heading per field) solved in full on the real connections, from
    /// `start` (a route of its lines) when given: its node sequence and the solver's total
    /// plus the penalty for its lost sweep.
    fn solve_in_full(&self, tables: &Tables, combo: &[f64], start: Option<&[usize]>) -> Option<Solved> {
        let solved = |inst: &Instance| {
            let seq = start.map_or_else(|| gtsp::solve(inst), |s| gtsp::solve_from(inst, s));
            let cost = inst.total(&seq) + self.penalty(tables, combo);
            (seq, cost)
        };
        if self.ranks_on_real_connections() {
            return self.on_ranking_instance(tables, combo, |_, inst| solved(inst));
        }
        let lines = self.swept_lines(tables, combo);
        (!lines.is_empty()).then(|| self.on_real_connections(&lines, |route| solved(&route.instance())))
    }

    /// Around no-fly zones, what the zones make of a combination's route, cheaply: its quick
    /// route (`seq`, found as if there were none) improved by one local search on connections
    /// that pass a zone by the hops along its detour ([`Connector::hops_only`]), and the total
    /// plus the penalty for its lost sweep. A tenth of a full solve's time; on 23 generated
    /// fields with 1–15 zones the routes of the search that settles are 0.19 % longer on
    /// average (−1.0 % to +2.1 %) than those of the search that solved every stage's best in
    /// full, in a tenth of the time at most zones.
    fn settle(&self, tables: &Tables, combo: &[f64], seq: &[usize]) -> Option<Solved> {
        let lines = self.swept_lines(tables, combo);
        (!lines.is_empty()).then(|| {
            let connector = self.problem.connector.hops_only();
            let (seq, total) = LineProblem { connector: &connector, ..self.route(&lines) }.improve(seq);
            (seq, total + self.penalty(tables, combo))
        })
    }

    fn ranks_on_real_connections(&self) -> bool {
        std::ptr::eq(self.ranking_connector, self.problem.connector)
    }

    /// Sweeps and prices (in parallel) what `combos` need and `tables` lack.
    fn tabulate(&self, tables: &mut Tables, combos: &[Vec<f64>]) {
        let mut fresh: Vec<Key> = combos.iter().flat_map(|c| keys(c)).filter(|k| !tables.swept.contains_key(k)).collect();
        fresh.sort_unstable();
        fresh.dedup();
        let swept: Vec<(Key, Swept)> = fresh
            .par_iter()
            .map(|&(r, h)| {
                // sweeping is geometry that asks no connection: a stopped plan skips it
                let (lines, lost_m) = if self.problem.connector.stopped() { (Vec::new(), 0.0) } else { self.field_lines(r, f64::from_bits(h)) };
                // the blocks' instances read these; a lazy one prices its own
                let route = self.ranking_route(&lines);
                let (from_start, to_end) = if self.tabulates_blocks() { (route.start_costs(), route.end_costs()) } else { (None, None) };
                ((r, h), Swept { lines, lost_m, from_start, to_end })
            })
            .collect();
        tables.swept.extend(swept);
        if !self.tabulates_blocks() {
            return;
        }
        let mut pairs: Vec<(Key, Key)> = combos
            .iter()
            .flat_map(|c| {
                let ks = keys(c);
                ks.iter().flat_map(|&a| ks.iter().map(move |&b| (a, b))).collect::<Vec<_>>()
            })
            .filter(|p| !tables.blocks.contains_key(p))
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        let blocks: Vec<((Key, Key), Vec<f64>)> = pairs
            .par_iter()
            .map(|&(a, b)| {
                let (la, lb) = (&tables.swept[&a].lines, &tables.swept[&b].lines);
                let lines: Vec<Line> = if a == b { la.clone() } else { la.iter().chain(lb).copied().collect() };
                let route = self.ranking_route(&lines);
                let off = if a == b { 0 } else { 2 * la.len() };
                let costs = (0..2 * la.len()).flat_map(|u| (0..2 * lb.len()).map(move |v| (u, v))).map(|(u, v)| route.connection(u, off + v)).collect();
                ((a, b), costs)
            })
            .collect();
        tables.blocks.extend(blocks);
        if !self.separate_fields() {
            return;
        }
        let fresh: Vec<Key> = tables.swept.keys().filter(|k| !tables.alone.contains_key(k)).copied().collect();
        let alone: Vec<(Key, f64)> = fresh
            .par_iter()
            .map(|&k| {
                // free ends: the legs from the start and to the end are flown once, not per field
                let quick = self.instance_of(tables, &[k]).map_or(0.0, |(_, inst)| {
                    let inst = Instance { from_start: None, to_end: None, ..inst };
                    inst.total(&gtsp::quick(&inst))
                });
                (k, quick + self.problem.coverage_penalty * tables.swept[&k].lost_m)
            })
            .collect();
        tables.alone.extend(alone);
    }

    /// Several fields, each at a heading of its own.
    fn separate_fields(&self) -> bool {
        !self.shared && self.fields.len() > 1
    }

    /// With several fields flown at headings of their own, combinations share the connections
    /// between two fields at their headings: those are tabulated once. So are all in open sky,
    /// where the lower bounds they give skip most quick solves (at 0 holes the multirotor bench
    /// took 190 ms without them, 147 ms with). Otherwise, around no-fly zones, no combination
    /// shares another's connections and each is priced lazily, only what its quick solve asks
    /// for: tabulating took 0.26 s of `h15_00`'s 1.0 s.
    fn tabulates_blocks(&self) -> bool {
        self.separate_fields() || self.ranks_on_real_connections()
    }

    /// The lines of a combination, from the tables.
    fn swept_lines(&self, tables: &Tables, combo: &[f64]) -> Vec<Line> {
        keys(combo).iter().flat_map(|k| tables.swept[k].lines.iter().copied()).collect()
    }

    /// `f` of a combination's route and instance on the connections combinations are ranked
    /// on, `None` without lines: assembled from the tables' blocks, or priced lazily.
    fn on_ranking_instance<T>(&self, tables: &Tables, combo: &[f64], f: impl FnOnce(&LineProblem, &Instance) -> T) -> Option<T> {
        if self.tabulates_blocks() {
            let (lines, inst) = self.instance(tables, combo)?;
            return Some(f(&self.ranking_route(&lines), &inst));
        }
        let lines = self.swept_lines(tables, combo);
        if lines.is_empty() {
            return None;
        }
        let route = self.ranking_route(&lines);
        let inst = route.instance();
        Some(f(&route, &inst))
    }

    /// The lines and the instance of a combination (a heading per field), assembled from the
    /// tables; `None` without lines.
    fn instance(&self, tables: &Tables, combo: &[f64]) -> Option<(Vec<Line>, Instance<'static>)> {
        self.instance_of(tables, &keys(combo))
    }

    /// [`Self::instance`] of the fields at these keys.
    fn instance_of(&self, tables: &Tables, keys: &[Key]) -> Option<(Vec<Line>, Instance<'static>)> {
        let lines: Vec<Line> = keys.iter().flat_map(|k| tables.swept[k].lines.iter().copied()).collect();
        if lines.is_empty() {
            return None;
        }
        let n = 2 * lines.len();
        let mut raw = vec![f64::INFINITY; n * n];
        let mut row0 = 0;
        for a in keys {
            let na = 2 * tables.swept[a].lines.len();
            let mut col0 = 0;
            for b in keys {
                let nb = 2 * tables.swept[b].lines.len();
                let block = &tables.blocks[&(*a, *b)];
                for u in 0..na {
                    raw[(row0 + u) * n + col0..(row0 + u) * n + col0 + nb].copy_from_slice(&block[u * nb..(u + 1) * nb]);
                }
                col0 += nb;
            }
            row0 += na;
        }
        let concat = |pick: fn(&Swept) -> &Option<Vec<f64>>| -> Option<Vec<f64>> {
            keys.iter().map(|k| pick(&tables.swept[k]).clone()).collect::<Option<Vec<Vec<f64>>>>().map(|v| v.concat())
        };
        let inst = self.ranking_route(&lines).assemble(raw, concat(|s| &s.from_start), concat(|s| &s.to_end));
        Some((lines, inst))
    }

    /// Ranks the `choices` not seen before (a heading per group): least reach first (a lower
    /// bound, or with fields at headings of their own what the sum of the fields alone leaves
    /// plausible, [`SUM_OF_FIELDS_SLACK`]), each solved quickly unless its reach exceeds the
    /// best route found, in parallel chunks so that cancellation is honoured. Then the best
    /// [`FINALISTS`] not yet settled are solved in full before the ranking picks anything.
    fn evaluate(&self, tables: &mut Tables, ranking: &mut Ranking, choices: Vec<Vec<f64>>, progress: &dyn Progress, (from, to): (f64, f64)) -> Result<(), PlanError> {
        if self.problem.connector.stopped() {
            return Err(PlanError::Cancelled);
        }
        let fresh: Vec<Vec<f64>> = choices.into_iter().filter(|c| ranking.first_look(c)).collect();
        let combos: Vec<Vec<f64>> = fresh.iter().map(|c| self.per_field(c)).collect();
        self.tabulate(tables, &combos);
        let tables = &*tables;
        let mut reach: Vec<(f64, usize)> = combos
            .par_iter()
            .enumerate()
            .map(|(i, combo)| {
                let bound = if self.problem.connector.stopped() {
                    None
                } else if self.tabulates_blocks() {
                    self.instance(tables, combo).map(|(lines, inst)| self.ranking_route(&lines).lower_bound(&inst))
                } else {
                    // a bound asks for every connection: there is no block to read it from
                    keys(combo).iter().any(|k| !tables.swept[k].lines.is_empty()).then_some(0.0)
                };
                let fields_alone = if self.separate_fields() { SUM_OF_FIELDS_SLACK * keys(combo).iter().map(|k| tables.alone[k]).sum::<f64>() } else { 0.0 };
                (bound.map_or(f64::INFINITY, |b| fields_alone.max(b + self.penalty(tables, combo))), i)
            })
            .collect();
        reach.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut best = ranking.best_cost();
        // an exact solve on the real connections settles the combination
        let real = self.ranks_on_real_connections();
        for (k, chunk) in reach.chunks(CHUNK).enumerate() {
            if chunk[0].0 >= best || !chunk[0].0.is_finite() {
                break;
            }
            let costs: Vec<(f64, Vec<usize>, bool, usize)> = chunk
                .par_iter()
                .filter(|(reach, _)| *reach < best && !self.problem.connector.stopped())
                .filter_map(|&(_, i)| {
                    let (seq, total, exact) = self.on_ranking_instance(tables, &combos[i], |_, inst| {
                        let seq = gtsp::quick(inst);
                        let total = inst.total(&seq);
                        (seq, total, gtsp::quick_is_exact(inst))
                    })?;
                    Some((total + self.penalty(tables, &combos[i]), seq, real && exact, i))
                })
                .collect();
            for (cost, quick_seq, exact, i) in costs {
                best = best.min(cost);
                let seq = exact.then(|| quick_seq.clone());
                ranking.ranked.push(Ranked { cost, quick: cost, quick_seq, choice: fresh[i].clone(), seq });
            }
            if !progress.report(from + (to - from) * ((k + 1) * CHUNK) as f64 / reach.len() as f64) {
                return Err(PlanError::Cancelled);
            }
        }
        let expect = |ranking: &mut Ranking| if real { ranking.sort() } else { ranking.expect_as_neighbours() };
        expect(ranking);
        // real costs may exceed ranking costs: settle again while an unsettled combination
        // reaches the top
        loop {
            let unsettled = |i: &usize| ranking.ranked[*i].seq.is_none();
            let mut open: Vec<usize> = (0..ranking.ranked.len().min(self.finalists)).filter(unsettled).collect();
            if open.is_empty() {
                break;
            }
            // settled in pairs: a round of an odd count also settles the next combination in the
            // ranking, on the core it would leave idle (a fixed pair, so that the route does
            // not depend on the machine's cores)
            let spare = open.len() % SETTLED_TOGETHER;
            open.extend((self.finalists..ranking.ranked.len()).filter(|&i| unsettled(&i) && ranking.ranked[i].cost.is_finite()).take(spare));
            let open: Vec<(usize, Vec<f64>)> = open.into_iter().map(|i| (i, self.per_field(&ranking.ranked[i].choice))).collect();
            if self.problem.connector.stopped() {
                return Err(PlanError::Cancelled);
            }
            let solved: Vec<(usize, Option<Solved>)> = open
                .into_par_iter()
                .map(|(i, combo)| (i, if real { self.solve_in_full(tables, &combo, None) } else { self.settle(tables, &combo, &ranking.ranked[i].quick_seq) }))
                .collect();
            for (i, result) in solved {
                let (seq, cost) = result.unwrap_or((Vec::new(), f64::INFINITY));
                ranking.ranked[i].cost = cost;
                ranking.ranked[i].seq = Some(seq);
            }
            expect(ranking);
        }
        Ok(())
    }
}

/// The flyable lines of `field` (numbered `region`) swept whole at heading `h`, and the metres
/// of sweep lost to turning room before no-fly zones (lines cut short or dropped).
pub fn field_lines(problem: &Problem<'_>, field: &MultiPolygon, region: usize, h: f64) -> (Vec<Line>, f64) {
    let mut pattern = sweep(field, problem.keep_out, h, problem.layout);
    end_lines(&mut pattern, field, problem.layout.ends, field.unsigned_area());
    let whole: Vec<Line> =
        pattern.lines.iter().flatten().chain(&pattern.gap_fills).map(|s| Line { a: from_sweep_frame(h, s.a, s.offset), b: from_sweep_frame(h, s.b, s.offset), region }).collect();
    let flown = problem.flyable(whole.iter().copied());
    let metres = |lines: &[Line]| lines.iter().map(Line::length).sum::<f64>();
    let lost_m = (metres(&whole) - metres(&flown)).max(0.0);
    (flown, lost_m)
}

/// The flight along a node sequence of `route`: connections from the start, between lines
/// (turns inside a region, transits between regions) and to the end.
pub fn fly_lines(route: &LineProblem<'_>, seq: &[usize], half_swath: f64) -> Result<FlightPath, PlanError> {
    let legs = route.legs(seq);
    let mut path = FlightPath::default();
    let Some((&(first, _), &(_, last))) = legs.first().zip(legs.last()) else { return Ok(path) };
    let (start, end) = route.terminals(first, last);
    let join = |path: &mut FlightPath, kind: PieceKind, from: crate::turn::dubins::Pose, to: crate::turn::dubins::Pose| -> Result<(), PlanError> {
        let points = route.connector.path(from, to).ok_or_else(|| {
            PlanError::Infeasible(format!(
                "no flyable way outside the no-fly zones from ({:.0}, {:.0}) to ({:.0}, {:.0}) in the local frame: the turning radius is too large for the space around them",
                from.x, from.y, to.x, to.y
            ))
        })?;
        path.push(kind, points, 0.0);
        Ok(())
    };
    if let Some(s) = start {
        join(&mut path, PieceKind::Transit, s, first)?;
    }
    for (i, &(entry, exit)) in legs.iter().enumerate() {
        if i > 0 {
            let same_region = route.lines[seq[i - 1] / 2].region == route.lines[seq[i] / 2].region;
            join(&mut path, if same_region { PieceKind::Turn } else { PieceKind::Transit }, legs[i - 1].1, entry)?;
        }
        path.push(PieceKind::Sweep, vec![entry.coord(), exit.coord()], half_swath);
    }
    if let Some(e) = end {
        join(&mut path, PieceKind::Transit, last, e)?;
    }
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ranked(deg: f64, cost: f64, quick: f64, settled: bool) -> Ranked {
        Ranked { cost, quick, quick_seq: Vec::new(), choice: vec![deg.to_radians()], seq: settled.then(Vec::new) }
    }

    #[test]
    fn unsettled_headings_are_raised_as_their_settled_neighbours_were() {
        // settled at 1° (zones raised it 8 %), 3° (5 %) and 90° (3 %)
        let mut ranking = Ranking {
            ranked: vec![
                ranked(1.0, 1080.0, 1000.0, true),
                ranked(3.0, 1050.0, 1000.0, true),
                ranked(90.0, 1030.0, 1000.0, true),
                ranked(4.5, 990.0, 990.0, false),
                ranked(178.0, 1000.0, 1000.0, false),
                ranked(30.0, 950.0, 950.0, false),
                ranked(91.0, 980.0, 980.0, false),
            ],
            seen: HashSet::new(),
        };
        ranking.expect_as_neighbours();
        let cost = |deg: f64| ranking.ranked.iter().find(|r| (r.choice[0] - deg.to_radians()).abs() < 1e-9).unwrap().cost;
        // within 4° of both: the least raise; across 180°/0° only 1° is near
        assert!((cost(4.5) - 990.0 * 1.05).abs() < 1e-9, "{}", cost(4.5));
        assert!((cost(178.0) - 1080.0).abs() < 1e-9, "{}", cost(178.0));
        // no settled neighbour: the least raise of all
        assert!((cost(30.0) - 950.0 * 1.03).abs() < 1e-9, "{}", cost(30.0));
        assert!((cost(91.0) - 980.0 * 1.03).abs() < 1e-9, "{}", cost(91.0));
        assert!(ranking.ranked.windows(2).all(|w| w[0].cost <= w[1].cost), "sorted");
        // settled combinations the zones made cheaper raise nothing
        let mut cheaper = Ranking { ranked: vec![ranked(90.0, 900.0, 1000.0, true), ranked(30.0, 950.0, 950.0, false)], seen: HashSet::new() };
        cheaper.expect_as_neighbours();
        assert_eq!(cheaper.ranked.iter().map(|r| r.cost).collect::<Vec<_>>(), vec![900.0, 950.0]);
    }

    #[test]
    fn a_heading_refined_from_two_neighbours_is_looked_at_once() {
        let mut ranking =
            Ranking { ranked: vec![ranked(44.0, 1.0, 1.0, true), ranked(42.0, 2.0, 2.0, true), ranked(1.0, 3.0, 3.0, true), ranked(179.0, 4.0, 4.0, true)], seen: HashSet::new() };
        let around = ranking.around(4, &REFINE_DEG);
        assert_eq!(around.len(), 4 * REFINE_DEG.len());
        let looked: Vec<f64> = around.into_iter().filter(|c| ranking.first_look(c)).map(|c| c[0].to_degrees()).collect();
        // 40.5°–45.5° and, across 0°/180°, 177.5°–2.5°, each once
        assert_eq!(looked.len(), 11 + 11, "{looked:?}");
        assert!(!ranking.first_look(&[43.5_f64.to_radians()]), "43.5° was looked at");
        assert!(ranking.first_look(&[46.0_f64.to_radians()]), "46° was not");
    }
}
