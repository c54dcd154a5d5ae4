//! `boustrophedon`: lines in the direction that needs the fewest of them (or the given
//! heading), the boustrophedon cells they form around holes and no-fly zones, each cell flown
//! back and forth, cells in nearest-first order, transits around no-fly zones.

use super::{PlannedPath, Planner, Problem, Progress, connect};
use crate::planner::decompose::{Decomposition, boustrophedon::Boustrophedon};
use crate::planner::error::PlanError;
use crate::planner::path::{FlightPath, PieceKind};
use crate::planner::route::nearest_cell;
use crate::planner::sweep::{fewest_lines_direction, sweep};

pub struct BoustrophedonPlanner;

impl Planner for BoustrophedonPlanner {
    fn id(&self) -> &'static str {
        "boustrophedon"
    }

    fn description(&self) -> &'static str {
        "Back-and-forth lines in the direction that needs the fewest lines; the field is split into \
         boustrophedon cells around holes and no-fly zones, each flown back and forth, nearest cell \
         first, with transits that go around no-fly zones."
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        let angle = problem.sweep_angle.unwrap_or_else(|| fewest_lines_direction(problem.region, problem.spacing));
        let pattern = sweep(problem.region, problem.keep_out, angle, problem.spacing);
        if !progress.report(0.3) {
            return Err(PlanError::Cancelled);
        }
        let cells = Boustrophedon.cells(&pattern);
        if cells.is_empty() {
            return Err(PlanError::Infeasible("no sweep line fits in the area left to cover".into()));
        }
        let tour = nearest_cell::order(&cells, &pattern, problem.start, problem.end);
        if !progress.report(0.5) {
            return Err(PlanError::Cancelled);
        }
        let half = problem.spacing / 2.0;
        let mut path = FlightPath::default();
        let mut here = problem.start;
        for (k, visit) in tour.iter().enumerate() {
            for (i, (a, b)) in visit.legs(&cells[visit.cell], &pattern).into_iter().enumerate() {
                if let Some(h) = here {
                    let kind = if i == 0 { PieceKind::Transit } else { PieceKind::Turn };
                    connect(&mut path, kind, h, a, problem.transit)?;
                }
                path.push(PieceKind::Sweep, vec![a, b], half);
                here = Some(b);
            }
            if !progress.report(0.5 + 0.4 * (k + 1) as f64 / tour.len() as f64) {
                return Err(PlanError::Cancelled);
            }
        }
        if let (Some(h), Some(end)) = (here, problem.end) {
            connect(&mut path, PieceKind::Transit, h, end, problem.transit)?;
        }
        Ok(PlannedPath { path, sweep_angle: angle, cells: cells.len() })
    }
}
