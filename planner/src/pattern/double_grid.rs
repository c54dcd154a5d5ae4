//! Double grid: the planner's set of lines, then the area planned again with lines across it
//! (at 90°) from where the first set ends.

use super::{append, end_pose};
use crate::error::PlanError;
use crate::planners::{PlannedPath, Planner, Problem, Progress};

/// `first_set`'s plan left where it ends, then the area planned again with lines across it
/// from there, to the problem's end.
pub(crate) fn double_grid(
    planner: &dyn Planner,
    problem: &Problem<'_>,
    first_set: &dyn Fn(&Problem<'_>) -> Result<PlannedPath, PlanError>,
    progress: &dyn Progress,
) -> Result<PlannedPath, PlanError> {
    let mut plan = first_set(&Problem { end: None, end_heading: None, ..*problem })?;
    let Some((end, heading)) = end_pose(&plan.path) else { return Ok(plan) };
    let across = (plan.sweep_angle + std::f64::consts::FRAC_PI_2).rem_euclid(std::f64::consts::PI);
    let second = planner.plan(&Problem { sweep_angle: Some(across), start: Some(end), start_heading: Some(heading), ..*problem }, progress)?;
    append(&mut plan, second, problem)?;
    Ok(plan)
}
