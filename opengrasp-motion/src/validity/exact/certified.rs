//! Certified motion checks on the exact checker: states near a checked state are not checked
//! again when their distances cannot have closed.
//!
//! Core splits a state check into tests ([`GapTest`]: each self-collision pair, each part
//! against the obstacles), each reporting a lower bound `g` on its distance when it passes.
//! Along a straight motion a part moves at most `Σⱼ |Δqⱼ| rⱼ` ([`MotionBound`]); a link pair's
//! distance changes only through the joints that move one link and not the other. So a test
//! that passed with gap `g` at state `i` passes at every state `j` with `|j − i| · δ < g − ε`
//! (`δ` its bound per step, `ε` = [`SLACK`]) and is not run there; a state whose tests are all
//! certified is not placed at all. The verdict is that of checking every state.

use opengrasp_core::collision::{CollisionWorld, GapTest};
use opengrasp_core::model::{JointGroup, LinkId, Robot};

use crate::validate::{segment_subdivisions, subdivision_into};
use crate::validity::MotionBound;

/// Absolute slack (m) taken off every gap: covers the rounding of the kinematics, of the
/// interpolated states and of the distance queries (GJK's tolerance is far below it), so
/// that a certified state's shapes are at least this far apart.
const SLACK: f64 = 1e-6;

/// Gaps are capped here (m): obstacles farther than this from a part's box are not visited.
pub(super) const CAP: f64 = 0.5;

/// The tests of a state check and, per test, one weight per group value: the test's
/// distance changes by at most `Σⱼ |Δqⱼ| wⱼ` over a straight motion by `Δq`.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ExactCertificates {
    pub(super) tests: Vec<GapTest>,
    /// `tests.len() × dim`, row-major.
    weights: Vec<f64>,
    dim: usize,
}

impl ExactCertificates {
    /// The tests of `world`'s robot `robot_id` with weights from `bound` (the links'
    /// motion bound for `group`); `None` if the world cannot split the check (a carried
    /// object) or a test's link is not in the bound.
    pub(super) fn new(
        world: &CollisionWorld,
        robot_id: opengrasp_core::scene::RobotId,
        robot: &Robot,
        group: &JointGroup,
        bound: &MotionBound,
    ) -> Option<Self> {
        let tests = world.gap_tests(robot_id).ok()??;
        let dim = group.len();
        let index = |link: LinkId| bound.links().iter().position(|&l| l == link);
        // Per link, the group values driving a joint on its chain that is not on `other`'s.
        let own = |link: LinkId, other: LinkId| {
            let theirs = robot.chain_to(other);
            let mut own = vec![false; dim];
            for j in robot.chain_to(link).into_iter().filter(|j| !theirs.contains(j)) {
                if let Some(g) = robot.driving_dof(j).and_then(|(d, _)| group.dofs().iter().position(|&x| x == d)) {
                    own[g] = true;
                }
            }
            own
        };
        let mut weights = Vec::with_capacity(tests.len() * dim);
        for test in &tests {
            match *test {
                GapTest::Obstacles { link, .. } => {
                    let k = index(link)?;
                    weights.extend((0..dim).map(|j| bound.radius(k, j)));
                }
                GapTest::Pair { link_a, link_b, .. } => {
                    let (ka, kb) = (index(link_a)?, index(link_b)?);
                    let (own_a, own_b) = (own(link_a, link_b), own(link_b, link_a));
                    weights.extend((0..dim).map(|j| {
                        let wa = if own_a[j] { bound.radius(ka, j) } else { 0.0 };
                        let wb = if own_b[j] { bound.radius(kb, j) } else { 0.0 };
                        wa + wb
                    }));
                }
            }
        }
        Some(Self { tests, weights, dim })
    }

    /// Number of tests (the length of a state's certificate).
    pub(super) fn len(&self) -> usize {
        self.tests.len()
    }

    /// Per test, the reciprocal of its bound per step of the motion `a → b` in `n` steps
    /// (∞ if the test cannot change), the bound inflated against rounding.
    fn per_step(&self, a: &[f64], b: &[f64], n: usize) -> Vec<f64> {
        self.weights
            .chunks_exact(self.dim.max(1))
            .map(|w| {
                let d: f64 = w.iter().zip(a).zip(b).map(|((w, x), y)| w * (y - x).abs()).sum();
                n.max(1) as f64 / (d * (1.0 + 1e-9))
            })
            .collect()
    }

    /// The verdict of the discrete check of `a → b` at `step` (`b` and the `n` subdivision
    /// states, `a` excluded), with the tests certified by `a_gaps`/`b_gaps` (the gaps of the
    /// end states, one per test, or empty) and by each checked state skipped, and the number
    /// of states the one-by-one check in the same order tests (up to the first invalid one).
    /// `check(q, skip, gaps)` runs the tests without `skip(t)` at group state `q` (see
    /// [`CollisionWorld::gaps_unchecked`]).
    pub(super) fn motion_valid(
        &self,
        a: &[f64],
        b: &[f64],
        step: f64,
        ends: (&[f64], &[f64]),
        mut check: impl FnMut(&[f64], &dyn Fn(usize) -> bool, &mut Vec<f64>) -> bool,
    ) -> (bool, u64) {
        let n = segment_subdivisions(a, b, step);
        let tests = self.len();
        let per_step = self.per_step(a, b, n);
        let words = n / 64 + 1;
        // Per test (row of `words`), a bit per state index: certified.
        let mut certified = vec![0u64; tests * words];
        for (state, gaps) in [(0, ends.0), (n, ends.1)] {
            if gaps.len() == tests {
                for t in 0..tests {
                    set_bits(&mut certified[t * words..(t + 1) * words], reach(gaps[t], per_step[t], state, n));
                }
            }
        }
        let mut order = vec![n];
        if n > 1 {
            let mut stride = n.next_power_of_two() / 2;
            while stride >= 1 {
                order.extend((stride..n).step_by(2 * stride));
                stride /= 2;
            }
        }
        let mut q = Vec::with_capacity(a.len());
        let mut gaps = Vec::with_capacity(tests);
        let states = order.len() as u64;
        for (pos, i) in order.into_iter().enumerate() {
            let is_certified = |t: usize| certified[t * words + i / 64] >> (i % 64) & 1 == 1;
            if (0..tests).all(is_certified) {
                continue;
            }
            subdivision_into(a, b, i, n, &mut q);
            if !check(&q, &is_certified, &mut gaps) {
                return (false, pos as u64 + 1);
            }
            for (t, &gap) in gaps.iter().enumerate() {
                if !gap.is_nan() {
                    set_bits(&mut certified[t * words..(t + 1) * words], reach(gap, per_step[t], i, n));
                }
            }
        }
        (true, states)
    }
}

/// The states of a motion of `n` steps that a test passing with `gap` at state `i` certifies:
/// `lo..=hi`, those within `⌊(gap − slack) · per_step⌋` of `i` (only `i` when that is
/// negative, all when infinite).
fn reach(gap: f64, per_step: f64, i: usize, n: usize) -> (usize, usize) {
    let steps = ((gap - SLACK) * per_step).max(0.0);
    let reach = if steps >= n as f64 { n } else { steps as usize };
    (i.saturating_sub(reach), (i + reach).min(n))
}

/// Sets the bits `lo..=hi` of a bit set.
fn set_bits(bits: &mut [u64], (lo, hi): (usize, usize)) {
    for (w, word) in bits.iter_mut().enumerate().take(hi / 64 + 1).skip(lo / 64) {
        let from = if w == lo / 64 { lo % 64 } else { 0 };
        let to = if w == hi / 64 { hi % 64 } else { 63 };
        *word |= (u64::MAX >> (63 - to)) & (u64::MAX << from);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reach_counts_whole_steps_inside_the_gap() {
        // gap 0.1 m, 0.03 m per step: 3 steps either side (0.09 < 0.1 − slack < 0.12).
        assert_eq!(reach(0.1, 1.0 / 0.03, 10, 20), (7, 13));
        assert_eq!(reach(0.1, 1.0 / 0.03, 1, 20), (0, 4));
        assert_eq!(reach(0.1, 1.0 / 0.03, 19, 20), (16, 20));
        // A gap within the slack certifies only the state itself; an unbounded one all.
        assert_eq!(reach(0.5e-6, 1e9, 5, 20), (5, 5));
        assert_eq!(reach(0.1, f64::INFINITY, 5, 20), (0, 20));
    }

    #[test]
    fn set_bits_spans_words() {
        let mut bits = [0u64; 3];
        set_bits(&mut bits, (60, 130));
        assert_eq!(bits[0], 0xF000_0000_0000_0000);
        assert_eq!(bits[1], u64::MAX);
        assert_eq!(bits[2], 0b111);
        let mut one = [0u64; 1];
        set_bits(&mut one, (5, 5));
        assert_eq!(one[0], 1 << 5);
    }
}
