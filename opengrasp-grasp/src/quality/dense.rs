//! Dense active-set solvers for the two small programs of the force-closure test: the strict
//! LP by a two-phase tableau simplex, the min-norm point by Wolfe's algorithm.
//!
//! The programs have 7 rows and one column per primitive wrench (at most ~100), so a dense
//! tableau of 7 × (n + 10) numbers is all the state either solver needs. Both return `None`
//! when they cannot certify their answer (iteration cap, a numerically singular basis); the
//! callers in [`super::solver`] then fall back to the interior-point solves.

use crate::contact::Wrench;

/// Rows of the strict LP: six wrench components and the weights' sum.
const ROWS: usize = 7;
/// Pivot elements below this (in absolute value) are never used.
const PIVOT_TOL: f64 = 1e-11;
/// Reduced costs above `-COST_TOL` count as optimal.
const COST_TOL: f64 = 1e-10;
/// Simplex iterations per phase before giving up.
const MAX_PIVOTS: usize = 2000;
/// After this many pivots Dantzig's rule gives way to Bland's (no cycling).
const BLAND_AFTER: usize = 100;

/// The tableau of `min cᵀx s.t. A x = b, x ≥ 0` with `ROWS` rows, in canonical form for
/// `basis`; row-major, `cols` coefficients followed by the right-hand side per row.
struct Tableau {
    cols: usize,
    t: Vec<f64>,
    basis: [usize; ROWS],
    /// Reduced costs (`cols` entries) and minus the objective value.
    cost: Vec<f64>,
}

impl Tableau {
    fn at(&self, i: usize, j: usize) -> f64 {
        self.t[i * (self.cols + 1) + j]
    }

    fn rhs(&self, i: usize) -> f64 {
        self.at(i, self.cols)
    }

    fn pivot(&mut self, r: usize, e: usize) {
        let w = self.cols + 1;
        let p = self.t[r * w + e];
        for v in &mut self.t[r * w..(r + 1) * w] {
            *v /= p;
        }
        let (before, rest) = self.t.split_at_mut(r * w);
        let (row, after) = rest.split_at_mut(w);
        for other in before.chunks_exact_mut(w).chain(after.chunks_exact_mut(w)) {
            let f = other[e];
            if f != 0.0 {
                for (o, &x) in other.iter_mut().zip(row.iter()) {
                    *o -= f * x;
                }
                other[e] = 0.0;
            }
        }
        let f = self.cost[e];
        if f != 0.0 {
            for (o, &x) in self.cost.iter_mut().zip(row.iter()) {
                *o -= f * x;
            }
            self.cost[e] = 0.0;
        }
        self.basis[r] = e;
    }

    /// Runs the simplex on the current cost row over the columns `< allowed`; false if the
    /// iteration cap was hit (never seen on grasp wrench sets).
    fn optimise(&mut self, allowed: usize) -> bool {
        let mut blocked: Vec<usize> = Vec::new();
        for it in 0..MAX_PIVOTS {
            let bland = it >= BLAND_AFTER;
            let mut enter = None;
            let mut best = -COST_TOL;
            for j in 0..allowed {
                if blocked.contains(&j) {
                    continue;
                }
                let d = self.cost[j];
                if d < best {
                    enter = Some(j);
                    if bland {
                        break;
                    }
                    best = d;
                }
            }
            let Some(e) = enter else { return true };
            let mut leave: Option<(usize, f64)> = None;
            for i in 0..ROWS {
                let a = self.at(i, e);
                if a > PIVOT_TOL {
                    let ratio = self.rhs(i).max(0.0) / a;
                    let better = match leave {
                        None => true,
                        Some((l, r)) => ratio < r || (ratio == r && self.basis[i] < self.basis[l]),
                    };
                    if better {
                        leave = Some((i, ratio));
                    }
                }
            }
            let Some((r, _)) = leave else {
                // No positive entry: the program would be unbounded along column e, which
                // neither phase is, so its negative reduced cost is rounding noise.
                if blocked.len() == self.cols {
                    return false;
                }
                blocked.push(e);
                continue;
            };
            blocked.clear();
            self.pivot(r, e);
        }
        false
    }
}

/// The strict force-closure LP of [`super::solver::strict_combination`] solved exactly at a
/// vertex: `Some((s, λ))` with the optimum `s` (`-∞` and no weights if infeasible), `None` if
/// the simplex failed.
///
/// With `λ = μ + s·1` the LP becomes `max s` over `μ ≥ 0`, `s` free (split `s = s⁺ − s⁻`):
/// `W μ + s W·1 = 0`, `1ᵀμ + n s = 1`. Phase 1 minimises the sum of 7 artificial variables,
/// phase 2 maximises `s`; the final basic solution is recomputed from the original columns
/// (a 7 × 7 LU solve) so pivoting errors do not accumulate into the weights.
pub(crate) fn strict_lp(wrenches: &[Wrench]) -> Option<(f64, Option<Vec<f64>>)> {
    let n = wrenches.len();
    let sum: Wrench = wrenches.iter().sum();
    // Columns: μ (n), s⁺, s⁻, artificials (ROWS).
    let (sp, sm, art) = (n, n + 1, n + 2);
    let cols = n + 2 + ROWS;
    let column = |j: usize, out: &mut [f64; ROWS]| {
        if j < n {
            out[..6].copy_from_slice(wrenches[j].as_slice());
            out[6] = 1.0;
        } else if j == sp || j == sm {
            let sign = if j == sp { 1.0 } else { -1.0 };
            for k in 0..6 {
                out[k] = sign * sum[k];
            }
            out[6] = sign * n as f64;
        } else {
            *out = [0.0; ROWS];
            out[j - art] = 1.0;
        }
    };
    let w = cols + 1;
    let mut t = vec![0.0; ROWS * w];
    let mut c = [0.0; ROWS];
    for j in 0..art {
        column(j, &mut c);
        for i in 0..ROWS {
            t[i * w + j] = c[i];
        }
    }
    for i in 0..ROWS {
        t[i * w + art + i] = 1.0;
    }
    t[6 * w + cols] = 1.0;
    // Phase 1 cost: Σ artificials, priced out against the artificial basis.
    let mut cost = vec![0.0; w];
    for j in 0..w {
        cost[j] = -(0..ROWS).map(|i| t[i * w + j]).sum::<f64>();
    }
    for i in 0..ROWS {
        cost[art + i] = 0.0;
    }
    let mut basis = [0; ROWS];
    for (i, b) in basis.iter_mut().enumerate() {
        *b = art + i;
    }
    let mut tab = Tableau { cols, t, basis, cost };
    if !tab.optimise(art) {
        return None;
    }
    if -tab.cost[cols] > 1e-9 {
        return Some((f64::NEG_INFINITY, None));
    }
    // Drive zero-level artificials out of the basis; a row where that is impossible is
    // redundant and keeps its artificial at zero (its row has no other entries).
    for i in 0..ROWS {
        if tab.basis[i] >= art {
            let pick = (0..art)
                .filter(|&j| tab.at(i, j).abs() > 1e-9)
                .max_by(|&a, &b| tab.at(i, a).abs().total_cmp(&tab.at(i, b).abs()));
            if let Some(j) = pick {
                tab.pivot(i, j);
            }
        }
    }
    // Phase 2: minimise −s = −s⁺ + s⁻.
    tab.cost.iter_mut().for_each(|v| *v = 0.0);
    tab.cost[sp] = -1.0;
    tab.cost[sm] = 1.0;
    for i in 0..ROWS {
        let cb = tab.cost[tab.basis[i]];
        if cb != 0.0 {
            for j in 0..w {
                tab.cost[j] -= cb * tab.t[i * w + j];
            }
        }
    }
    if !tab.optimise(art) {
        return None;
    }
    // Recompute the basic solution from the original columns.
    let mut b = [[0.0; ROWS]; ROWS];
    for (k, &j) in tab.basis.iter().enumerate() {
        column(j, &mut c);
        for i in 0..ROWS {
            b[i][k] = c[i];
        }
    }
    let mut rhs = [0.0; ROWS];
    rhs[6] = 1.0;
    let xb = solve7(b, rhs)?;
    let mut mu = vec![0.0; n];
    let mut s = 0.0;
    for (&j, &v) in tab.basis.iter().zip(&xb) {
        if j < n {
            mu[j] = v.max(0.0);
        } else if j == sp {
            s += v;
        } else if j == sm {
            s -= v;
        }
    }
    if !s.is_finite() {
        return None;
    }
    Some((s, Some(mu.iter().map(|m| m + s).collect())))
}

/// Solves the 7 × 7 system `a x = b` by LU with partial pivoting; `None` if singular.
fn solve7(mut a: [[f64; ROWS]; ROWS], mut b: [f64; ROWS]) -> Option<[f64; ROWS]> {
    for k in 0..ROWS {
        let p = (k..ROWS).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        if a[p][k].abs() < 1e-14 {
            return None;
        }
        a.swap(k, p);
        b.swap(k, p);
        let (top, below) = a.split_at_mut(k + 1);
        let pivot = &top[k];
        for (i, row) in below.iter_mut().enumerate() {
            let f = row[k] / pivot[k];
            if f != 0.0 {
                for (x, &y) in row[k..].iter_mut().zip(&pivot[k..]) {
                    *x -= f * y;
                }
                b[k + 1 + i] -= f * b[k];
            }
        }
    }
    let mut x = [0.0; ROWS];
    for k in (0..ROWS).rev() {
        let s: f64 = (k + 1..ROWS).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k][k];
    }
    Some(x)
}

/// Wolfe's algorithm stops when `x·x − min_j wⱼ·x` falls below this times the largest
/// squared wrench norm (the distance is then within `tol·M/‖x‖` of the optimum).
const WOLFE_GAP: f64 = 1e-15;
/// Major iterations of Wolfe's algorithm before giving up.
const WOLFE_MAX: usize = 500;

/// Distance from the origin to the convex hull of `wrenches` and convex weights attaining it,
/// by Wolfe's (1976) min-norm-point algorithm; `None` if it did not converge (a numerically
/// dependent corral or the iteration cap).
///
/// The corral (at most 7 affinely independent wrenches) is kept with its convex weights; each
/// major step adds the wrench most opposed to the current point, each minor step moves to
/// the affine minimiser of the corral (a small least-squares solve) or, if that leaves the
/// simplex, as far towards it as the weights allow and drops the wrench whose weight hit 0.
pub(crate) fn wolfe_min_norm(wrenches: &[Wrench]) -> Option<(f64, Vec<f64>)> {
    let n = wrenches.len();
    let scale = wrenches.iter().map(|w| w.norm_squared()).fold(0.0, f64::max);
    if n == 0 || !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let first = (0..n).min_by(|&a, &b| wrenches[a].norm_squared().total_cmp(&wrenches[b].norm_squared()))?;
    let mut corral: Vec<usize> = vec![first];
    let mut weights: Vec<f64> = vec![1.0];
    let mut x = wrenches[first];
    let mut done = false;
    for _ in 0..WOLFE_MAX {
        let xx = x.norm_squared();
        let (j, pj) = (0..n).map(|i| (i, wrenches[i].dot(&x))).min_by(|a, b| a.1.total_cmp(&b.1))?;
        if xx - pj <= WOLFE_GAP * scale || corral.contains(&j) {
            done = true;
            break;
        }
        corral.push(j);
        weights.push(0.0);
        // Minor cycle.
        loop {
            let v = affine_minimiser(wrenches, &corral)?;
            if v.iter().all(|&vi| vi > 0.0) {
                weights.copy_from_slice(&v);
                break;
            }
            let mut theta = 1.0f64;
            for (&wi, &vi) in weights.iter().zip(&v) {
                if vi <= 0.0 && wi - vi > 0.0 {
                    theta = theta.min(wi / (wi - vi));
                }
            }
            for (wi, &vi) in weights.iter_mut().zip(&v) {
                *wi = (1.0 - theta) * *wi + theta * vi;
            }
            // Drop the wrenches whose weight reached zero (at least the blocking one).
            let drop = weights
                .iter()
                .enumerate()
                .filter(|(_, &wi)| wi <= 0.0)
                .map(|(k, _)| k)
                .next()
                .or_else(|| weights.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).map(|(k, _)| k))?;
            corral.remove(drop);
            weights.remove(drop);
            let mut k = 0;
            while k < corral.len() {
                if weights[k] <= 0.0 {
                    corral.remove(k);
                    weights.remove(k);
                } else {
                    k += 1;
                }
            }
            let total: f64 = weights.iter().sum();
            if total.is_nan() || total <= 0.0 {
                return None;
            }
            weights.iter_mut().for_each(|wi| *wi /= total);
        }
        x = corral.iter().zip(&weights).map(|(&i, &wi)| wrenches[i] * wi).sum();
    }
    if !done {
        return None;
    }
    let mut full = vec![0.0; n];
    for (&i, &wi) in corral.iter().zip(&weights) {
        full[i] = wi;
    }
    Some((x.norm(), full))
}

/// Weights `v` (summing to one) of the point of the affine hull of `corral` nearest the
/// origin, by Householder QR of the differences to the first wrench; `None` if the corral is
/// numerically affinely dependent.
fn affine_minimiser(wrenches: &[Wrench], corral: &[usize]) -> Option<Vec<f64>> {
    let k = corral.len() - 1;
    let p0 = wrenches[corral[0]];
    if k == 0 {
        return Some(vec![1.0]);
    }
    // Columns d_i = p_i − p0 (6 × k), right-hand side −p0; least squares by Householder QR.
    let mut a = [[0.0; 6]; 6];
    for (c, &i) in corral[1..].iter().enumerate() {
        let d = wrenches[i] - p0;
        a[c].copy_from_slice(d.as_slice());
    }
    let mut rhs: [f64; 6] = (-p0).into();
    let col_scale = a[..k].iter().map(|c| c.iter().map(|v| v * v).sum::<f64>()).fold(0.0, f64::max).sqrt();
    let mut diag = [0.0; 6];
    for c in 0..k {
        let norm = a[c][c..].iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm <= 1e-12 * col_scale {
            return None;
        }
        let alpha = if a[c][c] > 0.0 { -norm } else { norm };
        // Householder vector u = a_c[c..] − alpha e_c, applied as I − 2uuᵀ/uᵀu.
        let mut u = [0.0; 6];
        u[c..].copy_from_slice(&a[c][c..]);
        u[c] -= alpha;
        let uu: f64 = u[c..].iter().map(|v| v * v).sum();
        if uu == 0.0 {
            return None;
        }
        let reflect = |v: &mut [f64; 6]| {
            let f = 2.0 * (c..6).map(|r| u[r] * v[r]).sum::<f64>() / uu;
            for r in c..6 {
                v[r] -= f * u[r];
            }
        };
        for col in a.iter_mut().take(k).skip(c + 1) {
            reflect(col);
        }
        reflect(&mut rhs);
        diag[c] = alpha;
    }
    let mut beta = [0.0; 6];
    for c in (0..k).rev() {
        let s: f64 = (c + 1..k).map(|j| a[j][c] * beta[j]).sum();
        beta[c] = (rhs[c] - s) / diag[c];
    }
    let mut v = Vec::with_capacity(k + 1);
    v.push(1.0 - beta[..k].iter().sum::<f64>());
    v.extend_from_slice(&beta[..k]);
    v.iter().all(|x| x.is_finite()).then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Neither dense solver needs its clarabel fallback on random wrench sets of grasp size
    /// (the equivalence with clarabel is tested in `tests/solver_equivalence.rs`).
    #[test]
    fn dense_solvers_certify_random_wrench_sets() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for case in 0..2000 {
            let n = rng.random_range(1..90);
            let shift = rng.random_range(0.0..1.0);
            let offset = Wrench::from_fn(|_, _| rng.random_range(-1.0..1.0)) * shift;
            let w: Vec<Wrench> = (0..n).map(|_| Wrench::from_fn(|_, _| rng.random_range(-1.0..1.0)) + offset).collect();
            assert!(strict_lp(&w).is_some(), "case {case}");
            assert!(wolfe_min_norm(&w).is_some(), "case {case}");
        }
    }
}
