//! coverplan: coverage path planning for drones and farm vehicles.
//!
//! [`planner`] is the pure planning library; [`store`], [`jobs`] and [`http`] make the service
//! around it ([`server`] starts it), and the `coverplan` binary is the command line.

pub mod bench;
pub mod config;
pub mod http;
pub mod jobs;
pub use coverplan_planner as planner;
pub mod server;
pub mod store;
