//! Forward kinematics: the pose of every link in one pass over the tree.

use std::ops::Index;

use nalgebra::Isometry3;

use crate::error::Result;
use crate::model::{LinkId, Robot};

/// Poses of all links in the robot's root frame, indexed by [`LinkId`].
#[derive(Clone, Debug, PartialEq)]
pub struct LinkPoses(pub Vec<Isometry3<f64>>);

impl Index<LinkId> for LinkPoses {
    type Output = Isometry3<f64>;
    fn index(&self, id: LinkId) -> &Isometry3<f64> {
        &self.0[id.0]
    }
}

impl LinkPoses {
    /// The poses as a slice indexed by `LinkId.0`.
    pub fn as_slice(&self) -> &[Isometry3<f64>] {
        &self.0
    }
}

/// Poses of all links for configuration `q`, in the robot's root frame.
///
/// # Errors
/// [`crate::CoreError::DimensionMismatch`], [`crate::CoreError::NonFiniteJointValue`] or
/// [`crate::CoreError::JointOutOfLimits`] if `q` is not a valid configuration.
pub fn forward_kinematics(robot: &Robot, q: &[f64]) -> Result<LinkPoses> {
    robot.validate_configuration(q)?;
    let mut poses = Vec::new();
    forward_kinematics_into(robot, q, &mut poses);
    Ok(LinkPoses(poses))
}

/// Forward kinematics without validation, reusing `poses` (resized to the link count).
///
/// For hot loops (planners, collision checking) where `q` is known to have
/// [`Robot::dof`] finite entries; values are not checked against limits.
///
/// # Panics
/// If `q` is shorter than [`Robot::dof`].
pub fn forward_kinematics_into(robot: &Robot, q: &[f64], poses: &mut Vec<Isometry3<f64>>) {
    poses.clear();
    poses.resize(robot.links().len(), Isometry3::identity());
    for &j in robot.joints_topological() {
        let joint = robot.joint(j);
        let value = robot.joint_position(q, j);
        poses[joint.child.0] = poses[joint.parent.0] * joint.origin * joint.motion(value);
    }
}

/// Pose of one link in the robot's root frame (walks only the chain to that link).
///
/// # Errors
/// As [`forward_kinematics`].
pub fn link_pose(robot: &Robot, q: &[f64], link: LinkId) -> Result<Isometry3<f64>> {
    robot.validate_configuration(q)?;
    Ok(link_pose_unchecked(robot, q, link))
}

/// [`link_pose`] without validation.
pub fn link_pose_unchecked(robot: &Robot, q: &[f64], link: LinkId) -> Isometry3<f64> {
    robot.chain_to(link).into_iter().fold(Isometry3::identity(), |acc, j| {
        let joint = robot.joint(j);
        acc * joint.origin * joint.motion(robot.joint_position(q, j))
    })
}
