//! Group commit: several submissions in one transaction, each isolated by a savepoint, and
//! concurrent uploads through [`Db::insert_grouped`] all stored exactly once.

mod common;

use std::sync::Arc;

use common::{cell, grasp_file};
use opengrasp_highscore::{Db, HighscoreError, Store, Submission, Submitter};

/// A distinct valid submission for each `i` (the planner name and epsilon differ).
fn submission(i: usize, who: &str) -> Submission {
    let eps = 0.01 + 0.001 * (i % 100) as f64;
    let f = grasp_file(vec![cell(&format!("p{i}"), "barrett", "mug", 10, 4, eps)]);
    Submission::from_json(&serde_json::to_string(&f).unwrap(), Submitter::new(who)).unwrap()
}

#[test]
fn a_rejected_submission_in_a_group_leaves_the_others_stored() {
    let mut store = Store::open_in_memory().unwrap();
    let a = submission(1, "ann");
    let stolen = submission(1, "bob"); // ann's results under another name: 409
    let retried = submission(1, "ann"); // ann's retry: the same id, nothing written
    let unknown = {
        let f = grasp_file(vec![cell("q", "no such hand", "mug", 10, 4, 0.02)]);
        Submission::from_json(&serde_json::to_string(&f).unwrap(), Submitter::new("cy")).unwrap()
    };
    let b = submission(2, "dee");
    let out = store.insert_batch(&[&a, &stolen, &retried, &unknown, &b]).unwrap();
    let a_id = out[0].as_ref().unwrap().id;
    assert!(!out[0].as_ref().unwrap().duplicate);
    assert!(matches!(out[1], Err(HighscoreError::Duplicate { id }) if id == a_id.0), "{:?}", out[1]);
    assert_eq!(out[2].as_ref().unwrap().id, a_id);
    assert!(out[2].as_ref().unwrap().duplicate);
    assert!(matches!(out[3], Err(HighscoreError::UnknownBenchmark { .. })), "{:?}", out[3]);
    let b_id = out[4].as_ref().unwrap().id;
    assert_ne!(a_id, b_id);
    // Exactly a and b: the unknown-hand submission's row and cells were rolled back.
    let counts = store.counts().unwrap();
    assert_eq!((counts.submissions, counts.grasp_cells), (2, 2));
    let ranking = store.ranking("grasp/barrett").unwrap();
    assert_eq!(ranking.entries.len(), 2);
    assert_eq!(store.submission_json(b_id).unwrap(), b.raw);
}

#[test]
fn concurrent_grouped_uploads_are_each_stored_once() {
    let dir = std::env::temp_dir().join(format!("opengrasp-group-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok(); // a stale database from an earlier process with this id
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("board.sqlite");
    let db = Arc::new(Db::open(&path).unwrap());
    let (threads, each) = (8, 12);
    let workers: Vec<_> = (0..threads)
        .map(|t| {
            let db = db.clone();
            std::thread::spawn(move || {
                (0..each)
                    .map(|k| {
                        let s = submission(t * each + k, "lab");
                        let raw = s.raw.clone();
                        let stored = db.insert_grouped(s).unwrap();
                        assert_eq!(stored.benchmarks, vec!["grasp/barrett".to_string()]);
                        assert!(!stored.inserted.duplicate);
                        (stored.inserted.id, raw)
                    })
                    .collect::<Vec<_>>()
            })
        })
        .collect();
    let mut acknowledged: Vec<_> = workers.into_iter().flat_map(|w| w.join().unwrap()).collect();
    drop(db);
    acknowledged.sort_by_key(|(id, _)| *id);
    acknowledged.dedup_by_key(|(id, _)| *id);
    assert_eq!(acknowledged.len(), threads * each, "every upload has its own id");
    let store = Store::open(&path).unwrap();
    assert_eq!(store.counts().unwrap().submissions, (threads * each) as u64);
    for (id, raw) in &acknowledged {
        assert_eq!(&store.submission_json(*id).unwrap(), raw, "submission {id:?} stored verbatim");
    }
    // A retry through the group path is the same entry.
    drop(store);
    let db = Db::open(&path).unwrap();
    let again = db.insert_grouped(submission(0, "lab")).unwrap();
    assert!(again.inserted.duplicate);
    assert_eq!(again.inserted.id, acknowledged.iter().find(|(_, r)| *r == submission(0, "lab").raw).unwrap().0);
    std::fs::remove_dir_all(&dir).ok();
}
