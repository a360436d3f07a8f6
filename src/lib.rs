//! # OpenGRASP-rs
//!
//! Reproducible benchmarking of robot grasp and motion planners, after the OpenGRASP
//! benchmarking suite (Ulbrich et al. 2011). This facade re-exports the member crates and adds
//! the runner:
//!
//! - [`core`]: robots, kinematics, scenes, collision, physics ([`opengrasp_core`]);
//! - [`grasp`]: grasp quality, the shared grasp evaluator, grasp planners and the grasp
//!   benchmark ([`opengrasp_grasp`]);
//! - [`motion`]: motion planners, validators, metrics and the motion benchmark
//!   ([`opengrasp_motion`]);
//! - [`assets`]: the standard robots, hands, objects and scenes ([`opengrasp_assets`]);
//! - [`bench`](mod@bench) (`opengrasp-bench`), the benchmark harness, whose modules are re-exported here:
//!   [`suite`]: the [`Suite`](suite::Suite) builder that runs the reference planners and your own
//!   [`GraspPlanner`](grasp::planners::GraspPlanner)s and
//!   [`MotionPlanner`](motion::MotionPlanner)s in one benchmark, in parallel and
//!   deterministically;
//! - [`results`]: results files with provenance, written atomically and validated on load;
//! - [`report`]: the paper's Tables I–III (terminal, Markdown, CSV) with medians and
//!   percentiles; `plots` (feature `plots`): SVG and PNG Tukey box plots and bar charts;
//! - [`ompl`]: motion results in OMPL's benchmark log format (Planner Arena);
//! - `highscore` (feature `highscore`, `opengrasp-highscore`): the high-score board (SQLite
//!   store and HTTP service);
//! - `viewer` (feature `viewer`, `opengrasp-viewer`): headless PNG snapshots of scenes, motion
//!   runs and grasps; with feature `rerun` also rerun recordings;
//! - `cli` (feature `cli`): the `opengrasp` command line (`opengrasp list | run | report |
//!   view | submit | highscore | serve`); [`view`] (feature `cli`): `opengrasp view` and
//!   `run --record`.
//!
//! # Features
//!
//! `cli` (default) builds the `opengrasp` command and pulls in `highscore`, `plots` and
//! `viewer`. `rerun` (off by default; Rust 1.95) adds rerun recordings to `opengrasp view` and
//! `opengrasp run --record`. A
//! library that only needs the SDK and the harness depends on
//! `opengrasp = { version = "0.1", default-features = false }` and compiles no HTTP server,
//! SQLite, command-line parser or plotting library.
//!
//! # Example
//!
//! A tiny motion suite with the reference RRT-Connect and a Table-III-style report:
//!
//! ```
//! use opengrasp::prelude::*;
//! use opengrasp::motion::planners::RrtConnect;
//!
//! # fn main() -> opengrasp::Result<()> {
//! let results = Suite::new()
//!     .motion_planner("default options", || Box::new(RrtConnect::default()))
//!     .motion_scene(opengrasp::suite::planar_scene())
//!     .runs(3)
//!     .seed(1)
//!     .run()?;
//! let motion = results.motion.as_ref().expect("the motion benchmark ran");
//! assert_eq!(motion.runs.len(), 3);
//! println!("{}", opengrasp::report::motion_table(motion, opengrasp::report::Format::Table));
//! # Ok(())
//! # }
//! ```

pub use opengrasp_assets as assets;
pub use opengrasp_bench as bench;
pub use opengrasp_bench::{ompl, report, results, suite};
pub use opengrasp_core as core;
pub use opengrasp_grasp as grasp;
#[cfg(feature = "highscore")]
pub use opengrasp_highscore as highscore;
pub use opengrasp_motion as motion;

#[cfg(feature = "plots")]
pub use opengrasp_bench::plots;
#[cfg(feature = "viewer")]
pub use opengrasp_viewer as viewer;

#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "cli")]
pub mod view;

pub use opengrasp_bench::{Error, Result, ResultsFile};

/// The most used types in one import: `use opengrasp::prelude::*;`.
pub mod prelude {
    pub use crate::core::collision::CollisionWorld;
    pub use crate::core::model::{JointGroup, Robot, RobotBuilder};
    pub use crate::core::nalgebra::{Isometry3, Point3, Vector3};
    pub use crate::core::physics::{MockBackend, PhysicsEngine, RapierBackend};
    pub use crate::core::scene::Scene;
    pub use crate::core::CoreError;
    pub use crate::grasp::planners::{GraspCandidate, GraspPlanner, GraspRequest, Preshape};
    pub use crate::grasp::GraspError;
    pub use crate::motion::{Goal, MotionError, MotionPlanner, PlanningProblem, Solution, StateValidityChecker};
    pub use crate::results::{Provenance, ResultsFile};
    pub use crate::suite::{Suite, SuiteSize};
}
