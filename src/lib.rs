//! coverplan: coverage path planning for drones and farm vehicles.
//!
//! [`planner`] is the pure planning library; [`store`], [`jobs`] and [`http`] make the service
//! around it ([`server`] starts it), and the `coverplan` binary is the command line.

#[cfg(feature = "bench")]
pub mod bench;
pub mod config;
pub mod http;
pub mod jobs;
pub use coverplan_planner as planner;
pub mod server;
pub mod store;
pub mod telemetry;

/// What a caught panic says (its message when it has one).
pub fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| panic.downcast_ref::<String>().cloned()).unwrap_or_else(|| "unknown cause".into())
}
