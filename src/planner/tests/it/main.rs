//! The planner's integration tests, in one binary: they use the crate as the service does.

mod architecture;
mod energy_planners;
mod inspection;
mod obstacles;
mod patrolling;
mod seed004;
mod several_fields;
