//! Loading robots from URDF and writing them back.
//!
//! - [`load_file`] reads a `.urdf` file, finding meshes next to it or by `package://` URI, as
//!   ROS does: packages are found by their `package.xml` name among the file's own package,
//!   its sibling packages and `ROS_PACKAGE_PATH` / `AMENT_PREFIX_PATH` (see [`FileResolver`]);
//!   [`load_file_with`] takes [`LoadOptions`] (skip visuals, explicit packages and search
//!   roots, [`XmlLimits`]) and returns the load's [`LoadWarning`]s;
//! - [`from_str`] / [`from_str_with`] parse URDF text with any [`MeshResolver`] —
//!   [`FileResolver`] (base directory, packages, search roots) or [`InMemoryResolver`] (assets
//!   shipped in memory);
//! - [`to_urdf_string`] / [`export`] write a [`Robot`] as URDF plus mesh files, such that loading
//!   the result gives the same model back.
//!
//! [`Robot`]: crate::model::Robot
//!
//! Parsing uses `urdf-rs`; the robot is assembled with [`crate::model::RobotBuilder`], so URDF
//! robots are validated exactly like robots built in code. Meshes are read by
//! [`crate::mesh_io`] (`.stl`, `.obj` and `.dae`).
//!
//! # Conventions and limits
//! - `<origin rpy>` is fixed-axis roll-pitch-yaw (`R = Rz(yaw) Ry(pitch) Rx(roll)`).
//! - `floating`, `planar` and `spherical` joints are rejected with
//!   [`CoreError::MalformedUrdf`](crate::CoreError::MalformedUrdf): the model has only fixed,
//!   revolute, continuous and prismatic joints. Give a mobile base its own pose in the scene.
//! - A mimic joint naming a joint that does not exist is
//!   [`CoreError::UnknownJoint`](crate::CoreError::UnknownJoint); a `<mimic>` on a fixed joint,
//!   or naming one, is ignored with [`LoadWarning::MimicIgnored`] (MoveIt ignores it too).
//! - Visuals never fail a robot: one that cannot be loaded is left out with
//!   [`LoadWarning::VisualNotLoaded`]; collision geometry errors fail the load.
//! - Hostile text: size, nesting depth and element count are checked ([`XmlLimits`]) before
//!   urdf-rs sees the text, giving [`CoreError::LimitExceeded`](crate::CoreError::LimitExceeded).
//! - Unknown elements (`<gazebo>`, `<transmission>`, `<ros2_control>`, ...) are ignored.
//! - Capsules are read from and written as `<capsule radius length>` (`length` between the
//!   hemisphere centres, along z), which urdf-rs supports; ROS urdfdom does not read them.
//! - Meshes: `.stl`, `.obj` and COLLADA `.dae` ([`crate::mesh_io::read_mesh`]); `scale` is
//!   applied at load time (faces it makes degenerate, such as mm → m slivers, are dropped)
//!   and exported meshes are written already scaled, in STL or OBJ. Binary STL export rounds
//!   vertices to `f32`; choose [`crate::mesh_io::MeshFormat::Obj`] in [`ExportOptions`] for
//!   exact meshes.
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
