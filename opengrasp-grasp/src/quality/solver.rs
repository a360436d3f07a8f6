//! The two programs behind the force-closure tests: the strict LP and the min-norm point.
//!
//! The quality metrics use the dense active-set solvers ([`strict_combination_vertex`],
//! [`min_norm_distance`]: exact up to rounding, ~100× fewer instructions on grasp-sized wrench
//! sets); the clarabel interior-point solves ([`strict_combination`], [`min_norm_point`]) are
//! their fallback and return weights in the interior of the optimal face, which is what a force
//! distribution wants.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

use crate::contact::Wrench;
use crate::error::{GraspError, Result};

/// Solution of the min-norm problem `min ‖Σ λᵢ wᵢ‖ s.t. λ ≥ 0, Σ λᵢ = 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct MinNorm {
    /// Distance from the origin to the convex hull of the wrenches: `‖Σ λᵢ wᵢ‖` evaluated at
    /// the solver's weights after projecting them onto the simplex (so it is a certified
    /// upper bound of the exact distance, accurate to about `1e-8`).
    pub distance: f64,
    /// The convex weights `λ` (non-negative, summing to one).
    pub weights: Vec<f64>,
}

fn settings() -> DefaultSettings<f64> {
    DefaultSettings { verbose: false, max_iter: 100, ..DefaultSettings::default() }
}

fn ok_status(status: SolverStatus) -> bool {
    matches!(status, SolverStatus::Solved | SolverStatus::AlmostSolved)
}

fn solver_error(problem: &'static str, status: impl std::fmt::Debug) -> GraspError {
    GraspError::Solver { problem, status: format!("{status:?}") }
}

/// Minimum-norm point of the convex hull of `wrenches` (the force-closure QP).
///
/// Solved in epigraph form as a second-order cone program, which keeps the distance
/// accurate near zero: variables `(λ, t)`, minimise `t` subject to `Σλ = 1`, `λ ≥ 0` and
/// `‖W λ‖ ≤ t`.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for an empty wrench set, [`GraspError::Solver`] if
/// clarabel fails.
pub fn min_norm_point(wrenches: &[Wrench]) -> Result<MinNorm> {
    let n = wrenches.len();
    if n == 0 {
        return Err(GraspError::InvalidParameter { name: "wrenches", reason: "empty wrench set".into() });
    }
    // Rows: 0 Σλ = 1 (zero cone); 1..=n: λ ≥ 0; n+1..n+8: (t, Wλ) ∈ SOC(7).
    let m = n + 8;
    let mut colptr = Vec::with_capacity(n + 2);
    let mut rowval = Vec::with_capacity(8 * n + 1);
    let mut nzval = Vec::with_capacity(8 * n + 1);
    for (j, w) in wrenches.iter().enumerate() {
        colptr.push(rowval.len());
        rowval.push(0);
        nzval.push(1.0);
        rowval.push(1 + j);
        nzval.push(-1.0);
        for (k, &wk) in w.iter().enumerate() {
            if wk != 0.0 {
                rowval.push(n + 2 + k);
                nzval.push(-wk);
            }
        }
    }
    colptr.push(rowval.len());
    rowval.push(n + 1);
    nzval.push(-1.0);
    colptr.push(rowval.len());
    let a = CscMatrix::new(m, n + 1, colptr, rowval, nzval);
    let p = CscMatrix::zeros((n + 1, n + 1));
    let mut q = vec![0.0; n + 1];
    q[n] = 1.0;
    let mut b = vec![0.0; m];
    b[0] = 1.0;
    let cones =
        [SupportedConeT::ZeroConeT(1), SupportedConeT::NonnegativeConeT(n), SupportedConeT::SecondOrderConeT(7)];
    let mut solver =
        DefaultSolver::new(&p, &q, &a, &b, &cones, settings()).map_err(|e| solver_error("min-norm qp", e))?;
    solver.solve();
    let status = solver.solution.status;
    if !ok_status(status) {
        return Err(solver_error("min-norm qp", status));
    }
    let mut weights: Vec<f64> = solver.solution.x[..n].iter().map(|&l| l.max(0.0)).collect();
    let sum: f64 = weights.iter().sum();
    if !(sum > 0.0 && sum.is_finite()) {
        return Err(solver_error("min-norm qp", status));
    }
    weights.iter_mut().for_each(|l| *l /= sum);
    let point: Wrench = wrenches.iter().zip(&weights).map(|(w, &l)| w * l).sum();
    Ok(MinNorm { distance: point.norm(), weights })
}

/// Largest `s` such that some convex combination `Σ λᵢ wᵢ = 0` has every `λᵢ ≥ s`
/// (the strict force-closure LP), with the maximising weights; margin `-∞` (and no weights)
/// if the origin is not in the affine hull.
///
/// `s > 0` means the origin is a strictly positive combination of all wrenches, i.e. it
/// lies in the relative interior of their convex hull; together with a full-dimensional
/// wrench set this is force closure. `s` is at most `1/n`.
///
/// If clarabel stalls (which happens on degenerate programs whose optimum is `s = 0`) the
/// result is `-∞` as well: no strict margin was found.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for an empty wrench set, [`GraspError::Solver`] if
/// clarabel rejects the problem data.
pub fn strict_combination(wrenches: &[Wrench]) -> Result<StrictCombination> {
    let n = wrenches.len();
    if n == 0 {
        return Err(GraspError::InvalidParameter { name: "wrenches", reason: "empty wrench set".into() });
    }
    // Variables (λ, s). Rows 0..6: Wλ = 0; 6: Σλ = 1 (zero cone); 7..7+n: λᵢ − s ≥ 0.
    let m = n + 7;
    let mut colptr = Vec::with_capacity(n + 2);
    let mut rowval = Vec::with_capacity(8 * n + n);
    let mut nzval = Vec::with_capacity(8 * n + n);
    for (j, w) in wrenches.iter().enumerate() {
        colptr.push(rowval.len());
        for (k, &wk) in w.iter().enumerate() {
            if wk != 0.0 {
                rowval.push(k);
                nzval.push(wk);
            }
        }
        rowval.push(6);
        nzval.push(1.0);
        rowval.push(7 + j);
        nzval.push(-1.0);
    }
    colptr.push(rowval.len());
    for j in 0..n {
        rowval.push(7 + j);
        nzval.push(1.0);
    }
    colptr.push(rowval.len());
    let a = CscMatrix::new(m, n + 1, colptr, rowval, nzval);
    let p = CscMatrix::zeros((n + 1, n + 1));
    let mut q = vec![0.0; n + 1];
    q[n] = -1.0;
    let mut b = vec![0.0; m];
    b[6] = 1.0;
    let cones = [SupportedConeT::ZeroConeT(7), SupportedConeT::NonnegativeConeT(n)];
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings())
        .map_err(|e| solver_error("strict force-closure lp", e))?;
    solver.solve();
    let none = StrictCombination { margin: f64::NEG_INFINITY, weights: None };
    match solver.solution.status {
        s if ok_status(s) && solver.solution.x[n].is_finite() => {
            Ok(StrictCombination { margin: solver.solution.x[n], weights: Some(solver.solution.x[..n].to_vec()) })
        }
        // Infeasible: the origin is not even in the affine hull. Stalls (iteration limit,
        // insufficient progress, numerical error) only happen on degenerate programs whose
        // optimum is s = 0, i.e. the origin on the boundary: no strict margin either way.
        _ => Ok(none),
    }
}

/// Result of [`strict_combination`].
#[derive(Debug, Clone, PartialEq)]
pub struct StrictCombination {
    /// The LP optimum `s` (largest minimum weight), `-∞` if infeasible.
    pub margin: f64,
    /// The weights `λ` at the optimum (`None` if infeasible).
    pub weights: Option<Vec<f64>>,
}

/// The strict force-closure LP of [`strict_combination`] solved at a vertex by a dense
/// two-phase simplex (7 rows, one column per wrench): the same optimum `s` (to about `1e-12`
/// where clarabel's is accurate to about `1e-8`), with vertex weights, which make
/// `Σ λᵢ wᵢ = 0` to rounding error. Falls back to [`strict_combination`] if the simplex
/// cannot certify its result (never seen on grasp wrench sets, kept for safety).
///
/// Unlike clarabel, which stalls on degenerate programs whose optimum is `s = 0` (the origin on
/// the boundary), this returns that optimum (`≈ 0`); `-∞` only when the origin is outside the
/// affine hull. Each optimum is a vertex, so when the optimal weights are not unique they can
/// differ from clarabel's (which lie in the interior of the optimal face): use
/// [`strict_combination`] when the weights are used as a force distribution.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for an empty wrench set, [`GraspError::NonFinite`] for a
/// NaN or infinite component; [`GraspError::Solver`] if the fallback fails.
pub fn strict_combination_vertex(wrenches: &[Wrench]) -> Result<StrictCombination> {
    check_wrenches(wrenches)?;
    match super::dense::strict_lp(wrenches) {
        Some((margin, weights)) => Ok(StrictCombination { margin, weights }),
        None => strict_combination(wrenches),
    }
}

/// A non-empty wrench set with finite components.
fn check_wrenches(wrenches: &[Wrench]) -> Result<()> {
    if wrenches.is_empty() {
        return Err(GraspError::InvalidParameter { name: "wrenches", reason: "empty wrench set".into() });
    }
    crate::error::ensure_finite("wrenches", wrenches.iter().flat_map(|w| w.iter().copied()))
}

/// The strict force-closure LP's optimum `s` alone (see [`strict_combination_vertex`]).
///
/// # Errors
/// See [`strict_combination`].
pub fn positive_combination_margin(wrenches: &[Wrench]) -> Result<f64> {
    Ok(strict_combination_vertex(wrenches)?.margin)
}

/// Distance from the origin to the convex hull of `wrenches` (the value of
/// [`min_norm_point`]) by Wolfe's min-norm-point algorithm, an exact active-set method: the
/// norm of a convex combination (an upper bound of the distance, as [`min_norm_point`]'s)
/// within about `1e-15 / distance` of the optimum in wrench units². Falls back to
/// [`min_norm_point`] if Wolfe's algorithm does not converge.
///
/// # Errors
/// As [`strict_combination_vertex`].
pub fn min_norm_distance(wrenches: &[Wrench]) -> Result<f64> {
    check_wrenches(wrenches)?;
    match super::dense::wolfe_min_norm(wrenches) {
        Some((distance, _)) => Ok(distance),
        None => Ok(min_norm_point(wrenches)?.distance),
    }
}

/// `‖Σ λ̂ᵢ wᵢ‖` for the projection `λ̂` of `weights` onto the probability simplex by clamping
/// and normalising: an upper bound of the distance from the origin to the hull. `None` if
/// the clamped weights sum to zero.
pub fn combination_norm(wrenches: &[Wrench], weights: &[f64]) -> Option<f64> {
    let sum: f64 = weights.iter().map(|&l| l.max(0.0)).sum();
    if !(sum > 0.0 && sum.is_finite()) {
        return None;
    }
    let point: Wrench = wrenches.iter().zip(weights).map(|(w, &l)| w * (l.max(0.0) / sum)).sum();
    Some(point.norm())
}
