//! Grasp quality metrics: force closure, Ferrari-Canny epsilon, wrench-space volume, the
//! GraspNet friction sweep and Dex-Net's robust epsilon.
//!
//! All metrics are pure functions of the contacts, the [`ObjectFrame`] and the
//! [`ContactModel`]; they act on the grasp wrench space `W = conv{wᵢ}` of the primitive
//! wrenches (see [`crate::contact`]).
//!
//! * **Min-norm distance** (the force-closure QP): distance from the origin to `W`, by
//!   Wolfe's active-set algorithm ([`solver::min_norm_distance`]; clarabel's
//!   [`solver::min_norm_point`] is the fallback). Zero iff the origin is in `W`
//!   ([`QualityReport::origin_in_hull`]). When the strict LP below already found a
//!   strictly positive zero combination, its residual is reported instead (≈ 1e-16) and the
//!   QP is skipped. This alone cannot tell a grasp whose wrench space
//!   merely touches the origin (e.g. two antipodal point contacts, which cannot resist a
//!   torque about their axis) from a force-closure grasp.
//! * **Force closure** (strict): the origin lies in the *interior* of `W`. Tested as
//!   (a) the wrenches span 6 affine dimensions (singular values of the centred wrench matrix,
//!   [`QualityOptions::rank_tolerance`]) and (b) the LP "largest `s` with `Σλᵢwᵢ = 0`,
//!   `Σλᵢ = 1`, `λᵢ ≥ s`" has `s > tolerance` (a dense simplex,
//!   [`solver::strict_combination_vertex`]; clarabel's [`solver::strict_combination`] is the fallback):
//!   a strictly positive combination puts the origin in the relative interior of `W`, and
//!   full dimension makes that the interior.
//! * **Epsilon** (Ferrari-Canny, L1 variant): the radius of the largest origin-centred ball
//!   inside `W`, i.e. the smallest facet offset of the 6-D convex hull ([`hull`]); 0 if the
//!   origin is not strictly inside. Equivalently `min over unit u of max_i wᵢ · u`. Found
//!   without the full hull by an expanding-polytope search that refines only the facets
//!   nearest the origin ([`ConvexHull::depth_flat`]).
//! * **Volume** and **facet count** of the 6-D hull of `W`: opt-in statistics
//!   ([`QualityOptions::hull_statistics`]), since they need the full hull (several times the
//!   cost of the rest of the metrics).
//!
//! Wrench sets spanning fewer than 6 dimensions (no contacts, one contact, coplanar
//! configurations…) are *degenerate*: they never give force closure, epsilon and volume
//! are 0 and [`QualityReport::degenerate`] is set; nothing panics.

mod dense;
pub mod hull;
pub mod solver;

use nalgebra::{Unit, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::contact::{Contact, ContactModel, GraspWrenchSpace, ObjectFrame};
use crate::error::{ensure_finite, GraspError, Result};
use hull::{ConvexHull, HullOptions};

/// The friction coefficients of GraspNet-1Billion's friction sweep, in increasing order.
pub const GRASPNET_FRICTIONS: [f64; 6] = [0.2, 0.4, 0.6, 0.8, 1.0, 1.2];

/// Options of [`GraspQuality::evaluate`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QualityOptions {
    /// Friction coefficient, cone edges and contact type. Default: [`ContactModel::default`]
    /// (μ = 0.5, 8 edges, point contacts with friction).
    pub contact: ContactModel,
    /// Numerical tolerance in wrench units: min-norm distances up to it count as "origin in
    /// the hull", the strict LP margin must exceed it, and epsilons below it are reported as
    /// 0. Default: `1e-6`.
    pub tolerance: f64,
    /// Relative singular-value threshold of the wrench set's affine rank. Default: `1e-9`.
    pub rank_tolerance: f64,
    /// Whether to compute epsilon (`false` leaves it at 0 and only answers the force-closure
    /// questions; the hull statistics are then not computed either). Default: `true`.
    pub compute_hull: bool,
    /// Whether to build the full 6-D hull for its volume and facet count
    /// ([`QualityReport::volume`], [`QualityReport::hull_facets`]); epsilon does not need it.
    /// Default: `false` (absent from older serialized options).
    #[serde(default)]
    pub hull_statistics: bool,
    /// Options of the convex hull (joggle, retries, seed). Default: [`HullOptions::default`].
    pub hull: HullOptions,
}

impl Default for QualityOptions {
    fn default() -> Self {
        Self {
            contact: ContactModel::default(),
            tolerance: 1e-6,
            rank_tolerance: 1e-9,
            compute_hull: true,
            hull_statistics: false,
            hull: HullOptions::default(),
        }
    }
}

impl QualityOptions {
    /// Checks the options' ranges.
    ///
    /// # Errors
    /// [`GraspError::NonFinite`] / [`GraspError::InvalidParameter`] for a bad contact model
    /// or a negative or non-finite tolerance.
    pub fn validate(&self) -> Result<()> {
        self.contact.validate()?;
        ensure_finite("quality tolerances", [self.tolerance, self.rank_tolerance])?;
        for (name, value) in [("tolerance", self.tolerance), ("rank_tolerance", self.rank_tolerance)] {
            if value < 0.0 {
                return Err(GraspError::InvalidParameter { name, reason: format!("{value} is negative") });
            }
        }
        Ok(())
    }
}

/// All quality metrics of one grasp.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct QualityReport {
    /// Force closure: the origin is strictly inside the grasp wrench space (full 6-D rank
    /// and a strictly positive combination of the primitive wrenches summing to zero).
    pub force_closure: bool,
    /// The min-norm QP test: the origin lies in the (closed) convex hull of the primitive
    /// wrenches, possibly on its boundary (`min_norm_distance ≤ tolerance`).
    pub origin_in_hull: bool,
    /// Distance from the origin to the convex hull of the primitive wrenches (0 when inside;
    /// `+∞` for an empty grasp).
    pub min_norm_distance: f64,
    /// Optimum `s` of the strict LP (largest minimum convex weight of a zero combination),
    /// in `[−∞, 1/n]`; `−∞` when the origin is not in the wrenches' affine hull or the set
    /// is degenerate (the LP is then not solved).
    pub positive_combination_margin: f64,
    /// Ferrari-Canny epsilon (L1): radius of the largest origin-centred ball in the wrench
    /// space; 0 without force closure.
    pub epsilon: f64,
    /// Volume of the grasp wrench space's 6-D hull, with
    /// [`QualityOptions::hull_statistics`] (and `compute_hull`); `None` otherwise, `Some(0.0)`
    /// if degenerate or when the hull was skipped ([`GraspQuality::evaluate_hull_if_closure`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<f64>,
    /// Affine dimension (0-6) spanned by the primitive wrenches.
    pub wrench_dimension: usize,
    /// The wrench set spans fewer than 6 dimensions (epsilon and volume are then 0).
    pub degenerate: bool,
    /// Number of primitive wrenches.
    pub num_wrenches: usize,
    /// Number of facets of the 6-D hull, with [`QualityOptions::hull_statistics`] (as
    /// [`QualityReport::volume`]: `Some(0)` if the hull was not built, `None` if not asked).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hull_facets: Option<usize>,
}

/// Mean and spread of epsilon under random perturbations ([`GraspQuality::robust_epsilon`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RobustEpsilon {
    /// Mean epsilon over the samples (Dex-Net's robust Ferrari-Canny).
    pub mean: f64,
    /// Sample standard deviation of epsilon (0 for a single sample).
    pub std: f64,
    /// Fraction of samples that are force closure.
    pub force_closure_rate: f64,
    /// Number of samples.
    pub samples: usize,
}

/// Perturbation model of [`GraspQuality::robust_epsilon`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobustOptions {
    /// Number of Monte-Carlo samples (≥ 1). Default: `32`.
    pub samples: usize,
    /// Seed of the ChaCha8 generator. Default: `0`.
    pub seed: u64,
    /// Standard deviation of each contact-position coordinate (m). Default: `0.002`.
    pub position_std: f64,
    /// Standard deviation of the normal's tilt along each tangent direction (rad).
    /// Default: `0.05`.
    pub normal_std: f64,
    /// Standard deviation of the friction coefficient (clamped at 0). Default: `0.05`.
    pub friction_std: f64,
}

impl Default for RobustOptions {
    fn default() -> Self {
        Self { samples: 32, seed: 0, position_std: 0.002, normal_std: 0.05, friction_std: 0.05 }
    }
}

/// Entry point of the grasp quality metrics.
///
/// ```
/// use nalgebra::{Point3, Vector3};
/// use opengrasp_grasp::contact::{Contact, ObjectFrame};
/// use opengrasp_grasp::quality::{GraspQuality, QualityOptions};
///
/// # fn main() -> opengrasp_grasp::Result<()> {
/// // Three fingers on the equator of a unit sphere, pushing towards the centre.
/// let contacts = (0..3)
///     .map(|i| {
///         let a = std::f64::consts::TAU * i as f64 / 3.0;
///         let p = Point3::new(a.cos(), a.sin(), 0.0);
///         Contact::new(p, -p.coords)
///     })
///     .collect::<Result<Vec<_>, _>>()?;
/// let frame = ObjectFrame::new(Point3::origin(), 1.0)?;
/// let report = GraspQuality::evaluate(&contacts, &frame, &QualityOptions::default())?;
/// assert!(report.force_closure && report.epsilon > 0.0);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct GraspQuality;

impl GraspQuality {
    /// Evaluates every metric of the grasp given by `contacts` on the object `frame`.
    ///
    /// # Errors
    /// Invalid contacts, frame or options (see [`GraspWrenchSpace::new`] and
    /// [`QualityOptions::validate`]); [`GraspError::Solver`] or [`GraspError::HullFailed`]
    /// on numerical breakdown. Degenerate grasps are not errors.
    pub fn evaluate(contacts: &[Contact], frame: &ObjectFrame, options: &QualityOptions) -> Result<QualityReport> {
        options.validate()?;
        let ws = GraspWrenchSpace::new(contacts, frame, &options.contact)?;
        Self::evaluate_wrench_space(&ws, options)
    }

    /// Evaluates every metric of an explicit wrench space (`options.contact` is unused).
    ///
    /// # Errors
    /// See [`GraspQuality::evaluate`].
    pub fn evaluate_wrench_space(ws: &GraspWrenchSpace, options: &QualityOptions) -> Result<QualityReport> {
        Self::evaluate_impl(ws, options, false)
    }

    /// As [`GraspQuality::evaluate`], but epsilon (when `options.compute_hull`) and the hull
    /// statistics (when also `options.hull_statistics`) are computed only for force-closure
    /// grasps: the others keep epsilon at 0 and the statistics at `Some(0)`, exactly as with
    /// `compute_hull = false`. The force-closure LP (and the min-norm QP when needed) is solved
    /// once. This is what a grasp evaluator wants: epsilon is 0 without force closure.
    ///
    /// # Errors
    /// See [`GraspQuality::evaluate`].
    pub fn evaluate_hull_if_closure(
        contacts: &[Contact],
        frame: &ObjectFrame,
        options: &QualityOptions,
    ) -> Result<QualityReport> {
        options.validate()?;
        let ws = GraspWrenchSpace::new(contacts, frame, &options.contact)?;
        Self::evaluate_impl(&ws, options, true)
    }

    fn evaluate_impl(ws: &GraspWrenchSpace, options: &QualityOptions, hull_if_closure: bool) -> Result<QualityReport> {
        options.validate()?;
        let wrenches = ws.wrenches();
        let n = wrenches.len();
        let stats = options.compute_hull && options.hull_statistics;
        let mut report = QualityReport {
            force_closure: false,
            origin_in_hull: false,
            min_norm_distance: f64::INFINITY,
            positive_combination_margin: f64::NEG_INFINITY,
            epsilon: 0.0,
            volume: stats.then_some(0.0),
            wrench_dimension: 0,
            degenerate: true,
            num_wrenches: n,
            hull_facets: stats.then_some(0),
        };
        if n == 0 {
            return Ok(report);
        }
        report.wrench_dimension = ws.affine_rank(options.rank_tolerance);
        report.degenerate = report.wrench_dimension < 6;
        if !report.degenerate {
            let strict = solver::strict_combination_vertex(wrenches)?;
            report.positive_combination_margin = strict.margin;
            report.force_closure = strict.margin > options.tolerance;
            if report.force_closure {
                // The LP's strictly positive weights already put the origin in the hull:
                // their residual is the (≈ 0) min-norm distance, no second solve needed.
                if let Some(d) = strict.weights.as_deref().and_then(|l| solver::combination_norm(wrenches, l)) {
                    report.min_norm_distance = d;
                }
            }
        }
        if !report.min_norm_distance.is_finite() || report.min_norm_distance > options.tolerance {
            report.min_norm_distance = solver::min_norm_distance(wrenches)?;
        }
        report.origin_in_hull = report.min_norm_distance <= options.tolerance;
        if report.degenerate {
            return Ok(report);
        }
        if options.compute_hull && (report.force_closure || !hull_if_closure) {
            let coords: Vec<f64> = wrenches.iter().flat_map(|w| w.iter().copied()).collect();
            let origin = [0.0; 6];
            let metrics = ConvexHull::depth_flat(6, &coords, &options.hull, &origin).and_then(|depth| {
                let summary =
                    stats.then(|| ConvexHull::summary_flat(6, &coords, &options.hull, &origin)).transpose()?;
                Ok((depth, summary))
            });
            match metrics {
                Ok((depth, summary)) => {
                    report.epsilon = if depth > options.tolerance { depth } else { 0.0 };
                    if let Some(hull) = summary {
                        report.volume = Some(hull.volume);
                        report.hull_facets = Some(hull.facets);
                    }
                }
                Err(GraspError::DegenerateHull { affine_rank, .. }) => {
                    report.wrench_dimension = affine_rank;
                    report.degenerate = true;
                    report.force_closure = false;
                }
                Err(e) => return Err(e),
            }
        }
        Ok(report)
    }

    /// Whether the grasp is force closure (the strict test of
    /// [`QualityReport::force_closure`], without the min-norm QP and the hull).
    ///
    /// # Errors
    /// See [`GraspQuality::evaluate`].
    pub fn is_force_closure(contacts: &[Contact], frame: &ObjectFrame, options: &QualityOptions) -> Result<bool> {
        options.validate()?;
        let ws = GraspWrenchSpace::new(contacts, frame, &options.contact)?;
        if ws.is_empty() || ws.affine_rank(options.rank_tolerance) < 6 {
            return Ok(false);
        }
        Ok(solver::positive_combination_margin(ws.wrenches())? > options.tolerance)
    }

    /// GraspNet-1Billion friction score: the smallest μ of [`GRASPNET_FRICTIONS`]
    /// (0.2, 0.4, …, 1.2) at which the grasp is force closure, `None` if it never is.
    /// Lower is better. `options.contact.friction` is ignored.
    ///
    /// # Errors
    /// See [`GraspQuality::evaluate`].
    pub fn friction_score(contacts: &[Contact], frame: &ObjectFrame, options: &QualityOptions) -> Result<Option<f64>> {
        Self::friction_sweep(contacts, frame, options, &GRASPNET_FRICTIONS)
    }

    /// The smallest μ of `frictions` (tried in increasing order) at which the grasp is force
    /// closure, `None` if none. Force closure is monotone in μ (the linearised cones are
    /// nested), so this is the threshold friction up to the grid's resolution.
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] / [`GraspError::NonFinite`] for a negative or
    /// non-finite μ; otherwise see [`GraspQuality::evaluate`].
    pub fn friction_sweep(
        contacts: &[Contact],
        frame: &ObjectFrame,
        options: &QualityOptions,
        frictions: &[f64],
    ) -> Result<Option<f64>> {
        let mut sorted = frictions.to_vec();
        sorted.sort_by(f64::total_cmp);
        let mut opts = options.clone();
        for mu in sorted {
            opts.contact.friction = mu;
            if Self::is_force_closure(contacts, frame, &opts)? {
                return Ok(Some(mu));
            }
        }
        Ok(None)
    }

    /// Robust epsilon (Dex-Net): mean and standard deviation of epsilon over
    /// `robust.samples` seeded Monte-Carlo perturbations of the contact positions, normals
    /// and friction coefficient (a stand-in for hand/object pose and material uncertainty).
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] for zero samples or negative/non-finite standard
    /// deviations; otherwise see [`GraspQuality::evaluate`].
    pub fn robust_epsilon(
        contacts: &[Contact],
        frame: &ObjectFrame,
        options: &QualityOptions,
        robust: &RobustOptions,
    ) -> Result<RobustEpsilon> {
        options.validate()?;
        frame.validate()?;
        if robust.samples == 0 {
            return Err(GraspError::InvalidParameter { name: "samples", reason: "must be at least 1".into() });
        }
        let stds = [
            ("position_std", robust.position_std),
            ("normal_std", robust.normal_std),
            ("friction_std", robust.friction_std),
        ];
        for (name, value) in stds {
            if !(value.is_finite() && value >= 0.0) {
                return Err(GraspError::InvalidParameter {
                    name,
                    reason: format!("{value} is not a finite non-negative number"),
                });
            }
        }
        // Validate the unperturbed contacts once so bad input fails before sampling.
        GraspWrenchSpace::new(contacts, frame, &options.contact)?;
        let mut rng = ChaCha8Rng::seed_from_u64(robust.seed);
        let mut opts = options.clone();
        let mut perturbed = contacts.to_vec();
        let (mut sum, mut sum_sq, mut closures) = (0.0, 0.0, 0usize);
        for _ in 0..robust.samples {
            for (p, c) in perturbed.iter_mut().zip(contacts) {
                let (t1, t2) = c.tangents();
                let offset = Vector3::new(gaussian(&mut rng), gaussian(&mut rng), gaussian(&mut rng));
                let tilt = gaussian(&mut rng) * t1 + gaussian(&mut rng) * t2;
                p.point = c.point + robust.position_std * offset;
                p.normal = Unit::new_normalize(c.normal.into_inner() + robust.normal_std * tilt);
            }
            opts.contact.friction = (options.contact.friction + robust.friction_std * gaussian(&mut rng)).max(0.0);
            let report = Self::evaluate(&perturbed, frame, &opts)?;
            sum += report.epsilon;
            sum_sq += report.epsilon * report.epsilon;
            closures += usize::from(report.force_closure);
        }
        let n = robust.samples as f64;
        let mean = sum / n;
        let std = if robust.samples > 1 { ((sum_sq - n * mean * mean) / (n - 1.0)).max(0.0).sqrt() } else { 0.0 };
        Ok(RobustEpsilon { mean, std, force_closure_rate: closures as f64 / n, samples: robust.samples })
    }
}

/// A standard normal sample (Box-Muller).
fn gaussian(rng: &mut impl Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}
