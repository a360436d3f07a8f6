//! The robot model: links, joints, geometry and joint groups.

mod geometry;
mod group;
mod robot;
pub mod samples;

pub use geometry::{Geometry, Shape, TriangleMesh};
pub use group::JointGroup;
pub use robot::{
    Inertial, Joint, JointId, JointKind, JointLimits, JointSpec, Link, LinkId, Mimic, Robot, RobotBuilder,
};
