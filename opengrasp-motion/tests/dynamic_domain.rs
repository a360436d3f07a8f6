//! RRT-Connect with dynamic-domain sampling (`RrtConnectOptions::dynamic_domain`): solves the
//! MotionBenchMaker Panda problems on the sphere model with paths the meshes accept, the same
//! path for the same seed, and refuses a bad radius with a typed error.

use std::sync::Arc;
use std::time::Duration;

use opengrasp_motion::planners::{RrtConnect, RrtConnectOptions};
use opengrasp_motion::problem_set::{self, LoadedProblemSet, PlanningModel};
use opengrasp_motion::validate::{path_valid_discrete, validate_path, ValidationOptions, DEFAULT_STEP};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::{MotionError, MotionPlanner};

#[test]
fn dynamic_domain_rrt_connect_solves_the_panda_problems_deterministically() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda/problems");
    let sets: Vec<LoadedProblemSet> =
        problem_set::load(dir).unwrap().iter().map(|s| LoadedProblemSet::new(s).unwrap()).collect();
    let model = PlanningModel::Spheres(Arc::new(sets[0].layered_sphere_model(GreedyCoverOptions::default()).unwrap()));
    let options = RrtConnectOptions { dynamic_domain: Some(4.0), ..RrtConnectOptions::default() };
    let mut solved = 0;
    for set in &sets {
        for i in 0..set.len() {
            let inst = set.instance_with(i, &model).unwrap();
            let spheres = inst.planner_checker();
            let problem = inst.problem(spheres, Duration::from_secs(60), i as u64, DEFAULT_STEP);
            let first = RrtConnect::new(options).plan(&problem).unwrap();
            let again = RrtConnect::new(options).plan(&problem).unwrap();
            assert_eq!(first.path, again.path, "{} problem {i}: same seed, another path", set.name());
            assert_eq!(first.iterations, again.iterations);
            assert!(path_valid_discrete(spheres, &first.path, DEFAULT_STEP));
            let v = validate_path(&*inst.checker, &first.path, &ValidationOptions::default());
            assert!(v.discrete, "{} problem {i}: invalid under the meshes", set.name());
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
