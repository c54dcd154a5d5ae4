//! A plan under a time limit, in a test binary of its own: the limit is wall-clock time, and
//! beside the other tests (run in parallel on this 2-core machine) the plan got a fraction of
//! the processors and sometimes missed it.

use coverplan_planner::metrics::OptimalityStatus;
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanParams, Stop, plan};
use serde_json::json;

/// Near its time limit EG-CPP ends the search with the best tour so far and says so: a
/// 10 × 10 grid (about 4.6 s of search here, release build) planned under a 2.4 s limit.
#[test]
fn eg_cpp_answers_within_its_time_limit_with_the_gap_it_left() {
    // a 190 m square around (10° E, 45° N)
    let (dx, dy) = (190.0 / (111_320.0 * 45f64.to_radians().cos()), 190.0 / 110_574.0);
    let area = json!({"type": "Polygon", "coordinates": [[[10.0, 45.0], [10.0 + dx, 45.0], [10.0 + dx, 45.0 + dy], [10.0, 45.0 + dy], [10.0, 45.0]]]});
    let params: PlanParams = serde_json::from_value(json!({"planner": "eg_cpp", "line_spacing_m": 20})).unwrap();
    let mission = MissionGeometry::area(&area);
    let mut profiles = builtin_profiles();
    profiles.iter_mut().for_each(|v| v.battery.energy_wh = 1e5);
    let started = std::time::Instant::now();
    let stop = Stop::until(started + std::time::Duration::from_millis(2400));
    let out = plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &stop).unwrap();
    let optimality = out.stats.optimality.unwrap();
    assert!(optimality.status == OptimalityStatus::TimeLimited && optimality.gap > 0.0 && optimality.gap < 1.0, "{optimality:?}");
    assert_eq!(out.stats.cells, 100);
    assert!(started.elapsed().as_secs_f64() < 2.4);
}
