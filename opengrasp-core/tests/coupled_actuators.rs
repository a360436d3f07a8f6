//! Coupled (mimic) joints share one actuator: two fingers on revolute joints coupled 1:1 (one
//! motor closing both, as a single-actuator gripper) squeezing a free cube deliver the
//! actuator's torque in total, so each presses with `τ / (2 R)` (`2 · F · R = τ` by virtual
//! work), not `τ / R` each as with one full motor per joint.
#![cfg(feature = "rapier")]

use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::model::{
    Geometry, Inertial, JointId, JointKind, JointSpec, Link, LinkId, Robot, RobotBuilder, Shape,
};
use opengrasp_core::physics::{ContactBody, JointTarget, MockBackend, PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::{Scene, SceneObject};
use opengrasp_core::CoreError;

/// Lever (m): the fingertip ball's centre distance from its joint axis.
const R: f64 = 0.2;
/// Actuator effort limit (N·m).
const TAU: f64 = 1.0;
/// Distance (m) between the two parallel joint axes (and the two fingertip balls' centres).
const GAP: f64 = 0.05;

/// Two fingers along +x with a 1 cm ball at x = `R`: one on a revolute joint about +z at the
/// origin, the other about −z at y = `GAP`, so both close towards y = `GAP` / 2. The second
/// joint mimics the first 1:1. Each finger weighs `mass` kg.
fn fingers(mass: f64) -> Robot {
    let bar = Isometry3::translation(0.1, 0.0, 0.0);
    let finger = |name: &str| {
        Link::new(name)
            .with_shape(Shape::new(bar, Geometry::cuboid(0.16, 0.008, 0.008)))
            .with_shape(Shape::new(Isometry3::translation(R, 0.0, 0.0), Geometry::Sphere { radius: 0.01 }))
            .with_inertial(Inertial::solid_box(mass, Vector3::new(0.2, 0.02, 0.02), bar))
    };
    let revolute = |name: &str, child: &str, y: f64, axis: Vector3<f64>| {
        JointSpec::new(name, JointKind::Revolute, "base", child)
            .origin(Isometry3::translation(0.0, y, 0.0))
            .axis(axis)
            .limits(-1.0, 1.0, 0.2, TAU)
    };
    RobotBuilder::new("coupled_fingers")
        .link(Link::new("base"))
        .link(finger("lower"))
        .link(finger("upper"))
        .joint(revolute("j1", "lower", 0.0, Vector3::z()))
        .joint(revolute("j2", "upper", GAP, -Vector3::z()).mimic("j1", 1.0, 0.0))
        .build()
        .unwrap()
}

/// Steady normal forces (N) of the two 0.3 kg fingertips on a free 0.1 kg cube between them (0.5 mm
/// from each ball, no gravity), the actuator commanded 0.3 rad beyond the contact; and how far
/// the cube moved (m).
fn squeeze_forces(coupled_actuators: bool) -> ([f64; 2], f64) {
    squeeze(coupled_actuators, 0.3, JointTarget::Position(0.3), None)
}

/// [`squeeze_forces`] with fingers of `mass` kg and the actuator commanded `target`; `cap`
/// overrides both joints' motor force limits ([`PhysicsEngine::set_joint_force_limit`]).
fn squeeze(coupled_actuators: bool, mass: f64, target: JointTarget, cap: Option<f64>) -> ([f64; 2], f64) {
    let mut scene = Scene::new("fingers squeezing a cube");
    let robot = scene.add_robot("fingers", Arc::new(fingers(mass)), Isometry3::identity()).unwrap();
    let start = Isometry3::translation(R, GAP / 2.0, 0.0);
    let side = GAP - 0.02 - 0.001;
    let cube = SceneObject::new("cube", start, vec![Shape::at_origin(Geometry::cuboid(side, side, side))], 0.1);
    let cube = scene.add_object(cube).unwrap();
    let options = PhysicsOptions { gravity: Vector3::zeros(), coupled_actuators, ..PhysicsOptions::default() };
    let mut engine = RapierBackend::from_scene(&scene, &options).unwrap();
    engine.set_joint_target(robot, 0, target).unwrap();
    if let Some(cap) = cap {
        for j in [JointId(0), JointId(1)] {
            engine.set_joint_force_limit(robot, j, cap).unwrap();
        }
    }
    engine.step_n(480, 1.0 / 240.0).unwrap(); // 2 s: the reference reaches 0.3 rad after 1.5 s
    let contacts = engine.contacts();
    let force = |link: usize| {
        let finger = ContactBody::Link { robot, link: LinkId(link) };
        contacts
            .iter()
            .filter(|c| c.body1 == finger || c.body2 == finger)
            .map(|c| c.normal_force * c.normal.y.abs())
            .sum()
    };
    let moved = (engine.object_pose(cube).unwrap().translation.vector - start.translation.vector).norm();
    ([force(1), force(2)], moved)
}

#[test]
fn coupled_fingers_deliver_the_actuators_torque_not_twice_it() {
    let (shared, moved) = squeeze_forces(true);
    assert!(moved < 2e-3, "the cube was pushed {moved} m");
    let half = TAU / (2.0 * R); // 2.5 N each: 2 · 2.5 N · R = τ
    for f in shared {
        assert!((f - half).abs() < 0.01 * half, "shared actuator: {shared:?} N, expected {half} N each");
    }

    // One full motor per joint (the uncoupled model): each finger presses with τ / R, so the
    // pair acts with twice the actuator's torque.
    let (solo, _) = squeeze_forces(false);
    for f in solo {
        assert!((f - TAU / R).abs() < 0.01 * TAU / R, "one motor per joint: {solo:?} N, expected {} N each", TAU / R);
    }
    // Deterministic.
    assert_eq!(squeeze_forces(true).0.map(f64::to_bits), shared.map(f64::to_bits));
}

/// A stall-torque actuator ([`JointTarget::Effort`], an explicit joint torque) on light fingers
/// (10 g, as a robot hand's phalanges) delivers the actuator's torque, shared by the coupled
/// joints, as the position motor does once blocked (on these stiff 120 Hz contacts), and
/// clamps a larger command to the effort limit.
#[test]
fn effort_targets_press_light_fingers_with_the_actuators_torque() {
    let half = TAU / (2.0 * R); // 2.5 N per finger
    let (position, _) = squeeze(true, 0.01, JointTarget::Position(0.3), None);
    println!("10 g fingers under position control: {position:?} N (limit {half} N each)");
    assert!(position.iter().all(|&f| (f - half).abs() < 0.01 * half), "position motor: {position:?} N");

    let (effort, moved) = squeeze(true, 0.01, JointTarget::Effort(TAU), None);
    println!("10 g fingers, effort target: {effort:?} N, cube moved {moved} m");
    assert!(moved < 2e-3, "the cube was pushed {moved} m");
    for f in effort {
        assert!((f - half).abs() < 0.01 * half, "effort target: {effort:?} N, expected {half} N each");
    }
    // A command beyond the effort limit is clamped to it; half the limit presses half as hard.
    let (clamped, _) = squeeze(true, 0.01, JointTarget::Effort(10.0 * TAU), None);
    assert_eq!(clamped.map(f64::to_bits), effort.map(f64::to_bits));
    let (weak, _) = squeeze(true, 0.01, JointTarget::Effort(0.5 * TAU), None);
    for f in weak {
        assert!((f - 0.5 * half).abs() < 0.01 * half, "half effort: {weak:?} N");
    }
    // Uncoupled: each joint pushes with the full command.
    let (solo, _) = squeeze(false, 0.01, JointTarget::Effort(TAU), None);
    for f in solo {
        assert!((f - TAU / R).abs() < 0.01 * TAU / R, "one actuator per joint: {solo:?} N");
    }
    // Deterministic.
    assert_eq!(squeeze(true, 0.01, JointTarget::Effort(TAU), None).0.map(f64::to_bits), effort.map(f64::to_bits));
}

/// A motor force cap ([`PhysicsEngine::set_joint_force_limit`]) below the actuator's share makes
/// the blocked position motor press with exactly the cap (an implicit stall torque), on light
/// fingers too; bad caps and joints are typed errors on both backends.
#[test]
fn joint_force_caps_set_the_stall_torque_of_position_motors() {
    for (mass, cap) in [(0.3, 0.2), (0.01, 0.2), (0.01, 0.05)] {
        let (forces, moved) = squeeze(true, mass, JointTarget::Position(0.3), Some(cap));
        assert!(moved < 2e-3, "the cube was pushed {moved} m");
        for f in forces {
            assert!((f - cap / R).abs() < 0.01 * cap / R, "cap {cap} N·m, {mass} kg: {forces:?} N");
        }
    }
    let mut scene = Scene::new("caps");
    let robot = scene.add_robot("fingers", Arc::new(fingers(0.01)), Isometry3::identity()).unwrap();
    let mut rapier = RapierBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    let mut mock = MockBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    for (joint, cap, invalid_parameter) in
        [(0, -1.0, true), (0, f64::NAN, true), (0, f64::INFINITY, true), (7, 1.0, false)]
    {
        for result in [
            rapier.set_joint_force_limit(robot, JointId(joint), cap),
            mock.set_joint_force_limit(robot, JointId(joint), cap),
        ] {
            match result {
                Err(CoreError::InvalidParameter { .. }) => assert!(invalid_parameter),
                Err(CoreError::InvalidHandle { .. }) => assert!(!invalid_parameter),
                other => panic!("joint {joint}, cap {cap}: {other:?}"),
            }
        }
    }
}
