//! A bounded loopback load test of the high-score service: fills a fresh database with
//! `SUBMISSIONS` distinct tiny-suite submissions, then measures
//! - uploads over HTTP (`POST /api/submissions` with a token) per second, from one client
//!   and then from `UPLOADERS` concurrent clients (group commit), and
//! - ranking requests (`GET /api/benchmarks/motion/planar-post/ranking`, first page) per
//!   second with `CLIENTS` concurrent clients for `SECONDS`, with the latency percentiles.
//!
//! ```sh
//! cargo run --release -p opengrasp-highscore --example load -- [SUBMISSIONS] [CLIENTS] [SECONDS] [UPLOADS] [UPLOADERS]
//! ```
//! (defaults 10000 16 10 500 16). Only 127.0.0.1 is contacted; every loop is bounded.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

use opengrasp_bench::results::ResultsFile;
use opengrasp_bench::suite::{Suite, SuiteSize};
use opengrasp_highscore::{client, ServerOptions, Store, Submission, Submitter};

/// `results` with every planner renamed `name-i` (a distinct submission for each `i`).
fn renamed(results: &ResultsFile, i: usize) -> String {
    let mut r = results.clone();
    let rename = |n: &mut String| *n = format!("{n}-{i}");
    if let Some(g) = &mut r.grasp {
        g.planners.iter_mut().for_each(|p| rename(&mut p.name));
        g.cells.iter_mut().for_each(|c| rename(&mut c.cell.planner));
    }
    if let Some(m) = &mut r.motion {
        m.planners.iter_mut().for_each(|p| rename(&mut p.name));
        m.runs.iter_mut().for_each(|x| rename(&mut x.planner));
        m.summaries.iter_mut().for_each(|s| rename(&mut s.planner));
    }
    r.to_json().expect("a valid results file")
}

/// One `GET` on a fresh connection; the status code.
fn get(addr: SocketAddr, path: &str) -> std::io::Result<u16> {
    let mut s = TcpStream::connect_timeout(&addr, Duration::from_secs(5))?;
    s.set_read_timeout(Some(Duration::from_secs(10)))?;
    write!(s, "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n")?;
    let mut answer = Vec::new();
    s.read_to_end(&mut answer)?;
    let head = String::from_utf8_lossy(&answer[..answer.len().min(12)]).to_string();
    Ok(head.get(9..12).and_then(|c| c.parse().ok()).unwrap_or(0))
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: usize| std::env::args().nth(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (submissions, clients, seconds, uploads) = (arg(1, 10_000), arg(2, 16), arg(3, 10) as u64, arg(4, 500));
    let uploaders = arg(5, 16).max(1);
    let dir = std::env::temp_dir().join(format!("opengrasp-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let db = dir.join("board.sqlite");
    let base = Suite::standard(SuiteSize::Tiny).jobs(1).run()?;

    let t = Instant::now();
    {
        let mut store = Store::open(&db)?;
        for i in 0..submissions {
            let text = renamed(&base, i);
            store.insert_submission(&Submission::from_json(&text, Submitter::new(format!("lab {}", i % 50)))?)?;
        }
    }
    let fill = t.elapsed().as_secs_f64();
    println!("filled {submissions} submissions directly in {fill:.1} s ({:.0}/s)", submissions as f64 / fill);

    let token = Store::open(&db)?.issue_token("load-test")?.1;
    let server = opengrasp_highscore::spawn(&db, "127.0.0.1:0", ServerOptions::default())?;
    let addr = server.addr();
    let url = format!("http://{addr}");
    let t = Instant::now();
    for i in 0..uploads {
        client::upload(&url, &token, &Submitter::new("uploader"), &renamed(&base, submissions + i))?;
    }
    let up = t.elapsed().as_secs_f64();
    println!("{uploads} uploads over HTTP, 1 client, in {up:.2} s: {:.0} submissions/s", uploads as f64 / up);

    // The bodies are made before the clock starts: the figure is the server's.
    let bodies: Vec<String> = (0..uploads).map(|i| renamed(&base, submissions + uploads + i)).collect();
    let bodies = std::sync::Arc::new(bodies);
    let t = Instant::now();
    let workers: Vec<_> = (0..uploaders)
        .map(|w| {
            let (bodies, url, token) = (bodies.clone(), url.clone(), token.clone());
            std::thread::spawn(move || {
                let mut ids = Vec::new();
                for body in bodies.iter().skip(w).step_by(uploaders) {
                    match client::upload(&url, &token, &Submitter::new("uploader"), body) {
                        Ok(a) if !a.duplicate => ids.push(a.id),
                        _ => return Err(format!("upload failed in client {w}")),
                    }
                }
                Ok(ids)
            })
        })
        .collect();
    let mut acknowledged = Vec::new();
    for w in workers {
        acknowledged.extend(w.join().map_err(|_| "an uploader panicked")??);
    }
    let up = t.elapsed().as_secs_f64();
    println!(
        "{} uploads over HTTP, {uploaders} clients, in {up:.2} s: {:.0} submissions/s",
        acknowledged.len(),
        acknowledged.len() as f64 / up
    );
    let store = Store::open_read_only(&db)?;
    let lost = acknowledged
        .iter()
        .filter(|id| store.submission_json(opengrasp_highscore::SubmissionId(**id)).is_err())
        .count();
    assert_eq!(lost, 0, "every acknowledged upload is stored");
    drop(store);

    let path = "/api/benchmarks/motion/planar-post/ranking?limit=100";
    assert_eq!(get(addr, path)?, 200, "the ranking answers");
    let deadline = Instant::now() + Duration::from_secs(seconds);
    let workers: Vec<_> = (0..clients)
        .map(|_| {
            std::thread::spawn(move || {
                let (mut lat, mut errors) = (Vec::new(), 0usize);
                while Instant::now() < deadline {
                    let t = Instant::now();
                    match get(addr, path) {
                        Ok(200) => lat.push(t.elapsed().as_secs_f64() * 1e3),
                        _ => errors += 1,
                    }
                }
                (lat, errors)
            })
        })
        .collect();
    let (mut lat, mut errors) = (Vec::new(), 0);
    for w in workers {
        let (l, e) = w.join().map_err(|_| "a client thread panicked")?;
        lat.extend(l);
        errors += e;
    }
    lat.sort_by(f64::total_cmp);
    println!(
        "{clients} clients, {seconds} s, {} entries per ranking page: {} ranking requests ({:.0}/s), {errors} errors; \
         latency p50 {:.1} ms, p99 {:.1} ms, max {:.1} ms",
        100,
        lat.len(),
        lat.len() as f64 / seconds as f64,
        percentile(&lat, 0.5),
        percentile(&lat, 0.99),
        lat.last().copied().unwrap_or(0.0)
    );
    server.shutdown()?;
    std::fs::remove_dir_all(&dir).ok();
    Ok(())
}
