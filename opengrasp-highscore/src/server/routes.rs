//! Routes and handlers of the web service (see the [module docs](super)).

use std::sync::Arc;

use axum::body::{Body, Bytes};
use axum::extract::rejection::{PathRejection, QueryRejection};
use axum::extract::{Path as UrlPath, Query, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use http_body_util::BodyExt;
use serde::{Deserialize, Serialize};

use super::{server_error, ServerOptions};
use crate::error::{HighscoreError, Result};
use crate::{html, Db, Ranking, Submission, SubmissionId, Submitter};

/// Shared state of the handlers.
#[derive(Debug)]
pub(super) struct AppState {
    db: Db,
    pub(super) options: ServerOptions,
}

impl AppState {
    pub(super) fn new(db: Db, options: ServerOptions) -> Self {
        Self { db, options }
    }
}

type Shared = Arc<AppState>;

/// Content-Security-Policy of every answer: no scripts at all, inline styles and inline
/// (data:) images only, no framing, no plugins, forms only to this origin.
pub const CONTENT_SECURITY_POLICY: &str = "default-src 'none'; style-src 'unsafe-inline'; img-src 'self' data:; \
base-uri 'none'; form-action 'self'; frame-ancestors 'none'";

/// The service's routes over shared state.
pub(super) fn router(state: Shared) -> Router {
    Router::new()
        .route("/", get(index))
        .route("/highscore/{kind}/{name}", get(ranking_page))
        .route("/submission/{id}", get(submission_page))
        .route("/api/benchmarks", get(list_benchmarks))
        .route("/api/benchmarks/{kind}/{name}/ranking", get(ranking_json))
        .route("/api/submissions", post(submit))
        .route("/api/submissions/{id}", get(submission_json))
        .fallback(not_found)
        .layer(axum::middleware::map_response(security_headers))
        .with_state(state)
}

async fn security_headers(mut response: Response) -> Response {
    let h = response.headers_mut();
    h.insert(header::CONTENT_SECURITY_POLICY, HeaderValue::from_static(CONTENT_SECURITY_POLICY));
    h.insert(header::X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
    h.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    h.insert(header::REFERRER_POLICY, HeaderValue::from_static("no-referrer"));
    response
}

/// JSON error body.
#[derive(Debug, Serialize, Deserialize)]
struct ErrorBody {
    error: String,
    message: String,
}

fn error_response(status: StatusCode, code: &str, message: String) -> Response {
    (status, Json(ErrorBody { error: code.to_string(), message })).into_response()
}

fn status_of(e: &HighscoreError, unknown_benchmark: StatusCode) -> StatusCode {
    match e {
        HighscoreError::TooLarge { .. } => StatusCode::PAYLOAD_TOO_LARGE,
        HighscoreError::InvalidJson { .. } => StatusCode::BAD_REQUEST,
        HighscoreError::InvalidField { .. } => StatusCode::UNPROCESSABLE_ENTITY,
        HighscoreError::UnknownBenchmark { .. } => unknown_benchmark,
        HighscoreError::UnknownSubmission { .. } => StatusCode::NOT_FOUND,
        HighscoreError::Unauthorized { .. } => StatusCode::UNAUTHORIZED,
        HighscoreError::Duplicate { .. } => StatusCode::CONFLICT,
        HighscoreError::Busy(_) => StatusCode::SERVICE_UNAVAILABLE,
        HighscoreError::BodyTimeout => StatusCode::REQUEST_TIMEOUT,
        _ => StatusCode::INTERNAL_SERVER_ERROR,
    }
}

fn error_of(e: &HighscoreError, unknown_benchmark: StatusCode) -> Response {
    let status = status_of(e, unknown_benchmark);
    let mut response = error_response(status, e.code(), e.to_string());
    decorate(&mut response, e);
    response
}

/// `Retry-After` on 503, `WWW-Authenticate` on 401.
fn decorate(response: &mut Response, e: &HighscoreError) {
    match e {
        HighscoreError::Busy(_) => {
            response.headers_mut().insert(header::RETRY_AFTER, HeaderValue::from_static("1"));
        }
        HighscoreError::Unauthorized { .. } => {
            response.headers_mut().insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
        }
        _ => {}
    }
}

fn html_error(e: &HighscoreError) -> Response {
    let status = status_of(e, StatusCode::NOT_FOUND);
    let mut response = (status, Html(html::error_page(status.as_u16(), &e.to_string()))).into_response();
    decorate(&mut response, e);
    response
}

/// Runs blocking database work off the async workers.
async fn blocking<T: Send + 'static>(f: impl FnOnce() -> Result<T> + Send + 'static) -> Result<T> {
    tokio::task::spawn_blocking(f).await.map_err(|e| server_error("", &e.to_string()))?
}

fn benchmark_id(path: std::result::Result<UrlPath<(String, String)>, PathRejection>) -> Option<String> {
    path.ok().map(|UrlPath((kind, name))| format!("{kind}/{name}"))
}

/// Pagination of rankings: `?offset=0&limit=100` (limit at most 1,000).
#[derive(Clone, Copy, Debug, Default, Deserialize)]
pub(super) struct Page {
    offset: Option<usize>,
    limit: Option<usize>,
}

/// Default and largest page of a ranking.
const PAGE: usize = 100;
const MAX_PAGE: usize = 1000;

fn page_of(full: &Ranking, page: Page) -> Ranking {
    let offset = page.offset.unwrap_or(0).min(full.entries.len());
    let limit = page.limit.unwrap_or(PAGE).clamp(1, MAX_PAGE);
    let end = offset.saturating_add(limit).min(full.entries.len());
    Ranking {
        benchmark: full.benchmark.clone(),
        rules: full.rules.clone(),
        total: full.entries.len(),
        offset,
        entries: full.entries[offset..end].to_vec(),
    }
}

async fn ranking(state: &Shared, id: String, page: Page) -> Result<Ranking> {
    let state = state.clone();
    blocking(move || state.db.ranking(&id).map(|full| page_of(&full, page))).await
}

async fn not_found() -> Response {
    error_response(StatusCode::NOT_FOUND, "not_found", "no such endpoint".into())
}

async fn index(State(state): State<Shared>) -> Response {
    let s = state.clone();
    match blocking(move || s.db.read(|s| s.benchmarks())).await {
        Ok(b) => Html(html::index_page(&b)).into_response(),
        Err(e) => html_error(&e),
    }
}

async fn list_benchmarks(State(state): State<Shared>) -> Response {
    let s = state.clone();
    match blocking(move || s.db.read(|s| s.benchmarks())).await {
        Ok(b) => Json(b).into_response(),
        Err(e) => error_of(&e, StatusCode::NOT_FOUND),
    }
}

async fn ranking_json(
    State(state): State<Shared>,
    path: std::result::Result<UrlPath<(String, String)>, PathRejection>,
    page: std::result::Result<Query<Page>, QueryRejection>,
) -> Response {
    let Some(id) = benchmark_id(path) else {
        return error_response(StatusCode::BAD_REQUEST, "bad_path", "malformed benchmark path".into());
    };
    match ranking(&state, id, page.map(|Query(p)| p).unwrap_or_default()).await {
        Ok(r) => Json(r).into_response(),
        Err(e) => error_of(&e, StatusCode::NOT_FOUND),
    }
}

async fn ranking_page(
    State(state): State<Shared>,
    path: std::result::Result<UrlPath<(String, String)>, PathRejection>,
    page: std::result::Result<Query<Page>, QueryRejection>,
) -> Response {
    let Some(id) = benchmark_id(path) else {
        return (StatusCode::BAD_REQUEST, Html(html::error_page(400, "malformed benchmark path"))).into_response();
    };
    let page = page.map(|Query(p)| p).unwrap_or_default();
    let s = state.clone();
    let charted = blocking(move || {
        let r = s.db.ranking(&id).map(|full| page_of(&full, page))?;
        let data = s.db.read(|store| store.chart_data(&r))?;
        Ok((r, data))
    })
    .await;
    match charted {
        Ok((r, data)) => Html(html::ranking_page(&r, &data)).into_response(),
        Err(e) => html_error(&e),
    }
}

async fn submission_json(
    State(state): State<Shared>,
    path: std::result::Result<UrlPath<i64>, PathRejection>,
) -> Response {
    let Ok(UrlPath(id)) = path else {
        return error_response(StatusCode::BAD_REQUEST, "bad_path", "the submission id is not an integer".into());
    };
    let s = state.clone();
    match blocking(move || s.db.read(|s| s.submission_json(SubmissionId(id)))).await {
        Ok(text) => ([(header::CONTENT_TYPE, "application/json")], text).into_response(),
        Err(e) => error_of(&e, StatusCode::NOT_FOUND),
    }
}

async fn submission_page(
    State(state): State<Shared>,
    path: std::result::Result<UrlPath<i64>, PathRejection>,
) -> Response {
    let Ok(UrlPath(id)) = path else {
        return (StatusCode::BAD_REQUEST, Html(html::error_page(400, "the submission id is not an integer")))
            .into_response();
    };
    let s = state.clone();
    match blocking(move || s.db.read(|s| s.submission_summary(SubmissionId(id)))).await {
        Ok(summary) => Html(html::submission_page(&summary)).into_response(),
        Err(e) => html_error(&e),
    }
}

/// Body of `POST /api/submissions`; `results` is kept as the uploaded bytes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Upload<'a> {
    submitter: String,
    #[serde(default)]
    team: Option<String>,
    #[serde(borrow)]
    results: &'a serde_json::value::RawValue,
}

/// Answer of a stored submission.
#[derive(Debug, Serialize)]
struct Submitted {
    id: SubmissionId,
    benchmarks: Vec<String>,
    duplicate: bool,
}

fn bearer(headers: &HeaderMap) -> Option<&str> {
    let v = headers.get(header::AUTHORIZATION)?.to_str().ok()?;
    let (scheme, token) = v.split_once(' ')?;
    scheme.eq_ignore_ascii_case("bearer").then(|| token.trim())
}

/// Reads the body within the size limit and the body timeout.
async fn read_body(state: &AppState, headers: &HeaderMap, body: Body) -> Result<Bytes> {
    let limit = state.options.body_limit;
    let declared = headers.get(header::CONTENT_LENGTH).and_then(|v| v.to_str().ok()?.parse::<u64>().ok());
    if let Some(n) = declared.filter(|&n| n > limit as u64) {
        return Err(HighscoreError::TooLarge { size: n, limit: limit as u64 });
    }
    let limited = http_body_util::Limited::new(body, limit);
    match tokio::time::timeout(state.options.body_read_timeout, limited.collect()).await {
        Err(_) => Err(HighscoreError::BodyTimeout),
        Ok(Err(e)) if e.is::<http_body_util::LengthLimitError>() => {
            Err(HighscoreError::TooLarge { size: limit as u64 + 1, limit: limit as u64 })
        }
        Ok(Err(e)) => Err(HighscoreError::InvalidJson { message: format!("reading the body failed: {e}") }),
        Ok(Ok(collected)) => Ok(collected.to_bytes()),
    }
}

fn close(mut response: Response) -> Response {
    response.headers_mut().insert(header::CONNECTION, HeaderValue::from_static("close"));
    response
}

async fn submit(State(state): State<Shared>, headers: HeaderMap, body: Body) -> Response {
    // The token first: an unauthenticated client never gets its body read.
    let team = if state.options.require_token {
        let Some(token) = bearer(&headers).map(str::to_string) else {
            let e = HighscoreError::Unauthorized { reason: "an API token is required (Authorization: Bearer)".into() };
            return close(error_of(&e, StatusCode::UNPROCESSABLE_ENTITY));
        };
        let s = state.clone();
        match blocking(move || s.db.read(|s| s.check_token(&token))).await {
            Ok(team) => Some(team),
            Err(e) => return close(error_of(&e, StatusCode::UNPROCESSABLE_ENTITY)),
        }
    } else {
        None
    };
    let bytes = match read_body(&state, &headers, body).await {
        Ok(b) => b,
        Err(e) => return close(error_of(&e, StatusCode::UNPROCESSABLE_ENTITY)),
    };
    let s = state.clone();
    // Parsing and validation are CPU work: off the async workers, like the write. Group
    // commit: concurrent uploads share one transaction; each is answered once durable.
    let result = blocking(move || {
        let submission = parse_upload(&bytes, team)?;
        reverify(&submission, s.options.verify_sample)?;
        let done = s.db.insert_grouped(submission)?;
        Ok(Submitted { id: done.inserted.id, benchmarks: done.benchmarks, duplicate: done.inserted.duplicate })
    })
    .await;
    match result {
        Ok(done) if done.duplicate => (StatusCode::OK, Json(done)).into_response(),
        Ok(done) => (StatusCode::CREATED, Json(done)).into_response(),
        Err(e) => error_of(&e, StatusCode::UNPROCESSABLE_ENTITY),
    }
}

/// The validated submission of an upload body (`team`: the token's team, if tokens are on).
fn parse_upload(bytes: &[u8], team: Option<String>) -> Result<Submission> {
    let u = serde_json::from_slice::<Upload<'_>>(bytes)
        .map_err(|e| HighscoreError::InvalidJson { message: e.to_string() })?;
    let team = match (team, u.team) {
        (Some(t), Some(asked)) if t != asked => {
            return Err(HighscoreError::field("team", format!("the token was issued to team {t:?}")))
        }
        (Some(t), _) => Some(t),
        (None, asked) => asked,
    };
    Submission::from_json(u.results.get(), Submitter { name: u.submitter, team })
}

/// Replays `sample` reference runs of the upload (drawn with a seed taken from its content
/// hash: deterministic per upload, not chosen by the submitter).
fn reverify(submission: &Submission, sample: usize) -> Result<()> {
    if sample == 0 {
        return Ok(());
    }
    let seed = u64::from_str_radix(submission.content_hash.get(..16).unwrap_or("0"), 16).unwrap_or(0);
    let v = crate::verify::verify_sample(&submission.results, sample, seed)?;
    match v.mismatches.first() {
        None => Ok(()),
        Some(first) => Err(HighscoreError::field(
            "results",
            format!("{} of {} replayed runs differ from the upload; first: {first}", v.mismatches.len(), v.checked),
        )),
    }
}
