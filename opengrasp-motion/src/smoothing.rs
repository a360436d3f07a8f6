//! Path post-processing: repair of segments the validators reject, then random shortcuts.
//!
//! Both steps accept a new segment only if it passes the same checks as the final validators
//! ([`crate::validate::validate_path`]): the discrete check at the planning step, the strict
//! discrete check and (with [`ShortcutOptions::certify`]) the continuous check. So a
//! post-processed path is never less valid than the planned one, and every repaired or
//! shortcut segment passes every validator.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::validate::{
    distance, segment_valid_continuous, segment_valid_discrete, segment_valid_discrete_by, CcdOptions, DEFAULT_STEP,
};
use crate::validity::StateValidityChecker;

/// Options of [`shortcut`] and [`repair`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShortcutOptions {
    /// Shortcut attempts (default 100).
    pub iterations: usize,
    /// Step of the strict discrete check of each new segment (default 0.002, the strict
    /// validator's step).
    pub step: f64,
    /// Step of the planning-step discrete check of each new segment (default 0.02, the
    /// planning step).
    pub planning_step: f64,
    /// Also require each new segment to pass the continuous validator when the checker
    /// supports it (default true).
    pub certify: bool,
    /// Options of that continuous check (defaults of [`CcdOptions`]).
    pub ccd: CcdOptions,
    /// Random detours tried per rejected segment by [`repair`] (default 200).
    pub repair_attempts: usize,
    /// Seed of the generator choosing shortcut end points and detours (default 0).
    pub seed: u64,
}

impl Default for ShortcutOptions {
    fn default() -> Self {
        Self {
            iterations: 100,
            step: DEFAULT_STEP / 10.0,
            planning_step: DEFAULT_STEP,
            certify: true,
            ccd: CcdOptions::default(),
            repair_attempts: 200,
            seed: 0,
        }
    }
}

/// Statistics of post-processing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ShortcutStats {
    /// Shortcut attempts made.
    pub attempts: usize,
    /// Shortcuts accepted.
    pub accepted: usize,
    /// Waypoints removed by the final pruning pass of [`shortcut`].
    pub pruned: usize,
    /// Segments rejected by a validator and replaced by a valid detour ([`repair`]).
    pub repaired: usize,
    /// Segments rejected by a validator that could not be repaired.
    pub unrepaired: usize,
}

/// The segment check shared by [`repair`], [`shortcut`] and the final validators.
struct SegmentCheck<'a> {
    checker: &'a dyn StateValidityChecker,
    options: ShortcutOptions,
    ccd: CcdOptions,
}

impl<'a> SegmentCheck<'a> {
    fn new(checker: &'a dyn StateValidityChecker, options: &ShortcutOptions) -> Self {
        // The strict discrete check already covers self-collision at the continuous
        // validator's step or finer: do not repeat it inside the continuous check.
        let ccd = if options.step <= options.ccd.self_collision_step {
            CcdOptions { self_collision_step: f64::INFINITY, ..options.ccd }
        } else {
            options.ccd
        };
        Self { checker, options: *options, ccd }
    }

    /// The verdict of the three validators on `a → b` (all must accept), computed cheaply:
    ///
    /// 1. the planning-step discrete check (a tenth of the strict check's states) rejects most
    ///    bad segments first;
    /// 2. the continuous check then certifies, by conservative advancement, that every link
    ///    stays clear of the environment along the whole segment;
    /// 3. so the strict discrete check only has to test what the link distances do not
    ///    measure ([`StateValidityChecker::residual_valid`]: self-collision, carried objects
    ///    against the robot), on every state of its grid. Checkers without that split get
    ///    full state checks.
    ///
    /// The verdict is the conjunction of the three validators' verdicts, exactly as if each
    /// ran in full: certified clearance means the environment part of every strict state is
    /// free, which is all the residual check leaves out.
    fn ok(&self, a: &[f64], b: &[f64]) -> bool {
        if !segment_valid_discrete(self.checker, a, b, self.options.planning_step) {
            return false;
        }
        let continuous =
            if self.options.certify { segment_valid_continuous(self.checker, a, b, &self.ccd) } else { None };
        match continuous {
            Some(false) => false,
            Some(true) => segment_valid_discrete_by(
                |q| self.checker.residual_valid(q).unwrap_or_else(|| self.checker.is_valid(q)),
                a,
                b,
                self.options.step,
            ),
            None => segment_valid_discrete(self.checker, a, b, self.options.step),
        }
    }
}

/// Replaces every segment that fails the checks of [`ShortcutOptions`] by a two-segment detour
/// through a random point near its midpoint (Gaussian offsets growing from 0.02 to about 0.5 in
/// each coordinate over [`ShortcutOptions::repair_attempts`] tries, clamped to `limits`).
/// Segments that cannot be repaired are kept and counted in
/// [`ShortcutStats::unrepaired`].
pub fn repair(
    checker: &dyn StateValidityChecker,
    path: &[Vec<f64>],
    limits: &[(f64, f64)],
    options: &ShortcutOptions,
) -> (Vec<Vec<f64>>, ShortcutStats) {
    let check = SegmentCheck::new(checker, options);
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed ^ 0x5eed_0f2e_9a12);
    let mut stats = ShortcutStats::default();
    let mut out: Vec<Vec<f64>> = path.first().cloned().into_iter().collect();
    for w in path.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        if check.ok(a, b) {
            out.push(b.clone());
            continue;
        }
        let n = options.repair_attempts.max(1);
        let mut fixed = None;
        for k in 0..n {
            let sigma = 0.02 * (25.0f64).powf(k as f64 / n as f64);
            let m: Vec<f64> = a
                .iter()
                .zip(b)
                .enumerate()
                .map(|(j, (x, y))| {
                    let v = 0.5 * (x + y) + sigma * gaussian(&mut rng);
                    limits.get(j).map_or(v, |&(lo, hi)| v.clamp(lo, hi))
                })
                .collect();
            if checker.is_valid(&m) && check.ok(a, &m) && check.ok(&m, b) {
                fixed = Some(m);
                break;
            }
        }
        match fixed {
            Some(m) => {
                stats.repaired += 1;
                out.push(m);
            }
            None => stats.unrepaired += 1,
        }
        out.push(b.clone());
    }
    (out, stats)
}

/// A standard normal sample (Box-Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// Random shortcutting: `iterations` times, two random points on the path (by arc length, on
/// different segments) are joined by a straight segment which replaces the path between them
/// if it is shorter and it and the two partial segments leading to it pass the checks of
/// [`ShortcutOptions`].
///
/// Finally, waypoints whose two neighbours can be joined directly are removed (one pass).
///
/// A replacement is never longer than what it replaces (triangle inequality), so the path
/// length never increases, and every new segment passes the validators' checks, so the result
/// is at least as valid as the input.
pub fn shortcut(
    checker: &dyn StateValidityChecker,
    path: &[Vec<f64>],
    options: &ShortcutOptions,
) -> (Vec<Vec<f64>>, ShortcutStats) {
    let check = SegmentCheck::new(checker, options);
    let mut path: Vec<Vec<f64>> = path.to_vec();
    let mut stats = ShortcutStats::default();
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    for _ in 0..options.iterations {
        if path.len() < 3 {
            break;
        }
        stats.attempts += 1;
        let cumulative: Vec<f64> = std::iter::once(0.0)
            .chain(path.windows(2).scan(0.0, |acc, w| {
                *acc += distance(&w[0], &w[1]);
                Some(*acc)
            }))
            .collect();
        let total = *cumulative.last().unwrap_or(&0.0);
        if total <= 0.0 {
            break;
        }
        let (mut s1, mut s2) = (rng.random::<f64>() * total, rng.random::<f64>() * total);
        if s1 > s2 {
            std::mem::swap(&mut s1, &mut s2);
        }
        let seg = |s: f64| cumulative.partition_point(|&c| c <= s).clamp(1, path.len() - 1) - 1;
        let (i1, i2) = (seg(s1), seg(s2));
        if i1 == i2 {
            continue;
        }
        let point = |i: usize, s: f64| -> Vec<f64> {
            let len = cumulative[i + 1] - cumulative[i];
            let t = if len > 0.0 { ((s - cumulative[i]) / len).clamp(0.0, 1.0) } else { 0.0 };
            path[i].iter().zip(&path[i + 1]).map(|(a, b)| a + t * (b - a)).collect()
        };
        let (p1, p2) = (point(i1, s1), point(i2, s2));
        let old = distance(&p1, &path[i1 + 1]) + (cumulative[i2] - cumulative[i1 + 1]) + distance(&path[i2], &p2);
        let new = distance(&p1, &p2);
        if new >= old - 1e-9 {
            continue;
        }
        // The partial segments path[i1] → p1 and p2 → path[i2 + 1] lie on old segments but are
        // sampled on a different grid: check them as well.
        if !check.ok(&p1, &p2) || !check.ok(&path[i1], &p1) || !check.ok(&p2, &path[i2 + 1]) {
            continue;
        }
        let mut next = Vec::with_capacity(path.len());
        next.extend_from_slice(&path[..=i1]);
        next.push(p1);
        next.push(p2);
        next.extend_from_slice(&path[i2 + 1..]);
        next.dedup_by(|a, b| distance(a, b) < 1e-12);
        path = next;
        stats.accepted += 1;
    }
    // Vertex pruning: drop waypoints whose neighbours can be joined directly. Random shortcuts
    // leave pairs of close waypoints with sharp turns between them, which dominate OMPL's
    // smoothness; removing them also shortens the path (triangle inequality).
    let mut i = 1;
    while i + 1 < path.len() {
        if check.ok(&path[i - 1], &path[i + 1]) {
            path.remove(i);
            stats.pruned += 1;
        } else {
            i += 1;
        }
    }
    (path, stats)
}
