//! `Idempotency-Key` on every `POST /api/…`: a client that retries a request whose answer it
//! lost (a timeout, a dropped connection) gets the first answer again instead of a second
//! mission or plan. The same key with another request is 422; while the first request is still
//! being answered, 409. Answers of 5xx are not kept, so a retry tries again.

use axum::body::{Body, to_bytes};
use axum::extract::{Request, State};
use axum::http::{HeaderValue, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use sha2::{Digest, Sha256};

use super::AppState;
use super::auth::Caller;
use super::error::ApiError;
use crate::store::idempotency::{self, Begin};

pub const HEADER: &str = "idempotency-key";
/// Set on a replayed answer.
pub const REPLAYED: &str = "idempotent-replayed";

fn refuse(status: StatusCode, code: &'static str, detail: impl Into<String>) -> Response {
    ApiError::Client { status, code, detail: detail.into(), pointer: None }.into_response()
}

/// What makes two requests the same: method, path and query, media type and body.
fn fingerprint(request: &axum::http::request::Parts, body: &[u8]) -> String {
    let mut hash = Sha256::new();
    for part in [request.method.as_str().as_bytes(), request.uri.to_string().as_bytes(), request.headers.get(header::CONTENT_TYPE).map_or(&b""[..], |v| v.as_bytes())] {
        hash.update((part.len() as u64).to_le_bytes());
        hash.update(part);
    }
    hash.update(body);
    hex::encode(hash.finalize())
}

pub async fn idempotent(State(state): State<AppState>, request: Request, next: Next) -> Response {
    if request.method() != Method::POST || !request.uri().path().starts_with("/api/") {
        return next.run(request).await;
    }
    let Some(key) = request.headers().get(HEADER) else { return next.run(request).await };
    let key = match key.to_str() {
        Ok(k) if (1..=255).contains(&k.len()) => k.to_owned(),
        _ => return refuse(StatusCode::BAD_REQUEST, "invalid_idempotency_key", "an Idempotency-Key has 1 to 255 visible ASCII characters"),
    };
    let tenant = request.extensions().get::<Caller>().map(|c| c.tenant.clone()).unwrap_or_default();
    let (parts, body) = request.into_parts();
    let Ok(body) = to_bytes(body, state.config.max_body_bytes).await else {
        return refuse(StatusCode::PAYLOAD_TOO_LARGE, "body_too_large", "the request body is larger than the server accepts");
    };
    let db = &state.db;
    match idempotency::begin(db, &tenant, &key, &fingerprint(&parts, &body)).await {
        Err(e) => ApiError::from(e).into_response(),
        Ok(Begin::Mismatch) => {
            refuse(StatusCode::UNPROCESSABLE_ENTITY, "idempotency_key_reused", "this Idempotency-Key was sent with another request; use a new key for a new request")
        }
        Ok(Begin::InProgress) => refuse(StatusCode::CONFLICT, "idempotency_in_progress", "the first request with this Idempotency-Key is still being answered; retry shortly"),
        Ok(Begin::Replay { status, content_type, body }) => {
            let mut response = (StatusCode::from_u16(status).unwrap_or(StatusCode::OK), body).into_response();
            if let Some(value) = content_type.and_then(|t| HeaderValue::from_str(&t).ok()) {
                response.headers_mut().insert(header::CONTENT_TYPE, value);
            }
            response.headers_mut().insert(REPLAYED, HeaderValue::from_static("true"));
            response
        }
        Ok(Begin::New) => {
            let response = next.run(Request::from_parts(parts, Body::from(body))).await;
            let (parts, body) = response.into_parts();
            let Ok(bytes) = to_bytes(body, usize::MAX).await else {
                let _ = idempotency::forget(db, &tenant, &key).await;
                return ApiError::Internal("the answer could not be read back".into()).into_response();
            };
            let kept = if parts.status.is_server_error() {
                idempotency::forget(db, &tenant, &key).await
            } else {
                let content_type = parts.headers.get(header::CONTENT_TYPE).and_then(|v| v.to_str().ok());
                idempotency::finish(db, &tenant, &key, parts.status.as_u16(), content_type, &bytes).await
            };
            if let Err(e) = kept {
                tracing::error!(error = %e, "an idempotent answer could not be kept");
            }
            Response::from_parts(parts, Body::from(bytes))
        }
    }
}
