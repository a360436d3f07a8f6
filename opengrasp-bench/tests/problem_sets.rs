//! Motion problem sets as benchmark scenes: the vendored MotionBenchMaker subset (5 Panda
//! `table_pick` problems, `opengrasp-motion/tests/data/mbm`) through the suite, graded and
//! logged like the kitchen scenes.

use std::path::PathBuf;

use opengrasp_bench::problem_sets::{load_problem_sets, problem_set_scene, ProblemSetChecker};
use opengrasp_bench::suite::Suite;
use opengrasp_motion::benchmark::RunStatus;
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::Goal;

fn table_pick() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../opengrasp-motion/tests/data/mbm/panda/problems/table_pick_panda")
}

#[test]
fn run_r_plans_problem_r_whatever_the_base_seed() {
    let set = std::sync::Arc::new(load_problem_sets(table_pick()).unwrap().remove(0));
    let goal = |i: usize| set.goal(i).cloned().unwrap();
    let scene = problem_set_scene(set.clone(), 40);
    assert!(!scene.shared_environment);
    assert_eq!(scene.name, "table_pick_panda");
    for run in 0..7u64 {
        let instance = (scene.generate)(40 + run).unwrap();
        assert_eq!(instance.goal, goal(run as usize % 5), "run {run}");
    }
    assert!(matches!(goal(0), Goal::Configuration(ref q) if q.len() == 7));
}

#[test]
fn rrt_connect_solves_a_problem_set_through_the_suite_with_reports_and_ompl_logs() {
    let sets = load_problem_sets(table_pick()).unwrap();
    let suite = Suite::new()
        .seed(3)
        .with_problem_sets(sets, 3)
        .retain_planners(&["RRT-Connect".to_string()])
        .unwrap()
        .runs(2)
        .jobs(1);
    let results = suite.run().unwrap();
    let motion = results.motion.as_ref().unwrap();
    assert_eq!(motion.runs.len(), 2);
    assert!(motion.runs.iter().all(|r| r.scene == "table_pick_panda" && r.planner == "RRT-Connect"));
    let runs: Vec<usize> = motion.runs.iter().map(|r| r.run).collect();
    assert_eq!(runs, [0, 1]);
    let solved = motion.runs.iter().filter(|r| r.status == RunStatus::Solved).count();
    assert_eq!(solved, 2);
    for r in &motion.runs {
        let p = r.processed.as_ref().unwrap();
        assert!(p.validity.discrete && p.validity.strict, "run {}", r.run);
        assert!(p.metrics.ee_length.is_some(), "the SRDF's end effector (panda_link8) is measured");
    }
    let logs = opengrasp_bench::ompl::logs(motion, &results.provenance);
    assert_eq!(logs.len(), 1);
    assert!(logs[0].1.contains("2 runs"), "{}", &logs[0].1[..400.min(logs[0].1.len())]);
    let table = opengrasp_bench::report::motion_table(motion, opengrasp_bench::report::Format::Markdown);
    assert!(table.contains("table_pick_panda"));
}

#[test]
fn runs_default_to_the_largest_set_and_every_planner_runs() {
    let dir = std::env::temp_dir().join(format!("opengrasp-bench-sets-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let problem = r#"{ "start": [1.2, 0.3], "goal": { "configuration": [-1.2, 0.3] },
        "obstacles": [ { "name": "ball", "type": "sphere", "radius": 0.1, "pose": { "position": [2, 2, 0] } } ] }"#;
    let text = format!(
        r#"{{ "name": "planar", "robot": {{ "stock": "planar_arm" }}, "problems": [{problem}, {problem}, {problem}] }}"#
    );
    std::fs::write(dir.join("planar.json"), text).unwrap();
    let sets = load_problem_sets(dir.join("planar.json")).unwrap();
    let results = Suite::new().seed(0).with_problem_sets(sets, 0).jobs(1).run().unwrap();
    let motion = results.motion.unwrap();
    let planners: std::collections::BTreeSet<&str> = motion.runs.iter().map(|r| r.planner.as_str()).collect();
    assert_eq!(planners.into_iter().collect::<Vec<_>>(), ["PRM", "RRT-Connect"], "IK-RRT only on pose goals");
    assert_eq!(motion.runs.len(), 2 * 3, "3 runs per planner: the set's size");
    assert!(motion.runs.iter().all(|r| r.status == RunStatus::Solved));
}

/// `--checker spheres`: RRT-Connect plans on the Panda's sphere model (fewer checks' worth of
/// time), and the exact validators grade the paths: every planned and post-processed path
/// valid under the meshes.
#[test]
fn problem_sets_planned_on_spheres_are_graded_by_the_meshes() {
    let sets = load_problem_sets(table_pick()).unwrap();
    let suite = Suite::new()
        .seed(3)
        .with_problem_sets_checked_by(sets, 3, ProblemSetChecker::Spheres(GreedyCoverOptions::default()))
        .unwrap()
        .retain_planners(&["RRT-Connect".to_string()])
        .unwrap()
        .runs(5)
        .jobs(1);
    let results = suite.run().unwrap();
    let motion = results.motion.as_ref().unwrap();
    assert_eq!(motion.runs.len(), 5);
    for r in &motion.runs {
        assert_eq!(r.scene, "table_pick_panda (spheres)");
        assert_eq!(r.status, RunStatus::Solved, "run {}: {:?}", r.run, r.message);
        let planned = r.planned.as_ref().unwrap();
        assert!(planned.validity.discrete, "run {}: the sphere model's path fails the meshes", r.run);
        let processed = r.processed.as_ref().unwrap();
        assert!(processed.validity.discrete && processed.validity.strict, "run {}", r.run);
    }
}
