//! State and motion validity, clearance, path validation and metrics: the functions shared by
//! `opengrasp.Scene` (an owned scene of the standard world) and `opengrasp.Problem` (the query
//! a Python motion planner receives).

use std::time::Instant;

use numpy::PyArray1;
use opengrasp_core::model::{JointGroup, LinkId, Robot};
use opengrasp_motion::metrics::path_metrics;
use opengrasp_motion::validate::{
    segment_valid_continuous, segment_valid_discrete, validate_path, CcdOptions, ValidationOptions,
};
use opengrasp_motion::validity::StateValidityChecker;
use opengrasp_motion::Goal;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{array, array_2d, matrix, rows, vector, with_rows};
use crate::errors::{Error, Result};

/// What the validity methods need: a checker and the robot it is for.
pub struct View<'a> {
    /// The checker (group configurations).
    pub checker: &'a dyn StateValidityChecker,
    /// The robot.
    pub robot: &'a Robot,
    /// The planning group.
    pub group: &'a JointGroup,
    /// The full configuration holding the joints outside the group.
    pub q_full: &'a [f64],
}

impl View<'_> {
    /// A group configuration from Python, checked for dimension and finiteness.
    pub fn config(&self, q: &Bound<'_, PyAny>, what: &str) -> Result<Vec<f64>> {
        vector(q, what, Some(self.checker.dim()))
    }

    /// `is_valid` of one configuration.
    pub fn is_valid(&self, q: &Bound<'_, PyAny>) -> Result<bool> {
        let q = self.config(q, "q")?;
        Ok(self.checker.is_valid(&q))
    }

    /// `is_valid` of every row of an `(N, dim)` array, as a bool array (one call of the
    /// checker's batched [`StateValidityChecker::are_valid`]).
    pub fn is_valid_batch<'py>(&self, py: Python<'py>, qs: &Bound<'py, PyAny>) -> Result<Bound<'py, PyArray1<bool>>> {
        let dim = self.checker.dim();
        let out = with_rows(qs, "qs", dim, |data, n| {
            Ok(if dim == 0 {
                vec![self.checker.is_valid(&[]); n]
            } else {
                // The checker's batched method: vectorised checkers test several states at once.
                let mut out = vec![false; n];
                self.checker.are_valid(data, &mut out);
                out
            })
        })?;
        Ok(PyArray1::from_vec(py, out))
    }

    /// Seconds Rust takes for `is_valid` on every row, called one state at a time from a Rust
    /// loop (the reference figure of the batched-validity benchmark).
    pub fn rust_loop_seconds(&self, qs: &Bound<'_, PyAny>) -> Result<(f64, usize)> {
        let dim = self.checker.dim();
        with_rows(qs, "qs", dim, |data, n| {
            let start = Instant::now();
            let mut valid = 0;
            for q in data.chunks_exact(dim.max(1)) {
                valid += usize::from(self.checker.is_valid(std::hint::black_box(q)));
            }
            Ok((start.elapsed().as_secs_f64(), valid.min(n)))
        })
    }

    /// Motion validity of the straight segment `a → b`: discrete at `step`, or certified
    /// continuous when `continuous` (falls back to discrete if the checker cannot).
    pub fn motion_valid(
        &self,
        a: &Bound<'_, PyAny>,
        b: &Bound<'_, PyAny>,
        step: f64,
        continuous: bool,
    ) -> Result<bool> {
        let a = self.config(a, "a")?;
        let b = self.config(b, "b")?;
        if !(step > 0.0 && step.is_finite()) {
            return Err(Error::input(format!("step: must be finite and > 0, got {step}")));
        }
        if continuous {
            if let Some(v) = segment_valid_continuous(self.checker, &a, &b, &CcdOptions::default()) {
                return Ok(v);
            }
        }
        Ok(segment_valid_discrete(self.checker, &a, &b, step))
    }

    /// Clearance at `q` (`None` if the checker has no distances).
    pub fn clearance(&self, q: &Bound<'_, PyAny>) -> Result<Option<f64>> {
        let q = self.config(q, "q")?;
        Ok(self.checker.clearance(&q))
    }

    /// Clearance of every row (NaN where the checker has no distances).
    pub fn clearance_batch<'py>(&self, py: Python<'py>, qs: &Bound<'py, PyAny>) -> Result<Bound<'py, PyArray1<f64>>> {
        let dim = self.checker.dim();
        let out = with_rows(qs, "qs", dim, |data, _| {
            Ok(data.chunks_exact(dim.max(1)).map(|q| self.checker.clearance(q).unwrap_or(f64::NAN)).collect())
        })?;
        Ok(array(py, out))
    }

    /// The three validators' verdicts on a path `(K, dim)`.
    pub fn validate_path<'py>(&self, py: Python<'py>, path: &Bound<'py, PyAny>) -> Result<Bound<'py, PyDict>> {
        let path = rows(path, "path", Some(self.checker.dim()))?;
        let v = validate_path(self.checker, &path, &ValidationOptions::default());
        let d = PyDict::new(py);
        d.set_item("discrete", v.discrete)?;
        d.set_item("strict", v.strict)?;
        d.set_item("continuous", v.continuous)?;
        Ok(d)
    }

    /// The benchmark's path metrics (lengths, clearance, smoothness).
    pub fn path_metrics<'py>(
        &self,
        py: Python<'py>,
        path: &Bound<'py, PyAny>,
        tip: Option<LinkId>,
        step: f64,
    ) -> Result<Bound<'py, PyAny>> {
        let path = rows(path, "path", Some(self.checker.dim()))?;
        let m = path_metrics(self.robot, self.group, self.q_full, tip, self.checker, &path, step);
        crate::convert::to_py(py, &m)
    }

    /// The full configuration for group values `q`.
    pub fn full_configuration<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> Result<Bound<'py, PyArray1<f64>>> {
        let q = self.config(q, "q")?;
        let mut full = self.q_full.to_vec();
        self.group.insert(&mut full, &q)?;
        Ok(array(py, full))
    }

    /// Group joint limits as `(dim, 2)`.
    pub fn limits<'py>(&self, py: Python<'py>) -> Result<Bound<'py, numpy::PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self.group.limits(self.robot).into_iter().map(|(lo, hi)| vec![lo, hi]).collect();
        array_2d(py, &rows, 2)
    }
}

/// A goal as a dict: `kind` plus `configuration`, `configurations` or `tip`, `target` (4×4),
/// `position_tolerance`, `orientation_tolerance`.
pub fn goal_dict<'py>(py: Python<'py>, robot: &Robot, goal: &Goal) -> Result<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", goal.kind())?;
    match goal {
        Goal::Configuration(q) => d.set_item("configuration", array(py, q.clone()))?,
        Goal::ConfigurationSet(set) => {
            let cols = set.first().map_or(0, Vec::len);
            d.set_item("configurations", array_2d(py, set, cols)?)?
        }
        Goal::Pose(p) => {
            d.set_item("tip", robot.link(p.tip).name.clone())?;
            d.set_item("target", matrix(py, &p.target)?)?;
            d.set_item("position_tolerance", p.position_tolerance)?;
            d.set_item("orientation_tolerance", p.orientation_tolerance)?;
        }
    }
    Ok(d)
}

/// Generates a pyclass's `#[pymethods]` with the validity methods (through
/// `self.view(|v| ...)`) followed by the class's own methods.
macro_rules! validity_pymethods {
    ($ty:ty { $($extra:tt)* }) => {
        #[pymethods]
        impl $ty {
            /// Dimension of the group configurations (number of group joints).
            #[getter]
            fn dim(&self) -> PyResult<usize> {
                Ok(self.view(|v| Ok(v.checker.dim()))?)
            }

            /// Group joint limits as a `(dim, 2)` array of `(lower, upper)`.
            #[getter]
            fn limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
                Ok(self.view(|v| v.limits(py))?)
            }

            /// Names of the group's joints.
            #[getter]
            fn joint_names(&self) -> PyResult<Vec<String>> {
                Ok(self.view(|v| Ok(v.group.joint_names().to_vec()))?)
            }

            /// The robot's full configuration (joints outside the group held here).
            #[getter]
            fn q_full<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
                Ok(self.view(|v| Ok(crate::convert::array(py, v.q_full.to_vec())))?)
            }

            /// True if the group configuration `q` is collision-free.
            fn is_valid(&self, q: &Bound<'_, PyAny>) -> PyResult<bool> {
                Ok(self.view(|v| v.is_valid(q))?)
            }

            /// Validity of every row of an `(N, dim)` array: a bool array of length N. One
            /// call into Rust for the whole batch.
            fn is_valid_batch<'py>(&self, py: Python<'py>, qs: &Bound<'py, PyAny>) -> PyResult<Bound<'py, numpy::PyArray1<bool>>> {
                Ok(self.view(|v| v.is_valid_batch(py, qs))?)
            }

            /// True if the straight segment `a → b` is valid: checked every `step` (C-space
            /// norm), or certified continuous when `continuous` and the checker supports it.
            #[pyo3(signature = (a, b, step = 0.02, continuous = false))]
            fn motion_valid(&self, a: &Bound<'_, PyAny>, b: &Bound<'_, PyAny>, step: f64, continuous: bool) -> PyResult<bool> {
                Ok(self.view(|v| v.motion_valid(a, b, step, continuous))?)
            }

            /// Distance from the robot to the obstacles at `q` (m; ≤ 0 in collision), or
            /// `None` if the checker computes no distances.
            fn clearance(&self, q: &Bound<'_, PyAny>) -> PyResult<Option<f64>> {
                Ok(self.view(|v| v.clearance(q))?)
            }

            /// Clearance of every row of an `(N, dim)` array (NaN without distances).
            fn clearance_batch<'py>(&self, py: Python<'py>, qs: &Bound<'py, PyAny>) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
                Ok(self.view(|v| v.clearance_batch(py, qs))?)
            }

            /// The benchmark's validators on a path `(K, dim)`: `{"discrete", "strict",
            /// "continuous"}` (continuous is `None` if unsupported).
            fn validate_path<'py>(&self, py: Python<'py>, path: &Bound<'py, PyAny>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
                Ok(self.view(|v| v.validate_path(py, path))?)
            }

            /// The full configuration for group values `q`.
            fn full_configuration<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
                Ok(self.view(|v| v.full_configuration(py, q))?)
            }

            $($extra)*
        }
    };
}
pub(crate) use validity_pymethods;
