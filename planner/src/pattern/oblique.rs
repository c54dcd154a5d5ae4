//! Oblique: the planner's set of lines flown with the camera straight down, then four passes
//! with the gimbal pitched, each looking one way (docs/methods.md, camera §8).
//!
//! A camera pitched below the horizon images a trapezoid whose centre lies h / tan(pitch)
//! ahead of the vehicle. Each oblique pass flies the area moved that far back from where it
//! looks, so that its images centre on the area, with lines laid for the rectangle the
//! trapezoid surely holds ([`ObliqueView::footprint`]) at the overlaps asked for. All passes
//! keep the nadir set's direction: a multirotor holds the camera's heading while it flies the
//! lines both ways.

use std::f64::consts::FRAC_PI_2;

use geo::{Area, BooleanOps, Coord, Translate};

use super::{append, end_pose, look_with};
use crate::camera::ObliqueView;
use crate::error::PlanError;
use crate::path::Look;
use crate::planners::{PlannedPath, Planner, Problem, Progress};
use crate::sweep::LineLayout;

/// The nadir pass is the first; the oblique ones look along the lines, to their left, back
/// and to their right, in that order.
pub const PASSES: usize = 5;

pub(crate) fn oblique(
    planner: &dyn Planner,
    problem: &Problem<'_>,
    first_set: &dyn Fn(&Problem<'_>) -> Result<PlannedPath, PlanError>,
    view: &ObliqueView,
    progress: &dyn Progress,
) -> Result<PlannedPath, PlanError> {
    let nadir = problem.layout.footprint.expect("an oblique plan has a camera");
    let mut plan = first_set(&Problem { end: None, end_heading: None, ..*problem })?;
    let down = Look {
        pass: 1,
        gimbal_pitch_deg: -90.0,
        heading: None,
        centre_offset: Coord { x: 0.0, y: 0.0 },
        across_m: nadir.across_m,
        along_m: nadir.along_m,
        photo_spacing_m: nadir.photo_spacing_m,
    };
    look_with(&mut plan.path, down);
    let angle = plan.sweep_angle;
    for k in 0..PASSES - 1 {
        let heading = angle + k as f64 * FRAC_PI_2;
        let centre_offset = Coord { x: heading.cos(), y: heading.sin() } * view.centre_m;
        let moved = problem.region.translate(-centre_offset.x, -centre_offset.y);
        let region = if problem.keep_out.0.is_empty() { moved } else { moved.difference(problem.keep_out) };
        if region.unsigned_area() < 1.0 {
            continue;
        }
        let footprint = view.footprint(k % 2 == 1);
        let layout = LineLayout { spacing: footprint.across_m * view.line_step, footprint: Some(footprint), ..problem.layout };
        let last = k == PASSES - 2;
        let (start, start_heading) = end_pose(&plan.path).map_or((problem.start, problem.start_heading), |(c, h)| (Some(c), Some(h)));
        let pass = Problem {
            region: &region,
            layout,
            sweep_angle: Some(angle),
            start,
            start_heading,
            end: if last { problem.end } else { None },
            end_heading: if last { problem.end_heading } else { None },
            ..*problem
        };
        let mut flown = planner.plan(&pass, progress)?;
        let look = Look {
            pass: k + 2,
            gimbal_pitch_deg: view.gimbal_pitch_deg,
            heading: Some(heading),
            centre_offset,
            across_m: footprint.across_m,
            along_m: footprint.along_m,
            photo_spacing_m: footprint.photo_spacing_m,
        };
        look_with(&mut flown.path, look);
        append(&mut plan, flown, problem)?;
    }
    Ok(plan)
}
