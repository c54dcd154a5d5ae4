//! SQLite storage: API keys, missions, plans and vehicle profiles. WAL mode; every write transaction starts with
//! `BEGIN IMMEDIATE`, so concurrent writers wait for the lock (busy timeout) instead of
//! failing with "database is locked" when a read transaction tries to upgrade.

pub mod idempotency;
pub mod keys;
pub mod missions;
pub mod plans;
pub mod vehicles;

use std::str::FromStr;
use std::time::Duration;

use sqlx::migrate::Migrator;
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePool, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Sqlite, Transaction};

pub type Db = SqlitePool;

/// SQL for "now" as RFC 3339 UTC with milliseconds (a macro, so that queries stay literals).
#[macro_export]
macro_rules! sql_now {
    () => {
        "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')"
    };
}

/// The schema migrations of `migrations/`, embedded in the binary at build time.
pub static MIGRATOR: Migrator = sqlx::migrate!("./migrations");

/// Opens (creating it if missing) the database at `url` and runs the migrations.
pub async fn connect(url: &str) -> Result<Db, sqlx::Error> {
    let options = SqliteConnectOptions::from_str(url)?
        .create_if_missing(true)
        .journal_mode(SqliteJournalMode::Wal)
        .synchronous(SqliteSynchronous::Normal)
        .foreign_keys(true)
        .busy_timeout(Duration::from_secs(30));
    let pool = SqlitePoolOptions::new().max_connections(8).connect_with(options).await?;
    MIGRATOR.run(&pool).await?;
    vehicles::insert_builtins(&pool).await?;
    Ok(pool)
}

/// A write transaction that holds the write lock from its first statement.
pub async fn begin_write(db: &Db) -> Result<Transaction<'static, Sqlite>, sqlx::Error> {
    db.begin_with("BEGIN IMMEDIATE").await
}

pub fn new_id() -> String {
    uuid::Uuid::new_v4().to_string()
}
