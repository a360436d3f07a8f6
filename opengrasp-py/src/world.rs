//! The standard world's geometry and motion problem sets from files: `opengrasp.kitchen()`,
//! `opengrasp.load_problem_sets(path)` and `opengrasp.ProblemSet`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use opengrasp_assets::export::scene_meshes;
use opengrasp_core::scene::Scene;
use opengrasp_motion::problem_set::LoadedProblemSet;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::convert::{array, matrix, mesh_triangles, mesh_vertices};
use crate::errors::{guard, Error, Result};
use crate::robot::PyRobot;
use crate::scene::PyScene;
use crate::validity::goal_dict;

/// Every shape of `scene` as a list of dicts `{"name", "vertices" (V, 3), "triangles" (T, 3)}`
/// in world coordinates (metres).
fn meshes<'py>(py: Python<'py>, scene: &Scene) -> Result<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for (name, mesh) in scene_meshes(scene)? {
        let d = PyDict::new(py);
        d.set_item("name", name)?;
        d.set_item("vertices", mesh_vertices(py, &mesh)?)?;
        d.set_item("triangles", mesh_triangles(py, &mesh)?)?;
        list.append(d)?;
    }
    Ok(list)
}

/// The standard kitchen: a dict with `meshes` (every furniture part, object and humanoid link
/// as `{"name", "vertices", "triangles"}` in world coordinates, the humanoid at its start
/// pose), `locations` (name → 4×4 world pose of the named places), `robot` (the humanoid)
/// and `start_configuration`.
#[pyfunction]
pub fn kitchen(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let kitchen = guard(|| Ok(opengrasp_assets::scenes::kitchen()?))?;
    let d = PyDict::new(py);
    d.set_item("meshes", meshes(py, &kitchen.scene)?)?;
    let locations = PyDict::new(py);
    for (name, pose) in &kitchen.locations {
        locations.set_item(name, matrix(py, pose)?)?;
    }
    d.set_item("locations", locations)?;
    d.set_item("robot", PyRobot::new(kitchen.scene.robot(kitchen.robot).map_err(Error::from)?.robot.clone()))?;
    d.set_item("start_configuration", array(py, kitchen.start_configuration.clone()))?;
    Ok(d)
}

/// Loads the motion problem sets at `path`: a JSON problem-set file (format
/// `opengrasp-problem-set`), a MotionBenchMaker set directory or a directory of them. Robot
/// files are loaded and every problem is checked; errors raise `ModelError` /
/// `InvalidInputError` with the loader's message.
#[pyfunction]
pub fn load_problem_sets(py: Python<'_>, path: PathBuf) -> PyResult<Vec<PyProblemSet>> {
    Ok(load_sets(py, &path)?.into_iter().map(|set| PyProblemSet { set: Arc::new(set) }).collect())
}

/// The problem sets at `path`, loaded with the GIL released (robot files and meshes can take
/// a while); panics become `OpenGraspError`.
pub(crate) fn load_sets(py: Python<'_>, path: &Path) -> Result<Vec<LoadedProblemSet>> {
    py.detach(|| guard(|| Ok(opengrasp_bench::problem_sets::load_problem_sets(path)?)))
}

/// A loaded motion problem set: a robot, a planning group and problems (obstacles, start,
/// goal). `len(set)` problems; `set.scene(i)` is problem `i` as a `Scene` (the exact
/// checker the benchmark grades with), `set.meshes(i)` its geometry.
#[pyclass(name = "ProblemSet", module = "opengrasp", frozen)]
pub struct PyProblemSet {
    pub(crate) set: Arc<LoadedProblemSet>,
}

#[pymethods]
impl PyProblemSet {
    /// The set's name (the motion scene name in results).
    #[getter]
    fn name(&self) -> String {
        self.set.name().to_string()
    }

    /// The robot.
    #[getter]
    fn robot(&self) -> PyRobot {
        PyRobot::new(self.set.robot().clone())
    }

    /// Names of the planning group's joints.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.set.group().joint_names().to_vec()
    }

    /// The problems' names, in order.
    #[getter]
    fn problem_names(&self) -> Vec<String> {
        (0..self.set.len()).filter_map(|i| self.set.problem_name(i)).map(str::to_string).collect()
    }

    /// Problem `i`'s goal as a dict (see `Problem.goal`).
    fn goal<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyDict>> {
        let goal = self.set.goal(i).ok_or_else(|| self.out_of_range(i))?;
        Ok(goal_dict(py, self.set.robot(), goal)?)
    }

    /// Problem `i` as a `Scene`: start, goal, limits and the exact validity checker.
    fn scene(&self, i: usize) -> PyResult<PyScene> {
        let name = format!("{} / {}", self.set.name(), self.set.problem_name(i).ok_or_else(|| self.out_of_range(i))?);
        let instance = guard(|| Ok(self.set.instance(i)?))?;
        Ok(PyScene::from_instance(name, instance))
    }

    /// Problem `i`'s geometry: obstacles and robot links (at the start configuration) as
    /// `{"name", "vertices", "triangles"}` dicts in world coordinates.
    fn meshes<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyList>> {
        let scene = guard(|| Ok(self.set.scene(i)?))?;
        Ok(meshes(py, &scene)?)
    }

    fn __len__(&self) -> usize {
        self.set.len()
    }

    fn __repr__(&self) -> String {
        format!("ProblemSet({:?}, problems={}, dim={})", self.set.name(), self.set.len(), self.set.group().len())
    }
}

impl PyProblemSet {
    fn out_of_range(&self, i: usize) -> Error {
        Error::input(format!("problem index {i} out of range (the set has {})", self.set.len()))
    }
}
