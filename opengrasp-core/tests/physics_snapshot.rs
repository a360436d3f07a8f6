//! Speed features that must not change the physics: `PhysicsEngine::snapshot` (a copy of a
//! running simulation continues exactly as the original would, on every backend that supports
//! it, and independently of the original) and `PhysicsOptions::independent_chains` (the same
//! dynamics up to rounding).

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::model::{Geometry, JointKind, JointSpec, Link, RobotBuilder, Shape};
#[cfg(feature = "rapier")]
use opengrasp_core::physics::RapierBackend;
use opengrasp_core::physics::{MockBackend, PhysicsEngine, PhysicsOptions};
use opengrasp_core::scene::{ObjectId, RobotId, Scene, SceneObject};

/// Everything observable after one step.
type State = (f64, Vec<f64>, Vec<f64>, Vec<Isometry3<f64>>, Vec<(f64, f64)>);

fn observe<E: PhysicsEngine>(engine: &E) -> State {
    let contacts = engine.contacts().iter().map(|c| (c.distance, c.normal_force)).collect();
    (
        engine.time(),
        engine.joint_positions(RobotId(0)).unwrap(),
        engine.joint_velocities(RobotId(0)).unwrap(),
        vec![engine.object_pose(ObjectId(0)).unwrap()],
        contacts,
    )
}

/// The settling prefix: the fingers close on the cube without gravity (contacts with
/// warm-start impulses, a multibody with motors and a free body carry state across the
/// snapshot).
fn prefix<E: PhysicsEngine>() -> E {
    let options = PhysicsOptions { gravity: Vector3::zeros(), ..PhysicsOptions::default() };
    let mut engine = E::from_scene(&two_finger_scene(), &options).unwrap();
    engine.set_joint_position_targets(RobotId(0), &[0.4, 0.0, 0.4, 0.0]).unwrap();
    engine.step_n(75, 1.0 / 240.0).unwrap();
    engine
}

/// The continuation: new gravity, an impulse on the cube, 75 more steps, observed each step.
fn continuation<E: PhysicsEngine>(engine: &mut E, gravity: Vector3<f64>) -> Vec<State> {
    engine.set_gravity(gravity).unwrap();
    engine.apply_object_impulse(ObjectId(0), Vector3::new(0.01, 0.0, 0.01), Point3::new(0.0, 0.01, 0.46)).unwrap();
    (0..75)
        .map(|_| {
            engine.step(1.0 / 240.0).unwrap();
            observe(engine)
        })
        .collect()
}

/// A straight run and a run continued from a snapshot (taken before the original goes on with
/// different inputs) give bitwise the same trajectory.
fn snapshot_continues_bitwise<E: PhysicsEngine>() -> Vec<State> {
    let gravity = Vector3::new(3.0, -2.0, -9.81);
    let mut straight = prefix::<E>();
    let expected = continuation(&mut straight, gravity);

    let mut original = prefix::<E>();
    let mut copy = original.snapshot().expect("the backend supports snapshots");
    assert_eq!(observe(&copy), observe(&original), "{}: the copy starts elsewhere", original.name());
    // The original goes its own way first: the copy must not share its state.
    let other = continuation(&mut original, Vector3::new(0.0, 0.0, 9.81));
    let actual = continuation(&mut copy, gravity);
    assert_eq!(actual, expected, "{}: the snapshot's continuation differs from a straight run", copy.name());
    // The original's own continuation equals a straight run with its inputs too.
    let mut straight_other = prefix::<E>();
    assert_eq!(other, continuation(&mut straight_other, Vector3::new(0.0, 0.0, 9.81)), "{}", copy.name());
    actual
}

#[test]
fn mock_snapshot_continues_bitwise() {
    let states = snapshot_continues_bitwise::<MockBackend>();
    // The proximal joints reached their 0.4 rad targets at their velocity limit (2 rad/s) after
    // 0.2 s, before the snapshot (0.3125 s); nothing resists in the mock.
    let (time, q, ..) = states.last().unwrap();
    assert!((time - 150.0 / 240.0).abs() < 1e-12);
    assert_eq!(q, &vec![0.4, 0.0, 0.4, 0.0]);
}

#[cfg(feature = "rapier")]
#[test]
fn rapier_snapshot_continues_bitwise() {
    let states = snapshot_continues_bitwise::<RapierBackend>();
    // Something happened across the snapshot: contacts acted and the cube moved under the
    // tilted gravity and the impulse.
    assert!(states.iter().any(|s| s.4.iter().any(|&(_, f)| f > 0.0)), "no contact forces after the snapshot");
    let (first, last) = (states[0].3[0].translation.vector, states.last().unwrap().3[0].translation.vector);
    assert!((last - first).norm() > 3e-4, "cube from {first:?} to {last:?}"); // 0.9 mm measured
}

/// A palm with two fingers of two revolute joints each (a proximal and a distal phalanx), both
/// chains hanging from the fixed root, closing (about x) on a free 4 cm cube below the palm.
fn two_finger_scene() -> Scene {
    let phalanx = |name: &str| {
        Link::new(name)
            .with_shape(Shape::new(Isometry3::translation(0.0, 0.0, -0.02), Geometry::cuboid(0.02, 0.008, 0.04)))
    };
    let joint = |name: &str, parent: &str, child: &str, origin: Isometry3<f64>, sign: f64| {
        JointSpec::new(name, JointKind::Revolute, parent, child)
            .origin(origin)
            .axis(Vector3::x() * sign)
            .limits(-1.5, 1.5, 2.0, 2.0)
    };
    let hand = RobotBuilder::new("two fingers")
        .link(Link::new("palm").with_shape(Shape::at_origin(Geometry::cuboid(0.04, 0.1, 0.01))))
        .link(phalanx("l1"))
        .link(phalanx("l2"))
        .link(phalanx("r1"))
        .link(phalanx("r2"))
        .joint(joint("l1_joint", "palm", "l1", Isometry3::translation(0.0, 0.035, -0.006), -1.0))
        .joint(joint("l2_joint", "l1", "l2", Isometry3::translation(0.0, 0.0, -0.04), -1.0))
        .joint(joint("r1_joint", "palm", "r1", Isometry3::translation(0.0, -0.035, -0.006), 1.0))
        .joint(joint("r2_joint", "r1", "r2", Isometry3::translation(0.0, 0.0, -0.04), 1.0))
        .build()
        .unwrap();
    let mut scene = Scene::new("two fingers");
    scene.add_robot("hand", Arc::new(hand), Isometry3::translation(0.0, 0.0, 0.5)).unwrap();
    let cube = SceneObject::new(
        "cube",
        Isometry3::translation(0.0, 0.0, 0.5 - 0.045),
        vec![Shape::at_origin(Geometry::cuboid(0.04, 0.04, 0.04))],
        0.05,
    );
    scene.add_object(cube).unwrap();
    scene
}

/// The fingers close on the cube (no gravity) for 0.5 s; the joint positions and the cube's
/// pose every step.
#[cfg(feature = "rapier")]
fn squeeze_trajectory(independent_chains: bool) -> Vec<(Vec<f64>, Isometry3<f64>)> {
    let options = PhysicsOptions { independent_chains, gravity: Vector3::zeros(), ..PhysicsOptions::default() };
    let mut engine = RapierBackend::from_scene(&two_finger_scene(), &options).unwrap();
    engine.set_joint_position_targets(RobotId(0), &[0.4, 0.0, 0.4, 0.0]).unwrap();
    (0..120)
        .map(|_| {
            engine.step(1.0 / 240.0).unwrap();
            (engine.joint_positions(RobotId(0)).unwrap(), engine.object_pose(ObjectId(0)).unwrap())
        })
        .collect()
}

/// Same trajectory within 1e-9 (bitwise in this small case; the ARMAR-III and Barrett hands'
/// larger multibodies round differently).
#[cfg(feature = "rapier")]
#[test]
fn independent_chains_give_the_same_dynamics() {
    let one = squeeze_trajectory(false);
    let split = squeeze_trajectory(true);
    let (mut dq, mut dx): (f64, f64) = (0.0, 0.0);
    for ((q1, p1), (q2, p2)) in one.iter().zip(&split) {
        dq = q1.iter().zip(q2).map(|(a, b)| (a - b).abs()).fold(dq, f64::max);
        dx = dx.max((p1.translation.vector - p2.translation.vector).norm());
    }
    assert!(dq < 1e-9 && dx < 1e-9, "joints differ by {dq} rad, the cube by {dx} m");
    // The split happened: a fixed anchor body for the second finger's multibody (palm, four
    // phalanges, cube: six bodies otherwise).
    let bodies = |independent_chains| {
        let options = PhysicsOptions { independent_chains, ..PhysicsOptions::default() };
        format!("{:?}", RapierBackend::from_scene(&two_finger_scene(), &options).unwrap())
    };
    assert!(bodies(false).contains("bodies: 6") && bodies(true).contains("bodies: 7"), "{}", bodies(true));
    // The fingers pushed the cube: free and without gravity, only contacts move it.
    let (_, cube) = split.last().unwrap();
    let moved = (cube.translation.vector - Vector3::new(0.0, 0.0, 0.5 - 0.045)).norm();
    assert!(moved > 1e-3 || cube.rotation.angle() > 1e-2, "{cube:?}");
}
