//! Routing kept for comparison, not used by the planners: the standard route of seeds 003 and
//! 004 (the Noon–Bean transformation of the GTSP to an asymmetric TSP, [`noon_bean`], solved
//! by [`atsp`]) and the benchmark that sets it beside the direct GTSP search of
//! [`crate::route::gtsp`] (`coverplan bench --routing`).

pub mod atsp;
pub mod noon_bean;

use std::time::Instant;

use geo::{Coord, MultiPolygon};

use crate::route::connect::Connector;
use crate::route::gtsp::{kicks, solve};
use crate::route::line_tour::{Line, LineProblem};
use crate::route::visibility::TransitPlanner;
use crate::turn::TurnModel;

/// One row of the routing benchmark.
#[derive(Debug, Clone, PartialEq)]
pub struct RoutingRun {
    pub lines: usize,
    pub cost_matrix_ms: f64,
    pub solve_ms: f64,
    /// Length of the direct search's route.
    pub length_m: f64,
    /// Length of the plain order 1, 2, 3, …
    pub boustrophedon_m: f64,
    /// Length of the Noon–Bean route (NaN when its search broke a cluster).
    pub noon_bean_m: f64,
    pub noon_bean_ms: f64,
}

/// Routes `n` parallel 1 km lines, 20 m apart, with Dubins turns of radius 50 m (so the best
/// order skips lines) and a free start and end: the direct search, the plain boustrophedon
/// order, and the Noon–Bean route with as many kicks.
pub fn parallel_lines(n: usize) -> RoutingRun {
    let none = MultiPolygon(vec![]);
    let transit = TransitPlanner::new(&none, &none);
    let connector = Connector::new(TurnModel::Dubins(50.0), &transit, None);
    let lines: Vec<Line> = (0..n).map(|i| Line { a: Coord { x: 0.0, y: 20.0 * i as f64 }, b: Coord { x: 1000.0, y: 20.0 * i as f64 }, region: 0 }).collect();
    let problem = LineProblem::new(&lines, &connector);
    let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1000.0;
    let t0 = Instant::now();
    let inst = problem.instance();
    let t1 = Instant::now();
    let seq = solve(&inst);
    let t2 = Instant::now();
    let boustrophedon: Vec<usize> = (0..n).map(|k| 2 * k + k % 2).collect();
    let t3 = Instant::now();
    let noon_bean_m = noon_bean::solve(&inst, kicks(n)).map_or(f64::NAN, |s| inst.total(&s));
    let t4 = Instant::now();
    RoutingRun {
        lines: n,
        cost_matrix_ms: ms(t0, t1),
        solve_ms: ms(t1, t2),
        length_m: inst.total(&seq),
        boustrophedon_m: inst.total(&boustrophedon),
        noon_bean_m,
        noon_bean_ms: ms(t3, t4),
    }
}
