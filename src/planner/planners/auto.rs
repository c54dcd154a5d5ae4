//! `auto`: plans with every other planner (in parallel), prices each plan with the vehicle's
//! energy model, and keeps the best for the objective (energy, time or length) among the
//! plans that cover the area as well as the best of them does (multirotor planners spec §4).
//! The others' figures are reported beside it.

use geo::Area;
use rayon::prelude::*;

use super::{Alternative, PlannedPath, Planner, Problem, Progress, registry};
use crate::energy::model_for;
use crate::error::PlanError;
use crate::metrics::covered_area;
use crate::params::Objective;

pub struct Auto;

/// A plan may cover this much less than the best-covering one and still be chosen (here, and
/// among the directions of `sweep_direction: optimal`).
pub const COVERAGE_SLACK: f64 = 0.01;

impl Planner for Auto {
    fn id(&self) -> &'static str {
        "auto"
    }

    fn description(&self) -> &'static str {
        "Plans with every applicable planner and keeps the one with the least energy, time or length \
         (`objective`), among those that cover the area as well as the best; the others' figures are reported."
    }

    fn direction_rule(&self) -> &'static str {
        "each planner's own"
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        let model = model_for(problem.vehicle);
        let others: Vec<&'static dyn Planner> = registry().iter().copied().filter(|p| p.id() != self.id()).collect();
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
                    let coverage = covered_area(&planned.path, problem.region) / problem.region.unsigned_area();
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
        let best_coverage = scored.iter().map(|s| s.2).fold(0.0, f64::max);
        let (id, _, _, planned) = scored
            .into_iter()
            .filter(|s| s.2 >= best_coverage * (1.0 - COVERAGE_SLACK))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .ok_or_else(|| PlanError::Infeasible(format!("no planner could plan this mission: {}", alternatives.iter().filter_map(|a| a.error.as_deref()).collect::<Vec<_>>().join("; "))))?;
        alternatives.retain(|a| a.planner != id);
        Ok(PlannedPath { planner: Some(id), alternatives, ..planned })
    }
}
