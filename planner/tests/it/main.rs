//! The planner's integration tests, in one binary: they use the crate as the service does. The
//! long property sweeps over every planner are `tests/sweeps/` (feature `sweeps`).

mod architecture;
mod corridors;
mod energy_planners;
mod farms;
mod flown;
mod inspection;
mod landing_sites;
mod limits;
mod obstacles;
mod patrolling;
mod patterns;
mod resume;
mod seed004;
mod several_fields;
mod terrain;
mod wind;
