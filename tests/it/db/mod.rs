//! The tests that start the application on a database (in process on port 0, or the binary):
//! `tests/run_all.sh` runs this module a second time on PostgreSQL (`-- db::`), so a test added
//! here runs on both backends. `repository::every_test_that_starts_the_app_runs_on_both_backends`
//! fails on such a test outside this module.

mod api;
mod corridors;
mod deployment;
mod farms;
mod ground_plans;
mod inspection;
pub mod interop;
mod jobs;
mod observability;
mod openapi;
mod patrols;
mod process;
mod replicas;
mod resume;
mod tenancy;
mod terrain;
mod vehicles;
