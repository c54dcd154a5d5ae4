//! Vehicle profiles. The built-ins are shared by every tenant (stored with tenant `''`) and
//! inserted at start-up when missing, so an operator's edits to them survive restarts; they
//! cannot be deleted. Every other profile belongs to the tenant that made it, and its id may
//! not be a built-in's.

use serde::Serialize;
use sqlx::FromRow;
use sqlx::types::Json;
use utoipa::ToSchema;

use super::{Db, Statement, WritePool};
use crate::on_db;
use crate::planner::vehicle::{Vehicle, builtin_profiles};

/// A stored profile.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct StoredVehicle {
    #[serde(flatten)]
    pub vehicle: Vehicle,
    /// Shipped with coverplan: can be edited, not deleted.
    pub builtin: bool,
    pub created_at: String,
    pub updated_at: String,
}

/// A row of `vehicles`.
#[derive(FromRow)]
struct VehicleRow {
    body: Json<Vehicle>,
    builtin: bool,
    created_at: String,
    updated_at: String,
}

impl From<VehicleRow> for StoredVehicle {
    fn from(r: VehicleRow) -> Self {
        StoredVehicle { vehicle: r.body.0, builtin: r.builtin, created_at: r.created_at, updated_at: r.updated_at }
    }
}

macro_rules! columns {
    () => {
        "body, builtin, created_at, updated_at"
    };
}

/// The tenant of the built-in profiles.
const SHARED: &str = "";

pub async fn insert_builtins(db: &Db) -> Result<(), sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        for v in builtin_profiles() {
            sqlx::query(sql(Statement {
                sqlite: concat!(
                    "INSERT INTO vehicles (tenant, id, builtin, body, created_at, updated_at) VALUES ('', ?, TRUE, ?, ",
                    crate::sqlite_now!(),
                    ", ",
                    crate::sqlite_now!(),
                    ") ON CONFLICT DO NOTHING"
                ),
                postgres: concat!(
                    "INSERT INTO vehicles (tenant, id, builtin, body, created_at, updated_at) VALUES ('', $1, TRUE, $2, ",
                    crate::postgres_now!(),
                    ", ",
                    crate::postgres_now!(),
                    ") ON CONFLICT DO NOTHING"
                ),
            }))
            .bind(&v.profile)
            .bind(Json(&v))
            .execute(&mut *tx)
            .await?;
        }
        tx.commit().await
    })
}

/// The built-ins and `tenant`'s own profiles.
pub async fn list(db: &Db, tenant: &str) -> Result<Vec<StoredVehicle>, sqlx::Error> {
    let rows: Vec<VehicleRow> = on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: concat!("SELECT ", columns!(), " FROM vehicles WHERE tenant IN ('', ?) ORDER BY builtin DESC, id"),
        postgres: concat!("SELECT ", columns!(), " FROM vehicles WHERE tenant IN ('', $1) ORDER BY builtin DESC, id")
    }))
    .bind(tenant)
    .fetch_all(pool)
    .await?);
    Ok(rows.into_iter().map(Into::into).collect())
}

/// Every profile `tenant` may name, for resolving a plan's `vehicle.profile`.
pub async fn profiles(db: &Db, tenant: &str) -> Result<Vec<Vehicle>, sqlx::Error> {
    Ok(list(db, tenant).await?.into_iter().map(|v| v.vehicle).collect())
}

/// A built-in or one of `tenant`'s profiles.
pub async fn get(db: &Db, tenant: &str, id: &str) -> Result<Option<StoredVehicle>, sqlx::Error> {
    let row: Option<VehicleRow> = on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: concat!("SELECT ", columns!(), " FROM vehicles WHERE id = ? AND tenant IN ('', ?)"),
        postgres: concat!("SELECT ", columns!(), " FROM vehicles WHERE id = $1 AND tenant IN ('', $2)")
    }))
    .bind(id)
    .bind(tenant)
    .fetch_optional(pool)
    .await?);
    Ok(row.map(Into::into))
}

/// Inserts a new profile of `tenant`'s; `None` when its id is a built-in's or one of the
/// tenant's own.
pub async fn create(db: &Db, tenant: &str, v: &Vehicle) -> Result<Option<StoredVehicle>, sqlx::Error> {
    let row: Option<VehicleRow> = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let taken: bool = sqlx::query_scalar(sql(Statement {
            sqlite: "SELECT EXISTS (SELECT 1 FROM vehicles WHERE id = ? AND tenant IN ('', ?))",
            postgres: "SELECT EXISTS (SELECT 1 FROM vehicles WHERE id = $1 AND tenant IN ('', $2))",
        }))
        .bind(&v.profile)
        .bind(tenant)
        .fetch_one(&mut *tx)
        .await?;
        if taken {
            return Ok(None);
        }
        // a concurrent insert of the same id inserts nothing here
        let row = sqlx::query_as(sql(Statement {
            sqlite: concat!(
                "INSERT INTO vehicles (tenant, id, builtin, body, created_at, updated_at) VALUES (?, ?, FALSE, ?, ",
                crate::sqlite_now!(),
                ", ",
                crate::sqlite_now!(),
                ") ON CONFLICT DO NOTHING RETURNING ",
                columns!()
            ),
            postgres: concat!(
                "INSERT INTO vehicles (tenant, id, builtin, body, created_at, updated_at) VALUES ($1, $2, FALSE, $3, ",
                crate::postgres_now!(),
                ", ",
                crate::postgres_now!(),
                ") ON CONFLICT DO NOTHING RETURNING ",
                columns!()
            ),
        }))
        .bind(tenant)
        .bind(&v.profile)
        .bind(Json(v))
        .fetch_optional(&mut *tx)
        .await?;
        tx.commit().await?;
        row
    });
    Ok(row.map(Into::into))
}

/// Replaces the figures of one of `tenant`'s profiles, or of a built-in when `tenant` is
/// `None` (an administrator); `None` when there is no such profile.
pub async fn update(db: &Db, tenant: Option<&str>, id: &str, v: &Vehicle) -> Result<Option<StoredVehicle>, sqlx::Error> {
    let row: Option<VehicleRow> = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let row = sqlx::query_as(sql(Statement {
            sqlite: concat!("UPDATE vehicles SET body = ?, updated_at = ", crate::sqlite_now!(), " WHERE id = ? AND tenant = ? RETURNING ", columns!()),
            postgres: concat!("UPDATE vehicles SET body = $1, updated_at = ", crate::postgres_now!(), " WHERE id = $2 AND tenant = $3 RETURNING ", columns!()),
        }))
        .bind(Json(v))
        .bind(id)
        .bind(tenant.unwrap_or(SHARED))
        .fetch_optional(&mut *tx)
        .await?;
        tx.commit().await?;
        row
    });
    Ok(row.map(Into::into))
}

pub enum Deleted {
    Yes,
    NotFound,
    Builtin,
}

/// Deletes one of `tenant`'s profiles (built-ins stay).
pub async fn delete(db: &Db, tenant: &str, id: &str) -> Result<Deleted, sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let builtin: Option<bool> = sqlx::query_scalar(sql(Statement {
            sqlite: "SELECT builtin FROM vehicles WHERE id = ? AND tenant IN ('', ?)",
            postgres: "SELECT builtin FROM vehicles WHERE id = $1 AND tenant IN ('', $2)",
        }))
        .bind(id)
        .bind(tenant)
        .fetch_optional(&mut *tx)
        .await?;
        let outcome = match builtin {
            None => Deleted::NotFound,
            Some(true) => Deleted::Builtin,
            Some(false) => {
                sqlx::query(sql(Statement { sqlite: "DELETE FROM vehicles WHERE id = ? AND tenant = ?", postgres: "DELETE FROM vehicles WHERE id = $1 AND tenant = $2" }))
                    .bind(id)
                    .bind(tenant)
                    .execute(&mut *tx)
                    .await?;
                Deleted::Yes
            }
        };
        tx.commit().await?;
        Ok(outcome)
    })
}
