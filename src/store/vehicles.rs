//! Vehicle profiles. The built-ins are inserted at start-up when missing, so an operator's
//! edits to them survive restarts; they cannot be deleted.

use serde::Serialize;
use sqlx::Row;
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

fn from_row(r: &sqlx::sqlite::SqliteRow) -> Result<StoredVehicle, sqlx::Error> {
    let body: String = r.try_get("body")?;
    Ok(StoredVehicle {
        vehicle: serde_json::from_str(&body).map_err(|e| sqlx::Error::Decode(Box::new(e)))?,
        builtin: r.try_get::<i64, _>("builtin")? != 0,
        created_at: r.try_get("created_at")?,
        updated_at: r.try_get("updated_at")?,
    })
}

fn body(v: &Vehicle) -> String {
    serde_json::to_string(v).expect("a vehicle serialises")
}

pub async fn insert_builtins(db: &Db) -> Result<(), sqlx::Error> {
    let mut tx = begin_write(db).await?;
    for v in builtin_profiles() {
        sqlx::query(concat!("INSERT OR IGNORE INTO vehicles (id, builtin, body, created_at, updated_at) VALUES (?, 1, ?, ", sql_now!(), ", ", sql_now!(), ")"))
            .bind(&v.profile)
            .bind(body(&v))
            .execute(&mut *tx)
            .await?;
    }
    tx.commit().await
}

pub async fn list(db: &Db) -> Result<Vec<StoredVehicle>, sqlx::Error> {
    sqlx::query("SELECT * FROM vehicles ORDER BY builtin DESC, id").fetch_all(db).await?.iter().map(from_row).collect()
}

/// Every profile, for resolving a plan's `vehicle.profile`.
pub async fn profiles(db: &Db) -> Result<Vec<Vehicle>, sqlx::Error> {
    Ok(list(db).await?.into_iter().map(|v| v.vehicle).collect())
}

pub async fn get(db: &Db, id: &str) -> Result<Option<StoredVehicle>, sqlx::Error> {
    sqlx::query("SELECT * FROM vehicles WHERE id = ?").bind(id).fetch_optional(db).await?.as_ref().map(from_row).transpose()
}

/// Inserts a new profile; `None` when its id is taken.
pub async fn create(db: &Db, v: &Vehicle) -> Result<Option<StoredVehicle>, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let done = sqlx::query(concat!("INSERT OR IGNORE INTO vehicles (id, builtin, body, created_at, updated_at) VALUES (?, 0, ?, ", sql_now!(), ", ", sql_now!(), ")"))
        .bind(&v.profile)
        .bind(body(v))
        .execute(&mut *tx)
        .await?;
    tx.commit().await?;
    if done.rows_affected() == 0 {
        return Ok(None);
    }
    get(db, &v.profile).await
}

/// Replaces a profile's figures; `None` when there is no such profile.
pub async fn update(db: &Db, id: &str, v: &Vehicle) -> Result<Option<StoredVehicle>, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let done = sqlx::query(concat!("UPDATE vehicles SET body = ?, updated_at = ", sql_now!(), " WHERE id = ?")).bind(body(v)).bind(id).execute(&mut *tx).await?;
    tx.commit().await?;
    if done.rows_affected() == 0 {
        return Ok(None);
    }
    get(db, id).await
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
