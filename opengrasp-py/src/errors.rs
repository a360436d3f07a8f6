//! Rust errors as Python exceptions.
//!
//! Every error of the Rust crates becomes an exception of the hierarchy defined in
//! `opengrasp/errors.py` (so that a class can derive from both `OpenGraspError` and
//! `ValueError`), carrying the Rust error's message:
//!
//! | exception | for |
//! | --- | --- |
//! | `InvalidInputError(OpenGraspError, ValueError)` | bad arguments: dimensions, non-finite values, limits, unknown names, options out of range |
//! | `ModelError(OpenGraspError, ValueError)` | malformed URDF / SRDF / meshes / hand and object spec files |
//! | `ResultsError(OpenGraspError, ValueError)` | results files that do not parse or validate |
//! | `PlanningError(OpenGraspError)` | planner and solver failures (timeouts, hull or QP failures, a Python planner's error) |
//! | `HighscoreError(OpenGraspError)` | the high-score store |
//! | `OpenGraspError(Exception)` | anything else (I/O, internal errors) |
//!
//! Panics never cross the boundary: entry points that run larger Rust computations go through
//! [`guard`], which turns a panic into an `OpenGraspError`.

use std::fmt::Display;
use std::panic::{catch_unwind, AssertUnwindSafe};

use opengrasp_core::CoreError;
use opengrasp_grasp::GraspError;
use opengrasp_motion::MotionError;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// The exception class an error maps to (a class of `opengrasp/errors.py`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `OpenGraspError`.
    Base,
    /// `InvalidInputError`.
    Input,
    /// `ModelError`.
    Model,
    /// `ResultsError`.
    Results,
    /// `PlanningError`.
    Planning,
    /// `HighscoreError`.
    Highscore,
}

impl Kind {
    fn class_name(self) -> &'static str {
        match self {
            Kind::Base => "OpenGraspError",
            Kind::Input => "InvalidInputError",
            Kind::Model => "ModelError",
            Kind::Results => "ResultsError",
            Kind::Planning => "PlanningError",
            Kind::Highscore => "HighscoreError",
        }
    }
}

/// An error on its way to Python: the exception class and the Rust message.
#[derive(Debug)]
pub struct Error {
    /// The exception class.
    pub kind: Kind,
    /// The message (the Rust error's `Display`).
    pub message: String,
}

/// Result of the binding functions before conversion to `PyResult`.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// An error of `kind` with `message`.
    pub fn new(kind: Kind, message: impl Display) -> Self {
        Self { kind, message: message.to_string() }
    }

    /// An `InvalidInputError`.
    pub fn input(message: impl Display) -> Self {
        Self::new(Kind::Input, message)
    }
}

/// Builds the Python exception of `kind` (falls back to `RuntimeError` if the `opengrasp`
/// package is not importable, e.g. when the extension is loaded on its own).
pub fn exception(py: Python<'_>, kind: Kind, message: &str) -> PyErr {
    let built =
        py.import("opengrasp.errors").and_then(|m| m.getattr(kind.class_name())).and_then(|cls| cls.call1((message,)));
    match built {
        Ok(value) => PyErr::from_value(value),
        Err(_) => PyRuntimeError::new_err(format!("{}: {message}", kind.class_name())),
    }
}

impl From<Error> for PyErr {
    fn from(e: Error) -> Self {
        Python::attach(|py| exception(py, e.kind, &e.message))
    }
}

fn core_kind(e: &CoreError) -> Kind {
    match e {
        CoreError::MalformedUrdf { .. }
        | CoreError::MalformedSrdf { .. }
        | CoreError::MeshNotFound { .. }
        | CoreError::PackageNotFound { .. }
        | CoreError::LimitExceeded { .. }
        | CoreError::MeshFormat { .. }
        | CoreError::DegenerateMesh { .. }
        | CoreError::InvalidGeometry { .. }
        | CoreError::InvalidModel { .. }
        | CoreError::MalformedSpec { .. }
        | CoreError::FileTooLarge { .. } => Kind::Model,
        CoreError::UnknownLink { .. }
        | CoreError::UnknownJoint { .. }
        | CoreError::NotActuated { .. }
        | CoreError::EmptyJointGroup { .. }
        | CoreError::UnknownJointGroup { .. }
        | CoreError::DimensionMismatch { .. }
        | CoreError::NonFiniteJointValue { .. }
        | CoreError::JointOutOfLimits { .. }
        | CoreError::NonFinite { .. }
        | CoreError::InvalidParameter { .. }
        | CoreError::UnknownPreshape { .. }
        | CoreError::InvalidHandle { .. }
        | CoreError::EmptyScene { .. } => Kind::Input,
        _ => Kind::Base,
    }
}

fn grasp_kind(e: &GraspError) -> Kind {
    match e {
        GraspError::NonFinite { .. }
        | GraspError::ZeroNormal { .. }
        | GraspError::InvalidParameter { .. }
        | GraspError::DimensionMismatch { .. } => Kind::Input,
        GraspError::Core(c) => core_kind(c),
        GraspError::Json(_) => Kind::Model,
        _ => Kind::Planning,
    }
}

fn motion_kind(e: &MotionError) -> Kind {
    match e {
        MotionError::Core(c) => core_kind(c),
        MotionError::DimensionMismatch { .. }
        | MotionError::NonFinite { .. }
        | MotionError::OutOfLimits { .. }
        | MotionError::InvalidState { .. }
        | MotionError::InvalidParameter { .. }
        | MotionError::UnsupportedGoal { .. } => Kind::Input,
        MotionError::ProblemSetIo { .. }
        | MotionError::ProblemSetTooLarge { .. }
        | MotionError::ProblemSetSyntax { .. }
        | MotionError::ProblemSetInvalid { .. } => Kind::Model,
        _ => Kind::Planning,
    }
}

fn bench_kind(e: &opengrasp_bench::Error) -> Kind {
    use opengrasp_bench::Error as B;
    match e {
        B::Parse { .. } | B::SchemaVersion { .. } | B::Invalid { .. } => Kind::Results,
        B::InvalidOption { .. } => Kind::Input,
        B::Core(c) => core_kind(c),
        B::Asset(a) => asset_kind(a),
        B::Grasp(g) => grasp_kind(g),
        B::Motion(m) => motion_kind(m),
        _ => Kind::Base,
    }
}

fn asset_kind(e: &opengrasp_assets::AssetError) -> Kind {
    use opengrasp_assets::AssetError as A;
    match e {
        A::UnknownAsset { .. } | A::InvalidParameter { .. } => Kind::Input,
        A::Core(c) => core_kind(c),
        _ => Kind::Base,
    }
}

fn highscore_kind(e: &opengrasp_highscore::HighscoreError) -> Kind {
    use opengrasp_highscore::HighscoreError as H;
    match e {
        H::TooLarge { .. } | H::InvalidJson { .. } | H::InvalidField { .. } | H::SchemaVersion { .. } => Kind::Results,
        H::UnknownBenchmark { .. } | H::UnknownSubmission { .. } => Kind::Input,
        _ => Kind::Highscore,
    }
}

macro_rules! from_error {
    ($($ty:ty => $kind:expr),* $(,)?) => {$(
        impl From<$ty> for Error {
            fn from(e: $ty) -> Self {
                let kind: fn(&$ty) -> Kind = $kind;
                Error::new(kind(&e), &e)
            }
        }
    )*};
}

from_error! {
    CoreError => core_kind,
    GraspError => grasp_kind,
    MotionError => motion_kind,
    opengrasp_bench::Error => bench_kind,
    opengrasp_assets::AssetError => asset_kind,
    opengrasp_highscore::HighscoreError => highscore_kind,
    serde_json::Error => |_| Kind::Results,
}

impl From<PyErr> for Error {
    fn from(e: PyErr) -> Self {
        Error::new(Kind::Base, e)
    }
}

/// Runs `f`, turning a Rust panic into an `OpenGraspError` ("internal error: ...") instead
/// of letting it unwind into the interpreter.
pub fn guard<T>(f: impl FnOnce() -> Result<T>) -> Result<T> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        Err(Error::new(Kind::Base, format!("internal error (a Rust panic, please report it): {what}")))
    })
}
