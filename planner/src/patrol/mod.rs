//! Patrolling with several UAVs (seed 002 §4.3, `docs/methods.md`, patrolling spec): a grid
//! over the area whose cells the UAVs revisit evenly and unpredictably, each moving one cell
//! per cycle to the least-visited neighbour. NC-Drone (node counting that keeps straight on
//! when it can) and the methods it was compared with, their shared or own matrices, and the
//! Watershed, time-based, evaporation and periodic-sharing strategies.
//!
//! ```
//! use coverplan_planner::patrol::{CellGrid, Strategy, simulate};
//! let grid = CellGrid::open(20, 20);
//! let starts = [0; 4];
//! let run = simulate(&grid, &Strategy::nc_drone(), &starts, 2_000, 7, &|| false).unwrap();
//! assert_eq!(run.corners.len(), 4);
//! assert!(run.visits.iter().all(|&v| v > 0), "every cell visited in 2 000 cycles");
//! assert!(run.metrics.qmi > 0.0 && run.metrics.ntm > 0);
//! ```

mod grid;
mod metrics;
mod mission;
mod shared_cycle;
mod simulate;
mod update_rules;
mod watershed;

pub use grid::{CellGrid, MAX_CELLS};
pub use metrics::{PatrolMetrics, Visits};
pub use mission::{DESCRIPTION, PARAMETERS, PLANNER_ID, PatrolOutput, PatrolParams, PatrolStats, StrategyName, UavTotals, patrol};
pub use shared_cycle::{closed_walk, simulate_shared_cycle};
pub use simulate::{Evaporation, PatrolState, Sharing, Simulation, Strategy, TieRule, Valleys, metrics_over_seeds, next_moves, simulate};
pub use update_rules::UpdateRule;
