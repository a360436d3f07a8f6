//! High-score board: the results database, its rankings and the HTTP service on loopback.

mod common;

use common::{cell, grasp_file, motion_file, provenance, run};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use opengrasp_bench::results::ResultsFile;
use opengrasp_highscore::{self as highscore, Counts, EntryMetrics, HighscoreError, ServerOptions, Store, Submitter};
use opengrasp_motion::benchmark::{RunRecord, RunStatus};
use serde_json::Value;

const TOL: f64 = 1e-12;

// ---------------------------------------------------------------- helpers

/// A fresh database path in the system temp dir (removed by `TempDb::drop`).
struct TempDb(PathBuf);

impl TempDb {
    fn new(tag: &str) -> Self {
        static N: AtomicUsize = AtomicUsize::new(0);
        let n = N.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("opengrasp-highscore-{}-{tag}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir");
        Self(dir)
    }
    fn db(&self) -> PathBuf {
        self.0.join("results.sqlite")
    }
    fn file(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
    fn counts(&self) -> Counts {
        Store::open(&self.db()).expect("open").counts().expect("counts")
    }
}

impl Drop for TempDb {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn submit_file(
    t: &TempDb,
    file: &ResultsFile,
    who: impl Into<Submitter>,
) -> highscore::Result<highscore::SubmissionId> {
    let path = t.file("results.json");
    file.save(&path).expect("save results");
    highscore::submit(&t.db(), &path, who)
}

/// A minimal HTTP/1.1 client over loopback: one request per connection (`Connection: close`),
/// the body written from a second thread so a server that answers early (413) cannot block us.
fn http(addr: SocketAddr, method: &str, path: &str, body: Option<Vec<u8>>) -> (u16, String) {
    let (status, _, body) = http_full(addr, method, path, body, TOKEN.with(|t| t.borrow().clone()).as_deref());
    (status, body)
}

thread_local! {
    /// The API token `http` sends (set by `with_token`).
    static TOKEN: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// Issues a token for team H2T and makes `http` send it on this thread.
fn with_token(db: &Path) -> String {
    let (_, token) = Store::open(db).expect("open").issue_token("H2T").expect("token");
    TOKEN.with(|t| *t.borrow_mut() = Some(token.clone()));
    token
}

/// As `http`, with an optional bearer token; also returns the response head.
fn http_full(
    addr: SocketAddr,
    method: &str,
    path: &str,
    body: Option<Vec<u8>>,
    token: Option<&str>,
) -> (u16, String, String) {
    assert!(addr.ip().is_loopback(), "tests only talk to loopback");
    let mut stream = TcpStream::connect_timeout(&addr, Duration::from_secs(10)).expect("connect");
    stream.set_read_timeout(Some(Duration::from_secs(60))).expect("timeout");
    stream.set_write_timeout(Some(Duration::from_secs(60))).expect("timeout");
    let body = body.unwrap_or_default();
    let auth = token.map(|t| format!("Authorization: Bearer {t}\r\n")).unwrap_or_default();
    let head = format!(
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\nContent-Type: application/json\r\n\
         {auth}Content-Length: {}\r\n\r\n",
        body.len()
    );
    let mut writer = stream.try_clone().expect("clone");
    let w = std::thread::spawn(move || {
        let _ = writer.write_all(head.as_bytes());
        let _ = writer.write_all(&body);
        let _ = writer.flush();
    });
    let mut raw = Vec::new();
    // A reset after an early answer ends the read with an error; what was read is kept.
    let _ = stream.read_to_end(&mut raw);
    let _ = w.join();
    let split = raw.windows(4).position(|w| w == b"\r\n\r\n").expect("response head");
    let head = String::from_utf8_lossy(&raw[..split]).to_string();
    let status: u16 = head.split_whitespace().nth(1).and_then(|s| s.parse().ok()).expect("status code");
    let mut body = raw[split + 4..].to_vec();
    if head.to_ascii_lowercase().contains("transfer-encoding: chunked") {
        let mut out = Vec::new();
        let mut rest = &body[..];
        while let Some(eol) = rest.windows(2).position(|w| w == b"\r\n") {
            let size = usize::from_str_radix(String::from_utf8_lossy(&rest[..eol]).trim(), 16).expect("chunk size");
            if size == 0 {
                break;
            }
            out.extend_from_slice(&rest[eol + 2..eol + 2 + size]);
            rest = &rest[eol + 4 + size..];
        }
        body = out;
    }
    (status, head, String::from_utf8(body).expect("utf-8 body"))
}

fn json(body: &str) -> Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("not json ({e}): {body}"))
}

fn upload(submitter: &str, results: &ResultsFile) -> Vec<u8> {
    let results: Value = serde_json::from_str(&results.to_json().expect("json")).expect("value");
    serde_json::to_vec(&serde_json::json!({ "submitter": submitter, "team": "H2T", "results": results })).expect("body")
}

// ---------------------------------------------------------------- library

#[test]
fn slugs_of_scene_names() {
    assert_eq!(highscore::slug("standard (7-DoF stand-in)"), "standard-7-dof-stand-in");
    assert_eq!(highscore::slug("IK-based (ARMAR-III kitchen)"), "ik-based-armar-iii-kitchen");
    assert_eq!(highscore::slug("  planar post "), "planar-post");
    assert_eq!(highscore::slug("(!)"), "");
}

#[test]
fn builtin_benchmarks_are_registered_and_distinct() {
    let t = TempDb::new("builtin");
    // Reads never create the database.
    assert!(matches!(highscore::benchmarks(&t.db()), Err(HighscoreError::NoDatabase { .. })));
    assert!(matches!(highscore::ranking(&t.db(), None), Err(HighscoreError::NoDatabase { .. })));
    assert!(!t.db().exists());
    Store::open(&t.db()).expect("create");
    let b = highscore::benchmarks(&t.db()).expect("benchmarks");
    let ids: Vec<&str> = b.iter().map(|b| b.id.as_str()).collect();
    for id in ["grasp/barrett", "grasp/armar3", "motion/planar-post", "motion/standard-7-dof-stand-in"] {
        assert!(ids.contains(&id), "{id} missing from {ids:?}");
    }
    let mut dedup = ids.clone();
    dedup.dedup();
    assert_eq!(dedup.len(), ids.len());
    assert!(b.iter().all(|b| b.submissions == 0));
    // Re-opening keeps the schema and does not duplicate benchmarks.
    assert_eq!(highscore::benchmarks(&t.db()).expect("again").len(), b.len());
}

#[test]
fn grasp_ranking_pools_objects_then_breaks_ties_by_epsilon() {
    let t = TempDb::new("grasp-rank");
    // alpha: (5 + 3) / (10 + 10) = 40 %, epsilon (0.1·5 + 0.3·3) / 8 = 0.175.
    let a = submit_file(
        &t,
        &grasp_file(vec![
            cell("alpha", "barrett", "salt_can", 10, 5, 0.1),
            cell("alpha", "barrett", "cup", 10, 3, 0.3),
        ]),
        "ann",
    )
    .expect("alpha");
    // beta: 8 / 20 = 40 %, epsilon 0.2 -> ahead of alpha on the tie-breaker.
    let b = submit_file(&t, &grasp_file(vec![cell("beta", "barrett", "cup", 20, 8, 0.2)]), "bob").expect("beta");
    // gamma: 50 % -> first whatever its epsilon.
    let c = submit_file(&t, &grasp_file(vec![cell("gamma", "barrett", "cup", 4, 2, 0.01)]), "cy").expect("gamma");
    assert!(a < b && b < c);
    let r = highscore::ranking(&t.db(), Some("grasp/barrett")).expect("ranking");
    assert_eq!(r.len(), 1);
    let e = &r[0].entries;
    let order: Vec<&str> = e.iter().map(|e| e.planner.as_str()).collect();
    assert_eq!(order, ["gamma", "beta", "alpha"]);
    assert_eq!(e.iter().map(|e| e.rank).collect::<Vec<_>>(), [1, 2, 3]);
    match &e[2].metrics {
        EntryMetrics::Grasp { objects, palm_contact, force_closure_palm, fc_percent, mean_epsilon, .. } => {
            assert_eq!((*objects, *palm_contact, *force_closure_palm), (2, 20, 8));
            assert!((fc_percent - 40.0).abs() < TOL);
            assert!((mean_epsilon - 0.175).abs() < TOL);
        }
        m => panic!("grasp metrics expected, got {m:?}"),
    }
    assert_eq!(e[2].submitter, "ann");
    assert_eq!(e[2].seed, Some(7));
    assert_eq!(e[2].parameters.as_deref(), Some("alpha defaults"));
    // Lookup by the hand name works too; the other hand has no entries.
    assert_eq!(highscore::ranking(&t.db(), Some("grasp/Barrett")).expect("by name")[0].entries.len(), 3);
    assert!(highscore::ranking(&t.db(), Some("grasp/armar3")).expect("armar3")[0].entries.is_empty());
    let table = highscore::render_rankings(&r);
    assert!(table.contains("grasp/barrett") && table.contains("gamma") && table.contains("40.0"), "{table}");
}

#[test]
fn motion_ranking_success_then_median_time_then_validity() {
    let t = TempDb::new("motion-rank");
    let s = "planar post";
    // fast: 3/4 solved, median 0.2 s, all valid.
    let fast: Vec<RunRecord> = [(true, 0.1), (true, 0.3), (true, 0.2), (false, 5.0)]
        .iter()
        .enumerate()
        .map(|(i, &(ok, t))| run("fast", s, i, ok, t, true))
        .collect();
    // slow: 3/4 solved, median 0.6 s.
    let slow: Vec<RunRecord> = [(true, 0.5), (true, 0.6), (true, 0.7), (false, 5.0)]
        .iter()
        .enumerate()
        .map(|(i, &(ok, t))| run("slow", s, i, ok, t, true))
        .collect();
    // sloppy: like fast but one post-processed path invalid -> behind fast.
    let sloppy: Vec<RunRecord> = [(true, 0.1), (true, 0.3), (true, 0.2), (false, 5.0)]
        .iter()
        .enumerate()
        .map(|(i, &(ok, t))| run("sloppy", s, i, ok, t, i != 1))
        .collect();
    // sure: 4/4 solved but slow -> first on success rate.
    let sure: Vec<RunRecord> = (0..4).map(|i| run("sure", s, i, true, 3.0, true)).collect();
    // never: 0/4 -> last, no median.
    let never: Vec<RunRecord> = (0..4).map(|i| run("never", s, i, false, 5.0, false)).collect();
    let all: Vec<RunRecord> = [slow, sloppy, fast.clone(), sure, never].concat();
    let first = submit_file(&t, &motion_file(all), Submitter::new("dora").with_team("lab")).expect("submit");
    // The same fast results again, later: equal on every key -> shares the rank.
    let second = submit_file(&t, &motion_file(fast), "eve").expect("again");
    let r = &highscore::ranking(&t.db(), Some("motion/planar-post")).expect("ranking")[0];
    let rows: Vec<(usize, &str, i64)> =
        r.entries.iter().map(|e| (e.rank, e.planner.as_str(), e.submission.0)).collect();
    assert_eq!(
        rows,
        [
            (1, "sure", first.0),
            (2, "fast", first.0),
            (2, "fast", second.0),
            (4, "sloppy", first.0),
            (5, "slow", first.0),
            (6, "never", first.0)
        ]
    );
    match &r.entries[3].metrics {
        EntryMetrics::Motion { runs, solved, success_rate, median_planning_time, valid_processed } => {
            assert_eq!((*runs, *solved), (4, 3));
            assert!((success_rate - 75.0).abs() < TOL);
            assert!((median_planning_time.expect("median") - 0.2).abs() < TOL);
            assert!((valid_processed - 200.0 / 3.0).abs() < 1e-9);
        }
        m => panic!("motion metrics expected, got {m:?}"),
    }
    assert!(matches!(r.entries[5].metrics, EntryMetrics::Motion { median_planning_time: None, .. }));
    assert_eq!(r.entries[0].team.as_deref(), Some("lab"));
    let all = highscore::ranking(&t.db(), None).expect("all");
    assert!(all.iter().any(|r| r.benchmark.id == "motion/planar-post" && r.benchmark.submissions == 2));
}

#[test]
fn rejected_files_leave_the_database_unchanged() {
    let t = TempDb::new("reject");
    submit_file(&t, &grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 0.1)]), "ann").expect("valid");
    let before = t.counts();
    assert_eq!(before, Counts { submissions: 1, grasp_cells: 1, motion_runs: 0 });
    // One known and one unknown hand: the whole file is rejected, nothing half-written.
    let mixed =
        grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 0.1), cell("alpha", "shadow", "cup", 1, 1, 0.1)]);
    match submit_file(&t, &mixed, "ann") {
        Err(HighscoreError::UnknownBenchmark { id }) => assert_eq!(id, "grasp/shadow"),
        other => panic!("unknown benchmark expected, got {other:?}"),
    }
    assert_eq!(t.counts(), before);
    // Empty submitter, control characters, overlong names.
    for who in ["", "a\u{7}b", &"x".repeat(highscore::MAX_NAME + 1)] {
        let e = submit_file(&t, &grasp_file(vec![cell("alpha", "barrett", "cup", 1, 1, 0.1)]), who);
        assert!(matches!(e, Err(HighscoreError::InvalidField { .. })), "{who:?}: {e:?}");
    }
    // Malformed file, missing file, a negative time written by hand.
    let path = t.file("bad.json");
    std::fs::write(&path, "{ not json").expect("write");
    assert!(matches!(highscore::submit(&t.db(), &path, "ann"), Err(HighscoreError::InvalidJson { .. })));
    assert!(matches!(highscore::submit(&t.db(), &t.file("missing.json"), "ann"), Err(HighscoreError::Io { .. })));
    let mut bad = serde_json::to_value(grasp_file(vec![cell("alpha", "barrett", "cup", 1, 1, 0.1)])).expect("value");
    bad["grasp"]["cells"][0]["planning_seconds"] = serde_json::json!(-1.0);
    std::fs::write(&path, bad.to_string()).expect("write");
    match highscore::submit(&t.db(), &path, "ann") {
        Err(HighscoreError::InvalidField { field, .. }) => assert_eq!(field, "grasp.cells[0].planning_seconds"),
        other => panic!("invalid field expected, got {other:?}"),
    }
    // Nothing to rank.
    let empty = ResultsFile::new(provenance());
    assert!(matches!(submit_file(&t, &empty, "ann"), Err(HighscoreError::InvalidField { .. })));
    assert_eq!(t.counts(), before);
}

#[test]
fn newer_schema_is_refused_and_benchmarks_can_be_registered() {
    let t = TempDb::new("schema");
    let id = highscore::register_benchmark(&t.db(), highscore::BenchmarkKind::Grasp, "Shadow Hand", "the shadow hand")
        .expect("register");
    assert_eq!(id, "grasp/shadow-hand");
    let f = grasp_file(vec![cell("alpha", "Shadow Hand", "cup", 2, 1, 0.1)]);
    submit_file(&t, &f, "ann").expect("registered hand accepted");
    assert_eq!(highscore::ranking(&t.db(), Some(&id)).expect("ranking")[0].entries.len(), 1);
    {
        let conn = rusqlite::Connection::open(t.db()).expect("open");
        conn.pragma_update(None, "user_version", 99).expect("pragma");
    }
    match Store::open(&t.db()) {
        Err(HighscoreError::SchemaVersion { found: 99, supported }) => assert_eq!(supported, highscore::SCHEMA_VERSION),
        other => panic!("schema version error expected, got {other:?}"),
    }
}

// ---------------------------------------------------------------- HTTP

#[test]
fn http_submit_rank_and_render() {
    let t = TempDb::new("http");
    let server = highscore::spawn(&t.db(), "127.0.0.1:0", ServerOptions::default()).expect("spawn");
    with_token(&t.db());
    let addr = server.addr();

    let (status, body) = http(addr, "GET", "/api/benchmarks", None);
    assert_eq!(status, 200, "{body}");
    let list = json(&body);
    assert!(list.as_array().expect("array").iter().any(|b| b["id"] == "grasp/barrett"));

    let evil = "<script>alert(1)</script>";
    let f = grasp_file(vec![cell(evil, "barrett", "cup", 10, 5, 0.1), cell("plain", "barrett", "cup", 10, 2, 0.3)]);
    let (status, body) = http(addr, "POST", "/api/submissions", Some(upload("ann & co", &f)));
    assert_eq!(status, 201, "{body}");
    let done = json(&body);
    assert_eq!(done["benchmarks"], serde_json::json!(["grasp/barrett"]));
    let id = done["id"].as_i64().expect("id");

    let (status, body) = http(addr, "GET", "/api/benchmarks/grasp/barrett/ranking", None);
    assert_eq!(status, 200, "{body}");
    let r = json(&body);
    assert_eq!(r["entries"][0]["planner"], evil);
    assert_eq!(r["entries"][0]["rank"], 1);
    assert_eq!(r["entries"][0]["submission"], id);
    assert_eq!(r["entries"][0]["team"], "H2T");
    assert!((r["entries"][0]["metrics"]["fc_percent"].as_f64().expect("fc") - 50.0).abs() < TOL);
    assert_eq!(r["entries"][1]["planner"], "plain");

    let (status, page) = http(addr, "GET", "/highscore/grasp/barrett", None);
    assert_eq!(status, 200);
    assert!(page.contains("&lt;script&gt;alert(1)&lt;/script&gt;"), "{page}");
    assert!(!page.contains(evil), "unescaped planner name in the page");
    assert!(page.contains("ann &amp; co"));
    let (status, index) = http(addr, "GET", "/", None);
    assert_eq!(status, 200);
    assert!(index.contains("href=\"/highscore/grasp/barrett\""));

    let (status, stored) = http(addr, "GET", &format!("/api/submissions/{id}"), None);
    assert_eq!(status, 200);
    assert_eq!(ResultsFile::from_json(&stored).expect("stored file"), f);

    for path in ["/api/benchmarks/grasp/shadow/ranking", "/highscore/motion/nowhere", "/api/submissions/999", "/nope"] {
        let (status, body) = http(addr, "GET", path, None);
        assert_eq!(status, 404, "{path}: {body}");
    }
    server.shutdown().expect("shutdown");
}

#[test]
fn http_rejects_bad_uploads_without_writing() {
    let t = TempDb::new("http-reject");
    let server = highscore::spawn(&t.db(), "127.0.0.1:0", ServerOptions::default()).expect("spawn");
    with_token(&t.db());
    let addr = server.addr();
    let good = grasp_file(vec![cell("alpha", "barrett", "cup", 10, 5, 0.1)]);
    let (status, body) = http(addr, "POST", "/api/submissions", Some(upload("ann", &good)));
    assert_eq!(status, 201, "{body}");
    let before = t.counts();

    let good_value: Value = serde_json::from_slice(&upload("ann", &good)).expect("value");
    let with = |f: &dyn Fn(&mut Value)| {
        let mut v = good_value.clone();
        f(&mut v);
        serde_json::to_vec(&v).expect("body")
    };
    let mut too_big_number = String::from_utf8(upload("ann", &good)).expect("utf-8");
    too_big_number = too_big_number.replacen("\"mean_epsilon\":0.1", "\"mean_epsilon\":1e400", 1);
    assert!(too_big_number.contains("1e400"));
    let mut oversized = b"{\"submitter\":\"ann\",\"results\":\"".to_vec();
    oversized.resize(highscore::MAX_UPLOAD_BYTES + 1024, b'a');
    oversized.extend_from_slice(b"\"}");

    let cases: Vec<(&str, Vec<u8>, u16, &str)> = vec![
        ("malformed json", b"{\"submitter\": \"ann\", \"results\": {".to_vec(), 400, "invalid_json"),
        ("not an object", b"[1, 2, 3]".to_vec(), 400, "invalid_json"),
        ("number too large for f64", too_big_number.into_bytes(), 400, "invalid_json"),
        ("missing results", br#"{"submitter": "ann"}"#.to_vec(), 400, "invalid_json"),
        ("unknown top-level field", with(&|v| v["extra"] = 1.into()), 400, "invalid_json"),
        (
            "negative time",
            with(&|v| v["results"]["grasp"]["cells"][0]["planning_seconds"] = serde_json::json!(-0.5)),
            422,
            "invalid_field",
        ),
        (
            "percentage above 100",
            with(&|v| v["results"]["grasp"]["cells"][0]["fc_percent_palm"] = serde_json::json!(150.0)),
            422,
            "invalid_field",
        ),
        ("empty submitter", with(&|v| v["submitter"] = "  ".into()), 422, "invalid_field"),
        ("overlong team", with(&|v| v["team"] = "t".repeat(500).into()), 422, "invalid_field"),
        (
            "unknown benchmark",
            with(&|v| v["results"]["grasp"]["cells"][0]["hand"] = "shadow".into()),
            422,
            "unknown_benchmark",
        ),
        ("schema version", with(&|v| v["results"]["schema_version"] = 2.into()), 422, "invalid_field"),
        ("oversized upload", oversized, 413, "too_large"),
    ];
    for (what, body, expected, code) in cases {
        let (status, answer) = http(addr, "POST", "/api/submissions", Some(body));
        assert_eq!(status, expected, "{what}: {answer}");
        let err = json(&answer);
        assert_eq!(err["error"], code, "{what}: {answer}");
        assert!(err["message"].as_str().is_some_and(|m| !m.is_empty()), "{what}: {answer}");
        assert_eq!(t.counts(), before, "{what} changed the database");
    }
    // The server still works after the rejections.
    let (status, body) = http(addr, "GET", "/api/benchmarks/grasp/barrett/ranking", None);
    assert_eq!(status, 200);
    assert_eq!(json(&body)["entries"].as_array().expect("entries").len(), 1);
    drop(server);
}

#[test]
fn real_tiny_motion_run_is_submitted_and_ranked() {
    use opengrasp_motion::planners::RrtConnect;
    let results = opengrasp_bench::suite::Suite::new()
        .motion_planner("default options", || Box::new(RrtConnect::default()))
        .motion_scene(opengrasp_bench::suite::planar_scene())
        .runs(3)
        .seed(1)
        .jobs(1)
        .run()
        .expect("tiny motion suite");
    let t = TempDb::new("real");
    let path = t.file("run.json");
    results.save(&path).expect("save");
    let server = highscore::spawn(&t.db(), "127.0.0.1:0", ServerOptions::default()).expect("spawn");
    with_token(&t.db());
    let text = std::fs::read_to_string(&path).expect("read");
    let body = format!(r#"{{"submitter": "ci", "results": {text}}}"#);
    let (status, answer) = http(server.addr(), "POST", "/api/submissions", Some(body.into_bytes()));
    assert_eq!(status, 201, "{answer}");
    let (status, answer) = http(server.addr(), "GET", "/api/benchmarks/motion/planar-post/ranking", None);
    assert_eq!(status, 200);
    let r = json(&answer);
    let entry = &r["entries"][0];
    assert_eq!(entry["planner"], "RRT-Connect");
    assert_eq!(entry["metrics"]["runs"], 3);
    let solved = results.motion.as_ref().expect("motion").runs.iter().filter(|r| r.status == RunStatus::Solved).count();
    assert_eq!(entry["metrics"]["solved"], solved as u64);
    server.shutdown().expect("shutdown");
    // The same file through the library path ranks identically.
    let t2 = TempDb::new("real-lib");
    highscore::submit(&t2.db(), Path::new(&path), "ci").expect("submit");
    let lib = &highscore::ranking(&t2.db(), Some("motion/planar post")).expect("ranking")[0];
    assert_eq!(serde_json::to_value(&lib.entries[0].metrics).expect("json"), entry["metrics"]);
}

// ---------------------------------------------------------------- properties

mod properties {
    use super::*;
    use proptest::prelude::*;

    fn motion_metrics() -> impl Strategy<Value = EntryMetrics> {
        (0u64..5, 1u64..5, proptest::option::of(0.0f64..2.0), 0u64..3).prop_map(|(solved, extra, t, valid)| {
            let runs = solved + extra;
            EntryMetrics::Motion {
                runs,
                solved,
                success_rate: 100.0 * solved as f64 / runs as f64,
                median_planning_time: if solved > 0 { t.map(|t| (t * 4.0).round() / 4.0) } else { None },
                valid_processed: 50.0 * valid.min(2) as f64,
            }
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        #[test]
        fn slug_is_idempotent_and_url_safe(name in "\\PC{0,40}") {
            let s = highscore::slug(&name);
            prop_assert_eq!(highscore::slug(&s), s.clone());
            prop_assert!(s.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'));
            prop_assert!(!s.starts_with('-') && !s.ends_with('-') && !s.contains("--"));
        }

        #[test]
        fn escaped_html_has_no_markup(text in "\\PC{0,60}") {
            let e = highscore::html::escape(&text);
            prop_assert!(!e.contains('<') && !e.contains('>') && !e.contains('"') && !e.contains('\''));
        }

        #[test]
        fn motion_order_is_a_total_order(a in motion_metrics(), b in motion_metrics(), c in motion_metrics()) {
            prop_assert_eq!(a.compare(&b), b.compare(&a).reverse());
            prop_assert!(a.compare(&a).is_eq());
            if a.compare(&b).is_le() && b.compare(&c).is_le() {
                prop_assert!(a.compare(&c).is_le());
            }
            // A higher success rate always ranks first, whatever the times.
            if let (EntryMetrics::Motion { success_rate: sa, .. }, EntryMetrics::Motion { success_rate: sb, .. }) = (&a, &b) {
                if sa > sb {
                    prop_assert!(a.compare(&b).is_lt());
                }
            }
        }
    }
}

#[test]
fn suite_sizes_are_ranked_as_separate_leagues() {
    let t = TempDb::new("leagues");
    let sized = |size: &str, planner: &str, palm: usize, fc: usize| {
        let mut c = cell(planner, "barrett", "cup", palm, fc, 0.1);
        let max = match size {
            "tiny" => Some(4),
            "default" => Some(128),
            _ => None,
        };
        if let Some(m) = max {
            // The reference sizes evaluate at most their candidate limit per cell.
            c.cell.generated = c.cell.generated.min(m);
            c.cell.evaluated = c.cell.evaluated.min(m);
            c.cell.fc_percent_all = 100.0 * fc as f64 / c.cell.evaluated as f64;
        }
        let mut f = grasp_file(vec![c]);
        f.provenance.suite_size = size.into();
        f.grasp.as_mut().expect("grasp").max_candidates = max;
        f
    };
    // A tiny run with 100 % must not outrank paper-sized runs; each size has its own ranks.
    submit_file(&t, &sized("tiny", "lucky", 2, 2), "ann").expect("tiny");
    submit_file(&t, &sized("default", "mid", 20, 10), "bob").expect("default");
    submit_file(&t, &sized("paper", "steady", 400, 200), "cy").expect("paper a");
    submit_file(&t, &sized("paper", "better", 400, 300), "dan").expect("paper b");
    let r = &highscore::ranking(&t.db(), Some("grasp/barrett")).expect("ranking")[0];
    let rows: Vec<(&str, usize, &str)> =
        r.entries.iter().map(|e| (e.suite_size.as_str(), e.rank, e.planner.as_str())).collect();
    assert_eq!(rows, [("paper", 1, "better"), ("paper", 2, "steady"), ("default", 1, "mid"), ("tiny", 1, "lucky")]);
    assert!(r.rules.contains("suite size"));
}
