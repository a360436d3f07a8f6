//! The previous quickhull builder, kept unchanged as the reference of the equivalence tests
//! (`ConvexHull::from_flat_reference`): the optimised [`super::builder`] must give bit-identical
//! facets, planes, epsilon and volume.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::builder::Dynamic;
use super::linalg::{determinant, plane};
use super::{dot, ConvexHull};

/// Quickhull state on the joggled points (facets stored flat, `d` entries per facet).
pub(super) struct Reference<'a> {
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

impl<'a> Reference<'a> {
    pub(super) fn run(
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
        let mut b = Reference {
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
    pub(super) fn dist(&self, f: usize, i: usize) -> f64 {
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
    pub(super) fn add_facet(
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
                Dynamic(d),
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
    pub(super) fn verify(&self) -> std::result::Result<(), String> {
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

    pub(super) fn finish(self, original: &[f64], joggle: f64, attempts: usize) -> ConvexHull {
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
