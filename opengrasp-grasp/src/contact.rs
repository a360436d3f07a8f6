//! Contacts, friction cones and the primitive wrenches of a grasp.
//!
//! A [`Contact`] is a point on the object's surface with the unit normal pointing **into**
//! the object (the direction a finger pushes). Under the [`ContactModel`] each contact
//! contributes *primitive wrenches* `w = (f, τ / ρ) ∈ ℝ⁶` about the object's centre of mass:
//!
//! * **Point contact with Coulomb friction** (coefficient `μ`): the friction cone
//!   `‖f_t‖ ≤ μ f_n` is replaced by the inscribed polyhedral cone with `k` edges
//!   `f_j = n + μ (cos θ_j t₁ + sin θ_j t₂)`, `θ_j = 2πj/k` (`t₁, t₂` an orthonormal tangent
//!   basis). Every edge has a unit normal component, so convex combinations of primitive
//!   wrenches are the wrenches of contact forces whose normal components sum to one (the
//!   "L1" grasp wrench space of Ferrari & Canny). With `μ = 0` the cone collapses to the
//!   single normal force.
//! * **Soft-finger contact** adds torsional friction about the normal: a torsional moment
//!   `|m_n| ≤ γ f_n`, with `γ` the *torsional friction coefficient* in metres (roughly the
//!   friction coefficient times the radius of the contact patch; e.g. `μ = 0.5` and a 4 mm
//!   patch give `γ ≈ 0.002 m`). It is linearised by two extra primitive wrenches per
//!   contact: the unit normal force with the moment `±γ n`.
//!
//! Torques `τ = (p − c) × f (+ m_n)` are taken about the centre of mass `c` and divided by
//! the object's maximum radius `ρ` ([`ObjectFrame`]), so that forces and torques are
//! commensurate and metrics are invariant to the object's scale (the GraspIt!/Dex-Net
//! convention).

use nalgebra::{Point3, Unit, Vector3, Vector6};
use serde::{Deserialize, Serialize};

use crate::error::{ensure_finite, GraspError, Result};

/// A primitive wrench: force (rows 0-2, N per unit normal force) and torque divided by the
/// object's maximum radius (rows 3-5).
pub type Wrench = Vector6<f64>;

/// A contact between a finger and the object.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    /// Contact point, in the same frame as [`ObjectFrame::center_of_mass`] (m).
    pub point: Point3<f64>,
    /// Unit surface normal pointing into the object (the direction the finger pushes).
    pub normal: Unit<Vector3<f64>>,
}

impl Contact {
    /// A contact at `point` with inward normal `normal` (any non-zero length; normalised).
    ///
    /// # Errors
    /// [`GraspError::NonFinite`] for NaN/infinite input, [`GraspError::ZeroNormal`] (index 0)
    /// if `normal` has (numerically) zero length.
    pub fn new(point: Point3<f64>, normal: Vector3<f64>) -> Result<Self> {
        ensure_finite("contact", point.iter().chain(normal.iter()).copied())?;
        let normal = Unit::try_new(normal, 1e-12).ok_or(GraspError::ZeroNormal { index: 0 })?;
        Ok(Self { point, normal })
    }

    /// A contact from an already normalised inward normal.
    pub fn from_unit(point: Point3<f64>, normal: Unit<Vector3<f64>>) -> Self {
        Self { point, normal }
    }

    /// Orthonormal tangent basis `(t₁, t₂)` with `t₁ × t₂ = n` (deterministic in `n`).
    pub fn tangents(&self) -> (Vector3<f64>, Vector3<f64>) {
        let n = self.normal.into_inner();
        // Cross with the coordinate axis least aligned with n.
        let a = if n.x.abs() <= n.y.abs() && n.x.abs() <= n.z.abs() {
            Vector3::x()
        } else if n.y.abs() <= n.z.abs() {
            Vector3::y()
        } else {
            Vector3::z()
        };
        let t1 = n.cross(&a).normalize();
        let t2 = n.cross(&t1);
        (t1, t2)
    }
}

/// How a contact transmits wrenches.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum ContactType {
    /// Point contact with Coulomb friction: forces inside the friction cone, no moment.
    #[default]
    PointWithFriction,
    /// Soft finger: point contact with friction plus torsional friction about the normal.
    SoftFinger {
        /// Torsional friction coefficient `γ` (m): the torsional moment is bounded by
        /// `γ` times the normal force.
        torsional_friction: f64,
    },
}

/// Friction and cone linearisation shared by all contacts of a grasp.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactModel {
    /// Coulomb friction coefficient `μ ≥ 0`. Default: `0.5`.
    pub friction: f64,
    /// Number `k ≥ 3` of edges of the polyhedral (inscribed) friction cone. Default: `8`.
    pub cone_edges: usize,
    /// Point contact or soft finger. Default: [`ContactType::PointWithFriction`].
    pub contact_type: ContactType,
}

impl Default for ContactModel {
    fn default() -> Self {
        Self { friction: 0.5, cone_edges: 8, contact_type: ContactType::PointWithFriction }
    }
}

impl ContactModel {
    /// Checks the parameters' ranges.
    ///
    /// # Errors
    /// [`GraspError::NonFinite`] or [`GraspError::InvalidParameter`] for a negative or
    /// non-finite friction, fewer than 3 cone edges or a negative torsional coefficient.
    pub fn validate(&self) -> Result<()> {
        ensure_finite("contact model friction", [self.friction])?;
        if self.friction < 0.0 {
            return Err(GraspError::InvalidParameter {
                name: "friction",
                reason: format!("{} is negative", self.friction),
            });
        }
        if self.cone_edges < 3 {
            return Err(GraspError::InvalidParameter {
                name: "cone_edges",
                reason: format!("{} is below 3", self.cone_edges),
            });
        }
        if let ContactType::SoftFinger { torsional_friction } = self.contact_type {
            ensure_finite("torsional friction", [torsional_friction])?;
            if torsional_friction < 0.0 {
                return Err(GraspError::InvalidParameter {
                    name: "torsional_friction",
                    reason: format!("{torsional_friction} is negative"),
                });
            }
        }
        Ok(())
    }

    /// Number of primitive wrenches each contact contributes.
    pub fn wrenches_per_contact(&self) -> usize {
        let cone = if self.friction > 0.0 { self.cone_edges } else { 1 };
        match self.contact_type {
            ContactType::PointWithFriction => cone,
            ContactType::SoftFinger { .. } => cone + 2,
        }
    }
}

/// Where torques are taken and how they are scaled.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ObjectFrame {
    /// The object's centre of mass, in the contacts' frame (m).
    pub center_of_mass: Point3<f64>,
    /// The object's maximum radius `ρ` about its centre of mass (m); torques are divided
    /// by it.
    pub max_radius: f64,
}

impl ObjectFrame {
    /// A frame with the given centre of mass and maximum radius.
    ///
    /// # Errors
    /// [`GraspError::NonFinite`] or [`GraspError::InvalidParameter`] unless `max_radius` is
    /// positive and everything is finite.
    pub fn new(center_of_mass: Point3<f64>, max_radius: f64) -> Result<Self> {
        let frame = Self { center_of_mass, max_radius };
        frame.validate()?;
        Ok(frame)
    }

    /// The frame of an object given by its surface points (e.g. mesh vertices): `ρ` is the
    /// largest distance of a point from `center_of_mass`.
    ///
    /// # Errors
    /// As [`ObjectFrame::new`]; an empty slice or all points at the centre give a zero
    /// radius, which is invalid.
    pub fn from_points(center_of_mass: Point3<f64>, points: &[Point3<f64>]) -> Result<Self> {
        ensure_finite("object points", points.iter().flat_map(|p| p.iter().copied()))?;
        let radius = points.iter().map(|p| (p - center_of_mass).norm()).fold(0.0, f64::max);
        Self::new(center_of_mass, radius)
    }

    /// Checks that the frame is finite with a positive radius.
    ///
    /// # Errors
    /// See [`ObjectFrame::new`].
    pub fn validate(&self) -> Result<()> {
        ensure_finite("object frame", self.center_of_mass.iter().copied().chain([self.max_radius]))?;
        if self.max_radius <= 0.0 {
            return Err(GraspError::InvalidParameter {
                name: "max_radius",
                reason: format!("{} is not positive", self.max_radius),
            });
        }
        Ok(())
    }
}

/// Appends the primitive wrenches of one contact to `out`; the contact and the model are
/// assumed valid (see [`GraspWrenchSpace::new`] for the checked entry point).
pub fn contact_wrenches(contact: &Contact, frame: &ObjectFrame, model: &ContactModel, out: &mut Vec<Wrench>) {
    let n = contact.normal.into_inner();
    let r = (contact.point - frame.center_of_mass) / frame.max_radius;
    let push = |out: &mut Vec<Wrench>, f: Vector3<f64>, moment: Vector3<f64>| {
        let tau = r.cross(&f) + moment / frame.max_radius;
        out.push(Wrench::new(f.x, f.y, f.z, tau.x, tau.y, tau.z));
    };
    if model.friction > 0.0 {
        let (t1, t2) = contact.tangents();
        let k = model.cone_edges;
        for j in 0..k {
            let theta = std::f64::consts::TAU * j as f64 / k as f64;
            let f = n + model.friction * (theta.cos() * t1 + theta.sin() * t2);
            push(out, f, Vector3::zeros());
        }
    } else {
        push(out, n, Vector3::zeros());
    }
    if let ContactType::SoftFinger { torsional_friction } = model.contact_type {
        push(out, n, torsional_friction * n);
        push(out, n, -torsional_friction * n);
    }
}

/// The primitive wrenches of a grasp: the generators of its grasp wrench space.
#[derive(Debug, Clone, PartialEq)]
pub struct GraspWrenchSpace {
    wrenches: Vec<Wrench>,
    num_contacts: usize,
}

impl GraspWrenchSpace {
    /// Primitive wrenches of `contacts` about `frame` under `model`.
    ///
    /// # Errors
    /// [`GraspError::NonFinite`] if a contact is not finite, [`GraspError::ZeroNormal`] if a
    /// normal is not of unit length (e.g. built with `Unit::new_unchecked`), and the errors
    /// of [`ContactModel::validate`] and [`ObjectFrame::validate`].
    pub fn new(contacts: &[Contact], frame: &ObjectFrame, model: &ContactModel) -> Result<Self> {
        model.validate()?;
        frame.validate()?;
        let mut wrenches = Vec::with_capacity(contacts.len() * model.wrenches_per_contact());
        for (index, c) in contacts.iter().enumerate() {
            ensure_finite("contact", c.point.iter().chain(c.normal.iter()).copied())?;
            if (c.normal.norm() - 1.0).abs() > 1e-6 {
                return Err(GraspError::ZeroNormal { index });
            }
            contact_wrenches(c, frame, model, &mut wrenches);
        }
        Ok(Self { wrenches, num_contacts: contacts.len() })
    }

    /// A wrench space from explicit primitive wrenches (e.g. from another contact model).
    ///
    /// # Errors
    /// [`GraspError::NonFinite`] if a wrench is not finite.
    pub fn from_wrenches(wrenches: Vec<Wrench>) -> Result<Self> {
        ensure_finite("wrenches", wrenches.iter().flat_map(|w| w.iter().copied()))?;
        Ok(Self { wrenches, num_contacts: 0 })
    }

    /// The primitive wrenches.
    pub fn wrenches(&self) -> &[Wrench] {
        &self.wrenches
    }

    /// Number of primitive wrenches.
    pub fn len(&self) -> usize {
        self.wrenches.len()
    }

    /// Whether there are no primitive wrenches.
    pub fn is_empty(&self) -> bool {
        self.wrenches.is_empty()
    }

    /// Number of contacts the wrenches came from (0 for [`from_wrenches`](Self::from_wrenches)).
    pub fn num_contacts(&self) -> usize {
        self.num_contacts
    }

    /// Affine dimension (0-6) spanned by the wrenches, from the singular values of the
    /// centred wrench matrix: singular values below `relative_tolerance` times the largest
    /// (or below `1e-12` absolute) do not count. An empty set has dimension 0.
    ///
    /// A set whose centred Gram matrix is proven well inside full rank (a Cholesky
    /// factorisation of `G − tI` with `t` far above the rounding; the proof is in the source,
    /// `full_rank_certified`) gets 6 without the singular value decomposition, the number the
    /// decomposition gives; the others take the decomposition.
    pub fn affine_rank(&self, relative_tolerance: f64) -> usize {
        let n = self.wrenches.len();
        if n < 2 {
            return 0;
        }
        let mean = self.wrenches.iter().sum::<Wrench>() / n as f64;
        if full_rank_certified(&self.wrenches, &mean, relative_tolerance) {
            return 6;
        }
        centred_svd_rank(&self.wrenches, &mean, relative_tolerance)
    }

    /// [`affine_rank`](Self::affine_rank) always from the singular value decomposition (the
    /// reference of the tests; not for use).
    #[doc(hidden)]
    pub fn affine_rank_svd(&self, relative_tolerance: f64) -> usize {
        let n = self.wrenches.len();
        if n < 2 {
            return 0;
        }
        let mean = self.wrenches.iter().sum::<Wrench>() / n as f64;
        centred_svd_rank(&self.wrenches, &mean, relative_tolerance)
    }
}

/// The affine rank of `wrenches` from the singular values of the wrench matrix centred on
/// `mean` (see [`GraspWrenchSpace::affine_rank`]).
fn centred_svd_rank(wrenches: &[Wrench], mean: &Wrench, relative_tolerance: f64) -> usize {
    let m = nalgebra::DMatrix::from_fn(6, wrenches.len(), |r, c| wrenches[c][r] - mean[r]);
    let sv = m.singular_values();
    let max = sv.max();
    sv.iter().filter(|&&s| s > relative_tolerance * max && s > 1e-12).count()
}

/// Whether the centred wrench matrix `M` (the very entries `wᵢ − mean` the decomposition
/// reads) certainly has six singular values above `relative_tolerance` times the largest and
/// above `1e-12`, so that the decomposition counts 6.
///
/// Proof: the Cholesky factorisation of `G − tI`, `G = M Mᵀ` (6 × 6) and
/// `t = (4 tol² + 1e-8) T + 1e-22` with `T = trace G ≥ σ₁²`, completes with positive pivots
/// only if `λ_min(G) > t − ε`, where `ε` covers the rounding of `G` (`γₙ`-relative, at most
/// `6 γₙ T`) and of the factorisation (`≤ 6 γ₇ T`): below `1e-10 T` for up to `10⁵` wrenches,
/// far under the `1e-8 T` of `t`. Then `σ₆ ≥ (0.99 t)^½`, at least `1.99 tol σ₁`,
/// `1e-4 σ₁` and `0.99e-11`, while the decomposition's singular values are within
/// `≈ 1e-12 σ₁` of the exact ones: its count is 6. Anything else is left to it.
fn full_rank_certified(wrenches: &[Wrench], mean: &Wrench, relative_tolerance: f64) -> bool {
    if wrenches.len() < 7 || wrenches.len() > 100_000 {
        return false;
    }
    let mut g = [[0.0f64; 6]; 6];
    for w in wrenches {
        let m: [f64; 6] = std::array::from_fn(|r| w[r] - mean[r]);
        for i in 0..6 {
            for j in 0..=i {
                g[i][j] += m[i] * m[j];
            }
        }
    }
    let trace: f64 = (0..6).map(|i| g[i][i]).sum();
    let t = (4.0 * relative_tolerance * relative_tolerance + 1e-8) * trace + 1e-22;
    if !t.is_finite() {
        return false;
    }
    // Lower triangle of the Cholesky factor of G − tI.
    let mut l = [[0.0f64; 6]; 6];
    for j in 0..6 {
        let pivot = g[j][j] - t - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        // (NaN fails too.)
        if pivot.is_nan() || pivot <= 0.0 {
            return false;
        }
        l[j][j] = pivot.sqrt();
        for i in j + 1..6 {
            l[i][j] = (g[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / l[j][j];
        }
    }
    true
}
