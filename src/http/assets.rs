//! The map page and its vendored libraries, embedded in the binary at build time, so that
//! `coverplan serve` serves the page from any working directory.

use axum::http::{HeaderMap, StatusCode, Uri, header};
use axum::response::{IntoResponse, Response};
use rust_embed::Embed;

use super::error::ApiError;

#[derive(Embed)]
#[folder = "static/"]
struct Page;

/// Answers `GET /…` with the embedded file (`index.html` for a folder), with its type and an
/// `ETag` so that browsers revalidate instead of downloading again.
pub async fn embedded(uri: Uri, headers: HeaderMap) -> Response {
    let path = uri.path().trim_start_matches('/');
    let path = if path.is_empty() || path.ends_with('/') { format!("{path}index.html") } else { path.to_owned() };
    let Some(file) = Page::get(&path) else {
        return ApiError::Client { status: StatusCode::NOT_FOUND, code: "not_found", detail: format!("no page at `/{path}`"), pointer: None }.into_response();
    };
    let etag = format!("\"{}\"", file.metadata.sha256_hash().iter().map(|b| format!("{b:02x}")).collect::<String>());
    if headers.get(header::IF_NONE_MATCH).is_some_and(|v| v.as_bytes() == etag.as_bytes()) {
        return (StatusCode::NOT_MODIFIED, [(header::ETAG, etag)]).into_response();
    }
    ([(header::CONTENT_TYPE, file.metadata.mimetype().to_owned()), (header::ETAG, etag), (header::CACHE_CONTROL, "no-cache".to_owned())], file.data).into_response()
}
