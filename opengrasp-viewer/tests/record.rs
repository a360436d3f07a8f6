//! The rerun recording read back with rerun's own decoder (`re_log_encoding` through the
//! `rerun` crate's re-exports): the expected entities, static or on the expected timelines at
//! the expected time points. Run with `cargo test -p opengrasp-viewer --features rerun` (CI
//! does, see `.ci/run`).

#[cfg(not(feature = "rerun"))]
#[test]
fn recording_tests_need_the_rerun_feature() {
    eprintln!("=== SKIPPED: the rerun recording tests (run `cargo test -p opengrasp-viewer --features rerun`) ===");
}

#[cfg(feature = "rerun")]
mod recording {

    use std::collections::{BTreeMap, BTreeSet};
    use std::sync::OnceLock;

    use opengrasp_bench::results::ResultsFile;
    use opengrasp_bench::suite::{Suite, SuiteSize};
    use opengrasp_grasp::benchmark::TactileRecording;
    use opengrasp_motion::benchmark::RunStatus;
    use opengrasp_viewer::grasp::{best_candidate, find_grasp, grasp_id};
    use opengrasp_viewer::motion::path_states;
    use opengrasp_viewer::record::{grasp_prefix, run_prefix, Recorder, Selection};
    use opengrasp_viewer::replay::{replay, run_id};
    use opengrasp_viewer::ViewerError;
    use rerun::external::re_log_encoding::DecoderApp;
    use rerun::log::{Chunk, LogMsg};

    fn results() -> &'static ResultsFile {
        static R: OnceLock<ResultsFile> = OnceLock::new();
        R.get_or_init(|| {
            Suite::standard(SuiteSize::Tiny)
                .record_grasps(true)
                .record_tactile(Some(TactileRecording::default()))
                .max_candidates(Some(24))
                .runs(2)
                .jobs(1)
                .seed(3)
                .run()
                .unwrap()
        })
    }

    /// Entity → timeline → time points ("static" for static data) of a recording.
    type Index = BTreeMap<String, BTreeMap<String, BTreeSet<i64>>>;

    fn record(selection: &Selection, name: &str) -> Index {
        let path = std::env::temp_dir().join(format!("opengrasp-viewer-{name}-{}.rrd", std::process::id()));
        let recorder = Recorder::to_file(&path).unwrap();
        let skipped = recorder.log_results(results(), selection, &[], 0.02).unwrap();
        assert!(skipped.is_empty(), "{skipped:?}");
        recorder.finish().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).ok();
        let mut index = Index::new();
        for msg in DecoderApp::decode_lazy(bytes.as_slice()) {
            let LogMsg::ArrowMsg(_, arrow) = msg.unwrap() else { continue };
            let chunk = Chunk::from_arrow_msg(&arrow).unwrap();
            let entry = index.entry(chunk.entity_path().to_string().trim_start_matches('/').to_string()).or_default();
            if chunk.timelines().is_empty() {
                entry.entry("static".into()).or_default().insert(0);
            }
            for (timeline, column) in chunk.timelines() {
                entry.entry(timeline.to_string()).or_default().extend(column.times_raw().iter().copied());
            }
        }
        index
    }

    #[test]
    fn a_run_is_recorded_as_two_scrubbable_trajectories() {
        let motion = results().motion.as_ref().unwrap();
        let r = motion.runs.iter().find(|r| r.status == RunStatus::Solved).unwrap();
        let run = replay(motion, &run_id(r), &[]).unwrap();
        let index = record(&Selection::Run(run_id(r)), "run");
        let prefix = run_prefix(&run);
        assert_eq!(prefix, format!("scenes/planar_post/rrt_connect_run_{}", r.run));
        // The post of the scene, the summary and both tip paths are static.
        for e in ["world/post", "summary", "planned/tip_path", "processed/tip_path"] {
            let key = format!("{prefix}/{e}");
            assert!(index.get(&key).is_some_and(|t| t.contains_key("static")), "{key}: {:?}", index.keys());
        }
        // Every link is posed at every densified state of its path, on its own timeline.
        let links: Vec<String> = run.world.instance.robot.links().iter().map(|l| l.name.clone()).collect();
        for (timeline, path) in [("planned", &run.planned), ("processed", &run.processed)] {
            let n = path_states(&run.world, path, 0.02).unwrap().len() as i64;
            assert!(n > 10);
            for l in &links {
                let key = format!("{prefix}/{timeline}/robot/{l}");
                let times = &index[&key][timeline];
                assert_eq!(times, &(0..n).collect::<BTreeSet<_>>(), "{key}");
            }
            // The link meshes are static, logged once under their links.
            assert!(index
                .keys()
                .any(|k| k.starts_with(&format!("{prefix}/{timeline}/robot/")) && index[k].contains_key("static")));
        }
        // Nothing of the grasp benchmark in a single-run recording.
        assert!(!index.keys().any(|k| k.starts_with("grasps/")));
    }

    #[test]
    fn a_grasp_is_recorded_with_contacts_cones_and_tactile_images() {
        let grasp = results().grasp.as_ref().unwrap();
        let cell = &grasp.cells[0];
        let best = best_candidate(cell).unwrap();
        let id = grasp_id(cell, best);
        assert_eq!(find_grasp(grasp, &id).unwrap().1, best);
        let index = record(&Selection::Grasp(id.clone()), "grasp");
        let prefix = grasp_prefix(&id);
        for e in ["contacts", "friction_cones", "summary", "salt_can"] {
            let key = format!("{prefix}/{e}");
            assert!(index.get(&key).is_some_and(|t| t.contains_key("static")), "{key}: {:?}", index.keys());
        }
        let frame = best.tactile.as_ref().expect("the tiny suite's hand has tactile pads");
        for pad in &frame.pads {
            let key = format!("{prefix}/tactile/{}", opengrasp_viewer::snapshot::file_token(&pad.name));
            assert!(index.contains_key(&key), "{key}");
        }
        assert!(!index.keys().any(|k| k.starts_with("scenes/")));
    }

    #[test]
    fn the_overview_has_every_scene_and_grasp_cell() {
        let index = record(&Selection::Overview, "overview");
        assert!(index.keys().any(|k| k.starts_with("scenes/planar_post/") && k.ends_with("/world/post")));
        let cells = results().grasp.as_ref().unwrap().cells.len();
        let recorded: BTreeSet<&str> = index
            .keys()
            .filter(|k| k.starts_with("grasps/"))
            .map(|k| k.splitn(5, '/').take(4).last().unwrap())
            .collect();
        assert_eq!(recorded.len(), 1, "one object in the tiny suite: {recorded:?}");
        let prefixes: BTreeSet<String> = index
            .keys()
            .filter(|k| k.starts_with("grasps/"))
            .map(|k| k.split('/').take(5).collect::<Vec<_>>().join("/"))
            .collect();
        assert_eq!(prefixes.len(), cells);
    }

    #[test]
    fn unknown_ids_and_missing_sections_are_typed_errors() {
        let path = std::env::temp_dir().join(format!("opengrasp-viewer-bad-{}.rrd", std::process::id()));
        let recorder = Recorder::to_file(&path).unwrap();
        let bad = recorder.log_results(results(), &Selection::Run("PRM/planar post/77".into()), &[], 0.02);
        assert!(matches!(bad, Err(ViewerError::UnknownRun { .. })), "{bad:?}");
        let bad = recorder.log_results(results(), &Selection::Grasp("x/y/z/0".into()), &[], 0.02);
        assert!(matches!(bad, Err(ViewerError::UnknownGrasp { .. })), "{bad:?}");
        let mut no_motion = results().clone();
        no_motion.motion = None;
        let bad = recorder.log_results(&no_motion, &Selection::Run("0".into()), &[], 0.02);
        assert!(matches!(bad, Err(ViewerError::UnknownRun { available: 0, .. })), "{bad:?}");
        recorder.finish().unwrap();
        std::fs::remove_file(&path).ok();
    }
}
