//! Grasping from Python: stock and user hands and objects, grasp quality of contacts (force
//! closure, Ferrari-Canny ε, volume) and the benchmark's grasp evaluator on a hand pose.

use nalgebra::{Point3, Unit};
use numpy::{PyArray1, PyArray2};
use opengrasp_core::hand::Hand;
use opengrasp_core::object::ObjectModel;
use opengrasp_grasp::evaluator::{EvaluatorOptions, GraspEvaluator};
use opengrasp_grasp::planners::GraspCandidate;
use opengrasp_grasp::{Contact, ContactModel, ContactType, GraspQuality, ObjectFrame, QualityOptions};
use pyo3::prelude::*;

use crate::convert::{array, isometry, mesh_triangles, mesh_vertices, to_py, vector3, with_rows};
use crate::errors::{guard, Error, Result};
use crate::planners::PyHandInfo;
use crate::robot::PyRobot;

/// A hand: a robot plus its spec (palm frame, fingers, preshapes, closing motion).
///
/// `Hand(name_or_path)`: a stock hand (`"armar3"`, `"barrett"`, `"sdh"`) or a hand spec file.
#[pyclass(name = "Hand", module = "opengrasp", frozen)]
pub struct PyHand {
    pub(crate) hand: Hand,
}

#[pymethods]
impl PyHand {
    #[new]
    fn py_new(name_or_path: &str) -> PyResult<Self> {
        Ok(Self { hand: opengrasp_bench::stock::resolve_hand(name_or_path).map_err(Error::from)? })
    }
    /// The hand's name.
    #[getter]
    fn name(&self) -> String {
        self.hand.name().to_string()
    }
    /// The hand's robot model.
    #[getter]
    fn robot(&self) -> PyRobot {
        PyRobot::new(self.hand.robot_arc())
    }
    /// What a planner knows about the hand (palm-frame approach and closing axes, preshapes,
    /// aperture).
    #[getter]
    fn info(&self) -> PyResult<PyHandInfo> {
        Ok(PyHandInfo { info: opengrasp_grasp::evaluator::hand_info(&self.hand).map_err(Error::from)? })
    }
    fn __repr__(&self) -> String {
        format!("Hand({:?})", self.hand.name())
    }
}

/// An object: a closed triangle mesh (object frame) with mass and friction.
///
/// `ObjectModel(name_or_path)`: a stock KIT object (see `object_names()`) or a mesh or
/// metadata file.
#[pyclass(name = "ObjectModel", module = "opengrasp", frozen)]
pub struct PyObject {
    pub(crate) object: ObjectModel,
}

#[pymethods]
impl PyObject {
    #[new]
    fn py_new(name_or_path: &str) -> PyResult<Self> {
        Ok(Self { object: opengrasp_bench::stock::resolve_object(name_or_path).map_err(Error::from)? })
    }
    /// The object's name.
    #[getter]
    fn name(&self) -> String {
        self.object.name.clone()
    }
    /// Mass (kg).
    #[getter]
    fn mass(&self) -> f64 {
        self.object.mass()
    }
    /// Friction coefficient with the hand.
    #[getter]
    fn friction(&self) -> f64 {
        self.object.friction
    }
    /// Centre of mass (object frame, m).
    #[getter]
    fn center_of_mass<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.object.center_of_mass().coords.as_slice().to_vec())
    }
    /// Bounding-box size (m).
    #[getter]
    fn size<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.object.size().as_slice().to_vec())
    }
    /// Surface vertices, `(V, 3)`.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        Ok(mesh_vertices(py, &self.object.mesh)?)
    }
    /// Triangles, `(T, 3)` vertex indices.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        Ok(mesh_triangles(py, &self.object.mesh)?)
    }
    fn __repr__(&self) -> String {
        format!("ObjectModel({:?}, mass={})", self.object.name, self.object.mass())
    }
}

/// Names of the stock hands.
#[pyfunction]
pub fn hand_names() -> Vec<&'static str> {
    opengrasp_bench::stock::HAND_NAMES.to_vec()
}

/// Names of the stock objects.
#[pyfunction]
pub fn object_names() -> Vec<&'static str> {
    opengrasp_bench::stock::OBJECT_NAMES.to_vec()
}

fn contacts(points: &Bound<'_, PyAny>, normals: &Bound<'_, PyAny>) -> Result<Vec<Contact>> {
    let p = with_rows(points, "points", 3, |d, n| Ok((d.to_vec(), n)))?;
    let nrm = with_rows(normals, "normals", 3, |d, n| Ok((d.to_vec(), n)))?;
    if p.1 != nrm.1 {
        return Err(Error::input(format!("points has {} rows but normals has {}", p.1, nrm.1)));
    }
    (0..p.1)
        .map(|i| {
            let c = Contact::new(
                Point3::new(p.0[3 * i], p.0[3 * i + 1], p.0[3 * i + 2]),
                nalgebra::Vector3::new(nrm.0[3 * i], nrm.0[3 * i + 1], nrm.0[3 * i + 2]),
            );
            c.map_err(|e| match e {
                opengrasp_grasp::GraspError::ZeroNormal { .. } => Error::input(format!("normal {i} has zero length")),
                e => e.into(),
            })
        })
        .collect()
}

/// Quality of a grasp given by its contacts: `points` and inward `normals` `(N, 3)` in the
/// object frame, the object's `center_of_mass` and `max_radius` (torque scale; default: the
/// farthest contact from the centre of mass).
///
/// Returns a dict: `force_closure`, `epsilon` (Ferrari-Canny L1), `origin_in_hull`,
/// `min_norm_distance`, `wrench_dimension`, `degenerate`, ...; with `hull_statistics=True`
/// also the wrench-space hull's `volume` and `hull_facets` (the full 6-D hull, several times
/// slower; epsilon does not need it).
#[pyfunction]
#[pyo3(signature = (points, normals, center_of_mass = None, max_radius = None, friction = 0.5, cone_edges = 8, torsional_friction = None, hull_statistics = false))]
#[allow(clippy::too_many_arguments)]
pub fn grasp_quality<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    normals: &Bound<'py, PyAny>,
    center_of_mass: Option<&Bound<'py, PyAny>>,
    max_radius: Option<f64>,
    friction: f64,
    cone_edges: usize,
    torsional_friction: Option<f64>,
    hull_statistics: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let contacts = contacts(points, normals)?;
    let com = match center_of_mass {
        Some(c) => Point3::from(vector3(c, "center_of_mass")?),
        None => Point3::origin(),
    };
    let frame = match max_radius {
        Some(r) => ObjectFrame::new(com, r),
        None => ObjectFrame::from_points(com, &contacts.iter().map(|c| c.point).collect::<Vec<_>>()),
    }
    .map_err(Error::from)?;
    let contact_type = match torsional_friction {
        Some(t) => ContactType::SoftFinger { torsional_friction: t },
        None => ContactType::PointWithFriction,
    };
    let options = QualityOptions {
        contact: ContactModel { friction, cone_edges, contact_type },
        hull_statistics,
        ..QualityOptions::default()
    };
    let report = py.detach(|| guard(|| Ok(GraspQuality::evaluate(&contacts, &frame, &options)?)))?;
    Ok(to_py(py, &report)?)
}

/// The benchmark's grasp evaluator for one hand and one object: approach along a direction
/// until contact, close the fingers, collect contacts and grade them (the same code that
/// grades every planner in the suite).
#[pyclass(name = "GraspEvaluator", module = "opengrasp")]
pub struct PyGraspEvaluator {
    evaluator: GraspEvaluator,
    approach_palm: Unit<nalgebra::Vector3<f64>>,
}

#[pymethods]
impl PyGraspEvaluator {
    /// `GraspEvaluator(hand, object, friction=None)`: `friction` overrides the object's.
    #[new]
    #[pyo3(signature = (hand, object, friction = None))]
    fn py_new(hand: &PyHand, object: &PyObject, friction: Option<f64>) -> PyResult<Self> {
        let options = EvaluatorOptions { friction, ..EvaluatorOptions::default() };
        let evaluator = guard(|| Ok(GraspEvaluator::new(&hand.hand, &object.object, options)?))?;
        let approach_palm = evaluator.hand_info().approach;
        Ok(Self { evaluator, approach_palm })
    }

    /// Evaluates the palm pose `pose` (4×4, object frame). `approach` (object frame) defaults
    /// to the hand's approach axis at that pose; `preshape` is `None`, a name or joint values.
    ///
    /// Returns a dict: `status` (`"Closed"` / `"Missed"`), `force_closure`, `epsilon`,
    /// `hand_pose` (4×4 list), `q`, `contacts`, `palm_contact`, `fingers_in_contact`,
    /// `retraction`, `quality` (see `grasp_quality`).
    #[pyo3(signature = (pose, approach = None, preshape = None, standoff = 0.0))]
    fn evaluate<'py>(
        &mut self,
        py: Python<'py>,
        pose: &Bound<'py, PyAny>,
        approach: Option<&Bound<'py, PyAny>>,
        preshape: Option<&Bound<'py, PyAny>>,
        standoff: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        let hand_pose = isometry(pose, "pose")?;
        let approach = match approach {
            Some(a) => {
                Unit::try_new(vector3(a, "approach")?, 1e-12).ok_or_else(|| Error::input("approach: zero vector"))?
            }
            None => Unit::new_normalize(hand_pose.rotation * self.approach_palm.into_inner()),
        };
        let candidate =
            GraspCandidate { hand_pose, preshape: crate::planners::preshape(preshape)?, approach, standoff };
        let evaluator = &mut self.evaluator;
        let evaluation = py.detach(|| guard(|| Ok(evaluator.evaluate(&candidate)?)))?;
        let d = to_py(py, &evaluation)?;
        d.set_item("force_closure", evaluation.force_closure())?;
        d.set_item("epsilon", evaluation.epsilon())?;
        Ok(d)
    }
}
