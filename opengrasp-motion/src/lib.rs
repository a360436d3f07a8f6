//! # opengrasp-motion
//!
//! Motion planners, path post-processing, validators, metrics and the motion-planning
//! benchmark of OpenGRASP-rs (section IV-B of the OpenGRASP paper, Table III).
//!
//! - [`problem`]: the [`MotionPlanner`] trait a user implements to enter the benchmark
//!   (`setup` for reusable work such as roadmaps, timed separately from `plan`), the
//!   [`PlanningProblem`] it receives (robot, joint group, start, [`Goal`] — a configuration, a
//!   set of configurations or a pose reached through IK — validity checker, time limit, seed,
//!   discrete step) and the [`Solution`] it returns.
//!   [`PlanningProblem::builder`] fills the defaults (joints outside the group at home, 10 s,
//!   seed 0, step 0.02): no full configuration when the group covers every joint.
//! - [`problem_set`]: motion problem sets from files — a documented JSON format (robot URDF +
//!   SRDF + group, obstacles as boxes, spheres, cylinders, capsules and meshes with poses,
//!   start, configuration or pose goals) and MotionBenchMaker's MoveIt scene + request YAML.
//! - [`validity`]: the [`StateValidityChecker`] interface, its implementation over core's
//!   parry-based collision world ([`validity::CollisionChecker`]), a closed-form sphere model
//!   ([`validity::SphereWorld`]) and the per-link [`validity::MotionBound`] used for
//!   continuous checking.
//! - [`scene_spheres`]: a conservative sphere model of a robot in a core scene, for planning
//!   (exact geometry stays the judge).
//! - [`planners`]: RRT-Connect, PRM (roadmap built in `setup`, reused across queries) and
//!   IK-RRT, all seeded with `ChaCha8Rng`.
//! - [`nearest`]: the [`nearest::NearestNeighbors`] trait, a bucket kd-tree (the planners'
//!   default) and the linear scan, which answer identically.
//! - [`smoothing`]: random shortcuts, each validated by the strict (and continuous) check.
//! - [`validate`]: discrete checks at the planning step (default
//!   [`validate::DEFAULT_STEP`] = 0.02 in the Euclidean C-space norm, i.e. rad for revolute
//!   joints), strict checks at a tenth of it, and certified continuous checks by conservative
//!   advancement (Schwarzer, Saha & Latombe 2005).
//! - [`protocol`]: the certified protocol (default) and the paper's reference protocol
//!   (coarse step, plain shortcutting, fine re-check).
//! - [`metrics`]: C-space and end-effector path length, clearance, OMPL smoothness,
//!   percentiles.
//! - [`benchmark`]: the [`BenchmarkScene`](benchmark::BenchmarkScene) (a seeded generator of problem instances)
//!   and [`benchmark::run_benchmark`], which grades every planner with the same validators and
//!   metrics and records every run as a serde-serialisable [`benchmark::RunRecord`]. The
//!   standard suite's kitchen scenes, built on the stock world, live in the harness
//!   (`opengrasp-bench`): this crate does not depend on any stock model.
//!
//! ```
//! use std::sync::Arc;
//! use std::time::Duration;
//! use nalgebra::{Isometry3, Vector3};
//! use opengrasp_core::model::{samples, JointGroup};
//! use opengrasp_motion::planners::RrtConnect;
//! use opengrasp_motion::smoothing::{shortcut, ShortcutOptions};
//! use opengrasp_motion::validate::{path_length, validate_path, ValidationOptions};
//! use opengrasp_motion::validity::{ObstacleBox, SphereWorld};
//! use opengrasp_motion::{Goal, MotionPlanner, PlanningProblem};
//!
//! # fn main() -> opengrasp_motion::Result<()> {
//! // A planar two-link arm with a box in its way.
//! let robot = Arc::new(samples::planar_arm(&[0.5, 0.4])?);
//! let group = JointGroup::all(&robot, "arm")?;
//! let post = ObstacleBox::new("post", Isometry3::translation(0.6, 0.0, 0.0), Vector3::new(0.1, 0.1, 0.5));
//! let world = SphereWorld::new(robot.clone(), group.clone(), vec![0.0, 0.0], Isometry3::identity(), vec![post])?;
//!
//! let goal = Goal::Configuration(vec![-1.2, 0.3]);
//! let problem = PlanningProblem {
//!     robot: &robot,
//!     group: &group,
//!     q_full: &[0.0, 0.0],
//!     start: &[1.2, 0.3],
//!     goal: &goal,
//!     checker: &world,
//!     time_limit: Duration::from_secs(5),
//!     seed: 7,
//!     step: 0.02,
//! };
//! let solution = RrtConnect::default().plan(&problem)?;
//! let (smoothed, _) = shortcut(&world, &solution.path, &ShortcutOptions::default());
//! assert!(path_length(&smoothed) <= path_length(&solution.path));
//! let validity = validate_path(&world, &smoothed, &ValidationOptions::default());
//! assert!(validity.discrete && validity.strict && validity.continuous == Some(true));
//! # Ok(())
//! # }
//! ```

/// The version of this crate (recorded in results files' provenance).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

pub mod benchmark;
pub mod certify;
pub mod error;
pub mod metrics;
pub mod nearest;
pub mod planners;
pub mod problem;
pub mod problem_builder;
pub mod problem_set;
pub mod protocol;
pub mod scene_spheres;
pub mod smoothing;
pub mod validate;
pub mod validity;

pub use error::{MotionError, Result};
pub use problem::{Goal, MotionPlanner, PlanningProblem, PoseGoal, SetupContext, Solution};
pub use problem_builder::ProblemBuilder;
pub use validity::StateValidityChecker;
