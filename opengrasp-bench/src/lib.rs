//! # opengrasp-bench: the OpenGRASP-rs benchmark harness
//!
//! Runs grasp and motion planners — the reference ones and your own — through the standard
//! benchmarks, in parallel and deterministically, and turns the runs into results files,
//! reports and logs:
//!
//! - [`suite`]: the [`Suite`](suite::Suite) builder (planners, hands, objects, scenes, sizes);
//! - [`scenes`] and [`clean_table`]: the standard motion scenes on the stock kitchen and
//!   humanoid (scenes 1 and 2, their 7-DoF stand-ins, and scene 3, Clean the Table);
//! - [`problem_sets`]: motion problem sets from files (JSON, MotionBenchMaker) as scenes;
//! - [`stock`]: the stock hands and objects by name, user ones by path;
//! - [`paper`]: the OpenGRASP paper's published figures;
//! - [`results`]: results files with provenance, written atomically and validated on load;
//! - [`report`]: the paper's Tables I–III (terminal, Markdown, CSV) with medians and
//!   percentiles;
//! - [`ompl`]: motion results in OMPL's benchmark log format (Planner Arena);
//! - `plots` (feature `plots`): SVG and PNG box plots (Tukey) and bar charts.
//!
//! The SDK crates (`opengrasp-core`, `-grasp`, `-motion`, `-assets`) know nothing of this
//! crate; the high-score board (`opengrasp-highscore`) and the `opengrasp` command build on it.
//!
//! # Example
//!
//! A tiny motion suite with the reference RRT-Connect and a Table-III-style report:
//!
//! ```
//! use opengrasp_bench::suite::{planar_scene, Suite};
//! use opengrasp_motion::planners::RrtConnect;
//!
//! # fn main() -> opengrasp_bench::Result<()> {
//! let results = Suite::new()
//!     .motion_planner("default options", || Box::new(RrtConnect::default()))
//!     .motion_scene(planar_scene())
//!     .runs(3)
//!     .seed(1)
//!     .run()?;
//! let motion = results.motion.as_ref().expect("the motion benchmark ran");
//! assert_eq!(motion.runs.len(), 3);
//! println!("{}", opengrasp_bench::report::motion_table(motion, opengrasp_bench::report::Format::Table));
//! # Ok(())
//! # }
//! ```

/// The version of this crate (recorded in results files' provenance).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

pub mod clean_table;
pub mod error;
pub mod ompl;
pub mod paper;
#[cfg(feature = "plots")]
pub mod plots;
pub mod problem_sets;
pub mod report;
pub mod results;
pub mod scenes;
pub mod stock;
pub mod suite;

pub use error::{Error, Result};
pub use results::ResultsFile;
