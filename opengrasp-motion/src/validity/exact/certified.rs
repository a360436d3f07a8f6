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

use crate::validate::{coarse_to_fine_into, segment_subdivisions, subdivision_into};
use crate::validity::steps::{reach, set_bits, StepWeights};
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
    weights: StepWeights,
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
        let mut weights = Vec::with_capacity(tests.len() * dim);
        for test in &tests {
            match *test {
                GapTest::Obstacles { link, .. } => {
                    let k = index(link)?;
                    weights.extend((0..dim).map(|j| bound.radius(k, j)));
                }
                GapTest::Pair { link_a, link_b, .. } => {
                    let (ka, kb) = (index(link_a)?, index(link_b)?);
                    weights.extend(bound.pair_radii(robot, group, ka, kb));
                }
            }
        }
        Some(Self { tests, weights: StepWeights::from_rows(&weights, dim) })
    }

    /// Number of tests (the length of a state's certificate).
    pub(super) fn len(&self) -> usize {
        self.tests.len()
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
        let mut per_step = Vec::with_capacity(tests);
        self.weights.per_step_into(a, b, n, &mut per_step);
        let words = n / 64 + 1;
        // Per test (row of `words`), a bit per state index: certified.
        let mut certified = vec![0u64; tests * words];
        for (state, gaps) in [(0, ends.0), (n, ends.1)] {
            if gaps.len() == tests {
                for t in 0..tests {
                    set_bits(
                        &mut certified[t * words..(t + 1) * words],
                        1,
                        reach(gaps[t], SLACK, per_step[t], state, n),
                    );
                }
            }
        }
        let mut order = vec![n];
        coarse_to_fine_into(n, &mut order);
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
                    set_bits(&mut certified[t * words..(t + 1) * words], 1, reach(gap, SLACK, per_step[t], i, n));
                }
            }
        }
        (true, states)
    }
}
