//! The physics check's gradual fixture release (`PhysicsCheckOptions::release`): the measured
//! fixture wrench and its linear ramp, against closed-form answers; the damping ramp of the
//! quasi-static closing (`PhysicsCheckOptions::closing_damping`) and its option errors.

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::physics::{PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::{ObjectId, Scene};
use opengrasp_grasp::evaluator::{
    fixture_wrench, physics_check, release_gradually, undamp_gradually, PhysicsCheckOptions, ReleaseWindow,
};
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

#[test]
fn the_damping_ramp_slows_a_drifting_object_by_the_integrated_rate() {
    // No gravity, the can drifting at v0: each step divides its velocity by 1 + h r_k, the rate
    // r_k = r (1 − (k + ½) / n) falling linearly to zero; then it coasts undamped.
    let (mut engine, _) = clamped_can(Vector3::zeros());
    engine.set_object_fixed(ObjectId(0), false).unwrap();
    // One step at rest first: rapier applies the mass properties in it.
    engine.step(1.0 / 240.0).unwrap();
    let (v0, rate, duration, dt) = (0.1, 10.0, 0.1, 1.0 / 240.0);
    let centre = engine.object_pose(ObjectId(0)).unwrap() * nalgebra::Point3::origin();
    let object = opengrasp_assets::objects::by_name("salt_can").unwrap();
    engine.apply_object_impulse(ObjectId(0), Vector3::x() * (v0 * object.inertial.mass), centre).unwrap();
    undamp_gradually(&mut engine, ObjectId(0), rate, duration, dt).unwrap();
    let n = (duration / dt).ceil() as usize;
    let expected = (0..n).fold(v0, |v, k| v / (1.0 + dt * rate * (1.0 - (k as f64 + 0.5) / n as f64)));
    let v = engine.object_velocity(ObjectId(0)).unwrap().linear;
    // Continuous time: exp(−r T / 2) = 0.61 v0 (the discrete product is 0.7 % above it).
    println!("after the ramp {v:?}, discrete {expected}, continuous {}", v0 * (-rate * duration / 2.0).exp());
    assert!((v.x - expected).abs() < 1e-12 && v.y.abs() < 1e-12 && v.z.abs() < 1e-12, "{v:?} vs {expected}");
    assert!((v.x / v0 - (-rate * duration / 2.0).exp()).abs() < 0.01 * (-rate * duration / 2.0).exp());
    engine.step_n(10, dt).unwrap();
    assert!((engine.object_velocity(ObjectId(0)).unwrap().linear.x - expected).abs() < 1e-12);
}

#[test]
fn a_bad_closing_damping_is_a_typed_error() {
    for tau in [0.0, -0.01, f64::NAN, f64::INFINITY] {
        let options = PhysicsCheckOptions { closing_damping: Some(tau), fixture: false, ..Default::default() };
        assert!(matches!(options.validate(), Err(GraspError::InvalidParameter { name: "closing_damping", .. })));
    }
    for ramp in [-0.1, f64::NAN] {
        let options = PhysicsCheckOptions { damping_ramp: ramp, ..Default::default() };
        assert!(matches!(options.validate(), Err(GraspError::InvalidParameter { name: "damping_ramp", .. })));
    }
    // The damped object is free while the fingers close: a fixture cannot clamp it too.
    let options = PhysicsCheckOptions { closing_damping: Some(0.01), fixture: true, ..Default::default() };
    assert!(matches!(options.validate(), Err(GraspError::InvalidParameter { name: "closing_damping", .. })));
    let options = PhysicsCheckOptions { closing_damping: Some(0.01), fixture: false, ..Default::default() };
    assert!(options.validate().is_ok());
}

#[test]
fn a_bad_release_window_is_a_typed_error() {
    let good = ReleaseWindow { timestep: 1e-3, contact_frequency: 120.0, before: 0.02, after: 0.03 };
    let check =
        |window: ReleaseWindow| PhysicsCheckOptions { release_window: Some(window), ..Default::default() }.validate();
    assert!(check(good).is_ok());
    for bad in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let e = check(ReleaseWindow { timestep: bad, ..good });
        assert!(matches!(e, Err(GraspError::InvalidParameter { name: "release_window.timestep", .. })), "{e:?}");
        let e = check(ReleaseWindow { contact_frequency: bad, ..good });
        assert!(
            matches!(e, Err(GraspError::InvalidParameter { name: "release_window.contact_frequency", .. })),
            "{e:?}"
        );
    }
    for bad in [-1e-3, f64::NAN, f64::INFINITY] {
        let e = check(ReleaseWindow { before: bad, ..good });
        assert!(matches!(e, Err(GraspError::InvalidParameter { name: "release_window.before", .. })), "{e:?}");
        let e = check(ReleaseWindow { after: bad, ..good });
        assert!(matches!(e, Err(GraspError::InvalidParameter { name: "release_window.after", .. })), "{e:?}");
    }
    // Zero before and after are a window of the release alone; more than the settle is an error.
    assert!(check(ReleaseWindow { before: 0.0, after: 0.0, ..good }).is_ok());
    let e = check(ReleaseWindow { before: 0.25, ..good });
    assert!(matches!(e, Err(GraspError::InvalidParameter { name: "release_window.before", .. })), "{e:?}");
}
