//! The `coverplan` command: the server, offline planning, the OpenAPI document, a health check.

use std::io::{IsTerminal, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context;
use clap::{Parser, Subcommand};
use serde_json::Value;

use coverplan::config::{Config, database_url};
use coverplan::http::auth::RateLimit;
use coverplan::jobs::QueueSettings;
use coverplan::planner::export::{self, AltitudeFrame, ExportOptions, ExportRequest, Firmware};
use coverplan::planner::{self, FieldLimits, MissionGeometry, PlanError, PlanParams, Stop, import};
use coverplan::store;

#[derive(Parser)]
#[command(name = "coverplan", version, about = "Coverage path planning for drones and farm vehicles")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the HTTP server (API, map page, Swagger UI at /docs).
    Serve(ServeArgs),
    /// Plan a mission file offline and write the trajectory as GeoJSON or a flight file.
    Plan {
        /// Mission JSON ({"name", "area", "no_fly_zones"?, "home"?}), or a file to import:
        /// GeoJSON, KML, KMZ, shapefile zip, ISOXML TaskData or QGroundControl .plan
        #[arg(long)]
        mission: PathBuf,
        /// Plan parameters JSON, as POSTed to /api/v1/missions/{id}/plans (default: {"line_spacing_m": 20})
        #[arg(long)]
        params: Option<PathBuf>,
        /// Output file (default: standard output)
        #[arg(long)]
        out: Option<PathBuf>,
        /// Export format (`GET /api/v1/formats` describes each)
        #[arg(long, default_value = export::default_format().id, value_parser = clap::builder::PossibleValuesParser::new(export::format_ids()))]
        format: String,
        /// Autopilot of plan and waypoints files: ardupilot or px4
        #[arg(long, default_value = "ardupilot", value_parser = ["ardupilot", "px4"])]
        firmware: String,
        /// Elevation model (GeoTIFF, or SRTM .hgt plain or zipped): the plan flies at
        /// altitude_m above this ground (altitude_reference terrain, unless the parameters say home)
        #[arg(long)]
        terrain: Option<PathBuf>,
        /// Over terrain, the flight files' altitudes: amsl (as planned) or terrain (above the
        /// ground under each waypoint, for vehicles with a rangefinder)
        #[arg(long, default_value = "amsl", value_parser = ["amsl", "terrain"])]
        altitude_frame: String,
        /// Most waypoints the controller loads (plan, waypoints, wpml; wpml's default 99): past
        /// it lines are their two ends, then the flight is cut into missions
        #[arg(long)]
        max_waypoints: Option<usize>,
    },
    /// Time the planners on the generated fields and print a table (built with `--features bench`).
    #[cfg(feature = "bench")]
    Bench(coverplan::bench::BenchArgs),
    /// Manage API keys: once any key exists, every API request needs one.
    Keys {
        #[command(subcommand)]
        action: KeysAction,
        /// SQLite file or URL of the server's database.
        #[arg(long, env = "COVERPLAN_DATABASE_URL", default_value = "coverplan.db", global = true)]
        database_url: String,
    },
    /// Print the OpenAPI document.
    Openapi,
    /// Exit 0 when the local server answers /healthz (for container health checks).
    Healthcheck {
        #[arg(long, env = "COVERPLAN_ADDR", default_value = "127.0.0.1:8080")]
        addr: SocketAddr,
    },
}

#[derive(Subcommand)]
enum KeysAction {
    /// Make a key for a tenant (created with its first key); prints the key once, alone on the
    /// last line.
    Create {
        /// Letters, digits, `-`, `_` and `.`, up to 64.
        #[arg(long)]
        tenant: String,
        /// May also edit the built-in vehicle profiles and read /metrics.
        #[arg(long)]
        admin: bool,
    },
    /// List the keys (ids, tenants, never the secrets).
    List,
    /// Revoke a key by its id.
    Revoke { id: String },
}

#[derive(clap::Args)]
struct ServeArgs {
    #[arg(long, env = "COVERPLAN_ADDR", default_value = "127.0.0.1:8080")]
    addr: SocketAddr,
    /// SQLite file or URL (created if missing), or `postgres://…` for replicas sharing one
    /// PostgreSQL database.
    #[arg(long, env = "COVERPLAN_DATABASE_URL", default_value = "coverplan.db")]
    database_url: String,
    /// Pooled database connections.
    #[arg(long, env = "COVERPLAN_DB_CONNECTIONS", default_value_t = 8)]
    db_connections: u32,
    /// Seconds a running plan's claim holds without a heartbeat: a plan whose replica died is
    /// taken again this long after its last heartbeat (heartbeats come every 0.5 s).
    #[arg(long, env = "COVERPLAN_LEASE_S", default_value_t = 30.0)]
    lease_s: f64,
    /// This replica's name in the record of claims (default: the host's name and a random suffix).
    #[arg(long, env = "COVERPLAN_REPLICA")]
    replica: Option<String>,
    /// Planning workers (default: the number of CPUs).
    #[arg(long, env = "COVERPLAN_WORKERS")]
    workers: Option<usize>,
    /// Serve the map page from this folder instead of the copy built into the binary (for
    /// working on the page without rebuilding).
    #[arg(long, env = "COVERPLAN_STATIC_DIR")]
    static_dir: Option<PathBuf>,
    /// Largest field accepted, in hectares.
    #[arg(long, env = "COVERPLAN_MAX_AREA_HA", default_value_t = 10_000.0)]
    max_area_ha: f64,
    /// Most vertices accepted in one mission.
    #[arg(long, env = "COVERPLAN_MAX_VERTICES", default_value_t = 20_000)]
    max_vertices: usize,
    /// Largest request body, in bytes.
    #[arg(long, env = "COVERPLAN_MAX_BODY_BYTES", default_value_t = 5 * 1024 * 1024)]
    max_body_bytes: usize,
    /// Seconds running plans get to finish at shutdown before they are requeued (SQLite; replicas
    /// on PostgreSQL hand them back at once).
    #[arg(long, env = "COVERPLAN_SHUTDOWN_GRACE_S", default_value_t = 30)]
    shutdown_grace_s: u64,
    /// Map tile URL template for the page; an empty value turns tiles off (the page then draws
    /// on a plain background and needs no network).
    #[arg(long, env = "COVERPLAN_TILE_URL", default_value = "https://tile.openstreetmap.org/{z}/{x}/{y}.png")]
    tile_url: String,
    /// Attribution shown with the tiles.
    #[arg(long, env = "COVERPLAN_TILE_ATTRIBUTION", default_value = "© OpenStreetMap contributors")]
    tile_attribution: String,
    /// Refuse to start while the database has no API key (the Docker image sets it).
    #[arg(long, env = "COVERPLAN_REQUIRE_AUTH", default_value_t = false, action = clap::ArgAction::Set)]
    require_auth: bool,
    /// Plans one tenant may have queued or running at once; more answer 429.
    #[arg(long, env = "COVERPLAN_MAX_QUEUED", default_value_t = 20)]
    max_queued: i64,
    /// Requests per second each API key may send (with bursts of twice as many).
    #[arg(long, env = "COVERPLAN_RATE_PER_S", default_value_t = 100)]
    rate_per_s: u32,
    /// Longest time a plan may take, in seconds; a plan's `time_limit_s` may only shorten it.
    #[arg(long, env = "COVERPLAN_JOB_TIMEOUT_S", default_value_t = 120.0)]
    job_timeout_s: f64,
    /// Test knob: hold each job this many milliseconds before planning.
    #[arg(long, env = "COVERPLAN_JOB_START_DELAY_MS", default_value_t = 0, hide = true)]
    job_start_delay_ms: u64,
}

fn main() -> ExitCode {
    let logs =
        tracing_subscriber::fmt().with_env_filter(tracing_subscriber::EnvFilter::try_from_env("COVERPLAN_LOG").unwrap_or_else(|_| "info".into())).with_writer(std::io::stderr);
    // one JSON object per line for log collectors; a job's lines carry its span (plan, tenant)
    match std::env::var("COVERPLAN_LOG_FORMAT").as_deref() {
        Ok("json") => logs.json().with_current_span(true).with_span_list(false).init(),
        Ok("text") | Err(_) => logs.init(),
        Ok(other) => {
            logs.init();
            tracing::warn!("COVERPLAN_LOG_FORMAT={other} is neither `text` nor `json`: writing text");
        }
    }
    let result = match Cli::parse().command {
        Command::Serve(args) => serve(args),
        Command::Plan { mission, params, out, format, firmware, terrain, altitude_frame, max_waypoints } => {
            let options = ExportOptions {
                firmware: if firmware == "px4" { Firmware::Px4 } else { Firmware::Ardupilot },
                altitude_frame: if altitude_frame == "terrain" { AltitudeFrame::Terrain } else { AltitudeFrame::Amsl },
                altitude_m: None,
                max_waypoints,
            };
            plan(&mission, params.as_deref(), terrain.as_deref(), out.as_deref(), &format, options)
        }
        #[cfg(feature = "bench")]
        Command::Bench(args) => coverplan::bench::run_command(args),
        Command::Keys { action, database_url: url } => tokio::runtime::Runtime::new().map_err(Into::into).and_then(|rt| rt.block_on(keys(action, &database_url(&url)))),
        Command::Openapi => {
            print!("{}", coverplan::http::openapi::document());
            Ok(())
        }
        Command::Healthcheck { addr } => healthcheck(addr),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("coverplan: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn serve(args: ServeArgs) -> anyhow::Result<()> {
    let mut config = Config::new(args.addr, database_url(&args.database_url));
    if let Some(w) = args.workers {
        anyhow::ensure!(w >= 1, "COVERPLAN_WORKERS must be at least 1");
        config.workers = w;
    }
    config.static_dir = args.static_dir;
    config.max_body_bytes = args.max_body_bytes;
    config.limits = FieldLimits { max_area_ha: args.max_area_ha, max_vertices: args.max_vertices, ..FieldLimits::default() };
    config.shutdown_grace = Duration::from_secs(args.shutdown_grace_s);
    anyhow::ensure!(args.job_timeout_s.is_finite() && args.job_timeout_s >= 1.0, "COVERPLAN_JOB_TIMEOUT_S must be at least 1 (seconds)");
    anyhow::ensure!(args.lease_s.is_finite() && args.lease_s >= 2.0, "COVERPLAN_LEASE_S must be at least 2 (seconds)");
    anyhow::ensure!(args.db_connections >= 2, "COVERPLAN_DB_CONNECTIONS must be at least 2");
    config.db_connections = args.db_connections;
    config.queue = QueueSettings {
        time_limit: Duration::from_secs_f64(args.job_timeout_s),
        start_delay: Duration::from_millis(args.job_start_delay_ms),
        lease: Duration::from_secs_f64(args.lease_s),
        replica: args.replica,
    };
    anyhow::ensure!(args.max_queued >= 1, "COVERPLAN_MAX_QUEUED must be at least 1");
    config.require_auth = args.require_auth;
    config.max_queued = args.max_queued;
    config.rate_limit = RateLimit { per_second: args.rate_per_s.max(1), burst: args.rate_per_s.max(1).saturating_mul(2) };
    config.tile_url = Some(args.tile_url).filter(|u| !u.is_empty());
    config.tile_attribution = Some(args.tile_attribution).filter(|a| !a.is_empty());
    tokio::runtime::Runtime::new()?.block_on(coverplan::server::run(config, coverplan::server::shutdown_signal()))
}

async fn keys(action: KeysAction, url: &str) -> anyhow::Result<()> {
    let db = coverplan::store::connect(url).await.with_context(|| format!("opening {url}"))?;
    match action {
        KeysAction::Create { tenant, admin } => {
            anyhow::ensure!(store::keys::valid_tenant(&tenant), "a tenant name has 1 to 64 letters, digits, `-`, `_` or `.`");
            let (info, key) = store::keys::create(&db, &tenant, admin).await?;
            println!("key {} for tenant {}{}; it is shown only now:", info.id, info.tenant, if admin { " (admin)" } else { "" });
            println!("{key}");
        }
        KeysAction::List => {
            println!("{:<12}  {:<24}  {:<5}  {:<24}  revoked", "id", "tenant", "admin", "created");
            for k in store::keys::list(&db).await? {
                println!("{:<12}  {:<24}  {:<5}  {:<24}  {}", k.id, k.tenant, k.admin, k.created_at, k.revoked_at.as_deref().unwrap_or("-"));
            }
        }
        KeysAction::Revoke { id } => {
            anyhow::ensure!(store::keys::revoke(&db, &id).await?, "no key `{id}` that is not revoked already");
            println!("revoked {id}");
        }
    }
    db.close().await;
    Ok(())
}

fn read_json(path: &std::path::Path) -> anyhow::Result<Value> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("{} is not valid JSON", path.display()))
}

/// A mission document: the file itself when it is one, else the mission imported from it.
fn read_mission(path: &std::path::Path) -> anyhow::Result<Value> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    if let Ok(mission) = serde_json::from_slice::<Value>(&bytes)
        && mission.get("area").is_some()
    {
        return Ok(mission);
    }
    let imported = import::import(None, &bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    for warning in &imported.warnings {
        eprintln!("coverplan: {}: {warning}", path.display());
    }
    let name = imported.name.clone().or_else(|| path.file_stem().map(|s| s.to_string_lossy().into_owned()));
    Ok(serde_json::json!({"name": name, "area": imported.area, "no_fly_zones": imported.no_fly_zones, "obstacles": imported.obstacles, "home": imported.home}))
}

fn plan(
    mission_path: &std::path::Path,
    params_path: Option<&std::path::Path>,
    terrain_path: Option<&std::path::Path>,
    out: Option<&std::path::Path>,
    format: &str,
    options: ExportOptions,
) -> anyhow::Result<()> {
    anyhow::ensure!(export::find(format).is_some(), "no export format `{format}`; known: {}", export::format_ids().join(", "));
    let mission = read_mission(mission_path)?;
    let mut params: PlanParams = match params_path {
        Some(p) => serde_json::from_value(read_json(p)?).with_context(|| format!("{}: not valid plan parameters", p.display()))?,
        None => PlanParams { line_spacing_m: Some(20.0), ..PlanParams::default() },
    };
    let model = match terrain_path {
        Some(path) => {
            let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read the elevation model", path.display()))?;
            let name = path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            params.altitude_reference.get_or_insert(planner::params::AltitudeReference::Terrain);
            Some(planner::terrain::ElevationModel::read(&bytes, &name).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?)
        }
        None => None,
    };
    let home = mission.get("home").filter(|h| !h.is_null()).map(|h| serde_json::from_value::<[f64; 2]>(h.clone())).transpose().context("home must be [lon, lat]")?;
    mission.get("area").context("the mission has no `area`")?;
    let geometry = MissionGeometry { home, terrain: model.as_ref(), ..MissionGeometry::of(&mission) };
    let profiles = planner::vehicle::builtin_profiles();
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(100);
        b.set_style(indicatif::ProgressStyle::with_template("{spinner} planning [{bar:40}] {pos}%").expect("template"));
        b
    });
    let progress = |f: f64| {
        if let Some(b) = &bar {
            b.set_position((f * 100.0) as u64);
        }
        true
    };
    let stop = params.time_limit_s.map_or_else(Stop::never, |s| Stop::until(std::time::Instant::now() + Duration::from_secs_f64(s)));
    let output = planner::plan(&geometry, &params, &profiles, &FieldLimits::default(), &progress, &stop);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let output = output.map_err(|e| match e {
        PlanError::Cancelled if stop.timed_out() => anyhow::anyhow!("the plan took longer than its time_limit_s and was stopped"),
        e => anyhow::anyhow!("{e}"),
    })?;
    // the trajectory as the planner makes it, with the plan's figures as its properties
    let bytes = if export::find(format).is_some_and(|e| e.format().verbatim) {
        let mut collection = serde_json::to_value(&output.trajectory)?;
        collection["properties"] = serde_json::to_value(&output.stats)?;
        (serde_json::to_string_pretty(&collection)? + "\n").into_bytes()
    } else {
        let name = mission.get("name").and_then(Value::as_str).unwrap_or("mission");
        let request = ExportRequest { name, mission: geometry.clone(), params: &params, profiles: &profiles, trajectory: &output.trajectory, options };
        export::export(format, &request).map_err(|e| anyhow::anyhow!("{e}"))?.bytes
    };
    match out {
        Some(path) => std::fs::write(path, bytes).with_context(|| format!("writing {}", path.display()))?,
        None => std::io::stdout().write_all(&bytes)?,
    }
    let s = &output.stats;
    for warning in &s.warnings {
        eprintln!("coverplan: {warning}");
    }
    eprintln!(
        "{:.0} m, {:.0} s, {:.0} kJ, coverage {:.2} %, {} turns, {:.1} ms",
        s.length_m,
        s.duration_s,
        s.energy_j / 1000.0,
        s.coverage_ratio * 100.0,
        s.turns,
        s.planning_time_ms
    );
    Ok(())
}

/// A plain HTTP/1.0 request, so that the health check needs no client library.
fn healthcheck(addr: SocketAddr) -> anyhow::Result<()> {
    let mut stream = TcpStream::connect_timeout(&addr, Duration::from_secs(3)).with_context(|| format!("nothing answers on {addr}"))?;
    stream.set_read_timeout(Some(Duration::from_secs(3)))?;
    stream.write_all(b"GET /healthz HTTP/1.0\r\nHost: localhost\r\n\r\n")?;
    let mut response = String::new();
    stream.read_to_string(&mut response)?;
    let status_line = response.lines().next().unwrap_or_default();
    anyhow::ensure!(status_line.split_whitespace().nth(1) == Some("200"), "unhealthy: {status_line}");
    Ok(())
}
