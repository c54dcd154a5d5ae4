//! The rule that picks the plan that covers its field for the least cost.

/// Coverage at which a plan counts as covering its field (the issue-24 rule, as the spec's
/// benchmark targets): such plans compete on cost per covered area.
pub const COVERAGE_TARGET: f64 = 0.99;

/// When no candidate reaches [`COVERAGE_TARGET`], one may cover this much less than the
/// best-covering one and still be chosen.
pub const COVERAGE_SLACK: f64 = 0.01;

/// The rule by which `auto` chooses among planners and `sweep_direction: optimal` among
/// directions: the least cost per covered share of the field (cost / coverage) among the
/// candidates that cover at least [`COVERAGE_TARGET`], or, when none does, among those within
/// [`COVERAGE_SLACK`] of the best-covering one. A cheap plan that leaves ground unflown does not
/// win, and of two plans that both cover, the one that flies less per hectare covered does.
/// Costs within 1e-9 tie, and a tie goes to the earlier candidate. `None` when there are no
/// candidates.
///
/// ```
/// use coverplan_planner::metrics::best_covering;
/// // (coverage, length): the shortest plan covers too little, the next one qualifies
/// let plans = [(0.90, 800.0), (0.995, 1000.0), (1.0, 1200.0)];
/// assert_eq!(best_covering(&plans, |p| p.0, |p| p.1), Some(1));
/// // both cover; the second costs less per covered share (1005 against 1008)
/// let close = [(0.992, 1000.0), (0.999, 1004.0)];
/// assert_eq!(best_covering(&close, |p| p.0, |p| p.1), Some(1));
/// // none covers 99 %: the best coverage within 1 % competes
/// let poor = [(0.95, 900.0), (0.97, 1000.0), (0.962, 950.0)];
/// assert_eq!(best_covering(&poor, |p| p.0, |p| p.1), Some(2));
/// assert_eq!(best_covering(&[] as &[(f64, f64)], |p| p.0, |p| p.1), None);
/// ```
pub fn best_covering<T>(candidates: &[T], coverage: impl Fn(&T) -> f64, cost: impl Fn(&T) -> f64) -> Option<usize> {
    let most = candidates.iter().map(&coverage).fold(0.0, f64::max);
    let floor = if most >= COVERAGE_TARGET { COVERAGE_TARGET } else { most * (1.0 - COVERAGE_SLACK) };
    let per_covered = |c: &T| cost(c) / coverage(c).max(1e-12);
    let mut best: Option<usize> = None;
    for (i, c) in candidates.iter().enumerate() {
        if coverage(c) >= floor && best.is_none_or(|b| per_covered(c) < per_covered(&candidates[b]) - 1e-9) {
            best = Some(i);
        }
    }
    best
}
