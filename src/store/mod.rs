//! Storage of API keys, missions, plans (the job queue too) and vehicle profiles, on one of two
//! backends behind one set of functions:
//!
//! - **SQLite** (the zero-setup default, one machine): WAL mode; every write transaction starts
//!   with `BEGIN IMMEDIATE`, so concurrent writers wait for the lock (busy timeout) instead of
//!   failing with "database is locked" when a read transaction tries to upgrade.
//! - **PostgreSQL** (`postgres://…`, several replicas sharing one database): JSON in `jsonb`,
//!   jobs claimed with `FOR UPDATE SKIP LOCKED`, queued jobs announced with `NOTIFY`.
//!
//! Each backend has its own migrations (`migrations/sqlite`, `migrations/postgres`) and its own
//! text of every statement ([`Statement`]: bind markers, the clock and the insertion order
//! differ, and claiming a job locks rows on PostgreSQL); nothing is rewritten at run time. Every
//! function runs on either pool through [`on_db!`], which picks the backend's text.

pub mod farms;
pub mod idempotency;
pub mod keys;
pub mod missions;
pub mod plans;
pub mod terrain;
pub mod vehicles;

use std::str::FromStr;
use std::time::Duration;

use sqlx::migrate::Migrator;
use sqlx::postgres::{PgConnectOptions, PgPool, PgPoolOptions};
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePool, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Postgres, Sqlite, Transaction};

/// The database: a pool of connections to one of the two backends.
#[derive(Debug, Clone)]
pub enum Db {
    Sqlite(SqlitePool),
    Postgres(PgPool),
}

/// One statement written out in each backend's dialect: bind markers (`?` and `$1, $2, …`),
/// the clock, and the insertion order (SQLite's `rowid`, PostgreSQL's `seq` column) differ.
#[derive(Debug, Clone, Copy)]
pub struct Statement {
    pub sqlite: &'static str,
    pub postgres: &'static str,
}

/// Runs `$body` once for whichever backend `$db` is, with `$pool` bound to its pool and `$sql`
/// to the function that picks a [`Statement`]'s text for that backend.
#[macro_export]
macro_rules! on_db {
    ($db:expr, |$pool:ident, $sql:ident| $body:expr) => {
        match $db {
            $crate::store::Db::Sqlite($pool) => {
                let $sql = |s: $crate::store::Statement| s.sqlite;
                $body
            }
            $crate::store::Db::Postgres($pool) => {
                let $sql = |s: $crate::store::Statement| s.postgres;
                $body
            }
        }
    };
}

/// SQLite's "now" as RFC 3339 UTC with milliseconds (a macro, so that statements stay literals).
#[macro_export]
macro_rules! sqlite_now {
    () => {
        "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')"
    };
}

/// PostgreSQL's "now" in the same form as [`sqlite_now!`].
#[macro_export]
macro_rules! postgres_now {
    () => {
        r#"to_char(now() AT TIME ZONE 'UTC', 'YYYY-MM-DD"T"HH24:MI:SS.MS"Z"')"#
    };
}

/// SQLite's "now" in seconds since 1970, for leases (compared as numbers on both backends).
#[macro_export]
macro_rules! sqlite_epoch {
    () => {
        "((julianday('now') - 2440587.5) * 86400.0)"
    };
}

/// PostgreSQL's "now" in seconds since 1970: the wall clock, not the transaction's start, as a
/// lease is measured from when it is written.
#[macro_export]
macro_rules! postgres_epoch {
    () => {
        "extract(epoch FROM clock_timestamp())::double precision"
    };
}

/// The schema migrations of each backend, embedded in the binary at build time.
pub static MIGRATOR: Migrator = sqlx::migrate!("./migrations/sqlite");
pub static POSTGRES_MIGRATOR: Migrator = sqlx::migrate!("./migrations/postgres");

/// How long a statement may run on PostgreSQL before the server cancels it.
const STATEMENT_TIMEOUT: &str = "30s";

/// True for a URL that names a PostgreSQL database.
pub fn is_postgres(url: &str) -> bool {
    url.starts_with("postgres://") || url.starts_with("postgresql://")
}

/// Opens the database at `url` (`sqlite:…`, created if missing, or `postgres://…`), runs the
/// migrations and inserts the built-in vehicle profiles.
pub async fn connect(url: &str) -> Result<Db, sqlx::Error> {
    connect_with(url, 8).await
}

/// As [`connect`], with at most `connections` pooled connections.
pub async fn connect_with(url: &str, connections: u32) -> Result<Db, sqlx::Error> {
    let db = if is_postgres(url) {
        let options = PgConnectOptions::from_str(url)?.options([("statement_timeout", STATEMENT_TIMEOUT)]).application_name("coverplan");
        let pool = PgPoolOptions::new().max_connections(connections).acquire_timeout(Duration::from_secs(10)).connect_with(options).await?;
        POSTGRES_MIGRATOR.run(&pool).await?;
        Db::Postgres(pool)
    } else {
        let options = SqliteConnectOptions::from_str(url)?
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            .synchronous(SqliteSynchronous::Normal)
            .foreign_keys(true)
            .busy_timeout(Duration::from_secs(30));
        let pool = SqlitePoolOptions::new().max_connections(connections).connect_with(options).await?;
        MIGRATOR.run(&pool).await?;
        Db::Sqlite(pool)
    };
    vehicles::insert_builtins(&db).await?;
    Ok(db)
}

impl Db {
    pub fn is_postgres(&self) -> bool {
        matches!(self, Db::Postgres(_))
    }

    /// True when the database answers.
    pub async fn ping(&self) -> bool {
        on_db!(self, |pool, _sql| sqlx::query("SELECT 1").execute(pool).await.is_ok())
    }

    pub async fn close(&self) {
        on_db!(self, |pool, _sql| pool.close().await)
    }
}

/// A pool whose write transactions hold what they write from their first statement.
pub trait WritePool {
    type Database: sqlx::Database;
    fn begin_write(&self) -> impl Future<Output = Result<Transaction<'static, Self::Database>, sqlx::Error>> + Send;
}

impl WritePool for SqlitePool {
    type Database = Sqlite;
    /// `BEGIN IMMEDIATE`: takes the write lock at once.
    async fn begin_write(&self) -> Result<Transaction<'static, Sqlite>, sqlx::Error> {
        self.begin_with("BEGIN IMMEDIATE").await
    }
}

impl WritePool for PgPool {
    type Database = Postgres;
    /// Row locks are taken by the statements themselves (`UPDATE`, `FOR UPDATE`).
    async fn begin_write(&self) -> Result<Transaction<'static, Postgres>, sqlx::Error> {
        self.begin().await
    }
}

/// Runs `op` again, up to three more times after short pauses, while it fails in a way that
/// may pass: a serialization failure or deadlock (PostgreSQL's 40001, 40P01), a lost
/// connection, or no free connection in time. For writes that must not be lost (a plan's
/// outcome); each attempt is a whole transaction.
pub async fn retrying<T, F, Fut>(mut op: F) -> Result<T, sqlx::Error>
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Result<T, sqlx::Error>>,
{
    let mut attempt = 0;
    loop {
        match op().await {
            Err(e) if attempt < 3 && is_transient(&e) => {
                attempt += 1;
                tracing::warn!(error = %e, attempt, "retrying a database write");
                tokio::time::sleep(Duration::from_millis(100 * attempt)).await;
            }
            done => return done,
        }
    }
}

fn is_transient(e: &sqlx::Error) -> bool {
    match e {
        sqlx::Error::Database(db) => matches!(db.code().as_deref(), Some("40001" | "40P01")),
        sqlx::Error::Io(_) | sqlx::Error::PoolTimedOut => true,
        _ => false,
    }
}

pub fn new_id() -> String {
    uuid::Uuid::new_v4().to_string()
}
