//! `kill -9` during uploads loses no acknowledged submission: the `opengrasp serve` process is
//! killed while a client uploads, and every upload the server answered 201 is in the database
//! when it is reopened (WAL + `synchronous=FULL`, one transaction per submission).

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use opengrasp::highscore::{client, Store, Submitter};
use opengrasp::results::ResultsFile;
use opengrasp::suite::{Suite, SuiteSize};

/// `results` with every planner renamed `name-i`: a distinct submission for each `i`.
fn renamed(results: &ResultsFile, i: usize) -> String {
    let mut r = results.clone();
    let rename = |n: &mut String| *n = format!("{n}-{i}");
    if let Some(m) = &mut r.motion {
        m.planners.iter_mut().for_each(|p| rename(&mut p.name));
        m.runs.iter_mut().for_each(|x| rename(&mut x.planner));
        m.summaries.iter_mut().for_each(|s| rename(&mut s.planner));
    }
    r.to_json().expect("a valid results file")
}

#[test]
fn kill_9_during_uploads_loses_no_acknowledged_submission() {
    let dir = std::env::temp_dir().join(format!("opengrasp-kill9-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let db = dir.join("board.sqlite");
    let token = Store::open(&db).unwrap().issue_token("lab").unwrap().1;
    let base = Suite::new().with_reference_motion(SuiteSize::Tiny).labelled("tiny").jobs(1).run().unwrap();

    let mut server = Command::new(env!("CARGO_BIN_EXE_opengrasp"))
        .args(["serve", "--addr", "127.0.0.1:0", "--db", db.to_str().unwrap()])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // "serving <db> on http://127.0.0.1:PORT/"
    let mut line = String::new();
    BufReader::new(server.stderr.take().unwrap()).read_line(&mut line).unwrap();
    let url = line.trim().rsplit(" on ").next().unwrap().trim_end_matches('/').to_string();
    assert!(url.starts_with("http://127.0.0.1:"), "{line}");

    // One client uploads distinct submissions until the server dies (at most 400, bounded).
    let acknowledged = Arc::new(Mutex::new(Vec::new()));
    let stop = Arc::new(AtomicBool::new(false));
    let uploader = {
        let (acknowledged, stop, url, token) = (acknowledged.clone(), stop.clone(), url.clone(), token.clone());
        std::thread::spawn(move || {
            for i in 0..400 {
                if stop.load(Ordering::Relaxed) {
                    break;
                }
                match client::upload(&url, &token, &Submitter::new("ann"), &renamed(&base, i)) {
                    Ok(answer) => acknowledged.lock().unwrap().push(answer.id),
                    Err(_) => break, // the server is gone
                }
            }
        })
    };
    // Kill once some uploads are acknowledged (or after at most 20 s).
    for _ in 0..200 {
        if acknowledged.lock().unwrap().len() >= 5 {
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    server.kill().unwrap(); // SIGKILL
    server.wait().unwrap();
    stop.store(true, Ordering::Relaxed);
    uploader.join().unwrap();

    let acknowledged = acknowledged.lock().unwrap().clone();
    assert!(acknowledged.len() >= 5, "the server acknowledged only {} uploads", acknowledged.len());
    let store = Store::open(&db).unwrap();
    for id in &acknowledged {
        let stored = store.submission_json(opengrasp::highscore::SubmissionId(*id));
        assert!(stored.is_ok(), "acknowledged submission {id} lost: {stored:?}");
    }
    assert!(store.counts().unwrap().submissions >= acknowledged.len() as u64);
    std::fs::remove_dir_all(&dir).ok();
}
