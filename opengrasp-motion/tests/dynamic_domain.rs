//! RRT-Connect with dynamic-domain sampling (`RrtConnectOptions::dynamic_domain`) and with
//! VAMP's tree balancing (`RrtConnectOptions::balance`, `RrtConnectOptions::vamp_like`):
//! solves the MotionBenchMaker Panda problems on the sphere model with paths the meshes
//! accept, the same path for the same seed; balancing checks far fewer states on the cage set;
//! a bad radius is refused with a typed error.

use std::sync::Arc;
use std::time::Duration;

use opengrasp_motion::benchmark::SceneInstance;
use opengrasp_motion::planners::{RrtConnect, RrtConnectOptions};
use opengrasp_motion::problem_set::{self, LoadedProblemSet, PlanningModel};
use opengrasp_motion::validate::{path_valid_discrete, validate_path, ValidationOptions, DEFAULT_STEP};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::CountingChecker;
use opengrasp_motion::{MotionError, MotionPlanner};

fn sets_and_model() -> (Vec<LoadedProblemSet>, PlanningModel) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda/problems");
    let sets: Vec<LoadedProblemSet> =
        problem_set::load(dir).unwrap().iter().map(|s| LoadedProblemSet::new(s).unwrap()).collect();
    let model = PlanningModel::Spheres(Arc::new(sets[0].layered_sphere_model(GreedyCoverOptions::default()).unwrap()));
    (sets, model)
}

/// Plans `inst` with `options` and seed `seed` twice on the sphere model: asserts the same
/// path both times, valid on the spheres and under the meshes; returns the states checked.
fn plan_twice_and_grade(inst: &SceneInstance, options: RrtConnectOptions, seed: u64, what: &str) -> u64 {
    let spheres = inst.planner_checker();
    let counter = CountingChecker::new(spheres);
    let problem = inst.problem(&counter, Duration::from_secs(60), seed, DEFAULT_STEP);
    let first = RrtConnect::new(options).plan(&problem).unwrap();
    let states = counter.checks();
    let again = RrtConnect::new(options).plan(&problem).unwrap();
    assert_eq!(first.path, again.path, "{what}: same seed, another path");
    assert_eq!(first.iterations, again.iterations);
    assert!(path_valid_discrete(spheres, &first.path, DEFAULT_STEP));
    let v = validate_path(&*inst.checker, &first.path, &ValidationOptions::default());
    assert!(v.discrete, "{what}: invalid under the meshes");
    states
}

#[test]
fn dynamic_domain_rrt_connect_solves_the_panda_problems_deterministically() {
    let (sets, model) = sets_and_model();
    let options = RrtConnectOptions { dynamic_domain: Some(4.0), ..RrtConnectOptions::default() };
    let mut solved = 0;
    for set in &sets {
        for i in 0..set.len() {
            let inst = set.instance_with(i, &model).unwrap();
            plan_twice_and_grade(&inst, options, i as u64, &format!("{} problem {i}", set.name()));
            solved += 1;
        }
    }
    assert_eq!(solved, 10);
    // A bad radius is refused before planning.
    let inst = sets[0].instance_with(0, &model).unwrap();
    let problem = inst.problem(inst.planner_checker(), Duration::from_secs(1), 0, DEFAULT_STEP);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let options = RrtConnectOptions { dynamic_domain: Some(bad), ..RrtConnectOptions::default() };
        assert!(matches!(
            RrtConnect::new(options).plan(&problem),
            Err(MotionError::InvalidParameter { name: "dynamic_domain", .. })
        ));
    }
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
    let (mut solved, mut cage) = (0, [0u64; 2]);
    for set in &sets {
        for i in 0..set.len() {
            let inst = set.instance_with(i, &model).unwrap();
            for (k, options) in [RrtConnectOptions::default(), RrtConnectOptions::vamp_like()].into_iter().enumerate() {
                let states = plan_twice_and_grade(&inst, options, i as u64, &format!("{} problem {i}", set.name()));
                if set.name().contains("cage") {
                    cage[k] += states;
                }
            }
            solved += 1;
        }
    }
    assert_eq!(solved, 10);
    // Cage, problem i with seed i: balancing checks under half the states of alternation.
    assert!(2 * cage[1] < cage[0], "states checked on cage: {cage:?}");
}
