//! PRM's `setup` checks its roadmap edges with the vertices' state certificates
//! (`StateValidityChecker::state_certificate`, `is_motion_valid_between`): the roadmap and the
//! planned paths must be exactly those of the one-by-one checks.

use std::sync::Arc;
use std::time::Duration;

mod arm_world;

use opengrasp_core::model::{JointGroup, Robot};
use opengrasp_motion::planners::{Prm, PrmOptions};
use opengrasp_motion::validity::{OneByOne, SphereWorld, StateValidityChecker};
use opengrasp_motion::{Goal, MotionPlanner, PlanningProblem, SetupContext};
use proptest::prelude::*;

/// Every node's edges, in order.
type Roadmap = Vec<Vec<(usize, f64)>>;

/// Sets up a PRM of `nodes` nodes on `checker` and plans from `start` to `goal`: the roadmap
/// after setup and the path.
fn roadmap_and_path(
    (robot, group): (&Arc<Robot>, &JointGroup),
    checker: &dyn StateValidityChecker,
    seed: u64,
    nodes: usize,
    (start, goal): (&[f64], &[f64]),
) -> (Roadmap, Option<Vec<Vec<f64>>>) {
    let q_full = robot.home_configuration();
    let mut prm = Prm::new(PrmOptions { nodes, k: 8, ..PrmOptions::default() });
    let context = SetupContext { robot, group, q_full: &q_full, checker, seed, step: 0.05 };
    prm.setup(&context).unwrap();
    let roadmap = (0..prm.roadmap_nodes()).map(|i| prm.roadmap_neighbours(i).to_vec()).collect();
    let goal = Goal::Configuration(goal.to_vec());
    let problem = PlanningProblem {
        robot,
        group,
        q_full: &q_full,
        start,
        goal: &goal,
        checker,
        time_limit: Duration::from_secs(5),
        seed,
        step: 0.05,
    };
    (roadmap, prm.plan(&problem).ok().map(|s| s.path))
}

/// The roadmap on the sphere world (certified edges) equals the one-by-one roadmap, on the
/// plain and the layered world; returns (nodes, edges, edges tried).
fn compare(world: &SphereWorld, robot: &Arc<Robot>, group: &JointGroup, seed: u64) -> (usize, usize, usize) {
    let (start, goal) = ([0.0; 7], [1.2, 0.6, -0.8, -1.0, 0.5, 0.7, -0.4]);
    let ends = (&start[..], &goal[..]);
    let nodes = 120;
    let certified = roadmap_and_path((robot, group), world, seed, nodes, ends);
    let reference = roadmap_and_path((robot, group), &OneByOne(world), seed, nodes, ends);
    assert_eq!(certified, reference, "seed {seed}");
    let uncertified = world.clone().with_certified_motions(false);
    assert_eq!(certified, roadmap_and_path((robot, group), &uncertified, seed, nodes, ends), "seed {seed}");
    let roadmap = &certified.0;
    let edges = roadmap.iter().map(Vec::len).sum::<usize>() / 2;
    // Node i tried its min(i, k) nearest predecessors.
    let tried = (0..roadmap.len()).map(|i| i.min(8)).sum();
    (roadmap.len(), edges, tried)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6))]
    /// Random seeds: identical roadmaps and paths, with edges both accepted and rejected.
    #[test]
    fn prm_roadmap_with_certificates_equals_the_one_by_one_roadmap(seed in 0u64..1_000_000) {
        let (robot, group, world, layered) = arm_world::arm_among_shapes();
        for w in [&world, &layered] {
            let (nodes, edges, tried) = compare(w, &robot, &group, seed);
            prop_assert_eq!(nodes, 120);
            prop_assert!(edges > 0 && edges < tried, "{} edges of {} tried", edges, tried);
        }
    }
}

/// A valid state's certificate holds one gap per test of the state check, each positive (the
/// test passed); an invalid state's certificate is empty.
#[test]
fn state_certificates_agree_with_state_checks() {
    use rand::{Rng, SeedableRng};
    let (robot, group, world, layered) = arm_world::arm_among_shapes();
    let limits = group.limits(&robot);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    for w in [&world, &layered] {
        let (mut valid, mut invalid, mut len) = (0, 0, None);
        let mut cert = Vec::new();
        for _ in 0..400 {
            let q: Vec<f64> = limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect();
            let ok = w.state_certificate(&q, &mut cert);
            assert_eq!(ok, w.is_valid(&q));
            if ok {
                valid += 1;
                assert_eq!(*len.get_or_insert(cert.len()), cert.len());
                assert!(cert.iter().all(|&g| g > 0.0), "{cert:?}");
            } else {
                invalid += 1;
                assert!(cert.is_empty());
            }
        }
        // Obstacle tests (4 obstacles × moving links) and link pairs.
        assert!(len.is_some_and(|n| n >= 4), "{len:?}");
        assert!(valid > 50 && invalid > 50, "{valid} valid, {invalid} invalid");
    }
}
