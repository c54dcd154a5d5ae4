//! The service's integration tests, in one binary so that the service is linked once:
//! each module starts the real application (port 0, a fresh database) or the real binary.

mod api;
#[cfg(feature = "bench")]
mod bench;
mod common;
mod ground_plans;
mod inspection;
mod interop;
mod jobs;
mod observability;
mod openapi;
mod patrols;
mod process;
mod registries;
mod replicas;
mod repository;
mod tenancy;
mod vehicles;
