//! Missions: a name and the geometry to cover, as the client sent it. Each belongs to a
//! tenant; every query is scoped to one.

use serde::Serialize;
use serde_json::Value;
use sqlx::FromRow;
use sqlx::types::Json;
use utoipa::ToSchema;

use super::{Db, Statement, WritePool, new_id};
use crate::on_db;
use crate::planner::MissionGeometry;
use crate::planner::terrain::ElevationModel;

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
    /// Structures to inspect: features with `height_m`, `base_m` and `name`.
    #[schema(value_type = Option<Object>)]
    pub structures: Option<Value>,
    /// [longitude, latitude]
    #[schema(min_items = 2, max_items = 2)]
    pub home: Option<[f64; 2]>,
    pub created_at: String,
    pub updated_at: String,
}

impl Mission {
    /// The planner's view of the mission, over `terrain` when given.
    pub fn geometry<'a>(&'a self, terrain: Option<&'a ElevationModel>) -> MissionGeometry<'a> {
        MissionGeometry {
            area: &self.area,
            no_fly_zones: self.no_fly_zones.as_ref(),
            obstacles: self.obstacles.as_ref(),
            structures: self.structures.as_ref(),
            home: self.home,
            terrain,
        }
    }
}

/// A mission without its geometry, for lists that show names.
#[derive(Debug, Clone, Serialize, ToSchema, FromRow)]
pub struct MissionSummary {
    pub id: String,
    pub name: String,
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
    pub structures: Option<Value>,
    pub home: Option<[f64; 2]>,
}

/// A row of `missions`.
#[derive(FromRow)]
struct MissionRow {
    id: String,
    name: String,
    area: Json<Value>,
    no_fly_zones: Option<Json<Value>>,
    obstacles: Option<Json<Value>>,
    structures: Option<Json<Value>>,
    home_lon: Option<f64>,
    home_lat: Option<f64>,
    created_at: String,
    updated_at: String,
}

impl From<MissionRow> for Mission {
    fn from(r: MissionRow) -> Self {
        Mission {
            id: r.id,
            name: r.name,
            area: r.area.0,
            no_fly_zones: r.no_fly_zones.map(|j| j.0),
            obstacles: r.obstacles.map(|j| j.0),
            structures: r.structures.map(|j| j.0),
            home: r.home_lon.zip(r.home_lat).map(|(lon, lat)| [lon, lat]),
            created_at: r.created_at,
            updated_at: r.updated_at,
        }
    }
}

macro_rules! columns {
    () => {
        "id, name, area, no_fly_zones, obstacles, structures, home_lon, home_lat, created_at, updated_at"
    };
}

/// Binds a mission's content in the order `name, area, no_fly_zones, obstacles, structures, home_lon, home_lat`.
macro_rules! bind_content {
    ($query:expr, $m:expr) => {
        $query
            .bind(&$m.name)
            .bind(Json(&$m.area))
            .bind($m.no_fly_zones.as_ref().map(Json))
            .bind($m.obstacles.as_ref().map(Json))
            .bind($m.structures.as_ref().map(Json))
            .bind($m.home.map(|h| h[0]))
            .bind($m.home.map(|h| h[1]))
    };
}

pub async fn create(db: &Db, tenant: &str, m: &NewMission) -> Result<Mission, sqlx::Error> {
    let id = new_id();
    let row: MissionRow = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let query = sqlx::query_as(sql(Statement {
            sqlite: concat!(
                "INSERT INTO missions (id, tenant, name, area, no_fly_zones, obstacles, structures, home_lon, home_lat, created_at, updated_at)
         VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ",
                crate::sqlite_now!(),
                ", ",
                crate::sqlite_now!(),
                ") RETURNING ",
                columns!()
            ),
            postgres: concat!(
                "INSERT INTO missions (id, tenant, name, area, no_fly_zones, obstacles, structures, home_lon, home_lat, created_at, updated_at)
         VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, ",
                crate::postgres_now!(),
                ", ",
                crate::postgres_now!(),
                ") RETURNING ",
                columns!()
            ),
        }));
        let row = bind_content!(query.bind(&id).bind(tenant), m).fetch_one(&mut *tx).await?;
        tx.commit().await?;
        row
    });
    Ok(row.into())
}

/// A mission of `tenant`'s; another tenant's is `None`, as one that does not exist.
pub async fn get(db: &Db, tenant: &str, id: &str) -> Result<Option<Mission>, sqlx::Error> {
    let row: Option<MissionRow> = on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: concat!("SELECT ", columns!(), " FROM missions WHERE id = ? AND tenant = ?"),
        postgres: concat!("SELECT ", columns!(), " FROM missions WHERE id = $1 AND tenant = $2")
    }))
    .bind(id)
    .bind(tenant)
    .fetch_optional(pool)
    .await?);
    Ok(row.map(Into::into))
}

/// How many missions a tenant has, for the pages' totals.
async fn count(db: &Db, tenant: &str) -> Result<i64, sqlx::Error> {
    on_db!(db, |pool, sql| sqlx::query_scalar(sql(Statement {
        sqlite: "SELECT COUNT(*) FROM missions WHERE tenant = ?",
        postgres: "SELECT COUNT(*) FROM missions WHERE tenant = $1"
    }))
    .bind(tenant)
    .fetch_one(pool)
    .await)
}

/// A page of a tenant's rows read by `select` (which ends `WHERE tenant = ? … LIMIT ? OFFSET ?`),
/// and the tenant's total count.
macro_rules! page {
    ($db:expr, $select:expr, $tenant:expr, $limit:expr, $offset:expr) => {{
        let rows = on_db!($db, |pool, sql| sqlx::query_as(sql($select)).bind($tenant).bind($limit).bind($offset).fetch_all(pool).await?);
        (rows, count($db, $tenant).await?)
    }};
}

/// A page of a tenant's missions, newest first, and the total count.
pub async fn list(db: &Db, tenant: &str, limit: i64, offset: i64) -> Result<(Vec<Mission>, i64), sqlx::Error> {
    let select = Statement {
        sqlite: concat!("SELECT ", columns!(), " FROM missions WHERE tenant = ? ORDER BY created_at DESC, rowid DESC LIMIT ? OFFSET ?"),
        postgres: concat!("SELECT ", columns!(), " FROM missions WHERE tenant = $1 ORDER BY created_at DESC, seq DESC LIMIT $2 OFFSET $3"),
    };
    let (rows, total): (Vec<MissionRow>, i64) = page!(db, select, tenant, limit, offset);
    Ok((rows.into_iter().map(Into::into).collect(), total))
}

/// A page of a tenant's mission summaries, newest first, and the total count.
pub async fn list_summaries(db: &Db, tenant: &str, limit: i64, offset: i64) -> Result<(Vec<MissionSummary>, i64), sqlx::Error> {
    Ok(page!(
        db,
        Statement {
            sqlite: "SELECT id, name, created_at, updated_at FROM missions WHERE tenant = ? ORDER BY created_at DESC, rowid DESC LIMIT ? OFFSET ?",
            postgres: "SELECT id, name, created_at, updated_at FROM missions WHERE tenant = $1 ORDER BY created_at DESC, seq DESC LIMIT $2 OFFSET $3"
        },
        tenant,
        limit,
        offset
    ))
}

/// Replaces a mission's content; `None` when the tenant has no such mission.
pub async fn update(db: &Db, tenant: &str, id: &str, m: &NewMission) -> Result<Option<Mission>, sqlx::Error> {
    let row: Option<MissionRow> = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let query = sqlx::query_as(sql(Statement {
            sqlite: concat!(
                "UPDATE missions SET name = ?, area = ?, no_fly_zones = ?, obstacles = ?, structures = ?, home_lon = ?, home_lat = ?, updated_at = ",
                crate::sqlite_now!(),
                " WHERE id = ? AND tenant = ? RETURNING ",
                columns!()
            ),
            postgres: concat!(
                "UPDATE missions SET name = $1, area = $2, no_fly_zones = $3, obstacles = $4, structures = $5, home_lon = $6, home_lat = $7, updated_at = ",
                crate::postgres_now!(),
                " WHERE id = $8 AND tenant = $9 RETURNING ",
                columns!()
            ),
        }));
        let row = bind_content!(query, m).bind(id).bind(tenant).fetch_optional(&mut *tx).await?;
        tx.commit().await?;
        row
    });
    Ok(row.map(Into::into))
}

/// Deletes a mission and its plans; false when the tenant had none.
pub async fn delete(db: &Db, tenant: &str, id: &str) -> Result<bool, sqlx::Error> {
    let deleted = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let done = sqlx::query(sql(Statement { sqlite: "DELETE FROM missions WHERE id = ? AND tenant = ?", postgres: "DELETE FROM missions WHERE id = $1 AND tenant = $2" }))
            .bind(id)
            .bind(tenant)
            .execute(&mut *tx)
            .await?;
        tx.commit().await?;
        done.rows_affected()
    });
    Ok(deleted > 0)
}
