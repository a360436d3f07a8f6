//! The ARMAR-III-like humanoid: holonomic platform (as base joints), hip yaw, torso and head,
//! two 7-DoF arms and two ARMAR-III hands.
//!
//! World-aligned frame of the root link on the floor, x forward, z up. At the zero
//! configuration the robot stands at the origin with both arms hanging, palms facing the body
//! (collision-free with its allowed-collision pairs).

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use opengrasp_core::model::{Geometry, Inertial, JointKind, JointSpec, Link, Robot, RobotBuilder, Shape};

use crate::error::Result;
use crate::hands::{armar3_hand_parts, armar3_hand_spec, Drive, Hand, Parts};

/// Key dimensions of the humanoid (m); sources in the crate docs.
pub mod dims {
    /// Radius of the mobile platform's lower body.
    pub const PLATFORM_RADIUS: f64 = 0.35;
    /// Height of the platform's lower body top above the floor.
    pub const PLATFORM_TOP: f64 = 0.45;
    /// Ground clearance of the platform body (the wheels are not modelled).
    pub const GROUND_CLEARANCE: f64 = 0.02;
    /// Height of the hip yaw joint above the floor.
    pub const HIP_HEIGHT: f64 = 0.85;
    /// Shoulder height above the hip joint.
    pub const SHOULDER_ABOVE_HIP: f64 = 0.45;
    /// Lateral offset of each shoulder from the body's mid-plane.
    pub const SHOULDER_OFFSET: f64 = 0.24;
    /// Upper arm length (shoulder to elbow).
    pub const UPPER_ARM: f64 = 0.311;
    /// Forearm length (elbow to wrist).
    pub const FOREARM: f64 = 0.276;
    /// Distance from the last wrist joint to the hand's palm base.
    pub const WRIST_TO_HAND: f64 = 0.02;
}

/// The arm, hip and head drives of the humanoid.
const ARM: Drive = Drive { velocity: 1.0, effort: 60.0 };

fn capsule_down(name: &str, length: f64, radius: f64, mass: f64) -> Link {
    let origin = Isometry3::translation(0.0, 0.0, -length / 2.0);
    Link::new(name)
        .with_shape(Shape::new(origin, Geometry::Capsule { radius, length: length - 2.0 * radius }))
        .with_inertial(Inertial::solid_cylinder(mass, radius, length, origin))
}

fn ball(name: &str, radius: f64, mass: f64) -> Link {
    Link::new(name).with_shape(Shape::at_origin(Geometry::Sphere { radius })).with_inertial(Inertial::solid_sphere(
        mass,
        radius,
        Isometry3::identity(),
    ))
}

/// One arm plus its hand; `side` is `"right"` (y < 0) or `"left"` (y > 0).
fn arm_parts(side: &str) -> Parts {
    use dims::*;
    let s = if side == "right" { -1.0 } else { 1.0 };
    let n = |x: &str| format!("{side}_{x}");
    let mut p = Parts::default();
    p.links.push(ball(&n("shoulder_link"), 0.06, 1.5));
    p.links.push(Link::new(n("shoulder_link2")).with_inertial(Inertial::solid_sphere(
        0.5,
        0.04,
        Isometry3::identity(),
    )));
    p.links.push(capsule_down(&n("upper_arm"), UPPER_ARM, 0.045, 2.5));
    p.links.push(capsule_down(&n("forearm"), FOREARM, 0.04, 1.8));
    p.links.push(ball(&n("wrist_link1"), 0.035, 0.3));
    p.links.push(Link::new(n("wrist_link2")).with_inertial(Inertial::solid_sphere(0.1, 0.02, Isometry3::identity())));
    p.links.push(Link::new(n("wrist_link3")).with_inertial(Inertial::solid_sphere(0.1, 0.02, Isometry3::identity())));
    let shoulder = Isometry3::translation(0.0, s * SHOULDER_OFFSET, SHOULDER_ABOVE_HIP);
    let id = Isometry3::identity();
    p.joints.push(ARM.revolute(&n("shoulder_1"), "torso", &n("shoulder_link"), shoulder, Vector3::y(), (-3.0, 0.8)));
    p.joints.push(ARM.revolute(
        &n("shoulder_2"),
        &n("shoulder_link"),
        &n("shoulder_link2"),
        id,
        Vector3::x() * s,
        (-0.1, 1.6),
    ));
    p.joints.push(ARM.revolute(
        &n("shoulder_3"),
        &n("shoulder_link2"),
        &n("upper_arm"),
        id,
        Vector3::z() * s,
        (-1.6, 1.6),
    ));
    p.joints.push(ARM.revolute(
        &n("elbow"),
        &n("upper_arm"),
        &n("forearm"),
        Isometry3::translation(0.0, 0.0, -UPPER_ARM),
        -Vector3::y(),
        (0.0, 2.4),
    ));
    p.joints.push(ARM.revolute(
        &n("wrist_1"),
        &n("forearm"),
        &n("wrist_link1"),
        Isometry3::translation(0.0, 0.0, -FOREARM),
        Vector3::z() * s,
        (-1.6, 1.6),
    ));
    p.joints.push(ARM.revolute(&n("wrist_2"), &n("wrist_link1"), &n("wrist_link2"), id, Vector3::x() * s, (-0.6, 0.6)));
    p.joints.push(ARM.revolute(&n("wrist_3"), &n("wrist_link2"), &n("wrist_link3"), id, -Vector3::y(), (-0.9, 0.9)));
    // Hand: fingers pointing down the arm, palm facing the body, thumb forward.
    let r = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[
        Vector3::new(0.0, -s, 0.0),
        Vector3::new(-s, 0.0, 0.0),
        Vector3::new(0.0, 0.0, -1.0),
    ]));
    let mount =
        Isometry3::from_parts(Translation3::new(0.0, 0.0, -WRIST_TO_HAND), UnitQuaternion::from_rotation_matrix(&r));
    let hand_prefix = format!("{side}_hand_");
    let palm = format!("{hand_prefix}palm");
    p.joints.push(JointSpec::new(n("hand_mount"), JointKind::Fixed, n("wrist_link3"), &palm).origin(mount));
    let hand = armar3_hand_parts(&hand_prefix, -s);
    p.links.extend(hand.links);
    p.joints.extend(hand.joints);
    p.allowed.extend(hand.allowed);
    for (a, b) in [
        ("torso", n("shoulder_link")),
        ("torso", n("shoulder_link2")),
        ("torso", n("upper_arm")),
        (&n("shoulder_link"), n("upper_arm")),
        (&n("forearm"), n("wrist_link2")),
        (&n("forearm"), n("wrist_link3")),
        (&n("forearm"), palm.clone()),
        (&n("wrist_link1"), palm.clone()),
        (&n("wrist_link1"), n("wrist_link3")),
        (&n("wrist_link2"), palm.clone()),
        (&n("wrist_link1"), format!("{hand_prefix}thumb_base")),
    ] {
        p.allowed.push((a.to_string(), b));
    }
    p
}

/// The ARMAR-III-like humanoid (34 DoF: 3 base, hip yaw, 2 × 7 arm, 2 × 8 hand).
///
/// Joint groups: `right_arm` (7), `left_arm` (7), `hip_right_arm` (hip yaw + right arm),
/// `base_hip_right_arm` (base x, y, yaw + hip yaw + right arm), `right_hand`, `left_hand` (8).
/// The right hand is [`armar3_right_hand`]; its tool link is `right_hand_palm`.
///
/// Built from fixed data validated by the crate's tests, so it does not fail at run time.
pub fn armar3() -> Robot {
    build_armar3().expect("stock ARMAR-III model is valid")
}

fn build_armar3() -> Result<Robot> {
    use dims::*;
    let platform_h = PLATFORM_TOP - GROUND_CLEARANCE;
    let column_h = HIP_HEIGHT - PLATFORM_TOP;
    let platform = Link::new("platform")
        .with_shape(Shape::new(
            Isometry3::translation(0.0, 0.0, GROUND_CLEARANCE + platform_h / 2.0),
            Geometry::Cylinder { radius: PLATFORM_RADIUS, length: platform_h },
        ))
        .with_shape(Shape::new(
            Isometry3::translation(0.0, 0.0, PLATFORM_TOP + column_h / 2.0),
            Geometry::Cylinder { radius: 0.15, length: column_h },
        ))
        .with_inertial(Inertial::solid_cylinder(
            70.0,
            PLATFORM_RADIUS,
            platform_h,
            Isometry3::translation(0.0, 0.0, GROUND_CLEARANCE + platform_h / 2.0),
        ));
    let torso_box = Isometry3::translation(0.0, 0.0, 0.28);
    let torso = Link::new("torso")
        .with_shape(Shape::new(torso_box, Geometry::cuboid(0.24, 0.32, 0.50)))
        .with_shape(Shape::new(
            Isometry3::translation(0.0, 0.0, 0.58),
            Geometry::Cylinder { radius: 0.04, length: 0.10 },
        ))
        .with_shape(Shape::new(Isometry3::translation(0.0, 0.0, 0.73), Geometry::Sphere { radius: 0.10 }))
        .with_inertial(Inertial::solid_box(20.0, Vector3::new(0.24, 0.32, 0.5), torso_box));
    let big = 10.0;
    let mut b = RobotBuilder::new("armar3")
        .link(Link::new("base_footprint"))
        .link(Link::new("base_x_link").with_inertial(Inertial::solid_sphere(0.1, 0.05, Isometry3::identity())))
        .link(Link::new("base_y_link").with_inertial(Inertial::solid_sphere(0.1, 0.05, Isometry3::identity())))
        .link(platform)
        .link(torso)
        .joint(
            JointSpec::new("base_x", JointKind::Prismatic, "base_footprint", "base_x_link")
                .axis(Vector3::x())
                .limits(-big, big, 1.0, 500.0),
        )
        .joint(
            JointSpec::new("base_y", JointKind::Prismatic, "base_x_link", "base_y_link")
                .axis(Vector3::y())
                .limits(-big, big, 1.0, 500.0),
        )
        .joint(
            JointSpec::new("base_yaw", JointKind::Revolute, "base_y_link", "platform")
                .axis(Vector3::z())
                .limits(-PI, PI, 1.0, 200.0),
        )
        .joint(ARM.revolute(
            "hip_yaw",
            "platform",
            "torso",
            Isometry3::translation(0.0, 0.0, HIP_HEIGHT),
            Vector3::z(),
            (-FRAC_PI_2, FRAC_PI_2),
        ));
    // Right arm first so its joints come first in the configuration after the hip.
    b = arm_parts("right").add_to(b);
    b = arm_parts("left").add_to(b);
    let mut robot = b.build()?;
    let arm = |side: &str| -> Vec<String> {
        ["shoulder_1", "shoulder_2", "shoulder_3", "elbow", "wrist_1", "wrist_2", "wrist_3"]
            .iter()
            .map(|j| format!("{side}_{j}"))
            .collect()
    };
    let hand = |side: &str| -> Vec<String> {
        ["thumb_opposition", "thumb_j1", "thumb_j2", "index_j1", "index_j2", "middle_j1", "middle_j2", "ring_j1"]
            .iter()
            .map(|j| format!("{side}_hand_{j}"))
            .collect()
    };
    let refs = |v: &[String]| -> Vec<String> { v.to_vec() };
    let right = arm("right");
    let groups: Vec<(&str, Vec<String>)> = vec![
        ("right_arm", refs(&right)),
        ("left_arm", arm("left")),
        ("hip_right_arm", std::iter::once("hip_yaw".to_string()).chain(right.iter().cloned()).collect()),
        (
            "base_hip_right_arm",
            ["base_x", "base_y", "base_yaw", "hip_yaw"]
                .iter()
                .map(|s| s.to_string())
                .chain(right.iter().cloned())
                .collect(),
        ),
        ("right_hand", hand("right")),
        ("left_hand", hand("left")),
    ];
    for (name, joints) in groups {
        let js: Vec<&str> = joints.iter().map(String::as_str).collect();
        robot.add_group(name, &js)?;
    }
    Ok(robot)
}

/// The right ARMAR-III hand of a humanoid built by [`armar3`] (or any robot using the same
/// `right_hand_` link names), as a [`Hand`] mounted on the arm.
///
/// # Errors
/// [`crate::AssetError::Core`] if the robot lacks the hand's links or joints.
pub fn armar3_right_hand(robot: impl Into<std::sync::Arc<Robot>>) -> Result<Hand> {
    Ok(Hand::from_robot(robot, armar3_hand_spec("right_hand_"))?)
}
