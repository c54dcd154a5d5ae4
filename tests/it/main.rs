//! The service's integration tests, in one binary so that the service is linked once:
//! each module starts the real application (port 0, a fresh database) or the real binary.

mod api;
mod common;
mod fleets;
mod ground_plans;
mod inspection;
mod interop;
mod jobs;
mod observability;
mod openapi;
mod patrols;
mod planner_properties;
mod process;
mod replicas;
mod repository;
mod tenancy;
mod vehicles;
