//! `auto`: plans with every other planner (in parallel), prices each plan with the vehicle's
//! energy model, and keeps the best for the objective (energy, time or length) among the
//! plans that cover the area as well as the best of them does (docs/methods.md, multirotor planners §4).
//! The others' figures are reported beside it.

use geo::Area;
use rayon::prelude::*;

use super::{COMMON_PARAMETERS, PlannedPath, Planner, Problem, Progress, registry};
use crate::error::PlanError;
use crate::metrics::{Alternative, best_covering, covered_area};
use crate::params::Objective;

pub struct Auto;

impl Planner for Auto {
    fn id(&self) -> &'static str {
        "auto"
    }

    fn name(&self) -> &'static str {
        "Best of every planner (auto)"
    }

    fn description(&self) -> &'static str {
        "Plans with every applicable planner and keeps the one with the least energy, time or length \
         (`objective`), among those that cover the area as well as the best; the others' figures are reported."
    }

    fn direction_rule(&self) -> &'static str {
        "each planner's own"
    }

    fn orders_lines_one_by_one(&self) -> bool {
        true
    }

    fn parameters(&self) -> Vec<&'static str> {
        COMMON_PARAMETERS.to_vec()
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        let model = problem.vehicle.energy_model_in(problem.wind.as_ref());
        let others: Vec<&'static dyn Planner> = registry().iter().copied().filter(|p| p.id() != self.id() && !p.for_ground_vehicles()).collect();
        let results: Vec<(&'static str, Result<PlannedPath, PlanError>)> = others.par_iter().map(|p| (p.id(), p.plan(problem, &|_| true))).collect();
        if !progress.report(0.8) {
            return Err(PlanError::Cancelled);
        }
        let mut scored = Vec::new();
        let mut alternatives = Vec::new();
        for (id, result) in results {
            match result {
                Ok(planned) => {
                    let e = model.estimate(&planned.path, None);
                    let (length, time, energy) = (planned.path.length(), e.duration_s(), e.energy_j());
                    let score = match problem.objective {
                        Objective::Energy => energy,
                        Objective::Time => time,
                        Objective::Length => length,
                    };
                    let coverage = covered_area(&planned.path, problem.region, problem.layout.photographed()) / problem.region.unsigned_area();
                    alternatives.push(Alternative {
                        planner: id.into(),
                        length_m: Some(length),
                        duration_s: Some(time),
                        energy_j: Some(energy),
                        coverage_ratio: Some(coverage),
                        error: None,
                    });
                    scored.push((id, score, coverage, planned));
                }
                Err(PlanError::Cancelled) => return Err(PlanError::Cancelled),
                Err(e) => alternatives.push(Alternative { planner: id.into(), length_m: None, duration_s: None, energy_j: None, coverage_ratio: None, error: Some(e.to_string()) }),
            }
        }
        let best = best_covering(&scored, |s| s.2, |s| s.1).ok_or_else(|| {
            PlanError::Infeasible(format!("no planner could plan this mission: {}", alternatives.iter().filter_map(|a| a.error.as_deref()).collect::<Vec<_>>().join("; ")))
        })?;
        let (id, _, _, planned) = scored.swap_remove(best);
        alternatives.retain(|a| a.planner != id);
        Ok(PlannedPath { planner: Some(id), alternatives, ..planned })
    }
}
