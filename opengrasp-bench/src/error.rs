//! The error type of the benchmark harness.

use std::io;
use std::path::PathBuf;

/// Errors of the benchmark harness (suites, results files, reports, plots).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Reading or writing a file failed.
    #[error("i/o error on {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: io::Error,
    },
    /// A file is not valid JSON of the expected shape.
    #[error("malformed results file {path}: {source}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: serde_json::Error,
    },
    /// Serialising results failed.
    #[error("cannot serialise results: {0}")]
    Serialize(#[source] serde_json::Error),
    /// The file has a schema version this build cannot read.
    #[error("unsupported results schema version {found} (this build reads {expected})")]
    SchemaVersion {
        /// Version in the file.
        found: u32,
        /// Version this build reads.
        expected: u32,
    },
    /// A value in the results is out of range or inconsistent.
    #[error("invalid results: {field}: {reason}")]
    Invalid {
        /// Path of the offending field (e.g. `motion.runs[3].planning_time`).
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A suite or command option is invalid.
    #[error("invalid option {name}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A model (hand, object, robot) could not be loaded.
    #[error(transparent)]
    Core(#[from] opengrasp_core::CoreError),
    /// A stock model could not be built.
    #[error(transparent)]
    Asset(#[from] opengrasp_assets::AssetError),
    /// The grasp benchmark failed.
    #[error(transparent)]
    Grasp(#[from] opengrasp_grasp::GraspError),
    /// The motion benchmark failed.
    #[error(transparent)]
    Motion(#[from] opengrasp_motion::MotionError),
    /// Drawing a plot failed.
    #[error("plot {path}: {reason}")]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// What failed.
        reason: String,
    },
}

/// Result type of the benchmark harness.
pub type Result<T, E = Error> = std::result::Result<T, E>;
