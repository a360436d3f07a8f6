//! The robot model: links, joints, geometry and joint groups.

mod geometry;
mod group;
mod parts;
mod robot;
pub mod samples;

pub use geometry::{Geometry, Shape, TriangleMesh};
pub use group::JointGroup;
pub use parts::{Inertial, Joint, JointId, JointKind, JointLimits, JointSpec, Link, LinkId, Mimic};
pub use robot::{Robot, RobotBuilder};
