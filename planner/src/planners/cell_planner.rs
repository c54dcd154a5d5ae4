//! Decomposition planners: a [`Decomposition`] makes swept cells, a [`CellOrder`] orders them,
//! and [`fly`] joins them into a path with turns and transits around no-fly zones.

use super::{PlannedPath, Planner, Problem, Progress, connect, no_sweep_lines};
use crate::decompose::{Cell, CoverageArea, Decomposition, boustrophedon::Boustrophedon, eecd::Eecd, energy_aware::EnergyAware, naive::Naive};
use crate::error::{InputError, PlanError};
use crate::path::{FlightPath, PieceKind};
use crate::route::line_tour::Line;
use crate::route::{CellOrder, CellVisit, RouteContext, cell_tour::CellTour, nearest_cell::NearestCell};
use crate::turn::TurnModel;
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
}

pub static BOUSTROPHEDON: CellPlanner = CellPlanner {
    id: "boustrophedon",
    name: "Back and forth around obstacles (boustrophedon)",
    description: "Boustrophedon cellular decomposition around holes and no-fly zones; each cell swept in its \
        own best direction; cells, directions and entry points ordered as one generalised travelling-salesman \
        problem, with transits around no-fly zones. The recommended planner for hard fields.",
    direction_rule: "the direction with the fewest lines for the decomposition, then each cell's own fewest-lines direction where shorter",
    decomposition: &Boustrophedon,
    order: &CellTour,
    multirotor_only: None,
    default_for: &[VehicleKind::Multirotor, VehicleKind::FixedWing],
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
