//! SQLite storage: missions, plans and vehicle profiles. WAL mode; every write transaction starts with
//! `BEGIN IMMEDIATE`, so concurrent writers wait for the lock (busy timeout) instead of
//! failing with "database is locked" when a read transaction tries to upgrade.

pub mod missions;
pub mod plans;
pub mod vehicles;

use std::str::FromStr;
use std::time::Duration;

use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePool, SqlitePoolOptions, SqliteSynchronous};
use sqlx::migrate::{Migration, MigrationType, Migrator};
use sqlx::{Sqlite, SqlSafeStr, Transaction};

pub type Db = SqlitePool;

/// SQL for "now" as RFC 3339 UTC with milliseconds (a macro, so that queries stay literals).
#[macro_export]
macro_rules! sql_now {
    () => {
        "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')"
    };
}

/// The schema migrations, embedded in the binary, in order.
const MIGRATIONS: &[(i64, &str, &str)] = &[
    (1, "init", include_str!("../../migrations/0001_init.sql")),
    (2, "obstacles", include_str!("../../migrations/0002_obstacles.sql")),
    (3, "vehicles", include_str!("../../migrations/0003_vehicles.sql")),
];

fn migrator() -> Migrator {
    Migrator::with_migrations(
        MIGRATIONS
            .iter()
            .map(|&(version, description, sql)| Migration::new(version, description.into(), MigrationType::Simple, sql.into_sql_str(), false))
            .collect(),
    )
}

/// Opens (creating it if missing) the database at `url` and runs the migrations.
pub async fn connect(url: &str) -> Result<Db, sqlx::Error> {
    let options = SqliteConnectOptions::from_str(url)?
        .create_if_missing(true)
        .journal_mode(SqliteJournalMode::Wal)
        .synchronous(SqliteSynchronous::Normal)
        .foreign_keys(true)
        .busy_timeout(Duration::from_secs(30));
    let pool = SqlitePoolOptions::new().max_connections(8).connect_with(options).await?;
    migrator().run(&pool).await?;
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
