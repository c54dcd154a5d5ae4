//! The real-time search update rules of the patrolling spec §2 (Koenig & Liu 2001): how the
//! cell a UAV leaves is marked, given its value and the value of the cell it moves to.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum UpdateRule {
    /// Node Counting: `u(s) + 1` (NC-Drone's rule).
    Nc,
    /// Learning Real-Time A*: `u(next) + 1`.
    Lrta,
    /// Thrun's rule: `max(u(s), u(next)) + 1`.
    Tvur,
    /// Wagner's rule: `u(s) + 1` if `u(s) ≤ u(next)`, else unchanged.
    Wvur,
}

impl UpdateRule {
    /// The new value of the cell left, `here`, for a move to a cell of value `next`.
    ///
    /// ```
    /// use coverplan_planner::patrol::UpdateRule;
    /// assert_eq!(UpdateRule::Nc.update(3.0, 1.0), 4.0);
    /// assert_eq!(UpdateRule::Lrta.update(3.0, 1.0), 2.0);
    /// assert_eq!(UpdateRule::Tvur.update(3.0, 1.0), 4.0);
    /// assert_eq!(UpdateRule::Wvur.update(3.0, 1.0), 3.0);
    /// ```
    pub fn update(self, here: f64, next: f64) -> f64 {
        match self {
            UpdateRule::Nc => here + 1.0,
            UpdateRule::Lrta => next + 1.0,
            UpdateRule::Tvur => here.max(next) + 1.0,
            UpdateRule::Wvur if here <= next => here + 1.0,
            UpdateRule::Wvur => here,
        }
    }
}
