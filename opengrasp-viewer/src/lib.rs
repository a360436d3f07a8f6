//! # opengrasp-viewer
//!
//! See what happened in an OpenGRASP benchmark: scenes, motion runs and grasps as pictures.
//!
//! - [`raster`]: a headless software rasteriser (z-buffer, flat Lambert shading, orthographic
//!   or perspective camera) writing PNG — no GPU, no display;
//! - [`drawing`]: what to draw ([`Drawing`]: coloured world meshes from
//!   [`opengrasp_assets::export::scene_meshes`], polylines, dots), shared by the PNG
//!   renderer and the rerun logger;
//! - [`world`]: the motion benchmark's scenes rebuilt by name, with their geometry;
//! - [`replay`]: a motion run planned again from its record (the results keep figures, not
//!   paths), checked against the record; [`motion`]: its states, end-effector path, invalid
//!   states and colliding pairs, as a drawing;
//! - [`grasp`]: a recorded grasp evaluated again: hand in its final pose coloured by force
//!   closure, contacts and friction cones;
//! - [`snapshot`]: the PNG snapshots of a results file that `opengrasp report --plots` embeds;
//! - `record` (feature `rerun`, Rust 1.95): all of it logged to a rerun recording (`.rrd`),
//!   motion runs as trajectories on scrubbable timelines, tactile frames as images.
//!
//! # Example
//!
//! A 1 m cube seen from above, orthographically: it covers exactly its projected square.
//!
//! ```
//! use opengrasp_core::model::{Geometry, Shape};
//! use opengrasp_core::nalgebra::{Isometry3, Point3, Vector3};
//! use opengrasp_core::scene::{Scene, StaticBody};
//! use opengrasp_viewer::drawing::{Drawing, Kind};
//! use opengrasp_viewer::raster::{Camera, Projection};
//!
//! # fn main() -> opengrasp_viewer::Result<()> {
//! let mut scene = Scene::new("one box");
//! let cube = Shape::at_origin(Geometry::Box { half_extents: Vector3::new(0.5, 0.5, 0.5) });
//! scene.add_body(StaticBody::new("cube", Isometry3::identity(), vec![cube]))?;
//! let mut drawing = Drawing::new();
//! drawing.add_scene(&scene, Kind::Robot)?;
//! // 100 × 100 pixels showing 2 m × 2 m: the cube covers pixels 25..75 in x and y.
//! let top = Projection::Orthographic { half_height: 1.0 };
//! let camera = Camera::look_at(Point3::new(0.0, 0.0, 5.0), Point3::origin(), Vector3::y(), top, 100, 100)?;
//! let canvas = drawing.render(camera);
//! assert_ne!(canvas.pixel(50, 50), Some([255, 255, 255]));
//! assert_eq!(canvas.pixel(20, 50), Some([255, 255, 255]));
//! std::fs::write(std::env::temp_dir().join("cube.png"), canvas.to_png()?).ok();
//! # Ok(())
//! # }
//! ```

pub mod drawing;
pub mod error;
pub mod grasp;
pub mod motion;
pub mod raster;
#[cfg(feature = "rerun")]
pub mod record;
pub mod replay;
pub mod snapshot;
pub mod world;

pub use drawing::Drawing;
pub use error::{Result, ViewerError};
