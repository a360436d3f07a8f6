//! RRT-Connect with VAMP's tree balancing (`RrtConnectOptions::balance`,
//! `RrtConnectOptions::vamp_like`): solves the MotionBenchMaker Panda problems on the sphere
//! model with paths the meshes accept, the same path for the same seed, and on the cage set
//! checks far fewer states than strict alternation.

use std::sync::Arc;
use std::time::Duration;

use opengrasp_motion::planners::{RrtConnect, RrtConnectOptions};
use opengrasp_motion::problem_set::{self, LoadedProblemSet, PlanningModel};
use opengrasp_motion::validate::{path_valid_discrete, validate_path, ValidationOptions, DEFAULT_STEP};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::CountingChecker;
use opengrasp_motion::MotionPlanner;

fn sets_and_model() -> (Vec<LoadedProblemSet>, PlanningModel) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda/problems");
    let sets: Vec<LoadedProblemSet> =
        problem_set::load(dir).unwrap().iter().map(|s| LoadedProblemSet::new(s).unwrap()).collect();
    let model = PlanningModel::Spheres(Arc::new(sets[0].layered_sphere_model(GreedyCoverOptions::default()).unwrap()));
    (sets, model)
}

#[test]
fn vamp_like_settings_balance_the_trees_with_range_one() {
    let o = RrtConnectOptions::vamp_like();
    assert!(o.balance);
    assert_eq!(o.range, 1.0);
    assert_eq!(o.dynamic_domain, None);
    // The benchmark's defaults are unchanged.
    assert!(!RrtConnectOptions::default().balance);
    assert_eq!(RrtConnectOptions::default().range, 0.5);
}

#[test]
fn balanced_rrt_connect_solves_the_panda_problems_deterministically_and_checks_fewer_states() {
    let (sets, model) = sets_and_model();
    let (mut solved, mut states) = (0, [0u64; 2]);
    for set in &sets {
        for i in 0..set.len() {
            let inst = set.instance_with(i, &model).unwrap();
            let spheres = inst.planner_checker();
            for (k, options) in [RrtConnectOptions::default(), RrtConnectOptions::vamp_like()].into_iter().enumerate() {
                let counter = CountingChecker::new(spheres);
                let problem = inst.problem(&counter, Duration::from_secs(60), i as u64, DEFAULT_STEP);
                let first = RrtConnect::new(options).plan(&problem).unwrap();
                if set.name().contains("cage") {
                    states[k] += counter.checks();
                }
                if k == 0 {
                    continue;
                }
                let again = RrtConnect::new(options).plan(&problem).unwrap();
                assert_eq!(first.path, again.path, "{} problem {i}: same seed, another path", set.name());
                assert_eq!(first.iterations, again.iterations);
                assert!(path_valid_discrete(spheres, &first.path, DEFAULT_STEP));
                let v = validate_path(&*inst.checker, &first.path, &ValidationOptions::default());
                assert!(v.discrete, "{} problem {i}: invalid under the meshes", set.name());
                solved += 1;
            }
        }
    }
    assert_eq!(solved, 10);
    // Cage, problem i with seed i: balancing checks under half the states of alternation.
    assert!(2 * states[1] < states[0], "states checked: {states:?}");
}
