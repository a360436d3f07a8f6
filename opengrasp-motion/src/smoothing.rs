//! Path post-processing: repair of segments the validators reject, then random shortcuts.
//!
//! Both steps accept a new segment only if it passes the same checks as the final validators
//! ([`crate::validate::validate_path`]): the discrete check at the planning step, the strict
//! discrete check and (with [`ShortcutOptions::certify`]) the continuous check. So a
//! post-processed path is never less valid than the planned one, and every repaired or
//! shortcut segment passes every validator.
//!
//! [`repair_with`] and [`shortcut_with`] take a [`SegmentCertifier`] as well: a segment it
//! proves free with a margin (on a conservative model, see [`crate::certify`]) is accepted
//! without the exact checks, and only when it cannot prove it do they run. The proof implies
//! the exact verdict (see [`crate::certify`]), so both give exactly the paths of [`repair`]
//! and [`shortcut`], faster.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::certify::{Certificate, SegmentCertifier};
use crate::validate::{
    distance, interpolate_into, segment_probe, segment_valid_continuous, segment_valid_discrete,
    segment_valid_discrete_by, CcdOptions, DEFAULT_STEP,
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

/// Advancement steps a [`SegmentCertifier`] may take per segment before the exact checks run.
const CERTIFIER_STEPS: usize = 1000;

/// Advancement steps of the first try: a proof still running after them is mostly a motion
/// crawling towards a contact (advancement slows down geometrically there), which the
/// planning-step check rejects for less; only a motion that passes it gets the rest of
/// [`CERTIFIER_STEPS`].
const FIRST_STEPS: usize = 100;

/// States of the exact planning-step check tried before the certifier (the first ones of its
/// coarse-to-fine order after the end state: the middle, the quarters, two eighths): cheap
/// rejections of segments that cross an obstacle. A segment through an obstacle that they
/// miss costs the certifier its crawl to the contact (some 80 advancement steps); with 6
/// states (the end state and 5 of these) rather than 4, scene 1's post-processing took 8.8 %
/// fewer instructions (30 paths) and a Clean the Table episode 0.5 % more; 8 or more cost
/// more than they catch. The end state is not probed: every segment checked here ends on
/// the path being processed (a waypoint or a point of a valid segment), which it hardly
/// ever fails.
const PROBE_STATES: usize = 5;

/// States looked at from where the certifier got stuck, a planning step apart.
const STUCK_PROBES: usize = 8;

/// Extra distance (m) the certifier keeps on top of the continuous validator's tolerance, for
/// the rounding of the exact distance queries.
const CERTIFIER_SLACK: f64 = 1e-6;

/// The segment check shared by [`repair`], [`shortcut`] and the final validators.
struct SegmentCheck<'a> {
    checker: &'a dyn StateValidityChecker,
    certifier: Option<&'a dyn SegmentCertifier>,
    /// Whether the links the group does not move are at least the continuous validator's
    /// tolerance from the obstacles and the robot's parts that move rigidly together are not
    /// in self-collision (`None`: not yet known; neither changes, so one exact query decides
    /// it for every segment).
    static_clear: std::cell::Cell<Option<bool>>,
    options: ShortcutOptions,
    ccd: CcdOptions,
}

impl<'a> SegmentCheck<'a> {
    fn new(
        checker: &'a dyn StateValidityChecker,
        certifier: Option<&'a dyn SegmentCertifier>,
        options: &ShortcutOptions,
    ) -> Self {
        // The strict discrete check already covers self-collision at the continuous
        // validator's step or finer: do not repeat it inside the continuous check.
        let ccd = if options.step <= options.ccd.self_collision_step {
            CcdOptions { self_collision_step: f64::INFINITY, ..options.ccd }
        } else {
            options.ccd
        };
        Self { checker, certifier, static_clear: std::cell::Cell::new(None), options: *options, ccd }
    }

    /// The verdict of [`SegmentCheck::check`] when the certifier decides it, [`Decision::Open`]
    /// otherwise:
    ///
    /// - `Rejected` if one of the first [`PROBE_STATES`] states of the planning-step
    ///   check is invalid (that check would reject it), or, when the continuous validator runs,
    ///   if the state where the certifier got stuck or one of the next [`STUCK_PROBES`] − 1
    ///   states a strict step apart collides with the environment and not with the robot
    ///   itself (conservative advancement cannot pass an environment collision);
    /// - `Certified(m)` if the certifier proves `a → b` free with a margin that makes every
    ///   exact validator accept it: every state is collision-free, so both discrete checks
    ///   (and the strict check's residual) accept; every link the group moves stays at least
    ///   `m + slack` from the obstacles, with `m` the larger of the tolerance and
    ///   `max_i B_i / (max_queries − 3)`, and the links it does not move keep their distance,
    ///   checked once against the tolerance (as are, by one exact state check, the self pairs
    ///   no group joint moves apart), so the continuous validator never sees a distance under
    ///   its tolerance; and its steps (`min_i d_i / B_i` over the moving links) are at least
    ///   `m / max_i B_i` long, so it reaches the end within `max_queries − 2` queries and
    ///   accepts.
    ///
    /// A proof still advancing after [`FIRST_STEPS`] steps runs on (to [`CERTIFIER_STEPS`],
    /// resumed where it stopped) only if the whole planning-step check accepts the segment
    /// (`Rejected` otherwise; the exact checks do not repeat it after an open decision).
    fn decided(&self, a: &[f64], b: &[f64]) -> Decision {
        let open = Decision::Open { coarse_passed: false };
        let (Some(certifier), Some(bound)) = (self.certifier, self.checker.motion_bound()) else {
            return open;
        };
        if !segment_probe(|q| self.checker.is_valid(q), a, b, self.options.planning_step, PROBE_STATES) {
            return Decision::Decided(Verdict::Rejected);
        }
        let Some(margin) = self.margin(a, b) else { return open };
        let tolerance = self.ccd.tolerance.max(0.0);
        // What no group joint moves is the same at every state: decide it once, at the first
        // segment's start (a valid state clears its fixed self pairs).
        let static_clear = self.static_clear.get().unwrap_or_else(|| {
            let mut d = Vec::new();
            let clear = self.checker.is_valid(a)
                && (!self.checker.link_distances(a, &mut d)
                    || d.iter().enumerate().all(|(i, &x)| bound.is_moving(i) || x >= tolerance));
            self.static_clear.set(Some(clear));
            clear
        });
        if !static_clear {
            return open;
        }
        let mut coarse_passed = false;
        let mut coarse = || {
            coarse_passed = segment_valid_discrete(self.checker, a, b, self.options.planning_step);
            coarse_passed
        };
        let Some(certificate) =
            certifier.certify_staged(a, b, bound, margin, (FIRST_STEPS, CERTIFIER_STEPS), &mut coarse)
        else {
            return Decision::Decided(Verdict::Rejected);
        };
        match certificate {
            Certificate::Free => Decision::Decided(Verdict::Certified(margin)),
            Certificate::Unknown { near: Some(t), .. } if self.options.certify && self.environment_hit(a, b, t) => {
                Decision::Decided(Verdict::Rejected)
            }
            Certificate::Unknown { .. } => Decision::Open { coarse_passed },
        }
    }

    /// Whether the state at `t` on `a → b` (where the certifier got stuck: the collision, if
    /// any, is at or just after it) or one of the next [`STUCK_PROBES`] − 1 states a strict
    /// step apart collides with the environment and not with the robot itself.
    fn environment_hit(&self, a: &[f64], b: &[f64], t: f64) -> bool {
        let len = distance(a, b);
        let dt = if len > 0.0 { self.options.step / len } else { 1.0 };
        let mut q = Vec::with_capacity(a.len());
        (0..STUCK_PROBES).map(|k| t + k as f64 * dt).take_while(|&s| s <= 1.0).any(|s| {
            interpolate_into(a, b, s, &mut q);
            self.checker.residual_valid(&q) == Some(true) && !self.checker.is_valid(&q)
        })
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
    ///
    /// A segment the certifier decides ([`SegmentCheck::decided`]) is not checked further:
    /// its decision is the verdict of the three validators.
    fn check(&self, a: &[f64], b: &[f64]) -> Verdict {
        let coarse_passed = match self.decided(a, b) {
            Decision::Decided(verdict) => return verdict,
            Decision::Open { coarse_passed } => coarse_passed,
        };
        let accepted = (coarse_passed || segment_valid_discrete(self.checker, a, b, self.options.planning_step))
            && match if self.options.certify { segment_valid_continuous(self.checker, a, b, &self.ccd) } else { None } {
                Some(false) => false,
                Some(true) => segment_valid_discrete_by(
                    |q| self.checker.residual_valid(q).unwrap_or_else(|| self.checker.is_valid(q)),
                    a,
                    b,
                    self.options.step,
                ),
                None => segment_valid_discrete(self.checker, a, b, self.options.step),
            };
        if accepted {
            Verdict::Accepted
        } else {
            Verdict::Rejected
        }
    }

    /// Whether `a → b` passes the three validators ([`SegmentCheck::check`]).
    fn ok(&self, a: &[f64], b: &[f64]) -> bool {
        self.check(a, b) != Verdict::Rejected
    }

    /// [`SegmentCheck::check`] of `a → b`, a piece of a segment the certifier proved free with
    /// margin `parent` (`None`: not proven).
    ///
    /// A certificate is a statement about states (every state of the segment keeps the moving
    /// links `parent` from the obstacles and the moving pairs `parent` apart), so it holds for
    /// every piece of the segment; and the margin a piece needs is at most its segment's (the
    /// speed bounds scale with the length). So a piece whose margin is at most `parent` gets
    /// the parent's certificate without any query: the certifier's verdict on it, had it
    /// been asked, is the validators' verdict, acceptance (the piece's end points lie on the
    /// segment up to the rounding of an interpolation, ~1e-16 rad, far within
    /// [`CERTIFIER_SLACK`]).
    fn check_piece(&self, parent: Option<f64>, a: &[f64], b: &[f64]) -> Verdict {
        match (parent, self.margin(a, b)) {
            (Some(proven), Some(needed)) if needed <= proven => Verdict::Certified(proven),
            _ => self.check(a, b),
        }
    }

    /// The margin the certifier must prove on `a → b` for its proof to imply the verdict of
    /// every validator (see [`SegmentCheck::decided`]), `None` if no margin does (no motion
    /// bound, or a continuous query budget under 4).
    fn margin(&self, a: &[f64], b: &[f64]) -> Option<f64> {
        let bound = self.checker.motion_bound()?;
        let tolerance = self.ccd.tolerance.max(0.0);
        if !self.options.certify {
            return Some(tolerance + CERTIFIER_SLACK);
        }
        // A long fast motion needs a margin above the tolerance for the continuous
        // validator's steps (at least margin / fastest) to fit its query budget.
        let budget = self.ccd.max_queries as f64 - 3.0;
        if budget <= 0.0 {
            return None;
        }
        let dq: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
        let fastest = (0..bound.links().len()).map(|i| bound.bound(i, &dq)).fold(0.0, f64::max);
        Some(tolerance.max(fastest / budget) + CERTIFIER_SLACK)
    }
}

/// What [`SegmentCheck::decided`] makes of a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Decision {
    /// Decided: the verdict of the validators.
    Decided(Verdict),
    /// Left to the exact checks; `coarse_passed`: the planning-step check already accepted
    /// the segment.
    Open { coarse_passed: bool },
}

/// The verdict of [`SegmentCheck::check`] on a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Verdict {
    /// A validator rejects the segment.
    Rejected,
    /// Every validator accepts it (checked exactly).
    Accepted,
    /// Every validator accepts it: the certifier proved it free with this margin.
    Certified(f64),
}

impl Verdict {
    /// The proven margin, if any.
    fn margin(self) -> Option<f64> {
        match self {
            Verdict::Certified(m) => Some(m),
            _ => None,
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
    repair_with(checker, None, path, limits, options)
}

/// [`repair`], accepting the segments `certifier` proves free without the exact checks (same
/// result, see the [module docs](self)).
pub fn repair_with(
    checker: &dyn StateValidityChecker,
    certifier: Option<&dyn SegmentCertifier>,
    path: &[Vec<f64>],
    limits: &[(f64, f64)],
    options: &ShortcutOptions,
) -> (Vec<Vec<f64>>, ShortcutStats) {
    let check = SegmentCheck::new(checker, certifier, options);
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
    shortcut_with(checker, None, path, options)
}

/// [`shortcut`], accepting the segments `certifier` proves free without the exact checks
/// (same result, see the [module docs](self)).
pub fn shortcut_with(
    checker: &dyn StateValidityChecker,
    certifier: Option<&dyn SegmentCertifier>,
    path: &[Vec<f64>],
    options: &ShortcutOptions,
) -> (Vec<Vec<f64>>, ShortcutStats) {
    let check = SegmentCheck::new(checker, certifier, options);
    let mut path: Vec<Vec<f64>> = path.to_vec();
    // Per segment of `path`: the margin the certifier proved it free with, if it did.
    let mut proven: Vec<Option<f64>> = vec![None; path.len().saturating_sub(1)];
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
        // sampled on a different grid: check them as well (pieces of certified segments are
        // certified already).
        let middle = check.check(&p1, &p2);
        if middle == Verdict::Rejected {
            continue;
        }
        let head = check.check_piece(proven[i1], &path[i1], &p1);
        if head == Verdict::Rejected {
            continue;
        }
        let tail = check.check_piece(proven[i2], &p2, &path[i2 + 1]);
        if tail == Verdict::Rejected {
            continue;
        }
        let mut next = Vec::with_capacity(path.len());
        next.extend_from_slice(&path[..=i1]);
        next.push(p1);
        next.push(p2);
        next.extend_from_slice(&path[i2 + 1..]);
        let mut next_proven = Vec::with_capacity(next.len());
        next_proven.extend_from_slice(&proven[..i1]);
        next_proven.extend([head.margin(), middle.margin(), tail.margin()]);
        next_proven.extend_from_slice(&proven[i2 + 1..]);
        (path, proven) = dedup(next, next_proven);
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

/// Drops every waypoint within 1e-12 of the one kept before it, with `proven` (per segment):
/// the segment into a dropped waypoint goes, and the one out of it becomes not proven (it now
/// starts at the kept waypoint).
fn dedup(path: Vec<Vec<f64>>, proven: Vec<Option<f64>>) -> (Vec<Vec<f64>>, Vec<Option<f64>>) {
    let mut out: Vec<Vec<f64>> = Vec::with_capacity(path.len());
    let mut out_proven: Vec<Option<f64>> = Vec::with_capacity(proven.len());
    let mut moved = false;
    for (k, q) in path.into_iter().enumerate() {
        if out.last().is_some_and(|last| distance(last, &q) < 1e-12) {
            moved = true;
            continue;
        }
        if k > 0 {
            out_proven.push(if moved { None } else { proven[k - 1] });
        }
        moved = false;
        out.push(q);
    }
    (out, out_proven)
}

#[cfg(test)]
mod tests {
    use super::dedup;

    /// A dropped waypoint takes its incoming segment's proof along and leaves the next one
    /// unproven (it now starts at the kept waypoint); the other proofs stay.
    #[test]
    fn dedup_keeps_the_proofs_of_unchanged_segments() {
        let path = vec![vec![0.0, 0.0], vec![1e-13, 0.0], vec![1.0, 0.0], vec![1.0, 1.0], vec![1.0, 1.0 + 5e-13]];
        let proven = vec![Some(0.1), Some(0.2), Some(0.3), Some(0.4)];
        let (out, out_proven) = dedup(path, proven);
        assert_eq!(out, vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]]);
        assert_eq!(out_proven, vec![None, Some(0.3)]);
        let (same, same_proven) = dedup(vec![vec![0.0], vec![2e-12], vec![1.0]], vec![Some(1.0), None]);
        assert_eq!(same, vec![vec![0.0], vec![2e-12], vec![1.0]]);
        assert_eq!(same_proven, vec![Some(1.0), None]);
    }
}
