//! `opengrasp.Robot`: robot models (URDF + SRDF, samples, the stock humanoid), forward
//! kinematics, Jacobians and inverse kinematics with numpy arrays.

use std::sync::Arc;

use nalgebra::{Isometry3, Matrix6xX, Point3};
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use opengrasp_core::kinematics::{
    forward_kinematics, forward_kinematics_into, jacobian_into, solve_ik, IkOptions, IkStatus,
};
use opengrasp_core::model::{samples, JointGroup, LinkId, Robot};
use opengrasp_core::srdf::Srdf;
use opengrasp_core::urdf;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{array, array_2d, isometry, matrix, vector, vector3, with_rows};
use crate::errors::{guard, Error, Result};

/// A robot model: links, joints, joint limits and named joint groups.
///
/// Configurations are full configurations (`dof` values in `joint_names` order) unless a
/// method takes a `group`, whose configurations hold one value per group joint.
#[pyclass(name = "Robot", module = "opengrasp", frozen)]
pub struct PyRobot {
    pub(crate) robot: Arc<Robot>,
}

impl PyRobot {
    pub(crate) fn new(robot: Arc<Robot>) -> Self {
        Self { robot }
    }

    fn link(&self, name: Option<&str>) -> Result<LinkId> {
        match name {
            Some(n) => Ok(self.robot.link_id(n)?),
            None => {
                // The last link of the model: the tip of a serial chain.
                let n = self.robot.links().len();
                if n == 0 {
                    return Err(Error::input("the robot has no links"));
                }
                Ok(LinkId(n - 1))
            }
        }
    }

    pub(crate) fn group(&self, name: Option<&str>) -> Result<JointGroup> {
        match name {
            Some(n) => Ok(self.robot.group(n)?.clone()),
            None => Ok(JointGroup::all(&self.robot, "all")?),
        }
    }

    fn configuration(&self, q: &Bound<'_, PyAny>) -> Result<Vec<f64>> {
        vector(q, "q", Some(self.robot.dof()))
    }
}

#[pymethods]
impl PyRobot {
    /// Loads a robot from a URDF file (meshes next to it or by `package://` URI), applying
    /// an SRDF file's groups and disabled collisions if given.
    ///
    /// Raises `ModelError` for a malformed file, `OpenGraspError` for I/O errors.
    #[staticmethod]
    #[pyo3(signature = (path, srdf = None))]
    fn from_urdf(path: std::path::PathBuf, srdf: Option<std::path::PathBuf>) -> PyResult<Self> {
        let mut robot = urdf::load_file(&path).map_err(Error::from)?;
        if let Some(s) = srdf {
            Srdf::load_file(&s).and_then(|d| d.apply(&mut robot)).map_err(Error::from)?;
        }
        Ok(Self::new(Arc::new(robot)))
    }

    /// Parses URDF text (primitive geometry only: meshes cannot be resolved), applying SRDF
    /// text if given.
    #[staticmethod]
    #[pyo3(signature = (urdf_text, srdf_text = None))]
    fn from_urdf_string(urdf_text: &str, srdf_text: Option<&str>) -> PyResult<Self> {
        let mut robot = urdf::from_str(urdf_text, &urdf::InMemoryResolver::new()).map_err(Error::from)?;
        if let Some(s) = srdf_text {
            Srdf::parse(s).and_then(|d| d.apply(&mut robot)).map_err(Error::from)?;
        }
        Ok(Self::new(Arc::new(robot)))
    }

    /// The planar arm with revolute joints about z and links of the given lengths along x
    /// (joints `joint_0`, ...; the last link is the tip; group `arm`).
    #[staticmethod]
    #[pyo3(signature = (lengths = vec![0.5, 0.4]))]
    fn planar_arm(lengths: Vec<f64>) -> PyResult<Self> {
        Ok(Self::new(Arc::new(samples::planar_arm(&lengths).map_err(Error::from)?)))
    }

    /// Core's 7-DoF sample arm (group `arm`, tip link `tool`): the stand-in scenes' robot.
    #[staticmethod]
    fn seven_dof_arm() -> PyResult<Self> {
        Ok(Self::new(Arc::new(samples::seven_dof_arm().map_err(Error::from)?)))
    }

    /// A serial chain of `n` revolute joints (alternating axes).
    #[staticmethod]
    fn serial_chain(n: usize) -> PyResult<Self> {
        Ok(Self::new(Arc::new(samples::serial_chain(n).map_err(Error::from)?)))
    }

    /// The stock ARMAR-III-like humanoid of the standard world.
    #[staticmethod]
    fn armar3() -> Self {
        Self::new(Arc::new(opengrasp_assets::robots::armar3()))
    }

    /// The robot's name.
    #[getter]
    fn name(&self) -> String {
        self.robot.name().to_string()
    }

    /// Number of configuration values.
    #[getter]
    fn dof(&self) -> usize {
        self.robot.dof()
    }

    /// Names of the actuated joints, in configuration order.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        (0..self.robot.dof()).map(|i| self.robot.joint(self.robot.dof_joint(i)).name.clone()).collect()
    }

    /// Names of the links, in the order of `fk_all`.
    #[getter]
    fn link_names(&self) -> Vec<String> {
        self.robot.links().iter().map(|l| l.name.clone()).collect()
    }

    /// Joint limits as a `(dof, 2)` array of `(lower, upper)`.
    #[getter]
    fn limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = (0..self.robot.dof())
            .map(|i| {
                let (lo, hi) = self.robot.dof_limits(i);
                vec![lo, hi]
            })
            .collect();
        Ok(array_2d(py, &rows, 2)?)
    }

    /// The home configuration (zeros clamped into the limits).
    fn home<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.robot.home_configuration())
    }

    /// The named joint groups: `{name: [joint names]}`.
    #[getter]
    fn groups(&self) -> Vec<(String, Vec<String>)> {
        self.robot.groups().iter().map(|g| (g.name().to_string(), g.joint_names().to_vec())).collect()
    }

    /// Configuration indices of a group's joints (`None`: every joint).
    #[pyo3(signature = (group = None))]
    fn group_indices(&self, group: Option<&str>) -> PyResult<Vec<usize>> {
        Ok(self.group(group)?.dofs().to_vec())
    }

    /// Pose (4×4) of `link` (default: the last link) in the robot's root frame at `q`.
    #[pyo3(signature = (q, link = None))]
    fn fk<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        link: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.configuration(q)?;
        let id = self.link(link)?;
        let pose = opengrasp_core::kinematics::link_pose(&self.robot, &q, id).map_err(Error::from)?;
        Ok(matrix(py, &pose)?)
    }

    /// Poses of every link at `q` as an `(n_links, 4, 4)` array (order of `link_names`).
    fn fk_all<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let q = self.configuration(q)?;
        let poses = forward_kinematics(&self.robot, &q).map_err(Error::from)?;
        Ok(stack_poses(py, poses.as_slice())?)
    }

    /// Poses of `link` (default: the last link) for a batch of configurations `(N, dof)`, as
    /// an `(N, 4, 4)` array. The GIL is released while Rust computes.
    #[pyo3(signature = (qs, link = None))]
    fn fk_batch<'py>(
        &self,
        py: Python<'py>,
        qs: &Bound<'py, PyAny>,
        link: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let id = self.link(link)?;
        let robot = self.robot.clone();
        let poses = with_rows(qs, "qs", robot.dof(), |data, n| {
            let dof = robot.dof();
            Ok(py.detach(|| {
                let mut buffer = Vec::new();
                let mut out = Vec::with_capacity(n);
                for r in 0..n {
                    forward_kinematics_into(&robot, &data[r * dof..(r + 1) * dof], &mut buffer);
                    out.push(buffer[id.0]);
                }
                out
            }))
        })?;
        Ok(stack_poses(py, &poses)?)
    }

    /// The 6×k geometric Jacobian of a point on `link` (rows: linear velocity, angular
    /// velocity, in the root frame) with respect to the joints of `group` (default: all).
    ///
    /// `point` is in the link frame (default: the link origin).
    #[pyo3(signature = (q, link = None, point = None, group = None))]
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        link: Option<&str>,
        point: Option<&Bound<'py, PyAny>>,
        group: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.configuration(q)?;
        let id = self.link(link)?;
        let p = match point {
            Some(p) => Point3::from(vector3(p, "point")?),
            None => Point3::origin(),
        };
        let group = self.group(group)?;
        let mut out = Matrix6xX::zeros(group.len());
        jacobian_into(&self.robot, &q, id, &p, group.dofs(), &mut out);
        let rows: Vec<Vec<f64>> = (0..6).map(|r| (0..group.len()).map(|c| out[(r, c)]).collect()).collect();
        Ok(array_2d(py, &rows, group.len())?)
    }

    /// Inverse kinematics: moves the joints of `group` (default: all) so that `link`
    /// (default: the last link) reaches `target` (4×4, root frame), starting from `q_start`
    /// (default: home). Damped least squares with seeded random restarts.
    ///
    /// Returns a dict: `q` (full configuration), `converged`, `status` (`"converged"`,
    /// `"unreachable"`, `"at joint limits"`), `position_error` (m), `orientation_error`
    /// (rad), `iterations`, `restarts`. Not converging is not an error.
    #[pyo3(signature = (target, link = None, group = None, q_start = None, position_only = false,
        position_tolerance = 1e-6, orientation_tolerance = 1e-6, max_iterations = 100, max_restarts = 50, seed = 0))]
    #[allow(clippy::too_many_arguments)]
    fn ik<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
        link: Option<&str>,
        group: Option<&str>,
        q_start: Option<&Bound<'py, PyAny>>,
        position_only: bool,
        position_tolerance: f64,
        orientation_tolerance: f64,
        max_iterations: usize,
        max_restarts: usize,
        seed: u64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let target: Isometry3<f64> = isometry(target, "target")?;
        let id = self.link(link)?;
        let group = self.group(group)?;
        let start = match q_start {
            Some(q) => self.configuration(q)?,
            None => self.robot.home_configuration(),
        };
        let options = IkOptions {
            position_tolerance,
            orientation_tolerance,
            max_iterations,
            max_restarts,
            seed,
            position_only,
            ..IkOptions::default()
        };
        let robot = self.robot.clone();
        let sol = py.detach(|| guard(|| Ok(solve_ik(&robot, &group, id, &target, &start, &options)?)))?;
        let d = PyDict::new(py);
        d.set_item("q", array(py, sol.q))?;
        d.set_item("converged", sol.status == IkStatus::Converged)?;
        d.set_item(
            "status",
            match sol.status {
                IkStatus::Converged => "converged",
                IkStatus::Unreachable => "unreachable",
                IkStatus::AtJointLimits => "at joint limits",
            },
        )?;
        d.set_item("position_error", sol.position_error)?;
        d.set_item("orientation_error", sol.orientation_error)?;
        d.set_item("iterations", sol.iterations)?;
        d.set_item("restarts", sol.restarts)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!("Robot(name={:?}, dof={}, links={})", self.robot.name(), self.robot.dof(), self.robot.links().len())
    }
}

/// Stacks poses into an `(n, 4, 4)` array.
pub(crate) fn stack_poses<'py>(py: Python<'py>, poses: &[Isometry3<f64>]) -> Result<Bound<'py, PyArray3<f64>>> {
    let mut flat = Vec::with_capacity(poses.len() * 16);
    for p in poses {
        let m = p.to_homogeneous();
        for r in 0..4 {
            for c in 0..4 {
                flat.push(m[(r, c)]);
            }
        }
    }
    PyArray1::from_vec(py, flat).reshape([poses.len(), 4, 4]).map_err(Error::input)
}
