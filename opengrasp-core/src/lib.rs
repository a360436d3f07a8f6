//! # opengrasp-core
//!
//! The machinery every OpenGRASP-rs benchmark stands on, with no knowledge of grasping or
//! planning: robot models ([`model`]) built in code or loaded from URDF ([`urdf`]) with joint
//! groups and allowed collisions from SRDF ([`srdf`]), forward and
//! inverse kinematics ([`kinematics`]), scenes ([`scene`]), collision, distance and contact
//! queries on parry3d ([`collision`]), the [`physics::PhysicsEngine`] trait with a rapier
//! backend and a deterministic mock, and the plain model types users describe their own hands
//! ([`hand::Hand`]: a robot plus a [`hand::HandSpec`]) and objects ([`object::ObjectModel`]:
//! a mesh plus mass and friction) with.
//!
//! All quantities are `f64` in SI units (metres, radians, newtons, seconds); poses are
//! `nalgebra::Isometry3<f64>`. Boxes: [`model::Geometry::Box`] stores half extents; every
//! constructor taking a box size ([`model::Geometry::cuboid`], [`model::Shape::cuboid`], URDF
//! `<box size>`) takes the full size.

#![forbid(unsafe_code)]

/// The version of this crate (recorded in results files' provenance).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

pub mod collision;
pub mod error;
pub mod hand;
pub mod kinematics;
pub mod mesh_io;
pub mod model;
pub mod object;
pub mod physics;
pub mod scene;
pub mod spec_file;
pub mod srdf;
pub mod urdf;

pub use error::{CoreError, Result};
pub use nalgebra;

/// A readable `'static` name for a type, the default name of planners: the last path segment
/// of a plain type (`RrtConnect` for `opengrasp_motion::planners::RrtConnect`), and the full
/// [`std::any::type_name`] of a generic one, whose arguments a single segment would cut
/// (`my_lab::Timed<opengrasp_motion::planners::RrtConnect>`, not `RrtConnect>`).
///
/// ```
/// struct Wrapper<T>(T);
/// assert_eq!(opengrasp_core::short_type_name::<String>(), "String");
/// assert!(opengrasp_core::short_type_name::<Wrapper<String>>().ends_with("Wrapper<alloc::string::String>"));
/// ```
pub fn short_type_name<T: ?Sized>() -> &'static str {
    let full = std::any::type_name::<T>();
    if full.contains(['<', '(', '[', '&', ' ']) {
        full
    } else {
        full.rsplit("::").next().unwrap_or(full)
    }
}
