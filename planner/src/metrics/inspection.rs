//! An inspection's figures: what each target shows, the budget and the search.

use serde::{Deserialize, Serialize};

/// An inspection's figures.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct InspectionStats {
    /// Points of interest on the targets, and how many are seen.
    pub pois: usize,
    pub pois_seen: usize,
    pub weighted_total: f64,
    pub weighted_seen: f64,
    /// Per structure and face.
    pub targets: Vec<TargetCoverage>,
    /// Viewpoints flown, and sampled in all (initial and added during the search).
    pub viewpoints: usize,
    pub viewpoints_sampled: usize,
    /// `length_m`, `time_s` or `energy_j`.
    pub budget_measure: String,
    pub budget_limit: f64,
    /// The path's cost in that measure (never above the limit).
    pub budget_used: f64,
    /// Search iterations, and why it stopped: `iterations`, `no_improvement` or `time_limit`.
    pub iterations: usize,
    pub search_end: String,
    /// The camera's fields of view and the range a point counts as seen in, as planned.
    pub fov_deg: [f64; 2],
    pub range_m: [f64; 2],
}

/// What is seen of one target: a structure's walls or roof.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct TargetCoverage {
    pub name: String,
    /// `walls` or `roof`.
    pub face: String,
    pub seen: usize,
    pub total: usize,
    pub weighted_seen: f64,
    pub weighted_total: f64,
    /// `weighted_seen / weighted_total`.
    pub coverage: f64,
}
