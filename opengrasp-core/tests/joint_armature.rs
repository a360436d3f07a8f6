//! `PhysicsOptions::joint_armature`: a joint's reflected motor inertia. A bar on a revolute
//! joint driven from rest by a constant torque `τ` (no gravity, no motor) turns as `I q̈ = τ`
//! with `I = I_link + I_a`, so `q(T) = τ T² / (2 I)`; bad armatures are typed errors.
#![cfg(feature = "rapier")]

use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::model::{Inertial, JointKind, JointSpec, Link, Robot, RobotBuilder};
use opengrasp_core::physics::{JointTarget, MockBackend, PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::Scene;
use opengrasp_core::CoreError;

/// Bar mass (kg), length and thickness (m).
const MASS: f64 = 2.0;
const LENGTH: f64 = 0.4;
const THICK: f64 = 0.02;
/// Drive torque (N·m).
const TAU: f64 = 1.0;

/// The bar's inertia about the joint axis (z through its end): `m (L² + t²) / 12 + m (L/2)²`.
fn link_inertia() -> f64 {
    MASS * (LENGTH * LENGTH + THICK * THICK) / 12.0 + MASS * (LENGTH / 2.0).powi(2)
}

/// A bar along +x hinged at the origin about +z (its joint axis given as `axis_scale · z`,
/// to check that the axis length does not scale the armature).
fn bar(axis_scale: f64) -> Robot {
    let centre = Isometry3::translation(LENGTH / 2.0, 0.0, 0.0);
    RobotBuilder::new("bar")
        .link(Link::new("base"))
        .link(Link::new("bar").with_inertial(Inertial::solid_box(MASS, Vector3::new(LENGTH, THICK, THICK), centre)))
        .joint(
            JointSpec::new("hinge", JointKind::Revolute, "base", "bar")
                .axis(Vector3::z() * axis_scale)
                .limits(-100.0, 100.0, 1000.0, 10.0),
        )
        .build()
        .unwrap()
}

/// Joint angle (rad) after `T` s of torque `TAU` from rest, with armature `armature`.
fn angle_after(armature: f64, t: f64, axis_scale: f64) -> f64 {
    let mut scene = Scene::new("armature");
    let robot = scene.add_robot("bar", Arc::new(bar(axis_scale)), Isometry3::identity()).unwrap();
    let options = PhysicsOptions { gravity: Vector3::zeros(), joint_armature: armature, ..PhysicsOptions::default() };
    let mut engine = RapierBackend::from_scene(&scene, &options).unwrap();
    engine.set_joint_target(robot, 0, JointTarget::Effort(TAU)).unwrap();
    let dt = 1.0 / 960.0;
    engine.step_n((t / dt).round() as usize, dt).unwrap();
    engine.joint_positions(robot).unwrap()[0]
}

/// `q(T)` of `I q̈ = τ` from rest.
fn analytic(inertia: f64, t: f64) -> f64 {
    TAU * t * t / (2.0 * inertia)
}

#[test]
fn a_torque_driven_joint_accelerates_as_link_plus_armature() {
    let t = 0.2;
    let i_link = link_inertia();
    for armature in [0.0, i_link, 4.0 * i_link, 1.0] {
        let q = angle_after(armature, t, 1.0);
        let expected = analytic(i_link + armature, t);
        let err = (q - expected).abs() / expected;
        assert!(err < 0.002, "armature {armature}: q = {q} rad, expected {expected} (error {err:.4})");
    }
    // Without damping the angle would scale as 1 / I: five times the inertia, far less motion.
    let (light, heavy) = (angle_after(0.0, t, 1.0), angle_after(4.0 * i_link, t, 1.0));
    assert!(heavy < 0.25 * light, "{heavy} vs {light}");
    // The armature is about the unit axis, whatever the length the model gives it.
    let scaled = angle_after(i_link, t, 3.0);
    assert!((scaled - angle_after(i_link, t, 1.0)).abs() < 1e-9, "{scaled}");
}

#[test]
fn zero_armature_leaves_the_dynamics_bitwise_unchanged() {
    let default = PhysicsOptions::default();
    assert_eq!(default.joint_armature, 0.0);
    let q = |options: &PhysicsOptions| {
        let mut scene = Scene::new("armature");
        let robot = scene.add_robot("bar", Arc::new(bar(1.0)), Isometry3::identity()).unwrap();
        let mut engine = RapierBackend::from_scene(&scene, options).unwrap();
        engine.set_joint_target(robot, 0, JointTarget::Position(0.5)).unwrap();
        engine.step_n(100, 1.0 / 240.0).unwrap();
        engine.joint_positions(robot).unwrap()[0]
    };
    assert_eq!(q(&default).to_bits(), q(&PhysicsOptions { joint_armature: 0.0, ..default.clone() }).to_bits());
}

#[test]
fn bad_armature_is_a_typed_error() {
    let mut scene = Scene::new("armature");
    scene.add_robot("bar", Arc::new(bar(1.0)), Isometry3::identity()).unwrap();
    for bad in [-1e-4, f64::NAN, f64::INFINITY] {
        let options = PhysicsOptions { joint_armature: bad, ..PhysicsOptions::default() };
        for result in [options.validate(), RapierBackend::from_scene(&scene, &options).map(|_| ())] {
            match result {
                Err(CoreError::InvalidParameter { name, .. }) => assert_eq!(name, "joint_armature"),
                other => panic!("armature {bad}: {other:?}"),
            }
        }
        assert!(matches!(MockBackend::from_scene(&scene, &options), Err(CoreError::InvalidParameter { .. })));
    }
}
