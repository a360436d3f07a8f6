//! Python planners as Rust planners: [`PyGraspPlanner`] implements `GraspPlanner` and
//! [`PyMotionPlanner`] implements `MotionPlanner` by calling a Python object's `plan` (and
//! `setup`) under the GIL, so the harness runs them like any Rust entrant.
//!
//! A grasp planner's `plan(request)` gets a [`PyGraspRequest`] (hand info, object mesh as
//! numpy arrays, seed) and returns a list of [`PyGraspCandidate`]s. A motion planner's
//! `plan(problem)` gets a [`PyProblem`] (start, goal, limits, validity checks, time limit,
//! seed) and returns the path as a `(K, dim)` array, or a dict `{"path": ..., "iterations":
//! n}`, or `None` for "no path within the time limit".

mod borrowed;

use std::fmt;
use std::sync::Arc;
use std::time::Instant;

use nalgebra::{Point3, Unit, Vector3};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use opengrasp_core::model::Robot;
use opengrasp_grasp::planners::{palm_pose, GraspCandidate, GraspPlanner, GraspRequest, HandInfo, Preshape};
use opengrasp_grasp::GraspError;
use opengrasp_motion::problem::{PlanningProblem, SetupContext, Solution};
use opengrasp_motion::validity::StateValidityChecker;
use opengrasp_motion::{MotionError, MotionPlanner};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::convert::{array, array_2d, isometry, matrix, rows, vector, vector3};
use crate::errors::{Error, Kind, Result};
use crate::robot::PyRobot;
use crate::validity::{goal_dict, validity_pymethods, View};
pub use borrowed::{lend_problem, lend_setup, Borrowed, Lent, Unavailable};

/// A Python exception raised inside a Python planner, with its traceback.
#[derive(Debug)]
pub struct PythonError(pub String);

impl fmt::Display for PythonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PythonError {}

/// `planner` raised `e`: its type, message and traceback as text.
fn python_error(py: Python<'_>, planner: &str, e: &PyErr) -> PythonError {
    let traceback = e.traceback(py).and_then(|t| t.format().ok()).unwrap_or_default();
    PythonError(format!("python planner `{planner}` raised {e}\n{traceback}").trim_end().to_string())
}

/// The name of a Python planner: its `name` attribute (a string or a method returning one),
/// else its class name.
pub fn planner_name(obj: &Bound<'_, PyAny>) -> String {
    if let Ok(n) = obj.getattr("name") {
        let n = if n.is_callable() { n.call0().ok() } else { Some(n) };
        if let Some(s) = n.and_then(|n| n.extract::<String>().ok()) {
            return s;
        }
    }
    obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "python planner".into())
}

/// What a grasp planner may know about the hand (palm-frame axes, preshapes, aperture).
#[pyclass(name = "HandInfo", module = "opengrasp", frozen)]
#[derive(Clone)]
pub struct PyHandInfo {
    pub(crate) info: HandInfo,
}

#[pymethods]
impl PyHandInfo {
    /// The hand's name.
    #[getter]
    fn name(&self) -> String {
        self.info.name.clone()
    }
    /// Direction the palm faces (unit, palm frame).
    #[getter]
    fn approach<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.info.approach.as_slice().to_vec())
    }
    /// Direction opposing fingers close along (unit, palm frame).
    #[getter]
    fn closing<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.info.closing.as_slice().to_vec())
    }
    /// Names of the preshapes; the first is the default.
    #[getter]
    fn preshapes(&self) -> Vec<String> {
        self.info.preshapes.clone()
    }
    /// Widest object the open hand encloses (m).
    #[getter]
    fn max_aperture(&self) -> f64 {
        self.info.max_aperture
    }
    fn __repr__(&self) -> String {
        format!("HandInfo(name={:?}, max_aperture={})", self.info.name, self.info.max_aperture)
    }
}

/// The input of a grasp planner: hand info, the object's surface and the seed.
#[pyclass(name = "GraspRequest", module = "opengrasp", frozen)]
pub struct PyGraspRequest {
    /// The hand.
    #[pyo3(get)]
    hand: Py<PyHandInfo>,
    /// Object surface vertices, `(V, 3)` float64 (object frame, m).
    #[pyo3(get)]
    vertices: Py<PyArray2<f64>>,
    /// Triangles as vertex indices, `(T, 3)` int64, counter-clockwise seen from outside.
    #[pyo3(get)]
    triangles: Py<PyArray2<i64>>,
    /// Seed for every random choice (same seed, same candidates).
    #[pyo3(get)]
    seed: u64,
}

#[pymethods]
impl PyGraspRequest {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "GraspRequest(hand={:?}, vertices={}, seed={})",
            self.hand.get().info.name,
            self.vertices.bind(py).len().unwrap_or(0),
            self.seed
        )
    }
}

impl PyGraspRequest {
    fn new(py: Python<'_>, request: &GraspRequest<'_>) -> Result<Self> {
        let v: Vec<Vec<f64>> = request.object.vertices().iter().map(|p| vec![p.x, p.y, p.z]).collect();
        let flat: Vec<i64> = request.object.triangles().iter().flat_map(|t| t.map(i64::from)).collect();
        let triangles =
            PyArray1::from_vec(py, flat).reshape([request.object.triangles().len(), 3]).map_err(Error::input)?;
        Ok(Self {
            hand: Py::new(py, PyHandInfo { info: request.hand.clone() })?,
            vertices: array_2d(py, &v, 3)?.unbind(),
            triangles: triangles.unbind(),
            seed: request.seed,
        })
    }
}

/// A candidate grasp: palm pose in the object frame (4×4), approach direction (object frame;
/// the hand moves along it towards the object), preshape (`None`: the default, a preshape
/// name, or closing-joint values) and standoff (m).
#[pyclass(name = "GraspCandidate", module = "opengrasp", frozen)]
#[derive(Clone)]
pub struct PyGraspCandidate {
    pub(crate) candidate: GraspCandidate,
}

/// A preshape from Python: `None`, a name or joint values.
pub fn preshape(obj: Option<&Bound<'_, PyAny>>) -> Result<Preshape> {
    match obj {
        None => Ok(Preshape::Default),
        Some(o) if o.is_none() => Ok(Preshape::Default),
        Some(o) => {
            if let Ok(s) = o.extract::<String>() {
                Ok(Preshape::Named(s))
            } else {
                Ok(Preshape::Joints(vector(o, "preshape", None)?))
            }
        }
    }
}

#[pymethods]
impl PyGraspCandidate {
    #[new]
    #[pyo3(signature = (pose, approach, preshape = None, standoff = 0.0))]
    fn py_new(
        pose: &Bound<'_, PyAny>,
        approach: &Bound<'_, PyAny>,
        preshape: Option<&Bound<'_, PyAny>>,
        standoff: f64,
    ) -> PyResult<Self> {
        let hand_pose = isometry(pose, "pose")?;
        let a = vector3(approach, "approach")?;
        let approach = Unit::try_new(a, 1e-12).ok_or_else(|| Error::input("approach: zero vector"))?;
        if !standoff.is_finite() {
            return Err(Error::input("standoff: not finite").into());
        }
        Ok(Self { candidate: GraspCandidate { hand_pose, preshape: self::preshape(preshape)?, approach, standoff } })
    }
    /// Palm pose in the object frame (4×4).
    #[getter]
    fn pose<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        Ok(matrix(py, &self.candidate.hand_pose)?)
    }
    /// Approach direction (unit, object frame).
    #[getter]
    fn approach<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.candidate.approach.as_slice().to_vec())
    }
    /// Standoff (m).
    #[getter]
    fn standoff(&self) -> f64 {
        self.candidate.standoff
    }
    fn __repr__(&self) -> String {
        let t = self.candidate.hand_pose.translation.vector;
        format!("GraspCandidate(position=[{:.4}, {:.4}, {:.4}], standoff={})", t.x, t.y, t.z, self.candidate.standoff)
    }
}

/// The palm pose (4×4, object frame) that puts the palm origin at `point` with the hand's
/// approach axis along `approach` and its closing axis as close as possible to `closing`.
#[pyfunction(name = "palm_pose")]
pub fn py_palm_pose<'py>(
    py: Python<'py>,
    hand: &PyHandInfo,
    point: &Bound<'py, PyAny>,
    approach: &Bound<'py, PyAny>,
    closing: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let p = Point3::from(vector3(point, "point")?);
    let a =
        Unit::try_new(vector3(approach, "approach")?, 1e-12).ok_or_else(|| Error::input("approach: zero vector"))?;
    let c: Vector3<f64> = vector3(closing, "closing")?;
    Ok(matrix(py, &palm_pose(&hand.info, &p, &a, &c))?)
}

/// A Python object with `plan(request) -> list[GraspCandidate]` as a Rust `GraspPlanner`.
pub struct PyGraspPlanner {
    name: String,
    object: Py<PyAny>,
}

impl PyGraspPlanner {
    /// Wraps `object` (its name from [`planner_name`]).
    pub fn new(object: &Bound<'_, PyAny>) -> Result<Self> {
        if !object.hasattr("plan")? {
            return Err(Error::input("a grasp planner needs a plan(request) method"));
        }
        Ok(Self { name: planner_name(object), object: object.clone().unbind() })
    }
}

impl GraspPlanner for PyGraspPlanner {
    fn name(&self) -> &str {
        &self.name
    }

    fn plan(&self, request: &GraspRequest<'_>) -> opengrasp_grasp::Result<Vec<GraspCandidate>> {
        Python::attach(|py| {
            let run = || -> PyResult<Vec<GraspCandidate>> {
                let req = Py::new(py, PyGraspRequest::new(py, request)?)?;
                let out = self.object.bind(py).call_method1("plan", (req,))?;
                let mut candidates = Vec::new();
                for item in out.try_iter()? {
                    let c: PyRef<'_, PyGraspCandidate> = item?.extract().map_err(|_| {
                        pyo3::exceptions::PyTypeError::new_err(
                            "plan() must return an iterable of opengrasp.GraspCandidate",
                        )
                    })?;
                    candidates.push(c.candidate.clone());
                }
                Ok(candidates)
            };
            run().map_err(|e| GraspError::Other(Box::new(python_error(py, &self.name, &e))))
        })
    }
}

/// A planning query handed to a Python motion planner's `plan` (or, without start and goal,
/// a scene handed to `setup`). Valid only during that call.
#[pyclass(name = "Problem", module = "opengrasp")]
pub struct PyProblem {
    lent: Lent,
    started: Instant,
    robot: std::sync::OnceLock<Arc<Robot>>,
}

const EXPIRED: &str = "this Problem was lent for one plan() or setup() call and is no longer valid";

fn unavailable(u: Unavailable) -> Error {
    match u {
        Unavailable::Expired => Error::new(Kind::Base, EXPIRED),
        Unavailable::WrongThread => {
            Error::new(Kind::Base, "a Problem can only be used on the thread that called plan()")
        }
    }
}

impl PyProblem {
    fn new(lent: Lent) -> Self {
        Self { lent, started: Instant::now(), robot: std::sync::OnceLock::new() }
    }

    fn view<R>(&self, f: impl FnOnce(&View<'_>) -> Result<R>) -> Result<R> {
        self.lent
            .with(|b| {
                let (checker, robot, group, q_full): (&dyn StateValidityChecker, _, _, _) = match b {
                    Borrowed::Problem(p) => (p.checker, p.robot, p.group, p.q_full),
                    Borrowed::Setup(s) => (s.checker, s.robot, s.group, s.q_full),
                };
                f(&View { checker, robot, group, q_full })
            })
            .unwrap_or_else(|u| Err(unavailable(u)))
    }

    fn problem<R>(&self, f: impl FnOnce(&PlanningProblem<'_>) -> Result<R>) -> Result<R> {
        self.lent
            .with(|b| match b {
                Borrowed::Problem(p) => f(p),
                Borrowed::Setup(_) => {
                    Err(Error::input("setup() has no query: start, goal and time limit exist in plan()"))
                }
            })
            .unwrap_or_else(|u| Err(unavailable(u)))
    }
}

validity_pymethods!(PyProblem {
    /// Start configuration (group values).
    #[getter]
    fn start<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(self.problem(|p| Ok(array(py, p.start.to_vec())))?)
    }

    /// The goal: a dict with `kind` (`"configuration"`, `"configuration set"`, `"pose"`) and
    /// `configuration` (dim,), `configurations` (n, dim) or `tip`, `target` (4×4, root frame),
    /// `position_tolerance`, `orientation_tolerance`.
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        Ok(self.problem(|p| goal_dict(py, p.robot, p.goal))?)
    }

    /// The wall-clock budget of `plan` (s).
    #[getter]
    fn time_limit(&self) -> PyResult<f64> {
        Ok(self.problem(|p| Ok(p.time_limit.as_secs_f64()))?)
    }

    /// Seconds left of the time limit (negative once exceeded).
    fn time_left(&self) -> PyResult<f64> {
        Ok(self.problem(|p| Ok(p.time_limit.as_secs_f64() - self.started.elapsed().as_secs_f64()))?)
    }

    /// The seed of the planner's random choices (e.g. `numpy.random.default_rng(seed)`).
    #[getter]
    fn seed(&self) -> PyResult<u64> {
        Ok(self
            .lent
            .with(|b| match b {
                Borrowed::Problem(p) => p.seed,
                Borrowed::Setup(s) => s.seed,
            })
            .map_err(unavailable)?)
    }

    /// Discrete checking step along segments (C-space norm; default 0.02).
    #[getter]
    fn step(&self) -> PyResult<f64> {
        Ok(self
            .lent
            .with(|b| match b {
                Borrowed::Problem(p) => p.step,
                Borrowed::Setup(s) => s.step,
            })
            .map_err(unavailable)?)
    }

    /// The robot (a copy, made on first access).
    #[getter]
    fn robot(&self) -> PyResult<PyRobot> {
        if let Some(r) = self.robot.get() {
            return Ok(PyRobot::new(r.clone()));
        }
        let r = self.view(|v| Ok(Arc::new(v.robot.clone())))?;
        Ok(PyRobot::new(self.robot.get_or_init(|| r).clone()))
    }

    /// True if group configuration `q` satisfies the goal (configurations within 1e-6, poses
    /// within the goal's tolerances).
    fn satisfies_goal(&self, q: &Bound<'_, PyAny>) -> PyResult<bool> {
        Ok(self.problem(|p| {
            let q = vector(q, "q", Some(p.group.len()))?;
            Ok(p.satisfies_goal(&q))
        })?)
    }

    /// One attempt at a valid goal configuration for a pose goal (IK from a random start drawn
    /// with `seed`), or `None`.
    fn sample_ik_goal<'py>(&self, py: Python<'py>, seed: u64) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        use rand::SeedableRng;
        Ok(self.problem(|p| {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let limits = p.limits();
            Ok(p.sample_ik_goal(&mut rng, &limits).map(|g| array(py, g)))
        })?)
    }

    /// True while the problem may be used (during the `plan` / `setup` call).
    #[getter]
    fn active(&self) -> bool {
        self.lent.is_active()
    }

    fn __repr__(&self) -> String {
        match self.lent.with(|b| match b {
            Borrowed::Problem(p) => format!("Problem(dim={}, goal={:?})", p.group.len(), p.goal.kind()),
            Borrowed::Setup(s) => format!("Problem(setup, dim={})", s.group.len()),
        }) {
            Ok(s) => s,
            Err(_) => "Problem(expired)".into(),
        }
    }
});

/// A Python motion planner as a Rust `MotionPlanner`: one instance per job, made by calling a
/// Python factory (a class or a function) under the GIL.
pub struct PyMotionPlanner {
    name: String,
    /// The Python planner, or the error its factory raised (reported by every `plan`).
    object: std::result::Result<Py<PyAny>, String>,
}

impl PyMotionPlanner {
    /// Calls `factory()` for a fresh planner.
    pub fn create(py: Python<'_>, factory: &Py<PyAny>, name: &str) -> Self {
        let object = factory.bind(py).call0().and_then(|o| {
            if o.hasattr("plan")? {
                Ok(o.unbind())
            } else {
                Err(pyo3::exceptions::PyTypeError::new_err("a motion planner needs a plan(problem) method"))
            }
        });
        Self { name: name.to_string(), object: object.map_err(|e| python_error(py, name, &e).0) }
    }
}

fn other(e: impl Into<String>) -> MotionError {
    MotionError::Other(Box::new(PythonError(e.into())))
}

/// A path from a planner's return value: `(K, dim)` array-like or a dict with `path` and
/// optionally `iterations`; `None` is a time-out.
fn solution(out: &Bound<'_, PyAny>, dim: usize, time_limit: f64) -> std::result::Result<Solution, MotionError> {
    if out.is_none() {
        return Err(MotionError::Timeout { seconds: time_limit });
    }
    let (path, iterations) = match out.cast::<PyDict>() {
        Ok(d) => {
            let path =
                d.get_item("path").ok().flatten().ok_or_else(|| other("plan() returned a dict without `path`"))?;
            let it = d.get_item("iterations").ok().flatten().and_then(|i| i.extract::<u64>().ok()).unwrap_or(0);
            (path, it)
        }
        Err(_) => (out.clone(), 0),
    };
    if path.is_none() {
        return Err(MotionError::Timeout { seconds: time_limit });
    }
    let path = if path.cast::<PyList>().is_ok_and(|l| l.is_empty()) {
        Vec::new()
    } else {
        rows(&path, "path", Some(dim)).map_err(|e| other(format!("plan() returned a bad path: {}", e.message)))?
    };
    Ok(Solution { path, iterations })
}

impl MotionPlanner for PyMotionPlanner {
    fn name(&self) -> &str {
        &self.name
    }

    fn setup(&mut self, context: &SetupContext<'_>) -> opengrasp_motion::Result<()> {
        let object = self.object.as_ref().map_err(|e| other(e.clone()))?;
        Python::attach(|py| {
            let obj = object.bind(py);
            if !obj.hasattr("setup").unwrap_or(false) {
                return Ok(());
            }
            lend_setup(context, |lent| {
                let p = Py::new(py, PyProblem::new(lent)).map_err(|e| other(e.to_string()))?;
                obj.call_method1("setup", (p,)).map(|_| ()).map_err(|e| other(python_error(py, &self.name, &e).0))
            })
        })
    }

    fn plan(&mut self, problem: &PlanningProblem<'_>) -> opengrasp_motion::Result<Solution> {
        let object = self.object.as_ref().map_err(|e| other(e.clone()))?;
        problem.validate()?;
        Python::attach(|py| {
            lend_problem(problem, |lent| {
                let p = Py::new(py, PyProblem::new(lent)).map_err(|e| other(e.to_string()))?;
                let out = object
                    .bind(py)
                    .call_method1("plan", (p,))
                    .map_err(|e| other(python_error(py, &self.name, &e).0))?;
                solution(&out, problem.group.len(), problem.time_limit.as_secs_f64())
            })
        })
    }
}
