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
//! Cost: the 32 primitive wrenches of a 4-contact, 8-edge grasp give about 1,200 facets in
//! 6-D, built in about half a millisecond on one core.

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
            match Builder::run(dim, &jog, &unique, &simplex, scale) {
                Ok(b) => return Ok(b.finish(coords, amp, attempt + 1)),
                Err(reason) => last_reason = reason,
            }
            joggle *= 10.0;
        }
        Err(GraspError::HullFailed { dimension: dim, attempts: options.max_attempts, reason: last_reason })
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

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    // Fixed-size fast path for the grasp wrench space (6-D).
    if let (Ok(a), Ok(b)) = (<&[f64; 6]>::try_from(a), <&[f64; 6]>::try_from(b)) {
        return (a[0] * b[0] + a[1] * b[1]) + (a[2] * b[2] + a[3] * b[3]) + (a[4] * b[4] + a[5] * b[5]);
    }
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Greedy (pivoted Gram-Schmidt) choice of `d + 1` affinely independent points.
fn initial_simplex(d: usize, pts: &[f64], unique: &[usize], scale: f64) -> Result<Vec<usize>> {
    let degenerate = |rank| GraspError::DegenerateHull { dimension: d, affine_rank: rank };
    if unique.is_empty() || scale == 0.0 {
        return Err(degenerate(0));
    }
    let p = |i: usize| &pts[i * d..(i + 1) * d];
    // Start from the point with the smallest first coordinate, then add the point farthest
    // from the affine span of the chosen ones.
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

/// Quickhull state on the joggled points (facets stored flat, `d` entries per facet).
struct Builder<'a> {
    d: usize,
    pts: &'a [f64],
    center: Vec<f64>,
    verts: Vec<usize>,
    nbrs: Vec<usize>,
    normals: Vec<f64>,
    offsets: Vec<f64>,
    alive: Vec<bool>,
    /// Outside points of each facet with their distance above it.
    outside: Vec<Vec<(usize, f64)>>,
    eps: f64,
    scale: f64,
    qr: Vec<f64>,
    vnorm: Vec<f64>,
}

impl<'a> Builder<'a> {
    fn run(
        d: usize,
        pts: &'a [f64],
        unique: &[usize],
        simplex: &[usize],
        scale: f64,
    ) -> std::result::Result<Self, String> {
        let mut center = vec![0.0; d];
        for &i in simplex {
            for (c, x) in center.iter_mut().zip(&pts[i * d..(i + 1) * d]) {
                *c += x / (d + 1) as f64;
            }
        }
        // Facets created: a few dozen per point in 6-D; vectors grow beyond if needed.
        let capacity = 16 * d * unique.len();
        let mut b = Builder {
            d,
            pts,
            center,
            verts: Vec::with_capacity(capacity * d),
            nbrs: Vec::with_capacity(capacity * d),
            normals: Vec::with_capacity(capacity * d),
            offsets: Vec::with_capacity(capacity),
            alive: Vec::with_capacity(capacity),
            outside: Vec::with_capacity(capacity),
            eps: 1e-13 * scale,
            scale,
            qr: vec![0.0; d * d],
            vnorm: vec![0.0; d],
        };
        // Initial simplex: facet j omits simplex[j]; its neighbour opposite simplex[k] is facet k.
        for j in 0..=d {
            let vs: Vec<usize> = simplex.iter().enumerate().filter(|&(k, _)| k != j).map(|(_, &v)| v).collect();
            let ns: Vec<usize> = (0..=d).filter(|&k| k != j).collect();
            b.add_facet(&vs, &ns, None)?;
        }
        for &i in unique {
            if simplex.contains(&i) {
                continue;
            }
            for f in 0..=d {
                let h = b.dist(f, i);
                if h > b.eps {
                    b.outside[f].push((i, h));
                    break;
                }
            }
        }
        let mut stack: Vec<usize> = (0..=d).filter(|&f| !b.outside[f].is_empty()).collect();
        let mut stamp = vec![0u32; 0];
        let mut state = vec![0u8; 0];
        let mut apex_dist = vec![0.0f64; 0];
        let mut iteration = 0u32;
        let mut visible = Vec::new();
        let mut horizon: Vec<(usize, usize)> = Vec::new();
        let mut ridges: Vec<(u64, usize, usize)> = Vec::new();
        let mut table: Vec<(u64, usize, usize)> = Vec::new();
        const PAIRED: usize = usize::MAX - 1;
        let mut rng = ChaCha8Rng::seed_from_u64(0x5eed);
        let zobrist: Vec<u64> = (0..pts.len() / d).map(|_| rng.random()).collect();
        let mut new_facets = Vec::new();
        let mut vs = vec![0; d];
        let mut ns = vec![usize::MAX; d];
        while let Some(f0) = stack.pop() {
            if !b.alive[f0] || b.outside[f0].is_empty() {
                continue;
            }
            iteration += 1;
            let apex = b.outside[f0].iter().max_by(|x, y| x.1.total_cmp(&y.1)).map_or(usize::MAX, |x| x.0);
            // Breadth-first search of the facets visible from the apex.
            stamp.resize(b.alive.len(), 0);
            state.resize(b.alive.len(), 0);
            apex_dist.resize(b.alive.len(), 0.0);
            visible.clear();
            horizon.clear();
            visible.push(f0);
            stamp[f0] = iteration;
            state[f0] = 1;
            apex_dist[f0] = b.dist(f0, apex);
            let mut head = 0;
            while head < visible.len() {
                let f = visible[head];
                head += 1;
                for i in 0..d {
                    let g = b.nbrs[f * d + i];
                    if stamp[g] != iteration {
                        stamp[g] = iteration;
                        apex_dist[g] = b.dist(g, apex);
                        state[g] = if apex_dist[g] > b.eps { 1 } else { 2 };
                        if state[g] == 1 {
                            visible.push(g);
                        }
                    }
                    if state[g] == 2 {
                        horizon.push((f, i));
                    }
                }
            }
            // Cone of new facets over the horizon.
            new_facets.clear();
            for &(f, i) in &horizon {
                vs.copy_from_slice(&b.verts[f * d..(f + 1) * d]);
                vs[i] = apex;
                let other = b.nbrs[f * d + i];
                ns.iter_mut().for_each(|x| *x = usize::MAX);
                ns[i] = other;
                let nf = b.add_facet(&vs, &ns, Some((f, other, apex, apex_dist[f], apex_dist[other])))?;
                let back = (0..d).find(|&j| b.nbrs[other * d + j] == f).ok_or("broken neighbour link")?;
                b.nbrs[other * d + back] = nf;
                new_facets.push((nf, i));
            }
            // Pair the new facets' ridges through the apex: a ridge's key is the
            // order-independent (Zobrist) hash of its vertices (64-bit, collisions are
            // astronomically unlikely and would fail the final verification).
            ridges.clear();
            for &(nf, i) in &new_facets {
                let vs = &b.verts[nf * d..(nf + 1) * d];
                let h = vs.iter().fold(0u64, |h, &v| h.wrapping_add(zobrist[v]));
                for k in (0..d).filter(|&k| k != i) {
                    ridges.push((h.wrapping_sub(zobrist[vs[k]]), nf, k));
                }
            }
            // Open-addressing table keyed by the ridge hash; each key must occur twice.
            let size = (2 * ridges.len()).next_power_of_two();
            table.clear();
            table.resize(size, (0, usize::MAX, 0));
            let mut unpaired = 0usize;
            for &(h, fa, ka) in &ridges {
                let mut slot = (h as usize) & (size - 1);
                loop {
                    let (hb, fb, kb) = table[slot];
                    if fb == usize::MAX {
                        table[slot] = (h, fa, ka);
                        unpaired += 1;
                        break;
                    }
                    if hb == h && fb != PAIRED {
                        b.nbrs[fa * d + ka] = fb;
                        b.nbrs[fb * d + kb] = fa;
                        table[slot].1 = PAIRED;
                        unpaired -= 1;
                        break;
                    }
                    slot = (slot + 1) & (size - 1);
                }
            }
            if unpaired != 0 {
                return Err("horizon ridges do not pair up".into());
            }
            // Reassign the outside points of the visible facets.
            for &f in &visible {
                b.alive[f] = false;
                let pts_f = std::mem::take(&mut b.outside[f]);
                for &(q, _) in &pts_f {
                    if q == apex {
                        continue;
                    }
                    for &(nf, _) in &new_facets {
                        let h = b.dist(nf, q);
                        if h > b.eps {
                            b.outside[nf].push((q, h));
                            break;
                        }
                    }
                }
            }
            for &(nf, _) in &new_facets {
                if !b.outside[nf].is_empty() {
                    stack.push(nf);
                }
            }
        }
        b.verify()?;
        Ok(b)
    }

    /// Signed distance of point `i` above facet `f`.
    #[inline]
    fn dist(&self, f: usize, i: usize) -> f64 {
        let d = self.d;
        dot(&self.normals[f * d..(f + 1) * d], &self.pts[i * d..(i + 1) * d]) - self.offsets[f]
    }

    /// Appends a facet, computing its oriented plane; fails on a degenerate simplex.
    ///
    /// With `cone = Some((visible, other, apex, a, c))` the facet is the cone of the horizon
    /// ridge between `visible` and `other` over `apex`, whose distances above them are `a`
    /// and `c`. Its normal then lies in the plane of the two
    /// parents' normals: `n ∝ −dist_other(apex) · n_visible + dist_visible(apex) · n_other`
    /// (orthogonal to the ridge and to `apex − ridge`), an `O(d)` update. It is accepted if
    /// the combination is well conditioned and two vertices lie on the new plane to
    /// `1e-11 · scale`; otherwise (and for the initial
    /// simplex) the plane comes from a Householder QR of the edges.
    fn add_facet(
        &mut self,
        vs: &[usize],
        ns: &[usize],
        cone: Option<(usize, usize, usize, f64, f64)>,
    ) -> std::result::Result<usize, String> {
        let d = self.d;
        let f = self.offsets.len();
        self.normals.resize((f + 1) * d, 0.0);
        let mut offset = None;
        if let Some((vis, other, apex, a, c)) = cone {
            let (head, tail) = self.normals.split_at_mut(f * d);
            let normal = &mut tail[..d];
            for (k, x) in normal.iter_mut().enumerate() {
                *x = a * head[other * d + k] - c * head[vis * d + k];
            }
            let len = dot(normal, normal).sqrt();
            // Well conditioned unless the parents are nearly opposite (a knife-edge ridge).
            if len > 1e-2 * (a.abs() + c.abs()) {
                normal.iter_mut().for_each(|x| *x /= len);
                let b = dot(normal, &self.pts[apex * d..(apex + 1) * d]);
                // Spot-check two vertices (one is not the apex) against drift of the
                // parents' normals.
                let on_plane = [vs[0], vs[d - 1]]
                    .iter()
                    .all(|&v| (dot(normal, &self.pts[v * d..(v + 1) * d]) - b).abs() <= 1e-11 * self.scale);
                let below = dot(normal, &self.center) - b < -1e-12 * self.scale;
                if on_plane && below {
                    offset = Some(b);
                }
            }
        }
        let offset = match offset {
            Some(b) => b,
            None => plane(
                d,
                self.pts,
                vs,
                &self.center,
                &mut self.qr,
                &mut self.vnorm,
                &mut self.normals[f * d..(f + 1) * d],
                self.scale,
            )
            .ok_or("degenerate facet")?,
        };
        self.offsets.push(offset);
        self.verts.extend_from_slice(vs);
        self.nbrs.extend_from_slice(ns);
        self.alive.push(true);
        self.outside.push(Vec::new());
        Ok(f)
    }

    /// Ridge pairing and local convexity of every pair of neighbouring facets.
    fn verify(&self) -> std::result::Result<(), String> {
        let d = self.d;
        let tol = 1e-7 * self.scale;
        for f in (0..self.alive.len()).filter(|&f| self.alive[f]) {
            for i in 0..d {
                let g = self.nbrs[f * d + i];
                if g == usize::MAX || !self.alive[g] {
                    return Err("facet with a dead or missing neighbour".into());
                }
                if g < f {
                    // Each ridge once: the two one-sided convexity tests are equivalent.
                    continue;
                }
                let j = (0..d).find(|&j| self.nbrs[g * d + j] == f).ok_or("asymmetric neighbour link")?;
                if self.dist(f, self.verts[g * d + j]) > tol {
                    return Err("non-convex ridge".into());
                }
            }
        }
        Ok(())
    }

    fn finish(self, original: &[f64], joggle: f64, attempts: usize) -> ConvexHull {
        let d = self.d;
        let alive: Vec<usize> = (0..self.alive.len()).filter(|&f| self.alive[f]).collect();
        let mut facet_vertices = Vec::with_capacity(alive.len() * d);
        let mut normals = Vec::with_capacity(alive.len() * d);
        let mut offsets = Vec::with_capacity(alive.len());
        let mut volume = 0.0;
        let mut m = vec![0.0; d * d];
        let factorial: f64 = (1..=d).map(|k| k as f64).product();
        for &f in &alive {
            let vs = &self.verts[f * d..(f + 1) * d];
            facet_vertices.extend_from_slice(vs);
            normals.extend_from_slice(&self.normals[f * d..(f + 1) * d]);
            offsets.push(self.offsets[f]);
            for (row, &v) in m.chunks_exact_mut(d).zip(vs) {
                for ((x, o), c) in row.iter_mut().zip(&original[v * d..(v + 1) * d]).zip(&self.center) {
                    *x = o - c;
                }
            }
            volume += determinant(d, &mut m).abs() / factorial;
        }
        let mut is_vertex = vec![false; original.len() / d];
        facet_vertices.iter().for_each(|&v| is_vertex[v] = true);
        let vertices = (0..is_vertex.len()).filter(|&v| is_vertex[v]).collect();
        ConvexHull {
            dim: d,
            facet_vertices,
            normals,
            offsets,
            vertices,
            interior: self.center,
            volume,
            joggle,
            attempts,
        }
    }
}

/// Unit normal (written to `normal`) and offset of the hyperplane through the points `vs`,
/// oriented so that `center` lies below it. `None` if the points are (numerically)
/// affinely dependent or the plane passes through `center`.
#[allow(clippy::too_many_arguments)]
fn plane(
    d: usize,
    pts: &[f64],
    vs: &[usize],
    center: &[f64],
    qr: &mut [f64],
    vnorm: &mut [f64],
    normal: &mut [f64],
    scale: f64,
) -> Option<f64> {
    let m = d - 1;
    let x0 = &pts[vs[0] * d..(vs[0] + 1) * d];
    // Columns of qr: edge vectors x_k − x_0, k = 1..d.
    let mut max_edge = 0.0_f64;
    for k in 0..m {
        let xk = &pts[vs[k + 1] * d..(vs[k + 1] + 1) * d];
        let col = &mut qr[k * d..(k + 1) * d];
        for r in 0..d {
            col[r] = xk[r] - x0[r];
        }
        max_edge = max_edge.max(dot(col, col).sqrt());
    }
    // Householder QR; the reflector of column k is stored in rows k.. of column k.
    for k in 0..m {
        let (head, tail) = qr.split_at_mut((k + 1) * d);
        let v = &mut head[k * d + k..(k + 1) * d];
        let norm = dot(v, v).sqrt();
        if norm <= 1e-12 * max_edge {
            return None;
        }
        let alpha = if v[0] >= 0.0 { -norm } else { norm };
        v[0] -= alpha;
        let vv = dot(v, v);
        vnorm[k] = vv;
        for j in 0..(m - k - 1) {
            let col = &mut tail[j * d + k..(j + 1) * d];
            let s = 2.0 * dot(v, col) / vv;
            for (c, vi) in col.iter_mut().zip(v.iter()) {
                *c -= s * vi;
            }
        }
    }
    // normal = H_0 H_1 … H_{m−1} e_{d−1}, orthogonal to every edge.
    normal.iter_mut().for_each(|x| *x = 0.0);
    normal[d - 1] = 1.0;
    for k in (0..m).rev() {
        let v = &qr[k * d + k..(k + 1) * d];
        let s = 2.0 * dot(v, &normal[k..]) / vnorm[k];
        for (x, vi) in normal[k..].iter_mut().zip(v) {
            *x -= s * vi;
        }
    }
    let len = dot(normal, normal).sqrt();
    normal.iter_mut().for_each(|x| *x /= len);
    let mut offset = dot(normal, x0);
    let below = dot(normal, center) - offset;
    if below.abs() <= 1e-12 * scale.max(max_edge) {
        return None;
    }
    if below > 0.0 {
        normal.iter_mut().for_each(|x| *x = -*x);
        offset = -offset;
    }
    Some(offset)
}

/// Determinant of the row-major `d × d` matrix `m` (destroyed), by LU with partial pivoting.
fn determinant(d: usize, m: &mut [f64]) -> f64 {
    let m = &mut m[..d * d];
    let mut det = 1.0;
    for k in 0..d {
        let mut p = k;
        let mut best = m[k * d + k].abs();
        for r in (k + 1)..d {
            let v = m[r * d + k].abs();
            if v > best {
                best = v;
                p = r;
            }
        }
        if best == 0.0 {
            return 0.0;
        }
        if p != k {
            let (top, bottom) = m.split_at_mut(p * d);
            top[k * d..(k + 1) * d].swap_with_slice(&mut bottom[..d]);
            det = -det;
        }
        let (top, bottom) = m.split_at_mut((k + 1) * d);
        let pivot_row = &top[k * d + k..(k + 1) * d];
        let pivot = pivot_row[0];
        det *= pivot;
        let inv = 1.0 / pivot;
        for row in bottom.chunks_exact_mut(d) {
            let row = &mut row[k..];
            let factor = row[0] * inv;
            for (x, &y) in row.iter_mut().zip(pivot_row) {
                *x -= factor * y;
            }
        }
    }
    det
}

#[cfg(test)]
mod tests {
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

    #[test]
    fn determinant_of_known_matrix() {
        let mut m = vec![2.0, 0.0, 1.0, 1.0, 3.0, 2.0, 1.0, 1.0, 2.0];
        assert!((determinant(3, &mut m) - 6.0).abs() < 1e-12);
    }
}
