//! Loading robots from URDF and writing them back.
//!
//! - [`load_file`] reads a `.urdf` file, finding meshes next to it or by `package://` URI;
//! - [`from_str`] parses URDF text with any [`MeshResolver`] — [`FileResolver`] (base directory
//!   plus package map) or [`InMemoryResolver`] (assets shipped in memory);
//! - [`to_urdf_string`] / [`export`] write a [`Robot`] as URDF plus mesh files, such that loading
//!   the result gives the same model back.
//!
//! [`Robot`]: crate::model::Robot
//!
//! Parsing uses `urdf-rs`; the robot is assembled with [`crate::model::RobotBuilder`], so URDF
//! robots are validated exactly like robots built in code. Meshes are read by
//! [`crate::mesh_io`] (`.stl` and `.obj`).
//!
//! # Conventions and limits
//! - `<origin rpy>` is fixed-axis roll-pitch-yaw (`R = Rz(yaw) Ry(pitch) Rx(roll)`).
//! - `floating`, `planar` and `spherical` joints are rejected with
//!   [`CoreError::MalformedUrdf`](crate::CoreError::MalformedUrdf): the model has only fixed,
//!   revolute, continuous and prismatic joints. Give a mobile base its own pose in the scene.
//! - A mimic joint naming a joint that does not exist is
//!   [`CoreError::UnknownJoint`](crate::CoreError::UnknownJoint).
//! - Capsules are read from and written as `<capsule radius length>` (`length` between the
//!   hemisphere centres, along z), which urdf-rs supports; ROS urdfdom does not read them.
//! - Meshes: `.stl` and `.obj` only (a `.dae` visual is a
//!   [`CoreError::MeshFormat`](crate::CoreError::MeshFormat) error); `scale` is applied at load
//!   time and exported meshes are written already scaled. Binary STL export rounds vertices to
//!   `f32`; choose [`crate::mesh_io::MeshFormat::Obj`] in [`ExportOptions`] for exact meshes.
//! - Not represented in URDF, so not exported: joint groups and explicitly allowed collision
//!   pairs (written and read as SRDF by [`crate::srdf`]), velocity/effort limits of continuous
//!   joints, materials.
//!
//! ```
//! use opengrasp_core::urdf::{self, InMemoryResolver};
//!
//! # fn main() -> opengrasp_core::Result<()> {
//! let text = r#"<robot name="pendulum">
//!   <link name="base"/>
//!   <link name="bob"><visual><geometry><sphere radius="0.05"/></geometry></visual></link>
//!   <joint name="swing" type="revolute">
//!     <parent link="base"/><child link="bob"/>
//!     <origin xyz="0 0 1"/><axis xyz="0 1 0"/>
//!     <limit lower="-1.5" upper="1.5" effort="10" velocity="2"/>
//!   </joint>
//! </robot>"#;
//! let robot = urdf::from_str(text, &InMemoryResolver::new())?;
//! assert_eq!(robot.dof(), 1);
//! assert_eq!(robot.dof_limits(0), (-1.5, 1.5));
//!
//! let doc = urdf::to_urdf_string(&robot, &urdf::ExportOptions::default());
//! let again = urdf::from_str(&doc.urdf, &doc.resolver())?;
//! assert_eq!(again.joints(), robot.joints());
//! # Ok(())
//! # }
//! ```

mod limits;
mod options;
mod reader;
mod resolver;
mod writer;

pub(crate) use limits::check_xml;
pub use limits::XmlLimits;
pub use options::{LoadOptions, LoadWarning, LoadedRobot, Visuals};
pub use reader::{file_resolver, from_str, from_str_with, from_urdf_rs, from_urdf_rs_with, load_file, load_file_with};
pub use resolver::{FileResolver, InMemoryResolver, MeshResolver, MAX_CRAWL_DEPTH};
pub(crate) use writer::write_atomically;
pub use writer::{export, export_with, to_urdf_string, ExportOptions, UrdfDocument};

/// The URDF parser used here, re-exported for [`from_urdf_rs`] and `TryFrom<&urdf_rs::Robot>`.
pub use urdf_rs;
