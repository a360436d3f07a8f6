//! Convex hulls in any dimension: quickhull with simplicial facets on joggled input.
//!
//! The grasp metrics need the convex hull of a few dozen primitive wrenches in 6-D (the
//! Ferrari-Canny epsilon is the distance from the origin to the nearest facet, the volume
//! metric the hull's volume). [`ConvexHull::new`] builds it for points of any dimension
//! `d ≥ 2` (Qhull itself is not used: its C build needs libclang):
//!
//! 1. **Degeneracy check.** An initial simplex is chosen greedily on the original points
//!    (Gram-Schmidt with pivoting on the point farthest from the affine span so far). If the
//!    points span fewer than `d` affine dimensions the call returns
//!    [`GraspError::DegenerateHull`] with the rank found; exact duplicate points are dropped.
//! 2. **Joggle.** As Qhull's `QJ` option does, every coordinate is perturbed by a
//!    deterministic (seeded) uniform random amount of at most `joggle × scale`, where `scale`
//!    is the largest absolute coordinate. Joggled points are in general position, so every
//!    facet is a simplex and no merging of coplanar facets is needed. Results are exact for
//!    the joggled points and move by `O(joggle × scale)` from those of the original points.
//! 3. **Quickhull.** Beneath-beyond insertion of the farthest outside point of a facet: the
//!    visible facets are found by a breadth-first search, replaced by a cone of new facets
//!    over their horizon. A new facet's normal is the `O(d)` combination of the normals of
//!    the two facets meeting at its horizon ridge (checked, with a Householder QR of the
//!    edge vectors as fallback); planes are oriented away from a fixed interior point (the
//!    centroid of the initial simplex). Ridges are paired through an order-independent
//!    hash of their vertices.
//! 4. **Verification.** Every ridge must be shared by exactly two facets and every pair of
//!    neighbouring facets must be locally convex (to `1e-7 × scale`). On failure the build
//!    is retried with a joggle ten times larger, up to [`HullOptions::max_attempts`] times,
//!    then [`GraspError::HullFailed`] is returned.
//!
//! Implementation: in 6-D (the wrench space) the builder is compiled for the fixed dimension,
//! so every per-facet loop has a constant length; outside sets are linked lists in one arena
//! with the farthest point kept on insertion; the growable arrays are reused per thread; the
//! volume uses an unrolled 6 × 6 LU. None of this changes a floating-point operation: the
//! previous builder is kept (`from_flat_reference`, hidden) and tests check the two agree bit
//! for bit (facets, planes, volume, depth).
//!
//! Cost: the 32 primitive wrenches of a 4-contact, 8-edge grasp give about 1,400 facets in
//! 6-D (about 2.5 times as many are created and discarded on the way); 48 wrenches give about
//! 2,700. A hull of the default suite's force-closure grasps (194 of them, 16 candidates per
//! cell) takes 8.7 million instructions on average (callgrind; 15.9 million with the previous
//! builder), about a millisecond on one core.

mod builder;
mod linalg;
mod reference;

use builder::{Builder, Dynamic, Fixed};
use linalg::initial_simplex;
use reference::Reference;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::error::{GraspError, Result};

/// Options of [`ConvexHull::new`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HullOptions {
    /// Joggle amplitude of the first attempt, relative to the largest absolute coordinate.
    /// Each retry multiplies it by 10. Default: `1e-9`.
    pub joggle: f64,
    /// Maximum number of (joggled) attempts before giving up. Default: `5`.
    pub max_attempts: usize,
    /// Seed of the joggle's random generator (attempt `a` uses `seed + a`). Default: `0`.
    pub seed: u64,
}

impl Default for HullOptions {
    fn default() -> Self {
        Self { joggle: 1e-9, max_attempts: 5, seed: 0 }
    }
}

/// One simplicial facet of a [`ConvexHull`], borrowed from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Facet<'a> {
    /// Indices (into the input points) of the facet's `d` vertices.
    pub vertices: &'a [usize],
    /// Outward unit normal `n`.
    pub normal: &'a [f64],
    /// Offset `b` of the supporting hyperplane: hull points satisfy `n · x ≤ b`.
    pub offset: f64,
}

/// The convex hull of a full-dimensional point set in `d` dimensions, as simplicial facets.
#[derive(Debug, Clone)]
pub struct ConvexHull {
    dim: usize,
    facet_vertices: Vec<usize>,
    normals: Vec<f64>,
    offsets: Vec<f64>,
    vertices: Vec<usize>,
    interior: Vec<f64>,
    volume: f64,
    joggle: f64,
    attempts: usize,
}

impl ConvexHull {
    /// Builds the convex hull of `points`, each a slice of `dim` coordinates.
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] if `dim < 2` or the options are out of range,
    /// [`GraspError::DimensionMismatch`] if a point does not have `dim` coordinates,
    /// [`GraspError::NonFinite`] for NaN/infinite coordinates,
    /// [`GraspError::DegenerateHull`] if the points span fewer than `dim` affine dimensions
    /// (including fewer than `dim + 1` distinct points), and [`GraspError::HullFailed`] if no
    /// consistent hull was found within `options.max_attempts` joggled attempts.
    pub fn new<P: AsRef<[f64]>>(dim: usize, points: &[P], options: &HullOptions) -> Result<Self> {
        if dim < 2 {
            return Err(GraspError::InvalidParameter { name: "dim", reason: format!("{dim} is below 2") });
        }
        if !(options.joggle.is_finite() && options.joggle > 0.0 && options.joggle < 1e-2) {
            return Err(GraspError::InvalidParameter {
                name: "joggle",
                reason: format!("{} is not in (0, 1e-2)", options.joggle),
            });
        }
        if options.max_attempts == 0 {
            return Err(GraspError::InvalidParameter { name: "max_attempts", reason: "must be at least 1".into() });
        }
        let mut flat = Vec::with_capacity(points.len() * dim);
        for (index, p) in points.iter().enumerate() {
            let p = p.as_ref();
            if p.len() != dim {
                return Err(GraspError::DimensionMismatch { index, expected: dim, actual: p.len() });
            }
            flat.extend_from_slice(p);
        }
        crate::error::ensure_finite("hull points", flat.iter().copied())?;
        Self::from_flat(dim, &flat, options)
    }

    /// Builds the hull from `n × dim` coordinates stored point after point (no copying of
    /// the caller's points into nested vectors). Same errors as [`ConvexHull::new`].
    ///
    /// # Errors
    /// See [`ConvexHull::new`].
    pub fn from_flat(dim: usize, coords: &[f64], options: &HullOptions) -> Result<Self> {
        Self::from_flat_with(dim, coords, options, false)
    }

    /// As [`ConvexHull::from_flat`], built by the previous (unoptimised) quickhull builder.
    /// The two give bit-identical hulls; this one is kept as the reference of the
    /// equivalence tests and benches, not for use.
    #[doc(hidden)]
    pub fn from_flat_reference(dim: usize, coords: &[f64], options: &HullOptions) -> Result<Self> {
        Self::from_flat_with(dim, coords, options, true)
    }

    fn from_flat_with(dim: usize, coords: &[f64], options: &HullOptions, reference: bool) -> Result<Self> {
        build(dim, coords, options, |jog, unique, simplex, scale, amp, attempt| {
            if reference {
                Reference::run(dim, jog, unique, simplex, scale).map(|b| b.finish(coords, amp, attempt))
            } else if dim == 6 {
                Builder::run(Fixed::<6>, jog, unique, simplex, scale).map(|b| b.finish(coords, amp, attempt))
            } else {
                Builder::run(Dynamic(dim), jog, unique, simplex, scale).map(|b| b.finish(coords, amp, attempt))
            }
        })
    }

    /// The depth of `point` ([`ConvexHull::depth`]), the volume and the facet count of the hull
    /// of `coords` (flat, `dim` per point), without keeping the hull: the same construction as
    /// [`ConvexHull::from_flat`] and bit for bit the same three numbers, minus the copies of
    /// the facets into a [`ConvexHull`] (the grasp metrics need only these numbers).
    ///
    /// # Errors
    /// As [`ConvexHull::from_flat`]; [`GraspError::DimensionMismatch`] if `point` does not
    /// have `dim` coordinates.
    pub fn summary_flat(dim: usize, coords: &[f64], options: &HullOptions, point: &[f64]) -> Result<HullSummary> {
        if point.len() != dim {
            return Err(GraspError::DimensionMismatch { index: 0, expected: dim, actual: point.len() });
        }
        build(dim, coords, options, |jog, unique, simplex, scale, _, _| {
            if dim == 6 {
                Builder::run(Fixed::<6>, jog, unique, simplex, scale).map(|b| b.summary(coords, point))
            } else {
                Builder::run(Dynamic(dim), jog, unique, simplex, scale).map(|b| b.summary(coords, point))
            }
        })
    }

    /// The depth of `point` in the hull of `coords` (flat, `dim` per point) without building
    /// the hull: an expanding-polytope search from the initial simplex that refines only the
    /// facets nearest the point (see `builder::epsilon`). On the same joggled points as
    /// [`ConvexHull::summary_flat`], so for a point inside the hull it agrees with that depth
    /// to about `1e-14 × scale`, unless the hull needed a larger joggle; for a point outside it is non-positive (not
    /// necessarily the hull's depth, which measures the largest facet violation). The grasp
    /// metrics use it for the Ferrari-Canny epsilon (`point` = the origin). When the search's
    /// polytope fails its verification (near-coplanar facets within the joggle, a few percent
    /// of grasp wrench sets), the full hull of the same joggled points answers instead.
    ///
    /// # Errors
    /// As [`ConvexHull::summary_flat`].
    pub fn depth_flat(dim: usize, coords: &[f64], options: &HullOptions, point: &[f64]) -> Result<f64> {
        if point.len() != dim {
            return Err(GraspError::DimensionMismatch { index: 0, expected: dim, actual: point.len() });
        }
        // On an inconsistent polytope (near-coplanar facets within the joggle), the full hull of
        // the same joggled points; a retry with a larger joggle only if that fails too.
        build(dim, coords, options, |jog, unique, simplex, scale, _, _| {
            if dim == 6 {
                Builder::depth_search(Fixed::<6>, jog, unique, simplex, scale, point)
                    .map(|(depth, _)| depth)
                    .or_else(|_| Builder::run(Fixed::<6>, jog, unique, simplex, scale).map(|b| b.depth(point)))
            } else {
                Builder::depth_search(Dynamic(dim), jog, unique, simplex, scale, point)
                    .map(|(depth, _)| depth)
                    .or_else(|_| Builder::run(Dynamic(dim), jog, unique, simplex, scale).map(|b| b.depth(point)))
            }
        })
    }

    /// Dimension of the space.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of (simplicial) facets.
    pub fn num_facets(&self) -> usize {
        self.offsets.len()
    }

    /// The facets.
    pub fn facets(&self) -> impl ExactSizeIterator<Item = Facet<'_>> + '_ {
        let d = self.dim;
        (0..self.offsets.len()).map(move |f| Facet {
            vertices: &self.facet_vertices[f * d..(f + 1) * d],
            normal: &self.normals[f * d..(f + 1) * d],
            offset: self.offsets[f],
        })
    }

    /// Sorted indices of the input points that are vertices of the hull.
    pub fn vertices(&self) -> &[usize] {
        &self.vertices
    }

    /// A point strictly inside the hull (centroid of the initial simplex).
    pub fn interior_point(&self) -> &[f64] {
        &self.interior
    }

    /// The hull's `d`-dimensional volume: sum over facets of the simplices they span with
    /// [`interior_point`](Self::interior_point), computed on the original coordinates.
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Absolute joggle amplitude used by the successful attempt.
    pub fn joggle(&self) -> f64 {
        self.joggle
    }

    /// Number of attempts needed (1 unless the first joggled build failed).
    pub fn attempts(&self) -> usize {
        self.attempts
    }

    /// Signed depth of `point`: `min over facets of (b − n · x)`.
    ///
    /// For a point inside the hull this is the radius of the largest ball centred at the
    /// point that fits in the hull; it is negative outside (then `−depth` is the largest
    /// violation of a facet inequality, a lower bound of the distance to the hull).
    /// Returns NaN if `point` does not have [`dim`](Self::dim) coordinates.
    pub fn depth(&self, point: &[f64]) -> f64 {
        if point.len() != self.dim {
            return f64::NAN;
        }
        self.facets().map(|f| f.offset - dot(f.normal, point)).fold(f64::INFINITY, f64::min)
    }

    /// Whether `point` satisfies every facet inequality within `tolerance`.
    pub fn contains(&self, point: &[f64], tolerance: f64) -> bool {
        self.depth(point) >= -tolerance
    }
}

/// Depth of a point, volume and facet count of a hull ([`ConvexHull::summary_flat`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HullSummary {
    /// Signed distance of the point inside the hull ([`ConvexHull::depth`]).
    pub depth: f64,
    /// Volume ([`ConvexHull::volume`]).
    pub volume: f64,
    /// Number of facets ([`ConvexHull::num_facets`]).
    pub facets: usize,
}

/// The checks, duplicate removal, initial simplex and joggle-and-retry loop shared by every
/// hull construction; `attempt` builds on one joggle.
fn build<T>(
    dim: usize,
    coords: &[f64],
    options: &HullOptions,
    mut build_once: impl FnMut(&[f64], &[usize], &[usize], f64, f64, usize) -> std::result::Result<T, String>,
) -> Result<T> {
    if dim < 2 || coords.len() % dim != 0 {
        return Err(GraspError::InvalidParameter {
            name: "coords",
            reason: format!("{} coordinates do not form points of dimension {dim} (dim ≥ 2)", coords.len()),
        });
    }
    crate::error::ensure_finite("hull points", coords.iter().copied())?;
    let n = coords.len() / dim;
    let scale = coords.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    // Drop exact duplicates (they would become near-coincident points after joggling).
    let mut unique: Vec<usize> = Vec::with_capacity(n);
    for i in 0..n {
        let p = &coords[i * dim..(i + 1) * dim];
        if !unique.iter().any(|&j| &coords[j * dim..(j + 1) * dim] == p) {
            unique.push(i);
        }
    }
    let simplex = initial_simplex(dim, coords, &unique, scale)?;

    let mut joggle = options.joggle;
    let mut last_reason = String::new();
    let mut jog = vec![0.0; coords.len()];
    for attempt in 0..options.max_attempts {
        let mut rng = ChaCha8Rng::seed_from_u64(options.seed.wrapping_add(attempt as u64));
        let amp = joggle * scale;
        for (j, &c) in jog.iter_mut().zip(coords) {
            *j = c + amp * (2.0 * rng.random::<f64>() - 1.0);
        }
        match build_once(&jog, &unique, &simplex, scale, amp, attempt + 1) {
            Ok(built) => return Ok(built),
            Err(reason) => last_reason = reason,
        }
        joggle *= 10.0;
    }
    Err(GraspError::HullFailed { dimension: dim, attempts: options.max_attempts, reason: last_reason })
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    // Fixed-size fast path for the grasp wrench space (6-D).
    if let (Ok(a), Ok(b)) = (<&[f64; 6]>::try_from(a), <&[f64; 6]>::try_from(b)) {
        return (a[0] * b[0] + a[1] * b[1]) + (a[2] * b[2] + a[3] * b[3]) + (a[4] * b[4] + a[5] * b[5]);
    }
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::linalg::{determinant, determinant6};
    use super::*;

    fn cube(d: usize) -> Vec<Vec<f64>> {
        (0..1usize << d).map(|m| (0..d).map(|k| if m >> k & 1 == 1 { 1.0 } else { -1.0 }).collect()).collect()
    }

    #[test]
    fn square_and_cube_volume_and_facets() {
        let h = ConvexHull::new(2, &cube(2), &HullOptions::default()).unwrap();
        assert_eq!(h.num_facets(), 4);
        assert!((h.volume() - 4.0).abs() < 1e-6);
        let h = ConvexHull::new(3, &cube(3), &HullOptions::default()).unwrap();
        // 6 square faces, each split into 2 triangles.
        assert_eq!(h.num_facets(), 12);
        assert_eq!(h.vertices().len(), 8);
        assert!((h.volume() - 8.0).abs() < 1e-6);
        assert!((h.depth(&[0.0, 0.0, 0.0]) - 1.0).abs() < 1e-6);
    }

    /// The initial simplex as it was first written (every residual recomputed from the
    /// first point each round): the oracle of the incremental one.
    fn initial_simplex_recomputed(d: usize, pts: &[f64], unique: &[usize], scale: f64) -> Result<Vec<usize>> {
        let degenerate = |rank| GraspError::DegenerateHull { dimension: d, affine_rank: rank };
        if unique.is_empty() || scale == 0.0 {
            return Err(degenerate(0));
        }
        let p = |i: usize| &pts[i * d..][..d];
        let first = *unique.iter().min_by(|&&a, &&b| p(a)[0].total_cmp(&p(b)[0])).unwrap_or(&unique[0]);
        let mut simplex = vec![first];
        let mut basis: Vec<Vec<f64>> = Vec::with_capacity(d);
        let mut r = vec![0.0; d];
        for k in 0..d {
            let mut best = (0.0, usize::MAX, Vec::new());
            for &i in unique {
                for (rj, (a, b)) in r.iter_mut().zip(p(i).iter().zip(p(first))) {
                    *rj = a - b;
                }
                for q in &basis {
                    let s = dot(q, &r);
                    for (rj, qj) in r.iter_mut().zip(q) {
                        *rj -= s * qj;
                    }
                }
                let norm = dot(&r, &r).sqrt();
                if norm > best.0 {
                    best = (norm, i, r.clone());
                }
            }
            if best.0 <= 1e-12 * scale {
                return Err(degenerate(k));
            }
            let (norm, i, mut v) = best;
            v.iter_mut().for_each(|x| *x /= norm);
            simplex.push(i);
            basis.push(v);
        }
        Ok(simplex)
    }

    /// The incremental initial simplex picks the very points of the recomputing one, and
    /// fails with the same rank, on random clouds in 2-7 dimensions (some flattened to a
    /// lower rank, some with duplicates left out of `unique`).
    #[test]
    fn incremental_initial_simplex_matches_the_recomputed_one() {
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let mut degenerate = 0;
        for case in 0..3000 {
            let d = 2 + case % 6;
            let n = rng.random_range(1..40);
            let mut pts: Vec<f64> = (0..n * d).map(|_| rng.random_range(-1.0..1.0)).collect();
            // A quarter of the clouds lie in a lower-dimensional subspace.
            let flat = if case % 4 == 0 { rng.random_range(1..d) } else { d };
            pts.chunks_exact_mut(d).for_each(|p| p[flat..].iter_mut().for_each(|x| *x = 0.0));
            let unique: Vec<usize> = (0..n).filter(|i| i % 7 != 3).collect();
            if unique.is_empty() {
                continue;
            }
            let scale = pts.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let fast = linalg::initial_simplex(d, &pts, &unique, scale);
            let slow = initial_simplex_recomputed(d, &pts, &unique, scale);
            match (fast, slow) {
                (Ok(a), Ok(b)) => assert_eq!(a, b, "case {case}"),
                (
                    Err(GraspError::DegenerateHull { affine_rank: a, .. }),
                    Err(GraspError::DegenerateHull { affine_rank: b, .. }),
                ) => {
                    assert_eq!(a, b, "case {case}");
                    degenerate += 1;
                }
                (a, b) => panic!("case {case}: {a:?} vs {b:?}"),
            }
        }
        assert!(degenerate >= 500, "only {degenerate} degenerate clouds");
    }

    #[test]
    fn determinant_of_known_matrix() {
        let mut m = vec![2.0, 0.0, 1.0, 1.0, 3.0, 2.0, 1.0, 1.0, 2.0];
        assert!((determinant(3, &mut m) - 6.0).abs() < 1e-12);
    }

    #[test]
    fn fixed_6x6_determinant_is_bit_identical_to_the_general_one() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for case in 0..2000 {
            let mut m: Vec<f64> = (0..36).map(|_| rng.random_range(-1.0..1.0)).collect();
            if case % 7 == 0 {
                // Singular: a repeated row.
                let row = m[..6].to_vec();
                m[30..].copy_from_slice(&row);
            }
            let fixed = determinant6(&m);
            assert_eq!(fixed.to_bits(), determinant(6, &mut m.clone()).to_bits(), "case {case}");
        }
        let mut identity = vec![0.0; 36];
        (0..6).for_each(|i| identity[i * 7] = 2.0);
        assert_eq!(determinant6(&identity), 64.0);
    }
}
