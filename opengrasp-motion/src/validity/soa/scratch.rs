//! Per-thread buffers of the sphere model's state and motion checks.

use std::cell::RefCell;

use super::super::chain::{Lanes, Mat34};
use super::LaneCentres;

/// Sphere centres of one state, struct of arrays, plus each link's bounding-sphere centre.
#[derive(Debug, Default)]
pub(in crate::validity) struct Centres {
    pub(super) x: Vec<f64>,
    pub(super) y: Vec<f64>,
    pub(super) z: Vec<f64>,
    pub(super) link: Vec<[f64; 3]>,
    /// Cluster bounding-sphere centres (placed with their link's spheres).
    pub(super) cluster: Vec<[f64; 3]>,
    /// The state being placed, counting from 1: a flag below is set for this state when it
    /// holds `epoch` (so starting a state clears none of them).
    pub(super) epoch: u32,
    /// Whether each link's cluster centres are placed yet, and each cluster's spheres (both
    /// are placed when first needed: most clusters are culled by their bounding sphere).
    pub(super) placed: Vec<u32>,
    pub(super) filled: Vec<u32>,
    /// Whether each link's bounding-sphere centre is placed yet.
    pub(super) linked: Vec<u32>,
    /// The broad phase's distances of a link to the obstacles (a buffer).
    pub(super) distances: Vec<f64>,
}

impl Centres {
    /// Starts a new state of `spheres` spheres, `links` links and `clusters` clusters: every
    /// flag unset (the buffers sized only when the cover differs from the last one's).
    #[inline(always)]
    pub(super) fn restart(&mut self, spheres: usize, links: usize, clusters: usize) {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 || self.x.len() != spheres || self.placed.len() != links || self.filled.len() != clusters {
            self.epoch = 1;
            for xs in [&mut self.x, &mut self.y, &mut self.z] {
                xs.resize(spheres, 0.0);
            }
            self.link.resize(links, [0.0; 3]);
            self.cluster.resize(clusters, [0.0; 3]);
            for (flags, n) in [(&mut self.placed, links), (&mut self.linked, links), (&mut self.filled, clusters)] {
                flags.clear();
                flags.resize(n, 0);
            }
        }
    }
}

/// Per-thread buffers of the sphere model's state checks.
#[derive(Debug, Default)]
pub(in crate::validity) struct Scratch {
    pub frames: Vec<Mat34>,
    pub centres: Centres,
    pub coarse: Centres,
    pub q: Vec<f64>,
    /// Buffers of the batched kernels: frame poses, fine and coarse centres, group values
    /// per lane, and the order of a motion's states.
    pub lane_frames: Vec<[Lanes; 12]>,
    pub lane_centres: LaneCentres,
    pub lane_coarse: LaneCentres,
    pub lane_q: Vec<Lanes>,
    pub order: Vec<usize>,
    /// Buffers of the certified motion checks: `|Δq|` per step, and per state word and test
    /// one bit per state the test is certified at.
    pub per_step: Vec<f64>,
    pub certified: Vec<u64>,
    /// Per word of `certified`, the states every test is certified at.
    pub all: Vec<u64>,
    /// The tests that last failed certified motion checks, most recent first, tried first
    /// at the next states: only the work changes, a state is invalid whichever of its tests
    /// fails first.
    pub recent: Recent,
    /// The gaps of a certified motion's end state.
    pub end_gaps: Vec<f64>,
    /// Per link, the obstacle that last failed its obstacle test, tried first at the next
    /// state (only the work changes, as for `recent`).
    pub first_obstacle: Vec<usize>,
    /// Link-obstacle and pair tests run by certified motion checks (to test how much work
    /// they skip).
    #[cfg(test)]
    pub evaluated: u64,
}

/// Failed tests a [`Scratch`] remembers.
pub(in crate::validity) const RECENT: usize = 16;

/// Test indices, `usize::MAX` past the last.
#[derive(Clone, Copy, Debug)]
pub(in crate::validity) struct Recent(pub [usize; RECENT]);

impl Default for Recent {
    fn default() -> Self {
        Self([usize::MAX; RECENT])
    }
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Runs `f` with this thread's scratch (fresh buffers on re-entrance).
pub(in crate::validity) fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut s) => f(&mut s),
        Err(_) => f(&mut Scratch::default()),
    })
}

#[cfg(test)]
mod tests {
    use super::Centres;

    #[test]
    fn a_new_state_unsets_every_flag_even_when_the_count_wraps() {
        let mut c = Centres::default();
        c.restart(5, 2, 3);
        assert_eq!((c.epoch, c.x.len(), c.link.len(), c.filled.len()), (1, 5, 2, 3));
        c.placed[1] = c.epoch;
        c.restart(5, 2, 3);
        assert_eq!(c.epoch, 2);
        assert_ne!(c.placed[1], c.epoch);
        // After 2³² states the count starts again at 1, where flags of the first state are
        // still set: they must be cleared.
        c.epoch = u32::MAX;
        c.restart(5, 2, 3);
        assert_eq!((c.epoch, c.placed.as_slice()), (1, [0, 0].as_slice()));
        // A cover of another size resizes the buffers and clears the flags.
        c.linked[0] = 2;
        c.restart(7, 4, 1);
        assert_eq!((c.epoch, c.x.len(), c.link.len(), c.cluster.len()), (1, 7, 4, 1));
        assert!(c.linked.iter().chain(&c.placed).chain(&c.filled).all(|&f| f == 0));
    }
}
