//! Issue 19: the board cannot be gamed, uploads are authenticated and idempotent, and the
//! server survives idle, slow and oversized connections and file-descriptor exhaustion.
//! Tests talk to 127.0.0.1 only, are bounded in connections and time, and assert survival and
//! correctness, never timings.

mod common;

use common::{cell, grasp_file, motion_file, run};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use opengrasp_bench::results::ResultsFile;
use opengrasp_highscore::{self as highscore, HighscoreError, ServerOptions, Store, Submission, Submitter};
use opengrasp_motion::benchmark::RunRecord;

struct TempDb(PathBuf);

impl TempDb {
    fn new(tag: &str) -> Self {
        static N: AtomicUsize = AtomicUsize::new(0);
        let n = N.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("opengrasp-hardening-{}-{tag}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir");
        Self(dir)
    }
    fn db(&self) -> PathBuf {
        self.0.join("results.sqlite")
    }
}

impl Drop for TempDb {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn check(f: &ResultsFile) -> highscore::Result<Submission> {
    // Serialise without the file's own validation so implausible values reach the board.
    Submission::from_json(&serde_json::to_string(f).expect("json"), Submitter::new("ann"))
}

fn rejected(what: &str, f: &ResultsFile, field_part: &str) {
    match check(f) {
        Err(HighscoreError::InvalidField { field, reason }) => {
            assert!(field.contains(field_part), "{what}: field {field} ({reason}) should name {field_part}")
        }
        other => panic!("{what}: rejection expected, got {other:?}"),
    }
}

#[test]
fn gaming_values_are_rejected() {
    let good_runs = || (0..4).map(|i| fast_run(i, 0.1 + i as f64 * 0.01)).collect::<Vec<_>>();
    check(&motion_file(good_runs())).expect("a plausible motion file");
    check(&grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 0.1)])).expect("a plausible grasp file");

    rejected("epsilon 1e300", &grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 1e300)]), "mean_epsilon");
    rejected("epsilon above the bound", &grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 1.2)]), "mean_epsilon");
    rejected(
        "epsilon without force closure",
        &grasp_file(vec![cell("alpha", "barrett", "cup", 10, 0, 0.3)]),
        "epsilon",
    );
    let mut pct = grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 0.1)]);
    pct.grasp.as_mut().unwrap().cells[0].cell.fc_percent_palm = 90.0;
    rejected("fc_percent_palm disagrees with the counts", &pct, "fc_percent_palm");
    rejected(
        "the same cell twice",
        &grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 0.1), cell("alpha", "barrett", "cup", 10, 5, 0.1)]),
        "grasp.cells[1]",
    );

    rejected("all planning times 0", &motion_file((0..4).map(|i| fast_run(i, 0.0)).collect()), "planning_time");
    let copied: Vec<RunRecord> = (0..500).map(|_| fast_run(0, 0.1)).collect();
    rejected("one run copied 500 times", &motion_file(copied), "motion.runs[1].run");
    rejected("incomplete runs", &motion_file(good_runs()[..3].to_vec()), "motion.runs");
    let mut seeds = good_runs();
    seeds[2].seed = 99;
    rejected("a run seeded otherwise", &motion_file(seeds), "seed");

    let mut summary = motion_file(good_runs());
    let m = summary.motion.as_mut().unwrap();
    let mut s = opengrasp_bench::results::motion_summaries(m);
    m.summaries = s.clone();
    check(&summary).expect("summaries equal to the runs' are accepted");
    s[0].success_rate = 50.0;
    s[0].solved = 2;
    summary.motion.as_mut().unwrap().summaries = s;
    rejected("summary not matching the runs", &summary, "motion.summaries[0]");

    let mut league = motion_file(good_runs());
    league.provenance.suite_size = "<b>tiny</b>".into();
    rejected("a private league", &league, "suite_size");
    let mut tiny = motion_file(good_runs());
    tiny.provenance.suite_size = "tiny".into();
    rejected("the tiny suite with 4 runs", &tiny, "motion.options.runs");

    for name in ["evil\u{202E}gnp.exe", "a\u{200B}b", "x\u{2066}y"] {
        let e = Submission::from_json(&serde_json::to_string(&motion_file(good_runs())).unwrap(), Submitter::new(name));
        assert!(matches!(e, Err(HighscoreError::InvalidField { .. })), "{name:?}: {e:?}");
    }
    assert!(
        (highscore::plausible::REFERENCE_FRICTION - opengrasp_grasp::contact::ContactModel::default().friction).abs()
            < 1e-15
    );
}

/// One raw HTTP/1.1 exchange (`Connection: close`): status, head, body.
fn http(addr: SocketAddr, request: &[u8]) -> (u16, String, String) {
    assert!(addr.ip().is_loopback());
    let mut s = TcpStream::connect_timeout(&addr, Duration::from_secs(10)).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    let _ = s.write_all(request);
    let mut raw = Vec::new();
    let _ = s.read_to_end(&mut raw);
    let text = String::from_utf8_lossy(&raw).to_string();
    let (head, body) = text.split_once("\r\n\r\n").unwrap_or((&text, ""));
    let status = head.split_whitespace().nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
    (status, head.to_string(), body.to_string())
}

fn post(addr: SocketAddr, token: Option<&str>, body: &str) -> (u16, String, String) {
    let auth = token.map(|t| format!("Authorization: Bearer {t}\r\n")).unwrap_or_default();
    let req = format!(
        "POST /api/submissions HTTP/1.1\r\nHost: x\r\nConnection: close\r\n{auth}Content-Length: {}\r\n\r\n{body}",
        body.len()
    );
    http(addr, req.as_bytes())
}

fn get(addr: SocketAddr, path: &str) -> (u16, String, String) {
    http(addr, format!("GET {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").as_bytes())
}

#[test]
fn uploads_need_a_token_are_verbatim_and_idempotent() {
    let t = TempDb::new("token");
    let server = highscore::spawn(&t.db(), "127.0.0.1:0", ServerOptions::default()).expect("spawn");
    let addr = server.addr();
    let (_, token) = Store::open(&t.db()).unwrap().issue_token("H2T").unwrap();
    // Odd spacing and key order: kept byte for byte.
    let results = format!("  {}  ", grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 0.1)]).to_json().unwrap());
    let body = format!(r#"{{"submitter": "ann", "results": {results}}}"#);

    let (status, head, _) = post(addr, None, &body);
    assert_eq!(status, 401);
    assert!(head.to_ascii_lowercase().contains("www-authenticate: bearer"), "{head}");
    assert_eq!(post(addr, Some("ogt_not-a-token"), &body).0, 401);
    let (status, _, answer) = post(addr, Some(&token), &body);
    assert_eq!(status, 201, "{answer}");
    let id = serde_json::from_str::<serde_json::Value>(&answer).unwrap()["id"].as_i64().unwrap();
    // A retry is the same entry, not a second one.
    let (status, _, again) = post(addr, Some(&token), &body);
    assert_eq!(status, 200, "{again}");
    assert_eq!(serde_json::from_str::<serde_json::Value>(&again).unwrap()["id"].as_i64(), Some(id));
    // The same results under another name: conflict.
    let (status, _, _) = post(addr, Some(&token), &body.replace("\"ann\"", "\"bob\""));
    assert_eq!(status, 409);
    let (status, _, stored) = get(addr, &format!("/api/submissions/{id}"));
    assert_eq!(status, 200);
    assert_eq!(stored, results.trim(), "the uploaded bytes are served verbatim");
    let (_, _, ranking) = get(addr, "/api/benchmarks/grasp/barrett/ranking");
    let r: serde_json::Value = serde_json::from_str(&ranking).unwrap();
    assert_eq!(r["total"], 1);
    assert_eq!(r["entries"][0]["team"], "H2T", "the team comes from the token");

    // The command-line client against the same server.
    let file = grasp_file(vec![cell("alpha", "barrett", "cup", 12, 5, 0.1)]).to_json().unwrap();
    let who = Submitter::new("carl");
    let answer = highscore::client::upload(&format!("http://{addr}"), &token, &who, &file).expect("upload");
    assert!(!answer.duplicate && answer.benchmarks == ["grasp/barrett"]);
    match highscore::client::upload(&format!("http://{addr}"), "wrong", &who, &file) {
        Err(HighscoreError::Remote { status: 401, .. }) => {}
        other => panic!("401 expected, got {other:?}"),
    }
    server.shutdown().expect("shutdown");
}

#[test]
fn security_headers_pagination_and_early_413() {
    let t = TempDb::new("headers");
    let server = highscore::spawn(&t.db(), "127.0.0.1:0", ServerOptions::default()).expect("spawn");
    let addr = server.addr();
    for path in ["/", "/highscore/grasp/barrett", "/api/benchmarks", "/nope"] {
        let (_, head, _) = get(addr, path);
        let h = head.to_ascii_lowercase();
        assert!(h.contains("content-security-policy: default-src 'none'"), "{path}: {head}");
        assert!(h.contains("x-content-type-options: nosniff"), "{path}: {head}");
    }
    let (status, _, body) = get(addr, "/api/benchmarks/grasp/barrett/ranking?offset=5&limit=2");
    assert_eq!(status, 200, "{body}");
    // A declared 100 MB body is refused at once, without waiting for it.
    let (_, token) = Store::open(&t.db()).unwrap().issue_token("H2T").unwrap();
    let started = Instant::now();
    let req = format!(
        "POST /api/submissions HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer {token}\r\nContent-Length: 100000000\r\n\r\n{{"
    );
    let (status, _, _) = http(addr, req.as_bytes());
    assert_eq!(status, 413);
    eprintln!("declared 100 MB body refused in {:?}", started.elapsed());
    server.shutdown().expect("shutdown");
}

#[test]
fn idle_and_slow_connections_do_not_take_the_server_down() {
    let t = TempDb::new("slowloris");
    let options = ServerOptions {
        max_connections: 64,
        header_read_timeout: Duration::from_millis(500),
        body_read_timeout: Duration::from_millis(500),
        ..ServerOptions::default()
    };
    let server = highscore::spawn(&t.db(), "127.0.0.1:0", options).expect("spawn");
    let addr = server.addr();
    let (_, token) = Store::open(&t.db()).unwrap().issue_token("H2T").unwrap();
    let mut held = Vec::new();
    for i in 0..300 {
        let Ok(mut s) = TcpStream::connect_timeout(&addr, Duration::from_secs(5)) else { continue };
        match i % 3 {
            0 => {}                                                     // idle
            1 => drop(s.write_all(b"GET / HTTP/1.1\r\nHost: x\r\nX-Slow: ")), // partial head
            _ => drop(s.write_all(
                format!("POST /api/submissions HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer {token}\r\nContent-Length: 1000\r\n\r\n{{").as_bytes(),
            )), // slow body
        }
        held.push(s);
    }
    // The timeouts free the slots: a normal request gets through while all 300 are held.
    let started = Instant::now();
    let mut ok = false;
    while started.elapsed() < Duration::from_secs(60) {
        if get(addr, "/api/benchmarks").0 == 200 {
            ok = true;
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    assert!(ok, "the server answered no request while 300 idle/slow connections were open");
    eprintln!("served a request {:?} after opening 300 idle/slow connections", started.elapsed());
    // The held connections were closed by the server.
    std::thread::sleep(Duration::from_millis(1500));
    let mut closed = 0;
    for mut s in held {
        s.set_read_timeout(Some(Duration::from_millis(200))).unwrap();
        let mut buf = [0u8; 512];
        if s.read(&mut buf).is_ok() {
            closed += 1; // EOF or an error answer (408/400) then EOF
        }
    }
    eprintln!("{closed} of the held connections were answered or closed by the server");
    assert_eq!(get(addr, "/").0, 200);
    server.shutdown().expect("shutdown");
}

/// Child half of `fd_exhaustion_is_survived`: serves with a low descriptor limit.
#[test]
#[ignore = "run by fd_exhaustion_is_survived in a child process"]
fn fd_exhaustion_child() {
    let Ok(db) = std::env::var("OPENGRASP_FD_CHILD_DB") else { return };
    let pid = std::process::id().to_string();
    let status = std::process::Command::new("prlimit").args(["--pid", &pid, "--nofile=64:64"]).status();
    assert!(status.is_ok_and(|s| s.success()), "prlimit failed");
    let options = ServerOptions { max_connections: 10_000, ..ServerOptions::default() };
    let server = highscore::spawn(std::path::Path::new(&db), "127.0.0.1:0", options).expect("spawn");
    // The address goes through a file: the test harness may capture stdout.
    std::fs::write(format!("{db}.addr"), server.addr().to_string()).expect("address file");
    let mut line = String::new();
    let _ = std::io::stdin().read_line(&mut line); // until the parent closes stdin
    server.shutdown().expect("the server survived");
}

#[test]
fn fd_exhaustion_is_survived() {
    if std::process::Command::new("prlimit").arg("--version").output().is_err() {
        eprintln!("SKIPPED fd_exhaustion_is_survived: prlimit (util-linux) is not installed");
        return;
    }
    let t = TempDb::new("fd");
    Store::open(&t.db()).unwrap();
    let mut child = std::process::Command::new(std::env::current_exe().unwrap())
        .args(["--exact", "fd_exhaustion_child", "--ignored", "--nocapture", "--test-threads=1"])
        .env("OPENGRASP_FD_CHILD_DB", t.db())
        .stdin(std::process::Stdio::piped())
        .spawn()
        .expect("child");
    let addr_file = format!("{}.addr", t.db().display());
    let started = Instant::now();
    let addr = loop {
        if let Some(a) = std::fs::read_to_string(&addr_file).ok().and_then(|s| s.trim().parse::<SocketAddr>().ok()) {
            break a;
        }
        assert!(started.elapsed() < Duration::from_secs(60), "the child server did not start");
        assert!(child.try_wait().unwrap().is_none(), "the child server died at start");
        std::thread::sleep(Duration::from_millis(50));
    };
    // 200 connections against a 64-descriptor server: accept fails with EMFILE.
    let held: Vec<TcpStream> =
        (0..200).filter_map(|_| TcpStream::connect_timeout(&addr, Duration::from_secs(5)).ok()).collect();
    std::thread::sleep(Duration::from_millis(500));
    assert!(child.try_wait().unwrap().is_none(), "the server process died under fd exhaustion");
    drop(held);
    let started = Instant::now();
    let mut ok = false;
    while started.elapsed() < Duration::from_secs(60) {
        if get(addr, "/api/benchmarks").0 == 200 {
            ok = true;
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    assert!(ok, "the server did not recover after fd exhaustion");
    drop(child.stdin.take());
    let status = child.wait().unwrap();
    assert!(status.success(), "child ended with {status}");
}

/// A solved run of the planner `fast` on the planar post in `time` s, valid after post-processing.
fn fast_run(i: usize, time: f64) -> RunRecord {
    run("fast", "planar post", i, true, time, true)
}
