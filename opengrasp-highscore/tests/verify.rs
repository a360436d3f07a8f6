//! Re-verification by replay: a genuine tiny reference results file passes; the same file
//! with changed numbers that still pass the plausibility checks is caught.

use opengrasp_bench::suite::{Suite, SuiteSize};
use opengrasp_highscore::verify::verify_sample;
use opengrasp_highscore::{Submission, Submitter};
use opengrasp_motion::benchmark::{RunStatus, Summary};

#[test]
fn genuine_reference_runs_pass_and_tampered_ones_are_caught() {
    let genuine = Suite::new().with_reference_motion(SuiteSize::Tiny).labelled("tiny").jobs(1).run().unwrap();
    let runs = genuine.motion.as_ref().unwrap().runs.len();
    assert!(runs >= 4, "the tiny reference suite has {runs} runs");
    let all = verify_sample(&genuine, runs, 7).unwrap();
    assert_eq!(all.checked, runs, "every run of a reference planner is replayed");
    assert!(all.mismatches.is_empty(), "{:?}", all.mismatches);

    // Shorter post-processed paths: plausible (the board accepts the file) but not what
    // the seeds give.
    let mut tampered = genuine.clone();
    let mut changed = 0;
    for r in &mut tampered.motion.as_mut().unwrap().runs {
        if let (RunStatus::Solved, Some(p)) = (r.status, r.processed.as_mut()) {
            p.metrics.length *= 0.8;
            changed += 1;
        }
    }
    assert!(changed > 0, "the tiny suite solves some runs");
    // The summaries are recomputed from the changed runs, as a careful cheat would.
    let m = tampered.motion.as_mut().unwrap();
    for s in &mut m.summaries {
        let records: Vec<_> = m.runs.iter().filter(|r| r.planner == s.planner && r.scene == s.scene).collect();
        *s = Summary::from_records(&s.planner, &s.scene, &records);
    }
    let text = serde_json::to_string(&tampered).unwrap();
    let plausible = Submission::from_json(&text, Submitter::new("eve"));
    assert!(plausible.is_ok(), "the tampered file passes plausibility: {plausible:?}");
    let caught = verify_sample(&tampered, runs, 7).unwrap();
    assert_eq!(caught.checked, runs);
    assert_eq!(caught.mismatches.len(), changed, "{:?}", caught.mismatches);
    assert!(caught.mismatches[0].contains("post-processed path length"), "{:?}", caught.mismatches);

    // A sample of 1: drawn by the seed, always one run checked.
    assert_eq!(verify_sample(&genuine, 1, 3).unwrap().checked, 1);
    // A planner of a reference name with other parameters is not judged.
    let mut renamed = tampered.clone();
    renamed.motion.as_mut().unwrap().planners.iter_mut().for_each(|p| p.parameters = "mine".into());
    assert_eq!(verify_sample(&renamed, runs, 7).unwrap(), Default::default());
}

#[test]
fn the_server_refuses_an_upload_whose_replayed_runs_differ() {
    use std::io::{Read, Write};
    let dir = std::env::temp_dir().join(format!("opengrasp-verify-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let options = opengrasp_highscore::ServerOptions { require_token: false, verify_sample: 2, ..Default::default() };
    let server = opengrasp_highscore::spawn(&dir.join("board.sqlite"), "127.0.0.1:0", options).unwrap();
    let post = |results: &str| -> (u16, String) {
        let body = format!("{{\"submitter\": \"eve\", \"results\": {results}}}");
        let mut s = std::net::TcpStream::connect(server.addr()).unwrap();
        write!(
            s,
            "POST /api/submissions HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n\
             Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        )
        .unwrap();
        let mut out = String::new();
        s.read_to_string(&mut out).unwrap();
        (out[9..12].parse().unwrap(), out)
    };
    let genuine = Suite::new().with_reference_motion(SuiteSize::Tiny).labelled("tiny").jobs(1).run().unwrap();
    // Every run's iterations changed: whichever runs are drawn, they differ.
    let mut tampered = genuine.clone();
    for r in &mut tampered.motion.as_mut().unwrap().runs {
        r.iterations = r.iterations.map(|n| n + 1);
    }
    let (status, answer) = post(&serde_json::to_string(&tampered).unwrap());
    assert_eq!(status, 422, "{answer}");
    assert!(answer.contains("2 of 2 replayed runs differ"), "{answer}");
    let (status, answer) = post(&genuine.to_json().unwrap());
    assert_eq!(status, 201, "{answer}");
    server.shutdown().unwrap();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn grasp_cells_are_replayed_and_changed_counts_caught() {
    let genuine = Suite::new().with_reference_grasp(SuiteSize::Tiny).labelled("tiny").jobs(1).run().unwrap();
    let cells = genuine.grasp.as_ref().unwrap().cells.len();
    assert_eq!(cells, 2, "the tiny reference suite: 2 planners x 1 hand x 1 object");
    let all = verify_sample(&genuine, cells, 11).unwrap();
    assert_eq!(all.checked, cells, "every cell replayed");
    assert_eq!(verify_sample(&genuine, 1, 11).unwrap().checked, 1, "a sample of one cell");
    assert!(all.mismatches.is_empty(), "{:?}", all.mismatches);

    // Better grasp quality in every cell with a force-closure grasp (mean and median ε 20 %
    // higher, still within the analytic bound): the replay gives the true values.
    let mut tampered = genuine.clone();
    let mut changed = 0;
    for c in &mut tampered.grasp.as_mut().unwrap().cells {
        let c = &mut c.cell;
        if c.force_closure_palm > 0 && c.mean_epsilon > 0.0 {
            c.mean_epsilon *= 1.2;
            c.median_epsilon *= 1.2;
            changed += 1;
        }
    }
    assert!(changed > 0, "some tiny cell has a force-closure grasp");
    let text = serde_json::to_string(&tampered).unwrap();
    let plausible = Submission::from_json(&text, Submitter::new("eve"));
    assert!(plausible.is_ok(), "the tampered file passes plausibility: {plausible:?}");
    let caught = verify_sample(&tampered, cells, 11).unwrap();
    assert_eq!(caught.checked, cells);
    assert_eq!(caught.mismatches.len(), changed, "{:?}", caught.mismatches);
    assert!(caught.mismatches[0].contains("mean epsilon"), "{:?}", caught.mismatches);
}
