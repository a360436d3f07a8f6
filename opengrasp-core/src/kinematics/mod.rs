//! Kinematics: forward kinematics, Jacobians and inverse kinematics.

mod fk;
mod ik;
mod jacobian;

pub use fk::{forward_kinematics, forward_kinematics_into, link_pose, link_pose_unchecked, LinkPoses};
pub use ik::{solve_ik, IkOptions, IkSolution, IkStatus};
pub use jacobian::{jacobian, jacobian_into};
