//! Certified motion checks of the exact checker (`CollisionChecker::state_certificate`,
//! `is_motion_valid_between`): states near the ends and near each checked state are certified
//! by the state check's gaps and the motion bound. The verdicts must be exactly those of
//! checking every state one by one, in particular for motions whose end states are valid but
//! which pass through an obstacle or through the robot itself; PRM's roadmap must be the
//! one-by-one roadmap.

use std::sync::Arc;

use nalgebra::Isometry3;
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{samples, Geometry, JointGroup, Robot, Shape};
use opengrasp_core::scene::{RobotId, Scene, StaticBody};
use opengrasp_motion::planners::{Prm, PrmOptions};
use opengrasp_motion::validate::segment_valid_discrete;
use opengrasp_motion::validity::{CollisionChecker, OneByOne, StateValidityChecker};
use opengrasp_motion::{MotionPlanner, SetupContext};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The seven-joint arm in a cupboard (table, shelf, divider, back wall: the stand-in scene's
/// boxes, full sizes) with a ball and a post (sphere and cylinder obstacles).
fn arm_in_cupboard() -> (Arc<Robot>, JointGroup, CollisionChecker) {
    let robot = Arc::new(samples::seven_dof_arm().unwrap());
    let group = robot.group("arm").unwrap().clone();
    let mut scene = Scene::new("cupboard");
    scene.add_robot("arm", robot.clone(), Isometry3::identity()).unwrap();
    let boxes = [
        ("table", [0.65, 0.0, 0.225], [0.6, 1.2, 0.05]),
        ("shelf", [0.65, 0.0, 0.85], [0.6, 1.2, 0.04]),
        ("divider", [0.7, 0.0, 0.54], [0.5, 0.04, 0.58]),
        ("back", [0.97, 0.0, 0.54], [0.04, 1.2, 0.58]),
    ];
    let body = |name: &str, [x, y, z]: [f64; 3], g: Geometry| {
        StaticBody::new(name, Isometry3::translation(x, y, z), vec![Shape::at_origin(g)])
    };
    for (name, centre, [x, y, z]) in boxes {
        scene.add_body(body(name, centre, Geometry::cuboid(x, y, z))).unwrap();
    }
    scene.add_body(body("ball", [-0.35, 0.3, 0.8], Geometry::Sphere { radius: 0.12 })).unwrap();
    scene.add_body(body("post", [-0.2, -0.5, 0.6], Geometry::Cylinder { radius: 0.05, length: 1.2 })).unwrap();
    let world = Arc::new(CollisionWorld::new(&scene).unwrap());
    let q_full = robot.home_configuration();
    let checker = CollisionChecker::new(world, RobotId(0), robot.clone(), group.clone(), q_full).unwrap();
    (robot, group, checker)
}

/// A valid state's certificate holds one gap per test, each in `[0, 0.5]` m; an invalid
/// state's is empty; the verdict is `is_valid`'s.
#[test]
fn state_certificates_agree_with_state_checks() {
    let (robot, group, checker) = arm_in_cupboard();
    let limits = group.limits(&robot);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut valid, mut invalid, mut len) = (0, 0, None);
    let mut cert = Vec::new();
    for _ in 0..300 {
        let q: Vec<f64> = limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect();
        let ok = checker.state_certificate(&q, &mut cert);
        assert_eq!(ok, checker.is_valid(&q));
        if ok {
            valid += 1;
            assert_eq!(*len.get_or_insert(cert.len()), cert.len());
            assert!(cert.iter().all(|g| (0.0..=0.5).contains(g)), "{cert:?}");
        } else {
            invalid += 1;
            assert!(cert.is_empty());
        }
    }
    // 9 parts against the obstacles and the self-collision pairs.
    assert!(len.is_some_and(|n| n > 9), "{len:?}");
    assert!(valid > 50 && invalid > 50, "{valid} valid, {invalid} invalid");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4))]
    /// Motions between valid states (up to 1.5 rad per joint, steps 0.05–0.1): the certified
    /// verdict, with both ends' certificates, with one, and with none, equals the one-by-one
    /// discrete check's, and `check_motion` gives the one-by-one verdict and count; many motions pass through a collision between valid ends.
    #[test]
    fn certified_motions_agree_with_the_one_by_one_check(seed in 0u64..1_000_000) {
        let (robot, group, checker) = arm_in_cupboard();
        let limits = group.limits(&robot);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (mut accepted, mut through) = (0, 0);
        let (mut ca, mut cb) = (Vec::new(), Vec::new());
        while accepted + through < 100 {
            let a: Vec<f64> = limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect();
            let b: Vec<f64> = a
                .iter()
                .zip(&limits)
                .map(|(&x, &(lo, hi))| (x + rng.random_range(-1.5..=1.5)).clamp(lo, hi))
                .collect();
            if !checker.state_certificate(&a, &mut ca) || !checker.state_certificate(&b, &mut cb) {
                continue;
            }
            let step = rng.random_range(0.05..0.1);
            let reference = segment_valid_discrete(&OneByOne(&checker), &a, &b, step);
            prop_assert_eq!(checker.is_motion_valid_between(&a, &ca, &b, &cb, step), reference);
            prop_assert_eq!(checker.is_motion_valid_between(&a, &ca, &b, &[], step), reference);
            prop_assert_eq!(checker.is_motion_valid_between(&a, &[], &b, &[], step), reference);
            // Without certificates: the one-by-one verdict and count.
            prop_assert_eq!(checker.check_motion(&a, &b, step), OneByOne(&checker).check_motion(&a, &b, step));
            if reference { accepted += 1 } else { through += 1 }
        }
        prop_assert!(accepted > 15 && through > 15, "{} accepted, {} through a collision", accepted, through);
    }
}

/// PRM's roadmap (every node's edges, in order) on the exact checker equals the one built
/// one state at a time; some edges are rejected.
#[test]
fn prm_roadmap_on_the_exact_checker_equals_the_one_by_one_roadmap() {
    let (robot, group, checker) = arm_in_cupboard();
    let q_full = robot.home_configuration();
    let build = |checker: &dyn StateValidityChecker| {
        let mut prm = Prm::new(PrmOptions { nodes: 60, k: 8, ..PrmOptions::default() });
        let context = SetupContext { robot: &robot, group: &group, q_full: &q_full, checker, seed: 1, step: 0.05 };
        prm.setup(&context).unwrap();
        (0..prm.roadmap_nodes()).map(|i| prm.roadmap_neighbours(i).to_vec()).collect::<Vec<_>>()
    };
    let certified = build(&checker);
    assert_eq!(certified, build(&OneByOne(&checker)));
    assert_eq!(certified.len(), 60);
    let edges = certified.iter().map(Vec::len).sum::<usize>() / 2;
    let tried: usize = (0..60).map(|i: usize| i.min(8)).sum();
    assert!(edges > 0 && edges < tried, "{edges} edges of {tried} tried");
}
