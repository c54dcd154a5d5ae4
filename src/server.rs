//! Starting and stopping the service: database, workers, HTTP.

use std::future::Future;
use std::net::SocketAddr;
use std::sync::Arc;

use tokio::net::TcpListener;

use crate::config::Config;
use crate::http::{AppState, router};
use crate::jobs::{self, JobQueue, Runner};
use crate::store;

/// Runs the server until `shutdown` completes, then drains the workers.
pub async fn run(config: Config, shutdown: impl Future<Output = ()> + Send + 'static) -> anyhow::Result<()> {
    let listener = TcpListener::bind(config.addr).await?;
    let (addr, served) = serve(listener, config, shutdown).await?;
    tracing::info!(%addr, "stopped");
    served
}

/// Serves on `listener`; returns the bound address and the outcome once stopped.
pub async fn serve(listener: TcpListener, config: Config, shutdown: impl Future<Output = ()> + Send + 'static) -> anyhow::Result<(SocketAddr, anyhow::Result<()>)> {
    let addr = listener.local_addr()?;
    let db = store::connect_with(&config.database_url, config.db_connections).await?;
    if !store::keys::required(&db).await? {
        anyhow::ensure!(!config.require_auth, "COVERPLAN_REQUIRE_AUTH is set but the database has no API key: make one with `coverplan keys create --tenant NAME`");
        tracing::warn!("no API key exists: the server is open, and every request acts for the `default` tenant (make a key with `coverplan keys create` to require keys)");
    }
    // SQLite has one server: what it left running, it left for good. Replicas on PostgreSQL
    // take over only plans whose lease ran out (the others are running elsewhere).
    let (requeued, failed) = store::plans::requeue_abandoned(&db, !db.is_postgres()).await?;
    if requeued + failed > 0 {
        tracing::warn!(requeued, failed, "plans interrupted by the last stop");
    }
    let limits = config.limits;
    let runner: Runner = Arc::new(move |job, request, progress, stop| jobs::plan_job(job, request, &limits, progress, stop));
    let (queue, workers) = JobQueue::start(db.clone(), config.workers, runner, config.queue.clone());
    // replicas hand their running plans back at once: another replica takes them now
    let grace = if db.is_postgres() { std::time::Duration::ZERO } else { config.shutdown_grace };
    let limiter = crate::http::auth::KeyLimiter::new(config.rate_limit);
    let state = AppState { db: db.clone(), jobs: queue.clone(), config: Arc::new(config), limiter };
    tracing::info!(%addr, workers = workers.len(), replica = %queue.replica, database = if db.is_postgres() { "postgres" } else { "sqlite" }, "coverplan listening");
    let result = axum::serve(listener, router(state)).with_graceful_shutdown(shutdown).await;
    queue.shutdown(workers, grace).await;
    db.close().await;
    Ok((addr, result.map_err(Into::into)))
}

/// Resolves on SIGTERM or Ctrl-C.
pub async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! { _ = ctrl_c => {}, _ = term => {} }
    tracing::info!("shutting down: no new jobs, finishing running ones");
}
