//! Who is calling: `Authorization: Bearer KEY` resolved to a [`Caller`] (a tenant) for every
//! API request, and each key's request rate limited.
//!
//! A server with no key in its database runs open: every request acts for the `default`
//! tenant with every right, as before tenants existed. Once a key exists (`coverplan keys
//! create`), every `/api/` request except the page's `ui-config` and `/metrics` need one.

use std::num::NonZeroU32;
use std::sync::Arc;

use axum::extract::{FromRequestParts, Request, State};
use axum::http::request::Parts;
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use governor::clock::{Clock, DefaultClock};
use governor::{DefaultKeyedRateLimiter, Quota, RateLimiter};

use super::AppState;
use super::error::ApiError;
use crate::store::keys;
pub use crate::store::keys::Caller;

pub use crate::config::RateLimit;

/// One bucket per key (a generic cell rate algorithm: `burst` at once, refilled at
/// `per_second`).
pub struct KeyLimiter {
    buckets: DefaultKeyedRateLimiter<String>,
}

impl KeyLimiter {
    pub fn new(limit: RateLimit) -> Arc<Self> {
        let per_second = NonZeroU32::new(limit.per_second.max(1)).expect("at least one");
        let burst = NonZeroU32::new(limit.burst.max(1)).expect("at least one");
        Arc::new(KeyLimiter { buckets: RateLimiter::keyed(Quota::per_second(per_second).allow_burst(burst)) })
    }

    /// `Err(seconds to wait)` when `key` is over its rate.
    fn check(&self, key: &str) -> Result<(), u64> {
        self.buckets.check_key(&key.to_owned()).map_err(|not_until| not_until.wait_time_from(DefaultClock::default().now()).as_secs().max(1))
    }
}

/// True for the routes that act for a tenant.
pub fn protected(path: &str) -> bool {
    (path.starts_with("/api/") && path != "/api/v1/ui-config") || path == "/metrics"
}

fn unauthorised(detail: &str) -> Response {
    let mut response = ApiError::Client { status: StatusCode::UNAUTHORIZED, code: "unauthorised", detail: detail.into(), pointer: None }.into_response();
    response.headers_mut().insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
    response
}

fn bearer(headers: &HeaderMap) -> Option<&str> {
    let value = headers.get(header::AUTHORIZATION)?.to_str().ok()?;
    let (scheme, token) = value.split_once(' ')?;
    scheme.eq_ignore_ascii_case("bearer").then(|| token.trim())
}

/// Resolves the caller of a protected route, or answers 401 (no or a bad key) or 429 (over
/// the key's rate, with `Retry-After`).
pub async fn authenticate(State(state): State<AppState>, mut request: Request, next: Next) -> Response {
    if !protected(request.uri().path()) {
        return next.run(request).await;
    }
    let caller = match keys::required(&state.db).await {
        Err(e) => return ApiError::from(e).into_response(),
        Ok(false) => Caller::open(),
        Ok(true) => {
            let Some(presented) = bearer(request.headers()) else {
                return unauthorised("this server needs an API key: send `Authorization: Bearer KEY` (an operator makes keys with `coverplan keys create`)");
            };
            match keys::authenticate(&state.db, presented).await {
                Err(e) => return ApiError::from(e).into_response(),
                Ok(None) => return unauthorised("the API key is unknown or revoked"),
                Ok(Some(caller)) => caller,
            }
        }
    };
    if let Some(key) = &caller.key_id
        && let Err(wait_s) = state.limiter.check(key)
    {
        let detail = format!("this key sends requests faster than the server allows; retry in {wait_s} s");
        return ApiError::TooMany { code: "rate_limited", detail, retry_after_s: wait_s }.into_response();
    }
    request.extensions_mut().insert(caller);
    next.run(request).await
}

impl<S: Send + Sync> FromRequestParts<S> for Caller {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, _state: &S) -> Result<Self, Self::Rejection> {
        parts.extensions.get::<Caller>().cloned().ok_or_else(|| ApiError::Internal(format!("{} is not behind authentication", parts.uri.path())))
    }
}
