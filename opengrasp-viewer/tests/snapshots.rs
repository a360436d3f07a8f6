//! Snapshots of a real (tiny) results file: the motion run is replayed exactly, the grasp is
//! evaluated again, PNGs are written and decode; bad ids are typed errors.

use std::sync::OnceLock;

use opengrasp_bench::results::ResultsFile;
use opengrasp_bench::suite::{Suite, SuiteSize};
use opengrasp_motion::benchmark::RunStatus;
use opengrasp_motion::validate::distance;
use opengrasp_viewer::drawing::BACKGROUND;
use opengrasp_viewer::grasp::{best_candidate, find_grasp, grasp_drawing, replay_grasp};
use opengrasp_viewer::motion::{path_states, run_drawing};
use opengrasp_viewer::replay::{find_run, replay, run_id};
use opengrasp_viewer::snapshot::{write_snapshots, SnapshotOptions};
use opengrasp_viewer::ViewerError;

/// The tiny suite (planar arm around a post; Barrett on the salt can) with every grasp
/// candidate recorded, run once for all tests.
fn results() -> &'static ResultsFile {
    static R: OnceLock<ResultsFile> = OnceLock::new();
    R.get_or_init(|| {
        Suite::standard(SuiteSize::Tiny)
            .record_grasps(true)
            .max_candidates(Some(24))
            .runs(3)
            .jobs(1)
            .seed(7)
            .run()
            .unwrap()
    })
}

fn decode(path: &std::path::Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn every_solved_run_replays_to_its_recorded_path() {
    let motion = results().motion.as_ref().unwrap();
    let solved: Vec<_> = motion.runs.iter().filter(|r| r.status == RunStatus::Solved).collect();
    assert!(solved.len() >= 4, "{} solved runs", solved.len());
    for r in solved {
        // `replay` itself compares iterations, validity and both lengths with the record.
        let run = replay(motion, &run_id(r), &[]).unwrap();
        let start = &run.world.instance.start;
        assert!(distance(&run.planned[0], start) <= 1e-9);
        assert!(distance(&run.processed[0], start) <= 1e-9);
        assert!(distance(run.processed.last().unwrap(), &[-1.2, 0.3]) <= 1e-6);
        assert_eq!(run.processed.last(), r.final_state.as_ref());
        // The post-processed path of a solved run under the certified protocol is valid.
        let states = path_states(&run.world, &run.processed, 0.02).unwrap();
        assert!(states.iter().all(|s| s.valid));
        let d = run_drawing(&run, 0.02).unwrap();
        assert_eq!(d.lines.len(), 2);
        assert!(d.dots.is_empty());
    }
}

#[test]
fn runs_are_found_by_id_or_position_and_unknown_ids_are_typed_errors() {
    let motion = results().motion.as_ref().unwrap();
    let first = &motion.runs[0];
    assert_eq!(find_run(motion, &run_id(first)).unwrap(), first);
    assert_eq!(find_run(motion, "1").unwrap(), &motion.runs[1]);
    for bad in ["RRT-Connect/planar post/99", "nope", "100000"] {
        match find_run(motion, bad) {
            Err(ViewerError::UnknownRun { id, available, example }) => {
                assert_eq!(id, bad);
                assert_eq!(available, motion.runs.len());
                assert_eq!(example, run_id(first));
            }
            other => panic!("{bad}: {:?}", other.map(|r| r.run)),
        }
    }
    let grasp = results().grasp.as_ref().unwrap();
    assert!(matches!(find_grasp(grasp, "medial-axis/barrett/salt_can/100000"), Err(ViewerError::UnknownGrasp { .. })));
}

#[test]
fn a_grasp_replays_with_its_contacts_and_cones() {
    let grasp = results().grasp.as_ref().unwrap();
    let cell = &grasp.cells[0];
    let best = best_candidate(cell).unwrap();
    assert!(best.force_closure, "the tiny suite has a force-closure grasp");
    let g = replay_grasp(cell, best).unwrap();
    assert_eq!(g.evaluation.contacts.len(), best.contacts);
    let d = grasp_drawing(&g).unwrap();
    assert_eq!(d.dots.len(), best.contacts);
    // 8 edges and a rim per contact; each edge ends at its contact and is 3 cm long at the
    // friction angle atan(mu) about the inward normal.
    assert_eq!(d.lines.len(), 9 * best.contacts);
    let mu = g.object.friction;
    for (i, c) in g.evaluation.contacts.iter().enumerate() {
        for edge in d.lines.iter().filter(|l| l.name.starts_with(&format!("cone/{i}/edge"))) {
            let (outer, apex) = (edge.points[0], edge.points[1]);
            assert_eq!(apex, c.contact.point);
            let v = apex - outer;
            assert!((v.norm() - 0.03).abs() < 1e-12);
            let angle = v.normalize().dot(&c.contact.normal).clamp(-1.0, 1.0).acos();
            assert!((angle - mu.atan()).abs() < 1e-9, "{angle} vs {}", mu.atan());
        }
    }
}

#[test]
fn snapshots_are_written_and_decode() {
    let dir = std::env::temp_dir().join(format!("opengrasp-viewer-snapshots-{}", std::process::id()));
    let options = SnapshotOptions { width: 320, height: 240, ..SnapshotOptions::default() };
    let shots = write_snapshots(results(), &dir, &[], &options).unwrap();
    assert!(shots.skipped.is_empty(), "{:?}", shots.skipped);
    let names: Vec<String> =
        shots.written.iter().map(|s| s.path.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert!(names.contains(&"scene_planar_post.png".to_string()), "{names:?}");
    assert!(names.iter().any(|n| n.starts_with("grasp_barrett_salt_can_")), "{names:?}");
    for s in &shots.written {
        let (w, h, rgb) = decode(&s.path);
        assert_eq!((w, h), (320, 240));
        let drawn = rgb.chunks(3).filter(|p| *p != BACKGROUND).count();
        // The framed scene fills a good part of the image but not all of it.
        assert!(drawn > 320 * 240 / 50 && drawn < 320 * 240 * 9 / 10, "{}: {drawn} pixels", s.path.display());
    }
    let md = opengrasp_bench::report::images_markdown(
        "Snapshots",
        &shots.written.iter().map(|s| (s.caption.clone(), s.path.display().to_string())).collect::<Vec<_>>(),
    );
    assert_eq!(md.matches("![").count(), shots.written.len());
    std::fs::remove_dir_all(&dir).ok();
}
