//! `opengrasp.Scene`: an instance of a standard motion benchmark scene (robot, group, start,
//! goal and its validity checker), and the catalogue of scene names.

use numpy::PyArray1;
use opengrasp_bench::scenes::{armar_ik_scene, armar_standard_scene, ik_scene, standard_scene, CheckerKind};
use opengrasp_bench::suite::planar_scene;
use opengrasp_motion::benchmark::{BenchmarkScene, SceneInstance};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::array;
use crate::errors::{guard, Error, Result};
use crate::robot::PyRobot;
use crate::validity::{goal_dict, validity_pymethods, View};

/// A scene's name and constructor.
pub type SceneConstructor = (&'static str, fn() -> BenchmarkScene);

/// The motion scenes by name: the suite's standard scenes and the planar test scene.
pub fn scene_constructors() -> Vec<SceneConstructor> {
    vec![
        ("planar post", planar_scene as fn() -> BenchmarkScene),
        ("standard (7-DoF stand-in)", || standard_scene(CheckerKind::Exact)),
        ("standard (7-DoF stand-in, spheres)", || standard_scene(CheckerKind::Spheres)),
        ("IK-based (7-DoF stand-in)", || ik_scene(CheckerKind::Exact)),
        ("standard (ARMAR-III kitchen)", armar_standard_scene),
        ("IK-based (ARMAR-III kitchen)", armar_ik_scene),
    ]
}

/// The benchmark scene called `name` (ASCII case-insensitive).
pub fn scene_by_name(name: &str) -> Result<BenchmarkScene> {
    let all = scene_constructors();
    all.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)).map(|(_, f)| f()).ok_or_else(|| {
        Error::input(format!("unknown scene {name:?}; known: {:?}", all.iter().map(|(n, _)| *n).collect::<Vec<_>>()))
    })
}

/// Names of the motion scenes `Scene` and `Suite.motion_scene` accept.
#[pyfunction]
pub fn scene_names() -> Vec<&'static str> {
    scene_constructors().into_iter().map(|(n, _)| n).collect()
}

/// One instance of a standard motion scene: robot, planning group, start, goal and the
/// scene's state validity checker (the one the benchmark grades with).
///
/// `Scene(name, seed=0)`; names from `scene_names()`. Scenes whose environment changes per
/// run (the IK-based ones) place their object from `seed`.
#[pyclass(name = "Scene", module = "opengrasp", unsendable)]
pub struct PyScene {
    name: String,
    instance: SceneInstance,
}

impl PyScene {
    /// A scene object for an instance built elsewhere (e.g. a problem of a problem set).
    pub fn from_instance(name: String, instance: SceneInstance) -> Self {
        Self { name, instance }
    }

    fn view<R>(&self, f: impl FnOnce(&View<'_>) -> Result<R>) -> Result<R> {
        let i = &self.instance;
        f(&View { checker: &*i.checker, robot: &i.robot, group: &i.group, q_full: &i.q_full })
    }
}

validity_pymethods!(PyScene {
    #[new]
    #[pyo3(signature = (name, seed = 0))]
    fn py_new(name: &str, seed: u64) -> PyResult<Self> {
        let scene = scene_by_name(name)?;
        let instance = guard(|| Ok((scene.generate)(seed)?))?;
        Ok(Self { name: scene.name, instance })
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }

    /// The robot.
    #[getter]
    fn robot(&self) -> PyRobot {
        PyRobot::new(self.instance.robot.clone())
    }

    /// Start configuration (group values).
    #[getter]
    fn start<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.instance.start.clone())
    }

    /// The goal as a dict (see `Problem.goal`).
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        Ok(goal_dict(py, &self.instance.robot, &self.instance.goal)?)
    }

    /// Name of the end-effector link used for workspace metrics, if any.
    #[getter]
    fn tip(&self) -> Option<String> {
        self.instance.tip.map(|t| self.instance.robot.link(t).name.clone())
    }

    /// The benchmark's metrics of a path `(K, dim)`: waypoints, length, ee_length,
    /// clearance_mean, clearance_min, smoothness (densified at `step`).
    #[pyo3(signature = (path, step = 0.02))]
    fn path_metrics<'py>(&self, py: Python<'py>, path: &Bound<'py, PyAny>, step: f64) -> PyResult<Bound<'py, PyAny>> {
        let tip = self.instance.tip;
        Ok(self.view(|v| v.path_metrics(py, path, tip, step))?)
    }

    /// Times `is_valid` on every row of `qs` called one state at a time from a Rust loop:
    /// `(seconds, valid_count)`. The reference of the batched-validity benchmark.
    fn rust_loop_seconds(&self, qs: &Bound<'_, PyAny>) -> PyResult<(f64, usize)> {
        Ok(self.view(|v| v.rust_loop_seconds(qs))?)
    }

    fn __repr__(&self) -> String {
        format!("Scene({:?}, dim={})", self.name, self.instance.group.len())
    }
});
