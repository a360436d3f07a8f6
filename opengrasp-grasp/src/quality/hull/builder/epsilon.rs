//! The depth of a point in a hull without the hull: an expanding-polytope search (EPA).
//!
//! The Ferrari-Canny epsilon is `min over unit u of max_i wᵢ · u` — the smallest offset of the
//! hull's facets — and only the facets nearest the origin decide it. The search grows a
//! polytope `Q` inside the hull `P` of the (joggled) points, from the builder's initial
//! simplex: it takes the facet of `Q` with the smallest depth below the point, queries the
//! support point of `P` in that facet's normal direction (the point farthest above it) and
//! stops when no point lies more than the builder's `eps` above it: that facet then
//! supports `P`, so its depth is `P`'s. Otherwise the support point joins `Q` through the
//! quickhull insertion ([`Builder::insert`]: the visible facets are replaced by a cone over
//! their horizon), and the new facets join the priority queue. Facets far from the point are
//! never refined, and the points inside `Q` never need outside sets.
//!
//! The final facet is a facet of the joggled points' hull, the one nearest the point. Every
//! plane of `Q` passes through all its vertices to `1e-14 × scale` (the hull's `O(d)` update
//! of the parents' normals is accepted only then, else the QR of the vertices; the hull itself
//! spot-checks two vertices to `1e-11 × scale`), so the depth is that of the exact facet to
//! about `1e-14 × scale`.
//!
//! Cost on the default suite's Barrett/salt-can force-closure grasps (callgrind): about 18
//! insertions and 1,560 facets created per grasp, 2.5 million instructions, against about
//! 10 million for the full hull.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::super::dot;
use super::{Builder, Dim};

/// A key that orders `f64`s as [`f64::total_cmp`] does.
#[inline]
fn order_key(x: f64) -> u64 {
    let bits = x.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

impl<'a, D: Dim> Builder<'a, D> {
    /// Depth of `point` in the hull of the points `unique` (the initial `simplex` among them):
    /// `min over facets of (b − n · point)` of the hull [`Builder::run`] builds, to rounding,
    /// when the point is inside; a non-positive number when it is outside (then `0 ≥` the
    /// result `≥` the hull's depth up to `eps`). Also returns the number of facets created.
    /// Fails (for a retry with a larger joggle) when the polytope's final verification does.
    pub(in crate::quality::hull) fn depth_search(
        dim: D,
        pts: &'a [f64],
        unique: &[usize],
        simplex: &[usize],
        scale: f64,
        point: &[f64],
    ) -> std::result::Result<(f64, usize), String> {
        let d = dim.n();
        let mut b = Self::start(dim, pts, simplex, scale, true)?;
        let mut x = b.take_scratch();
        let depth = |b: &Self, f: usize| b.s.offsets[f] - dot(&b.s.normals[f * d..][..d], point);
        let mut queue: BinaryHeap<Reverse<(u64, u32)>> =
            (0..=d).map(|f| Reverse((order_key(depth(&b, f)), f as u32))).collect();
        let result = (|| loop {
            let Some(Reverse((_, f0))) = queue.pop() else {
                return Err("empty facet queue".to_string());
            };
            let f0 = f0 as usize;
            if !b.s.alive[f0] {
                continue;
            }
            // Support point in the facet's normal direction: the farthest point above it.
            let mut apex = None;
            let mut farthest = b.eps;
            for &i in unique {
                let h = b.dist(f0, i);
                if h > farthest {
                    (apex, farthest) = (Some(i), h);
                }
            }
            let Some(apex) = apex else {
                b.verify()?;
                return Ok((depth(&b, f0), b.s.alive.len()));
            };
            for nf in b.insert(f0, apex, &mut x)? {
                queue.push(Reverse((order_key(depth(&b, nf)), nf as u32)));
            }
        })();
        b.put_scratch(x);
        result
    }
}

#[cfg(test)]
mod tests {
    use super::order_key;

    #[test]
    fn order_key_sorts_like_total_cmp() {
        let mut xs = [3.5, -0.0, 0.0, -2.0, 1e-300, -1e300, f64::INFINITY, f64::NEG_INFINITY, 7.0];
        let mut by_key = xs;
        xs.sort_by(f64::total_cmp);
        by_key.sort_by_key(|&x| order_key(x));
        assert_eq!(xs.map(f64::to_bits), by_key.map(f64::to_bits));
    }
}
