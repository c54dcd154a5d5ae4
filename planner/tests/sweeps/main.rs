//! The long property sweeps: every registered planner over the fixture, real and generated
//! fields, fleets, and ground vehicles over generated fields with ponds. Built with feature
//! `sweeps` (`tests/run_all.sh` turns it on), so that a plain `cargo test` stays quick.

mod fixed_wing;
mod fixtures;
mod fleets;
mod ground_plans;
mod ground_work;
mod planner_properties;
