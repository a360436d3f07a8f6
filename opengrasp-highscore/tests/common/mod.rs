//! Results-file fixtures shared by the high-score tests.

#![allow(dead_code)] // each test binary uses a different subset

use opengrasp_bench::results::{GraspRecord, GraspSection, MotionSection, PlannerInfo, Provenance, ResultsFile};
use opengrasp_grasp::benchmark::CellResult;
use opengrasp_motion::benchmark::{BenchmarkOptions, PathReport, RunRecord, RunStatus};
use opengrasp_motion::metrics::PathMetrics;
use opengrasp_motion::validate::PathValidity;

/// Provenance with fixed timestamps: a fixture built twice is the same submission (same
/// content hash) whatever the clock did in between.
pub fn provenance() -> Provenance {
    let mut p = Provenance::collect("custom", 1);
    p.git_commit = None;
    p.started_at = "2026-01-01T00:00:00Z".into();
    p.finished_at = p.started_at.clone();
    p
}

/// A grasp cell: `palm` palm-contact candidates, `fc` of them in force closure, mean epsilon.
pub fn cell(planner: &str, hand: &str, object: &str, palm: usize, fc: usize, eps: f64) -> GraspRecord {
    GraspRecord {
        seed: 7,
        cell: CellResult {
            planner: planner.into(),
            hand: hand.into(),
            object: object.into(),
            generated: palm + 5,
            evaluated: palm + 5,
            closed: palm,
            palm_contact: palm,
            force_closure_palm: fc,
            force_closure: fc,
            fc_percent_palm: if palm == 0 { 0.0 } else { 100.0 * fc as f64 / palm as f64 },
            fc_percent_all: 100.0 * fc as f64 / (palm + 5) as f64,
            mean_epsilon: eps,
            median_epsilon: eps,
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
            evaluation_seconds: 0.02,
            evaluations_per_second: 100.0,
            candidates: vec![],
        },
    }
}

pub fn planners(names: &[&str]) -> Vec<PlannerInfo> {
    names.iter().map(|n| PlannerInfo { name: n.to_string(), parameters: format!("{n} defaults") }).collect()
}

pub fn grasp_file(cells: Vec<GraspRecord>) -> ResultsFile {
    let mut names: Vec<&str> = cells.iter().map(|c| c.cell.planner.as_str()).collect();
    names.dedup();
    let mut f = ResultsFile::new(provenance());
    f.grasp = Some(GraspSection {
        seed: 7,
        hands: vec!["barrett".into()],
        objects: vec![],
        max_candidates: None,
        planners: planners(&names),
        cells,
    });
    f
}

pub fn report(valid: bool) -> PathReport {
    PathReport {
        validity: PathValidity { discrete: true, strict: valid, continuous: Some(valid) },
        metrics: PathMetrics {
            waypoints: 3,
            length: 2.5,
            ee_length: None,
            clearance_mean: Some(0.1),
            clearance_min: Some(0.05),
            smoothness: 0.5,
        },
    }
}

/// A motion run: solved in `time` s with a valid (or not) post-processed path, or a timeout.
pub fn run(planner: &str, scene: &str, i: usize, solved: bool, time: f64, valid: bool) -> RunRecord {
    RunRecord {
        planner: planner.into(),
        scene: scene.into(),
        run: i,
        seed: i as u64,
        status: if solved { RunStatus::Solved } else { RunStatus::Timeout },
        message: None,
        setup_time: 0.0,
        planning_time: time,
        postprocessing_time: solved.then_some(0.01),
        planning_checks: 100,
        postprocessing_checks: 10,
        iterations: Some(50),
        shortcuts: Some(1),
        repaired_segments: Some(0),
        unrepaired_segments: Some(0),
        planned: solved.then(|| report(true)),
        processed: solved.then(|| report(valid)),
        final_state: solved.then(|| vec![0.0, 0.0]),
        ik_position_error: None,
        ik_orientation_error: None,
    }
}

pub fn motion_file(runs: Vec<RunRecord>) -> ResultsFile {
    let mut names: Vec<&str> = runs.iter().map(|r| r.planner.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    let mut f = ResultsFile::new(provenance());
    f.motion = Some(MotionSection {
        options: BenchmarkOptions { runs: 4, ..BenchmarkOptions::default() },
        scenes: vec!["planar post".into()],
        planners: planners(&names),
        runs,
        summaries: vec![],
        episodes: vec![],
    });
    f
}
