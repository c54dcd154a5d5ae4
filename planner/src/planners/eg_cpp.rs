//! EG-CPP (seed 002 §4.2, docs/methods.md, multirotor planners §3): a grid of photo positions over the
//! area, wavefront labels from a start cell, and a depth-first search that always moves to
//! the unvisited neighbours with the highest label, minimising an energy cost with branch
//! and bound. Every valid cell is tried as the start, corner cells first, in batches searched
//! in parallel that share the best tour found before them (the incumbent), so later starts
//! prune on it from their first move; the first incumbent is the grid's cheapest back-and-forth.
//!
//! The search cost is the additive one (docs/methods.md, energy §5): each straight run costs the
//! rest-to-rest energy of its length (the measured OEM table of seed 002), each heading change
//! 6.117 J per degree. The bound prunes with `continue`, not with the published code's
//! `return`, which dropped the remaining siblings too. The search is exponential, so it is
//! anytime: each start has a share of [`SEARCH_EXPANSIONS`]; a start cut off there keeps the
//! best tour it found, and the plan reports `optimality` `search_limited` with the gap to the
//! lower bound instead of `proven`. The budget counts expansions, not seconds, so the same
//! input gives the same plan on every machine; only a plan's time limit, when three quarters
//! of it are spent, ends the search by the clock (`time_limited`, with its gap). Grids above [`MAX_GRID_CELLS`] are refused.

use std::collections::VecDeque;
use std::time::Instant;

use geo::{Contains, Coord, Point};
use rayon::prelude::*;

use super::{PlannedPath, Planner, Problem, Progress, connect};
use crate::error::{InputError, PlanError};
use crate::geom::distance;
use crate::metrics::{Optimality, OptimalityStatus};
use crate::path::{FlightPath, PieceKind};
use crate::vehicle::VehicleKind;

pub struct EgCpp;

/// Largest grid searched (the visited set is one `u128`).
pub const MAX_GRID_CELLS: usize = 100;
/// Search nodes all start cells may expand together (about 3 s on one core here).
pub const SEARCH_EXPANSIONS: u64 = 120_000_000;
/// Start cells searched in parallel on one incumbent: fixed, so that the result does not
/// depend on the number of cores.
const STARTS_PER_BATCH: usize = 8;

/// Rest-to-rest energy of a straight run (seed 002's OEM table, docs/methods.md, energy §7): (m, J).
const REST_TO_REST: [(f64, f64); 22] = [
    (0.0, 0.0),
    (1.0, 539.4),
    (2.0, 791.6),
    (3.0, 978.9),
    (5.0, 1264.9),
    (7.0, 1487.3),
    (10.0, 1755.4),
    (15.0, 2104.1),
    (20.0, 2383.2),
    (30.0, 2830.2),
    (40.0, 3195.1),
    (50.0, 3512.9),
    (70.0, 4065.1),
    (100.0, 4778.8),
    (150.0, 5834.6),
    (200.0, 6841.6),
    (300.0, 8844.3),
    (400.0, 10846.2),
    (500.0, 12848.0),
    (700.0, 16851.5),
    (1000.0, 22856.7),
    (1086.0, 24578.2),
];
/// Beyond the table, per metre.
const REST_TO_REST_SLOPE: f64 = 20.0175;
/// No straight run costs less per metre than this: the bound on what is left.
const MIN_J_PER_M: f64 = 20.0;
/// Rotation energy per degree of heading change.
const TURN_J_PER_DEG: f64 = 6.11698;

pub fn run_energy(d: f64) -> f64 {
    let last = REST_TO_REST[REST_TO_REST.len() - 1];
    if d >= last.0 {
        return last.1 + (d - last.0) * REST_TO_REST_SLOPE;
    }
    let k = REST_TO_REST.iter().position(|&(x, _)| x > d).expect("d is inside the table");
    let ((x0, y0), (x1, y1)) = (REST_TO_REST[k - 1], REST_TO_REST[k]);
    y0 + (y1 - y0) * (d - x0) / (x1 - x0)
}

/// The eight moves: (column step, row step).
const MOVES: [(i64, i64); 8] = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)];

fn turn_energy(from: usize, to: usize) -> f64 {
    let steps = (to as i64 - from as i64).rem_euclid(8);
    steps.min(8 - steps) as f64 * 45.0 * TURN_J_PER_DEG
}

/// The valid cells and the clear moves between them.
struct Grid {
    centres: Vec<Coord>,
    rc: Vec<(i64, i64)>,
    /// (neighbour, move index, length)
    moves: Vec<Vec<(usize, usize, f64)>>,
    /// The shortest move.
    step: f64,
    /// The most moves one straight run can make: a row or column of the box, less one.
    longest_run: usize,
}

impl Grid {
    fn build(problem: &Problem<'_>) -> Result<Grid, InputError> {
        let angle = problem.sweep_angle.unwrap_or(0.0);
        let (s, c) = angle.sin_cos();
        let to_grid = |p: Coord| Coord { x: p.x * c + p.y * s, y: -p.x * s + p.y * c };
        let from_grid = |p: Coord| Coord { x: p.x * c - p.y * s, y: p.x * s + p.y * c };
        let pts: Vec<Coord> = problem.region.0.iter().flat_map(|p| p.exterior().0.iter().map(|&q| to_grid(q))).collect();
        let (lo, hi) = pts.iter().fold((Coord { x: f64::MAX, y: f64::MAX }, Coord { x: f64::MIN, y: f64::MIN }), |(lo, hi), p| {
            (Coord { x: lo.x.min(p.x), y: lo.y.min(p.y) }, Coord { x: hi.x.max(p.x), y: hi.y.max(p.y) })
        });
        let footprint = problem.layout.footprint.map_or(problem.layout.spacing, |f| f.across_m);
        // docs/methods.md, camera §4a: outer footprints flush with the box, spacing re-fitted
        let axis = |width: f64| -> (usize, f64) {
            let n = ((width - footprint).max(0.0) / problem.layout.spacing).ceil() as usize + 1;
            let spacing = if n > 1 { (width - footprint) / (n - 1) as f64 } else { 0.0 };
            (n, spacing)
        };
        let ((nc, dx), (nr, dy)) = (axis(hi.x - lo.x), axis(hi.y - lo.y));
        let too_large = |n: usize| {
            InputError::new(
                "instance_too_large",
                "/line_spacing_m",
                format!("eg_cpp searches at most {MAX_GRID_CELLS} grid cells; this area needs {n} at this spacing: widen the spacing or use boustrophedon"),
            )
        };
        if nc.saturating_mul(nr) > 64 * MAX_GRID_CELLS {
            return Err(too_large(nc.saturating_mul(nr)));
        }
        let origin = |n: usize, d: f64, lo: f64, width: f64| if n > 1 { lo + footprint / 2.0 } else { lo + width / 2.0 - d };
        let (x0, y0) = (origin(nc, dx, lo.x, hi.x - lo.x), origin(nr, dy, lo.y, hi.y - lo.y));
        let mut centres = Vec::new();
        let mut rc = Vec::new();
        for r in 0..nr {
            for col in 0..nc {
                let p = from_grid(Coord { x: x0 + col as f64 * dx, y: y0 + r as f64 * dy });
                if problem.region.contains(&Point::from(p)) {
                    centres.push(p);
                    rc.push((r as i64, col as i64));
                }
            }
        }
        if centres.len() > MAX_GRID_CELLS {
            return Err(too_large(centres.len()));
        }
        let index = |r: i64, col: i64| rc.iter().position(|&q| q == (r, col));
        let moves: Vec<Vec<(usize, usize, f64)>> = rc
            .iter()
            .enumerate()
            .map(|(i, &(r, col))| {
                MOVES
                    .iter()
                    .enumerate()
                    .filter_map(|(m, &(dc, dr))| index(r + dr, col + dc).map(|j| (j, m)))
                    .filter(|&(j, _)| problem.transit.is_clear(centres[i], centres[j]))
                    .map(|(j, m)| (j, m, distance(centres[i], centres[j])))
                    .collect()
            })
            .collect();
        let step = moves.iter().flatten().map(|&(_, _, len)| len).fold(f64::INFINITY, f64::min);
        Ok(Grid { centres, rc, moves, step: if step.is_finite() { step } else { 0.0 }, longest_run: nc.max(nr) - 1 })
    }

    /// Breadth-first distance in moves from `start`, 1 at the start; 0 where unreachable.
    fn labels(&self, start: usize) -> Vec<u32> {
        let mut label = vec![0; self.centres.len()];
        label[start] = 1;
        let mut queue = VecDeque::from([start]);
        while let Some(i) = queue.pop_front() {
            for &(j, _, _) in &self.moves[i] {
                if label[j] == 0 {
                    label[j] = label[i] + 1;
                    queue.push_back(j);
                }
            }
        }
        label
    }
}

/// Lower bounds on the cost of moves still to make, `[m]` for `m` moves: runs are at most
/// `longest_run` moves of at least `step` each, a run's energy grows with its length and is
/// concave, every new run starts with a turn of 45° or more, and continuing the current run
/// costs at least [`MIN_J_PER_M`] per metre.
struct Floors {
    rest: Vec<f64>,
}

impl Floors {
    fn new(grid: &Grid) -> Floors {
        let n = grid.centres.len();
        let longest = grid.longest_run.max(1);
        let turn = 45.0 * TURN_J_PER_DEG;
        // runs that each start with a turn
        let mut turned = vec![0.0; n];
        for m in 1..n {
            turned[m] = (1..=m.min(longest)).map(|k| turn + run_energy(k as f64 * grid.step) + turned[m - k]).fold(f64::INFINITY, f64::min);
        }
        // the first `c` moves may continue the current run
        let rest = (0..n).map(|m| (0..=m.min(longest)).map(|c| c as f64 * grid.step * MIN_J_PER_M + turned[m - c]).fold(f64::INFINITY, f64::min)).collect();
        Floors { rest }
    }
}

/// The best tour from one start cell.
struct Search<'g> {
    floors: &'g Floors,
    grid: &'g Grid,
    label: Vec<u32>,
    start: usize,
    path: Vec<usize>,
    /// The cheapest tour found, or at first the incumbent's cost: only cheaper tours count.
    best: f64,
    best_path: Vec<usize>,
    expansions: u64,
    budget: u64,
    /// Once the budget ran out: the least any tour left unsearched may cost.
    unsearched: f64,
    /// Asked every [`STOP_CHECK_EVERY`] expansions whether to end early.
    interrupt: &'g dyn Fn() -> Option<Halt>,
}

/// Expansions between two looks at the stop flag (well under a millisecond of search).
const STOP_CHECK_EVERY: u64 = 4096;

/// Why a search ended early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Halt {
    /// Its share of [`SEARCH_EXPANSIONS`] ran out: what it found stands, unproven.
    Budget,
    /// Most of the plan's time limit is spent: what it found stands, unproven.
    Time,
    /// The plan is stopping.
    Stop,
}

/// The closing flight from cell `last` (reached by `last_move`) straight back to `start`.
fn close_cost(grid: &Grid, start: usize, last: usize, last_move: Option<usize>) -> f64 {
    let (a, b) = (grid.centres[last], grid.centres[start]);
    let d = distance(a, b);
    if d == 0.0 {
        return 0.0;
    }
    let turn = last_move.map_or(0.0, |m| {
        let (dc, dr) = MOVES[m];
        let (s, c) = ((b.y - a.y) / d, (b.x - a.x) / d);
        let change = s.atan2(c) - (dr as f64).atan2(dc as f64);
        change.sin().atan2(change.cos()).abs().to_degrees() * TURN_J_PER_DEG
    });
    turn + run_energy(d)
}

/// The cost of one more move `m` of `len` after `last_move`, with the run so far `run_m` long
/// (seed 002 Eqs. 14–15: a straight continuation re-prices the whole run), and the run after it.
fn move_cost(last_move: Option<usize>, run_m: f64, m: usize, len: f64) -> (f64, f64) {
    match last_move {
        Some(prev) if prev == m => (run_energy(run_m + len) - run_energy(run_m), run_m + len),
        Some(prev) => (turn_energy(prev, m) + run_energy(len), len),
        None => (run_energy(len), len),
    }
}

/// The cost of the closed tour `order` by moves between neighbouring cells, as the search prices
/// it; `None` when two cells in a row are not joined by a clear move.
fn tour_cost(grid: &Grid, order: &[usize]) -> Option<f64> {
    let (mut cost, mut run_m, mut last_move) = (0.0, 0.0, None);
    for w in order.windows(2) {
        let &(_, m, len) = grid.moves[w[0]].iter().find(|&&(j, _, _)| j == w[1])?;
        let (delta, run) = move_cost(last_move, run_m, m, len);
        (cost, run_m, last_move) = (cost + delta, run, Some(m));
    }
    Some(cost + close_cost(grid, order[0], *order.last()?, last_move))
}

/// Back-and-forth tours of the grid, along its rows and along its columns, each from either
/// end: the first incumbent, so that the bound bites from the first start searched (the method's
/// own tours, always on to the cells farthest from the start, cannot return to it cheaply on a
/// long grid). Only those made of clear moves between neighbours.
fn back_and_forth(grid: &Grid) -> Option<Tour> {
    let mut tours = Vec::new();
    for transpose in [false, true] {
        let key = |k: usize| if transpose { (grid.rc[k].1, grid.rc[k].0) } else { grid.rc[k] };
        let mut cells: Vec<usize> = (0..grid.rc.len()).collect();
        cells.sort_by_key(|&k| key(k));
        let mut order = Vec::with_capacity(cells.len());
        for line in cells.chunk_by(|&a, &b| key(a).0 == key(b).0) {
            if key(line[0]).0 % 2 == 0 {
                order.extend(line);
            } else {
                order.extend(line.iter().rev());
            }
        }
        let reversed: Vec<usize> = order.iter().rev().copied().collect();
        tours.extend([order, reversed]);
    }
    tours.into_iter().filter_map(|t| Some((tour_cost(grid, &t)?, t))).min_by(|a, b| a.0.total_cmp(&b.0))
}

impl Search<'_> {
    /// Depth-first branch and bound.
    fn search(&mut self, visited: u128, cost: f64, run_m: f64, last_move: Option<usize>) -> Result<(), Halt> {
        self.expansions += 1;
        let n = self.grid.centres.len();
        let halt = if self.expansions > self.budget {
            Some(Halt::Budget)
        } else if self.expansions.is_multiple_of(STOP_CHECK_EVERY) {
            (self.interrupt)()
        } else {
            None
        };
        if let Some(halt) = halt {
            self.unsearched = self.unsearched.min(cost + self.floors.rest[n - self.path.len()]);
            return Err(halt);
        }
        let here = *self.path.last().expect("the path has its start");
        if self.path.len() == n {
            let total = cost + close_cost(self.grid, self.start, here, last_move);
            if total < self.best {
                self.best = total;
                self.best_path = self.path.clone();
            }
            return Ok(());
        }
        let free = |j: usize| visited & (1u128 << j) == 0;
        let top = self.grid.moves[here].iter().filter(|&&(j, _, _)| free(j)).map(|&(j, _, _)| self.label[j]).max();
        let Some(top) = top else { return Ok(()) }; // dead end
        let mut children: Vec<(f64, f64, usize, usize)> = self.grid.moves[here]
            .iter()
            .filter(|&&(j, _, _)| free(j) && self.label[j] == top)
            .map(|&(j, m, len)| {
                let (delta, run) = move_cost(last_move, run_m, m, len);
                (delta, run, j, m)
            })
            .collect();
        children.sort_by(|a, b| a.0.total_cmp(&b.0).then(self.grid.rc[a.2].cmp(&self.grid.rc[b.2])));
        let left = n - self.path.len() - 1;
        for (k, &(delta, run, j, m)) in children.iter().enumerate() {
            if cost + delta + self.floors.rest[left] >= self.best {
                continue; // not `return`: the siblings may still be cheaper
            }
            self.path.push(j);
            let r = self.search(visited | (1u128 << j), cost + delta, run, Some(m));
            self.path.pop();
            if let Err(Halt::Budget | Halt::Time) = r {
                // the siblings not tried yet are unsearched too
                let rest = children[k + 1..].iter().map(|c| cost + c.0 + self.floors.rest[left]).fold(f64::INFINITY, f64::min);
                self.unsearched = self.unsearched.min(rest);
            }
            r?;
        }
        Ok(())
    }
}

/// A tour's cost and its cells in flight order.
type Tour = (f64, Vec<usize>);

/// What the search from one start found: a tour cheaper than the incumbent it was given, and
/// when its budget or the time cut it off, the least a tour it did not search may cost.
struct FromStart {
    tour: Option<Tour>,
    unsearched: Option<f64>,
    out_of_time: bool,
}

/// The cheapest tour from `start` that costs less than `incumbent`; `None` when the plan is
/// stopping.
fn tour_from(grid: &Grid, floors: &Floors, start: usize, incumbent: f64, budget: u64, interrupt: &dyn Fn() -> Option<Halt>) -> Option<FromStart> {
    let mut s = Search {
        floors,
        grid,
        label: grid.labels(start),
        start,
        path: vec![start],
        best: incumbent,
        best_path: Vec::new(),
        expansions: 0,
        budget,
        unsearched: f64::INFINITY,
        interrupt,
    };
    let halt = s.search(1u128 << start, 0.0, 0.0, None).err();
    if halt == Some(Halt::Stop) {
        return None;
    }
    Some(FromStart { tour: (!s.best_path.is_empty()).then_some((s.best, s.best_path)), unsearched: halt.map(|_| s.unsearched), out_of_time: halt == Some(Halt::Time) })
}

impl Planner for EgCpp {
    fn lays_parallel_lines(&self) -> bool {
        false
    }
    /// A grid over a fleet's band often falls apart into cells no clear move joins.
    fn plans_fleet_parts(&self) -> bool {
        false
    }
    /// Its runs join photo positions at cell centres: by the swath metric each run loses half a
    /// cell at both ends, and a one-cell grid sweeps nothing.
    fn coverage_target(&self) -> Option<f64> {
        None
    }
    fn id(&self) -> &'static str {
        "eg_cpp"
    }

    fn name(&self) -> &'static str {
        "Energy-aware grid (EG-CPP)"
    }

    fn description(&self) -> &'static str {
        "Energy-aware grid coverage (seed 002 §4.2): photo positions on a grid, searched with an energy cost and \
         branch and bound from every start cell, proven optimal when the search completes (stats.optimality). \
         Multirotors; small irregular areas with no-fly zones (at most 100 cells)."
    }

    fn direction_rule(&self) -> &'static str {
        "grid aligned with east–north, or with heading_deg"
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        if problem.vehicle.kind != VehicleKind::Multirotor {
            return Err(InputError::new("planner_not_applicable", "/vehicle/kind", "eg_cpp is a multirotor planner: its tours turn on the spot").into());
        }
        let grid = Grid::build(problem)?;
        if grid.centres.is_empty() {
            return Err(super::no_sweep_lines());
        }
        let apart = grid.labels(0).iter().filter(|&&l| l == 0).count();
        if apart > 0 {
            return Err(not_one_tour(format!(
                "{apart} of the {} grid cells cannot be reached from the others by clear moves between neighbouring cells (a no-fly zone or the field's outline separates them)",
                grid.centres.len()
            )));
        }
        let from_start = |i: usize| problem.start.map_or(0.0, |s| run_energy(distance(s, grid.centres[i])));
        let n = grid.centres.len();
        // corner cells first: their tours tend to be cheap, which gives the incumbent early
        let mut starts: Vec<usize> = (0..n).collect();
        starts.sort_by_key(|&i| (grid.moves[i].len(), i));
        let budget = SEARCH_EXPANSIONS / n as u64;
        let floors = Floors::new(&grid);
        let mut best: Option<Tour> = back_and_forth(&grid).map(|(cost, order)| (cost + from_start(order[0]), order));
        // the cheapest any start cut off by its budget might still reach
        let mut floor = f64::INFINITY;
        // past three quarters of the time limit the search ends with what it has, leaving the
        // rest to fly and measure the tour
        let stop = problem.connector.stop();
        let started = Instant::now();
        let wrap_up = stop.deadline().map(|d| started + d.saturating_duration_since(started).mul_f64(0.75));
        let interrupt = || {
            if stop.requested() { Some(Halt::Stop) } else { wrap_up.filter(|&w| Instant::now() >= w).map(|_| Halt::Time) }
        };
        let mut out_of_time = false;
        for (k, batch) in starts.chunks(STARTS_PER_BATCH).enumerate() {
            if out_of_time {
                // starts never searched: any of their tours may still be the cheapest
                floor = floor.min(batch.iter().map(|&i| from_start(i) + floors.rest[n - 1]).fold(f64::INFINITY, f64::min));
                continue;
            }
            let incumbent = best.as_ref().map_or(f64::INFINITY, |b| b.0);
            let found: Vec<Option<FromStart>> = batch.par_iter().map(|&i| tour_from(&grid, &floors, i, incumbent - from_start(i), budget, &interrupt)).collect();
            for (&i, f) in batch.iter().zip(found) {
                let f = f.ok_or(PlanError::Cancelled)?;
                out_of_time |= f.out_of_time;
                if let Some(unsearched) = f.unsearched {
                    floor = floor.min(from_start(i) + unsearched);
                }
                if let Some((cost, path)) = f.tour {
                    let cost = cost + from_start(i);
                    if best.as_ref().is_none_or(|b| cost < b.0) {
                        best = Some((cost, path));
                    }
                }
            }
            if !progress.report(0.8 * (k + 1) as f64 * STARTS_PER_BATCH as f64 / n as f64) {
                return Err(PlanError::Cancelled);
            }
        }
        let Some((cost, order)) = best else {
            return Err(if floor.is_finite() {
                InputError::new(
                    "instance_too_large",
                    "/planner",
                    if out_of_time {
                        format!("eg_cpp found no tour of this {n}-cell grid within the plan's time limit: allow more time, use boustrophedon or a wider spacing")
                    } else {
                        format!("eg_cpp found no tour of this {n}-cell grid within its search budget ({SEARCH_EXPANSIONS} expansions): use boustrophedon or a wider spacing")
                    },
                )
                .into()
            } else {
                not_one_tour(format!("no tour visits each of the {n} grid cells once under the method's rule (always on to the neighbours farthest from the start)"))
            });
        };
        let optimality = if out_of_time {
            Optimality { status: OptimalityStatus::TimeLimited, gap: ((cost - floor) / cost).max(0.0) }
        } else if floor < cost {
            Optimality { status: OptimalityStatus::SearchLimited, gap: (cost - floor) / cost }
        } else {
            Optimality { status: OptimalityStatus::Proven, gap: 0.0 }
        };
        let mut planned = PlannedPath::new(fly(&grid, &order, problem)?, problem.sweep_angle.unwrap_or(0.0), n);
        planned.optimality = Some(optimality);
        Ok(planned)
    }
}

/// EG-CPP flies one tour of the whole grid; `why` there is none.
fn not_one_tour(why: String) -> PlanError {
    InputError::new("planner_not_applicable", "/no_fly_zones", format!("eg_cpp cannot plan this field: {why}; use boustrophedon or line_gtsp")).into()
}

/// The tour as straight runs between corners, closed back to its first cell.
fn fly(grid: &Grid, order: &[usize], problem: &Problem<'_>) -> Result<FlightPath, PlanError> {
    let half = problem.layout.half_swath();
    let mut path = FlightPath::default();
    let first = grid.centres[order[0]];
    if let Some(s) = problem.start {
        connect(&mut path, PieceKind::Transit, s, first, problem.transit)?;
    }
    let mut run_start = first;
    for k in 1..order.len() {
        let here = grid.centres[order[k]];
        let straight_on = order.get(k + 1).is_some_and(|&next| {
            let (a, b) = (here - grid.centres[order[k - 1]], grid.centres[next] - here);
            (a.x * b.y - a.y * b.x).abs() < 1e-6 * distance(Coord::zero(), a) * distance(Coord::zero(), b) && a.x * b.x + a.y * b.y > 0.0
        });
        if !straight_on {
            path.push(PieceKind::Sweep, vec![run_start, here], half);
            run_start = here;
        }
    }
    if order.len() == 1 {
        path.push(PieceKind::Sweep, vec![first, first], half);
    }
    let last = path.end().expect("the tour has a run");
    connect(&mut path, PieceKind::Transit, last, first, problem.transit)?;
    if let Some(end) = problem.end {
        connect(&mut path, PieceKind::Transit, first, end, problem.transit)?;
    }
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `cols` × `rows` grid of cells `spacing` apart with every move clear.
    fn rectangle(cols: i64, rows: i64, spacing: f64) -> Grid {
        let rc: Vec<(i64, i64)> = (0..rows).flat_map(|r| (0..cols).map(move |c| (r, c))).collect();
        let centres: Vec<Coord> = rc.iter().map(|&(r, c)| Coord { x: c as f64 * spacing, y: r as f64 * spacing }).collect();
        let moves = rc
            .iter()
            .map(|&(r, c)| {
                MOVES
                    .iter()
                    .enumerate()
                    .filter_map(|(m, &(dc, dr))| {
                        rc.iter().position(|&q| q == (r + dr, c + dc)).map(|j| (j, m, distance(centres[rc.iter().position(|&q| q == (r, c)).unwrap()], centres[j])))
                    })
                    .collect()
            })
            .collect();
        Grid { centres, rc, moves, step: spacing, longest_run: (cols.max(rows) - 1) as usize }
    }

    /// The floors prune only what cannot win: from every start of several small grids the
    /// search with them finds tours exactly as cheap as the search that prunes on nothing.
    #[test]
    fn floors_never_prune_the_cheapest_tour() {
        for (cols, rows) in [(3, 3), (4, 3), (5, 2), (4, 4), (6, 2)] {
            let grid = rectangle(cols, rows, 20.0);
            let n = grid.centres.len();
            let floors = Floors::new(&grid);
            let none = Floors { rest: vec![0.0; n] };
            assert!(floors.rest.iter().zip(&floors.rest[1..]).all(|(a, b)| a <= b) && floors.rest[n - 1] > (n - 1) as f64 * 20.0 * MIN_J_PER_M);
            for start in 0..n {
                let cost = |f: &Floors| tour_from(&grid, f, start, f64::INFINITY, u64::MAX, &|| None).and_then(|t| t.tour).map(|t| t.0);
                let (pruned, exhaustive) = (cost(&floors), cost(&none));
                assert!(pruned.is_some() && exhaustive.is_some(), "{cols}×{rows} from {start}");
                assert!((pruned.unwrap() - exhaustive.unwrap()).abs() < 1e-6, "{cols}×{rows} from {start}: {pruned:?} vs {exhaustive:?}");
            }
        }
    }

    /// A search cut off by its budget says how much it may have missed: the least a tour it
    /// did not search may cost, never above the cheapest tour there is.
    #[test]
    fn a_cut_search_bounds_what_it_did_not_search() {
        let grid = rectangle(4, 4, 20.0);
        let floors = Floors::new(&grid);
        let optimum = tour_from(&grid, &floors, 0, f64::INFINITY, u64::MAX, &|| None).unwrap().tour.unwrap().0;
        let cut = tour_from(&grid, &floors, 0, f64::INFINITY, 40, &|| None).unwrap();
        let unsearched = cut.unsearched.expect("40 expansions do not finish a 16-cell grid");
        let found = cut.tour.map_or(f64::INFINITY, |t| t.0);
        assert!(unsearched.min(found) <= optimum + 1e-6 && unsearched > 0.0, "{unsearched} {found} {optimum}");
    }

    /// The back-and-forth incumbent visits every cell once by clear neighbour moves and is
    /// priced as the search prices tours: on a long grid, where the method's own tours end far
    /// from their start, it is the cheaper; a grid with a cell missing mid-row has none.
    #[test]
    fn a_long_grid_starts_from_a_back_and_forth_tour() {
        let grid = rectangle(25, 4, 20.0);
        let (cost, order) = back_and_forth(&grid).expect("a full rectangle has one");
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..100).collect::<Vec<_>>());
        assert_eq!(tour_cost(&grid, &order), Some(cost));
        // 4 runs of 24 moves, 3 steps between them with two 90° turns each, a 60 m flight home
        let expected = 4.0 * run_energy(480.0) + 3.0 * run_energy(20.0) + 6.0 * 90.0 * TURN_J_PER_DEG + 90.0 * TURN_J_PER_DEG + run_energy(60.0);
        assert!((cost - expected).abs() < 1e-6, "{cost} against {expected}");
        let floors = Floors::new(&grid);
        let first = tour_from(&grid, &floors, 0, f64::INFINITY, 100_000, &|| None).unwrap().tour.unwrap().0;
        assert!(cost < first, "back and forth {cost:.0} J, the method's first tour from a corner {first:.0} J");
        let mut holed = rectangle(5, 3, 20.0);
        let middle = 7; // row 1, column 2
        for m in &mut holed.moves {
            m.retain(|&(j, _, _)| j != middle);
        }
        holed.moves[middle].clear();
        assert!(back_and_forth(&holed).is_none());
    }

    #[test]
    fn run_energy_follows_the_table_and_never_undercuts_the_bound() {
        assert!((run_energy(100.0) - 4778.8).abs() < 1e-9);
        assert!((run_energy(2000.0) - (24578.2 + 914.0 * 20.0175)).abs() < 1e-6);
        // the bound of the search: every metre costs at least MIN_J_PER_M, also at the margin
        let mut d = 0.5;
        while d < 1500.0 {
            assert!(run_energy(d) >= MIN_J_PER_M * d);
            assert!(run_energy(d + 0.5) - run_energy(d) >= MIN_J_PER_M * 0.5 - 1e-9, "{d}");
            d += 0.5;
        }
        assert_eq!(turn_energy(0, 4), 180.0 * TURN_J_PER_DEG);
        assert_eq!(turn_energy(7, 1), 90.0 * TURN_J_PER_DEG);
    }
}
