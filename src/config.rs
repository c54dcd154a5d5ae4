//! Server configuration, from flags or `COVERPLAN_*` environment variables. The lowest layer of
//! the service: `http`, `jobs` and `store` read their settings from here.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

use crate::planner::FieldLimits;

#[derive(Debug, Clone)]
pub struct Config {
    pub addr: SocketAddr,
    pub database_url: String,
    /// Pooled database connections (`COVERPLAN_DB_CONNECTIONS`).
    pub db_connections: u32,
    pub workers: usize,
    /// Folder to serve the page from instead of the copy embedded in the binary (page development).
    pub static_dir: Option<PathBuf>,
    pub max_body_bytes: usize,
    pub limits: FieldLimits,
    /// How long running plans may take to finish at shutdown before they are requeued.
    pub shutdown_grace: Duration,
    /// Jobs' time limit (and the test knob that holds each claimed job before planning).
    pub queue: QueueSettings,
    /// Refuse to start without API keys (`COVERPLAN_REQUIRE_AUTH`).
    pub require_auth: bool,
    /// Plans one tenant may have queued or running at once.
    pub max_queued: i64,
    /// Requests per key.
    pub rate_limit: RateLimit,
    /// Map tiles for the page (a Leaflet URL template); `None`: no tiles, the page works offline.
    pub tile_url: Option<String>,
    pub tile_attribution: Option<String>,
}

impl Config {
    /// Defaults for a server on `addr` with the database at `database_url`.
    pub fn new(addr: SocketAddr, database_url: impl Into<String>) -> Self {
        Config {
            addr,
            database_url: database_url.into(),
            db_connections: 8,
            workers: std::thread::available_parallelism().map(|n| n.get()).unwrap_or(2),
            static_dir: None,
            max_body_bytes: 5 * 1024 * 1024,
            limits: FieldLimits::default(),
            shutdown_grace: Duration::from_secs(30),
            queue: QueueSettings::default(),
            require_auth: false,
            max_queued: 20,
            rate_limit: RateLimit { per_second: 100, burst: 200 },
            tile_url: None,
            tile_attribution: None,
        }
    }
}

/// `coverplan.db` in the working directory becomes `sqlite://coverplan.db`; `sqlite:` and
/// `postgres://` URLs stay as they are.
pub fn database_url(value: &str) -> String {
    if value.starts_with("sqlite:") || crate::store::is_postgres(value) { value.to_owned() } else { format!("sqlite://{value}") }
}

/// Requests per second and burst allowed to each key.
#[derive(Debug, Clone, Copy)]
pub struct RateLimit {
    pub per_second: u32,
    pub burst: u32,
}

/// How the queue runs its jobs.
#[derive(Debug, Clone)]
pub struct QueueSettings {
    /// The longest any plan may take (`COVERPLAN_JOB_TIMEOUT_S`); a plan's own `time_limit_s`
    /// may only shorten it.
    pub time_limit: Duration,
    /// Holds each job this long after claiming it (a test knob: makes "killed while running"
    /// reproducible). Zero in production.
    pub start_delay: Duration,
    /// How long a claim holds without a heartbeat (`COVERPLAN_LEASE_S`): a plan whose replica
    /// died is taken again this long after its last heartbeat.
    pub lease: Duration,
    /// This process's name in the claims it makes (`COVERPLAN_REPLICA`); by default the host's
    /// name and a random suffix.
    pub replica: Option<String>,
}

impl Default for QueueSettings {
    fn default() -> Self {
        QueueSettings { time_limit: Duration::from_secs(120), start_delay: Duration::ZERO, lease: Duration::from_secs(30), replica: None }
    }
}
