//! Small robots built in code, for examples, tests and benchmarks.

use std::f64::consts::PI;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::{Geometry, Inertial, JointKind, JointSpec, Link, Robot, RobotBuilder, Shape};
use crate::error::Result;

/// A capsule along local z from `z = 0` to `z = length`.
fn capsule_link(name: &str, radius: f64, length: f64, mass: f64) -> Link {
    let origin = Isometry3::translation(0.0, 0.0, length * 0.5);
    Link::new(name)
        .with_shape(Shape::new(origin, Geometry::Capsule { radius, length }))
        .with_inertial(Inertial::solid_cylinder(mass, radius, length, origin))
}

/// A planar arm: revolute joints about z, link `i` of length `lengths[i]` along its local x.
///
/// Joint `joint{i}` has limits ±π; the end effector is the fixed link `tool` at the tip.
/// With joint values θ the tool sits at `Σ lᵢ (cos Σθ, sin Σθ)` (closed form for tests).
///
/// # Errors
/// [`crate::CoreError::InvalidModel`] if `lengths` is empty, or invalid geometry for
/// non-positive lengths.
pub fn planar_arm(lengths: &[f64]) -> Result<Robot> {
    let mut b = RobotBuilder::new("planar_arm").link(Link::new("base"));
    let mut parent = "base".to_string();
    let mut offset = 0.0;
    for (i, &l) in lengths.iter().enumerate() {
        let name = format!("link{i}");
        let shape = Shape::new(Isometry3::translation(l * 0.5, 0.0, 0.0), Geometry::cuboid(l, 0.04, 0.04));
        b = b.link(Link::new(&name).with_shape(shape));
        b = b.joint(
            JointSpec::new(format!("joint{i}"), JointKind::Revolute, &parent, &name)
                .origin(Isometry3::translation(offset, 0.0, 0.0))
                .axis(Vector3::z())
                .limits(-PI, PI, 2.0, 10.0),
        );
        parent = name;
        offset = l;
    }
    if lengths.is_empty() {
        return Err(crate::CoreError::InvalidModel { reason: "planar arm needs at least one link".into() });
    }
    b.link(Link::new("tool"))
        .joint(
            JointSpec::new("tool_joint", JointKind::Fixed, &parent, "tool")
                .origin(Isometry3::translation(offset, 0.0, 0.0)),
        )
        .build()
}

/// A serial chain of `n` revolute joints alternating about z and y, links 0.1 m long, limits
/// ±2.9 rad; tip link `tool`. Used to benchmark kinematics on long chains.
///
/// # Errors
/// [`crate::CoreError::InvalidModel`] if `n == 0`.
pub fn serial_chain(n: usize) -> Result<Robot> {
    if n == 0 {
        return Err(crate::CoreError::InvalidModel { reason: "serial chain needs at least one joint".into() });
    }
    let mut b = RobotBuilder::new(format!("chain{n}")).link(Link::new("base"));
    let mut parent = "base".to_string();
    for i in 0..n {
        let name = format!("link{i}");
        b = b.link(capsule_link(&name, 0.02, 0.1, 0.5));
        let axis = if i % 2 == 0 { Vector3::z() } else { Vector3::y() };
        let z = if i == 0 { 0.0 } else { 0.1 };
        b = b.joint(
            JointSpec::new(format!("joint{i}"), JointKind::Revolute, &parent, &name)
                .origin(Isometry3::translation(0.0, 0.0, z))
                .axis(axis)
                .limits(-2.9, 2.9, 2.0, 10.0),
        );
        parent = name;
    }
    b.link(Link::new("tool"))
        .joint(
            JointSpec::new("tool_joint", JointKind::Fixed, &parent, "tool")
                .origin(Isometry3::translation(0.0, 0.0, 0.1)),
        )
        .build()
}

/// A 7-DoF anthropomorphic arm (shoulder z-y-z, elbow y, wrist z-y-z, KUKA-LWR-like
/// proportions: 0.31 m base column, 0.40 m upper arm, 0.39 m forearm, 0.08 m flange) with
/// capsule collision links and a box "hand" on the tool frame. Joint group `arm` holds all
/// seven joints; the end-effector link is `tool`. Collisions between `link5` and `link7`
/// (which always overlap across the short `link6`) are allowed.
///
/// # Errors
/// Never in practice (the model is fixed); the `Result` comes from [`RobotBuilder::build`].
pub fn seven_dof_arm() -> Result<Robot> {
    let axes = [Vector3::z(), Vector3::y(), Vector3::z(), Vector3::y(), Vector3::z(), Vector3::y(), Vector3::z()];
    let limits = [2.96, 2.09, 2.96, 2.09, 2.96, 2.09, 3.05];
    let mut b = RobotBuilder::new("seven_dof_arm").link(Link::new("base").with_shape(Shape::new(
        Isometry3::translation(0.0, 0.0, 0.1),
        Geometry::Cylinder { radius: 0.08, length: 0.2 },
    )));
    let mut parent = "base".to_string();
    let mut prev_len = 0.0;
    for i in 0..7 {
        let name = format!("link{}", i + 1);
        let len = match i {
            0 => 0.31 - 0.2,
            1 => 0.2,
            2 => 0.2,
            3 => 0.2,
            4 => 0.19,
            5 => 0.1,
            _ => 0.08,
        };
        b = b.link(capsule_link(&name, 0.06, len, 2.0));
        let z = if i == 0 { 0.2 } else { prev_len };
        b = b.joint(
            JointSpec::new(format!("joint{}", i + 1), JointKind::Revolute, &parent, &name)
                .origin(Isometry3::translation(0.0, 0.0, z))
                .axis(axes[i])
                .limits(-limits[i], limits[i], 1.5, 100.0),
        );
        parent = name;
        prev_len = len;
    }
    let hand = Link::new("tool")
        .with_shape(Shape::new(Isometry3::translation(0.0, 0.0, 0.05), Geometry::cuboid(0.08, 0.12, 0.06)));
    let flange = Isometry3::from_parts(Translation3::new(0.0, 0.0, prev_len), UnitQuaternion::identity());
    let mut robot =
        b.link(hand).joint(JointSpec::new("tool_joint", JointKind::Fixed, &parent, "tool").origin(flange)).build()?;
    robot.add_group("arm", &["joint1", "joint2", "joint3", "joint4", "joint5", "joint6", "joint7"])?;
    // The 0.1 m link6 is shorter than two capsule radii: link5 and link7 overlap in every
    // configuration, so the pair is disabled as an SRDF would.
    robot.allow_collision("link5", "link7")?;
    Ok(robot)
}

/// A parallel-jaw gripper: a 4 × 16 × 2 cm palm (link `palm`, top face at z = 0) and two
/// 1 × 2 × 6 cm fingers standing on it along +z, sliding along ±y on the prismatic joints
/// `left_joint` (actuated) and `right_joint` (mimics it). The joint value is each finger's
/// distance from the centre plane (0 closed .. `max_opening / 2`), so the jaws are `2 q` apart.
///
/// # Errors
/// [`crate::CoreError::InvalidGeometry`] for a non-finite or non-positive `max_opening`.
pub fn parallel_gripper(max_opening: f64) -> Result<Robot> {
    if !(max_opening.is_finite() && max_opening > 0.0) {
        return Err(crate::CoreError::InvalidGeometry { reason: format!("max_opening {max_opening} must be > 0") });
    }
    let (t, w, h) = (0.01, 0.02, 0.06);
    let palm_origin = Isometry3::translation(0.0, 0.0, -0.01);
    let palm = Link::new("palm")
        .with_shape(Shape::new(palm_origin, Geometry::cuboid(0.04, 0.16, 0.02)))
        .with_inertial(Inertial::solid_box(0.2, Vector3::new(0.04, 0.16, 0.02), palm_origin));
    let finger =
        |name: &str, side: f64| {
            let origin = Isometry3::translation(0.0, side * t / 2.0, h / 2.0);
            Link::new(name)
                .with_shape(Shape::new(origin, Geometry::cuboid(w, t, h)))
                .with_inertial(Inertial::solid_box(0.03, Vector3::new(w, t, h), origin))
        };
    RobotBuilder::new("parallel_gripper")
        .link(palm)
        .link(finger("left_finger", 1.0))
        .link(finger("right_finger", -1.0))
        .joint(JointSpec::new("left_joint", JointKind::Prismatic, "palm", "left_finger").axis(Vector3::y()).limits(
            0.0,
            max_opening / 2.0,
            0.1,
            20.0,
        ))
        .joint(
            JointSpec::new("right_joint", JointKind::Prismatic, "palm", "right_finger")
                .axis(-Vector3::y())
                .limits(0.0, max_opening / 2.0, 0.1, 20.0)
                .mimic("left_joint", 1.0, 0.0),
        )
        .build()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::forward_kinematics;

    #[test]
    fn planar_arm_matches_closed_form() {
        let (l1, l2) = (0.7, 0.4);
        let robot = planar_arm(&[l1, l2]).unwrap();
        let tool = robot.link_id("tool").unwrap();
        for &(a, b) in &[(0.0, 0.0), (0.3, -1.1), (PI / 2.0, PI / 2.0), (-2.5, 3.0)] {
            let poses = forward_kinematics(&robot, &[a, b]).unwrap();
            let p = poses[tool].translation.vector;
            let x = l1 * f64::cos(a) + l2 * f64::cos(a + b);
            let y = l1 * f64::sin(a) + l2 * f64::sin(a + b);
            assert!((p - Vector3::new(x, y, 0.0)).norm() < 1e-12, "{a} {b}: {p:?}");
            let yaw = poses[tool].rotation.euler_angles().2;
            let expected = (a + b + PI).rem_euclid(2.0 * PI) - PI;
            assert!((yaw - expected).abs() < 1e-9 || ((yaw - expected).abs() - 2.0 * PI).abs() < 1e-9);
        }
    }

    #[test]
    fn seven_dof_arm_is_straight_up_at_zero() {
        let robot = seven_dof_arm().unwrap();
        assert_eq!(robot.dof(), 7);
        let poses = forward_kinematics(&robot, &[0.0; 7]).unwrap();
        let tool = poses[robot.link_id("tool").unwrap()].translation.vector;
        // 0.2 base column + link lengths 0.11 + 0.2 * 3 + 0.19 + 0.1 + 0.08
        assert!((tool - Vector3::new(0.0, 0.0, 0.2 + 0.11 + 0.6 + 0.19 + 0.1 + 0.08)).norm() < 1e-12);
        assert!(matches!(
            forward_kinematics(&robot, &[0.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
            Err(crate::CoreError::JointOutOfLimits { .. })
        ));
        assert!(matches!(
            forward_kinematics(&robot, &[f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
            Err(crate::CoreError::NonFiniteJointValue { .. })
        ));
        assert!(matches!(forward_kinematics(&robot, &[0.0; 6]), Err(crate::CoreError::DimensionMismatch { .. })));
    }

    #[test]
    fn parallel_gripper_jaws_are_twice_the_joint_value_apart() {
        let robot = parallel_gripper(0.1).unwrap();
        assert_eq!(robot.dof(), 1);
        let poses = forward_kinematics(&robot, &[0.03]).unwrap();
        let left = poses[robot.link_id("left_finger").unwrap()].translation.y;
        let right = poses[robot.link_id("right_finger").unwrap()].translation.y;
        assert!((left - 0.03).abs() < 1e-12 && (right + 0.03).abs() < 1e-12);
        assert!(parallel_gripper(f64::NAN).is_err());
    }

    #[test]
    fn serial_chain_has_n_dofs() {
        assert_eq!(serial_chain(10).unwrap().dof(), 10);
        assert!(serial_chain(0).is_err());
    }
}
