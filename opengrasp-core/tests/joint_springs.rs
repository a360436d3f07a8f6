//! Per-joint force-based springs ([`PhysicsEngine::set_joint_spring`]): a finger hanging on its
//! spring under gravity settles where the spring's torque balances gravity's, with the absolute
//! stiffness (N·m/rad) whatever the link's inertia; a mimic joint rests at its own spring position.
#![cfg(feature = "rapier")]

use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::model::{
    Geometry, Inertial, JointId, JointKind, JointSpec, Link, LinkId, Robot, RobotBuilder, Shape,
};
use opengrasp_core::physics::{JointSpring, MockBackend, PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::{RobotId, Scene};
use opengrasp_core::CoreError;

/// Centre of mass of each finger (m) from its joint axis.
const L: f64 = 0.1;
const G: f64 = 9.81;

/// Two bars along +x (mass `mass` each, centre of mass at x = `L`) on revolute joints about +z,
/// the second mimicking the first 1:1; effort limit `effort` N·m.
fn fingers(mass: f64, effort: f64) -> Robot {
    let bar = Isometry3::translation(L, 0.0, 0.0);
    let finger = |name: &str| {
        Link::new(name)
            .with_shape(Shape::new(bar, Geometry::cuboid(0.2, 0.01, 0.01)))
            .with_inertial(Inertial::solid_box(mass, Vector3::new(0.2, 0.01, 0.01), bar))
    };
    let revolute = |name: &str, child: &str, z: f64| {
        JointSpec::new(name, JointKind::Revolute, "base", child)
            .origin(Isometry3::translation(0.0, 0.0, z))
            .axis(Vector3::z())
            .limits(-1.5, 1.5, 1.0, effort)
    };
    RobotBuilder::new("springs")
        .link(Link::new("base"))
        .link(finger("a"))
        .link(finger("b"))
        .joint(revolute("ja", "a", 0.0))
        .joint(revolute("jb", "b", 0.1).mimic("ja", 1.0, 0.0))
        .build()
        .unwrap()
}

/// The rapier engine with gravity `g` along −y acting on the links (no compensation).
fn engine(mass: f64, effort: f64, g: f64) -> (RapierBackend, RobotId) {
    let mut scene = Scene::new("springs");
    let robot = scene.add_robot("fingers", Arc::new(fingers(mass, effort)), Isometry3::identity()).unwrap();
    let options = PhysicsOptions {
        gravity: Vector3::new(0.0, -g, 0.0),
        gravity_compensation: false,
        coupled_actuators: true,
        ..PhysicsOptions::default()
    };
    (RapierBackend::from_scene(&scene, &options).unwrap(), robot)
}

/// Angle (rad) of finger `link` about +z.
fn angle(engine: &RapierBackend, robot: RobotId, link: usize) -> f64 {
    let r = engine.link_pose(robot, LinkId(link)).unwrap().rotation;
    r.scaled_axis().z
}

/// A spring `k (θ₀ − q)` holding a bar of weight `m g` at lever `L`: equilibrium where
/// `k (θ₀ − q) = m g L cos q`, for a heavy and a light bar alike (the stiffness is absolute).
#[test]
fn a_spring_holds_a_hanging_finger_where_its_torque_balances_gravity() {
    for (mass, k, rest) in [(0.3, 5.0, 0.0), (0.01, 0.5, 0.2), (0.3, 20.0, -0.3)] {
        let (mut e, robot) = engine(mass, 10.0, G);
        for j in [JointId(0), JointId(1)] {
            e.set_joint_spring(robot, j, Some(JointSpring { position: rest, stiffness: k })).unwrap();
        }
        e.step_n(720, 1.0 / 240.0).unwrap();
        let mut mean = [0.0; 2];
        for _ in 0..240 {
            e.step(1.0 / 240.0).unwrap();
            for (m, link) in mean.iter_mut().zip([1, 2]) {
                *m += angle(&e, robot, link) / 240.0;
            }
        }
        // Solve k (rest − q) = m g L cos q by Newton's method.
        let mut q = rest;
        for _ in 0..50 {
            let f = k * (rest - q) - mass * G * L * q.cos();
            let df = -k + mass * G * L * q.sin();
            q -= f / df;
        }
        for got in mean {
            println!("{mass} kg, k {k}, rest {rest}: {got} rad, expected {q}");
            assert!((got - q).abs() < 0.01 * (rest - q).abs() + 1e-4, "{mass} kg, k {k}: {got} rad, expected {q}");
        }
    }
}

/// Without gravity, a mimic joint rests at its own spring position while its leader rests at
/// another; `None` returns it to the actuator's target (the leader's position).
#[test]
fn a_mimic_joint_rests_at_its_own_spring_position_until_released() {
    let (mut e, robot) = engine(0.05, 10.0, 0.0);
    let spring = |position| Some(JointSpring { position, stiffness: 2.0 });
    e.set_joint_spring(robot, JointId(0), spring(0.3)).unwrap();
    e.set_joint_spring(robot, JointId(1), spring(-0.4)).unwrap();
    e.step_n(480, 1.0 / 240.0).unwrap();
    let (a, b) = (angle(&e, robot, 1), angle(&e, robot, 2));
    assert!((a - 0.3).abs() < 1e-3 && (b + 0.4).abs() < 1e-3, "{a}, {b}");
    // Released, the mimic follows its leader's actuator (position target 0: the start).
    e.set_joint_spring(robot, JointId(0), None).unwrap();
    e.set_joint_spring(robot, JointId(1), None).unwrap();
    e.step_n(480, 1.0 / 240.0).unwrap();
    let (a, b) = (angle(&e, robot, 1), angle(&e, robot, 2));
    assert!(a.abs() < 1e-3 && b.abs() < 1e-3, "{a}, {b}");
}

/// The spring's torque is capped by the motor's force limit: a cap below the weight's torque
/// lets the bar sag until the weight's torque `m g L cos q` has fallen to the cap; bad springs
/// and joints are typed errors on both backends.
#[test]
fn spring_torque_is_capped_and_bad_springs_are_typed_errors() {
    let (mut e, robot) = engine(0.3, 10.0, G);
    // Its cap at 10 mrad (damping k h = 0.04 N·m·s/rad: the bar sags at about 1 rad/s).
    let stiff = Some(JointSpring { position: 0.0, stiffness: 10.0 });
    for j in [JointId(0), JointId(1)] {
        e.set_joint_spring(robot, j, stiff).unwrap();
        e.set_joint_force_limit(robot, j, 0.1).unwrap(); // weight's torque 0.29 N·m
    }
    e.step_n(960, 1.0 / 240.0).unwrap();
    let expected = -(0.1 / (0.3 * G * L)).acos(); // −1.2244 rad
    for link in [1, 2] {
        let q = angle(&e, robot, link);
        assert!((q - expected).abs() < 2e-3, "{q} rad, expected {expected}");
    }

    let mut scene = Scene::new("springs");
    let r = scene.add_robot("fingers", Arc::new(fingers(0.3, 10.0)), Isometry3::identity()).unwrap();
    let mut mock = MockBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    let bad = |position, stiffness| Some(JointSpring { position, stiffness });
    for (joint, spring, kind) in [
        (0, bad(f64::NAN, 1.0), "non-finite"),
        (0, bad(0.0, -1.0), "parameter"),
        (1, bad(0.0, f64::INFINITY), "parameter"),
        (5, bad(0.0, 1.0), "handle"),
    ] {
        for result in
            [e.set_joint_spring(robot, JointId(joint), spring), mock.set_joint_spring(r, JointId(joint), spring)]
        {
            match (result, kind) {
                (Err(CoreError::NonFinite { .. }), "non-finite")
                | (Err(CoreError::InvalidParameter { .. }), "parameter")
                | (Err(CoreError::InvalidHandle { .. }), "handle") => {}
                (other, _) => panic!("joint {joint}, {spring:?}: {other:?}, expected {kind}"),
            }
        }
    }
}
