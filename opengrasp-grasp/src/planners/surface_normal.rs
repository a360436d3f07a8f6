//! The surface-normal grasp planner of Berenson et al. (Humanoids 2007), as in OpenRAVE's
//! grasping database: the hand approaches surface points along the inverted surface normal,
//! with several roll angles about the approach axis and several standoffs.

use std::f64::consts::PI;

use crate::error::{GraspError, Result};
use nalgebra::{Point3, Rotation3, Unit, Vector3};
use opengrasp_core::model::TriangleMesh;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{
    any_perpendicular, check_positive, palm_pose, ray_cast, triangle_normal, GraspCandidate, GraspPlanner,
    GraspRequest, Preshape,
};

/// How the surface points (and normals) to approach are chosen.
#[derive(Clone, Debug, PartialEq)]
pub enum ApproachSampling {
    /// OpenRAVE's `computeBoxApproachRays`: a regular grid of rays on each face of the object's
    /// bounding box, spaced `delta` (m), cast inwards; each hit gives a point and its normal.
    /// Deterministic. Cells are centred, so a face of extent `e` gets `max(1, round(e / delta))`
    /// rays along that side.
    BoxGrid {
        /// Grid spacing (m). OpenRAVE's default is 0.02.
        delta: f64,
    },
    /// `count` points sampled uniformly over the surface (area-weighted), seeded by the request.
    AreaWeighted {
        /// Number of surface points.
        count: usize,
    },
}

/// Options of the [`SurfaceNormalPlanner`]; the defaults are OpenRAVE's grasping-database
/// defaults (`grasping.py`, `autogenerate`).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceNormalOptions {
    /// Approach points. Default: `BoxGrid { delta: 0.02 }` (OpenRAVE `computeBoxApproachRays(delta=0.02)`).
    pub sampling: ApproachSampling,
    /// Number of roll angles about the approach axis, evenly spaced over 2π.
    /// Default: 4 (OpenRAVE `rolls = arange(0, 2π, π/2)`, a step of π/2).
    pub rolls: usize,
    /// Distances (m) the hand backs off from the surface before closing.
    /// Default: `[0.0, 0.025]` (OpenRAVE `standoffs`).
    pub standoffs: Vec<f64>,
    /// Preshapes to try at every pose. Empty: one preshape per candidate, the one that fits
    /// the object's width along the candidate's closing axis ([`fitting_preshape`]).
    /// Default: `[Preshape::Default]` (OpenRAVE uses the hand's current, released finger
    /// configuration). The fitted choice is not the default: on the paper objects it gives
    /// fewer palm-contact grasps with the stock hands (it picks the Barrett's 90° spread and
    /// the ARMAR-III's raised thumb for most objects, which then touch before the palm).
    pub preshapes: Vec<Preshape>,
}

/// Clearance (m) a fitting preshape leaves on each side of the object along the closing axis.
pub const PRESHAPE_CLEARANCE: f64 = 0.01;

/// The preshape that fits an object `width` (m) wide along the closing axis: the one with the
/// smallest aperture ([`super::HandInfo::preshape_apertures`]) of at least
/// `width + 2 · PRESHAPE_CLEARANCE` (its fingers start closest around the object), else the
/// one with the widest aperture; the hand's default if it lists no apertures. Ties go to the
/// earlier preshape.
pub fn fitting_preshape(hand: &super::HandInfo, width: f64) -> Preshape {
    let apertures = &hand.preshape_apertures;
    if apertures.is_empty() || apertures.len() != hand.preshapes.len() {
        return Preshape::Default;
    }
    let need = width + 2.0 * PRESHAPE_CLEARANCE;
    let fits =
        (0..apertures.len()).filter(|&i| apertures[i] >= need).min_by(|&i, &j| apertures[i].total_cmp(&apertures[j]));
    let widest = (0..apertures.len()).reduce(|i, j| if apertures[j] > apertures[i] { j } else { i });
    match fits.or(widest) {
        Some(0) | None => Preshape::Default,
        Some(i) => Preshape::Named(hand.preshapes[i].clone()),
    }
}

impl Default for SurfaceNormalOptions {
    fn default() -> Self {
        Self {
            sampling: ApproachSampling::BoxGrid { delta: 0.02 },
            rolls: 4,
            standoffs: vec![0.0, 0.025],
            preshapes: vec![Preshape::Default],
        }
    }
}

/// Berenson et al.'s surface-normal planner (the OpenRAVE grasping database).
///
/// Candidates: for every approach point `p` with outward normal `n`, every roll `k·2π/rolls`
/// and every standoff and preshape, the palm is put at `p` with its approach axis along `-n`;
/// the closing axis is a fixed perpendicular of `-n` rotated by the roll.
/// Candidate order: points, then rolls, then standoffs, then preshapes. Without listed
/// preshapes each pose gets the one that fits the object's width along its closing axis.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceNormalPlanner {
    /// The planner's options.
    pub options: SurfaceNormalOptions,
}

impl SurfaceNormalPlanner {
    /// A planner with the given options.
    pub fn new(options: SurfaceNormalOptions) -> Self {
        Self { options }
    }

    /// The approach points: surface points with their outward unit normals, object frame.
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] for a non-positive grid spacing.
    pub fn approach_points(&self, mesh: &TriangleMesh, seed: u64) -> Result<Vec<(Point3<f64>, Vector3<f64>)>> {
        match self.options.sampling {
            ApproachSampling::BoxGrid { delta } => {
                check_positive("surface normal grid delta", delta)?;
                Ok(box_grid_points(mesh, delta))
            }
            ApproachSampling::AreaWeighted { count } => Ok(area_weighted_points(mesh, count, seed)),
        }
    }
}

impl GraspPlanner for SurfaceNormalPlanner {
    fn name(&self) -> &str {
        "surface-normals"
    }

    fn plan(&self, request: &GraspRequest<'_>) -> Result<Vec<GraspCandidate>> {
        let o = &self.options;
        if o.rolls == 0 {
            return Err(GraspError::InvalidParameter { name: "rolls", reason: "must be at least 1".into() });
        }
        for &s in &o.standoffs {
            super::check_non_negative("standoffs", s)?;
        }
        let standoffs: &[f64] = if o.standoffs.is_empty() { &[0.0] } else { &o.standoffs };
        let points = self.approach_points(request.object, request.seed)?;
        let vertices = request.object.vertices();
        let mut fitted = [Preshape::Default];
        let mut out = Vec::with_capacity(points.len() * o.rolls * standoffs.len() * o.preshapes.len().max(1));
        for (p, n) in &points {
            let approach = Unit::new_normalize(-n);
            let reference = any_perpendicular(&approach);
            for k in 0..o.rolls {
                let roll = 2.0 * PI * k as f64 / o.rolls as f64;
                let closing = Rotation3::from_axis_angle(&approach, roll) * reference;
                let pose = palm_pose(request.hand, p, &approach, &closing);
                let preshapes: &[Preshape] = if o.preshapes.is_empty() {
                    // The object's width along the hand's closing axis at this pose.
                    let axis = pose.rotation * request.hand.closing.into_inner();
                    let (lo, hi) = vertices.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                        let t = v.coords.dot(&axis);
                        (lo.min(t), hi.max(t))
                    });
                    fitted[0] = fitting_preshape(request.hand, hi - lo);
                    &fitted
                } else {
                    &o.preshapes
                };
                for &standoff in standoffs {
                    for preshape in preshapes {
                        out.push(GraspCandidate { hand_pose: pose, preshape: preshape.clone(), approach, standoff });
                    }
                }
            }
        }
        Ok(out)
    }
}

/// OpenRAVE-style box approach rays: grid on each bounding-box face, cast inward.
fn box_grid_points(mesh: &TriangleMesh, delta: f64) -> Vec<(Point3<f64>, Vector3<f64>)> {
    let (lo, hi) = mesh.aabb();
    let ext = hi - lo;
    let mut out = Vec::new();
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let nu = ((ext[u] / delta).round() as usize).max(1);
        let nv = ((ext[v] / delta).round() as usize).max(1);
        for side in [1.0, -1.0] {
            // Rays start outside the face with normal `side·e_axis` and travel against it.
            let mut dir = Vector3::zeros();
            dir[axis] = -side;
            for i in 0..nu {
                for j in 0..nv {
                    let mut origin = Point3::origin();
                    origin[axis] = if side > 0.0 { hi[axis] + delta } else { lo[axis] - delta };
                    origin[u] = lo[u] + (i as f64 + 0.5) * ext[u] / nu as f64;
                    origin[v] = lo[v] + (j as f64 + 0.5) * ext[v] / nv as f64;
                    if let Some((t, tri)) = ray_cast(mesh, &origin, &dir) {
                        let n = triangle_normal(mesh, tri);
                        if n.dot(&dir) < 0.0 {
                            out.push((origin + dir * t, n));
                        }
                    }
                }
            }
        }
    }
    out
}

/// Area-weighted uniform surface samples with the face normal.
fn area_weighted_points(mesh: &TriangleMesh, count: usize, seed: u64) -> Vec<(Point3<f64>, Vector3<f64>)> {
    let v = mesh.vertices();
    let mut cumulative = Vec::with_capacity(mesh.triangles().len());
    let mut total = 0.0;
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|k| v[k as usize]);
        total += (b - a).cross(&(c - a)).norm() * 0.5;
        cumulative.push(total);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            let x = rng.random::<f64>() * total;
            let i = cumulative.partition_point(|&c| c < x).min(cumulative.len() - 1);
            let [a, b, c] = mesh.triangles()[i].map(|k| v[k as usize]);
            let (mut r1, mut r2) = (rng.random::<f64>(), rng.random::<f64>());
            if r1 + r2 > 1.0 {
                r1 = 1.0 - r1;
                r2 = 1.0 - r2;
            }
            (a + (b - a) * r1 + (c - a) * r2, triangle_normal(mesh, i))
        })
        .collect()
}
