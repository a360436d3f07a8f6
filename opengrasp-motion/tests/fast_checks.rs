//! The fast paths of state checking and post-processing give the same verdicts as the plain
//! checks they replace.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{samples, Geometry, JointGroup, Robot, Shape, TriangleMesh};
use opengrasp_core::scene::{Scene, SceneObject, StaticBody};
use opengrasp_motion::planners::RrtConnect;
use opengrasp_motion::smoothing::{repair, shortcut, ShortcutOptions};
use opengrasp_motion::validate::{segment_valid_discrete, validate_path, ValidationOptions};
use opengrasp_motion::validity::{CollisionChecker, MotionBound, ObstacleBox, SphereWorld, StateValidityChecker};
use opengrasp_motion::{Goal, MotionPlanner, PlanningProblem};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Two 6 cm cubes 10 cm apart in one mesh: closed but not convex, so the collision world keeps
/// it as a triangle mesh (with its convex hull as a stand-in for far pairs).
fn two_cubes() -> TriangleMesh {
    let cube = TriangleMesh::cuboid(Vector3::new(0.06, 0.06, 0.06)).unwrap();
    let n = cube.vertices().len() as u32;
    let mut vertices: Vec<Point3<f64>> = cube.vertices().iter().map(|p| p - Vector3::new(0.0, 0.08, 0.0)).collect();
    vertices.extend(cube.vertices().iter().map(|p| p + Vector3::new(0.0, 0.08, 0.0)));
    let mut triangles = cube.triangles().to_vec();
    triangles.extend(cube.triangles().iter().map(|t| [t[0] + n, t[1] + n, t[2] + n]));
    TriangleMesh::new(vertices, triangles).unwrap()
}

/// The 7-DoF sample arm with a wall and a non-convex object in reach.
fn arm_scene() -> (Arc<Robot>, JointGroup, CollisionChecker) {
    let robot = Arc::new(samples::seven_dof_arm().unwrap());
    let mut scene = Scene::new("fast checks");
    let arm = scene.add_robot("arm", robot.clone(), Isometry3::identity()).unwrap();
    let wall = Shape::at_origin(Geometry::cuboid(0.05, 1.0, 0.6));
    scene.add_body(StaticBody::new("wall", Isometry3::translation(0.55, 0.0, 0.3), vec![wall])).unwrap();
    let object = Shape::at_origin(Geometry::Mesh(Arc::new(two_cubes())));
    scene.add_object(SceneObject::new("cubes", Isometry3::translation(0.3, 0.3, 0.6), vec![object], 0.2)).unwrap();
    let world = Arc::new(CollisionWorld::new(&scene).unwrap());
    let group = JointGroup::all(&robot, "arm").unwrap();
    let q_full = vec![0.0; robot.dof()];
    let checker = CollisionChecker::new(world, arm, robot.clone(), group.clone(), q_full).unwrap();
    (robot, group, checker)
}

/// Forwards everything but [`StateValidityChecker::residual_valid`] (and the batched methods,
/// left to their defaults): post-processing must then take its plain path.
struct Plain<'a>(&'a CollisionChecker);

impl StateValidityChecker for Plain<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        self.0.is_valid(q)
    }
    fn clearance(&self, q: &[f64]) -> Option<f64> {
        self.0.clearance(q)
    }
    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        self.0.link_distances(q, out)
    }
    fn motion_bound(&self) -> Option<&MotionBound> {
        self.0.motion_bound()
    }
}

fn random_q(rng: &mut ChaCha8Rng, limits: &[(f64, f64)]) -> Vec<f64> {
    limits.iter().map(|&(lo, hi)| lo + (hi - lo) * rng.random::<f64>()).collect()
}

#[test]
fn residual_check_equals_full_check_wherever_the_links_are_clear() {
    let (robot, group, checker) = arm_scene();
    let limits = group.limits(&robot);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut clear, mut self_hits) = (0, 0);
    let mut d = Vec::new();
    for _ in 0..400 {
        let q = random_q(&mut rng, &limits);
        let residual = checker.residual_valid(&q).expect("exact checker splits its check");
        // The residual check tests a subset of the pairs.
        assert!(residual || !checker.is_valid(&q), "q = {q:?}");
        assert!(checker.link_distances(&q, &mut d));
        if d.iter().all(|&x| x > 0.0) {
            clear += 1;
            assert_eq!(residual, checker.is_valid(&q), "q = {q:?}");
            self_hits += usize::from(!residual);
        }
    }
    assert!(clear > 50, "only {clear} clear samples");
    let _ = self_hits;
    // Outside the joint limits the link distances describe another configuration: no split.
    let mut q = vec![0.0; group.len()];
    q[1] = limits[1].1 + 0.5;
    assert_eq!(checker.residual_valid(&q), None);
}

#[test]
fn default_batched_and_motion_checks_equal_the_scalar_ones() {
    let (robot, group, checker) = arm_scene();
    let limits = group.limits(&robot);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let dim = group.len();
    let qs: Vec<f64> = (0..32).flat_map(|_| random_q(&mut rng, &limits)).collect();
    let mut out = vec![false; 32];
    checker.are_valid(&qs, &mut out);
    for (k, q) in qs.chunks(dim).enumerate() {
        assert_eq!(out[k], checker.is_valid(q));
    }
    for _ in 0..30 {
        let (a, b) = (random_q(&mut rng, &limits), random_q(&mut rng, &limits));
        assert_eq!(checker.is_motion_valid(&a, &b, 0.05), segment_valid_discrete(&checker, &a, &b, 0.05));
    }
}

#[test]
fn post_processing_with_certified_residual_checks_gives_the_plain_result() {
    let (robot, group, checker) = arm_scene();
    let start = vec![1.2, 0.4, 0.0, 0.8, 0.0, 0.3, 0.0];
    let goal = Goal::Configuration(vec![-1.2, 0.4, 0.0, 0.8, 0.0, 0.3, 0.0]);
    assert!(checker.is_valid(&start));
    let q_full = vec![0.0; robot.dof()];
    let limits = group.limits(&robot);
    let options = ValidationOptions::default();
    for seed in 0..3 {
        let problem = PlanningProblem {
            robot: &robot,
            group: &group,
            q_full: &q_full,
            start: &start,
            goal: &goal,
            checker: &checker,
            time_limit: std::time::Duration::from_secs(20),
            seed,
            step: 0.02,
        };
        let path = RrtConnect::default().plan(&problem).unwrap().path;
        let shortcut_options = ShortcutOptions { seed, iterations: 30, ..ShortcutOptions::default() };
        let (fast_repaired, fast_repair) = repair(&checker, &path, &limits, &shortcut_options);
        let (fast, fast_stats) = shortcut(&checker, &fast_repaired, &shortcut_options);
        let plain = Plain(&checker);
        let (slow_repaired, slow_repair) = repair(&plain, &path, &limits, &shortcut_options);
        let (slow, slow_stats) = shortcut(&plain, &slow_repaired, &shortcut_options);
        assert_eq!(fast, slow, "seed {seed}");
        assert_eq!((fast_stats, fast_repair), (slow_stats, slow_repair));
        let v = validate_path(&checker, &fast, &options);
        assert!(v.discrete && v.strict && v.continuous == Some(true), "seed {seed}: {v:?}");
    }
}

/// The 7-DoF sample arm in the cupboard of the stand-in scenes, as a sphere model.
fn sphere_cupboard() -> (Arc<Robot>, JointGroup, SphereWorld) {
    let robot = Arc::new(samples::seven_dof_arm().unwrap());
    let group = robot.group("arm").unwrap().clone();
    let boxes = vec![
        ObstacleBox::new("table", Isometry3::translation(0.65, 0.0, 0.225), Vector3::new(0.6, 1.2, 0.05)),
        ObstacleBox::new("shelf", Isometry3::translation(0.65, 0.0, 0.85), Vector3::new(0.6, 1.2, 0.04)),
        ObstacleBox::new(
            "divider",
            Isometry3::new(Vector3::new(0.7, 0.0, 0.54), Vector3::new(0.0, 0.0, 0.3)),
            Vector3::new(0.5, 0.04, 0.58),
        ),
    ];
    let world =
        SphereWorld::new(robot.clone(), group.clone(), robot.home_configuration(), Isometry3::identity(), boxes)
            .unwrap();
    (robot, group, world)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The vectorised state check agrees with the sphere model's closed-form distances (valid
    /// exactly when every link distance — boxes and half the self-collision gaps — is
    /// positive), and the batched and motion checks with the scalar ones.
    #[test]
    fn sphere_kernels_agree_with_distances_and_scalar_checks(seed in 0u64..10_000) {
        let (robot, group, world) = sphere_cupboard();
        let limits = group.limits(&robot);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let qs: Vec<Vec<f64>> = (0..8).map(|_| random_q(&mut rng, &limits)).collect();
        let mut d = Vec::new();
        for q in &qs {
            prop_assert!(world.link_distances(q, &mut d));
            let min = d.iter().copied().fold(f64::INFINITY, f64::min);
            // Away from contact (rounding of the two formulas aside) the verdicts agree.
            if min.abs() > 1e-9 {
                prop_assert_eq!(world.is_valid(q), min > 0.0);
            }
        }
        let flat: Vec<f64> = qs.iter().flatten().copied().collect();
        let mut out = vec![false; qs.len()];
        world.are_valid(&flat, &mut out);
        for (q, o) in qs.iter().zip(&out) {
            prop_assert_eq!(*o, world.is_valid(q));
        }
        prop_assert_eq!(
            world.is_motion_valid(&qs[0], &qs[1], 0.05),
            segment_valid_discrete(&world, &qs[0], &qs[1], 0.05)
        );
    }
}
