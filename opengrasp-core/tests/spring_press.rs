//! A stalled joint spring presses with its torque: two mirrored fingers of one or two revolute
//! joints pinch a free box without gravity, and each fingertip ball pushes it with `τ / L` (the
//! pressing spring's torque over the lever from its joint to the ball); a proximal joint held
//! by a stiff spring deflects only by the distal joint's reaction over its stiffness.
#![cfg(feature = "rapier")]

use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::model::{Geometry, Inertial, JointId, JointKind, JointSpec, Link, LinkId, RobotBuilder, Shape};
use opengrasp_core::physics::{ContactBody, JointSpring, PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::{ObjectId, RobotId, Scene, SceneObject};

/// Proximal and distal phalanx lengths (m): joint to joint, and distal joint to ball centre.
const L1: f64 = 0.05;
const L2: f64 = 0.025;
/// Fingertip ball radius (m).
const BALL: f64 = 0.005;
/// Half-width (m) of the pinched box.
const HALF_WIDTH: f64 = 0.025;
/// Spring rest this far (rad) past the touching configuration `q = 0`.
const THETA: f64 = 0.4;
/// The pressing joints start this far (rad) open: the springs close the fingers.
const OPEN: f64 = 0.02;

/// A phalanx along +z of length `len` (a 10 g stem), with the fingertip ball at its end if `tip`.
fn phalanx(name: &str, len: f64, tip: bool) -> Link {
    let stem = Isometry3::translation(0.0, 0.0, len / 2.0);
    let size = Vector3::new(0.01, 0.004, len);
    let link = Link::new(name)
        .with_shape(Shape::new(stem, Geometry::cuboid(size.x, size.y, size.z)))
        .with_inertial(Inertial::solid_box(0.01, size, stem));
    if tip {
        link.with_shape(Shape::new(Isometry3::translation(0.0, 0.0, len), Geometry::Sphere { radius: BALL }))
    } else {
        link
    }
}

/// Fingers `left` (y > 0, joints about +x) and `right` (mirrored) standing along +z, each of
/// one joint (`two` false: a phalanx of `L1 + L2`) or two (`L1`, `L2`) with effort limits
/// `efforts` (proximal, distal), their balls touching a free 0.1 kg box at the origin in the
/// straight configuration; joints in the order left proximal, [left distal,] right proximal,
/// [right distal]. The pressing joints start `OPEN`. Gravity off, 1 kHz contacts.
fn pinch(two: bool, efforts: [f64; 2]) -> (RapierBackend, [LinkId; 2]) {
    let mut b = RobotBuilder::new("fingers").link(Link::new("base"));
    for (name, side) in [("left", 1.0), ("right", -1.0)] {
        let revolute = |joint: &str, parent: &str, child: &str, origin: Vector3<f64>, effort: f64| {
            JointSpec::new(format!("{name}_{joint}"), JointKind::Revolute, parent, child)
                .origin(Isometry3::translation(origin.x, origin.y, origin.z))
                .axis(Vector3::x() * side)
                .limits(-1.5, 1.5, 1.0, effort)
        };
        let (p, d) = (format!("{name}_proximal"), format!("{name}_distal"));
        let base = Vector3::new(0.0, side * (HALF_WIDTH + BALL), -(L1 + L2));
        if two {
            b = b
                .link(phalanx(&p, L1, false))
                .joint(revolute("j1", "base", &p, base, efforts[0]))
                .link(phalanx(&d, L2, true))
                .joint(revolute("j2", &p, &d, Vector3::new(0.0, 0.0, L1), efforts[1]));
        } else {
            b = b.link(phalanx(&p, L1 + L2, true)).joint(revolute("j1", "base", &p, base, efforts[0]));
        }
    }
    let robot = b.build().unwrap();
    let tip = |name: &str| robot.link_id(&format!("{name}_{}", if two { "distal" } else { "proximal" })).unwrap();
    let tips = [tip("left"), tip("right")];
    let mut scene = Scene::new("pinch");
    let id = scene.add_robot("fingers", Arc::new(robot), Isometry3::identity()).unwrap();
    let q: Vec<f64> = if two { vec![0.0, -OPEN, 0.0, -OPEN] } else { vec![-OPEN, -OPEN] };
    scene.set_robot_configuration(id, &q).unwrap();
    let shape = Shape::at_origin(Geometry::cuboid(0.05, 2.0 * HALF_WIDTH, 0.04));
    scene.add_object(SceneObject::new("box", Isometry3::identity(), vec![shape], 0.1)).unwrap();
    let options = PhysicsOptions {
        gravity: Vector3::zeros(),
        contact_frequency: 1000.0,
        solver_iterations: 16,
        ..PhysicsOptions::default()
    };
    (RapierBackend::from_scene(&scene, &options).unwrap(), tips)
}

/// Normal force (N) on link `tip` summed over its contacts after the last step.
fn tip_force(engine: &RapierBackend, tip: LinkId) -> f64 {
    engine
        .contacts()
        .iter()
        .filter(|c| [c.body1, c.body2].iter().any(|b| matches!(b, ContactBody::Link { link, .. } if *link == tip)))
        .map(|c| c.normal_force)
        .sum()
}

/// A spring of cap `cap` resting `THETA` past the touch: `cap` there.
fn pressing(cap: f64) -> Option<JointSpring> {
    Some(JointSpring { position: THETA, stiffness: cap / THETA })
}

/// Runs `steps` steps of 1/240 s and returns each tip's normal force, the joint positions and the box's offset.
fn settle(e: &mut RapierBackend, tips: [LinkId; 2], steps: usize) -> ([f64; 2], Vec<f64>, f64) {
    e.step_n(steps, 1.0 / 240.0).unwrap();
    let moved = e.object_pose(ObjectId(0)).unwrap().translation.vector.norm();
    ([tip_force(e, tips[0]), tip_force(e, tips[1])], e.joint_positions(RobotId(0)).unwrap(), moved)
}

#[test]
fn a_stalled_spring_in_a_one_joint_finger_presses_with_its_cap() {
    let tau = 0.5;
    let (mut e, tips) = pinch(false, [tau, 0.0]);
    for j in [0, 1] {
        e.set_joint_spring(RobotId(0), JointId(j), pressing(tau)).unwrap();
    }
    let (f, q, moved) = settle(&mut e, tips, 72); // 0.3 s
    let lever = L1 + L2;
    println!("one joint: tips {f:?} N (τ/L = {} N), q = {q:?}, box moved {moved} m", tau / lever);
    for (f, q) in f.iter().zip(&q) {
        // The spring loses q / θ of its torque as the ball sinks in.
        let expected = tau / lever * (1.0 - q / THETA);
        assert!((f - expected).abs() < 0.02 * expected, "{f} N, expected {expected} N");
    }
    assert!(moved < 1e-4, "{moved}");
}

#[test]
fn a_stalled_distal_spring_presses_with_its_cap_while_a_stiff_proximal_spring_holds() {
    let (tau1, tau2) = (2.5, 0.5);
    let (mut e, tips) = pinch(true, [tau1, tau2]);
    // Proximal joints: held at q = 0 by springs of their full cap at 1 mrad.
    let lock = tau1 / 1e-3;
    for j in [0, 2] {
        e.set_joint_spring(RobotId(0), JointId(j), Some(JointSpring { position: 0.0, stiffness: lock })).unwrap();
        e.set_joint_spring(RobotId(0), JointId(j + 1), pressing(tau2)).unwrap();
    }
    // 1.2 s: the stiff spring's damping (time constant 0.25 s) has let it reach its deflection.
    let (f, q, moved) = settle(&mut e, tips, 288);
    println!("two joints: tips {f:?} N (τ/L = {} N), q = {q:?}, box moved {moved} m", tau2 / L2);
    for (k, f) in f.iter().enumerate() {
        let expected = tau2 / L2 * (1.0 - q[2 * k + 1] / THETA); // ≈ 20 N
        assert!((f - expected).abs() < 0.02 * expected, "{f} N, expected {expected} N");
        // The proximal joint carries F (L1 + L2) ≈ 1.5 N·m: its spring deflects ≈ 0.6 mrad.
        let reaction = f * (L1 + L2);
        assert!((q[2 * k].abs() - reaction / lock).abs() < 0.03 * reaction / lock, "proximal at {} rad", q[2 * k]);
    }
    assert!(moved < 1e-4, "{moved}");
}
