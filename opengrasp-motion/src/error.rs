//! The error type of `opengrasp-motion`.

/// Everything that can go wrong while setting up, planning, validating or benchmarking.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MotionError {
    /// An error from `opengrasp-core` (model, kinematics, IK).
    #[error(transparent)]
    Core(#[from] opengrasp_core::CoreError),
    /// A configuration has the wrong number of values for the joint group.
    #[error("configuration has {actual} values, expected {expected}")]
    DimensionMismatch {
        /// Expected length (the group's dimension).
        expected: usize,
        /// Given length.
        actual: usize,
    },
    /// A configuration contains NaN or infinite values.
    #[error("non-finite value in {what}")]
    NonFinite {
        /// Which input.
        what: &'static str,
    },
    /// A configuration lies outside the joint limits.
    #[error("{what} is outside the joint limits (joint {index}: {value} not in [{lower}, {upper}])")]
    OutOfLimits {
        /// Which input.
        what: &'static str,
        /// Index in the group.
        index: usize,
        /// The offending value.
        value: f64,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// The start or goal configuration is in collision.
    #[error("{what} configuration is in collision")]
    InvalidState {
        /// "start" or "goal".
        what: &'static str,
    },
    /// An option or parameter is out of its valid range.
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Why it is invalid.
        reason: String,
    },
    /// The planner did not find a path within its time limit.
    #[error("no path found within {seconds} s")]
    Timeout {
        /// The time limit (s).
        seconds: f64,
    },
    /// The planner does not support this kind of goal.
    #[error("planner `{planner}` does not support {goal} goals")]
    UnsupportedGoal {
        /// The planner's name.
        planner: String,
        /// The kind of goal.
        goal: &'static str,
    },
    /// Building a scene's world (robot, obstacles, objects) failed.
    #[error("cannot build the scene: {0}")]
    Scene(#[source] Box<dyn std::error::Error + Send + Sync>),
    /// A problem-set file (JSON problem set, MoveIt scene or request) cannot be read.
    #[error("cannot read problem set {path}: {source}")]
    ProblemSetIo {
        /// The file or directory.
        path: std::path::PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A problem-set file is larger than the loader accepts.
    #[error("problem set {path} has {actual} bytes, more than the limit of {limit}")]
    ProblemSetTooLarge {
        /// The file.
        path: std::path::PathBuf,
        /// The limit (bytes).
        limit: u64,
        /// The file's size (bytes).
        actual: u64,
    },
    /// A problem-set file is not valid JSON / YAML, or not of the expected shape.
    #[error("malformed problem set {path}: {reason}")]
    ProblemSetSyntax {
        /// The file.
        path: std::path::PathBuf,
        /// The parser's message (with line and column).
        reason: String,
    },
    /// A problem set is well-formed but describes something invalid (a negative size, an
    /// unknown joint, a start of the wrong length, an unsupported shape, no robot, ...).
    #[error("invalid problem set {path}: {field}: {reason}")]
    ProblemSetInvalid {
        /// The file (or directory) of the set.
        path: std::path::PathBuf,
        /// The offending field, e.g. `problems[3].obstacles[1].size`.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A user planner's own error.
    #[error("planner error: {0}")]
    Other(Box<dyn std::error::Error + Send + Sync>),
}

impl MotionError {
    /// True for errors caused by bad input (dimensions, limits, invalid start/goal) rather than
    /// by the planner.
    pub fn is_invalid_input(&self) -> bool {
        matches!(
            self,
            MotionError::DimensionMismatch { .. }
                | MotionError::NonFinite { .. }
                | MotionError::OutOfLimits { .. }
                | MotionError::InvalidState { .. }
                | MotionError::InvalidParameter { .. }
                | MotionError::UnsupportedGoal { .. }
        )
    }
}

/// Result alias for `opengrasp-motion`.
pub type Result<T, E = MotionError> = std::result::Result<T, E>;
