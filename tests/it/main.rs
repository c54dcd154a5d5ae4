//! The service's integration tests, in one binary so that the service is linked once:
//! each module starts the real application (port 0, a fresh database) or the real binary.

#[cfg(feature = "bench")]
mod bench;
mod common;
mod configuration;
mod db;
mod registries;
mod repository;
