//! The planner's integration tests, in one binary: they use the crate as the service does.

mod architecture;
mod energy_planners;
mod fixtures;
mod fleets;
mod ground_plans;
mod inspection;
mod obstacles;
mod patrolling;
mod planner_properties;
mod seed004;
mod several_fields;
