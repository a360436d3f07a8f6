//! Fixtures shared by the runner and command-line tests.

#![allow(dead_code)] // each test binary uses a different subset

use std::path::PathBuf;

use opengrasp::grasp::benchmark::CellResult;
use opengrasp::motion::benchmark::{BenchmarkOptions, PathReport, RunRecord, RunStatus};
use opengrasp::motion::metrics::PathMetrics;
use opengrasp::motion::validate::PathValidity;
use opengrasp::results::{self, GraspRecord, GraspSection, MotionSection, PlannerInfo, Provenance, ResultsFile};
use opengrasp::suite::planar_scene;

/// A fresh empty directory under the system temp dir.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("opengrasp-runner-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn cell(
    planner: &str,
    hand: &str,
    object: &str,
    evaluated: usize,
    palm: usize,
    fc_palm: usize,
    fc: usize,
) -> CellResult {
    let pct = |a: usize, b: usize| if b == 0 { 0.0 } else { 100.0 * a as f64 / b as f64 };
    CellResult {
        planner: planner.into(),
        hand: hand.into(),
        object: object.into(),
        generated: evaluated * 2,
        evaluated,
        closed: evaluated,
        palm_contact: palm,
        force_closure_palm: fc_palm,
        force_closure: fc,
        fc_percent_palm: pct(fc_palm, palm),
        fc_percent_all: pct(fc, evaluated),
        mean_epsilon: 0.05,
        median_epsilon: 0.04,
        physics_tested: 0,
        physics_held: 0,
        physics_slipped: 0,
        physics_dropped: 0,
        physics_grip_moved: 0,
        physics_diverged: 0,
        physics_grip_escaped: 0,
        static_holdable: 0,
        static_agree: 0,
        planning_seconds: 0.01,
        evaluation_seconds: 0.2,
        evaluations_per_second: evaluated as f64 / 0.2,
        candidates: Vec::new(),
    }
}

pub fn path_report(length: f64, clearance: f64, valid: bool) -> PathReport {
    PathReport {
        validity: PathValidity { discrete: valid, strict: valid, continuous: None },
        metrics: PathMetrics {
            waypoints: 5,
            length,
            ee_length: None,
            clearance_mean: Some(clearance),
            clearance_min: Some(clearance / 2.0),
            smoothness: 0.5,
        },
    }
}

pub fn run(planner: &str, run: usize, status: RunStatus, planning_time: f64, length: f64) -> RunRecord {
    let solved = status == RunStatus::Solved;
    RunRecord {
        planner: planner.into(),
        scene: "scene A".into(),
        run,
        seed: run as u64,
        status,
        message: (!solved).then(|| "planning timed out".to_string()),
        setup_time: 0.5,
        planning_time,
        postprocessing_time: solved.then_some(0.1),
        planning_checks: 100,
        postprocessing_checks: 50,
        iterations: solved.then_some(10),
        shortcuts: solved.then_some(2),
        repaired_segments: solved.then_some(0),
        unrepaired_segments: solved.then_some(0),
        planned: solved.then(|| path_report(length * 2.0, 0.2, run != 1)),
        processed: solved.then(|| path_report(length, 0.1, true)),
        final_state: solved.then(|| vec![0.1, 0.2]),
        ik_position_error: None,
        ik_orientation_error: None,
    }
}

/// A hand-made results file with known numbers.
pub fn hand_made() -> ResultsFile {
    let mut file = ResultsFile::new(Provenance::collect("custom", 1));
    let planners = vec![
        PlannerInfo { name: "medial-axis".into(), parameters: "defaults".into() },
        PlannerInfo { name: "surface-normals".into(), parameters: "defaults".into() },
    ];
    file.grasp = Some(GraspSection {
        seed: 3,
        hands: vec!["barrett".into()],
        objects: vec!["salt_can".into(), "white_cup".into()],
        max_candidates: Some(20),
        planners,
        cells: vec![
            GraspRecord { seed: 3, cell: cell("medial-axis", "barrett", "salt_can", 20, 10, 7, 9) },
            GraspRecord { seed: 3, cell: cell("surface-normals", "barrett", "salt_can", 20, 4, 1, 2) },
            GraspRecord { seed: 3, cell: cell("medial-axis", "barrett", "white_cup", 20, 10, 3, 3) },
            GraspRecord { seed: 3, cell: cell("surface-normals", "barrett", "white_cup", 20, 0, 0, 1) },
        ],
    });
    file.motion = Some(MotionSection {
        options: BenchmarkOptions { runs: 3, ..BenchmarkOptions::default() },
        scenes: vec!["scene A".into()],
        planners: vec![PlannerInfo { name: "P1".into(), parameters: "x = 1".into() }],
        runs: vec![
            run("P1", 0, RunStatus::Solved, 0.001, 1.0),
            run("P1", 1, RunStatus::Solved, 0.003, 2.0),
            run("P1", 2, RunStatus::Timeout, 0.008, 0.0),
        ],
        summaries: Vec::new(),
        episodes: Vec::new(),
    });
    file
}

pub fn per_run_scene() -> opengrasp::motion::benchmark::BenchmarkScene {
    let mut scene = planar_scene();
    scene.name = "planar post (per run)".into();
    scene.shared_environment = false;
    scene
}

pub fn without_timing(mut file: ResultsFile) -> (Option<GraspSection>, Option<MotionSection>) {
    if let Some(g) = &mut file.grasp {
        for r in &mut g.cells {
            r.cell.planning_seconds = 0.0;
            r.cell.evaluation_seconds = 0.0;
            r.cell.evaluations_per_second = 0.0;
        }
    }
    if let Some(m) = &mut file.motion {
        for r in &mut m.runs {
            r.setup_time = 0.0;
            r.planning_time = 0.0;
            r.postprocessing_time = r.postprocessing_time.map(|_| 0.0);
        }
        // Summaries aggregate the timing fields; recompute them without.
        m.summaries = results::motion_summaries(m);
    }
    (file.grasp, file.motion)
}
