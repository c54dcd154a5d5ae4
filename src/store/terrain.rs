//! A mission's elevation model: the file as uploaded, and what was read from it. One per
//! mission, deleted with it; reached only through a mission of the caller's tenant.

use serde_json::Value;
use sqlx::FromRow;
use sqlx::types::Json;

use super::{Db, Statement, WritePool};
use crate::on_db;

/// What is stored about a model besides its bytes.
#[derive(Debug, Clone, FromRow)]
pub struct TerrainRecord {
    pub file_name: String,
    pub summary: Json<Value>,
    pub created_at: String,
}

/// Stores (or replaces) the model of `tenant`'s mission `mission_id`; false when the tenant has
/// no such mission (nothing is written).
pub async fn put(db: &Db, tenant: &str, mission_id: &str, file_name: &str, model: &[u8], summary: &Value) -> Result<Option<TerrainRecord>, sqlx::Error> {
    Ok(on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let owned: Option<i32> = sqlx::query_scalar(sql(Statement {
            sqlite: "SELECT 1 FROM missions WHERE id = ? AND tenant = ?",
            postgres: "SELECT 1 FROM missions WHERE id = $1 AND tenant = $2 FOR UPDATE",
        }))
        .bind(mission_id)
        .bind(tenant)
        .fetch_optional(&mut *tx)
        .await?;
        if owned.is_none() {
            return Ok(None);
        }
        let record: TerrainRecord = sqlx::query_as(sql(Statement {
            sqlite: concat!(
                "INSERT INTO mission_terrain (mission_id, file_name, model, summary, created_at) VALUES (?, ?, ?, ?, ",
                crate::sqlite_now!(),
                ") ON CONFLICT (mission_id) DO UPDATE SET file_name = excluded.file_name, model = excluded.model, summary = excluded.summary, created_at = excluded.created_at
                 RETURNING file_name, summary, created_at"
            ),
            postgres: concat!(
                "INSERT INTO mission_terrain (mission_id, file_name, model, summary, created_at) VALUES ($1, $2, $3, $4, ",
                crate::postgres_now!(),
                ") ON CONFLICT (mission_id) DO UPDATE SET file_name = excluded.file_name, model = excluded.model, summary = excluded.summary, created_at = excluded.created_at
                 RETURNING file_name, summary, created_at"
            ),
        }))
        .bind(mission_id)
        .bind(file_name)
        .bind(model)
        .bind(Json(summary))
        .fetch_one(&mut *tx)
        .await?;
        tx.commit().await?;
        Some(record)
    }))
}

/// What is stored about the model of `tenant`'s mission, without its bytes.
pub async fn get(db: &Db, tenant: &str, mission_id: &str) -> Result<Option<TerrainRecord>, sqlx::Error> {
    on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: "SELECT t.file_name, t.summary, t.created_at FROM mission_terrain t JOIN missions m ON m.id = t.mission_id WHERE t.mission_id = ? AND m.tenant = ?",
        postgres: "SELECT t.file_name, t.summary, t.created_at FROM mission_terrain t JOIN missions m ON m.id = t.mission_id WHERE t.mission_id = $1 AND m.tenant = $2",
    }))
    .bind(mission_id)
    .bind(tenant)
    .fetch_optional(pool)
    .await)
}

/// The model's file name and bytes.
pub async fn model(db: &Db, tenant: &str, mission_id: &str) -> Result<Option<(String, Vec<u8>)>, sqlx::Error> {
    on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: "SELECT t.file_name, t.model FROM mission_terrain t JOIN missions m ON m.id = t.mission_id WHERE t.mission_id = ? AND m.tenant = ?",
        postgres: "SELECT t.file_name, t.model FROM mission_terrain t JOIN missions m ON m.id = t.mission_id WHERE t.mission_id = $1 AND m.tenant = $2",
    }))
    .bind(mission_id)
    .bind(tenant)
    .fetch_optional(pool)
    .await)
}

/// Removes the model; false when the tenant's mission had none.
pub async fn delete(db: &Db, tenant: &str, mission_id: &str) -> Result<bool, sqlx::Error> {
    let deleted = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let done = sqlx::query(sql(Statement {
            sqlite: "DELETE FROM mission_terrain WHERE mission_id = (SELECT id FROM missions WHERE id = ? AND tenant = ?)",
            postgres: "DELETE FROM mission_terrain WHERE mission_id = (SELECT id FROM missions WHERE id = $1 AND tenant = $2)",
        }))
        .bind(mission_id)
        .bind(tenant)
        .execute(&mut *tx)
        .await?;
        tx.commit().await?;
        done.rows_affected()
    });
    Ok(deleted > 0)
}
