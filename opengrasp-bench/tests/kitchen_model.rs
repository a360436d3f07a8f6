//! The kitchen scenes plan on a conservative sphere model (`SceneSphereModel`): every exact
//! collision is a model collision, and paths planned on the model pass the exact validators.

use std::time::Duration;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_bench::scenes::{armar_ik_scene, armar_standard_scene};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{Geometry, TriangleMesh};
use opengrasp_motion::benchmark::{postprocessing_options, BenchmarkOptions, SceneInstance};
use opengrasp_motion::planners::RrtConnect;
use opengrasp_motion::scene_spheres::{cover_overhang, shape_cover, SceneModelOptions, SceneSphereModel};
use opengrasp_motion::smoothing::{repair_with, shortcut_with};
use opengrasp_motion::validate::{segment_valid_discrete, validate_path, ValidationOptions};
use opengrasp_motion::validity::ObstaclePrimitive;
use opengrasp_motion::{MotionError, MotionPlanner};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Random states of the group within its limits: `(exact invalid, model invalid, exact
/// invalid but model valid, exact valid)` counts over `n` states.
fn compare(instance: &SceneInstance, n: usize, seed: u64) -> (usize, usize, usize, usize) {
    let model = instance.planning_checker.as_deref().expect("a planning model");
    let limits = instance.group.limits(&instance.robot);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut exact_bad, mut model_bad, mut missed, mut exact_ok) = (0, 0, 0, 0);
    for _ in 0..n {
        let q: Vec<f64> = limits.iter().map(|(lo, hi)| rng.random_range(*lo..=*hi)).collect();
        let (e, m) = (instance.checker.is_valid(&q), model.is_valid(&q));
        exact_bad += usize::from(!e);
        exact_ok += usize::from(e);
        model_bad += usize::from(!m);
        missed += usize::from(!e && m);
    }
    (exact_bad, model_bad, missed, exact_ok)
}

/// Scene 1 and two scene-2 instances: over random states, no state the exact world rejects
/// is accepted by the model; the model still accepts most exact-valid states, and the start
/// and goal.
#[test]
fn kitchen_sphere_model_is_conservative() {
    for (name, instance) in [
        ("scene 1", (armar_standard_scene().generate)(0).unwrap()),
        ("scene 2 seed 0", (armar_ik_scene().generate)(0).unwrap()),
        ("scene 2 seed 3", (armar_ik_scene().generate)(3).unwrap()),
    ] {
        let (exact_bad, model_bad, missed, exact_ok) = compare(&instance, 3000, 7);
        println!("{name}: exact rejects {exact_bad}, model rejects {model_bad} of 3000; missed {missed}");
        assert_eq!(missed, 0, "{name}: the model accepted {missed} states in exact collision");
        assert!(exact_bad >= 150, "{name}: too few colliding states to compare ({exact_bad})");
        // Conservative but not useless: at most a quarter of the exact-valid states lost.
        assert!(model_bad - exact_bad <= exact_ok / 4, "{name}: model rejects {model_bad}, exact {exact_bad}");
        let model = instance.planning_checker.as_deref().unwrap();
        assert!(model.is_valid(&instance.start), "{name}: start");
        if let opengrasp_motion::Goal::Configuration(g) = &instance.goal {
            assert!(model.is_valid(g), "{name}: goal");
        }
    }
}

/// Every point of a box, capsule and cylinder solid (random points inside, and the corners
/// of the box) lies in some covering sphere, and the spheres reach at most the budget beyond
/// the sides (the cylinder's flat ends excepted, bounded by `cover_overhang`).
#[test]
fn shape_covers_contain_the_solid() {
    let options = SceneModelOptions::default();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let shapes = [
        Geometry::Box { half_extents: Vector3::new(0.12, 0.16, 0.25) },
        Geometry::Box { half_extents: Vector3::new(0.015, 0.0425, 0.0475) },
        Geometry::Capsule { radius: 0.045, length: 0.221 },
        Geometry::Cylinder { radius: 0.04, length: 0.10 },
        Geometry::Sphere { radius: 0.1 },
    ];
    for g in &shapes {
        let origin =
            Isometry3::translation(0.3, -0.2, 0.1) * nalgebra::UnitQuaternion::from_euler_angles(0.3, 0.2, 1.0);
        let mut spheres = Vec::new();
        shape_cover(g, &origin, &options, &mut spheres).unwrap();
        let (lo, hi) = g.local_aabb();
        let solid = ObstaclePrimitive::from_geometry("s", origin, g).unwrap();
        let mut inside = 0;
        for k in 0..20_000 {
            let p = if k < 8 {
                Point3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                )
            } else {
                Point3::new(rng.random_range(lo.x..=hi.x), rng.random_range(lo.y..=hi.y), rng.random_range(lo.z..=hi.z))
            };
            let p = origin * p;
            if solid.signed_distance(&p) > 0.0 {
                continue;
            }
            inside += 1;
            assert!(spheres.iter().any(|(c, r)| (p - c).norm() <= *r), "{g:?}: {p:?} not covered");
        }
        assert!(inside > 5_000, "{g:?}: {inside}");
        let local: Vec<_> = spheres.iter().map(|(c, r)| (origin.inverse() * c, *r)).collect();
        let reach = cover_overhang(g, &local).unwrap();
        println!("{g:?}: {} spheres, overhang {reach:.4} m", spheres.len());
        match g {
            Geometry::Box { half_extents } => {
                assert!(
                    reach <= options.max_overhang.max(options.relative_overhang * half_extents.min()) + 1e-9,
                    "{reach}"
                )
            }
            Geometry::Capsule { radius, .. } => {
                assert!(reach <= options.max_overhang.max(options.relative_overhang * radius) + 1e-9, "{reach}")
            }
            Geometry::Sphere { .. } => assert!(reach.abs() < 1e-12, "{reach}"),
            _ => assert!(reach < 0.04, "{reach}"),
        }
    }
    let bad = SceneModelOptions { max_overhang: 0.0, ..options };
    let err = shape_cover(&shapes[0], &Isometry3::identity(), &bad, &mut Vec::new()).unwrap_err();
    assert!(matches!(err, MotionError::InvalidParameter { name: "max_overhang", .. }), "{err}");
    let mesh = Geometry::Mesh(std::sync::Arc::new(TriangleMesh::cuboid(Vector3::new(0.1, 0.2, 0.3)).unwrap()));
    let err = ObstaclePrimitive::from_geometry("m", Isometry3::identity(), &mesh).unwrap_err();
    assert!(matches!(err, MotionError::InvalidParameter { name: "obstacle", .. }), "{err}");
}

/// What the model does not cover is refused with typed errors: bad options and carried
/// objects.
#[test]
fn unmodelled_scenes_are_typed_errors() {
    let kitchen = opengrasp_assets::scenes::kitchen().unwrap();
    let mut scene = kitchen.scene.clone();
    let robot = scene.robot(kitchen.robot).unwrap().robot.clone();
    let group = robot.group("hip_right_arm").unwrap().clone();
    let q = kitchen.start_configuration.clone();
    let world = CollisionWorld::new(&scene).unwrap();
    let bad = SceneModelOptions { relative_overhang: f64::NAN, ..SceneModelOptions::default() };
    let err = SceneSphereModel::new(&scene, kitchen.robot, &group, &q, &world, &bad).unwrap_err();
    assert!(matches!(err, MotionError::InvalidParameter { name: "relative_overhang", .. }), "{err}");
    let err = SceneSphereModel::new(&scene, kitchen.robot, &group, &q[1..], &world, &SceneModelOptions::default())
        .unwrap_err();
    assert!(matches!(err, MotionError::DimensionMismatch { .. }), "{err}");
    let cup = scene.object_id("white_cup").unwrap();
    scene.attach(cup, kitchen.robot, "right_hand_palm").unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    let err =
        SceneSphereModel::new(&scene, kitchen.robot, &group, &q, &world, &SceneModelOptions::default()).unwrap_err();
    assert!(matches!(err, MotionError::InvalidParameter { name: "scene", .. }), "{err}");
}

/// RRT-Connect on the model, seeds 0..8, scene 1 and scene 2: every planned path is valid
/// under the exact geometry (discrete), and after the harness's post-processing discrete,
/// strict and continuous.
#[test]
fn paths_planned_on_the_kitchen_model_pass_the_exact_validators() {
    let options = BenchmarkOptions::default();
    let validation = ValidationOptions::default();
    for (name, scene) in [("scene 1", armar_standard_scene()), ("scene 2", armar_ik_scene())] {
        for seed in 0..8u64 {
            let instance = (scene.generate)(seed).unwrap();
            let model = instance.planning_checker.as_deref().expect("a planning model");
            let problem = instance.problem(model, Duration::from_secs(20), seed, 0.02);
            let path = RrtConnect::default().plan(&problem).expect("solved").path;
            for w in path.windows(2) {
                assert!(segment_valid_discrete(&*instance.checker, &w[0], &w[1], 0.02), "{name} seed {seed}");
            }
            let limits = instance.group.limits(&instance.robot);
            let so = postprocessing_options(&options, seed);
            let certifier = instance.certifier.as_deref();
            let (repaired, _) = repair_with(&*instance.checker, certifier, &path, &limits, &so);
            let (smoothed, _) = shortcut_with(&*instance.checker, certifier, &repaired, &so);
            let v = validate_path(&*instance.checker, &smoothed, &validation);
            assert!(v.discrete && v.strict && v.continuous == Some(true), "{name} seed {seed}: {v:?}");
        }
    }
}
