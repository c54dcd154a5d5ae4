//! API keys: each belongs to a tenant, whose missions, plans and vehicle profiles it reaches.
//!
//! A key reads `cpk_<id>_<secret>`. The id is public (lists and logs show it); of the secret only
//! its SHA-256 is stored, and a presented secret is compared with it in constant time. Secrets
//! are 244 random bits (two version-4 UUIDs from the operating system's generator), so a fast
//! hash is enough: there is nothing to guess that a slow one would protect.

use serde::Serialize;
use sha2::{Digest, Sha256};
use sqlx::FromRow;
use subtle::ConstantTimeEq;

use super::{Db, Statement, WritePool};
use crate::on_db;

const PREFIX: &str = "cpk_";

/// Who a request acts for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Caller {
    pub tenant: String,
    /// May edit what all tenants share (the built-in vehicle profiles) and read the metrics.
    pub admin: bool,
    /// The key's public id; `None` on a server without keys.
    pub key_id: Option<String>,
}

/// The tenant every mission belongs to on a server without keys.
pub const OPEN_TENANT: &str = "default";

impl Caller {
    /// Anyone, on a server without keys: the open tenant, with every right.
    pub fn open() -> Self {
        Caller { tenant: OPEN_TENANT.into(), admin: true, key_id: None }
    }
}

/// A key as listed (never its secret).
#[derive(Debug, Clone, Serialize, FromRow)]
pub struct KeyInfo {
    pub id: String,
    pub tenant: String,
    pub admin: bool,
    pub created_at: String,
    pub revoked_at: Option<String>,
}

/// A tenant name: 1 to 64 letters, digits, `-`, `_` or `.`.
pub fn valid_tenant(name: &str) -> bool {
    (1..=64).contains(&name.len()) && name.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
}

fn hash(secret: &str) -> String {
    hex::encode(Sha256::digest(secret.as_bytes()))
}

/// Makes a key for `tenant`; returns its description and the key itself, which is not stored.
pub async fn create(db: &Db, tenant: &str, admin: bool) -> Result<(KeyInfo, String), sqlx::Error> {
    let id = uuid::Uuid::new_v4().simple().to_string()[..12].to_owned();
    let secret = format!("{}{}", uuid::Uuid::new_v4().simple(), uuid::Uuid::new_v4().simple());
    let info: KeyInfo = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let info = sqlx::query_as(sql(Statement {
            sqlite: concat!(
                "INSERT INTO api_keys (id, tenant, admin, secret_hash, created_at) VALUES (?, ?, ?, ?, ",
                crate::sqlite_now!(),
                ") RETURNING id, tenant, admin, created_at, revoked_at"
            ),
            postgres: concat!(
                "INSERT INTO api_keys (id, tenant, admin, secret_hash, created_at) VALUES ($1, $2, $3, $4, ",
                crate::postgres_now!(),
                ") RETURNING id, tenant, admin, created_at, revoked_at"
            ),
        }))
        .bind(&id)
        .bind(tenant)
        .bind(admin)
        .bind(hash(&secret))
        .fetch_one(&mut *tx)
        .await?;
        tx.commit().await?;
        info
    });
    Ok((info, format!("{PREFIX}{id}_{secret}")))
}

pub async fn list(db: &Db) -> Result<Vec<KeyInfo>, sqlx::Error> {
    on_db!(db, |pool, _sql| sqlx::query_as("SELECT id, tenant, admin, created_at, revoked_at FROM api_keys ORDER BY created_at, id").fetch_all(pool).await)
}

/// Revokes a key; false when there is no such key or it was revoked already.
pub async fn revoke(db: &Db, id: &str) -> Result<bool, sqlx::Error> {
    let revoked = on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        let done = sqlx::query(sql(Statement {
            sqlite: concat!("UPDATE api_keys SET revoked_at = ", crate::sqlite_now!(), " WHERE id = ? AND revoked_at IS NULL"),
            postgres: concat!("UPDATE api_keys SET revoked_at = ", crate::postgres_now!(), " WHERE id = $1 AND revoked_at IS NULL"),
        }))
        .bind(id)
        .execute(&mut *tx)
        .await?;
        tx.commit().await?;
        done.rows_affected()
    });
    Ok(revoked > 0)
}

/// True once any key was ever made: from then on every API request needs one (revoking the
/// last key does not open the server).
pub async fn required(db: &Db) -> Result<bool, sqlx::Error> {
    on_db!(db, |pool, _sql| sqlx::query_scalar("SELECT EXISTS (SELECT 1 FROM api_keys)").fetch_one(pool).await)
}

#[derive(FromRow)]
struct StoredKey {
    tenant: String,
    admin: bool,
    secret_hash: String,
}

/// The caller a presented key stands for; `None` for a malformed, unknown or revoked key.
pub async fn authenticate(db: &Db, presented: &str) -> Result<Option<Caller>, sqlx::Error> {
    let Some((id, secret)) = presented.strip_prefix(PREFIX).and_then(|rest| rest.split_once('_')) else { return Ok(None) };
    let stored: Option<StoredKey> = on_db!(db, |pool, sql| sqlx::query_as(sql(Statement {
        sqlite: "SELECT tenant, admin, secret_hash FROM api_keys WHERE id = ? AND revoked_at IS NULL",
        postgres: "SELECT tenant, admin, secret_hash FROM api_keys WHERE id = $1 AND revoked_at IS NULL"
    }))
    .bind(id)
    .fetch_optional(pool)
    .await?);
    Ok(stored.filter(|k| bool::from(k.secret_hash.as_bytes().ct_eq(hash(secret).as_bytes()))).map(|k| Caller { tenant: k.tenant, admin: k.admin, key_id: Some(id.to_owned()) }))
}
