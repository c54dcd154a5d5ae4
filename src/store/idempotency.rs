//! Idempotency keys (as Stripe's `Idempotency-Key`): the first answer to a POST sent with a key is
//! kept for a day and given again to every retry with the same key and the same request.

use sqlx::FromRow;

use super::{Db, Statement, WritePool};
use crate::on_db;

/// Where a request with a key stands.
pub enum Begin {
    /// First time: answer it, then [`finish`] (or [`forget`]).
    New,
    /// Answered before: this is the answer.
    Replay { status: u16, content_type: Option<String>, body: Vec<u8> },
    /// The first request with this key is still being answered.
    InProgress,
    /// The key was used for another request.
    Mismatch,
}

#[derive(FromRow)]
struct Kept {
    fingerprint: String,
    status: Option<i64>,
    content_type: Option<String>,
    body: Option<Vec<u8>>,
}

/// Takes `key` for a request with `fingerprint`. Keys older than a day are dropped first, and a
/// key left unanswered for five minutes (its server stopped mid-request) is taken again.
pub async fn begin(db: &Db, tenant: &str, key: &str, fingerprint: &str) -> Result<Begin, sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        sqlx::query(sql(Statement {
            sqlite: "DELETE FROM idempotency WHERE created_at < strftime('%Y-%m-%dT%H:%M:%fZ', 'now', '-1 day')",
            postgres: "DELETE FROM idempotency WHERE created_at < to_char((now() - interval '1 day') AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"')",
        }))
        .execute(&mut *tx)
        .await?;
        sqlx::query(sql(Statement { sqlite: "DELETE FROM idempotency WHERE status IS NULL AND created_at < strftime('%Y-%m-%dT%H:%M:%fZ', 'now', '-5 minutes')", postgres: "DELETE FROM idempotency WHERE status IS NULL AND created_at < to_char((now() - interval '5 minutes') AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"')" })).execute(&mut *tx).await?;
        let kept: Option<Kept> = sqlx::query_as(sql(Statement {
            sqlite: "SELECT fingerprint, status, content_type, body FROM idempotency WHERE tenant = ? AND key = ?",
            postgres: "SELECT fingerprint, status, content_type, body FROM idempotency WHERE tenant = $1 AND key = $2",
        }))
        .bind(tenant)
        .bind(key)
        .fetch_optional(&mut *tx)
        .await?;
        let outcome = match kept {
            Some(k) if k.fingerprint != fingerprint => Begin::Mismatch,
            Some(Kept { status: None, .. }) => Begin::InProgress,
            Some(Kept { status: Some(status), content_type, body, .. }) => Begin::Replay { status: status as u16, content_type, body: body.unwrap_or_default() },
            None => {
                // a concurrent first request with the same key inserts nothing here and is told so
                let inserted = sqlx::query(sql(Statement {
                    sqlite: concat!("INSERT INTO idempotency (tenant, key, fingerprint, created_at) VALUES (?, ?, ?, ", crate::sqlite_now!(), ") ON CONFLICT DO NOTHING"),
                    postgres: concat!("INSERT INTO idempotency (tenant, key, fingerprint, created_at) VALUES ($1, $2, $3, ", crate::postgres_now!(), ") ON CONFLICT DO NOTHING"),
                }))
                .bind(tenant)
                .bind(key)
                .bind(fingerprint)
                .execute(&mut *tx)
                .await?;
                if inserted.rows_affected() == 1 { Begin::New } else { Begin::InProgress }
            }
        };
        tx.commit().await?;
        Ok(outcome)
    })
}

/// Keeps the answer to the request that took `key`.
pub async fn finish(db: &Db, tenant: &str, key: &str, status: u16, content_type: Option<&str>, body: &[u8]) -> Result<(), sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        sqlx::query(sql(Statement {
            sqlite: "UPDATE idempotency SET status = ?, content_type = ?, body = ? WHERE tenant = ? AND key = ?",
            postgres: "UPDATE idempotency SET status = $1, content_type = $2, body = $3 WHERE tenant = $4 AND key = $5",
        }))
        .bind(i64::from(status))
        .bind(content_type)
        .bind(body)
        .bind(tenant)
        .bind(key)
        .execute(&mut *tx)
        .await?;
        tx.commit().await
    })
}

/// Frees `key` (the server failed to answer: a retry should try again).
pub async fn forget(db: &Db, tenant: &str, key: &str) -> Result<(), sqlx::Error> {
    on_db!(db, |pool, sql| {
        let mut tx = pool.begin_write().await?;
        sqlx::query(sql(Statement { sqlite: "DELETE FROM idempotency WHERE tenant = ? AND key = ?", postgres: "DELETE FROM idempotency WHERE tenant = $1 AND key = $2" }))
            .bind(tenant)
            .bind(key)
            .execute(&mut *tx)
            .await?;
        tx.commit().await
    })
}
