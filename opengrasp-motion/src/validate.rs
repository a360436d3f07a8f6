//! Path and segment validation: discrete checks at a step, and certified continuous checks.
//!
//! The same validators grade every planner (see [`crate::benchmark`]):
//! - **discrete** at the planning step ([`ValidationOptions::step`]),
//! - **strict** discrete at a much finer step ([`ValidationOptions::strict_step`], default a
//!   tenth of the planning step),
//! - **continuous** by conservative advancement ([`segment_valid_continuous`]), when the checker
//!   provides per-link distances and a [`MotionBound`](crate::validity::MotionBound).
//!
//! Distances in configuration space are Euclidean over the group values (radians for revolute
//! joints, metres for prismatic ones).

use serde::{Deserialize, Serialize};

use crate::validity::StateValidityChecker;

/// Default discrete checking step in C-space (0.02, i.e. rad for revolute joints).
pub const DEFAULT_STEP: f64 = 0.02;

/// Euclidean distance between two configurations.
pub fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// Writes `a + t (b - a)` into `out`.
pub fn interpolate_into(a: &[f64], b: &[f64], t: f64, out: &mut Vec<f64>) {
    out.clear();
    out.extend(a.iter().zip(b).map(|(x, y)| x + t * (y - x)));
}

/// State `i` of the `n` equal subdivisions of `a → b` into `out`: `b` itself for `i == n`,
/// else the interpolation at `i / n` (the states of [`segment_valid_discrete`]).
pub(crate) fn subdivision_into(a: &[f64], b: &[f64], i: usize, n: usize, out: &mut Vec<f64>) {
    if i == n {
        out.clear();
        out.extend_from_slice(b);
    } else {
        interpolate_into(a, b, i as f64 / n as f64, out);
    }
}

/// Length of a path in C-space (sum of Euclidean segment lengths).
pub fn path_length(path: &[Vec<f64>]) -> f64 {
    path.windows(2).map(|w| distance(&w[0], &w[1])).sum()
}

/// Discrete check of the segment `a → b`: the states at `n = ⌈|b − a| / step⌉` equal
/// subdivisions (excluding `a`, including `b`) are checked, the end first and then
/// coarse-to-fine (bisection order), so collisions in the middle are found early.
///
/// Returns false on the first invalid state. A non-positive or non-finite `step` checks only
/// `b`.
pub fn segment_valid_discrete(checker: &dyn StateValidityChecker, a: &[f64], b: &[f64], step: f64) -> bool {
    segment_valid_discrete_with(checker, a, b, step)
}

/// [`segment_valid_discrete`] for any checker type (the default of
/// [`StateValidityChecker::is_motion_valid`]).
pub(crate) fn segment_valid_discrete_with<C: StateValidityChecker + ?Sized>(
    checker: &C,
    a: &[f64],
    b: &[f64],
    step: f64,
) -> bool {
    segment_valid_discrete_by(|q| checker.is_valid(q), a, b, step)
}

/// The coarse-to-fine state order of [`segment_valid_discrete`] with any state test.
pub(crate) fn segment_valid_discrete_by(valid: impl FnMut(&[f64]) -> bool, a: &[f64], b: &[f64], step: f64) -> bool {
    segment_valid_discrete_into(&mut Vec::with_capacity(a.len()), valid, a, b, step)
}

/// The number of equal subdivisions of `a → b` at `step` ([`segment_valid_discrete`]'s `n`;
/// 1 for a non-positive or non-finite step).
pub(crate) fn segment_subdivisions(a: &[f64], b: &[f64], step: f64) -> usize {
    let len = distance(a, b);
    if step > 0.0 && step.is_finite() {
        (len / step).ceil() as usize
    } else {
        1
    }
}

/// [`segment_valid_discrete_by`] with a caller's buffer for the interpolated states.
pub(crate) fn segment_valid_discrete_into(
    q: &mut Vec<f64>,
    mut valid: impl FnMut(&[f64]) -> bool,
    a: &[f64],
    b: &[f64],
    step: f64,
) -> bool {
    valid(b) && interior_valid(q, valid, a, b, segment_subdivisions(a, b, step), usize::MAX)
}

/// The first `states` states of [`segment_valid_discrete`]'s order after the end state (the
/// middle, the quarters, ...): false if one of them is invalid, so that the full check
/// rejects the segment too. The end state is left out: the callers' segments end on a path
/// whose states are known valid, and its check decides the segment in any case.
pub(crate) fn segment_probe(valid: impl FnMut(&[f64]) -> bool, a: &[f64], b: &[f64], step: f64, states: usize) -> bool {
    interior_valid(&mut Vec::with_capacity(a.len()), valid, a, b, segment_subdivisions(a, b, step), states)
}

/// Whether the first `states` of the coarse-to-fine subdivision states `1..n` of `a → b`
/// ([`coarse_to_fine`], each at `i / n`) are valid.
fn interior_valid(
    q: &mut Vec<f64>,
    mut valid: impl FnMut(&[f64]) -> bool,
    a: &[f64],
    b: &[f64],
    n: usize,
    states: usize,
) -> bool {
    coarse_to_fine(n).take(states).all(|i| {
        interpolate_into(a, b, i as f64 / n as f64, q);
        valid(q)
    })
}

/// The subdivision states `1..n` of a motion of `n` steps in the order of the discrete check
/// ([`segment_valid_discrete`]): coarse to fine, the middle first, then the quarters, and so
/// on (state `n`, the end, and state 0, the start, are not included).
pub(crate) fn coarse_to_fine(n: usize) -> impl Iterator<Item = usize> {
    strides(n).flat_map(move |stride| (stride..n).step_by(2 * stride))
}

/// Appends [`coarse_to_fine`]'s states to `order`, a stride at a time (each range's exact
/// length lets `extend` reserve it: motion checks build this list for every motion).
#[inline]
pub(crate) fn coarse_to_fine_into(n: usize, order: &mut Vec<usize>) {
    for stride in strides(n) {
        order.extend((stride..n).step_by(2 * stride));
    }
}

/// The strides of [`coarse_to_fine`]: the largest power of two below `n`, halved down to 1
/// (none for `n ≤ 1`).
fn strides(n: usize) -> impl Iterator<Item = usize> {
    let top = if n <= 1 { 0 } else { n.next_power_of_two() / 2 };
    std::iter::successors((top >= 1).then_some(top), |&stride| (stride > 1).then_some(stride / 2))
}

/// Discrete check of every segment of a path (and of its first state).
pub fn path_valid_discrete(checker: &dyn StateValidityChecker, path: &[Vec<f64>], step: f64) -> bool {
    match path.first() {
        None => false,
        Some(first) => {
            checker.is_valid(first) && path.windows(2).all(|w| segment_valid_discrete(checker, &w[0], &w[1], step))
        }
    }
}

/// Options of the continuous validator.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CcdOptions {
    /// A state whose link distance falls under this value counts as in contact (m, default
    /// 1e-4).
    pub tolerance: f64,
    /// Maximum distance queries per segment before giving up as "not certified" (default
    /// 100 000).
    pub max_queries: usize,
    /// Step of the discrete self-collision check added when the checker's link distances do
    /// not cover self-collision (default 0.002; `f64::INFINITY` checks only the end state).
    pub self_collision_step: f64,
}

impl Default for CcdOptions {
    fn default() -> Self {
        Self { tolerance: 1e-4, max_queries: 100_000, self_collision_step: DEFAULT_STEP / 10.0 }
    }
}

/// Certified continuous check of the segment `a → b` by conservative advancement (Schwarzer,
/// Saha & Latombe 2005).
///
/// With `d_i(t)` the distance of link `i` at `q(t) = a + t (b − a)` and `b_i = B_i(b − a)` the
/// [`MotionBound`](crate::validity::MotionBound) of the whole segment, no point of link `i` moves
/// farther than `(t' − t) b_i` between `t` and `t'`; so the segment is free on
/// `[t, t + min_i d_i / b_i]`. The validator advances by that amount until `t ≥ 1` (certified:
/// `Some(true)`), or a distance drops under [`CcdOptions::tolerance`] or the query budget runs
/// out (`Some(false)`). Returns `None` if the checker has no link distances or motion bound.
///
/// Self-collision: certified by the same bound when
/// [`StateValidityChecker::ccd_covers_self_collision`] (each link's distance is at most half
/// its distance to other links), otherwise checked discretely at
/// [`CcdOptions::self_collision_step`].
pub fn segment_valid_continuous(
    checker: &dyn StateValidityChecker,
    a: &[f64],
    b: &[f64],
    options: &CcdOptions,
) -> Option<bool> {
    let bound = checker.motion_bound()?;
    let mut d = Vec::new();
    if !checker.link_distances(a, &mut d) {
        return None;
    }
    let dq: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let rates: Vec<f64> = (0..bound.links().len()).map(|i| bound.bound(i, &dq)).collect();
    if !checker.ccd_covers_self_collision() && !segment_valid_discrete(checker, a, b, options.self_collision_step) {
        return Some(false);
    }
    let mut t = 0.0;
    let mut q = a.to_vec();
    for _ in 0..options.max_queries {
        let mut dt = f64::INFINITY;
        for (di, &rate) in d.iter().zip(&rates) {
            if *di < options.tolerance {
                return Some(false);
            }
            if rate > 0.0 {
                dt = dt.min(di / rate);
            }
        }
        t += dt;
        if t >= 1.0 {
            // The end state is reached inside the certified interval; check it as a state too.
            return Some(checker.link_distances(b, &mut d) && d.iter().all(|&x| x >= options.tolerance));
        }
        interpolate_into(a, b, t, &mut q);
        if !checker.link_distances(&q, &mut d) {
            return None;
        }
    }
    Some(false)
}

/// Options of [`validate_path`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ValidationOptions {
    /// Planning step for the discrete re-check (default [`DEFAULT_STEP`] = 0.02).
    pub step: f64,
    /// Step of the strict discrete check (default 0.002, a tenth of the planning step).
    pub strict_step: f64,
    /// Options of the continuous check (defaults of [`CcdOptions`]).
    pub ccd: CcdOptions,
}

impl Default for ValidationOptions {
    fn default() -> Self {
        Self { step: DEFAULT_STEP, strict_step: DEFAULT_STEP / 10.0, ccd: CcdOptions::default() }
    }
}

/// Verdicts of the three validators on one path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PathValidity {
    /// Discrete check at the planning step.
    pub discrete: bool,
    /// Discrete check at the strict step.
    pub strict: bool,
    /// Continuous (certified) check; `None` if the checker does not support it.
    pub continuous: Option<bool>,
}

/// Runs the discrete, strict and continuous validators on `path`.
pub fn validate_path(
    checker: &dyn StateValidityChecker,
    path: &[Vec<f64>],
    options: &ValidationOptions,
) -> PathValidity {
    let discrete = path_valid_discrete(checker, path, options.step);
    let strict = path_valid_discrete(checker, path, options.strict_step);
    let continuous = if path.is_empty() {
        Some(false)
    } else if path.len() == 1 {
        segment_valid_continuous(checker, &path[0], &path[0], &options.ccd)
    } else {
        let mut all = Some(true);
        for w in path.windows(2) {
            match segment_valid_continuous(checker, &w[0], &w[1], &options.ccd) {
                None => {
                    all = None;
                    break;
                }
                Some(false) => {
                    all = Some(false);
                    break;
                }
                Some(true) => {}
            }
        }
        all
    };
    PathValidity { discrete, strict, continuous }
}
