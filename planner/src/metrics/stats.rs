//! The result schema every plan reports, whichever planner made it.

use serde::{Deserialize, Serialize};

use super::{Conflict, GroundStats, InspectionStats, VehicleTotals};
use crate::sortie::SortieTotals;

#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Stats {
    pub length_m: f64,
    pub sweep_length_m: f64,
    pub turn_length_m: f64,
    pub transit_length_m: f64,
    /// Flight time and energy, take-off and landing included (each sortie's).
    pub duration_s: f64,
    pub energy_j: f64,
    pub energy_wh: f64,
    /// Of `energy_j`: climbing to the flight altitude and descending from it.
    pub takeoff_landing_energy_j: f64,
    /// Flights from home and back the plan is split into (1: one battery suffices).
    pub sorties: usize,
    /// Each sortie's figures, in flight order.
    pub sortie_totals: Vec<SortieTotals>,
    /// Batteries the plan needs: with a home, the lower bound (total energy over one battery's
    /// usable energy; `sorties` says how many the split flies); without one, a battery per
    /// stretch between `battery_swap` points.
    pub batteries_needed: usize,
    /// What the caller should know about this plan (for example that it needs several batteries
    /// and has no home to return to).
    #[serde(default)]
    pub warnings: Vec<String>,
    /// The planner that made the plan (with `auto`, the one chosen).
    #[serde(default)]
    pub planner: String,
    /// With `auto`: how every other planner did.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub alternatives: Vec<Alternative>,
    /// Share of the area to cover (field − holes − no-fly zones with their margin) under the swaths.
    pub coverage_ratio: f64,
    /// Share of the area to cover inside at least one photo's footprint (with a camera).
    pub photo_coverage_ratio: Option<f64>,
    /// Swath area flown more than once, as a share of the area swept: the summed swath areas
    /// over the area of their union, minus 1 (0 = no overlap between lines).
    pub overlap_ratio: f64,
    pub area_to_cover_m2: f64,
    /// Number of turns between sweep lines, and a ground vehicle's corner manoeuvres
    /// (`ground.corner_manoeuvres`).
    pub turns: usize,
    /// Metres of the path inside a no-fly zone (must be 0).
    pub nfz_intrusion_m: f64,
    pub sweep_lines: usize,
    pub cells: usize,
    pub photos: usize,
    pub line_spacing_m: f64,
    /// Compass bearing of the sweep lines.
    pub sweep_heading_deg: f64,
    /// Area divided by spacing: the sweep length no plan can beat.
    pub lower_bound_m: f64,
    /// `lower_bound_m / length_m`.
    pub efficiency: f64,
    pub planning_time_ms: f64,
    /// Metres of sweep line flown above the survey altitude to clear obstacles (not imaged).
    #[serde(default)]
    pub lost_coverage_m: f64,
    /// From planners whose search can prove its result (`eg_cpp`): whether it did.
    pub optimality: Option<Optimality>,
    /// Fleet: from the first take-off to the last landing (battery changes not counted). The
    /// totals above add up every drone's.
    pub makespan_s: Option<f64>,
    /// Fleet: each drone's figures, in the request's order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vehicles: Vec<VehicleTotals>,
    /// Fleet: every time two drones come within 10 m horizontally and 5 m vertically of each
    /// other (empty: none do).
    pub conflicts: Option<Vec<Conflict>>,
    /// Ground vehicle: the headland and the turns.
    pub ground: Option<GroundStats>,
    /// Inspection: the weighted share of the points of interest seen.
    pub inspection_coverage: Option<f64>,
    /// Inspection: what each target shows, the budget and the search.
    pub inspection: Option<InspectionStats>,
    /// With `altitude_reference` `terrain`: the height above ground flown, the climbs.
    pub terrain: Option<crate::terrain::TerrainStats>,
    /// A resumed plan: where the flight it resumes stopped, and what was left.
    pub resume: Option<ResumeStats>,
    /// The wind the plan was made for, at the flight altitude.
    pub wind: Option<WindStats>,
    /// `[lon, lat]` where the path begins and where it ends (one vehicle's plan; a farm's
    /// schedule drives to and from them).
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub begins_at: Option<[f64; 2]>,
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub ends_at: Option<[f64; 2]>,
    /// Pattern `oblique`: each pass's camera, photos and length, the nadir pass first.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub passes: Vec<PassStats>,
}

/// One pass of an oblique plan.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct PassStats {
    /// 1 for the nadir pass, 2 to 5 for the oblique ones.
    pub pass: usize,
    /// As gimbals say it: −90 straight down.
    pub gimbal_pitch_deg: f64,
    /// Compass bearing the camera faces on an oblique pass (absent on the nadir pass, where
    /// it faces the way the vehicle flies).
    pub camera_heading_deg: Option<f64>,
    pub photos: usize,
    /// The pass's lines, its turns and its way in from the pass before, m.
    pub length_m: f64,
    pub sweep_length_m: f64,
    /// Share of the area to cover inside the ground the pass's photos surely image (for an
    /// oblique pass, the rectangle round each image's centre that its trapezoid holds).
    pub photo_coverage_ratio: f64,
}

/// The wind a plan was made for, and what planning for it saved.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct WindStats {
    /// At the flight altitude.
    pub speed_mps: f64,
    pub from_deg: f64,
    /// The plan made as in still air, flown in this wind: what the wind-aware choice was
    /// weighed against (absent where nothing was chosen: a fixed heading, a fleet, objective
    /// `length`).
    pub still_air_plan_duration_s: Option<f64>,
    pub still_air_plan_energy_j: Option<f64>,
}

/// Where a resumed plan's original flight stopped, and what it had left.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct ResumeStats {
    /// The piece of the original trajectory the flight stopped on (its `seq`), and the share
    /// of it flown.
    pub seq: usize,
    pub fraction: f64,
    /// Where the flight stopped, `[lon, lat]`.
    pub position: [f64; 2],
    /// The original's flight after the cut, m (its returns home included).
    pub original_left_m: f64,
    /// The original's sweep lines after the cut, m; this plan's `sweep_length_m` is that and
    /// the stretch flown again before the cut.
    pub original_sweep_left_m: f64,
    /// The stretch of the cut line flown again (`photos_back` trigger distances), m.
    pub overlap_m: f64,
    /// Resumed from a log: the stretches of lines before the cut flown again because the log
    /// shows them not imaged, m.
    #[serde(default)]
    pub redone_m: Option<f64>,
}

/// Whether a planner's search proved its plan the cheapest under the method's rules.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Optimality {
    pub status: OptimalityStatus,
    /// How much cheaper than this plan's search cost the best plan could still be, as a share
    /// of it (0 when proven): the search's lower bound for what it left unsearched.
    pub gap: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum OptimalityStatus {
    /// The search was complete: no cheaper plan exists under the method's rules.
    Proven,
    /// The search budget ran out first; `gap` bounds what it may have missed.
    SearchLimited,
    /// The plan's time limit came first; `gap` bounds what it may have missed.
    TimeLimited,
}

impl OptimalityStatus {
    pub fn as_str(self) -> &'static str {
        match self {
            OptimalityStatus::Proven => "proven",
            OptimalityStatus::SearchLimited => "search_limited",
            OptimalityStatus::TimeLimited => "time_limited",
        }
    }
}

/// How another planner did on the same problem.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Alternative {
    pub planner: String,
    /// Figures of its plan (without take-off and landing, the same for every planner).
    pub length_m: Option<f64>,
    pub duration_s: Option<f64>,
    pub energy_j: Option<f64>,
    pub coverage_ratio: Option<f64>,
    /// Why it made no plan.
    pub error: Option<String>,
}
