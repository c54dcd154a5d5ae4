//! `line_gtsp` (seed 004, routing spec §6): every sweep line of every field is a cluster of its
//! two directions, connections are Dubins paths for a fixed-wing aircraft (straight transits
//! for a multirotor), and one generalised TSP over all lines gives the order, from the start
//! pose to the end pose. With `allow_reentry` the route may leave a field and come back.
//!
//! Each field's sweep heading is searched on a 2° grid (plus its hull's edge directions),
//! keeping headings whose line count is within δ of the field's fewest (δ: every heading for
//! one field, 3 for two, 1 for more). When that makes more than 20 000 combinations, a coarser
//! grid (4°, 6°, …) is searched first and the neighbourhoods of its best five on the 2° grid.
//! Combinations are evaluated in parallel by a quick solve (greedy and one local search),
//! cheapest lower bound first, skipping those whose bound exceeds the best route found;
//! connection costs are computed once per pair of fields and headings. After each stage the
//! best [`FINALISTS`] are solved in full and re-ranked; the best three are refined on a 0.5°
//! grid.

use std::collections::HashMap;

use geo::{Area, ConvexHull, Coord, MultiPolygon};
use rayon::prelude::*;

use super::{PlannedPath, Planner, Problem, Progress, no_sweep_lines};
use crate::error::PlanError;
use crate::path::{FlightPath, PieceKind};
use crate::route::line_tour::{Line, LineProblem};
use crate::sweep::{candidate_directions, from_sweep_frame, sweep, width_across};

pub struct LineGtsp;

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
const MAX_COARSE_COMBINATIONS: usize = 20_000;
/// Combinations ranked best by quick solves that are solved in full at each stage.
const FINALISTS: usize = 48;
/// Coarse combinations whose neighbourhood is searched on the 2° grid.
const COARSE_KEPT: usize = 5;

impl Planner for LineGtsp {
    fn id(&self) -> &'static str {
        "line_gtsp"
    }

    fn description(&self) -> &'static str {
        "Line-level generalised TSP (seed 004): every line of every field a cluster of its two directions, Dubins \
         connections for fixed-wing aircraft, one optimal route over all fields from the start pose to the end pose \
         (Held–Karp when small, iterated local search otherwise); allow_reentry lets the route leave a field and \
         come back. Built for fixed-wing survey of one to a few fields."
    }

    fn direction_rule(&self) -> &'static str {
        "per field, every heading on a 2° grid with a line count near the fewest, combinations searched for the shortest route, refined to 0.5°"
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        let fields: Vec<MultiPolygon> = problem.region.0.iter().map(|p| MultiPolygon(vec![p.clone()])).collect();
        let search = Search { problem, fields: &fields };
        // headings are chosen per group: one group per field, or one shared by all when there
        // are more than a few fields (their combinations would explode)
        let groups: Vec<MultiPolygon> = if fields.len() > SEPARATE_HEADINGS_UP_TO { vec![MultiPolygon(fields.iter().flat_map(|f| f.0.clone()).collect())] } else { fields.clone() };
        let per_field = |choice: &[f64]| -> Vec<f64> { if groups.len() == fields.len() { choice.to_vec() } else { vec![choice[0]; fields.len()] } };
        // quick solves rank the combinations (cost, group choice, solved in full?) ...
        let evaluate = |choices: Vec<Vec<f64>>, from: f64, to: f64| -> Result<Vec<(f64, Vec<f64>, bool)>, PlanError> {
            let combos: Vec<Vec<f64>> = choices.iter().map(|c| per_field(c)).collect();
            let ranked = search.evaluate(&combos, progress, from, to)?;
            // back to group choices: a shared heading is the first field's
            Ok(ranked.into_iter().map(|(c, combo)| (c, if groups.len() == fields.len() { combo } else { vec![combo[0]] }, false)).collect())
        };
        // ... and the best few are solved in full before the ranking picks anything
        let settle = |ranked: &mut Vec<(f64, Vec<f64>, bool)>| {
            let open: Vec<(usize, Vec<f64>)> = ranked.iter().enumerate().take(FINALISTS).filter(|(_, r)| !r.2).map(|(i, r)| (i, per_field(&r.1))).collect();
            let solved: Vec<(usize, f64)> = open.into_par_iter().map(|(i, combo)| (i, search.route(&search.lines(&combo)).solve().1)).collect();
            for (i, cost) in solved {
                ranked[i].0 = cost;
                ranked[i].2 = true;
            }
            ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
        };
        let best = match problem.sweep_angle {
            Some(a) => vec![a; fields.len()],
            None => {
                // many combinations: a coarser grid first (spec §6.4), its best refined on the 2° grid
                let mut step_deg = GRID_DEG;
                let headings = |step: f64| -> Vec<Vec<f64>> { groups.iter().map(|g| search.headings(g, groups.len(), step)).collect() };
                let mut candidates = headings(step_deg);
                while candidates.iter().map(Vec::len).product::<usize>() > MAX_COARSE_COMBINATIONS && step_deg < 12.0 {
                    step_deg += GRID_DEG;
                    candidates = headings(step_deg);
                }
                let mut ranked = evaluate(combinations(&candidates), 0.1, 0.5)?;
                settle(&mut ranked);
                // the 2° neighbours of the best coarse choices, then 0.5° around the best
                let reach = ((step_deg - GRID_DEG) / GRID_DEG).round() as i32;
                let grid_offsets: Vec<f64> = (-reach..=reach).map(|j| j as f64 * GRID_DEG).collect();
                for (offsets, keep, from, to) in [(grid_offsets, COARSE_KEPT, 0.5, 0.7), (REFINE_DEG.to_vec(), REFINED_COMBINATIONS, 0.7, 0.9)] {
                    if offsets.len() <= 1 {
                        continue;
                    }
                    let around = |choice: &Vec<f64>| {
                        let options: Vec<Vec<f64>> = choice.iter().map(|&h| offsets.iter().map(|&d| (h + d.to_radians()).rem_euclid(std::f64::consts::PI)).collect()).collect();
                        combinations(&options)
                    };
                    let finer: Vec<Vec<f64>> = ranked.iter().take(keep).flat_map(|(_, choice, _)| around(choice)).collect();
                    ranked.extend(evaluate(finer, from, to)?);
                    settle(&mut ranked);
                }
                let (_, choice, _) = ranked.into_iter().next().ok_or_else(no_sweep_lines)?;
                per_field(&choice)
            }
        };
        let lines = search.lines(&best);
        if lines.is_empty() {
            return Err(no_sweep_lines());
        }
        let route = search.route(&lines);
        let (seq, _) = route.solve();
        let path = fly_lines(&route, &seq, problem.layout.half_swath())?;
        let main = (0..fields.len()).max_by(|&a, &b| fields[a].unsigned_area().total_cmp(&fields[b].unsigned_area())).unwrap_or(0);
        Ok(PlannedPath::new(path, best.get(main).copied().unwrap_or(0.0), fields.len()))
    }
}

/// Every combination of one heading per field.
fn combinations(candidates: &[Vec<f64>]) -> Vec<Vec<f64>> {
    candidates.iter().fold(vec![Vec::new()], |acc, options| acc.iter().flat_map(|c| options.iter().map(move |&h| [c.clone(), vec![h]].concat())).collect())
}

struct Search<'a> {
    problem: &'a Problem<'a>,
    fields: &'a [MultiPolygon],
}

/// Lines of one field at one heading.
type Key = (usize, u64);

impl Search<'_> {
    /// Candidate headings of one field (math radians in [0, π)).
    fn headings(&self, field: &MultiPolygon, field_count: usize, step_deg: f64) -> Vec<f64> {
        let hull: Vec<Coord> = field.convex_hull().exterior().0.clone();
        let mut grid: Vec<f64> = (0..(180.0 / step_deg).ceil() as usize).map(|k| (k as f64 * step_deg).to_radians()).collect();
        let edges: Vec<f64> = candidate_directions(&hull).into_iter().take(hull.len().saturating_sub(1)).collect();
        grid.extend(edges.iter().copied());
        let count = |h: f64| self.problem.layout.count(width_across(&hull, h));
        let fewest = grid.iter().map(|&h| count(h)).min().unwrap_or(1);
        let delta = match field_count {
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

    /// The lines of field `region` at heading `h`.
    fn field_lines(&self, region: usize, h: f64) -> Vec<Line> {
        let pattern = sweep(&self.fields[region], self.problem.keep_out, h, self.problem.layout);
        self.problem.flyable(pattern.lines.iter().flatten().chain(&pattern.gap_fills).map(|s| Line { a: from_sweep_frame(h, s.a, s.offset), b: from_sweep_frame(h, s.b, s.offset), region }))
    }

    /// The lines of every field at its heading.
    fn lines(&self, combo: &[f64]) -> Vec<Line> {
        combo.iter().enumerate().flat_map(|(region, &h)| self.field_lines(region, h)).collect()
    }

    fn route<'l>(&'l self, lines: &'l [Line]) -> LineProblem<'l> {
        self.problem.line_problem(lines, self.problem.allow_reentry)
    }

    /// Every field's lines at every heading that `combos` use, swept once each.
    fn sweeps(&self, combos: &[Vec<f64>]) -> HashMap<Key, Vec<Line>> {
        let mut keys: Vec<Key> = combos.iter().flat_map(|c| c.iter().enumerate().map(|(r, h)| (r, h.to_bits()))).collect();
        keys.sort_unstable();
        keys.dedup();
        keys.par_iter().map(|&(r, h)| ((r, h), self.field_lines(r, f64::from_bits(h)))).collect()
    }

    /// Connection costs between the lines of two fields at their headings (or of one field),
    /// for every pair that `combos` use: each computed once, whatever the third field does.
    fn blocks(&self, combos: &[Vec<f64>], swept: &HashMap<Key, Vec<Line>>) -> HashMap<(Key, Key), Vec<f64>> {
        let mut pairs: Vec<(Key, Key)> = combos
            .iter()
            .flat_map(|c| {
                let keys: Vec<Key> = c.iter().enumerate().map(|(r, h)| (r, h.to_bits())).collect();
                keys.iter().flat_map(|&a| keys.iter().map(move |&b| (a, b))).collect::<Vec<_>>()
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
            .par_iter()
            .map(|&(a, b)| {
                let (la, lb) = (&swept[&a], &swept[&b]);
                let lines: Vec<Line> = if a == b { la.clone() } else { la.iter().chain(lb).copied().collect() };
                let route = self.route(&lines);
                let off = if a == b { 0 } else { 2 * la.len() };
                let costs = (0..2 * la.len()).flat_map(|u| (0..2 * lb.len()).map(move |v| (u, v))).map(|(u, v)| route.connection(u, off + v)).collect();
                ((a, b), costs)
            })
            .collect()
    }

    /// Costs of the combinations (lowest first; those whose lower bound exceeds the best found
    /// are dropped), evaluated in parallel chunks so that cancellation is honoured.
    fn evaluate(&self, combos: &[Vec<f64>], progress: &dyn Progress, from: f64, to: f64) -> Result<Vec<(f64, Vec<f64>)>, PlanError> {
        let swept = self.sweeps(combos);
        let blocks = self.blocks(combos, &swept);
        let terminals: HashMap<Key, (Option<Vec<f64>>, Option<Vec<f64>>)> = swept.iter().map(|(&k, lines)| {
            let route = self.route(lines);
            (k, (route.start_costs(), route.end_costs()))
        }).collect();
        // the instance of a combination, assembled from the blocks
        let instance = |combo: &[f64]| -> Option<(Vec<Line>, crate::route::gtsp::Instance)> {
            let keys: Vec<Key> = combo.iter().enumerate().map(|(r, h)| (r, h.to_bits())).collect();
            let lines: Vec<Line> = keys.iter().flat_map(|k| swept[k].iter().copied()).collect();
            if lines.is_empty() {
                return None;
            }
            let n = 2 * lines.len();
            let mut raw = vec![f64::INFINITY; n * n];
            let mut row0 = 0;
            for a in &keys {
                let na = 2 * swept[a].len();
                let mut col0 = 0;
                for b in &keys {
                    let nb = 2 * swept[b].len();
                    let block = &blocks[&(*a, *b)];
                    for u in 0..na {
                        raw[(row0 + u) * n + col0..(row0 + u) * n + col0 + nb].copy_from_slice(&block[u * nb..(u + 1) * nb]);
                    }
                    col0 += nb;
                }
                row0 += na;
            }
            let concat = |pick: fn(&(Option<Vec<f64>>, Option<Vec<f64>>)) -> &Option<Vec<f64>>| -> Option<Vec<f64>> {
                keys.iter().map(|k| pick(&terminals[k]).clone()).collect::<Option<Vec<Vec<f64>>>>().map(|v| v.concat())
            };
            let inst = self.route(&lines).assemble(raw, concat(|t| &t.0), concat(|t| &t.1));
            Some((lines, inst))
        };
        // bounds first: they order the search
        let mut bounded: Vec<(f64, usize)> = combos
            .par_iter()
            .enumerate()
            .map(|(i, combo)| match instance(combo) {
                Some((lines, inst)) => (self.route(&lines).lower_bound(&inst), i),
                None => (f64::INFINITY, i),
            })
            .collect();
        bounded.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut best = f64::INFINITY;
        let mut out = Vec::new();
        for (k, chunk) in bounded.chunks(CHUNK).enumerate() {
            if chunk[0].0 >= best || !chunk[0].0.is_finite() {
                break;
            }
            let costs: Vec<(f64, usize)> = chunk
                .par_iter()
                .filter(|(bound, _)| *bound < best)
                .filter_map(|&(_, i)| {
                    let (_, inst) = instance(&combos[i])?;
                    let seq = crate::route::gtsp::quick(&inst);
                    Some((inst.total(&seq), i))
                })
                .collect();
            for (c, i) in costs {
                best = best.min(c);
                out.push((c, combos[i].clone()));
            }
            if !progress.report(from + (to - from) * ((k + 1) * CHUNK) as f64 / bounded.len() as f64) {
                return Err(PlanError::Cancelled);
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(out)
    }
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

