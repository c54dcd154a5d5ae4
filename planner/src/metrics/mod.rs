//! Metrics stage: one measure of every plan, whichever planner made it (docs/methods.md, metrics §1–§4).
//!
//! - [`stats`]: the result schema ([`Stats`]), with the figures inspections ([`inspection`]),
//!   fleets ([`fleet`]) and ground work ([`ground`]) add to it;
//! - [`coverage`] and [`photos`]: the ground a plan covers;
//! - [`select`]: the rule that picks among plans;
//! - [`measure`]: a plan's figures from its path and estimates.

pub mod coverage;
pub mod fleet;
pub mod ground;
pub mod inspection;
pub mod measure;
pub mod photos;
pub mod select;
pub mod stats;

pub use coverage::{covered, covered_area, ground_swept, length_inside, photographed, swept, swept_and_strip_area, uncovered};
pub use fleet::{Conflict, VehicleTotals};
pub use ground::{GroundStats, ground_stats};
pub use inspection::{InspectionStats, TargetCoverage};
pub use measure::{MeasureInput, measure};
pub use photos::{Photo, photo_positions};
pub use select::{COVERAGE_SLACK, COVERAGE_TARGET, best_covering};
pub use stats::{Alternative, Optimality, OptimalityStatus, PassStats, ResumeStats, Stats, WindStats};
