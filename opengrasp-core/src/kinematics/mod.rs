//! Kinematics: forward kinematics, Jacobians and inverse kinematics.

mod fk;

pub use fk::{forward_kinematics, forward_kinematics_into, link_pose, link_pose_unchecked, LinkPoses};
