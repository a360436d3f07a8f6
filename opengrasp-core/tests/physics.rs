//! The physics layer: the same generic programs on the mock and rapier backends, rapier against
//! analytic rest heights, free fall and Newton's second law, determinism and error handling.

use std::sync::Arc;

#[cfg(feature = "rapier")]
use nalgebra::Matrix3;
use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::model::samples::planar_arm;
use opengrasp_core::model::{Geometry, LinkId, Shape};
#[cfg(feature = "rapier")]
use opengrasp_core::physics::{BodyVelocity, ContactBody, RapierBackend};
use opengrasp_core::physics::{JointTarget, MockBackend, PhysicsEngine, PhysicsOptions};
#[cfg(feature = "rapier")]
use opengrasp_core::scene::StaticBody;
use opengrasp_core::scene::{ObjectId, RobotId, Scene, SceneObject};
use opengrasp_core::CoreError;

#[cfg(feature = "rapier")]
const G: f64 = 9.81;
/// Link lengths of the planar arm used throughout.
const ARM: [f64; 2] = [0.5, 0.4];

/// A 2-link planar arm at the origin (joints about z, velocity limit 2 rad/s) and a 0.2 kg box
/// lying free far away from it, 1 m up (so it is never touched by the arm).
fn arm_scene() -> (Scene, RobotId, ObjectId) {
    let mut scene = Scene::new("arm");
    let arm = scene.add_robot("arm", Arc::new(planar_arm(&ARM).unwrap()), Isometry3::identity()).unwrap();
    let cube = SceneObject::new(
        "cube",
        Isometry3::translation(3.0, 0.0, 1.0),
        vec![Shape::at_origin(Geometry::cuboid(0.05, 0.05, 0.05))],
        0.2,
    );
    let obj = scene.add_object(cube).unwrap();
    (scene, arm, obj)
}

/// A static table whose top face is at `top` (a 1 × 1 × `top` box standing on z = 0).
#[cfg(feature = "rapier")]
fn table(top: f64) -> StaticBody {
    StaticBody::new(
        "table",
        Isometry3::translation(0.0, 0.0, top / 2.0),
        vec![Shape::at_origin(Geometry::cuboid(1.0, 1.0, top))],
    )
}

fn tool_pose_error<E: PhysicsEngine>(engine: &E, arm: RobotId) -> f64 {
    let robot = planar_arm(&ARM).unwrap();
    let q = engine.joint_positions(arm).unwrap();
    let tool = robot.link_id("tool").unwrap();
    let expected = forward_kinematics(&robot, &q).unwrap()[tool];
    let actual = engine.link_pose(arm, tool).unwrap();
    (actual.translation.vector - expected.translation.vector).norm() + actual.rotation.angle_to(&expected.rotation)
}

/// Drives the arm to a target configuration; it must arrive, stop, and report link poses that
/// match forward kinematics of the reported joint positions.
fn joint_tracking<E: PhysicsEngine>(tolerance: f64) {
    let (scene, arm, _) = arm_scene();
    let mut engine = E::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    assert_eq!(engine.dof(arm).unwrap(), 2);
    let target = [0.8, -0.6];
    engine.set_joint_position_targets(arm, &target).unwrap();
    // At 2 rad/s the 0.8 rad move takes 0.4 s: halfway through, joint 0 is near 0.4 rad.
    engine.step_n(24, 1.0 / 120.0).unwrap();
    let q = engine.joint_positions(arm).unwrap();
    assert!((q[0] - 0.4).abs() < 0.02 + tolerance, "{}: q0 at 0.2 s = {}", engine.name(), q[0]);
    assert!((engine.time() - 0.2).abs() < 1e-12);
    engine.step_n(96, 1.0 / 120.0).unwrap();
    let q = engine.joint_positions(arm).unwrap();
    let qd = engine.joint_velocities(arm).unwrap();
    for i in 0..2 {
        assert!((q[i] - target[i]).abs() < tolerance, "{}: q = {q:?}", engine.name());
        assert!(qd[i].abs() < 100.0 * tolerance, "{}: qd = {qd:?}", engine.name());
    }
    assert!(tool_pose_error(&engine, arm) < tolerance, "{}", engine.name());
    // A target beyond the joint limit (±π) is clamped to it.
    engine.set_joint_target(arm, 1, JointTarget::Position(10.0)).unwrap();
    engine.step_n(240, 1.0 / 120.0).unwrap();
    let q1 = engine.joint_positions(arm).unwrap()[1];
    assert!((q1 - std::f64::consts::PI).abs() < 0.02 + tolerance, "{}: q1 = {q1}", engine.name());
}

/// Velocity targets: clamped to the velocity limit, integrated over time.
fn velocity_tracking<E: PhysicsEngine>(tolerance: f64) {
    let (scene, arm, _) = arm_scene();
    let mut engine = E::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    engine.set_joint_velocity_targets(arm, &[0.5, -5.0]).unwrap();
    engine.step_n(60, 1.0 / 120.0).unwrap();
    let q = engine.joint_positions(arm).unwrap();
    let qd = engine.joint_velocities(arm).unwrap();
    assert!((q[0] - 0.25).abs() < 0.01 + tolerance, "{}: {q:?}", engine.name());
    assert!((q[1] + 1.0).abs() < 0.02 + tolerance, "{}: {q:?}", engine.name());
    assert!((qd[0] - 0.5).abs() < 0.01 + tolerance && (qd[1] + 2.0).abs() < 0.02 + tolerance, "{qd:?}");
    // Back to position control: holds where it is told.
    engine.set_joint_position_targets(arm, &[0.0, 0.0]).unwrap();
    engine.step_n(90, 1.0 / 120.0).unwrap();
    let q = engine.joint_positions(arm).unwrap();
    assert!(q[0].abs() < tolerance && q[1].abs() < tolerance, "{}: {q:?}", engine.name());
}

/// An object attached to the tool follows it; once detached it no longer does.
fn attachment_follows_link<E: PhysicsEngine>(tolerance: f64) {
    let (mut scene, arm, obj) = arm_scene();
    scene.set_object_pose(obj, Isometry3::translation(0.95, 0.0, 0.0)).unwrap();
    scene.attach(obj, arm, "tool").unwrap();
    let mut engine = E::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    let tool = LinkId(scene.robot(arm).unwrap().robot.link_id("tool").unwrap().0);
    engine.set_joint_position_targets(arm, &[std::f64::consts::FRAC_PI_2, 0.0]).unwrap();
    engine.step_n(240, 1.0 / 120.0).unwrap();
    // Arm straight along +y now: the object, 5 cm beyond the tip, is at (0, 0.95, 0).
    let p = engine.object_pose(obj).unwrap().translation.vector;
    assert!((p - Vector3::new(0.0, 0.95, 0.0)).norm() < tolerance, "{}: {p:?}", engine.name());
    let offset = engine.link_pose(arm, tool).unwrap().inverse() * engine.object_pose(obj).unwrap();
    assert!((offset.translation.vector - Vector3::new(0.05, 0.0, 0.0)).norm() < tolerance);
    assert!(matches!(engine.attach(obj, arm, tool), Err(CoreError::InvalidParameter { .. })));
    engine.set_gravity(Vector3::zeros()).unwrap();
    engine.detach(obj).unwrap();
    assert!(matches!(engine.detach(obj), Err(CoreError::InvalidHandle { .. })));
    let before = engine.object_pose(obj).unwrap().translation.vector;
    engine.set_joint_position_targets(arm, &[0.0, 0.0]).unwrap();
    engine.step_n(120, 1.0 / 120.0).unwrap();
    let after = engine.object_pose(obj).unwrap().translation.vector;
    // It is left behind (it may drift at its release velocity, but not follow the tool).
    let tip = engine.link_pose(arm, tool).unwrap().translation.vector;
    assert!((tip - Vector3::new(0.9, 0.0, 0.0)).norm() < 10.0 * tolerance);
    assert!((after - tip).norm() > 0.5, "{}: {before:?} -> {after:?}", engine.name());
}

/// Bad input gives typed errors, never a panic, and leaves the engine usable.
fn bad_input_is_rejected<E: PhysicsEngine>() {
    let (scene, arm, obj) = arm_scene();
    let bad_options = PhysicsOptions { timestep: 0.0, ..PhysicsOptions::default() };
    assert!(matches!(E::from_scene(&scene, &bad_options), Err(CoreError::InvalidParameter { .. })));
    let bad_options = PhysicsOptions { gravity: Vector3::new(0.0, f64::NAN, 0.0), ..PhysicsOptions::default() };
    assert!(matches!(E::from_scene(&scene, &bad_options), Err(CoreError::NonFinite { .. })));

    let mut e = E::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    for dt in [0.0, -0.01, f64::NAN, f64::INFINITY] {
        assert!(matches!(e.step(dt), Err(CoreError::InvalidParameter { .. })), "dt = {dt}");
    }
    let (bad_robot, bad_obj) = (RobotId(7), ObjectId(9));
    let handle = |r: Result<(), CoreError>| matches!(r, Err(CoreError::InvalidHandle { .. }));
    assert!(handle(e.set_joint_target(bad_robot, 0, JointTarget::Position(0.0))));
    assert!(handle(e.set_joint_target(arm, 2, JointTarget::Position(0.0))));
    assert!(handle(e.joint_positions(bad_robot).map(|_| ())));
    assert!(handle(e.joint_velocities(bad_robot).map(|_| ())));
    assert!(handle(e.link_pose(arm, LinkId(99)).map(|_| ())));
    assert!(handle(e.link_pose(bad_robot, LinkId(0)).map(|_| ())));
    assert!(handle(e.object_pose(bad_obj).map(|_| ())));
    assert!(handle(e.object_velocity(bad_obj).map(|_| ())));
    assert!(handle(e.set_object_pose(bad_obj, Isometry3::identity())));
    assert!(handle(e.set_object_force(bad_obj, Vector3::zeros(), Vector3::zeros())));
    assert!(handle(e.apply_object_impulse(bad_obj, Vector3::zeros(), Point3::origin())));
    assert!(handle(e.attach(bad_obj, arm, LinkId(0))));
    assert!(handle(e.attach(obj, bad_robot, LinkId(0))));
    assert!(handle(e.attach(obj, arm, LinkId(99))));
    assert!(handle(e.detach(obj)));

    let non_finite = |r: Result<(), CoreError>| matches!(r, Err(CoreError::NonFinite { .. }));
    assert!(non_finite(e.set_joint_target(arm, 0, JointTarget::Position(f64::NAN))));
    assert!(non_finite(e.set_joint_target(arm, 0, JointTarget::Velocity(f64::INFINITY))));
    assert!(non_finite(e.set_joint_position_targets(arm, &[0.3, f64::NAN])));
    assert!(non_finite(e.set_gravity(Vector3::new(f64::NAN, 0.0, 0.0))));
    assert!(non_finite(e.set_object_force(obj, Vector3::new(0.0, 0.0, f64::NAN), Vector3::zeros())));
    assert!(non_finite(e.set_object_force(obj, Vector3::zeros(), Vector3::repeat(f64::INFINITY))));
    assert!(non_finite(e.apply_object_impulse(obj, Vector3::repeat(f64::NAN), Point3::origin())));
    assert!(non_finite(e.apply_object_impulse(obj, Vector3::zeros(), Point3::new(f64::NAN, 0.0, 0.0))));
    let mut nan_pose = Isometry3::identity();
    nan_pose.translation.vector.x = f64::NAN;
    assert!(non_finite(e.set_object_pose(obj, nan_pose)));
    assert!(matches!(
        e.set_joint_position_targets(arm, &[0.1, 0.2, 0.3]),
        Err(CoreError::DimensionMismatch { expected: 2, actual: 3 })
    ));

    // Nothing above changed the state: targets stayed at the initial configuration.
    e.step_n(10, 0.01).unwrap();
    let q = e.joint_positions(arm).unwrap();
    assert!(q.iter().all(|v| v.abs() < 1e-6), "{q:?}");
    assert!(e.gravity().iter().all(|g| g.is_finite()));
}

#[test]
fn joint_tracking_mock() {
    joint_tracking::<MockBackend>(1e-12);
}

#[cfg(feature = "rapier")]
#[test]
fn joint_tracking_rapier() {
    joint_tracking::<RapierBackend>(2e-3);
}

#[test]
fn velocity_tracking_mock() {
    velocity_tracking::<MockBackend>(1e-12);
}

#[cfg(feature = "rapier")]
#[test]
fn velocity_tracking_rapier() {
    velocity_tracking::<RapierBackend>(2e-3);
}

#[test]
fn attachment_follows_link_mock() {
    attachment_follows_link::<MockBackend>(1e-9);
}

#[cfg(feature = "rapier")]
#[test]
fn attachment_follows_link_rapier() {
    attachment_follows_link::<RapierBackend>(3e-3);
}

#[test]
fn bad_input_is_rejected_mock() {
    bad_input_is_rejected::<MockBackend>();
}

#[cfg(feature = "rapier")]
#[test]
fn bad_input_is_rejected_rapier() {
    bad_input_is_rejected::<RapierBackend>();
}

#[cfg(feature = "rapier")]
#[test]
fn engines_are_object_safe_and_send() {
    fn assert_send<T: Send>() {}
    assert_send::<MockBackend>();
    assert_send::<RapierBackend>();
    let (scene, arm, _) = arm_scene();
    let options = PhysicsOptions::default();
    let mut engines: Vec<Box<dyn PhysicsEngine>> = vec![
        Box::new(MockBackend::from_scene(&scene, &options).unwrap()),
        Box::new(RapierBackend::from_scene(&scene, &options).unwrap()),
    ];
    for e in &mut engines {
        e.set_joint_position_targets(arm, &[0.2, 0.1]).unwrap();
        e.step_n(60, 1.0 / 60.0).unwrap();
        let q = e.joint_positions(arm).unwrap();
        assert!((q[0] - 0.2).abs() < 2e-3 && (q[1] - 0.1).abs() < 2e-3, "{}: {q:?}", e.name());
    }
    assert_eq!(engines[0].name(), "mock");
    assert_eq!(engines[1].name(), "rapier");
}

/// A cube of side `size` and mass `mass` at height `z` above the table centre.
#[cfg(feature = "rapier")]
fn drop_scene(object: SceneObject, table_top: Option<f64>) -> Scene {
    let mut scene = Scene::new("drop");
    if let Some(top) = table_top {
        scene.add_body(table(top)).unwrap();
    }
    scene.add_object(object).unwrap();
    scene
}

#[cfg(feature = "rapier")]
#[test]
fn box_comes_to_rest_on_table_at_analytic_height() {
    let (top, size, mass) = (0.4, 0.1, 0.5);
    let cube = SceneObject::new(
        "cube",
        Isometry3::translation(0.1, -0.05, 0.6),
        vec![Shape::at_origin(Geometry::cuboid(size, size, size))],
        mass,
    );
    let scene = drop_scene(cube, Some(top));
    let mut engine = RapierBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    engine.step_n(360, 1.0 / 240.0).unwrap(); // 1.5 s: falls 0.15 m in 0.17 s, then settles
    let pose = engine.object_pose(ObjectId(0)).unwrap();
    let expected = top + size / 2.0;
    let z = pose.translation.vector.z;
    println!("box rest height {z:.6} m, analytic {expected:.6} m, error {:.3e} m", z - expected);
    assert!((z - expected).abs() < 1e-3, "rest height {z}, expected {expected}");
    assert!(pose.rotation.angle() < 1e-3, "the box tipped: {}", pose.rotation.angle());
    let v = engine.object_velocity(ObjectId(0)).unwrap();
    assert!(v.linear.norm() < 1e-3 && v.angular.norm() < 1e-2, "{v:?}");

    // Contacts: cube on table, normal vertical, supporting its weight.
    let contacts = engine.contacts();
    assert!(!contacts.is_empty());
    let mut total = 0.0;
    for c in &contacts {
        let pair = [c.body1, c.body2];
        assert!(pair.contains(&ContactBody::Object(ObjectId(0))));
        assert!(pair.contains(&ContactBody::Static(opengrasp_core::scene::BodyId(0))));
        assert!(c.normal.z.abs() > 0.999, "{:?}", c.normal);
        assert!((c.point.z - top).abs() < 2e-3, "{:?}", c.point);
        // Normal points from body1 to body2: from the table up to the cube, or the reverse.
        let cube_first = c.body1 == ContactBody::Object(ObjectId(0));
        assert!(if cube_first { c.normal.z < 0.0 } else { c.normal.z > 0.0 });
        total += c.normal_force;
    }
    println!("support force {total:.4} N, weight {:.4} N", mass * G);
    assert!((total - mass * G).abs() < 0.05 * mass * G, "support {total} N vs weight {} N", mass * G);
}

#[cfg(feature = "rapier")]
#[test]
fn upright_cylinder_rests_on_its_end() {
    // URDF cylinders are along local z: standing on the table its centre is length/2 above it.
    let (top, radius, length) = (0.3, 0.03, 0.2);
    let can = SceneObject::new(
        "can",
        Isometry3::translation(0.0, 0.0, top + length / 2.0 + 0.01),
        vec![Shape::at_origin(Geometry::Cylinder { radius, length })],
        0.3,
    );
    let mut engine = RapierBackend::from_scene(&drop_scene(can, Some(top)), &PhysicsOptions::default()).unwrap();
    engine.step_n(120, 1.0 / 240.0).unwrap();
    let pose = engine.object_pose(ObjectId(0)).unwrap();
    let z = pose.translation.vector.z;
    assert!((z - (top + length / 2.0)).abs() < 1e-3, "cylinder centre at {z}");
    assert!(pose.rotation.angle() < 1e-3);
}

#[cfg(feature = "rapier")]
/// A 10 cm, 0.1 kg ball at height `h` above the ground of [`drop_scene`].
fn ball_scene(h: f64) -> Scene {
    let ball = SceneObject::new(
        "ball",
        Isometry3::translation(0.0, 0.0, h),
        vec![Shape::at_origin(Geometry::Sphere { radius: 0.05 })],
        0.1,
    );
    drop_scene(ball, Some(0.2))
}

#[test]
fn sphere_falls_half_g_t_squared() {
    let (h, t): (f64, f64) = (2.0, 0.5);
    let scene = ball_scene(h);
    let dt = 1.0 / 240.0;
    let mut engine = RapierBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    engine.step_n((t / dt).round() as usize, dt).unwrap();
    let fallen = h - engine.object_pose(ObjectId(0)).unwrap().translation.vector.z;
    let analytic = 0.5 * G * t * t;
    // Semi-implicit Euler overshoots by g·h·t/2 for an integration step h; rapier integrates with
    // `solver_iterations` (8) substeps of dt/8, so the error is about 1.3 mm here.
    println!("fallen {fallen:.5} m, analytic {analytic:.5} m");
    assert!((fallen - analytic).abs() <= 0.5 * G * (dt / 8.0) * t + 1e-6, "fallen {fallen}, analytic {analytic}");
    assert!(fallen > analytic, "semi-implicit Euler falls slightly faster than the exact solution");
    let v = engine.object_velocity(ObjectId(0)).unwrap().linear;
    assert!((v.z + G * t).abs() < 1e-6 && v.xy().norm() < 1e-9, "{v:?}");
    assert!(engine.contacts().is_empty());

    // The mock does not simulate gravity: free objects stay where they are (documented).
    let mut mock = MockBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    mock.step_n(120, dt).unwrap();
    assert_eq!(mock.object_pose(ObjectId(0)).unwrap(), scene.objects()[0].pose);
    assert_eq!(mock.object_velocity(ObjectId(0)).unwrap(), BodyVelocity::default());
    assert!(mock.contacts().is_empty());
}

#[cfg(feature = "rapier")]
#[test]
fn external_force_and_impulse_follow_newton() {
    let mass = 0.4;
    let ball = SceneObject {
        inertia: Matrix3::identity() * 1e-3,
        ..SceneObject::new(
            "ball",
            Isometry3::translation(0.0, 0.0, 1.0),
            vec![Shape::at_origin(Geometry::Sphere { radius: 0.05 })],
            mass,
        )
    };
    let scene = drop_scene(ball, None);
    let mut engine = RapierBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    engine.set_gravity(Vector3::zeros()).unwrap();
    assert_eq!(engine.gravity(), Vector3::zeros());
    // Constant force: x = F t² / 2m; constant torque: ω = τ t / I.
    let (force, t) = (Vector3::new(2.0, 0.0, 0.0), 0.25);
    engine.set_object_force(ObjectId(0), force, Vector3::new(0.0, 0.0, 1e-3)).unwrap();
    engine.step_n(60, t / 60.0).unwrap();
    let x = engine.object_pose(ObjectId(0)).unwrap().translation.x;
    let v = engine.object_velocity(ObjectId(0)).unwrap();
    assert!((v.linear.x - force.x / mass * t).abs() < 1e-9, "{v:?}");
    assert!((x - force.x / mass * t * t / 2.0).abs() < force.x / mass * t * t / 60.0, "x = {x}");
    assert!((v.angular.z - 1e-3 * t / 1e-3).abs() < 1e-6, "{v:?}");
    // Remove it and kick: Δv = J / m.
    engine.set_object_force(ObjectId(0), Vector3::zeros(), Vector3::zeros()).unwrap();
    let before = engine.object_velocity(ObjectId(0)).unwrap().linear;
    let centre = engine.object_pose(ObjectId(0)).unwrap() * Point3::origin();
    engine.apply_object_impulse(ObjectId(0), Vector3::new(0.0, 0.2, 0.0), centre).unwrap();
    engine.step(1.0 / 240.0).unwrap();
    let after = engine.object_velocity(ObjectId(0)).unwrap().linear;
    assert!(((after - before) - Vector3::new(0.0, 0.5, 0.0)).norm() < 1e-9, "{before:?} -> {after:?}");
    // Teleporting resets the velocity.
    engine.set_object_pose(ObjectId(0), Isometry3::translation(1.0, 1.0, 1.0)).unwrap();
    assert_eq!(engine.object_velocity(ObjectId(0)).unwrap(), BodyVelocity::default());
    assert_eq!(engine.object_pose(ObjectId(0)).unwrap(), Isometry3::translation(1.0, 1.0, 1.0));
}

/// Arm sweeping through a box on a table, a ball falling onto both.
#[cfg(feature = "rapier")]
fn busy_scene() -> Scene {
    let mut scene = Scene::new("busy");
    scene.add_body(table(0.2)).unwrap();
    scene.add_robot("arm", Arc::new(planar_arm(&ARM).unwrap()), Isometry3::translation(-0.4, -0.4, 0.25)).unwrap();
    let cube = SceneObject::new(
        "cube",
        Isometry3::translation(0.1, 0.1, 0.3),
        vec![Shape::at_origin(Geometry::cuboid(0.08, 0.08, 0.08))],
        0.3,
    );
    scene.add_object(cube).unwrap();
    let ball = SceneObject::new(
        "ball",
        Isometry3::translation(0.12, 0.1, 0.6),
        vec![Shape::at_origin(Geometry::Sphere { radius: 0.04 })],
        0.1,
    );
    scene.add_object(ball).unwrap();
    scene
}

#[cfg(feature = "rapier")]
fn trajectory(scene: &Scene) -> Vec<(Vec<f64>, Vec<Isometry3<f64>>)> {
    let mut engine = RapierBackend::from_scene(scene, &PhysicsOptions::default()).unwrap();
    engine.set_joint_position_targets(RobotId(0), &[1.2, 0.3]).unwrap();
    (0..150)
        .map(|i| {
            if i == 75 {
                engine
                    .apply_object_impulse(ObjectId(1), Vector3::new(0.05, 0.0, 0.1), Point3::new(0.1, 0.1, 0.5))
                    .unwrap();
            }
            engine.step(1.0 / 240.0).unwrap();
            let poses = (0..2).map(|o| engine.object_pose(ObjectId(o)).unwrap()).collect();
            (engine.joint_positions(RobotId(0)).unwrap(), poses)
        })
        .collect()
}

#[cfg(feature = "rapier")]
#[test]
fn rapier_is_deterministic() {
    let scene = busy_scene();
    let a = trajectory(&scene);
    let b = trajectory(&scene);
    assert_eq!(a, b, "two runs of the same scene differ");
    // And something actually happened: the arm moved and the ball fell.
    let (q, poses) = a.last().unwrap();
    assert!(q[0] > 0.5, "{q:?}");
    assert!(poses[1].translation.z < 0.59);
}

/// A parallel gripper hanging in the air: palm fixed at `palm`, two prismatic fingers closing
/// along y (the right one mimics the left), 10 N effort limit, 0.1 m/s.
#[cfg(feature = "rapier")]
fn gripper() -> opengrasp_core::model::Robot {
    use opengrasp_core::model::{JointKind, JointSpec, Link, RobotBuilder};
    let finger = |name: &str| {
        Link::new(name)
            .with_shape(Shape::new(Isometry3::translation(0.0, 0.0, -0.04), Geometry::cuboid(0.02, 0.01, 0.06)))
    };
    RobotBuilder::new("gripper")
        .link(Link::new("palm").with_shape(Shape::at_origin(Geometry::cuboid(0.03, 0.12, 0.02))))
        .link(finger("left"))
        .link(finger("right"))
        .joint(
            JointSpec::new("left_joint", JointKind::Prismatic, "palm", "left")
                .origin(Isometry3::translation(0.0, 0.05, -0.011))
                .axis(-Vector3::y())
                .limits(0.0, 0.045, 0.1, 10.0),
        )
        .joint(
            JointSpec::new("right_joint", JointKind::Prismatic, "palm", "right")
                .origin(Isometry3::translation(0.0, -0.05, -0.011))
                .axis(Vector3::y())
                .limits(0.0, 0.045, 0.1, 10.0)
                .mimic("left_joint", 1.0, 0.0),
        )
        .build()
        .unwrap()
}

#[cfg(feature = "rapier")]
#[test]
fn gripper_holds_object_by_friction_until_overloaded() {
    // Cube of 4 cm between the fingers: faces touch at q = 0.045 - 0.02 = 0.025.
    let palm = Isometry3::translation(0.0, 0.0, 0.5);
    let mut scene = Scene::new("grasp");
    let g = scene.add_robot("gripper", Arc::new(gripper()), palm).unwrap();
    scene.set_robot_configuration(g, &[0.024]).unwrap();
    let start = Isometry3::translation(0.0, 0.0, 0.5 - 0.011 - 0.04);
    let (mass, friction) = (0.1, 0.5);
    let cube = SceneObject {
        friction,
        ..SceneObject::new("cube", start, vec![Shape::at_origin(Geometry::cuboid(0.04, 0.04, 0.04))], mass)
    };
    let obj = scene.add_object(cube).unwrap();
    let mut engine = RapierBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    engine.set_joint_position_targets(g, &[0.04]).unwrap(); // squeeze beyond contact
    engine.step_n(120, 1.0 / 240.0).unwrap();

    // Fingers stopped by the cube, squeezing with their effort limit; the cube hangs on.
    let q = engine.joint_positions(g).unwrap()[0];
    assert!(q > 0.024 && q < 0.028, "finger at {q}");
    let y = |l: usize| engine.link_pose(g, LinkId(l)).unwrap().translation.y;
    let gap = (y(1) - 0.005) - (y(2) + 0.005);
    assert!((gap - 0.04).abs() < 2e-3, "gap between the finger pads {gap}");
    let z0 = engine.object_pose(obj).unwrap().translation.z;
    assert!((z0 - start.translation.z).abs() < 2e-3, "cube slipped to {z0}");
    let contacts = engine.contacts();
    let squeeze = |link: usize| -> f64 {
        contacts
            .iter()
            .filter(|c| [c.body1, c.body2].contains(&ContactBody::Link { robot: g, link: LinkId(link) }))
            .map(|c| c.normal_force * c.normal.y.abs())
            .sum()
    };
    let (left, right) = (squeeze(1), squeeze(2));
    assert!((left - 10.0).abs() < 1.0 && (right - 10.0).abs() < 1.0, "squeeze {left} N / {right} N");

    // Shaking: friction holds up to 2 · μ · F = 2 · 0.65 · 10 N = 13 N (μ averaged with 0.8).
    engine.set_object_force(obj, Vector3::new(0.0, 0.0, -5.0), Vector3::zeros()).unwrap();
    engine.step_n(60, 1.0 / 240.0).unwrap();
    let z1 = engine.object_pose(obj).unwrap().translation.z;
    assert!((z1 - z0).abs() < 2e-3, "5 N pulled the cube from {z0} to {z1}");
    engine.set_object_force(obj, Vector3::new(0.0, 0.0, -30.0), Vector3::zeros()).unwrap();
    engine.step_n(60, 1.0 / 240.0).unwrap();
    let z2 = engine.object_pose(obj).unwrap().translation.z;
    assert!(z1 - z2 > 0.05, "30 N should pull the cube out: {z1} -> {z2}");
}

/// A single continuous joint about z carrying a 0.2 m bar (velocity limit from the options).
fn spinner() -> opengrasp_core::model::Robot {
    use opengrasp_core::model::{JointKind, JointSpec, Link, RobotBuilder};
    RobotBuilder::new("spinner")
        .link(Link::new("base"))
        .link(
            Link::new("bar")
                .with_shape(Shape::new(Isometry3::translation(0.1, 0.0, 0.0), Geometry::cuboid(0.2, 0.02, 0.02))),
        )
        .joint(JointSpec::new("spin", JointKind::Continuous, "base", "bar"))
        .build()
        .unwrap()
}

/// A continuous joint turned for several revolutions reports an unwrapped angle, and a
/// position target several turns away is reached the long way round.
fn continuous_joint_unwraps<E: PhysicsEngine>(tolerance: f64) {
    let mut scene = Scene::new("spin");
    let r = scene.add_robot("spinner", Arc::new(spinner()), Isometry3::identity()).unwrap();
    let options = PhysicsOptions { default_joint_velocity: 3.0, ..PhysicsOptions::default() };
    let mut engine = E::from_scene(&scene, &options).unwrap();
    engine.set_joint_velocity_targets(r, &[2.5]).unwrap();
    engine.step_n(240, 1.0 / 60.0).unwrap(); // 4 s at 2.5 rad/s: 10 rad, more than 1.5 turns
    let q = engine.joint_positions(r).unwrap()[0];
    assert!((q - 10.0).abs() < 0.05 + tolerance, "{}: q = {q}", engine.name());
    let bar = engine.link_pose(r, LinkId(1)).unwrap();
    assert!((bar.rotation.angle_to(&nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), q))) < 1e-6);
    engine.set_joint_position_targets(r, &[-3.0]).unwrap();
    engine.step_n(360, 1.0 / 60.0).unwrap(); // 13 rad at 3 rad/s: 4.3 s
    let q = engine.joint_positions(r).unwrap()[0];
    assert!((q + 3.0).abs() < tolerance, "{}: q = {q}", engine.name());
}

#[test]
fn continuous_joint_unwraps_mock() {
    continuous_joint_unwraps::<MockBackend>(1e-12);
}

#[cfg(feature = "rapier")]
#[test]
fn continuous_joint_unwraps_rapier() {
    continuous_joint_unwraps::<RapierBackend>(2e-3);
}

#[cfg(feature = "rapier")]
#[test]
fn self_collisions_follow_the_option() {
    // A 3-link planar arm folding link 2 back across link 0 (not adjacent: they collide only
    // when self-collisions are on).
    let mut scene = Scene::new("fold");
    let arm = scene.add_robot("arm", Arc::new(planar_arm(&[0.3, 0.3, 0.3]).unwrap()), Isometry3::identity()).unwrap();
    let target = [0.0, 2.6, 2.6];
    let run = |self_collisions: bool| {
        let options = PhysicsOptions { self_collisions, ..PhysicsOptions::default() };
        let mut engine = RapierBackend::from_scene(&scene, &options).unwrap();
        engine.set_joint_position_targets(arm, &target).unwrap();
        engine.step_n(120, 1.0 / 60.0).unwrap();
        let q = engine.joint_positions(arm).unwrap();
        let link_contacts = engine
            .contacts()
            .iter()
            .filter(|c| matches!((c.body1, c.body2), (ContactBody::Link { .. }, ContactBody::Link { .. })))
            .count();
        (q, link_contacts)
    };
    let (q_free, contacts_free) = run(false);
    assert!(q_free.iter().zip(&target).all(|(a, b)| (a - b).abs() < 2e-3), "{q_free:?}");
    assert_eq!(contacts_free, 0);
    let (q_blocked, contacts_blocked) = run(true);
    assert!((q_blocked[2] - target[2]).abs() > 0.1 || (q_blocked[1] - target[1]).abs() > 0.1, "{q_blocked:?}");
    assert!(contacts_blocked > 0);
}

#[cfg(feature = "rapier")]
#[test]
fn non_physical_inertia_is_rejected() {
    let (mut scene, _, _) = arm_scene();
    let bad = SceneObject {
        inertia: Matrix3::from_diagonal(&Vector3::new(1e-3, -1e-3, 1e-3)),
        ..SceneObject::new("bad", Isometry3::identity(), vec![Shape::at_origin(Geometry::Sphere { radius: 0.1 })], 1.0)
    };
    scene.add_object(bad).unwrap();
    let err = RapierBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap_err();
    assert!(matches!(err, CoreError::InvalidParameter { ref name, .. } if name == "inertia"), "{err}");
}

mod mock_properties {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

        /// The mock never exceeds the velocity limit, never leaves the joint limits, and lands
        /// exactly on a reachable target.
        #[test]
        fn mock_joints_are_velocity_limited_and_exact(
            t0 in -3.0f64..3.0, t1 in -3.0f64..3.0, dt in 0.001f64..0.05,
        ) {
            let (scene, arm, _) = arm_scene();
            let mut engine = MockBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
            engine.set_joint_position_targets(arm, &[t0, t1]).unwrap();
            let steps = (3.0 / 2.0 / dt).ceil() as usize + 1; // 3 rad at 2 rad/s
            let mut prev = engine.joint_positions(arm).unwrap();
            for _ in 0..steps {
                engine.step(dt).unwrap();
                let q = engine.joint_positions(arm).unwrap();
                for i in 0..2 {
                    prop_assert!((q[i] - prev[i]).abs() <= 2.0 * dt * (1.0 + 1e-12));
                    prop_assert!(q[i].abs() <= std::f64::consts::PI);
                }
                prev = q;
            }
            prop_assert_eq!(prev, vec![t0, t1]);
            prop_assert_eq!(engine.joint_velocities(arm).unwrap(), vec![0.0, 0.0]);
        }
    }
}

#[test]
fn clamped_object_stays_put_then_falls_from_rest_when_freed() {
    let (h, t): (f64, f64) = (2.0, 0.5);
    let scene = ball_scene(h);
    let dt = 1.0 / 240.0;
    let mut engine = RapierBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    engine.set_object_fixed(ObjectId(0), true).unwrap();
    engine.step_n((t / dt).round() as usize, dt).unwrap();
    // Clamped: gravity does not move it at all.
    assert_eq!(engine.object_pose(ObjectId(0)).unwrap(), scene.objects()[0].pose);
    assert_eq!(engine.object_velocity(ObjectId(0)).unwrap(), BodyVelocity::default());
    // Freed: it falls from rest, as a ball dropped at time zero (same bound as the free fall).
    engine.set_object_fixed(ObjectId(0), false).unwrap();
    engine.step_n((t / dt).round() as usize, dt).unwrap();
    let fallen = h - engine.object_pose(ObjectId(0)).unwrap().translation.vector.z;
    let analytic = 0.5 * G * t * t;
    assert!((fallen - analytic).abs() <= 0.5 * G * (dt / 8.0) * t + 1e-6, "fallen {fallen}, analytic {analytic}");
    // Bad handles are errors on both backends; the mock's free objects stay put anyway.
    assert!(matches!(engine.set_object_fixed(ObjectId(7), true), Err(CoreError::InvalidHandle { .. })));
    let mut mock = MockBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    mock.set_object_fixed(ObjectId(0), true).unwrap();
    assert!(matches!(mock.set_object_fixed(ObjectId(7), true), Err(CoreError::InvalidHandle { .. })));
}
