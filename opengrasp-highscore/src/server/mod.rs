//! The high-score web service: axum routes (`routes`) driven by hyper on a two-worker tokio
//! runtime, hardened for the open internet.
//!
//! # Endpoints
//!
//! | method and path | answer |
//! | --- | --- |
//! | `GET /api/benchmarks` | `200`, JSON array of [`BenchmarkInfo`](super::BenchmarkInfo) |
//! | `GET /api/benchmarks/{kind}/{name}/ranking?offset=&limit=` | `200`, JSON [`Ranking`](super::Ranking) (one page; `total` entries in all); `404` unknown benchmark |
//! | `POST /api/submissions` | `Authorization: Bearer <token>`; body `{"submitter": "...", "team": "..." (optional), "results": {results file}}`; `201` `{"id": n, "benchmarks": [ids], "duplicate": false}`, `200` with `"duplicate": true` for a retried upload |
//! | `GET /api/submissions/{id}` | `200`, the `results` bytes as uploaded; `404` unknown |
//! | `GET /` | HTML index of the benchmarks |
//! | `GET /highscore/{kind}/{name}?offset=&limit=` | HTML high-score page; `404` unknown benchmark |
//! | `GET /submission/{id}` | HTML page of one submission (entries, provenance, links) |
//!
//! Errors are JSON `{"error": code, "message": text}` ([`HighscoreError::code`]): `400`
//! malformed JSON or wrong shape, `401` missing or invalid token, `409` results already
//! submitted by someone else, `413` body above the limit (answered from `Content-Length`
//! before reading), `408` body not received in time, `422` invalid values or unknown benchmark
//! in an upload (or, with [`ServerOptions::verify_sample`], replayed runs that differ from it),
//! `404` unknown benchmark or submission, `503` (with `Retry-After`) when the
//! database is locked by another writer, `500` other database failures. A rejected upload
//! writes nothing (a savepoint per submission). Uploads are stored with group commit
//! ([`Db::insert_grouped`](super::Db::insert_grouped)): those that arrive while a transaction
//! commits are written together in the next one, and each is answered only once its commit
//! is durable.
//!
//! # Hardening
//!
//! Every response carries `Content-Security-Policy` (no scripts, inline styles only),
//! `X-Content-Type-Options: nosniff`, `X-Frame-Options: DENY` and `Referrer-Policy`. Each
//! connection must send a complete request head within [`ServerOptions::header_read_timeout`]
//! (this also closes idle keep-alive connections), a body within
//! [`ServerOptions::body_read_timeout`], and lives at most
//! [`ServerOptions::connection_lifetime`]. At most [`ServerOptions::max_connections`] are open
//! at once (more wait in the kernel's backlog). Accept errors (e.g. `EMFILE` when the process
//! runs out of file descriptors) are never fatal: the loop backs off briefly and goes on.

mod routes;

use std::net::SocketAddr;
use std::path::Path;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;

use super::error::{HighscoreError, Result};
use super::{Db, MAX_UPLOAD_BYTES};

/// Options of the web service.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ServerOptions {
    /// Largest accepted request body (bytes). Default: [`MAX_UPLOAD_BYTES`] (8 MiB).
    pub body_limit: usize,
    /// Most connections served at once; further clients wait in the listen backlog.
    /// Default: 256 (well below the common 1,024 file-descriptor limit).
    pub max_connections: usize,
    /// Time to receive a complete request head, and the idle time allowed between requests
    /// on a kept-alive connection. Default: 10 s.
    pub header_read_timeout: Duration,
    /// Time to receive a request body. Default: 30 s.
    pub body_read_timeout: Duration,
    /// Longest life of one connection, whatever it does. Default: 120 s.
    pub connection_lifetime: Duration,
    /// Whether uploads need an API token (`Authorization: Bearer`, see
    /// [`Store::issue_token`](super::Store::issue_token)). Default: `true`.
    pub require_token: bool,
    /// Motion runs of reference planners replayed from their seeds per upload (see
    /// [`verify_sample`](crate::verify::verify_sample)); an upload whose replayed runs
    /// differ is refused with 422. Default: 0 (off).
    pub verify_sample: usize,
}

impl Default for ServerOptions {
    fn default() -> Self {
        Self {
            body_limit: MAX_UPLOAD_BYTES,
            max_connections: 256,
            header_read_timeout: Duration::from_secs(10),
            body_read_timeout: Duration::from_secs(30),
            connection_lifetime: Duration::from_secs(120),
            require_token: true,
            verify_sample: 0,
        }
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

    /// Stops accepting connections, drops open ones and waits for the server thread.
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
        let result = join(self.thread.take(), self.addr);
        drop(shutdown);
        result
    }

    fn stop(&mut self) -> Result<()> {
        if let Some(tx) = self.shutdown.take() {
            let _ = tx.send(());
        }
        join(self.thread.take(), self.addr)
    }
}

fn join(thread: Option<JoinHandle<Result<()>>>, addr: SocketAddr) -> Result<()> {
    match thread.map(JoinHandle::join) {
        Some(Ok(r)) => r,
        Some(Err(_)) => Err(server_error(&addr.to_string(), "the server thread panicked")),
        None => Ok(()),
    }
}

impl Drop for ServerHandle {
    fn drop(&mut self) {
        let _ = self.stop();
    }
}

pub(crate) fn server_error(addr: &str, message: &str) -> HighscoreError {
    HighscoreError::Server { addr: addr.to_string(), source: std::io::Error::other(message.to_string()) }
}

/// Serves the database at `db_path` on `addr` (e.g. `127.0.0.1:8080`) until the process ends.
///
/// # Errors
/// Database errors when opening, [`HighscoreError::Server`] if the address cannot be bound or
/// the server fails.
pub fn serve(db_path: &Path, addr: &str, options: ServerOptions) -> Result<()> {
    spawn(db_path, addr, options)?.wait()
}

/// Starts the server on `addr` in a background thread (bind `127.0.0.1:0` for an ephemeral
/// port) and returns once it is listening; [`ServerHandle::addr`] is the bound address.
///
/// # Errors
/// As [`serve`].
pub fn spawn(db_path: &Path, addr: &str, options: ServerOptions) -> Result<ServerHandle> {
    let db = Db::open(db_path)?;
    let err = |source| HighscoreError::Server { addr: addr.to_string(), source };
    let listener = std::net::TcpListener::bind(addr).map_err(err)?;
    listener.set_nonblocking(true).map_err(err)?;
    let bound = listener.local_addr().map_err(err)?;
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().map_err(err)?;
    let (tx, rx) = tokio::sync::oneshot::channel::<()>();
    let state = Arc::new(routes::AppState::new(db, options));
    let thread = std::thread::Builder::new()
        .name("opengrasp-highscore".into())
        .spawn(move || {
            let result = runtime.block_on(accept_loop(listener, state, rx));
            runtime.shutdown_timeout(Duration::from_secs(1));
            result
        })
        .map_err(err)?;
    Ok(ServerHandle { addr: bound, shutdown: Some(tx), thread: Some(thread) })
}

/// Whether an accept error concerns only the one connection (the listener is fine).
fn per_connection(e: &std::io::Error) -> bool {
    use std::io::ErrorKind::*;
    matches!(e.kind(), ConnectionAborted | ConnectionReset | ConnectionRefused | Interrupted | WouldBlock)
}

async fn accept_loop(
    listener: std::net::TcpListener,
    state: Arc<routes::AppState>,
    mut shutdown: tokio::sync::oneshot::Receiver<()>,
) -> Result<()> {
    let addr = listener.local_addr().map_or_else(|_| "?".to_string(), |a| a.to_string());
    let listener =
        tokio::net::TcpListener::from_std(listener).map_err(|source| HighscoreError::Server { addr, source })?;
    let options = state.options.clone();
    let slots = Arc::new(tokio::sync::Semaphore::new(options.max_connections.max(1)));
    let router = routes::router(state);
    loop {
        let permit = tokio::select! {
            p = slots.clone().acquire_owned() => match p { Ok(p) => p, Err(_) => return Ok(()) },
            _ = &mut shutdown => return Ok(()),
        };
        let accepted = tokio::select! {
            a = listener.accept() => a,
            _ = &mut shutdown => return Ok(()),
        };
        let stream = match accepted {
            Ok((stream, _)) => stream,
            Err(e) if per_connection(&e) => continue,
            Err(_) => {
                // EMFILE / ENFILE / ENOBUFS: out of descriptors or memory. Never fatal: wait
                // for connections to close, then accept again.
                tokio::time::sleep(Duration::from_millis(50)).await;
                continue;
            }
        };
        let _ = stream.set_nodelay(true);
        let service = TowerToHyperService::new(router.clone());
        let options = options.clone();
        tokio::spawn(async move {
            let _permit = permit;
            let mut builder = hyper::server::conn::http1::Builder::new();
            builder
                .timer(TokioTimer::new())
                .header_read_timeout(options.header_read_timeout)
                .max_buf_size(64 * 1024)
                .keep_alive(true);
            let conn = builder.serve_connection(TokioIo::new(stream), service);
            let _ = tokio::time::timeout(options.connection_lifetime, conn).await;
        });
    }
}
