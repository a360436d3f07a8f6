//! Motion checks that skip tests a checked state certifies for its neighbours.
//!
//! A state check is a list of tests (each moving link against all obstacles, each checked
//! link pair), and each test can report a lower bound `g` on its sphere distance (the least
//! of [`SphereSoa::link_gap`] over the obstacles, [`SphereSoa::pair_gap`]). Along a straight motion the spheres
//! of link `k` move at most `Σⱼ |Δqⱼ| rₖⱼ` between two states ([`MotionBound`]); for a link
//! pair only the joints that move one link and not the other change their distance (rigid
//! motions keep distances). So a test that passed with gap `g` at state `i` passes at every
//! state `j` with `|j − i| · δ < g`, `δ` its bound per step, and is not run there; a state
//! whose tests are all certified is not computed at all. At each computed state the tests
//! that failed lately (per thread) run first, so a state in collision usually costs one test.
//! The verdict and the one-by-one count are those of checking every state in the default
//! order.

use std::sync::Arc;

use super::{LinkTable, SphereWorld};
use crate::validate::{coarse_to_fine_into, interpolate_into, segment_subdivisions};
use crate::validity::soa::{Scratch, FAR_BATCH};
use crate::validity::steps::{for_words, reach, set_bits, StepWeights};
use crate::validity::MotionBound;

/// Absolute slack (m) taken off every certified gap: covers the rounding of the kinematics
/// and of the interpolated states, many orders of magnitude below it.
const SLACK: f64 = 1e-9;

/// One test of a state check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Test {
    /// Link `k` (moving) against every obstacle, the one that failed last for it first.
    Obstacles { k: usize },
    /// Links `a` and `b`, not rigidly attached: moving pair `p`.
    Pair { a: usize, b: usize, p: usize },
}

/// The tests of a state check with what certifies them along a motion.
#[derive(Clone, Debug, Default)]
pub(super) struct Certificates {
    /// The tests, as [`SphereWorld::check_state`] runs them (obstacles, then link pairs).
    tests: Vec<Test>,
    /// Per test one weight per group value: the test's distance changes by at most
    /// `Σⱼ |Δqⱼ| wⱼ` over a straight motion by `Δq`.
    weights: StepWeights,
}

impl SphereWorld {
    /// The tests of a state check and their motion bounds. The radii of [`MotionBound`] are
    /// taken from the spheres of both covers (the coarse ones may reach past the fine ones),
    /// each link's extent the largest `|c| + r` of its spheres.
    pub(super) fn motion_tests(&self) -> Certificates {
        let dim = self.group.len();
        // The largest distance of a sphere's point from its link's origin is `|c| + r`.
        let mut extents = vec![0.0f64; self.links.len()];
        let coarse = self.coarse.as_ref().map(|(c, _)| c.spheres.as_slice()).unwrap_or_default();
        for &(k, c, r) in self.spheres.iter().chain(coarse) {
            extents[k] = extents[k].max((c.coords.norm() + r) * (1.0 + 1e-12));
        }
        let bound = MotionBound::with_extents(&self.robot, &self.group, &self.links, &extents)
            .unwrap_or_else(|_| self.bound.clone());
        let (mut tests, mut weights) = (Vec::new(), Vec::new());
        // One test per moving link for all obstacles: every obstacle's distance to link `k`
        // changes by at most the link's own bound, so their least gap certifies as far as
        // each of them would, with one test's bookkeeping instead of one per obstacle.
        if !self.obstacles.is_empty() {
            for k in (0..self.links.len()).filter(|&k| !self.soa.is_static(k)) {
                tests.push(Test::Obstacles { k });
                weights.extend((0..dim).map(|j| bound.radius(k, j)));
            }
        }
        for (p, &(a, b)) in self.moving_pairs.iter().enumerate() {
            tests.push(Test::Pair { a, b, p });
            weights.extend(bound.pair_radii(&self.robot, &self.group, a, b));
        }
        Certificates { tests, weights: StepWeights::from_rows(&weights, dim) }
    }

    /// Runs `test` on the placed state (`s.frames`, fine and coarse centres begun): `None`
    /// if it fails, else a lower bound on its sphere distance. Passes exactly when the tests
    /// of [`SphereWorld::check_state`] it stands for pass. Inlined into
    /// [`SphereWorld::gap_at`].
    #[inline(always)]
    fn test_gap(&self, test: Test, s: &mut Scratch) -> Option<f64> {
        let coarse = self.coarse.as_ref().map(|(_, soa)| soa);
        let (frames, fine, rough) = (s.frames.as_slice(), &mut s.centres, &mut s.coarse);
        match test {
            Test::Obstacles { k } => {
                // The link's bounding sphere against every obstacle first, all at once; then
                // the spheres against those it does not clear, the one that failed last for
                // this link first (a state in collision usually hits what one did lately).
                // The least gap does not depend on the order.
                let first = s.first_obstacle.get(k).copied().unwrap_or(usize::MAX);
                let mut least = f64::INFINITY;
                for from in (0..self.obstacles.len()).step_by(FAR_BATCH) {
                    let (far, mut near) = self.soa.far_obstacles(k, frames, fine, from);
                    least = least.min(far);
                    let mut lead = first.checked_sub(from).filter(|&i| i < FAR_BATCH && near >> i & 1 == 1);
                    while near != 0 {
                        let i = lead.take().unwrap_or(near.trailing_zeros() as usize);
                        near &= !(1u64 << i);
                        let o = from + i;
                        #[cfg(test)]
                        {
                            s.evaluated += 1;
                        }
                        let gap = coarse
                            .and_then(|c| c.link_gap(o, k, frames, rough))
                            .or_else(|| self.soa.link_gap(o, k, frames, fine));
                        let Some(gap) = gap else {
                            if s.first_obstacle.len() <= k {
                                s.first_obstacle.resize(k + 1, usize::MAX);
                            }
                            s.first_obstacle[k] = o;
                            return None;
                        };
                        least = least.min(gap);
                    }
                }
                Some(least)
            }
            Test::Pair { a, b, .. } => {
                coarse.and_then(|c| c.pair_gap(frames, rough, a, b)).or_else(|| self.soa.pair_gap(frames, fine, a, b))
            }
        }
    }

    /// The gap of `test` at `q` (`None` if it fails): from the pair's table if it settles it,
    /// else on the placed state, placing it (kinematics and centres) first unless `placed`.
    /// Inlined: the motion loop calls it for every uncertified test.
    #[inline(always)]
    fn gap_at(&self, test: Test, q: &[f64], s: &mut Scratch, placed: &mut bool) -> Option<f64> {
        #[cfg(test)]
        if matches!(test, Test::Pair { .. }) {
            s.evaluated += 1;
        }
        let table = match test {
            Test::Pair { p, .. } => self.table_gap(p, q),
            Test::Obstacles { k } => self.link_table_gap(k, q),
        };
        if table.is_some() {
            return table;
        }
        // The kinematics only once a test needs them (a table may settle the rest).
        if !*placed {
            *placed = true;
            self.place(q, s);
        }
        self.test_gap(test, s)
    }

    /// Places the state `q` for [`SphereWorld::test_gap`]: the kinematics, and every centre
    /// lazily (a state in collision often needs few links).
    fn place(&self, q: &[f64], s: &mut Scratch) {
        self.chain.frames(q, &mut s.frames);
        self.soa.begin_lazy(&mut s.centres);
        if let Some((_, coarse)) = &self.coarse {
            coarse.begin_lazy(&mut s.coarse);
        }
    }

    /// The gap of link `k`'s obstacle test at `q` from its [`LinkTable`], if it settles it
    /// (a new cell's centre checked on a scratch of its own).
    #[inline]
    fn link_table_gap(&self, k: usize, q: &[f64]) -> Option<f64> {
        let table = self.link_tables.get(k)?.as_ref()?;
        table.gap(q, |c| {
            let mut s = Scratch::default();
            self.place(c, &mut s);
            self.test_gap(Test::Obstacles { k }, &mut s)
        })
    }

    /// The [`LinkTable`]s of the links' obstacle tests (indexed by link), from the tests'
    /// weights.
    pub(super) fn link_tables(&self) -> Vec<Option<Arc<LinkTable>>> {
        let mut out = vec![None; self.links.len()];
        if !self.use_link_tables {
            return out;
        }
        let limits = self.group.limits(&self.robot);
        for (t, &test) in self.cert.tests.iter().enumerate() {
            if let Test::Obstacles { k } = test {
                out[k] = LinkTable::new(&self.cert.weights.row(t), &limits).map(Arc::new);
            }
        }
        out
    }

    /// [`StateValidityChecker::state_certificate`]: the verdict of
    /// [`SphereWorld::check_state`] and, for a valid `q`, the gap of every test in `out` (one
    /// per test, in order); `out` is left empty for an invalid `q`.
    pub(super) fn certify_state(&self, s: &mut Scratch, q: &[f64], out: &mut Vec<f64>) -> bool {
        out.clear();
        if !self.fixed_ok {
            return false;
        }
        let kinds = self.cert.tests.as_slice();
        // NaN: not run yet (a gap is never NaN for finite `q`; one that were would only be
        // computed twice).
        out.resize(kinds.len(), f64::NAN);
        let mut placed = false;
        // The tests that failed last first, as in the motion loop.
        let recent = s.recent.0;
        for (slot, &t) in recent.iter().enumerate().take_while(|&(_, &t)| t < kinds.len()) {
            let Some(gap) = self.gap_at(kinds[t], q, s, &mut placed) else {
                s.recent.0[..=slot].rotate_right(1);
                out.clear();
                return false;
            };
            out[t] = gap;
        }
        for (t, &test) in kinds.iter().enumerate() {
            if out[t].is_nan() {
                let Some(gap) = self.gap_at(test, q, s, &mut placed) else {
                    s.recent.0.rotate_right(1);
                    s.recent.0[0] = t;
                    out.clear();
                    return false;
                };
                out[t] = gap;
            }
        }
        true
    }

    /// Number of tests of a state check (the length of a [`SphereWorld::certify_state`]).
    pub(super) fn test_count(&self) -> usize {
        self.cert.tests.len()
    }

    /// [`StateValidityChecker::check_motion`] with certified tests skipped (see the module
    /// documentation): same verdict and count as checking the states one by one. Motions of
    /// more than [`MAX_STATES`] states are checked one by one.
    ///
    /// With `ends`, the [`SphereWorld::certify_state`] gaps of `a` and `b` (valid states, one
    /// gap per test) certify the states near the ends before any is computed: same verdict,
    /// fewer states (the count is then not the one-by-one count).
    pub(super) fn check_motion_certified(
        &self,
        s: &mut Scratch,
        a: &[f64],
        b: &[f64],
        step: f64,
        ends: Option<(&[f64], &[f64])>,
    ) -> Option<(bool, u64)> {
        let n = segment_subdivisions(a, b, step);
        if n >= MAX_STATES {
            return None;
        }
        if !self.fixed_ok {
            return Some((false, 1));
        }
        // The end state first, on its own unless its gaps are given: most motions a planner
        // tries end in collision, and then the motion needs no certificates at all.
        let mut end = std::mem::take(&mut s.end_gaps);
        let (a_gaps, b_gaps) = match ends {
            Some((a_gaps, b_gaps)) => (Some(a_gaps), b_gaps),
            None if self.certify_state(s, b, &mut end) => (None, end.as_slice()),
            None => {
                s.end_gaps = end;
                return Some((false, 1));
            }
        };
        let mut order = std::mem::take(&mut s.order);
        order.clear();
        order.push(n);
        coarse_to_fine_into(n, &mut order);
        // Per test, the reciprocal of its bound per step (∞ if it cannot change), the bound
        // inflated against rounding.
        let cert = &self.cert;
        cert.weights.per_step_into(a, b, n, &mut s.per_step);
        // Per state word and test, a bit per state index: certified (bit 0, the start, is
        // never checked); `all`, per word, the states every test is certified at (the end's
        // gaps certify the end itself, so the loop skips it).
        let (tests, words) = (cert.tests.len(), n / 64 + 1);
        s.certified.clear();
        s.certified.resize(tests * words, 0);
        s.all.clear();
        s.all.resize(words, 0);
        for t in 0..tests {
            if let Some(a_gaps) = a_gaps {
                set_bits(&mut s.certified[t..], tests, reach(a_gaps[t], SLACK, s.per_step[t], 0, n));
            }
            set_bits(&mut s.certified[t..], tests, reach(b_gaps[t], SLACK, s.per_step[t], n, n));
        }
        all_certified(&s.certified, tests, &mut s.all);
        s.end_gaps = end;
        let verdict = if words == 1 {
            self.check_states::<OneWord>(s, a, b, n, &order)
        } else {
            self.check_states::<Words>(s, a, b, n, &order)
        };
        s.order = order;
        Some(verdict)
    }

    /// The state loop of [`SphereWorld::check_motion_certified`]: checks the states of the
    /// motion `a → b` of `n` steps in `order`, skipping the tests (and states) that
    /// `s.certified` and `s.all` certify and certifying around each computed gap. Generic
    /// over the bit-set layout so that motions of one word keep single-word arithmetic. The
    /// loops run over pre-sliced rows (the tests, their bounds and a state word's bits) in
    /// blocks, with no index to check.
    fn check_states<B: StateBits>(
        &self,
        s: &mut Scratch,
        a: &[f64],
        b: &[f64],
        n: usize,
        order: &[usize],
    ) -> (bool, u64) {
        let kinds = self.cert.tests.as_slice();
        let tests = kinds.len();
        let mut q = std::mem::take(&mut s.q);
        let mut certified = std::mem::take(&mut s.certified);
        let per_step = std::mem::take(&mut s.per_step);
        let mut verdict = (true, order.len() as u64);
        'states: for (pos, &i) in order.iter().enumerate() {
            let (w, bit) = B::locate(i);
            if s.all[w] >> bit & 1 == 1 {
                continue;
            }
            if i == n {
                q.clear();
                q.extend_from_slice(b);
            } else {
                interpolate_into(a, b, i as f64 / n as f64, &mut q);
            }
            let mut placed = false;
            // The AND of the tests' words once this state is checked.
            let mut all = u64::MAX;
            // The state's word of every test, and the words before and after it.
            let (before, rest) = certified.split_at_mut(w * tests);
            let (row, after) = rest.split_at_mut(tests);
            // The tests that failed last first (a state in collision usually hits what one
            // did lately): a failing state then often costs one test, and a passing one none
            // more (the others skip them as certified).
            let recent = s.recent.0;
            for (slot, &t) in recent.iter().enumerate().take_while(|&(_, &t)| t < tests) {
                let bits = &mut row[t];
                if *bits >> bit & 1 == 0 {
                    let Some(gap) = self.gap_at(kinds[t], &q, s, &mut placed) else {
                        s.recent.0[..=slot].rotate_right(1);
                        verdict = (false, pos as u64 + 1);
                        break 'states;
                    };
                    let span = reach(gap, SLACK, per_step[t], i, n);
                    B::set(Row { before: &mut *before, bits, after: &mut *after, tests, t, w }, span);
                }
            }
            let blocks = row.chunks_mut(BLOCK).zip(kinds.chunks(BLOCK)).zip(per_step.chunks(BLOCK));
            // Most tests are certified: skip them a block at a time.
            for (block, ((words, kinds), per_step)) in blocks.enumerate() {
                let both = words.iter().fold(u64::MAX, |acc, &b| acc & b);
                if both >> bit & 1 == 1 {
                    all &= both;
                    continue;
                }
                for (j, ((bits, &test), &per_step)) in words.iter_mut().zip(kinds).zip(per_step).enumerate() {
                    if *bits >> bit & 1 == 0 {
                        let Some(gap) = self.gap_at(test, &q, s, &mut placed) else {
                            s.recent.0.rotate_right(1);
                            s.recent.0[0] = block * BLOCK + j;
                            verdict = (false, pos as u64 + 1);
                            break 'states;
                        };
                        let span = reach(gap, SLACK, per_step, i, n);
                        B::set(Row { before, bits, after, tests, t: block * BLOCK + j, w }, span);
                    }
                    all &= *bits;
                }
            }
            B::update_all(&certified, tests, all, &mut s.all);
        }
        s.q = q;
        s.certified = certified;
        s.per_step = per_step;
        verdict
    }
}

/// Test `t`'s certificate words around the state word `w` being checked: `bits` its word `w`,
/// `before` and `after` the words `< w` and `> w` of all `tests` tests.
struct Row<'a> {
    before: &'a mut [u64],
    bits: &'a mut u64,
    after: &'a mut [u64],
    tests: usize,
    t: usize,
    w: usize,
}

/// The layout of a motion check's certificate bits: per state word `w` and test `t`, the word
/// `w · tests + t` holds one bit per state (state `i` in word `i / 64`, bit `i % 64`).
trait StateBits {
    /// The word of state `i` and its bit in it.
    fn locate(i: usize) -> (usize, usize);
    /// Sets the bits `lo..=hi` of the row's test.
    fn set(row: Row<'_>, span: (usize, usize));
    /// Brings `all` up to date after a state was checked; `and` is the AND of the tests'
    /// words of that state after it.
    fn update_all(bits: &[u64], tests: usize, and: u64, all: &mut [u64]);
}

/// Motions of fewer than 64 states: one word per test.
struct OneWord;

impl StateBits for OneWord {
    #[inline(always)]
    fn locate(i: usize) -> (usize, usize) {
        (0, i)
    }

    #[inline(always)]
    fn set(row: Row<'_>, (lo, hi): (usize, usize)) {
        *row.bits |= (u64::MAX >> (63 - hi)) & (u64::MAX << lo);
    }

    #[inline(always)]
    fn update_all(_: &[u64], _: usize, and: u64, all: &mut [u64]) {
        all[0] = and;
    }
}

/// Longer motions: a checked state's certificates may reach into other words.
struct Words;

impl StateBits for Words {
    #[inline(always)]
    fn locate(i: usize) -> (usize, usize) {
        (i / 64, i % 64)
    }

    #[inline(always)]
    fn set(row: Row<'_>, span: (usize, usize)) {
        let Row { before, bits, after, tests, t, w } = row;
        for_words(span, |v, mask| match v.cmp(&w) {
            std::cmp::Ordering::Less => before[v * tests + t] |= mask,
            std::cmp::Ordering::Equal => *bits |= mask,
            std::cmp::Ordering::Greater => after[(v - w - 1) * tests + t] |= mask,
        });
    }

    #[inline(always)]
    fn update_all(bits: &[u64], tests: usize, _: u64, all: &mut [u64]) {
        all_certified(bits, tests, all);
    }
}

/// Per word, the AND of the `tests` bit sets stored word by word in `certified`.
fn all_certified(certified: &[u64], tests: usize, all: &mut [u64]) {
    for (w, out) in all.iter_mut().enumerate() {
        *out = certified[w * tests..(w + 1) * tests].iter().fold(u64::MAX, |acc, &b| acc & b);
    }
}

/// Tests whose certificate bits a motion check tests together.
const BLOCK: usize = 8;

/// Motions of fewer states than this are certified (one bit per state and test: at most
/// 512 bytes per test); longer ones are checked one by one.
const MAX_STATES: usize = 4096;

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use nalgebra::{Isometry3, Vector3};
    use opengrasp_core::model::{samples, JointGroup};

    use crate::validity::soa::with_scratch;
    use crate::validity::{ObstacleBox, SphereWorld, StateValidityChecker};

    /// The tests a certified check of `a → b` runs, and its verdict.
    fn evaluations(world: &SphereWorld, a: &[f64], b: &[f64]) -> (u64, (bool, u64)) {
        let before = with_scratch(|s| s.evaluated);
        let verdict = world.check_motion(a, b, 0.02);
        (with_scratch(|s| s.evaluated) - before, verdict)
    }

    /// The planar arm stretched along x hits the post, the last of six boxes: the first
    /// check clears the three far boxes by their bounding spheres, all at once, and runs the
    /// box tests of the two boxes beside the arm (near, not touching) before the post's; the
    /// same check again starts with the link test that failed, at the post, and runs only
    /// that box; the verdict and count stay those of checking every state.
    #[test]
    fn a_repeated_collision_costs_one_test() {
        let robot = Arc::new(samples::planar_arm(&[0.5, 0.4]).expect("arm"));
        let group = JointGroup::all(&robot, "arm").expect("group");
        let cube = |x: f64, y: f64| Isometry3::translation(x, y, 0.0);
        let far = [cube(-2.0, 0.0), cube(0.0, 2.0), cube(0.0, -2.0)]
            .map(|pose| ObstacleBox::new("far", pose, Vector3::new(0.1, 0.1, 0.1)));
        let beside = [cube(0.25, 0.2), cube(0.25, -0.2)]
            .map(|pose| ObstacleBox::new("beside", pose, Vector3::new(0.1, 0.1, 0.1)));
        let post = ObstacleBox::new("post", cube(0.6, 0.0), Vector3::new(0.1, 0.1, 0.5));
        let boxes = far.into_iter().chain(beside).chain([post]).collect();
        let world = SphereWorld::new(robot, group, vec![0.0, 0.0], Isometry3::identity(), boxes).expect("world");
        let (a, b) = ([1.2, 0.3], [0.0, 0.0]);
        let every_state = world.clone().with_certified_motions(false).check_motion(&a, &b, 0.02);
        assert!(!every_state.0);
        let (first, verdict) = evaluations(&world, &a, &b);
        assert_eq!(verdict, every_state);
        assert!(first >= 3, "{first} tests");
        let (second, verdict) = evaluations(&world, &a, &b);
        assert_eq!(verdict, every_state);
        assert_eq!(second, 1);
    }

    /// The planar arm's first link moves with the first joint alone, so its obstacle test has
    /// a table; the second link has none. Over the first joint's range (the second's value
    /// does not matter to the first link), a settled table entry passes the direct test and is
    /// at most the link's sphere distance to the boxes, and most values whose direct gap is
    /// over 1 cm are settled.
    #[test]
    fn link_tables_bound_the_direct_test() {
        let robot = Arc::new(samples::planar_arm(&[0.5, 0.4]).expect("arm"));
        let group = JointGroup::all(&robot, "arm").expect("group");
        let boxes = [(0.9, 0.0), (0.0, 0.45), (-0.7, -0.3)]
            .map(|(x, y)| ObstacleBox::new("box", Isometry3::translation(x, y, 0.0), Vector3::new(0.1, 0.1, 0.1)));
        let world = SphereWorld::new(robot, group, vec![0.0, 0.0], Isometry3::identity(), boxes.into())
            .expect("world")
            .with_link_tables(true);
        assert!(world.link_tables.iter().filter(|t| t.is_some()).count() >= 1);
        let (k, _) = world.link_tables.iter().enumerate().find(|(_, t)| t.is_some()).expect("a table");
        let limits = world.group.limits(&world.robot);
        let (lo, hi) = limits[0];
        let (mut settled, mut clear) = (0, 0);
        for i in 0..=2000 {
            let q = [lo + (hi - lo) * i as f64 / 2000.0, 0.3 * (i % 7) as f64];
            let direct = with_scratch(|s| {
                world.place(&q, s);
                world.test_gap(super::Test::Obstacles { k }, s)
            });
            clear += usize::from(direct.is_some_and(|g| g > 0.01));
            if let Some(bound) = world.link_table_gap(k, &q) {
                settled += 1;
                assert!(direct.is_some(), "a settled test passes");
                let distance = world.link_obstacle_distance(&world.centres_for(&q), k);
                assert!(bound > 0.0 && bound <= distance, "{bound} > {distance} at {q:?}");
            }
        }
        assert!(settled * 10 >= clear * 9, "{settled} settled of {clear} clear by 1 cm");
    }
}
