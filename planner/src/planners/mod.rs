//! Planners: each composes the stages into a complete method. Adding a planner means adding a
//! file (or, for a decomposition planner, a `CellPlanner` value) and one line in [`registry`].

pub mod auto;
pub mod cell_planner;
pub mod corridor;
pub mod e_spiral;
pub mod eg_cpp;
pub mod headland;
pub mod line_gtsp;

use geo::{Coord, MultiPolygon};
use serde::Serialize;

use super::error::PlanError;
use super::metrics::{Alternative, Optimality};
use super::params::Objective;
use super::path::{FlightPath, PieceKind};
use super::route::connect::Connector;
use super::route::line_tour::{Line, LineProblem, Terminal};
use super::route::visibility::TransitPlanner;
use super::sweep::LineLayout;
use super::turn::climb::Obstacles;
use super::vehicle::{Vehicle, VehicleKind};
use auto::Auto;
use cell_planner::{BOUSTROPHEDON, E_BF, EECD, ENERGY_AWARE, NAIVE};
use corridor::CorridorPlanner;
use e_spiral::ESpiral;
use eg_cpp::EgCpp;
use headland::{GroundSetup, HeadlandPlanner};
use line_gtsp::LineGtsp;

/// What every planner receives, in the local frame.
pub struct Problem<'a> {
    /// Area to cover: the fields minus their holes (which may be overflown) and minus the
    /// no-fly zones grown by the margin.
    pub region: &'a MultiPolygon,
    /// No-fly zones grown by the margin: sweep lines stop at their edge.
    pub keep_out: &'a MultiPolygon,
    pub transit: &'a TransitPlanner,
    /// How the vehicle flies from pose to pose: Dubins paths for a fixed-wing aircraft.
    pub connector: &'a Connector<'a>,
    pub layout: LineLayout,
    /// Fixed sweep direction (math radians), or `None` for the planner's own choice.
    pub sweep_angle: Option<f64>,
    pub start: Option<Coord>,
    pub end: Option<Coord>,
    /// Headings at the start and the end (math radians); `None`: free.
    pub start_heading: Option<f64>,
    pub end_heading: Option<f64>,
    /// Line-level routing may leave a field (or cell) and come back to it.
    pub allow_reentry: bool,
    /// Obstacles to climb over, when the mission has any.
    pub obstacles: Option<&'a Obstacles>,
    /// Metres of path one metre of sweep left unflown costs when a planner weighs headings
    /// (lines cut short to leave a fixed-wing aircraft room to turn before a no-fly zone).
    pub coverage_penalty: f64,
    pub vehicle: &'a Vehicle,
    /// What planner `auto` minimises.
    pub objective: Objective,
    /// The wind at the flight altitude, which planner `auto` weighs its planners' flights in.
    pub wind: Option<crate::wind::Wind>,
    /// A ground vehicle's headland; `None` for an aircraft.
    pub ground: Option<&'a GroundSetup>,
    /// The mission's corridors, in the local frame (their outlines are in `region`).
    pub corridors: &'a [crate::field::Corridor],
}

pub struct PlannedPath {
    pub path: FlightPath,
    /// Main sweep direction (math radians).
    pub sweep_angle: f64,
    pub cells: usize,
    /// The planner that made the path, when another one chose it (`auto`).
    pub planner: Option<&'static str>,
    /// The other planners' results, when one was chosen among several (`auto`).
    pub alternatives: Vec<Alternative>,
    /// From a search that can prove its result: whether it did.
    pub optimality: Option<Optimality>,
    /// [`crate::metrics::swept_and_strip_area`] of `path`, when the planner measured it beside
    /// its search.
    pub swept: Option<(MultiPolygon, f64)>,
    /// Pieces a sortie may end before instead of where the battery runs out (a resumed plan's:
    /// its original's sortie ends); the split that flies shorter is kept.
    pub sortie_breaks: Vec<usize>,
    /// A ground vehicle's refill trips (`payload`): what they cost.
    pub payload: Option<crate::route::refill::PayloadStats>,
}

impl PlannedPath {
    pub fn new(path: FlightPath, sweep_angle: f64, cells: usize) -> Self {
        PlannedPath { path, sweep_angle, cells, planner: None, alternatives: Vec::new(), optimality: None, swept: None, sortie_breaks: Vec::new(), payload: None }
    }
}

impl Problem<'_> {
    /// The stretch of each line the vehicle can fly (see [`Connector::turnable`]); lines with
    /// nothing left are dropped, and the coverage metric shows what that loses.
    pub fn flyable(&self, lines: impl IntoIterator<Item = Line>) -> Vec<Line> {
        lines.into_iter().filter_map(|l| self.connector.turnable(l.a, l.b).map(|(a, b)| Line { a, b, ..l })).collect()
    }

    /// Line-level routing of `lines` from this problem's start to its end.
    pub fn line_problem<'l>(&'l self, lines: &'l [Line], allow_reentry: bool) -> LineProblem<'l> {
        LineProblem {
            start: self.start.map(|at| Terminal { at, heading: self.start_heading }),
            end: self.end.map(|at| Terminal { at, heading: self.end_heading }),
            allow_reentry,
            obstacles: self.obstacles,
            ..LineProblem::new(lines, self.connector)
        }
    }
}

/// The refusal when the area leaves room for no sweep line.
fn no_sweep_lines() -> PlanError {
    PlanError::Infeasible("no sweep line fits in the area left to cover".into())
}

/// Reports progress in [0, 1]; answers `false` when the job should stop.
pub trait Progress {
    fn report(&self, fraction: f64) -> bool;
}

impl<F: Fn(f64) -> bool> Progress for F {
    fn report(&self, fraction: f64) -> bool {
        self(fraction)
    }
}

pub trait Planner: Send + Sync {
    fn id(&self) -> &'static str;
    /// What a person reads in a menu.
    fn name(&self) -> &'static str;
    fn description(&self) -> &'static str;
    /// How the planner picks the sweep direction when the user fixes none.
    fn direction_rule(&self) -> &'static str;
    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError>;
    /// True for a planner of ground vehicles (which plans nothing else, and which no other
    /// planner's vehicle can use).
    fn for_ground_vehicles(&self) -> bool {
        false
    }
    /// The kinds of vehicle this planner plans.
    fn vehicle_kinds(&self) -> &'static [VehicleKind] {
        if self.for_ground_vehicles() { &[VehicleKind::Ground] } else { &[VehicleKind::Multirotor, VehicleKind::FixedWing] }
    }
    /// The kinds of vehicle this planner is the default for, when a request names none.
    fn default_for(&self) -> &'static [VehicleKind] {
        &[]
    }
    /// Whether a fleet's parts (bands of the field, one per drone) may be planned with it.
    fn plans_fleet_parts(&self) -> bool {
        !self.for_ground_vehicles()
    }
    /// The share of the area its plans cover, at least, by the swath metric (a sweep's
    /// rectangle), on fields without no-fly zones; `None` for a method the swath metric does not
    /// measure.
    fn coverage_target(&self) -> Option<f64> {
        Some(0.99)
    }
    /// Whether it orders sweep lines one by one (its route tables grow with their square, so
    /// the request is held to [`crate::MAX_ROUTED_LINES`]-style limits before planning).
    fn orders_lines_one_by_one(&self) -> bool {
        false
    }
    /// False for a planner that flies no parallel lines, so has no line ends to place
    /// (`swath_ends`).
    fn lays_parallel_lines(&self) -> bool {
        true
    }
    /// True for a planner that flies the mission's corridors along their centre lines (and
    /// needs the mission to have some).
    fn follows_corridors(&self) -> bool {
        false
    }
    /// The request members (of `PlanParams`) this planner reads.
    fn parameters(&self) -> Vec<&'static str> {
        let line_members = ["swath_ends", "pattern"];
        COMMON_PARAMETERS.iter().copied().filter(|&name| (!line_members.contains(&name) || self.lays_parallel_lines()) && name != OBJECTIVE).collect()
    }
}

/// Every planner the service offers, in the order listed to users.
static REGISTRY: &[&dyn Planner] = &[&BOUSTROPHEDON, &NAIVE, &EECD, &ENERGY_AWARE, &E_BF, &ESpiral, &EgCpp, &LineGtsp, &Auto, &CorridorPlanner, &HeadlandPlanner];

/// Every planner the service offers.
pub fn registry() -> &'static [&'static dyn Planner] {
    REGISTRY
}

pub fn find(id: &str) -> Option<&'static dyn Planner> {
    registry().iter().copied().find(|p| p.id() == id)
}

/// The planner a request that names none gets for a vehicle of this kind.
pub fn default_for(kind: VehicleKind) -> Option<&'static dyn Planner> {
    registry().iter().copied().find(|p| p.default_for().contains(&kind))
}

/// What kind of method a planner is: what it plans, from which request members.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum MethodKind {
    /// Covers the mission's fields with sweeps (or a grid's runs, or a spiral).
    Coverage,
    /// Sees the mission's structures from viewpoints within a budget.
    Inspection,
    /// Revisits the cells of a grid over the mission's area, with several UAVs, for ever.
    Patrol,
}

/// One planner as `GET /api/v1/planners` lists it: everything a client needs to offer it.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct PlannerInfo {
    pub id: &'static str,
    /// What a person reads in a menu.
    pub name: &'static str,
    pub method: MethodKind,
    pub description: &'static str,
    /// How the planner chooses the sweep direction when `heading_deg` does not fix it.
    pub direction_rule: &'static str,
    /// The kinds of vehicle it plans.
    pub vehicle_kinds: Vec<VehicleKind>,
    /// The kinds of vehicle it is the default for, when a request names no planner.
    pub default_for: Vec<VehicleKind>,
    /// Whether a fleet's parts may be planned with it.
    pub fleets: bool,
    /// The request members it reads (members of its request's schema, which describes them):
    /// the service lists them with their descriptions.
    #[serde(skip)]
    pub parameters: Vec<&'static str>,
}

impl PlannerInfo {
    /// A coverage planner's entry.
    pub fn of(p: &dyn Planner) -> Self {
        PlannerInfo {
            id: p.id(),
            name: p.name(),
            method: MethodKind::Coverage,
            description: p.description(),
            direction_rule: p.direction_rule(),
            vehicle_kinds: p.vehicle_kinds().to_vec(),
            default_for: p.default_for().to_vec(),
            fleets: p.plans_fleet_parts(),
            parameters: p.parameters(),
        }
    }
}

/// The parameter of the planners that choose among plans (`auto`): what to minimise.
pub const OBJECTIVE: &str = "objective";

/// The request members (of `PlanParams`) every coverage planner reads; the service describes
/// each from the request's schema, so they are named here and documented once, on the member.
pub const COMMON_PARAMETERS: &[&str] = &[
    "line_spacing_m",
    "camera",
    "altitude_m",
    "gsd_cm",
    "side_overlap",
    "front_overlap",
    "heading_deg",
    "sweep_direction",
    "vehicle",
    OBJECTIVE,
    "max_sorties",
    "start",
    "end",
    "allow_reentry",
    "nfz_margin_m",
    "headland_passes",
    "headland_width_m",
    "headland_order",
    "swath_ends",
    "pattern",
    "overlap",
];

/// Appends a connection from the end of `path` to `to`, around no-fly zones when needed.
pub fn connect(path: &mut FlightPath, kind: PieceKind, from: Coord, to: Coord, transit: &TransitPlanner) -> Result<(), PlanError> {
    let points = transit
        .path(from, to)
        .ok_or_else(|| PlanError::Infeasible(format!("no path outside the no-fly zones joins ({:.1}, {:.1}) to ({:.1}, {:.1}) in the local frame", from.x, from.y, to.x, to.y)))?;
    let kind = if points.len() > 2 { PieceKind::Transit } else { kind };
    path.push(kind, points, 0.0);
    Ok(())
}
