//! Grasp planners: the [`GraspPlanner`] trait every entrant implements, and the two reference
//! planners of the OpenGRASP grasp benchmark (Ulbrich et al. 2011, section IV-A):
//!
//! - [`SurfaceNormalPlanner`]: approach along inverted surface normals with several roll angles
//!   and standoffs (Berenson et al. 2007, the OpenRAVE grasping database);
//! - [`MedialAxisPlanner`]: candidates derived from the symmetry structures of the object's
//!   medial axis (Przybylski et al., IROS 2010/2011).
//!
//! A planner only proposes [`GraspCandidate`]s; scoring happens in the shared
//! [`crate::evaluator`], so every planner is graded by the same criterion.

mod medial_axis;
mod surface_normal;

pub use medial_axis::{MedialAxis, MedialAxisOptions, MedialAxisPlanner, MedialBall, MedialStructure, StructureKind};
pub use surface_normal::{
    fitting_preshape, ApproachSampling, SurfaceNormalOptions, SurfaceNormalPlanner, PRESHAPE_CLEARANCE,
};

use crate::error::{GraspError, Result};
use nalgebra::{Isometry3, Point3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};
use opengrasp_core::model::TriangleMesh;
use serde::{Deserialize, Serialize};

/// What a planner may know about the hand: its name, palm-frame axes, preshapes and size.
///
/// All directions are expressed in the hand's palm frame. [`crate::evaluator::hand_info`] (or
/// [`crate::evaluator::GraspEvaluator::hand_info`]) produces this from an asset hand.
#[derive(Clone, Debug, PartialEq)]
pub struct HandInfo {
    /// The hand's name (e.g. `"barrett"`).
    pub name: String,
    /// Direction in which the palm faces, i.e. the hand moves towards the object (unit, palm frame).
    pub approach: Unit<Vector3<f64>>,
    /// Direction along which opposing fingers close (thumb towards fingers), perpendicular to
    /// `approach` (unit, palm frame).
    pub closing: Unit<Vector3<f64>>,
    /// Names of the hand's preshapes; the first is the default.
    pub preshapes: Vec<String>,
    /// Widest object the open hand can enclose between opposing fingers (m).
    pub max_aperture: f64,
    /// Per preshape (in the order of `preshapes`), the extent (m) of the open hand's geometry
    /// along `closing`: how wide an object the fingers start around. Empty if unknown (the
    /// planners then request the default preshape).
    pub preshape_apertures: Vec<f64>,
}

/// The preshape (finger configuration before closing) a candidate asks for.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum Preshape {
    /// The hand's first (default) preshape.
    #[default]
    Default,
    /// A named preshape of the hand.
    Named(String),
    /// Explicit values of the hand's closing joints (rad), in the hand's closing-joint order.
    Joints(Vec<f64>),
}

/// One candidate grasp: where the palm goes, how the fingers start, and which way the hand moves.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraspCandidate {
    /// Pose of the palm frame in the object frame. The evaluator starts here (typically in
    /// collision with the object) and retracts along `approach` until collision-free.
    pub hand_pose: Isometry3<f64>,
    /// Finger preshape before closing.
    pub preshape: Preshape,
    /// Approach direction in the object frame (unit): the hand moves along it towards the object.
    pub approach: Unit<Vector3<f64>>,
    /// Extra distance (m) the evaluator backs off after retracting to a collision-free pose,
    /// before closing the fingers (OpenRAVE's "standoff"); 0 closes right at the surface.
    pub standoff: f64,
}

/// The input of a grasp planner.
#[derive(Clone, Copy, Debug)]
pub struct GraspRequest<'a> {
    /// The hand to plan for.
    pub hand: &'a HandInfo,
    /// The object's surface in the object frame (closed, outward-oriented triangles expected).
    pub object: &'a TriangleMesh,
    /// Seed for every random choice of the planner (same seed, same candidates).
    pub seed: u64,
}

/// A grasp planner: turns a hand and an object into candidate grasps.
///
/// Implement [`GraspPlanner::plan`] (and optionally [`GraspPlanner::name`]) to enter the grasp
/// benchmark. Planners never score their own candidates: the shared evaluator does.
///
/// ```
/// use opengrasp_grasp::planners::{GraspCandidate, GraspPlanner, GraspRequest, Preshape};
/// use opengrasp_core::nalgebra::{Isometry3, Vector3, Unit};
///
/// /// Always proposes one top-down grasp at the object's origin.
/// struct TopDown;
/// impl GraspPlanner for TopDown {
///     fn name(&self) -> &str { "top-down" }
///     fn plan(&self, _req: &GraspRequest<'_>) -> opengrasp_grasp::Result<Vec<GraspCandidate>> {
///         Ok(vec![GraspCandidate {
///             hand_pose: Isometry3::identity(),
///             preshape: Preshape::Default,
///             approach: Unit::new_normalize(Vector3::new(0.0, 0.0, -1.0)),
///             standoff: 0.0,
///         }])
///     }
/// }
/// let planners: Vec<Box<dyn GraspPlanner>> = vec![Box::new(TopDown)];
/// assert_eq!(planners[0].name(), "top-down");
/// ```
///
/// Threading: a grasp planner is a pure function of its request (the seed is in it), so
/// `plan` takes `&self` and one instance is shared by the harness's parallel jobs, hence
/// `Send + Sync`. (Motion planners keep state, take `&mut self` and get one instance per job.)
pub trait GraspPlanner: Send + Sync {
    /// A short name for tables and result files (default:
    /// [`opengrasp_core::short_type_name`]).
    fn name(&self) -> &str {
        opengrasp_core::short_type_name::<Self>()
    }

    /// Proposes candidate grasps for `request.hand` on `request.object`.
    ///
    /// # Errors
    /// A [`GraspError`] for unusable input (e.g. [`GraspError::InvalidParameter`] for bad
    /// options); a user's planner may return its own error as [`GraspError::Other`].
    fn plan(&self, request: &GraspRequest<'_>) -> Result<Vec<GraspCandidate>>;
}

impl<T: GraspPlanner + ?Sized> GraspPlanner for &T {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn plan(&self, request: &GraspRequest<'_>) -> Result<Vec<GraspCandidate>> {
        (**self).plan(request)
    }
}

impl<T: GraspPlanner + ?Sized> GraspPlanner for Box<T> {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn plan(&self, request: &GraspRequest<'_>) -> Result<Vec<GraspCandidate>> {
        (**self).plan(request)
    }
}

/// The palm pose that puts the palm origin at `point` with the hand's approach axis along
/// `approach` (object frame) and its closing axis as close as possible to `closing`.
///
/// If `closing` is (nearly) parallel to `approach`, any perpendicular direction is used.
pub fn palm_pose(
    hand: &HandInfo,
    point: &Point3<f64>,
    approach: &Unit<Vector3<f64>>,
    closing: &Vector3<f64>,
) -> Isometry3<f64> {
    let a = approach.into_inner();
    let mut c = closing - a * a.dot(closing);
    if c.norm() < 1e-9 {
        c = any_perpendicular(&a);
    }
    let c = c.normalize();
    let object_basis = Rotation3::from_basis_unchecked(&[a, c, a.cross(&c)]);
    let ha = hand.approach.into_inner();
    let mut hc = hand.closing.into_inner() - ha * ha.dot(&hand.closing);
    if hc.norm() < 1e-9 {
        hc = any_perpendicular(&ha);
    }
    let hc = hc.normalize();
    let hand_basis = Rotation3::from_basis_unchecked(&[ha, hc, ha.cross(&hc)]);
    let rotation = object_basis * hand_basis.inverse();
    Isometry3::from_parts(Translation3::from(point.coords), UnitQuaternion::from_rotation_matrix(&rotation))
}

/// A unit vector perpendicular to `v` (deterministic).
pub(crate) fn any_perpendicular(v: &Vector3<f64>) -> Vector3<f64> {
    let helper = if v.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    v.cross(&helper).normalize()
}

/// Checks that a planner option is finite and positive.
pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GraspError::InvalidParameter { name, reason: format!("must be finite and > 0, got {value}") })
    }
}

/// Checks that an option is finite and non-negative.
pub(crate) fn check_non_negative(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(GraspError::InvalidParameter { name, reason: format!("must be finite and >= 0, got {value}") })
    }
}

/// The nearest intersection of the ray `origin + t·dir` (t > 0) with the mesh: `(t, triangle)`.
pub(crate) fn ray_cast(mesh: &TriangleMesh, origin: &Point3<f64>, dir: &Vector3<f64>) -> Option<(f64, usize)> {
    let v = mesh.vertices();
    let mut best: Option<(f64, usize)> = None;
    for (i, t) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = t.map(|k| v[k as usize]);
        if let Some(d) = ray_triangle(origin, dir, &a, &b, &c) {
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, i));
            }
        }
    }
    best
}

/// Möller–Trumbore ray/triangle intersection: the ray parameter of the hit, if any (t > 0).
pub(crate) fn ray_triangle(
    origin: &Point3<f64>,
    dir: &Vector3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Option<f64> {
    let e1 = b - a;
    let e2 = c - a;
    let p = dir.cross(&e2);
    let det = e1.dot(&p);
    if det.abs() < 1e-14 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - a;
    let u = s.dot(&p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(&e1);
    let w = dir.dot(&q) * inv;
    if w < 0.0 || u + w > 1.0 {
        return None;
    }
    let t = e2.dot(&q) * inv;
    (t > 1e-12).then_some(t)
}

/// Outward unit normal of triangle `i` (counter-clockwise seen from outside).
pub(crate) fn triangle_normal(mesh: &TriangleMesh, i: usize) -> Vector3<f64> {
    let v = mesh.vertices();
    let [a, b, c] = mesh.triangles()[i].map(|k| v[k as usize]);
    (b - a).cross(&(c - a)).normalize()
}
