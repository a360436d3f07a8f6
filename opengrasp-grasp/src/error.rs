//! The error type of `opengrasp-grasp`.

use opengrasp_core::CoreError;

/// Everything that can go wrong in `opengrasp-grasp`.
///
/// Bad input never panics: non-finite contacts, out-of-range options, solver breakdowns and
/// convex-hull failures each map to a variant here. A user's own grasp planner can carry its
/// error in [`GraspError::Other`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GraspError {
    /// A contact, frame or option contains NaN or an infinity.
    #[error("non-finite value in {what}")]
    NonFinite {
        /// Which input.
        what: String,
    },
    /// A contact normal has (numerically) zero length and cannot be normalised.
    #[error("contact {index} has a zero-length normal")]
    ZeroNormal {
        /// Index of the contact in the input slice.
        index: usize,
    },
    /// An option or parameter is out of its valid range.
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Why it is invalid.
        reason: String,
    },
    /// Points handed to the convex hull do not all have the hull's dimension.
    #[error("point {index} has {actual} coordinates, expected {expected}")]
    DimensionMismatch {
        /// Index of the offending point.
        index: usize,
        /// Expected number of coordinates.
        expected: usize,
        /// Given number of coordinates.
        actual: usize,
    },
    /// The points span fewer than `dimension` affine dimensions, so they have no
    /// full-dimensional convex hull.
    #[error("points span {affine_rank} of {dimension} dimensions: no full-dimensional hull")]
    DegenerateHull {
        /// Dimension of the space.
        dimension: usize,
        /// Affine dimension actually spanned by the points.
        affine_rank: usize,
    },
    /// The convex hull could not be built consistently even after joggling the input.
    #[error("convex hull failed in {dimension} dimensions after {attempts} attempts: {reason}")]
    HullFailed {
        /// Dimension of the space.
        dimension: usize,
        /// Number of (joggled) attempts made.
        attempts: usize,
        /// What went wrong on the last attempt.
        reason: String,
    },
    /// The conic solver (clarabel) did not reach a usable solution.
    #[error("{problem} solver stopped with status {status}")]
    Solver {
        /// Which optimisation problem ("min-norm qp", "strict force-closure lp").
        problem: &'static str,
        /// The solver's final status.
        status: String,
    },
    /// An error from `opengrasp-core`.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// Serialising results as JSON failed.
    #[error("cannot serialise results: {0}")]
    Json(#[from] serde_json::Error),
    /// Any other error, e.g. from a user's grasp planner.
    #[error(transparent)]
    Other(#[from] Box<dyn std::error::Error + Send + Sync>),
}

/// Result alias for `opengrasp-grasp`.
pub type Result<T, E = GraspError> = std::result::Result<T, E>;

/// Returns `Err(GraspError::NonFinite)` unless every value is finite.
pub(crate) fn ensure_finite(what: &str, values: impl IntoIterator<Item = f64>) -> Result<()> {
    if values.into_iter().all(f64::is_finite) {
        Ok(())
    } else {
        Err(GraspError::NonFinite { what: what.to_string() })
    }
}
