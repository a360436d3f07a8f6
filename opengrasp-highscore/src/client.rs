//! A minimal HTTP/1.1 client for `opengrasp submit --server URL`: one `POST
//! /api/submissions` over a plain TCP connection (`http://` only; put TLS in front with a
//! reverse proxy), bounded in time and size.

use std::io::{Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

use serde::{Deserialize, Serialize};

use super::error::{HighscoreError, Result};
use super::{Submission, Submitter};

/// Largest answer read from the server.
const MAX_ANSWER: usize = 1024 * 1024;

/// The server's answer to an upload.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct UploadAnswer {
    /// The stored submission.
    pub id: i64,
    /// Benchmarks it has entries on.
    pub benchmarks: Vec<String>,
    /// True if the server already had these results from this submitter.
    #[serde(default)]
    pub duplicate: bool,
}

fn remote(message: impl Into<String>) -> HighscoreError {
    HighscoreError::Remote { status: 0, message: message.into() }
}

/// `(host:port, path prefix)` of an `http://` URL.
fn parse_url(url: &str) -> Result<(String, String)> {
    let rest =
        url.strip_prefix("http://").ok_or_else(|| remote(format!("{url:?}: only http:// URLs are supported")))?;
    let (host, path) = match rest.find('/') {
        Some(i) => (&rest[..i], rest[i..].trim_end_matches('/')),
        None => (rest, ""),
    };
    if host.is_empty() {
        return Err(remote(format!("{url:?} has no host")));
    }
    let host = if host.contains(':') && !host.ends_with(']') { host.to_string() } else { format!("{host}:80") };
    Ok((host, path.to_string()))
}

/// Uploads a results file's text to the high-score server at `url` with an API token. The
/// file is validated locally first and sent verbatim.
///
/// # Errors
/// The validation errors of [`Submission::from_json`], [`HighscoreError::Remote`] for
/// connection failures and error answers (status and the server's message).
pub fn upload(url: &str, token: &str, submitter: &Submitter, results_text: &str) -> Result<UploadAnswer> {
    Submission::from_json(results_text, submitter.clone())?;
    let (host, prefix) = parse_url(url)?;
    let mut body = Vec::with_capacity(results_text.len() + 256);
    body.extend_from_slice(b"{\"submitter\":");
    body.extend(serde_json::to_vec(&submitter.name).unwrap_or_default());
    if let Some(team) = &submitter.team {
        body.extend_from_slice(b",\"team\":");
        body.extend(serde_json::to_vec(team).unwrap_or_default());
    }
    body.extend_from_slice(b",\"results\":");
    body.extend_from_slice(results_text.as_bytes());
    body.extend_from_slice(b"}");
    let head = format!(
        "POST {prefix}/api/submissions HTTP/1.1\r\nHost: {host}\r\nAuthorization: Bearer {token}\r\n\
         Content-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    );
    let addr = host
        .to_socket_addrs()
        .map_err(|e| remote(format!("cannot resolve {host}: {e}")))?
        .next()
        .ok_or_else(|| remote(format!("cannot resolve {host}")))?;
    let mut stream = TcpStream::connect_timeout(&addr, Duration::from_secs(10))
        .map_err(|e| remote(format!("cannot connect to {host}: {e}")))?;
    let io = |e: std::io::Error| remote(format!("talking to {host}: {e}"));
    stream.set_read_timeout(Some(Duration::from_secs(60))).map_err(io)?;
    stream.set_write_timeout(Some(Duration::from_secs(60))).map_err(io)?;
    stream.write_all(head.as_bytes()).map_err(io)?;
    // An early answer (401, 413) may close the connection before the body is sent.
    let _ = stream.write_all(&body);
    let _ = stream.flush();
    let mut raw = Vec::new();
    (&mut stream).take(MAX_ANSWER as u64).read_to_end(&mut raw).map_err(io)?;
    let (status, text) = parse_answer(&raw).ok_or_else(|| remote(format!("{host} sent no valid HTTP answer")))?;
    if !(200..300).contains(&status) {
        let message = serde_json::from_str::<serde_json::Value>(&text)
            .ok()
            .and_then(|v| v["message"].as_str().map(str::to_string))
            .unwrap_or(text);
        return Err(HighscoreError::Remote { status, message });
    }
    serde_json::from_str(&text).map_err(|e| remote(format!("unexpected answer ({e}): {text}")))
}

/// Status and (de-chunked) body of an HTTP/1.1 answer.
fn parse_answer(raw: &[u8]) -> Option<(u16, String)> {
    let split = raw.windows(4).position(|w| w == b"\r\n\r\n")?;
    let head = String::from_utf8_lossy(&raw[..split]).to_string();
    let status = head.split_whitespace().nth(1)?.parse().ok()?;
    let mut body = raw[split + 4..].to_vec();
    if head.to_ascii_lowercase().contains("transfer-encoding: chunked") {
        let mut out = Vec::new();
        let mut rest = &body[..];
        while let Some(eol) = rest.windows(2).position(|w| w == b"\r\n") {
            let size = usize::from_str_radix(String::from_utf8_lossy(&rest[..eol]).trim(), 16).ok()?;
            if size == 0 || rest.len() < eol + 2 + size {
                break;
            }
            out.extend_from_slice(&rest[eol + 2..eol + 2 + size]);
            rest = rest.get(eol + 4 + size..).unwrap_or_default();
        }
        body = out;
    }
    Some((status, String::from_utf8_lossy(&body).to_string()))
}
