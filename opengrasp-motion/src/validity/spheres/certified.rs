//! Motion checks that skip tests a checked state certifies for its neighbours.
//!
//! A state check is a list of tests (each moving link against each obstacle, each checked
//! link pair), and each test can report a lower bound `g` on its sphere distance
//! ([`SphereSoa::link_gap`], [`SphereSoa::pair_gap`]). Along a straight motion the spheres
//! of link `k` move at most `Σⱼ |Δqⱼ| rₖⱼ` between two states ([`MotionBound`]); for a link
//! pair only the joints that move one link and not the other change their distance (rigid
//! motions keep distances). So a test that passed with gap `g` at state `i` passes at every
//! state `j` with `|j − i| · δ < g`, `δ` its bound per step, and is not run there; a state
//! whose tests are all certified is not computed at all. The verdict and the one-by-one count
//! are those of checking every state in the default order.

use super::{SphereWorld, StateValidityChecker};
use crate::validate::{interpolate_into, segment_subdivisions};
use crate::validity::chain::Mat34;
use crate::validity::soa::{Centres, Scratch};
use crate::validity::MotionBound;

/// Absolute slack (m) taken off every certified gap: covers the rounding of the kinematics
/// and of the interpolated states, many orders of magnitude below it.
const SLACK: f64 = 1e-9;

/// One test of a state check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Test {
    /// Link `k` (moving) against obstacle `o`.
    Obstacle { o: usize, k: usize },
    /// Links `a` and `b`, not rigidly attached: moving pair `p`.
    Pair { a: usize, b: usize, p: usize },
}

/// The tests of a state check with what certifies them along a motion.
#[derive(Clone, Debug, Default)]
pub(super) struct Certificates {
    /// The tests, as [`SphereWorld::check_state`] runs them (obstacles, then link pairs).
    tests: Vec<Test>,
    /// Per test one weight per group value: the test's distance changes by at most
    /// `Σⱼ |Δqⱼ| wⱼ` over a straight motion by `Δq` (`tests.len() × dim`).
    weights: Vec<f64>,
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
        let mut cert = Certificates::default();
        for o in 0..self.obstacles.len() {
            for k in (0..self.links.len()).filter(|&k| !self.soa.is_static(k)) {
                cert.tests.push(Test::Obstacle { o, k });
                cert.weights.extend((0..dim).map(|j| bound.radius(k, j)));
            }
        }
        for (p, &(a, b)) in self.moving_pairs.iter().enumerate() {
            cert.tests.push(Test::Pair { a, b, p });
            let (la, lb) = (
                self.chain.lineage(self.chain.link(self.links[a]).0),
                self.chain.lineage(self.chain.link(self.links[b]).0),
            );
            // Group values driving a frame that carries one link and not the other.
            let own = |mine: &[(usize, usize)], other: &[(usize, usize)], j: usize| {
                mine.iter().any(|&(f, d)| d == j && !other.iter().any(|&(g, _)| g == f))
            };
            cert.weights.extend((0..dim).map(|j| {
                let wa = if own(&la, &lb, j) { bound.radius(a, j) } else { 0.0 };
                let wb = if own(&lb, &la, j) { bound.radius(b, j) } else { 0.0 };
                wa + wb
            }));
        }
        cert
    }

    /// Runs `test` on the placed state (`frames`, fine and coarse centres begun): `None` if
    /// it fails, else a lower bound on its sphere distance. Passes exactly when the test of
    /// [`SphereWorld::check_state`] passes.
    fn test_gap(&self, test: Test, frames: &[Mat34], fine: &mut Centres, rough: &mut Centres) -> Option<f64> {
        let coarse = self.coarse.as_ref().map(|(_, soa)| soa);
        match test {
            Test::Obstacle { o, k } => self.soa.link_far(o, k, fine).or_else(|| {
                coarse.and_then(|c| c.link_gap(o, k, frames, rough)).or_else(|| self.soa.link_gap(o, k, frames, fine))
            }),
            Test::Pair { a, b, .. } => {
                coarse.and_then(|c| c.pair_gap(frames, rough, a, b)).or_else(|| self.soa.pair_gap(frames, fine, a, b))
            }
        }
    }

    /// [`StateValidityChecker::check_motion`] with certified tests skipped (see the module
    /// documentation): same verdict and count as checking the states one by one. Motions of
    /// more than [`MAX_STATES`] states are checked one by one.
    pub(super) fn check_motion_certified(
        &self,
        s: &mut Scratch,
        a: &[f64],
        b: &[f64],
        step: f64,
    ) -> Option<(bool, u64)> {
        let n = segment_subdivisions(a, b, step);
        if n >= MAX_STATES {
            return None;
        }
        if !self.fixed_ok {
            return Some((false, 1));
        }
        let mut order = std::mem::take(&mut s.order);
        order.clear();
        order.push(n);
        if n > 1 {
            let mut stride = n.next_power_of_two() / 2;
            while stride >= 1 {
                order.extend((stride..n).step_by(2 * stride));
                stride /= 2;
            }
        }
        // Per test, the reciprocal of its bound per step (∞ if it cannot change), the bound
        // inflated against rounding.
        let dim = self.dim();
        let cert = &self.cert;
        s.per_step.clear();
        s.per_step.extend(cert.weights.chunks_exact(dim.max(1)).map(|w| {
            let d: f64 = w.iter().zip(a).zip(b).map(|((w, x), y)| w * (y - x).abs()).sum();
            n.max(1) as f64 / (d * (1.0 + 1e-9))
        }));
        // Per test, a bit per state index: certified (bit 0, the start, is never checked).
        s.certified.clear();
        s.certified.resize(cert.tests.len(), 0);
        let mut all = 0u64;
        let mut q = std::mem::take(&mut s.q);
        let mut verdict = (true, order.len() as u64);
        'states: for (pos, &i) in order.iter().enumerate() {
            if all >> i & 1 == 1 {
                continue;
            }
            if i == n {
                q.clear();
                q.extend_from_slice(b);
            } else {
                interpolate_into(a, b, i as f64 / n as f64, &mut q);
            }
            // The kinematics only once a test needs them (a table may settle the rest).
            let mut placed = false;
            all = u64::MAX;
            for (t, &test) in cert.tests.iter().enumerate() {
                let mut bits = s.certified[t];
                if bits >> i & 1 == 0 {
                    let table = match test {
                        Test::Pair { p, .. } => self.table_gap(p, &q),
                        Test::Obstacle { .. } => None,
                    };
                    if table.is_none() && !placed {
                        placed = true;
                        self.chain.frames(&q, &mut s.frames);
                        self.soa.begin(&s.frames, &mut s.centres);
                        if let Some((_, coarse)) = &self.coarse {
                            coarse.begin(&s.frames, &mut s.coarse);
                        }
                    }
                    let gap = table.or_else(|| self.test_gap(test, &s.frames, &mut s.centres, &mut s.coarse));
                    let Some(gap) = gap else {
                        verdict = (false, pos as u64 + 1);
                        break 'states;
                    };
                    // States within reach of `i`: `⌊(gap − slack) / per step⌋`, saturating
                    // (negative → 0, ∞ → all).
                    let reach = (((gap - SLACK) * s.per_step[t]) as usize).min(n);
                    let (lo, hi) = (i.saturating_sub(reach), (i + reach).min(n));
                    bits |= (u64::MAX >> (63 - hi)) & (u64::MAX << lo);
                    s.certified[t] = bits;
                }
                all &= bits;
            }
        }
        s.q = q;
        s.order = order;
        Some(verdict)
    }
}

/// Motions of at most this many states minus one are certified (one bit per state).
const MAX_STATES: usize = 64;
