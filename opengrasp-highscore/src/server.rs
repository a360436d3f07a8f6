//! The high-score web service (axum on a single-threaded tokio runtime).
//!
//! # Endpoints
//!
//! | method and path | answer |
//! | --- | --- |
//! | `GET /api/benchmarks` | `200`, JSON array of [`BenchmarkInfo`](super::BenchmarkInfo) |
//! | `GET /api/benchmarks/{kind}/{name}/ranking` | `200`, JSON [`Ranking`](super::Ranking); `404` unknown benchmark |
//! | `POST /api/submissions` | body `{"submitter": "...", "team": "..." (optional), "results": {results file}}`; `201` `{"id": n, "benchmarks": [ids]}` |
//! | `GET /api/submissions/{id}` | `200`, the submitted results file verbatim; `404` unknown |
//! | `GET /` | HTML index of the benchmarks |
//! | `GET /highscore/{kind}/{name}` | HTML high-score page; `404` unknown benchmark |
//!
//! Errors are JSON `{"error": code, "message": text}` ([`HighscoreError::code`]): `400`
//! malformed JSON or wrong shape, `413` body above the limit, `422` invalid values or unknown
//! benchmark in an upload, `404` unknown benchmark or submission, `500` database failures.
//! A rejected upload writes nothing (one transaction per submission).

use std::net::SocketAddr;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, PathRejection};
use axum::extract::{DefaultBodyLimit, Path as UrlPath, State};
use axum::http::{header, StatusCode};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde::{Deserialize, Serialize};

use super::error::{HighscoreError, Result};
use super::{html, Store, Submission, SubmissionId, Submitter, MAX_UPLOAD_BYTES};

/// Options of the web service.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ServerOptions {
    /// Largest accepted request body (bytes). Default: [`MAX_UPLOAD_BYTES`] (8 MiB).
    pub body_limit: usize,
}

impl Default for ServerOptions {
    fn default() -> Self {
        Self { body_limit: MAX_UPLOAD_BYTES }
    }
}

/// A running server (see [`spawn`]); dropping it shuts the server down.
#[derive(Debug)]
pub struct ServerHandle {
    addr: SocketAddr,
    shutdown: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<JoinHandle<Result<()>>>,
}

impl ServerHandle {
    /// The bound address (with the actual port when bound to port 0).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Stops accepting connections, lets open requests finish and waits for the server thread.
    ///
    /// # Errors
    /// [`HighscoreError::Server`] if the server failed while running.
    pub fn shutdown(mut self) -> Result<()> {
        self.stop()
    }

    /// Blocks until the server ends (for a command line that prints [`ServerHandle::addr`]
    /// first, then serves until the process is stopped).
    ///
    /// # Errors
    /// [`HighscoreError::Server`] if the server failed.
    pub fn wait(mut self) -> Result<()> {
        let shutdown = self.shutdown.take();
        let result = match self.thread.take().map(JoinHandle::join) {
            Some(Ok(r)) => r,
            Some(Err(_)) => Err(server_error(&self.addr.to_string(), "the server thread panicked")),
            None => Ok(()),
        };
        drop(shutdown);
        result
    }

    fn stop(&mut self) -> Result<()> {
        if let Some(tx) = self.shutdown.take() {
            let _ = tx.send(());
        }
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(r)) => r,
            Some(Err(_)) => Err(server_error(&self.addr.to_string(), "the server thread panicked")),
            None => Ok(()),
        }
    }
}

impl Drop for ServerHandle {
    fn drop(&mut self) {
        let _ = self.stop();
    }
}

fn server_error(addr: &str, message: &str) -> HighscoreError {
    HighscoreError::Server { addr: addr.to_string(), source: std::io::Error::other(message.to_string()) }
}

#[derive(Debug)]
struct AppState {
    store: Mutex<Store>,
    body_limit: usize,
}

type Shared = Arc<AppState>;

/// Serves the database at `db_path` on `addr` (e.g. `127.0.0.1:8080`) until the process ends.
///
/// # Errors
/// Database errors when opening, [`HighscoreError::Server`] if the address cannot be bound or
/// the server fails.
pub fn serve(db_path: &Path, addr: &str) -> Result<()> {
    let (listener, state) = bind(db_path, addr, &ServerOptions::default())?;
    run(listener, state, std::future::pending())
}

/// Starts the server on `addr` in a background thread (bind `127.0.0.1:0` for an ephemeral
/// port) and returns once it is listening.
///
/// # Errors
/// As [`serve`].
pub fn spawn(db_path: &Path, addr: &str, options: ServerOptions) -> Result<ServerHandle> {
    let (listener, state) = bind(db_path, addr, &options)?;
    let bound = listener.local_addr().map_err(|source| HighscoreError::Server { addr: addr.to_string(), source })?;
    let (tx, rx) = tokio::sync::oneshot::channel::<()>();
    let thread = std::thread::Builder::new()
        .name("opengrasp-highscore".into())
        .spawn(move || {
            run(listener, state, async move {
                let _ = rx.await;
            })
        })
        .map_err(|source| HighscoreError::Server { addr: addr.to_string(), source })?;
    Ok(ServerHandle { addr: bound, shutdown: Some(tx), thread: Some(thread) })
}

fn bind(db_path: &Path, addr: &str, options: &ServerOptions) -> Result<(std::net::TcpListener, Shared)> {
    let store = Store::open(db_path)?;
    let listener = std::net::TcpListener::bind(addr)
        .map_err(|source| HighscoreError::Server { addr: addr.to_string(), source })?;
    listener.set_nonblocking(true).map_err(|source| HighscoreError::Server { addr: addr.to_string(), source })?;
    Ok((listener, Arc::new(AppState { store: Mutex::new(store), body_limit: options.body_limit })))
}

fn run(
    listener: std::net::TcpListener,
    state: Shared,
    shutdown: impl std::future::Future<Output = ()> + Send + 'static,
) -> Result<()> {
    let addr = listener.local_addr().map_or_else(|_| "?".to_string(), |a| a.to_string());
    let err = |source| HighscoreError::Server { addr: addr.clone(), source };
    let runtime = tokio::runtime::Builder::new_current_thread().enable_io().build().map_err(err)?;
    runtime.block_on(async {
        let listener = tokio::net::TcpListener::from_std(listener).map_err(err)?;
        axum::serve(listener, router(state)).with_graceful_shutdown(shutdown).await.map_err(err)
    })
}

/// The service's routes over a shared store (exposed for embedding in a larger axum app).
fn router(state: Shared) -> Router {
    let limit = state.body_limit;
    Router::new()
        .route("/", get(index))
        .route("/highscore/{kind}/{name}", get(ranking_page))
        .route("/api/benchmarks", get(list_benchmarks))
        .route("/api/benchmarks/{kind}/{name}/ranking", get(ranking_json))
        .route("/api/submissions", post(submit))
        .route("/api/submissions/{id}", get(submission_json))
        .fallback(not_found)
        .layer(DefaultBodyLimit::max(limit))
        .with_state(state)
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

fn error_of(e: &HighscoreError, unknown_benchmark: StatusCode) -> Response {
    let status = match e {
        HighscoreError::TooLarge { .. } => StatusCode::PAYLOAD_TOO_LARGE,
        HighscoreError::InvalidJson { .. } => StatusCode::BAD_REQUEST,
        HighscoreError::InvalidField { .. } => StatusCode::UNPROCESSABLE_ENTITY,
        HighscoreError::UnknownBenchmark { .. } => unknown_benchmark,
        HighscoreError::UnknownSubmission { .. } => StatusCode::NOT_FOUND,
        _ => StatusCode::INTERNAL_SERVER_ERROR,
    };
    error_response(status, e.code(), e.to_string())
}

async fn with_store<T: Send + 'static>(
    state: &Shared,
    f: impl FnOnce(&mut Store) -> Result<T> + Send + 'static,
) -> Result<T> {
    let state = state.clone();
    tokio::task::spawn_blocking(move || {
        let mut store = state.store.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        f(&mut store)
    })
    .await
    .map_err(|e| server_error("", &e.to_string()))?
}

fn benchmark_id(path: std::result::Result<UrlPath<(String, String)>, PathRejection>) -> Option<String> {
    path.ok().map(|UrlPath((kind, name))| format!("{kind}/{name}"))
}

async fn not_found() -> Response {
    error_response(StatusCode::NOT_FOUND, "not_found", "no such endpoint".into())
}

async fn index(State(state): State<Shared>) -> Response {
    match with_store(&state, |s| s.benchmarks()).await {
        Ok(b) => Html(html::index_page(&b)).into_response(),
        Err(e) => error_of(&e, StatusCode::NOT_FOUND),
    }
}

async fn list_benchmarks(State(state): State<Shared>) -> Response {
    match with_store(&state, |s| s.benchmarks()).await {
        Ok(b) => Json(b).into_response(),
        Err(e) => error_of(&e, StatusCode::NOT_FOUND),
    }
}

async fn ranking_json(
    State(state): State<Shared>,
    path: std::result::Result<UrlPath<(String, String)>, PathRejection>,
) -> Response {
    let Some(id) = benchmark_id(path) else {
        return error_response(StatusCode::BAD_REQUEST, "bad_path", "malformed benchmark path".into());
    };
    match with_store(&state, move |s| s.ranking(&id)).await {
        Ok(r) => Json(r).into_response(),
        Err(e) => error_of(&e, StatusCode::NOT_FOUND),
    }
}

async fn ranking_page(
    State(state): State<Shared>,
    path: std::result::Result<UrlPath<(String, String)>, PathRejection>,
) -> Response {
    let Some(id) = benchmark_id(path) else {
        return (StatusCode::BAD_REQUEST, Html("<h1>malformed benchmark path</h1>".to_string())).into_response();
    };
    match with_store(&state, move |s| s.ranking(&id)).await {
        Ok(r) => Html(html::ranking_page(&r)).into_response(),
        Err(e @ HighscoreError::UnknownBenchmark { .. }) => {
            (StatusCode::NOT_FOUND, Html(format!("<h1>{}</h1>", html::escape(&e.to_string())))).into_response()
        }
        Err(e) => error_of(&e, StatusCode::NOT_FOUND),
    }
}

async fn submission_json(
    State(state): State<Shared>,
    path: std::result::Result<UrlPath<i64>, PathRejection>,
) -> Response {
    let Ok(UrlPath(id)) = path else {
        return error_response(StatusCode::BAD_REQUEST, "bad_path", "the submission id is not an integer".into());
    };
    match with_store(&state, move |s| s.submission_json(SubmissionId(id))).await {
        Ok(text) => ([(header::CONTENT_TYPE, "application/json")], text).into_response(),
        Err(e) => error_of(&e, StatusCode::NOT_FOUND),
    }
}

/// Body of `POST /api/submissions`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Upload {
    submitter: String,
    #[serde(default)]
    team: Option<String>,
    results: serde_json::Value,
}

/// Answer of a stored submission.
#[derive(Debug, Serialize)]
struct Submitted {
    id: SubmissionId,
    benchmarks: Vec<String>,
}

async fn submit(State(state): State<Shared>, body: std::result::Result<Bytes, BytesRejection>) -> Response {
    let body = match body {
        Ok(b) => b,
        Err(rejection) if rejection.status() == StatusCode::PAYLOAD_TOO_LARGE => {
            let e = HighscoreError::TooLarge { size: state.body_limit as u64 + 1, limit: state.body_limit as u64 };
            return error_of(&e, StatusCode::UNPROCESSABLE_ENTITY);
        }
        Err(rejection) => return error_response(rejection.status(), "bad_body", rejection.body_text()),
    };
    let parsed = serde_json::from_slice::<Upload>(&body)
        .map_err(|e| HighscoreError::InvalidJson { message: e.to_string() })
        .and_then(|u| {
            let text = serde_json::to_string(&u.results)
                .map_err(|e| HighscoreError::InvalidJson { message: e.to_string() })?;
            let submitter = Submitter { name: u.submitter, team: u.team };
            Submission::from_json(&text, submitter)
        });
    let submission = match parsed {
        Ok(s) => s,
        Err(e) => return error_of(&e, StatusCode::UNPROCESSABLE_ENTITY),
    };
    let result = with_store(&state, move |s| {
        let id = s.insert(&submission)?;
        let benchmarks = s.submission_benchmarks(id)?;
        Ok(Submitted { id, benchmarks })
    })
    .await;
    match result {
        Ok(done) => (StatusCode::CREATED, Json(done)).into_response(),
        Err(e) => error_of(&e, StatusCode::UNPROCESSABLE_ENTITY),
    }
}
