//! # opengrasp-py: OpenGRASP-rs from Python
//!
//! The Python extension `opengrasp._opengrasp` (PyO3, one abi3 wheel for CPython ≥ 3.9),
//! re-exported by the `opengrasp` package (`python/opengrasp/`):
//!
//! - the SDK with numpy arrays: [`robot`] (URDF/SRDF, FK, Jacobian, IK), [`scene`] and
//!   [`validity`] (standard motion scenes, state validity single and batched, motion validity,
//!   clearance, path validation and metrics), [`world`] (the kitchen's geometry, motion
//!   problem sets from JSON or MotionBenchMaker files), [`grasp`] (stock hands and objects, contacts →
//!   force closure, ε and volume, the grasp evaluator on a hand pose);
//! - Python planners in the standard suite: [`planners`] wraps Python objects as
//!   `GraspPlanner` / `MotionPlanner`, [`suite`] runs them next to the Rust reference planners
//!   with the same evaluator, validators, metrics and seeds, and writes, loads and submits
//!   results files;
//! - [`errors`]: every Rust error becomes an exception of `opengrasp.errors` carrying the
//!   Rust message; panics are caught.
//!
//! Build and install with `pip install ./opengrasp-py` (or `maturin develop` in this folder);
//! the Python tests are in `tests/` (pytest).

pub mod convert;
pub mod errors;
pub mod grasp;
pub mod planners;
pub mod robot;
pub mod scene;
pub mod suite;
pub mod validity;
pub mod world;

use pyo3::prelude::*;

/// The extension module `opengrasp._opengrasp`.
#[pymodule]
fn _opengrasp(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<robot::PyRobot>()?;
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(scene::scene_names, m)?)?;
    m.add_class::<world::PyProblemSet>()?;
    m.add_function(wrap_pyfunction!(world::load_problem_sets, m)?)?;
    m.add_function(wrap_pyfunction!(world::kitchen, m)?)?;
    m.add_class::<grasp::PyHand>()?;
    m.add_class::<grasp::PyObject>()?;
    m.add_class::<grasp::PyGraspEvaluator>()?;
    m.add_function(wrap_pyfunction!(grasp::hand_names, m)?)?;
    m.add_function(wrap_pyfunction!(grasp::object_names, m)?)?;
    m.add_function(wrap_pyfunction!(grasp::grasp_quality, m)?)?;
    m.add_class::<planners::PyHandInfo>()?;
    m.add_class::<planners::PyGraspRequest>()?;
    m.add_class::<planners::PyGraspCandidate>()?;
    m.add_class::<planners::PyProblem>()?;
    m.add_function(wrap_pyfunction!(planners::py_palm_pose, m)?)?;
    m.add_class::<suite::PySuite>()?;
    m.add_class::<suite::PyResults>()?;
    m.add_function(wrap_pyfunction!(suite::load_results, m)?)?;
    m.add_function(wrap_pyfunction!(suite::submit, m)?)?;
    m.add_function(wrap_pyfunction!(suite::ranking, m)?)?;
    m.add_function(wrap_pyfunction!(suite::register_benchmark, m)?)?;
    Ok(())
}
