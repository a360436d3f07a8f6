//! The quickhull construction behind [`ConvexHull`](super::ConvexHull): facet visibility,
//! horizon, cone of new facets, outside sets, verification and volume.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::linalg::{determinant, determinant6, plane};
use super::{dot, ConvexHull};

mod epsilon;

/// End of an outside-point list.
const NONE: u32 = u32::MAX;

/// A facet's outside list: first and last entry in [`Storage::entries`] and the farthest
/// point with its distance (the last one of the largest distance, the choice
/// `Iterator::max_by` makes over the list).
#[derive(Clone, Copy)]
struct Outside {
    head: u32,
    tail: u32,
    farthest: (usize, f64),
}

impl Outside {
    const EMPTY: Self = Outside { head: NONE, tail: NONE, farthest: (usize::MAX, 0.0) };
}

/// The growable arrays of a [`Builder`], kept per thread between builds so a hull of a few
/// thousand facets does not allocate (and page-fault) its megabyte of storage every time.
#[derive(Default)]
struct Storage {
    /// Vertices and neighbours of the facets, `d` per facet, as `u32` to halve the memory the
    /// breadth-first searches walk (`u32::MAX`: neighbour not yet linked).
    verts: Vec<u32>,
    nbrs: Vec<u32>,
    normals: Vec<f64>,
    offsets: Vec<f64>,
    alive: Vec<bool>,
    /// Each facet's outside list.
    outside: Vec<Outside>,
    /// Outside-list entries: (point, next entry).
    entries: Vec<(u32, u32)>,
    // Per-iteration scratch of the main loop.
    /// Per facet: the iteration that last computed its distance to the apex, and that
    /// distance (the facet is visible iff it is above `eps`).
    mark: Vec<(u32, f64)>,
    visible: Vec<usize>,
    horizon: Vec<(usize, usize)>,
    /// Open-addressing table of the new facets' ridges: (hash, facet, index in facet).
    table: Vec<(u64, u32, u32)>,
    zobrist: Vec<u64>,
}

impl Storage {
    fn clear(&mut self) {
        self.verts.clear();
        self.nbrs.clear();
        self.normals.clear();
        self.offsets.clear();
        self.alive.clear();
        self.outside.clear();
        self.entries.clear();
        self.mark.clear();
    }
}

/// The per-build scratch of [`Builder::insert`] (arrays borrowed from [`Storage`]).
struct Scratch {
    /// Random 64-bit keys of the points, summed into order-independent ridge hashes.
    zobrist: Vec<u64>,
    visible: Vec<usize>,
    horizon: Vec<(usize, usize)>,
    table: Vec<(u64, u32, u32)>,
    vs: Vec<usize>,
    ns: Vec<usize>,
    /// Insertions so far (the stamp of [`Storage::mark`]).
    iteration: u32,
}

thread_local! {
    static STORAGE: std::cell::RefCell<Storage> = std::cell::RefCell::default();
}

/// The dimension of a [`Builder`]: known at compile time ([`Fixed`], for the 6-D wrench
/// space, so every per-facet loop has a constant length) or at run time ([`Dynamic`]).
pub(super) trait Dim: Copy {
    /// The dimension.
    fn n(self) -> usize;
}

/// A dimension given at run time.
#[derive(Clone, Copy)]
pub(super) struct Dynamic(pub(super) usize);

impl Dim for Dynamic {
    #[inline(always)]
    fn n(self) -> usize {
        self.0
    }
}

/// A dimension fixed at compile time.
#[derive(Clone, Copy)]
pub(super) struct Fixed<const N: usize>;

impl<const N: usize> Dim for Fixed<N> {
    #[inline(always)]
    fn n(self) -> usize {
        N
    }
}

/// Quickhull state on the joggled points (facets stored flat, `d` entries per facet).
///
/// The construction (order of apexes, facets, planes and outside sets) is exactly that of
/// the previous builder kept in `super::reference`; only the bookkeeping is cheaper: outside
/// sets are linked lists in one arena with the farthest point tracked on insertion, the
/// storage is reused per thread, and the points are handed to new facets by a scan over
/// their contiguous planes.
pub(super) struct Builder<'a, D: Dim> {
    dim: D,
    pts: &'a [f64],
    center: Vec<f64>,
    s: Storage,
    eps: f64,
    /// Accept a plane from the `O(d)` cone update only if every vertex lies on it to
    /// `1e-14 × scale` (else the QR of the vertices): the hull spot-checks two vertices to
    /// `1e-11 × scale`, which lets normals drift far beyond rounding; the depth search needs
    /// accurate planes (the hull keeps its check for its reference results).
    exact_planes: bool,
    scale: f64,
    qr: Vec<f64>,
    vnorm: Vec<f64>,
}

impl<D: Dim> Drop for Builder<'_, D> {
    fn drop(&mut self) {
        let s = std::mem::take(&mut self.s);
        // Ignore a thread being torn down (the storage is then simply freed).
        let _ = STORAGE.try_with(|cell| {
            if let Ok(mut slot) = cell.try_borrow_mut() {
                *slot = s;
            }
        });
    }
}

impl<'a, D: Dim> Builder<'a, D> {
    /// The builder with the initial simplex's `d + 1` facets (facet `j` omits `simplex[j]`)
    /// and no outside sets.
    fn start(
        dim: D,
        pts: &'a [f64],
        simplex: &[usize],
        scale: f64,
        exact_planes: bool,
    ) -> std::result::Result<Self, String> {
        let d = dim.n();
        let mut center = vec![0.0; d];
        for &i in simplex {
            for (c, x) in center.iter_mut().zip(&pts[i * d..][..d]) {
                *c += x / (d + 1) as f64;
            }
        }
        let mut s = STORAGE
            .try_with(|cell| cell.try_borrow_mut().map(|mut s| std::mem::take(&mut *s)).unwrap_or_default())
            .unwrap_or_default();
        s.clear();
        let (qr, vnorm) = (vec![0.0; d * d], vec![0.0; d]);
        let mut b = Builder { dim, pts, center, s, eps: 1e-13 * scale, exact_planes, scale, qr, vnorm };
        // Initial simplex: facet j omits simplex[j]; its neighbour opposite simplex[k] is facet k.
        let mut vs: Vec<usize> = Vec::with_capacity(d);
        let mut ns: Vec<usize> = Vec::with_capacity(d);
        for j in 0..=d {
            vs.clear();
            vs.extend(simplex.iter().enumerate().filter(|&(k, _)| k != j).map(|(_, &v)| v));
            ns.clear();
            ns.extend((0..=d).filter(|&k| k != j));
            b.add_facet(&vs, &ns, None)?;
        }
        Ok(b)
    }

    /// The scratch of [`Builder::insert`], taken out of the storage.
    fn take_scratch(&mut self) -> Scratch {
        let d = self.dim.n();
        let mut rng = ChaCha8Rng::seed_from_u64(0x5eed);
        let mut zobrist = std::mem::take(&mut self.s.zobrist);
        zobrist.clear();
        zobrist.extend((0..self.pts.len() / d).map(|_| rng.random::<u64>()));
        Scratch {
            zobrist,
            visible: std::mem::take(&mut self.s.visible),
            horizon: std::mem::take(&mut self.s.horizon),
            table: std::mem::take(&mut self.s.table),
            vs: vec![0; d],
            ns: vec![usize::MAX; d],
            iteration: 0,
        }
    }

    /// Returns the scratch's arrays to the storage (kept per thread).
    fn put_scratch(&mut self, x: Scratch) {
        self.s.zobrist = x.zobrist;
        self.s.visible = x.visible;
        self.s.horizon = x.horizon;
        self.s.table = x.table;
    }

    /// Quickhull: the full hull of the points `unique` (the initial `simplex` among them).
    pub(super) fn run(
        dim: D,
        pts: &'a [f64],
        unique: &[usize],
        simplex: &[usize],
        scale: f64,
    ) -> std::result::Result<Self, String> {
        let d = dim.n();
        let mut b = Self::start(dim, pts, simplex, scale, false)?;
        for &i in unique {
            if simplex.contains(&i) {
                continue;
            }
            for f in 0..=d {
                let h = b.dist(f, i);
                if h > b.eps {
                    b.push_outside(f, i, h);
                    break;
                }
            }
        }
        let mut stack: Vec<usize> = (0..=d).filter(|&f| b.s.outside[f].head != NONE).collect();
        let mut x = b.take_scratch();
        let result = (|| {
            while let Some(f0) = stack.pop() {
                if !b.s.alive[f0] || b.s.outside[f0].head == NONE {
                    continue;
                }
                let apex = b.s.outside[f0].farthest.0;
                let new_facets = b.insert(f0, apex, &mut x)?;
                // Hand the outside points of the (now dead) visible facets to the first new
                // facet they are above (in creation order).
                for &f in &x.visible {
                    let mut e = b.s.outside[f].head;
                    b.s.outside[f].head = NONE;
                    while e != NONE {
                        let (q, next) = b.s.entries[e as usize];
                        e = next;
                        let q = q as usize;
                        if q == apex {
                            continue;
                        }
                        if let Some((nf, h)) = b.first_above(new_facets.clone(), q) {
                            b.push_outside(nf, q, h);
                        }
                    }
                }
                for nf in new_facets {
                    if b.s.outside[nf].head != NONE {
                        stack.push(nf);
                    }
                }
            }
            b.verify()
        })();
        b.put_scratch(x);
        result?;
        Ok(b)
    }

    /// Adds `apex` (above facet `f0`) to the polytope: the facets visible from it, found by a
    /// breadth-first search from `f0` and left in `x.visible`, die and are replaced by the
    /// cone of new facets over their horizon, which get the contiguous indices returned.
    fn insert(
        &mut self,
        f0: usize,
        apex: usize,
        x: &mut Scratch,
    ) -> std::result::Result<std::ops::Range<usize>, String> {
        const EMPTY: u32 = u32::MAX;
        const PAIRED: u32 = u32::MAX - 1;
        let d = self.dim.n();
        let b = self;
        x.iteration += 1;
        let iteration = x.iteration;
        let (visible, horizon, table, vs, ns, zobrist) =
            (&mut x.visible, &mut x.horizon, &mut x.table, &mut x.vs, &mut x.ns, &x.zobrist);
        // Breadth-first search of the facets visible from the apex.
        let nf_total = b.s.alive.len();
        b.s.mark.resize(nf_total, (0, 0.0));
        visible.clear();
        horizon.clear();
        visible.push(f0);
        // The apex is above f0 by the very distance that chose it.
        b.s.mark[f0] = (iteration, b.dist(f0, apex));
        let mut head = 0;
        while head < visible.len() {
            let f = visible[head];
            head += 1;
            for i in 0..d {
                let g = b.s.nbrs[f * d + i] as usize;
                let (stamp, mut h) = b.s.mark[g];
                if stamp != iteration {
                    h = b.dist(g, apex);
                    b.s.mark[g] = (iteration, h);
                    if h > b.eps {
                        visible.push(g);
                    }
                }
                let above = h > b.eps;
                if !above {
                    horizon.push((f, i));
                }
            }
        }
        // Cone of new facets over the horizon; they get the contiguous indices
        // first_new.. in horizon order.
        let first_new = b.s.offsets.len();
        for (k, &(f, i)) in horizon.iter().enumerate() {
            for (x, &v) in vs.iter_mut().zip(&b.s.verts[f * d..][..d]) {
                *x = v as usize;
            }
            vs[i] = apex;
            let other = b.s.nbrs[f * d + i] as usize;
            ns.iter_mut().for_each(|x| *x = usize::MAX);
            ns[i] = other;
            let cone = Some((f, other, apex, b.s.mark[f].1, b.s.mark[other].1));
            let nf = b.add_facet(vs, ns, cone)?;
            debug_assert_eq!(nf, first_new + k);
            let back = (0..d).find(|&j| b.s.nbrs[other * d + j] as usize == f).ok_or("broken neighbour link")?;
            b.s.nbrs[other * d + back] = nf as u32;
        }
        let new_facets = first_new..b.s.offsets.len();
        // Pair the new facets' ridges through the apex: a ridge's key is the
        // order-independent (Zobrist) hash of its vertices (64-bit, collisions are
        // astronomically unlikely and would fail the final verification).
        let size = (2 * new_facets.len() * (d - 1)).next_power_of_two();
        table.clear();
        table.resize(size, (0, EMPTY, 0));
        let mut unpaired = 0usize;
        for (&(_, i), nf) in horizon.iter().zip(new_facets.clone()) {
            let vs = &b.s.verts[nf * d..][..d];
            let hash = vs.iter().fold(0u64, |h, &v| h.wrapping_add(zobrist[v as usize]));
            for k in (0..d).filter(|&k| k != i) {
                let h = hash.wrapping_sub(zobrist[vs[k] as usize]);
                let mut slot = (h as usize) & (size - 1);
                loop {
                    let (hb, fb, kb) = table[slot];
                    if fb == EMPTY {
                        table[slot] = (h, nf as u32, k as u32);
                        unpaired += 1;
                        break;
                    }
                    if hb == h && fb != PAIRED {
                        b.s.nbrs[nf * d + k] = fb;
                        b.s.nbrs[fb as usize * d + kb as usize] = nf as u32;
                        table[slot].1 = PAIRED;
                        unpaired -= 1;
                        break;
                    }
                    slot = (slot + 1) & (size - 1);
                }
            }
        }
        if unpaired != 0 {
            return Err("horizon ridges do not pair up".to_string());
        }
        for &f in visible.iter() {
            b.s.alive[f] = false;
        }
        Ok(new_facets)
    }

    /// Appends point `q`, `h` above facet `f`, to the facet's outside list.
    #[inline]
    fn push_outside(&mut self, f: usize, q: usize, h: f64) {
        let e = self.s.entries.len() as u32;
        self.s.entries.push((q as u32, NONE));
        let o = &mut self.s.outside[f];
        if o.head == NONE {
            o.head = e;
            o.farthest = (q, h);
        } else {
            self.s.entries[o.tail as usize].1 = e;
            if o.farthest.1.total_cmp(&h) != std::cmp::Ordering::Greater {
                o.farthest = (q, h);
            }
        }
        o.tail = e;
    }

    /// The first facet of `facets` (in order) that point `q` is more than `eps` above, with
    /// that distance. Every distance is [`Builder::dist`]'s, bit for bit.
    #[inline]
    fn first_above(&self, facets: std::ops::Range<usize>, q: usize) -> Option<(usize, f64)> {
        let d = self.dim.n();
        let p = &self.pts[q * d..][..d];
        if let Ok(p) = <&[f64; 6]>::try_from(p) {
            // 6-D: four planes at a time (same arithmetic as `dot`, so same distances).
            let normals = &self.s.normals[facets.start * 6..facets.end * 6];
            let offsets = &self.s.offsets[facets.clone()];
            let mut base = facets.start;
            let mut chunks = normals.chunks_exact(24).zip(offsets.chunks_exact(4));
            for (n, o) in &mut chunks {
                let mut h = [0.0; 4];
                for (k, hk) in h.iter_mut().enumerate() {
                    let n = &n[k * 6..k * 6 + 6];
                    *hk = ((n[0] * p[0] + n[1] * p[1]) + (n[2] * p[2] + n[3] * p[3]) + (n[4] * p[4] + n[5] * p[5]))
                        - o[k];
                }
                if let Some(k) = h.iter().position(|&x| x > self.eps) {
                    return Some((base + k, h[k]));
                }
                base += 4;
            }
            return (base..facets.end).map(|f| (f, self.dist(f, q))).find(|&(_, h)| h > self.eps);
        }
        facets.map(|f| (f, self.dist(f, q))).find(|&(_, h)| h > self.eps)
    }

    /// Signed distance of point `i` above facet `f`.
    #[inline(always)]
    pub(super) fn dist(&self, f: usize, i: usize) -> f64 {
        let d = self.dim.n();
        dot(&self.s.normals[f * d..][..d], &self.pts[i * d..][..d]) - self.s.offsets[f]
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
    pub(super) fn add_facet(
        &mut self,
        vs: &[usize],
        ns: &[usize],
        cone: Option<(usize, usize, usize, f64, f64)>,
    ) -> std::result::Result<usize, String> {
        let d = self.dim.n();
        let f = self.s.offsets.len();
        self.s.normals.resize((f + 1) * d, 0.0);
        let mut offset = None;
        if let Some((vis, other, apex, a, c)) = cone {
            let (head, tail) = self.s.normals.split_at_mut(f * d);
            let normal = &mut tail[..d];
            let (n_other, n_vis) = (&head[other * d..][..d], &head[vis * d..][..d]);
            for ((x, no), nv) in normal.iter_mut().zip(n_other).zip(n_vis) {
                *x = a * no - c * nv;
            }
            let len = dot(normal, normal).sqrt();
            // Well conditioned unless the parents are nearly opposite (a knife-edge ridge).
            if len > 1e-2 * (a.abs() + c.abs()) {
                normal.iter_mut().for_each(|x| *x /= len);
                let b = dot(normal, &self.pts[apex * d..][..d]);
                // Spot-check two vertices (one is not the apex) against drift of the
                // parents' normals; with exact planes, every vertex to 1e-14 · scale.
                let on = |v: &usize, tol: f64| (dot(normal, &self.pts[v * d..][..d]) - b).abs() <= tol * self.scale;
                // (The apex is on the plane exactly: `b` is its own dot product.)
                let on_plane = if self.exact_planes {
                    vs[..d].iter().filter(|&&v| v != apex).all(|v| on(v, 1e-14))
                } else {
                    [vs[0], vs[d - 1]].iter().all(|v| on(v, 1e-11))
                };
                let below = dot(normal, &self.center) - b < -1e-12 * self.scale;
                if on_plane && below {
                    offset = Some(b);
                }
            }
        }
        let offset = match offset {
            Some(b) => b,
            None => plane(
                self.dim,
                self.pts,
                vs,
                &self.center,
                &mut self.qr,
                &mut self.vnorm,
                &mut self.s.normals[f * d..][..d],
                self.scale,
            )
            .ok_or("degenerate facet")?,
        };
        self.s.offsets.push(offset);
        if f >= (u32::MAX - 1) as usize || vs[..d].iter().any(|&v| v >= u32::MAX as usize) {
            return Err("too many facets or points".into());
        }
        // `usize::MAX` (no neighbour yet) becomes `u32::MAX`.
        self.s.verts.extend(vs[..d].iter().map(|&v| v as u32));
        self.s.nbrs.extend(ns[..d].iter().map(|&n| n.min(u32::MAX as usize) as u32));
        self.s.alive.push(true);
        self.s.outside.push(Outside::EMPTY);
        Ok(f)
    }

    /// Ridge pairing and local convexity of every pair of neighbouring facets.
    pub(super) fn verify(&self) -> std::result::Result<(), String> {
        let d = self.dim.n();
        let tol = 1e-7 * self.scale;
        for f in (0..self.s.alive.len()).filter(|&f| self.s.alive[f]) {
            for i in 0..d {
                let g = self.s.nbrs[f * d + i] as usize;
                if g == u32::MAX as usize || !self.s.alive[g] {
                    return Err("facet with a dead or missing neighbour".into());
                }
                if g < f {
                    // Each ridge once: the two one-sided convexity tests are equivalent.
                    continue;
                }
                let j = (0..d).find(|&j| self.s.nbrs[g * d + j] as usize == f).ok_or("asymmetric neighbour link")?;
                if self.dist(f, self.s.verts[g * d + j] as usize) > tol {
                    return Err("non-convex ridge".into());
                }
            }
        }
        Ok(())
    }

    /// Volume of the pyramid over facet `f` from the interior point, on the original
    /// (un-joggled) points; `m` is `d × d` scratch.
    #[inline]
    fn pyramid_volume(&self, f: usize, original: &[f64], m: &mut [f64], factorial: f64) -> f64 {
        let d = self.dim.n();
        let vs = &self.s.verts[f * d..][..d];
        let center = &self.center[..d];
        for (row, &v) in m.chunks_exact_mut(d).zip(vs) {
            for ((x, o), c) in row[..d].iter_mut().zip(&original[v as usize * d..][..d]).zip(center) {
                *x = o - c;
            }
        }
        if d == 6 { determinant6(m) } else { determinant(d, m) }.abs() / factorial
    }

    /// The depth of `point`: `min over facets of (b − n · point)`.
    pub(super) fn depth(&self, point: &[f64]) -> f64 {
        let d = self.dim.n();
        (0..self.s.alive.len())
            .filter(|&f| self.s.alive[f])
            .map(|f| self.s.offsets[f] - dot(&self.s.normals[f * d..][..d], point))
            .fold(f64::INFINITY, f64::min)
    }

    /// The depth of `point`, the volume and the facet count of the hull [`Builder::finish`]
    /// would give, bit for bit (same facets in the same order, same arithmetic), without
    /// copying the facets out.
    pub(super) fn summary(self, original: &[f64], point: &[f64]) -> super::HullSummary {
        let d = self.dim.n();
        let mut m = vec![0.0; d * d];
        let factorial: f64 = (1..=d).map(|k| k as f64).product();
        let (mut depth, mut volume, mut facets) = (f64::INFINITY, 0.0, 0);
        for f in (0..self.s.alive.len()).filter(|&f| self.s.alive[f]) {
            depth = f64::min(depth, self.s.offsets[f] - dot(&self.s.normals[f * d..][..d], point));
            volume += self.pyramid_volume(f, original, &mut m, factorial);
            facets += 1;
        }
        super::HullSummary { depth, volume, facets }
    }

    /// The hull of the original (un-joggled) points with this builder's facets.
    pub(super) fn finish(mut self, original: &[f64], joggle: f64, attempts: usize) -> ConvexHull {
        let d = self.dim.n();
        let s = &self.s;
        let count = s.alive.iter().filter(|&&a| a).count();
        let mut facet_vertices = Vec::with_capacity(count * d);
        let mut normals = Vec::with_capacity(count * d);
        let mut offsets = Vec::with_capacity(count);
        let mut volume = 0.0;
        let mut m = vec![0.0; d * d];
        let factorial: f64 = (1..=d).map(|k| k as f64).product();
        for f in (0..s.alive.len()).filter(|&f| s.alive[f]) {
            let vs = &s.verts[f * d..][..d];
            facet_vertices.extend(vs.iter().map(|&v| v as usize));
            normals.extend_from_slice(&s.normals[f * d..][..d]);
            offsets.push(s.offsets[f]);
            volume += self.pyramid_volume(f, original, &mut m, factorial);
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
            interior: std::mem::take(&mut self.center),
            volume,
            joggle,
            attempts,
        }
    }
}
