//! Decomposition planners: a [`Decomposition`] makes swept cells, a [`CellOrder`] orders them,
//! and [`fly`] joins them into a path with turns and transits around no-fly zones.

use geo::{Area, MultiPolygon};

use super::{PlannedPath, Planner, Problem, Progress, connect, no_sweep_lines};
use crate::decompose::{Cell, CoverageArea, Decomposition, boustrophedon::Boustrophedon, eecd::Eecd, energy_aware::EnergyAware, naive::Naive};
use crate::error::{InputError, PlanError};
use crate::path::{FlightPath, PieceKind};
use crate::route::connect::Connector;
use crate::route::line_tour::Line;
use crate::route::visibility::TransitPlanner;
use crate::route::{CellOrder, CellVisit, RouteContext, cell_tour::CellTour, nearest_cell::NearestCell};
use crate::turn::TurnModel;
use crate::turn::dubins::Pose;
use crate::vehicle::VehicleKind;

pub struct CellPlanner {
    pub id: &'static str,
    pub name: &'static str,
    pub description: &'static str,
    pub direction_rule: &'static str,
    pub decomposition: &'static dyn Decomposition,
    pub order: &'static dyn CellOrder,
    /// Why a fixed-wing aircraft is refused, for a planner whose method is a multirotor's
    /// (a fixed wing's lines are ordered on Dubins costs, which would make it another's twin).
    pub multirotor_only: Option<&'static str>,
    /// The vehicle kinds it is the default planner for.
    pub default_for: &'static [VehicleKind],
    /// For a fixed wing: how many headings with the fewest lines its plan is also tried at
    /// (see [`CellPlanner::plan_fixed_wing`]); 0 keeps the method's own rule.
    pub fixed_wing_headings: usize,
}

pub static BOUSTROPHEDON: CellPlanner = CellPlanner {
    id: "boustrophedon",
    name: "Back and forth around obstacles (boustrophedon)",
    description: "Boustrophedon cellular decomposition around holes and no-fly zones; each cell swept in its \
        own best direction; cells, directions and entry points ordered as one generalised travelling-salesman \
        problem, with transits around no-fly zones. The recommended planner for hard fields.",
    direction_rule: "the direction with the fewest lines for the decomposition, then each cell's own fewest-lines direction where shorter; \
        for a fixed wing, also the six directions with the fewest lines and, around no-fly zones, the field swept whole at the \
        heading (2° grid) whose cut lines promise the shortest route, the shortest per covered share kept",
    decomposition: &Boustrophedon,
    order: &CellTour,
    multirotor_only: None,
    default_for: &[VehicleKind::Multirotor, VehicleKind::FixedWing],
    fixed_wing_headings: 6,
};

pub static NAIVE: CellPlanner = CellPlanner {
    id: "naive",
    name: "Convex cells (naive)",
    description: "Convex cells cut at reflex vertices (seed 000 §3.2.1), each swept across its width, \
        visited nearest first.",
    direction_rule: "each cell across its narrowest width",
    decomposition: &Naive,
    order: &NearestCell,
    multirotor_only: None,
    default_for: &[],
    fixed_wing_headings: 0,
};

pub static EECD: CellPlanner = CellPlanner {
    id: "eecd",
    name: "Narrowest convex cells (EECD)",
    description: "Convex cells by the cuts that minimise the summed cell widths, neighbours with the same \
        direction merged while monotone (seed 000 §3.2.2); visiting order over each cell's four entry and exit \
        options.",
    direction_rule: "each cell across its narrowest width",
    decomposition: &Eecd,
    order: &CellTour,
    multirotor_only: None,
    default_for: &[],
    fixed_wing_headings: 0,
};

pub static ENERGY_AWARE: CellPlanner = CellPlanner {
    id: "energy_aware",
    name: "Energy-aware back and forth (Di Franco)",
    description: "Di Franco's energy-aware back-and-forth (seed 000 §3.2.3, E-BF of seed 002): lines parallel \
        to the longest edge in one main run, the concave pockets it leaves swept the same way, recursively.",
    direction_rule: "parallel to the longest edge (of the field, then of each pocket)",
    decomposition: &EnergyAware,
    order: &CellTour,
    multirotor_only: None,
    default_for: &[],
    fixed_wing_headings: 0,
};

pub static E_BF: CellPlanner = CellPlanner {
    id: "e_bf",
    name: "Energy-aware back and forth (E-BF)",
    description: "Energy-aware back-and-forth as seed 002 compares it with E-Spiral: the energy_aware geometry \
        (lines parallel to the longest edge, pockets the same way) flown in a fixed nearest-first order, each \
        leg at its energy-optimal speed. Multirotor only.",
    direction_rule: "parallel to the longest edge (of the field, then of each pocket)",
    decomposition: &EnergyAware,
    order: &NearestCell,
    multirotor_only: Some(
        "e_bf is seed 002's multirotor method (a fixed nearest-first order); for a fixed-wing aircraft use energy_aware: the same lines, ordered on Dubins turns",
    ),
    default_for: &[],
    fixed_wing_headings: 0,
};

impl Planner for CellPlanner {
    fn id(&self) -> &'static str {
        self.id
    }

    fn name(&self) -> &'static str {
        self.name
    }

    fn description(&self) -> &'static str {
        self.description
    }

    fn direction_rule(&self) -> &'static str {
        self.direction_rule
    }

    fn vehicle_kinds(&self) -> &'static [VehicleKind] {
        if self.multirotor_only.is_some() { &[VehicleKind::Multirotor] } else { &[VehicleKind::Multirotor, VehicleKind::FixedWing] }
    }

    fn default_for(&self) -> &'static [VehicleKind] {
        self.default_for
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        if let (Some(why), TurnModel::Dubins(_)) = (self.multirotor_only, problem.connector.turn) {
            return Err(InputError::new("planner_not_applicable", "/vehicle/kind", why).into());
        }
        if matches!(problem.connector.turn, TurnModel::Dubins(_)) && problem.sweep_angle.is_none() && self.fixed_wing_headings > 0 {
            return self.plan_fixed_wing(problem, progress);
        }
        self.plan_at(problem, progress)
    }
}

/// The lines a fixed wing's plan is tried with.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Lines {
    /// The decomposition's cells, each swept on its own.
    Cells,
    /// Each field swept whole (its lines cut by holes and zones, one phase across the field).
    WholeFields,
}

/// A heading tried (`None`: the decomposition's own) with the lines swept at it.
type Try = (Option<f64>, Lines);

/// A try planned, with the share it covers.
type Tried = (Try, f64, PlannedPath);

impl CellPlanner {
    /// A fixed wing's lines are ordered on Dubins costs, which the fewest lines do not settle:
    /// the decomposition's own plan and plans at the [`CellPlanner::fixed_wing_headings`]
    /// headings with the fewest lines (each swept by one heading throughout), in parallel, the
    /// shortest per covered share kept ([`crate::metrics::best_covering`]).
    ///
    /// Around no-fly zones, where pricing a connection means routing round them, the headings
    /// are ranked with connections over open sky and only the best is planned again beside the
    /// decomposition's own. So is the best of [`WHOLE_FIELD_HEADINGS`] headings at which each
    /// field is swept whole ([`best_whole_field_heading`]): cells each lay their own lines, which
    /// leaves extra lines at their seams and turns at each cell's ends round a zone, and
    /// the fewest lines across the field are not the fewest once holes cut them.
    fn plan_fixed_wing(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        let headings = crate::sweep::fewest_lines_directions(problem.region, problem.layout, self.fixed_wing_headings);
        let mut tries: Vec<Try> = std::iter::once((None, Lines::Cells)).chain(headings.into_iter().map(|h| (Some(h), Lines::Cells))).collect();
        if problem.transit.has_walls() {
            let open_sky = TransitPlanner::new(&MultiPolygon(vec![]), &MultiPolygon(vec![]));
            let ranking_connector = Connector::new(problem.connector.turn, &open_sky, None).in_wind_of(problem.connector).stopping_on(&problem.connector.stop());
            let ranking = Problem { transit: &open_sky, connector: &ranking_connector, ..*problem };
            let ranked = self.tried(&ranking, &tries)?;
            let best_cells = Self::best(problem, &ranked.iter().collect::<Vec<_>>()).map(|i| ranked[i].0);
            let best_whole = best_whole_field_heading(problem, &ranking);
            tries = std::iter::once((None, Lines::Cells)).chain(best_cells).chain(best_whole.map(|h| (Some(h), Lines::WholeFields))).collect();
            tries.dedup();
        }
        if !progress.report(0.5) {
            return Err(PlanError::Cancelled);
        }
        let planned = self.tried(problem, &tries)?;
        let best = Self::best(problem, &planned.iter().collect::<Vec<_>>()).expect("a try planned");
        Ok(planned.into_iter().nth(best).expect("an index of the plans").2)
    }

    /// The plan of each try, in parallel, with the share it covers. A try whose lines cannot
    /// be flown (no way round a zone at the turning radius) is passed over; the first error
    /// stands when no try plans.
    fn tried(&self, problem: &Problem<'_>, tries: &[Try]) -> Result<Vec<Tried>, PlanError> {
        use rayon::prelude::*;
        let area = problem.region.unsigned_area();
        let results: Vec<Result<Tried, PlanError>> = tries
            .par_iter()
            .map(|&(angle, lines)| {
                let at = Problem { sweep_angle: angle, ..*problem };
                let planned = match (lines, angle) {
                    (Lines::WholeFields, Some(h)) => plan_whole_fields(&at, h)?,
                    _ => self.plan_at(&at, &|_| true)?,
                };
                let coverage = crate::metrics::covered_area(&planned.path, problem.region, problem.layout.photographed()) / area;
                Ok(((angle, lines), coverage, planned))
            })
            .collect();
        let mut planned = Vec::new();
        let mut first_error = None;
        for result in results {
            match result {
                Ok(p) => planned.push(p),
                Err(PlanError::Cancelled) => return Err(PlanError::Cancelled),
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
        match first_error {
            Some(e) if planned.is_empty() => Err(e),
            _ => Ok(planned),
        }
    }

    /// Of the plans tried, the shortest per covered share (in wind, the quickest: measured as
    /// the connections are).
    fn best(problem: &Problem<'_>, planned: &[&Tried]) -> Option<usize> {
        crate::metrics::best_covering(planned, |p| p.1, |p| problem.connector.measure(&p.2.path))
    }

    fn plan_at(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        let area = CoverageArea { region: problem.region, keep_out: problem.keep_out, layout: problem.layout, angle: problem.sweep_angle };
        let cells = self.decomposition.cells(&area);
        if cells.is_empty() {
            return Err(no_sweep_lines());
        }
        if !progress.report(0.3) {
            return Err(PlanError::Cancelled);
        }
        let main = cells.iter().max_by(|a, b| a.sweep_length().total_cmp(&b.sweep_length())).expect("cells");
        if problem.connector.turn != TurnModel::Straight {
            let path = fly_line_level(&cells, problem)?;
            return Ok(PlannedPath::new(path, main.angle, cells.len()));
        }
        let ctx = RouteContext { transit: problem.transit, start: problem.start, end: problem.end };
        let tour = self.order.order(&cells, &ctx);
        if !progress.report(0.5) {
            return Err(PlanError::Cancelled);
        }
        let path = fly(&cells, &tour, problem)?;
        Ok(PlannedPath::new(path, main.angle, cells.len()))
    }
}

/// The flight through `cells` in the order of `tour`: lines, turns between lines of a cell,
/// transits between cells and from the start and to the end.
pub fn fly(cells: &[Cell], tour: &[CellVisit], problem: &Problem<'_>) -> Result<FlightPath, PlanError> {
    let half = problem.layout.half_swath();
    let mut path = FlightPath::default();
    let mut here = problem.start;
    for visit in tour {
        for (i, (a, b)) in visit.legs(&cells[visit.cell]).into_iter().enumerate() {
            if let Some(h) = here {
                let kind = if i == 0 { PieceKind::Transit } else { PieceKind::Turn };
                connect(&mut path, kind, h, a, problem.transit)?;
            }
            path.push(PieceKind::Sweep, vec![a, b], half);
            here = Some(b);
        }
    }
    if let (Some(h), Some(end)) = (here, problem.end) {
        connect(&mut path, PieceKind::Transit, h, end, problem.transit)?;
    }
    Ok(path)
}

/// Fixed wing: the cells' lines ordered one by one on Dubins costs (docs/methods.md, routing §1, line
/// level), each cell a region the route may leave and re-enter.
fn fly_line_level(cells: &[Cell], problem: &Problem<'_>) -> Result<FlightPath, PlanError> {
    let lines: Vec<Line> = problem.flyable(cells.iter().enumerate().flat_map(|(region, cell)| {
        cell.segments.iter().map(move |s| {
            let (a, b) = cell.ends(s);
            Line { a, b, region }
        })
    }));
    let route = problem.line_problem(&lines, true);
    let (seq, _) = route.solve();
    super::line_gtsp::fly_lines(&route, &seq, problem.layout.half_swath())
}

/// The flyable lines of every field swept whole at heading `h` (as `line_gtsp` sweeps a
/// field), and the metres of sweep lost to turning room before no-fly zones.
fn whole_field_lines(problem: &Problem<'_>, h: f64) -> (Vec<Line>, f64) {
    let mut lost_m = 0.0;
    let mut lines = Vec::new();
    for (region, field) in problem.region.0.iter().enumerate() {
        let (flown, lost) = super::line_gtsp::field_lines(problem, &MultiPolygon(vec![field.clone()]), region, h);
        lines.extend(flown);
        lost_m += lost;
    }
    (lines, lost_m)
}

/// Fixed wing: every field swept whole at heading `h`, its lines ordered one by one on
/// Dubins costs.
fn plan_whole_fields(problem: &Problem<'_>, h: f64) -> Result<PlannedPath, PlanError> {
    let (lines, _) = whole_field_lines(problem, h);
    if lines.is_empty() {
        return Err(no_sweep_lines());
    }
    let route = problem.line_problem(&lines, true);
    let (seq, _) = route.solve();
    let path = super::line_gtsp::fly_lines(&route, &seq, problem.layout.half_swath())?;
    Ok(PlannedPath::new(path, h, problem.region.0.len()))
}

/// Whole-field headings routed over open sky, around no-fly zones.
const WHOLE_FIELD_HEADINGS: usize = 6;
/// Grid of the headings whole fields are estimated at, degrees.
const WHOLE_FIELD_GRID_DEG: f64 = 2.0;

/// Of the headings on a [`WHOLE_FIELD_GRID_DEG`] grid, the [`WHOLE_FIELD_HEADINGS`] whose
/// whole-field lines promise the shortest flight without routing (the sweep, a U-turn per
/// line, the sweep lost to turning room at `coverage_penalty`), then the one of those whose
/// lines, as `problem` may fly them, route shortest over open sky (`ranking`'s connections),
/// with the same charge for lost sweep. Around holes and zones the lines a heading is cut
/// into, not the field's width, decide the turns: on `h05_00` the heading with the fewest
/// lines across the hull makes 64 lines, one 10° off 53.
fn best_whole_field_heading(problem: &Problem<'_>, ranking: &Problem<'_>) -> Option<f64> {
    use rayon::prelude::*;
    let w = problem.layout.spacing;
    let u_turn = problem.connector.turn.length(Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, w, std::f64::consts::PI));
    let grid: Vec<f64> = (0..(180.0 / WHOLE_FIELD_GRID_DEG) as usize).map(|k| (k as f64 * WHOLE_FIELD_GRID_DEG).to_radians()).collect();
    let penalty = |lost_m: f64| problem.coverage_penalty * lost_m;
    let mut estimated: Vec<(f64, f64, Vec<Line>, f64)> = grid
        .par_iter()
        .filter(|_| !problem.connector.stopped())
        .map(|&h| {
            let (lines, lost_m) = whole_field_lines(problem, h);
            (lines.iter().map(|l| l.length() + u_turn).sum::<f64>() + penalty(lost_m), h, lines, lost_m)
        })
        .filter(|e| !e.2.is_empty())
        .collect();
    estimated.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut chosen: Vec<(f64, Vec<Line>, f64)> = Vec::new();
    for (_, h, lines, lost_m) in estimated {
        if chosen.len() == WHOLE_FIELD_HEADINGS {
            break;
        }
        if chosen.iter().all(|c| crate::geom::axial_difference(c.0, h) >= crate::sweep::DISTINCT_DIRECTIONS_DEG.to_radians()) {
            chosen.push((h, lines, lost_m));
        }
    }
    chosen
        .par_iter()
        .filter(|_| !ranking.connector.stopped())
        .map(|(h, lines, lost_m)| (ranking.line_problem(lines, true).solve().1 + penalty(*lost_m), *h))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)))
        .map(|(_, h)| h)
}
