//! Dense linear algebra of the hull builders: the initial simplex, the plane through `d`
//! points and determinants (the general LU and its bit-identical 6 × 6 specialisation).

use crate::error::{GraspError, Result};

use super::builder::Dim;
use super::dot;

/// Greedy (pivoted Gram-Schmidt) choice of `d + 1` affinely independent points.
///
/// Each point's residual (its offset from the first point, less its projections on the
/// chosen directions, subtracted one after the other) is kept and updated by each new
/// direction only: the same operations in the same order as recomputing it every round.
pub(super) fn initial_simplex(d: usize, pts: &[f64], unique: &[usize], scale: f64) -> Result<Vec<usize>> {
    let degenerate = |rank| GraspError::DegenerateHull { dimension: d, affine_rank: rank };
    if unique.is_empty() || scale == 0.0 {
        return Err(degenerate(0));
    }
    let p = |i: usize| &pts[i * d..][..d];
    // Start from the point with the smallest first coordinate, then add the point farthest
    // from the affine span of the chosen ones.
    let first = *unique.iter().min_by(|&&a, &&b| p(a)[0].total_cmp(&p(b)[0])).unwrap_or(&unique[0]);
    let mut simplex = Vec::with_capacity(d + 1);
    simplex.push(first);
    let mut residuals = Vec::with_capacity(unique.len() * d);
    for &i in unique {
        residuals.extend(p(i).iter().zip(p(first)).map(|(a, b)| a - b));
    }
    let mut v = vec![0.0; d];
    for k in 0..d {
        let mut best = (0.0, usize::MAX);
        for (slot, r) in residuals.chunks_exact(d).enumerate() {
            let norm = dot(r, r).sqrt();
            if norm > best.0 {
                best = (norm, slot);
            }
        }
        if best.0 <= 1e-12 * scale {
            return Err(degenerate(k));
        }
        let (norm, slot) = best;
        for (x, r) in v.iter_mut().zip(&residuals[slot * d..][..d]) {
            *x = r / norm;
        }
        simplex.push(unique[slot]);
        if k + 1 < d {
            for r in residuals.chunks_exact_mut(d) {
                let s = dot(&v, r);
                for (rj, vj) in r.iter_mut().zip(&v) {
                    *rj -= s * vj;
                }
            }
        }
    }
    Ok(simplex)
}

/// Unit normal (written to `normal`) and offset of the hyperplane through the points `vs`,
/// oriented so that `center` lies below it. `None` if the points are (numerically)
/// affinely dependent or the plane passes through `center`. Generic over the dimension so
/// that with [`Fixed`](super::builder::Fixed) every loop has a constant length (the same
/// operations in the same order either way, so the same bits).
#[allow(clippy::too_many_arguments)]
pub(super) fn plane<D: Dim>(
    dim: D,
    pts: &[f64],
    vs: &[usize],
    center: &[f64],
    qr: &mut [f64],
    vnorm: &mut [f64],
    normal: &mut [f64],
    scale: f64,
) -> Option<f64> {
    let d = dim.n();
    let m = d - 1;
    let x0 = &pts[vs[0] * d..(vs[0] + 1) * d];
    // Columns of qr: edge vectors x_k − x_0, k = 1..d.
    let mut max_edge = 0.0_f64;
    for k in 0..m {
        let xk = &pts[vs[k + 1] * d..(vs[k + 1] + 1) * d];
        let col = &mut qr[k * d..][..d];
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

/// [`determinant`] of a 6 × 6 matrix, with the same operations in the same order (so the
/// same result, bit for bit) on a fixed-size copy: the entries below a pivot, which the
/// general version zeroes but never reads again, are not updated.
pub(super) fn determinant6(m: &[f64]) -> f64 {
    let mut a = [[0.0; 6]; 6];
    for (row, src) in a.iter_mut().zip(m.chunks_exact(6)) {
        row.copy_from_slice(src);
    }
    let mut det = 1.0;
    // One elimination step per column, with the column a constant so every loop unrolls.
    #[inline(always)]
    fn step<const K: usize>(a: &mut [[f64; 6]; 6], det: &mut f64) -> bool {
        let mut p = K;
        let mut best = a[K][K].abs();
        for (r, row) in a.iter().enumerate().skip(K + 1) {
            let v = row[K].abs();
            if v > best {
                best = v;
                p = r;
            }
        }
        if best == 0.0 {
            return false;
        }
        if p != K {
            a.swap(p, K);
            *det = -*det;
        }
        let pivot_row = a[K];
        let pivot = pivot_row[K];
        *det *= pivot;
        let inv = 1.0 / pivot;
        for row in a.iter_mut().skip(K + 1) {
            let factor = row[K] * inv;
            for c in (K + 1)..6 {
                row[c] -= factor * pivot_row[c];
            }
        }
        true
    }
    let full = step::<0>(&mut a, &mut det)
        && step::<1>(&mut a, &mut det)
        && step::<2>(&mut a, &mut det)
        && step::<3>(&mut a, &mut det)
        && step::<4>(&mut a, &mut det)
        && step::<5>(&mut a, &mut det);
    if full {
        det
    } else {
        0.0
    }
}

/// Determinant of the row-major `d × d` matrix `m` (destroyed), by LU with partial pivoting.
pub(super) fn determinant(d: usize, m: &mut [f64]) -> f64 {
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
            top[k * d..][..d].swap_with_slice(&mut bottom[..d]);
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
