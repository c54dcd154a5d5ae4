//! Patterns: the area flown again in further passes after the planner's own set of lines, one
//! pattern per file; the plain grid is the planner's set alone.

mod double_grid;
mod oblique;

pub(crate) use double_grid::double_grid;
pub(crate) use oblique::oblique;

use geo::Coord;

use crate::error::PlanError;
use crate::path::{FlightPath, Look, PieceKind};
use crate::planners::{PlannedPath, Problem};
use crate::turn::dubins::Pose;

/// Where `path` ends and the heading it ends in (math radians).
fn end_pose(path: &FlightPath) -> Option<(Coord, f64)> {
    let [.., a, end] = path.pieces.last()?.points[..] else { return None };
    Some((end, (end.y - a.y).atan2(end.x - a.x)))
}

/// `plan` continued by `next`, joined by the vehicle's way from where `plan` ends (in its last
/// heading) to where `next` begins; the figures measured on one set no longer hold.
fn append(plan: &mut PlannedPath, next: PlannedPath, problem: &Problem<'_>) -> Result<(), PlanError> {
    if let (Some((end, heading)), Some(piece)) = (end_pose(&plan.path), next.path.pieces.first())
        && piece.start() != end
    {
        let [s, t, ..] = piece.points[..] else { unreachable!("a piece has two points") };
        let to = Pose::at(s, (t.y - s.y).atan2(t.x - s.x));
        let points = problem.connector.path(Pose::at(end, heading), to).ok_or_else(|| PlanError::Infeasible("no clear way joins one pass of the pattern to the next".into()))?;
        plan.path.push(PieceKind::Transit, points, 0.0);
    }
    plan.path.pieces.extend(next.path.pieces);
    plan.cells += next.cells;
    (plan.swept, plan.optimality) = (None, None);
    plan.alternatives.clear();
    Ok(())
}

/// Marks every piece of `path` as flown with the camera's `look`.
fn look_with(path: &mut FlightPath, look: Look) {
    for piece in &mut path.pieces {
        piece.look = Some(look);
    }
}
