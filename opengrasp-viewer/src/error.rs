//! The viewer's error type.

use std::path::PathBuf;

/// Errors of the viewer: bad input (results, ids, cameras), the models it draws, files.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ViewerError {
    /// The results file could not be read or parsed, or failed validation.
    #[error(transparent)]
    Results(#[from] opengrasp_bench::Error),
    /// A robot, scene or collision query failed.
    #[error(transparent)]
    Core(#[from] opengrasp_core::CoreError),
    /// An asset could not be built or tessellated.
    #[error(transparent)]
    Asset(#[from] opengrasp_assets::AssetError),
    /// A grasp could not be evaluated again.
    #[error(transparent)]
    Grasp(#[from] opengrasp_grasp::GraspError),
    /// A motion scene could not be rebuilt.
    #[error(transparent)]
    Motion(#[from] opengrasp_motion::MotionError),
    /// No motion run with this id in the results (ids: `planner/scene/run`, or the run's
    /// position in the file).
    #[error("no motion run `{id}` in the results ({available} runs; ids look like `{example}`)")]
    UnknownRun {
        /// The id asked for.
        id: String,
        /// Runs in the file.
        available: usize,
        /// An id that exists (or a hint when there are none).
        example: String,
    },
    /// No grasp candidate with this id in the results.
    #[error("no grasp `{id}` in the results ({available} recorded candidates; ids look like `{example}`)")]
    UnknownGrasp {
        /// The id asked for.
        id: String,
        /// Recorded candidates in the file.
        available: usize,
        /// An id that exists (or a hint when there are none).
        example: String,
    },
    /// The results name a motion scene the viewer cannot rebuild.
    #[error("cannot rebuild motion scene `{scene}`: {reason}")]
    UnknownScene {
        /// The scene name.
        scene: String,
        /// Why.
        reason: String,
    },
    /// The run's planner is not one the viewer can replay (not a reference planner, or other
    /// parameters than the reference's).
    #[error("cannot replay planner `{planner}`: {reason}")]
    UnknownPlanner {
        /// The planner name.
        planner: String,
        /// Why.
        reason: String,
    },
    /// A replayed run differs from its record (not deterministic, or another version).
    #[error("replay of {run} differs from the record: {what}")]
    ReplayDiffers {
        /// The run id.
        run: String,
        /// The first difference.
        what: String,
    },
    /// A camera setting is unusable.
    #[error("invalid camera: {reason}")]
    InvalidCamera {
        /// Why.
        reason: String,
    },
    /// PNG encoding failed.
    #[error("png encoding failed: {reason}")]
    Png {
        /// The encoder's message.
        reason: String,
    },
    /// Logging to rerun or writing the recording failed.
    #[error("rerun: {reason}")]
    Rerun {
        /// The SDK's message.
        reason: String,
    },
    /// A file could not be written or read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
}

/// Result with [`ViewerError`].
pub type Result<T, E = ViewerError> = std::result::Result<T, E>;
