//! A patrol of a mission's area: its parameters as the API takes them, the grid over the area
//! less the no-fly zones, the simulation, and the result as GeoJSON (one path per UAV and the
//! visits per cell) with the metrics and each path's energy by the vehicle's model.

use geo::{BoundingRect, Coord};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use super::grid::{CellGrid, MAX_CELLS};
use super::metrics::PatrolMetrics;
use super::shared_cycle::simulate_shared_cycle;
use super::simulate::{Evaporation, Sharing, Strategy, TieRule, Valleys, simulate};
use super::update_rules::UpdateRule;
use crate::camera::Camera;
use crate::energy::EnergyModel;
use crate::error::{InputError, PlanError};
use crate::field::{Field, FieldLimits, MissionGeometry};
use crate::path::{FlightPath, PieceKind};
use crate::stop::Stop;
use crate::vehicle::Vehicle;
use crate::vehicle::{VehicleKind, VehicleParams};

/// The patrol's id among the methods a client can choose (`GET /api/v1/planners`).
pub const PLANNER_ID: &str = "patrol";

/// What a patrol does, as the catalogue describes it.
pub const DESCRIPTION: &str = "Patrolling (seed 002 §4.3): several UAVs revisit the cells of a grid over the mission's area \
     evenly and unpredictably, each moving to its least-visited neighbour (NC-Drone and the strategies it was compared with); \
     `POST /api/v1/missions/{id}/patrols`.";

/// The members of [`PatrolParams`], all of which a patrol reads.
pub const PARAMETERS: &[&str] = &[
    "cell_size_m",
    "camera",
    "altitude_m",
    "gsd_cm",
    "uavs",
    "starts",
    "strategy",
    "sharing",
    "comm_radius_cells",
    "sync_interval",
    "watershed",
    "ws_period",
    "time_ties",
    "evaporation",
    "tie_rule",
    "cycles",
    "seed",
    "nfz_margin_m",
    "vehicle",
];

/// The methods of the patrolling spec §2–§3.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum StrategyName {
    Nc,
    Lrta,
    Tvur,
    Wvur,
    NcDrone,
    /// The predictable baseline: all UAVs evenly spaced on one closed walk through every cell
    /// (no randomness; sharing, Watershed, ties and evaporation do not apply).
    SharedCycle,
}

/// What a patrol is asked for.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct PatrolParams {
    /// Side of a grid cell, metres, 1 to 1 000 (default 20, or the camera's footprint).
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 1000.0))]
    pub cell_size_m: Option<f64>,
    /// The UAVs' camera, looking straight down: a cell is the square its footprint covers at
    /// `altitude_m` (or at the altitude that gives `gsd_cm`), instead of `cell_size_m`.
    pub camera: Option<Camera>,
    /// Patrol altitude above ground, with `camera`.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 5000.0))]
    pub altitude_m: Option<f64>,
    /// Wanted ground sample distance, cm per pixel, with `camera` (instead of `altitude_m`).
    #[cfg_attr(feature = "schema", schema(minimum = 0.01, maximum = 1000.0))]
    pub gsd_cm: Option<f64>,
    /// How many UAVs, 1 to 64 (default 4), all starting on the free cell nearest the area's
    /// south-west corner as in the source; or give `starts`.
    #[cfg_attr(feature = "schema", schema(minimum = 1, maximum = 64))]
    pub uavs: Option<usize>,
    /// Start positions, [longitude, latitude] each: one UAV per position.
    #[cfg_attr(feature = "schema", schema(value_type = Option<Vec<Vec<f64>>>, min_items = 1, max_items = 64))]
    pub starts: Option<Vec<[f64; 2]>>,
    /// Default `nc_drone`.
    pub strategy: Option<StrategyName>,
    /// Default `centralised`; `max`, `avg` and `multi` share between UAVs within
    /// `comm_radius_cells`; `periodic` merges every `sync_interval` cycles (CFS).
    pub sharing: Option<Sharing>,
    /// Chebyshev range of the UAVs' radios, cells (default 3).
    #[cfg_attr(feature = "schema", schema(minimum = 0, maximum = 1000))]
    pub comm_radius_cells: Option<usize>,
    /// Cycles between synchronisations with `periodic` sharing (default 100).
    #[cfg_attr(feature = "schema", schema(minimum = 1))]
    pub sync_interval: Option<u32>,
    /// Watershed (`visits`) or WSTS (`last_visit`); none by default.
    pub watershed: Option<Valleys>,
    /// Cycles between Watershed decisions with a central matrix (default 100).
    #[cfg_attr(feature = "schema", schema(minimum = 1))]
    pub ws_period: Option<u32>,
    /// TS: ties go to the least recently visited cell first.
    pub time_ties: Option<bool>,
    pub evaporation: Option<Evaporation>,
    /// Overrides the strategy's tie rule.
    pub tie_rule: Option<TieRule>,
    /// Cycles to simulate, 1 to 1 000 000 (default 10 000), and at most 2 000 000 UAV moves in all.
    #[cfg_attr(feature = "schema", schema(minimum = 1, maximum = 1_000_000))]
    pub cycles: Option<u32>,
    /// Seed of the random choices (default 0): the same seed gives the same patrol.
    pub seed: Option<u64>,
    /// Clearance around no-fly zones, metres (default 10): cells whose centre is nearer are blocked.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1000.0))]
    pub nfz_margin_m: Option<f64>,
    /// The vehicle whose model prices each path (default: the multirotor default).
    #[serde(default, skip_serializing_if = "is_default")]
    pub vehicle: VehicleParams,
}

/// One UAV's path.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct UavTotals {
    pub turns: u64,
    pub length_m: f64,
    pub duration_s: f64,
    pub energy_j: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct PatrolStats {
    #[serde(flatten)]
    pub metrics: PatrolMetrics,
    pub cycles: u32,
    pub cell_size_m: f64,
    /// With a camera: the altitude the cells are imaged from.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub altitude_m: Option<f64>,
    pub free_cells: usize,
    pub uavs: Vec<UavTotals>,
    pub energy_j: f64,
    pub planning_time_ms: f64,
}

#[derive(Debug, Clone)]
pub struct PatrolOutput {
    pub stats: PatrolStats,
    /// A FeatureCollection: a LineString per UAV (`kind: "patrol"`) through its start, turns and
    /// end, with the cycle it was at each (`cycles`), then a Polygon per free cell with its
    /// `visits` (`kind: "visits"`).
    pub trajectory: Value,
}

/// Most UAV moves one patrol may simulate (4 UAVs × 500 000 cycles; about 20 MB of paths at
/// NC-Drone's rate of turns).
pub const MAX_UAV_CYCLES: u64 = 2_000_000;

fn is_default(v: &VehicleParams) -> bool {
    *v == VehicleParams::default()
}

fn out_of_range(pointer: &str, what: &str) -> InputError {
    InputError::new("parameter_out_of_range", pointer, what.to_string())
}

impl PatrolParams {
    /// The strategy these parameters describe, checked.
    pub fn strategy(&self) -> Result<Strategy, InputError> {
        let base = match self.strategy.unwrap_or(StrategyName::NcDrone) {
            StrategyName::NcDrone | StrategyName::SharedCycle => Strategy::nc_drone(),
            StrategyName::Nc => Strategy::classic(UpdateRule::Nc),
            StrategyName::Lrta => Strategy::classic(UpdateRule::Lrta),
            StrategyName::Tvur => Strategy::classic(UpdateRule::Tvur),
            StrategyName::Wvur => Strategy::classic(UpdateRule::Wvur),
        };
        if let Some(e) = self.evaporation
            && !(e.factor.is_finite() && e.factor >= 0.0 && e.interval >= 1)
        {
            return Err(out_of_range("/evaporation", "evaporation needs a factor of 0 or more and an interval of at least 1 cycle"));
        }
        let comm = self.comm_radius_cells.unwrap_or(3);
        if comm > 1000 {
            return Err(out_of_range("/comm_radius_cells", "comm_radius_cells is 0 to 1 000"));
        }
        let sync = self.sync_interval.unwrap_or(100);
        let ws = self.ws_period.unwrap_or(100);
        if sync == 0 || ws == 0 {
            return Err(out_of_range(if sync == 0 { "/sync_interval" } else { "/ws_period" }, "intervals are at least 1 cycle"));
        }
        Ok(Strategy {
            ties: self.tie_rule.unwrap_or(base.ties),
            time_ties: self.time_ties.unwrap_or(false),
            evaporation: self.evaporation,
            watershed: self.watershed,
            ws_period: ws,
            sharing: self.sharing.unwrap_or(Sharing::Centralised),
            comm_radius_cells: comm,
            sync_interval: sync,
            ..base
        })
    }
}

impl PatrolParams {
    /// Checks every figure against its range; returns the strategy and the vehicle. The area is
    /// checked when the patrol runs.
    pub fn resolve(&self, profiles: &[Vehicle]) -> Result<(Strategy, Vehicle), InputError> {
        let strategy = self.strategy()?;
        if !self.cell_size_m.is_none_or(|s| (1.0..=1000.0).contains(&s)) {
            return Err(out_of_range("/cell_size_m", "cell_size_m is 1 to 1 000 m"));
        }
        self.cell()?;
        if !self.cycles.is_none_or(|c| (1..=1_000_000).contains(&c)) {
            return Err(out_of_range("/cycles", "cycles is 1 to 1 000 000"));
        }
        if !self.uavs.is_none_or(|n| (1..=64).contains(&n)) {
            return Err(out_of_range("/uavs", "uavs is 1 to 64"));
        }
        if self.starts.as_ref().is_some_and(|s| s.is_empty() || s.len() > 64) {
            return Err(out_of_range("/starts", "give 1 to 64 start positions"));
        }
        let uavs = self.starts.as_ref().map_or(self.uavs.unwrap_or(4), Vec::len);
        let moves = (uavs as u64).saturating_mul(u64::from(self.cycles.unwrap_or(10_000)));
        if moves > MAX_UAV_CYCLES {
            return Err(InputError::new(
                "patrol_too_long",
                "/cycles",
                format!("{uavs} UAVs × cycles is {moves}; the limit is {MAX_UAV_CYCLES} (the paths would make a very large file): fewer cycles or UAVs"),
            ));
        }
        if !self.nfz_margin_m.is_none_or(|m| (0.0..=1000.0).contains(&m)) {
            return Err(out_of_range("/nfz_margin_m", "nfz_margin_m is 0 to 1 000 m"));
        }
        let vehicle = self.vehicle.resolve(profiles, "/vehicle")?;
        if vehicle.kind != VehicleKind::Multirotor {
            // the paths turn square at every cell
            return Err(InputError::new("not_a_multirotor", "/vehicle", "a patrol turns square from cell to cell: give a multirotor"));
        }
        Ok((strategy, vehicle))
    }
}

impl PatrolParams {
    /// The side of a cell, and the altitude it is imaged from when a camera sets it: the square
    /// inside the camera's footprint (spec §1, camera §2).
    fn cell(&self) -> Result<(f64, Option<f64>), InputError> {
        let Some(camera) = &self.camera else {
            if self.altitude_m.is_some() || self.gsd_cm.is_some() {
                let at = if self.altitude_m.is_some() { "/altitude_m" } else { "/gsd_cm" };
                return Err(InputError::new("camera_missing", at, "the altitude or GSD sets the cells' size with a camera: give camera, or cell_size_m alone"));
            }
            return Ok((self.cell_size_m.unwrap_or(20.0), None));
        };
        if self.cell_size_m.is_some() {
            return Err(InputError::new("cell_size_twice", "/cell_size_m", "the camera's footprint sets the cells' size: leave out cell_size_m"));
        }
        let footprint = camera.plan(self.altitude_m, self.gsd_cm, 0.0, 0.0)?;
        let side = footprint.footprint_across_m.min(footprint.footprint_along_m);
        if !(1.0..=1000.0).contains(&side) {
            let at = if self.gsd_cm.is_some() { "/gsd_cm" } else { "/altitude_m" };
            return Err(InputError::new("cell_size_out_of_range", at, format!("the camera's footprint there is {side:.1} m; cells are 1 to 1 000 m")));
        }
        Ok((side, Some(footprint.altitude_m)))
    }
}

/// Simulates the patrol of `mission` asked for by `params`.
pub fn patrol(mission: &MissionGeometry<'_>, params: &PatrolParams, profiles: &[Vehicle], limits: &FieldLimits, stop: &Stop) -> Result<PatrolOutput, PlanError> {
    let started = std::time::Instant::now();
    let (strategy, vehicle) = params.resolve(profiles)?;
    let (size, altitude_m) = params.cell()?;
    let cycles = params.cycles.unwrap_or(10_000);
    let margin = params.nfz_margin_m.unwrap_or(10.0);
    let field = Field::parse(mission, limits)?;
    let keep_out = crate::geom::grow(&field.no_fly_zones, margin);
    let area = if keep_out.0.is_empty() { field.area.clone() } else { geo::BooleanOps::difference(&field.area, &keep_out) };
    let bounds = area.bounding_rect().ok_or_else(|| InputError::new("nothing_to_cover", "/no_fly_zones", "the no-fly zones and their margin cover the whole area"))?;
    let grid = CellGrid::over(&area, bounds, size).ok_or_else(|| out_of_range("/cell_size_m", &format!("the grid would have more than {MAX_CELLS} cells: use larger cells")))?;
    let starts = starts(&grid, params, &field)?;
    let seed = params.seed.unwrap_or(0);
    let run = if params.strategy == Some(StrategyName::SharedCycle) {
        simulate_shared_cycle(&grid, starts[0], starts.len(), cycles)
    } else {
        simulate(&grid, &strategy, &starts, cycles, seed, &|| stop.requested()).ok_or(PlanError::Cancelled)?
    };
    let model = vehicle.energy_model();
    let mut features = Vec::new();
    let mut uavs = Vec::new();
    for (i, corners) in run.corners.iter().enumerate() {
        let points: Vec<Coord> = corners.iter().map(|&c| grid.centre(c)).collect();
        let totals = price(&points, run.turns[i], model.as_ref());
        let line: Vec<[f64; 2]> = points.iter().map(|&p| field.frame.to_wgs84(p)).collect();
        features.push(json!({"type": "Feature", "geometry": {"type": "LineString", "coordinates": line},
            "properties": {"kind": "patrol", "uav": i, "cycles": run.corner_cycles[i], "turns": totals.turns, "length_m": totals.length_m, "duration_s": totals.duration_s, "energy_j": totals.energy_j}}));
        uavs.push(totals);
    }
    let h = size / 2.0;
    for cell in (0..grid.len()).filter(|&c| grid.free[c]) {
        let c = grid.centre(cell);
        let ring: Vec<[f64; 2]> = [(-h, -h), (h, -h), (h, h), (-h, h), (-h, -h)].iter().map(|&(dx, dy)| field.frame.to_wgs84(Coord { x: c.x + dx, y: c.y + dy })).collect();
        features.push(json!({"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [ring]}, "properties": {"kind": "visits", "visits": run.visits[cell]}}));
    }
    let stats = PatrolStats {
        metrics: run.metrics,
        cycles,
        cell_size_m: size,
        altitude_m,
        free_cells: grid.free.iter().filter(|&&f| f).count(),
        energy_j: uavs.iter().map(|u| u.energy_j).sum(),
        uavs,
        planning_time_ms: started.elapsed().as_secs_f64() * 1000.0,
    };
    Ok(PatrolOutput { stats, trajectory: json!({"type": "FeatureCollection", "features": features}) })
}

/// The UAVs' start cells: the given positions, or `uavs` UAVs on the lower-left free cell.
fn starts(grid: &CellGrid, params: &PatrolParams, field: &Field) -> Result<Vec<usize>, InputError> {
    let Some(given) = &params.starts else {
        let n = params.uavs.unwrap_or(4);
        let first = grid.lower_left().ok_or_else(|| InputError::new("nothing_to_cover", "/cell_size_m", "no cell of the grid lies in the area: use smaller cells"))?;
        return Ok(vec![first; n]);
    };
    given
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let local = field.frame.to_local(p[0], p[1]);
            let col = ((local.x - grid.origin.x) / grid.size).round();
            let row = ((local.y - grid.origin.y) / grid.size).round();
            let inside = col >= 0.0 && row >= 0.0 && (col as usize) < grid.cols && (row as usize) < grid.rows;
            let cell = inside.then(|| grid.index(col as usize, row as usize)).filter(|&c| grid.free[c]);
            cell.ok_or_else(|| {
                InputError::new("start_outside_area", format!("/starts/{k}"), "this start is not on a free cell of the patrol grid (outside the area or in a no-fly zone)")
            })
        })
        .collect()
}

/// A UAV's path flown corner to corner, priced by the vehicle's model.
fn price(points: &[Coord], turns: u64, model: &dyn EnergyModel) -> UavTotals {
    let mut path = FlightPath::default();
    for w in points.windows(2).filter(|w| w[0] != w[1]) {
        path.push(PieceKind::Sweep, vec![w[0], w[1]], 0.0);
    }
    let estimate = model.estimate(&path, None);
    UavTotals { turns, length_m: path.length(), duration_s: estimate.duration_s(), energy_j: estimate.energy_j() }
}
