//! Vehicle profiles. The built-ins are inserted at start-up when missing, so an operator's
//! edits to them survive restarts; they cannot be deleted.

use serde::Serialize;
use sqlx::FromRow;
use sqlx::types::Json;
use utoipa::ToSchema;

use super::{Db, begin_write};
use crate::planner::vehicle::{Vehicle, builtin_profiles};
use crate::sql_now;

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

pub async fn insert_builtins(db: &Db) -> Result<(), sqlx::Error> {
    let mut tx = begin_write(db).await?;
    for v in builtin_profiles() {
        sqlx::query(concat!("INSERT OR IGNORE INTO vehicles (id, builtin, body, created_at, updated_at) VALUES (?, 1, ?, ", sql_now!(), ", ", sql_now!(), ")"))
            .bind(&v.profile)
            .bind(Json(&v))
            .execute(&mut *tx)
            .await?;
    }
    tx.commit().await
}

pub async fn list(db: &Db) -> Result<Vec<StoredVehicle>, sqlx::Error> {
    let rows: Vec<VehicleRow> = sqlx::query_as(concat!("SELECT ", columns!(), " FROM vehicles ORDER BY builtin DESC, id")).fetch_all(db).await?;
    Ok(rows.into_iter().map(Into::into).collect())
}

/// Every profile, for resolving a plan's `vehicle.profile`.
pub async fn profiles(db: &Db) -> Result<Vec<Vehicle>, sqlx::Error> {
    Ok(list(db).await?.into_iter().map(|v| v.vehicle).collect())
}

pub async fn get(db: &Db, id: &str) -> Result<Option<StoredVehicle>, sqlx::Error> {
    let row: Option<VehicleRow> = sqlx::query_as(concat!("SELECT ", columns!(), " FROM vehicles WHERE id = ?")).bind(id).fetch_optional(db).await?;
    Ok(row.map(Into::into))
}

/// Inserts a new profile; `None` when its id is taken.
pub async fn create(db: &Db, v: &Vehicle) -> Result<Option<StoredVehicle>, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let row: Option<VehicleRow> = sqlx::query_as(concat!(
        "INSERT OR IGNORE INTO vehicles (id, builtin, body, created_at, updated_at) VALUES (?, 0, ?, ",
        sql_now!(),
        ", ",
        sql_now!(),
        ") RETURNING ",
        columns!()
    ))
    .bind(&v.profile)
    .bind(Json(v))
    .fetch_optional(&mut *tx)
    .await?;
    tx.commit().await?;
    Ok(row.map(Into::into))
}

/// Replaces a profile's figures; `None` when there is no such profile.
pub async fn update(db: &Db, id: &str, v: &Vehicle) -> Result<Option<StoredVehicle>, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let row: Option<VehicleRow> = sqlx::query_as(concat!("UPDATE vehicles SET body = ?, updated_at = ", sql_now!(), " WHERE id = ? RETURNING ", columns!()))
        .bind(Json(v))
        .bind(id)
        .fetch_optional(&mut *tx)
        .await?;
    tx.commit().await?;
    Ok(row.map(Into::into))
}

pub enum Deleted {
    Yes,
    NotFound,
    Builtin,
}

pub async fn delete(db: &Db, id: &str) -> Result<Deleted, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let builtin: Option<i64> = sqlx::query_scalar("SELECT builtin FROM vehicles WHERE id = ?").bind(id).fetch_optional(&mut *tx).await?;
    let outcome = match builtin {
        None => Deleted::NotFound,
        Some(b) if b != 0 => Deleted::Builtin,
        Some(_) => {
            sqlx::query("DELETE FROM vehicles WHERE id = ?").bind(id).execute(&mut *tx).await?;
            Deleted::Yes
        }
    };
    tx.commit().await?;
    Ok(outcome)
}
