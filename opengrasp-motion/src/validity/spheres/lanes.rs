//! The batched checks of the sphere model: several states per kernel call, struct of arrays
//! across the states ([`SphereWorld::with_batched_checks`]).

use super::super::chain::LANES;
use super::super::soa::{and_not, any_lane, Mask, Scratch};
use super::SphereWorld;

impl SphereWorld {
    /// [`SphereWorld::check_state`] of the [`LANES`] states in `s.lane_q` (group value `d` of
    /// lane `l` at `s.lane_q[d][l]`) whose lanes are set in `alive`: returns the valid lanes
    /// among them. Each lane runs the scalar check's tests with its arithmetic, so its verdict
    /// equals `check_state` of its state; a lane leaves the remaining tests once invalid, and
    /// the batch stops when no lane is left.
    pub(super) fn check_lanes(&self, s: &mut Scratch, mut alive: Mask) -> Mask {
        if !self.fixed_ok {
            return [false; LANES];
        }
        self.chain.frames_lanes(&s.lane_q, &mut s.lane_frames);
        self.soa.begin_lanes(&s.lane_frames, &mut s.lane_centres);
        let (frames, fine) = (&s.lane_frames, &mut s.lane_centres);
        let coarse = self.coarse.as_ref().map(|(_, soa)| soa);
        if let Some(coarse) = coarse {
            coarse.begin_lanes(frames, &mut s.lane_coarse);
        }
        let rough = &mut s.lane_coarse;
        for o in 0..self.obstacles.len() {
            for k in 0..self.links.len() {
                if self.soa.is_static(k) {
                    continue;
                }
                let mut near = self.soa.link_near_lanes(o, k, fine);
                for l in 0..LANES {
                    near[l] &= alive[l];
                }
                if let Some(coarse) = coarse {
                    near = coarse.link_hits_lanes(o, k, frames, rough, near);
                }
                alive = and_not(&alive, &self.soa.link_hits_lanes(o, k, frames, fine, near));
                if !any_lane(&alive) {
                    return alive;
                }
            }
        }
        for &(a, b) in &self.moving_pairs {
            let mut near = alive;
            if let Some(coarse) = coarse {
                near = coarse.pair_hits_lanes(frames, rough, a, b, near);
            }
            alive = and_not(&alive, &self.soa.pair_hits_lanes(frames, fine, a, b, near));
            if !any_lane(&alive) {
                return alive;
            }
        }
        alive
    }

    /// Loads `count ≤ LANES` states into `s.lane_q` (state `j` written by `state(j, out)`),
    /// repeating the first in the unused lanes, and returns the mask of the used lanes.
    pub(super) fn load_lanes(&self, s: &mut Scratch, count: usize, mut state: impl FnMut(usize, &mut [f64])) -> Mask {
        let dim = self.group.len();
        s.lane_q.resize(dim, [0.0; LANES]);
        let mut q = std::mem::take(&mut s.q);
        q.resize(dim, 0.0);
        for l in 0..LANES {
            if l < count {
                state(l, &mut q);
            }
            for (d, &v) in q.iter().enumerate() {
                s.lane_q[d][l] = v;
            }
        }
        s.q = q;
        std::array::from_fn(|l| l < count)
    }

    /// [`StateValidityChecker::check_motion`] in batches of [`LANES`] states, taken in the
    /// one-by-one order (end state, then coarse to fine), so a collision stops the check after
    /// the first batch holding one; the count is that of the one-by-one check.
    pub(super) fn check_motion_lanes(&self, s: &mut Scratch, a: &[f64], b: &[f64], step: f64) -> (bool, u64) {
        let n = crate::validate::segment_subdivisions(a, b, step);
        // States by index: `n` is `b` itself, `i < n` is `a + (i / n)(b − a)`.
        // The end state alone first: many motions fail there.
        if !self.check_state(b, s) {
            return (false, 1);
        }
        if n <= 1 {
            return (true, 1);
        }
        let mut order = std::mem::take(&mut s.order);
        order.clear();
        crate::validate::coarse_to_fine_into(n, &mut order);
        let mut verdict = (true, order.len() as u64 + 1);
        for (batch, chunk) in order.chunks(LANES).enumerate() {
            let used = self.load_lanes(s, chunk.len(), |l, q| {
                let i = chunk[l];
                if i == n {
                    q.copy_from_slice(b);
                } else {
                    let t = i as f64 / n as f64;
                    for ((v, x), y) in q.iter_mut().zip(a).zip(b) {
                        *v = x + t * (y - x);
                    }
                }
            });
            let valid = self.check_lanes(s, used);
            if let Some(l) = (0..chunk.len()).find(|&l| !valid[l]) {
                verdict = (false, (batch * LANES + l + 2) as u64);
                break;
            }
        }
        s.order = order;
        verdict
    }
}
