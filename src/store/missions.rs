//! Missions: a name and the geometry to cover, as the client sent it.

use serde::Serialize;
use serde_json::Value;
use sqlx::Row;
use sqlx::sqlite::SqliteRow;
use utoipa::ToSchema;

use super::{Db, begin_write, new_id};

#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Mission {
    pub id: String,
    pub name: String,
    /// GeoJSON Polygon, MultiPolygon, Feature or FeatureCollection (WGS84).
    #[schema(value_type = Object)]
    pub area: Value,
    #[schema(value_type = Option<Object>)]
    pub no_fly_zones: Option<Value>,
    /// Polygon features with `height_m`.
    #[schema(value_type = Option<Object>)]
    pub obstacles: Option<Value>,
    /// [longitude, latitude]
    pub home: Option<[f64; 2]>,
    pub created_at: String,
    pub updated_at: String,
}

/// What a client writes.
#[derive(Debug, Clone)]
pub struct NewMission {
    pub name: String,
    pub area: Value,
    pub no_fly_zones: Option<Value>,
    pub obstacles: Option<Value>,
    pub home: Option<[f64; 2]>,
}

fn from_row(r: &SqliteRow) -> Result<Mission, sqlx::Error> {
    let json = |col: &str| -> Result<Option<Value>, sqlx::Error> {
        let text: Option<String> = r.try_get(col)?;
        text.map(|t| serde_json::from_str(&t).map_err(|e| sqlx::Error::Decode(Box::new(e)))).transpose()
    };
    let lon: Option<f64> = r.try_get("home_lon")?;
    let lat: Option<f64> = r.try_get("home_lat")?;
    Ok(Mission {
        id: r.try_get("id")?,
        name: r.try_get("name")?,
        area: json("area")?.unwrap_or(Value::Null),
        no_fly_zones: json("no_fly_zones")?,
        obstacles: json("obstacles")?,
        home: lon.zip(lat).map(|(a, b)| [a, b]),
        created_at: r.try_get("created_at")?,
        updated_at: r.try_get("updated_at")?,
    })
}

pub async fn create(db: &Db, m: &NewMission) -> Result<Mission, sqlx::Error> {
    let id = new_id();
    let mut tx = begin_write(db).await?;
    sqlx::query(concat!(
        "INSERT INTO missions (id, name, area, no_fly_zones, obstacles, home_lon, home_lat, created_at, updated_at)
         VALUES (?, ?, ?, ?, ?, ?, ?, ", crate::sql_now!(), ", ", crate::sql_now!(), ")"
    ))
    .bind(&id)
    .bind(&m.name)
    .bind(m.area.to_string())
    .bind(m.no_fly_zones.as_ref().map(Value::to_string))
    .bind(m.obstacles.as_ref().map(Value::to_string))
    .bind(m.home.map(|h| h[0]))
    .bind(m.home.map(|h| h[1]))
    .execute(&mut *tx)
    .await?;
    tx.commit().await?;
    Ok(get(db, &id).await?.expect("just inserted"))
}

pub async fn get(db: &Db, id: &str) -> Result<Option<Mission>, sqlx::Error> {
    sqlx::query("SELECT * FROM missions WHERE id = ?").bind(id).fetch_optional(db).await?.map(|r| from_row(&r)).transpose()
}

/// A page of missions, newest first, and the total count.
pub async fn list(db: &Db, limit: i64, offset: i64) -> Result<(Vec<Mission>, i64), sqlx::Error> {
    let rows = sqlx::query("SELECT * FROM missions ORDER BY created_at DESC, rowid DESC LIMIT ? OFFSET ?")
        .bind(limit)
        .bind(offset)
        .fetch_all(db)
        .await?;
    let total: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM missions").fetch_one(db).await?;
    Ok((rows.iter().map(from_row).collect::<Result<_, _>>()?, total))
}

/// Replaces a mission's content; `None` when there is no such mission.
pub async fn update(db: &Db, id: &str, m: &NewMission) -> Result<Option<Mission>, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let done = sqlx::query(concat!(
        "UPDATE missions SET name = ?, area = ?, no_fly_zones = ?, obstacles = ?, home_lon = ?, home_lat = ?, updated_at = ", crate::sql_now!(), " WHERE id = ?"
    ))
    .bind(&m.name)
    .bind(m.area.to_string())
    .bind(m.no_fly_zones.as_ref().map(Value::to_string))
    .bind(m.obstacles.as_ref().map(Value::to_string))
    .bind(m.home.map(|h| h[0]))
    .bind(m.home.map(|h| h[1]))
    .bind(id)
    .execute(&mut *tx)
    .await?;
    tx.commit().await?;
    if done.rows_affected() == 0 {
        return Ok(None);
    }
    get(db, id).await
}

/// Deletes a mission and its plans; false when there was none.
pub async fn delete(db: &Db, id: &str) -> Result<bool, sqlx::Error> {
    let mut tx = begin_write(db).await?;
    let done = sqlx::query("DELETE FROM missions WHERE id = ?").bind(id).execute(&mut *tx).await?;
    tx.commit().await?;
    Ok(done.rows_affected() > 0)
}
