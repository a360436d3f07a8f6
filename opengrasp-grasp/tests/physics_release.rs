//! The physics check's gradual fixture release (`PhysicsCheckOptions::release`): the measured
//! fixture wrench and its linear ramp, against closed-form answers.

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::physics::{PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::{ObjectId, Scene};
use opengrasp_grasp::evaluator::{fixture_wrench, physics_check, release_gradually, PhysicsCheckOptions};
use opengrasp_grasp::GraspError;

/// The salt can (0.55 kg) alone in a world with gravity `g`, clamped at the origin.
fn clamped_can(g: Vector3<f64>) -> (RapierBackend, opengrasp_assets::objects::ObjectModel) {
    let object = opengrasp_assets::objects::by_name("salt_can").unwrap();
    let mut scene = Scene::new("clamped can");
    scene.add_object(object.to_scene_object(Isometry3::identity())).unwrap();
    let mut engine = RapierBackend::from_scene(&scene, &PhysicsOptions { gravity: g, ..Default::default() }).unwrap();
    engine.set_object_fixed(ObjectId(0), true).unwrap();
    (engine, object)
}

#[test]
fn the_fixture_of_a_clamped_object_carries_its_weight() {
    let g = Vector3::new(1.0, -2.0, -9.81);
    let (engine, object) = clamped_can(g);
    let dt = 1.0 / 240.0;
    let (force, torque) = fixture_wrench(&engine, ObjectId(0), &object, dt).unwrap().unwrap();
    // Nothing but gravity acts: the fixture pushes with −m g at the centre of mass, no torque.
    let weight = object.inertial.mass * g;
    assert!((force + weight).norm() < 1e-9 * weight.norm(), "{force:?} vs {weight:?}");
    assert!(torque.norm() < 1e-9, "{torque:?}");
    // Probing copies leaves the engine where it was.
    assert_eq!(engine.object_pose(ObjectId(0)).unwrap(), Isometry3::identity());
    assert_eq!(engine.time(), 0.0);
}

#[test]
fn a_linear_release_lets_the_object_fall_g_t_squared_over_six() {
    let g = 9.81;
    let (mut engine, object) = clamped_can(Vector3::new(0.0, 0.0, -g));
    let (duration, dt) = (0.1, 1.0 / 240.0);
    release_gradually(&mut engine, ObjectId(0), &object, duration, dt).unwrap();
    // The fixture force falls from m g to 0 over T, so the acceleration grows as g t / T and
    // the object has fallen g T² / 6 = 16.35 mm at the end (continuous time). Step k holds the
    // force scaled by 1 − (k + ½) / n; rapier splits each step into `solver_iterations` small
    // steps, each integrating velocity then position (symplectic Euler): the same sums here
    // (measured 16.492 mm, equal to them to 1e-9).
    let n = (duration / dt).ceil() as usize;
    let m = PhysicsOptions::default().solver_iterations;
    let h = dt / m as f64;
    let (mut v, mut z) = (0.0, 0.0);
    for k in 0..n {
        for _ in 0..m {
            v -= g * (k as f64 + 0.5) / n as f64 * h;
            z += v * h;
        }
    }
    let fallen = engine.object_pose(ObjectId(0)).unwrap().translation.vector;
    println!("fallen {fallen:?}; discrete {z}; continuous {}", -g * duration * duration / 6.0);
    assert!((fallen.z - z).abs() < 1e-9, "{fallen:?} vs {z}");
    assert!((fallen.z + g * duration * duration / 6.0).abs() < 0.02 * g * duration * duration / 6.0);
    assert!(fallen.x.abs() < 1e-12 && fallen.y.abs() < 1e-12);
    // The ramp is over: no external force is left, the object falls freely from here.
    let v0 = engine.object_velocity(ObjectId(0)).unwrap().linear.z;
    engine.step(dt).unwrap();
    let v1 = engine.object_velocity(ObjectId(0)).unwrap().linear.z;
    assert!((v1 - v0 + g * dt).abs() < 1e-9, "{v0} -> {v1}");
    // A zero duration frees the object at once.
    let (mut engine, object) = clamped_can(Vector3::new(0.0, 0.0, -g));
    release_gradually(&mut engine, ObjectId(0), &object, 0.0, dt).unwrap();
    engine.step(dt).unwrap();
    assert!((engine.object_velocity(ObjectId(0)).unwrap().linear.z + g * dt).abs() < 1e-9);
}

#[test]
fn a_bad_release_time_is_a_typed_error() {
    let hand = opengrasp_assets::hands::barrett();
    let object = opengrasp_assets::objects::by_name("salt_can").unwrap();
    for release in [-0.1, f64::NAN, f64::INFINITY] {
        let options = PhysicsCheckOptions { release, ..Default::default() };
        assert!(matches!(options.validate(), Err(GraspError::InvalidParameter { name: "release", .. })));
        let evaluation = opengrasp_grasp::evaluator::GraspEvaluation {
            status: opengrasp_grasp::evaluator::EvaluationStatus::Closed,
            hand_pose: Isometry3::translation(0.0, 0.0, 0.2),
            q: vec![0.0; hand.robot().dof()],
            contacts: Vec::new(),
            palm_contact: false,
            fingers_in_contact: 0,
            retraction: 0.0,
            quality: None,
            friction_score: None,
            robust_epsilon: None,
        };
        assert!(matches!(
            physics_check(&hand, &object, &evaluation, &options),
            Err(GraspError::InvalidParameter { name: "release", .. })
        ));
    }
}
