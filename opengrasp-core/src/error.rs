//! The error type of `opengrasp-core`.

use std::path::PathBuf;

/// Everything that can go wrong in `opengrasp-core`.
///
/// Bad input never panics: malformed URDF, missing meshes, unknown names, non-finite or
/// out-of-limit joint values and degenerate geometry each map to a variant here.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CoreError {
    /// The URDF text could not be parsed or is structurally invalid.
    #[error("malformed urdf: {reason}")]
    MalformedUrdf {
        /// What is wrong with it.
        reason: String,
    },
    /// The SRDF text could not be parsed or names something inconsistent.
    #[error("malformed srdf: {reason}")]
    MalformedSrdf {
        /// What is wrong with it.
        reason: String,
    },
    /// A mesh file referenced by a robot or object could not be found or read.
    #[error("mesh not found: {}", path.display())]
    MeshNotFound {
        /// The path or URI that was looked up.
        path: PathBuf,
    },
    /// A `package://NAME/...` URI names a package found nowhere on the search path.
    #[error("package `{package}` of {uri} not found; searched: {}", display_paths(searched))]
    PackageNotFound {
        /// The package name.
        package: String,
        /// The whole URI.
        uri: String,
        /// Every directory that was looked at (registered packages, ancestors of the base
        /// directory, search-path roots), in order.
        searched: Vec<PathBuf>,
    },
    /// A document exceeds a resource limit (size, XML nesting depth, element count, group
    /// nesting): hostile or broken input, rejected before it is parsed further.
    #[error("{document} exceeds the {what} limit: {actual} > {limit}")]
    LimitExceeded {
        /// The kind of document (`urdf`, `srdf`, `collada`, `package.xml`).
        document: &'static str,
        /// The quantity limited (`size in bytes`, `nesting depth`, `element count`, ...).
        what: &'static str,
        /// The limit.
        limit: usize,
        /// The value found (at least; counting stops at the first excess).
        actual: usize,
    },
    /// A mesh file was found but could not be decoded.
    #[error("cannot read mesh {}: {reason}", path.display())]
    MeshFormat {
        /// The mesh file.
        path: PathBuf,
        /// Decoder message.
        reason: String,
    },
    /// A triangle mesh is unusable (empty, non-finite, out-of-range indices, zero-area faces).
    #[error("degenerate mesh: {reason}")]
    DegenerateMesh {
        /// What is degenerate.
        reason: String,
    },
    /// A primitive shape has a non-positive or non-finite dimension.
    #[error("invalid geometry: {reason}")]
    InvalidGeometry {
        /// What is invalid.
        reason: String,
    },
    /// The robot's link/joint structure is not a valid tree.
    #[error("invalid robot model: {reason}")]
    InvalidModel {
        /// What is invalid.
        reason: String,
    },
    /// No link with this name exists.
    #[error("unknown link `{name}`")]
    UnknownLink {
        /// The name looked up.
        name: String,
    },
    /// No joint with this name exists.
    #[error("unknown joint `{name}`")]
    UnknownJoint {
        /// The name looked up.
        name: String,
    },
    /// A joint cannot be used as a degree of freedom (fixed or mimic joint).
    #[error("joint `{name}` is not an actuated degree of freedom")]
    NotActuated {
        /// The joint's name.
        name: String,
    },
    /// A joint group has no joints.
    #[error("joint group `{name}` is empty")]
    EmptyJointGroup {
        /// The group's name.
        name: String,
    },
    /// No joint group with this name exists.
    #[error("unknown joint group `{name}`")]
    UnknownJointGroup {
        /// The name looked up.
        name: String,
    },
    /// A configuration vector has the wrong length.
    #[error("configuration has {actual} values, expected {expected}")]
    DimensionMismatch {
        /// Expected length.
        expected: usize,
        /// Given length.
        actual: usize,
    },
    /// A joint value is NaN or infinite.
    #[error("joint `{joint}` has non-finite value {value}")]
    NonFiniteJointValue {
        /// The joint's name.
        joint: String,
        /// The offending value.
        value: f64,
    },
    /// A joint value lies outside the joint's limits.
    #[error("joint `{joint}` value {value} outside limits [{lower}, {upper}]")]
    JointOutOfLimits {
        /// The joint's name.
        joint: String,
        /// The offending value.
        value: f64,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A pose, vector or parameter is NaN or infinite.
    #[error("non-finite value in {what}")]
    NonFinite {
        /// Which input.
        what: String,
    },
    /// An option or parameter is out of its valid range.
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: String,
        /// Why it is invalid.
        reason: String,
    },
    /// A hand has no preshape of this name.
    #[error("unknown preshape `{name}`")]
    UnknownPreshape {
        /// The name asked for.
        name: String,
    },
    /// A description file (hand spec, object metadata) is not valid JSON of its format.
    #[error("malformed description file {}: {reason}", path.display())]
    MalformedSpec {
        /// The file.
        path: PathBuf,
        /// What is wrong (the parser's message with line and column).
        reason: String,
    },
    /// A file is larger than the loader accepts.
    #[error("{} is larger than the limit of {limit} bytes", path.display())]
    FileTooLarge {
        /// The file.
        path: PathBuf,
        /// The limit (bytes).
        limit: u64,
    },
    /// A scene has nothing to operate on (no bodies, objects or robots where one is needed).
    #[error("empty scene: {reason}")]
    EmptyScene {
        /// What was missing.
        reason: String,
    },
    /// A scene handle (robot, object, body) does not refer to anything in the scene.
    #[error("invalid {kind} handle {index}")]
    InvalidHandle {
        /// Kind of handle ("robot", "object", "body").
        kind: &'static str,
        /// The handle's index.
        index: usize,
    },
    /// The simulation blew up: a dynamic body left the plausible range (farther than 1e6 m
    /// from the origin, faster than 1e6 m/s, or not finite). Stepping on would panic inside the
    /// broad phase, so the backend stops at the first substep that leaves a body there.
    #[error(
        "the simulation diverged at t = {time:.4} s: a body at {distance:e} m from the origin moving at {speed:e} m/s"
    )]
    SimulationDiverged {
        /// Simulated time (s) of the substep that diverged.
        time: f64,
        /// The body's distance from the origin (m).
        distance: f64,
        /// The body's speed (m/s).
        speed: f64,
    },
    /// The physics backend reported an error.
    #[error("physics backend error: {reason}")]
    Physics {
        /// What happened.
        reason: String,
    },
    /// An I/O error while reading or writing files.
    #[error("i/o error on {}: {source}", path.display())]
    Io {
        /// The file involved.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

fn display_paths(paths: &[PathBuf]) -> String {
    if paths.is_empty() {
        return "nothing (no search path: set ROS_PACKAGE_PATH or add roots)".to_string();
    }
    paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
}

/// Result alias for `opengrasp-core`.
pub type Result<T, E = CoreError> = std::result::Result<T, E>;

/// Returns `Err(CoreError::NonFinite)` unless every value is finite.
pub(crate) fn ensure_finite(what: &str, values: impl IntoIterator<Item = f64>) -> Result<()> {
    if values.into_iter().all(f64::is_finite) {
        Ok(())
    } else {
        Err(CoreError::NonFinite { what: what.to_string() })
    }
}

/// Returns `Err(CoreError::NonFinite)` unless the pose's translation and rotation are finite.
pub(crate) fn ensure_finite_pose(what: &str, pose: &nalgebra::Isometry3<f64>) -> Result<()> {
    ensure_finite(what, pose.translation.vector.iter().chain(pose.rotation.coords.iter()).copied())
}
