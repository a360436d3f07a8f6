//! State validity checking: the one interface every planner, validator and metric uses.
//!
//! A [`StateValidityChecker`] answers "is this group configuration collision-free?" and,
//! optionally, how far the robot is from obstacles (for clearance metrics) and how far each
//! link is from everything it could hit (for certified continuous collision checking with a
//! [`MotionBound`]).
//!
//! Implementations shipped with the crate:
//! - [`CollisionChecker`]: exact checks on core's parry-based [`CollisionWorld`](opengrasp_core::collision::CollisionWorld) (environment,
//!   objects, self-collision, attached objects).
//! - [`cover`]: sphere covers of meshes with a guaranteed bound (every surface point covered).
//! - [`SphereWorld`]: the links of a core [`Robot`](opengrasp_core::model::Robot) covered by spheres, among oriented boxes.
//!   Closed-form distances, fast, conservative; used by the stand-in benchmark scenes and tests.
//! - [`OneByOne`]: wraps any checker so batches and motions are checked one state at a time
//!   (the reference of batched checks).
//! - [`CountingChecker`]: wraps any checker and counts the calls (the benchmark uses it to
//!   report collision checks per run).

mod bound;
mod chain;
pub mod cover;
mod exact;
mod greedy;
mod obstacles;
mod soa;
mod spheres;
mod steps;

use std::cell::Cell;

pub use bound::MotionBound;
pub use exact::CollisionChecker;
pub use obstacles::{ObstacleBox, ObstaclePrimitive, ObstacleShape};
pub use spheres::{MeshCover, SelfCollisionPairs, SphereWorld};

/// Decides whether group configurations are valid (collision-free).
///
/// Configurations are *group* vectors: one value per joint of the planning group, in group
/// order. Only [`StateValidityChecker::dim`] and [`StateValidityChecker::is_valid`] are
/// required; the distance methods enable clearance metrics and continuous checking.
pub trait StateValidityChecker {
    /// Dimension of the group configurations this checker accepts.
    fn dim(&self) -> usize;

    /// True if `q` (group values) is collision-free. `q` has [`StateValidityChecker::dim`]
    /// finite entries; implementations may panic otherwise.
    fn is_valid(&self, q: &[f64]) -> bool;

    /// Distance from the robot (at least the parts the group moves) to the obstacles at `q`
    /// (negative or zero in collision), or `None` if the checker cannot compute distances
    /// (default).
    fn clearance(&self, q: &[f64]) -> Option<f64> {
        let _ = q;
        None
    }

    /// Writes into `out` one lower bound per entry of [`MotionBound::links`] on the distance
    /// from that link to everything it could hit, and returns true; returns false (default)
    /// if unsupported.
    ///
    /// If [`StateValidityChecker::ccd_covers_self_collision`] is true, each entry must also be
    /// at most half the distance to every link it may collide with, so that two links moving
    /// towards each other are certified by the same per-link bound.
    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        let _ = (q, out);
        false
    }

    /// The per-link motion bound matching [`StateValidityChecker::link_distances`], or `None`
    /// (default) if continuous checking is unsupported.
    fn motion_bound(&self) -> Option<&MotionBound> {
        None
    }

    /// True if [`StateValidityChecker::link_distances`] accounts for self-collision (see
    /// there). When false (default) the continuous validator adds a strict discrete check for
    /// self-collisions.
    fn ccd_covers_self_collision(&self) -> bool {
        false
    }

    /// Checks several configurations at once: `qs` holds `out.len()` configurations of
    /// [`StateValidityChecker::dim`] values each, back to back, and `out[k]` receives
    /// [`StateValidityChecker::is_valid`] of the `k`-th. The default calls `is_valid` in turn;
    /// vectorised checkers override it. Results must equal the scalar ones.
    fn are_valid(&self, qs: &[f64], out: &mut [bool]) {
        let dim = self.dim().max(1);
        for (q, o) in qs.chunks_exact(dim).zip(out.iter_mut()) {
            *o = self.is_valid(q);
        }
    }

    /// Discrete check of the motion `a → b` at `step`: true if `b` and the states at
    /// `n = ⌈|b − a| / step⌉` equal subdivisions are valid (exactly the verdict of
    /// [`segment_valid_discrete`](crate::validate::segment_valid_discrete): end state first,
    /// then coarse to fine). The default returns [`StateValidityChecker::check_motion`]'s
    /// verdict; planners call it for every edge.
    fn is_motion_valid(&self, a: &[f64], b: &[f64], step: f64) -> bool {
        self.check_motion(a, b, step).0
    }

    /// The verdict of [`StateValidityChecker::is_motion_valid`] and the number of states it
    /// needed: how many states the one-by-one check in that order tests before it stops (all
    /// of them if the motion is valid). The default checks them one by one with
    /// [`StateValidityChecker::is_valid`]; checkers that test several states at once override
    /// this method (same verdict, same count) and keep `is_motion_valid`'s default.
    fn check_motion(&self, a: &[f64], b: &[f64], step: f64) -> (bool, u64) {
        let mut checked = 0;
        let valid = crate::validate::segment_valid_discrete_by(
            |q| {
                checked += 1;
                self.is_valid(q)
            },
            a,
            b,
            step,
        );
        (valid, checked)
    }

    /// Validity of `q` with respect to everything [`StateValidityChecker::link_distances`]
    /// does *not* measure (for core's exact checker: self-collision and carried objects
    /// against the robot's own links), or `None` (default) if the checker cannot separate it.
    ///
    /// Lets post-processing certify a segment's environment clearance once by conservative
    /// advancement and then run its fine discrete checks on this cheaper remainder: for `q`
    /// with every link distance positive, `is_valid(q) == residual_valid(q).unwrap()` must
    /// hold.
    fn residual_valid(&self, q: &[f64]) -> Option<bool> {
        let _ = q;
        None
    }

    /// [`StateValidityChecker::is_valid`] of `q`, and into `out` (cleared first) what the
    /// check learnt about the neighbourhood of a valid `q`, for
    /// [`StateValidityChecker::is_motion_valid_between`]: planners that check many motions
    /// from the same states (a roadmap's vertices) compute it once per state. Left empty by
    /// the default and for invalid states.
    fn state_certificate(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        out.clear();
        self.is_valid(q)
    }

    /// [`StateValidityChecker::is_motion_valid`] of `a → b` (same verdict) given the
    /// [`StateValidityChecker::state_certificate`]s of `a` and `b` from this checker, which
    /// let it skip tests near the ends (an empty certificate is no help). The default ignores
    /// them.
    fn is_motion_valid_between(&self, a: &[f64], a_cert: &[f64], b: &[f64], b_cert: &[f64], step: f64) -> bool {
        let _ = (a_cert, b_cert);
        self.is_motion_valid(a, b, step)
    }
}

/// Forwards every method of [`StateValidityChecker`] through a pointer type.
macro_rules! forward_checker {
    ($($pointer:ty),*) => {$(
        impl<T: StateValidityChecker + ?Sized> StateValidityChecker for $pointer {
            fn dim(&self) -> usize {
                (**self).dim()
            }
            fn is_valid(&self, q: &[f64]) -> bool {
                (**self).is_valid(q)
            }
            fn clearance(&self, q: &[f64]) -> Option<f64> {
                (**self).clearance(q)
            }
            fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
                (**self).link_distances(q, out)
            }
            fn motion_bound(&self) -> Option<&MotionBound> {
                (**self).motion_bound()
            }
            fn ccd_covers_self_collision(&self) -> bool {
                (**self).ccd_covers_self_collision()
            }
            fn are_valid(&self, qs: &[f64], out: &mut [bool]) {
                (**self).are_valid(qs, out)
            }
            fn is_motion_valid(&self, a: &[f64], b: &[f64], step: f64) -> bool {
                (**self).is_motion_valid(a, b, step)
            }
            fn check_motion(&self, a: &[f64], b: &[f64], step: f64) -> (bool, u64) {
                (**self).check_motion(a, b, step)
            }
            fn residual_valid(&self, q: &[f64]) -> Option<bool> {
                (**self).residual_valid(q)
            }
            fn state_certificate(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
                (**self).state_certificate(q, out)
            }
            fn is_motion_valid_between(&self, a: &[f64], a_cert: &[f64], b: &[f64], b_cert: &[f64], step: f64) -> bool {
                (**self).is_motion_valid_between(a, a_cert, b, b_cert, step)
            }
        }
    )*};
}

forward_checker!(&T, Box<T>);

/// A checker that accepts every configuration of the given dimension (free space).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AlwaysValid(pub usize);

impl StateValidityChecker for AlwaysValid {
    fn dim(&self) -> usize {
        self.0
    }
    fn is_valid(&self, _q: &[f64]) -> bool {
        true
    }
}

/// Wraps a checker and forwards only [`StateValidityChecker::dim`] and
/// [`StateValidityChecker::is_valid`], so batches and motions are checked one state at a time
/// by the trait's defaults: the reference that batched checkers must match.
pub struct OneByOne<'a>(pub &'a dyn StateValidityChecker);

impl StateValidityChecker for OneByOne<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        self.0.is_valid(q)
    }
}

/// Wraps a checker and counts validity checks and distance queries.
pub struct CountingChecker<'a> {
    inner: &'a dyn StateValidityChecker,
    checks: Cell<u64>,
    distance_queries: Cell<u64>,
}

impl<'a> CountingChecker<'a> {
    /// A counter around `inner`, starting at zero.
    pub fn new(inner: &'a dyn StateValidityChecker) -> Self {
        Self { inner, checks: Cell::new(0), distance_queries: Cell::new(0) }
    }
    /// Number of states checked so far: [`StateValidityChecker::is_valid`] calls, states of
    /// batches and of motion checks.
    pub fn checks(&self) -> u64 {
        self.checks.get()
    }
    /// Number of clearance and link-distance queries so far.
    pub fn distance_queries(&self) -> u64 {
        self.distance_queries.get()
    }
    /// Resets both counters to zero.
    pub fn reset(&self) {
        self.checks.set(0);
        self.distance_queries.set(0);
    }
}

impl StateValidityChecker for CountingChecker<'_> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        self.checks.set(self.checks.get() + 1);
        self.inner.is_valid(q)
    }
    fn clearance(&self, q: &[f64]) -> Option<f64> {
        self.distance_queries.set(self.distance_queries.get() + 1);
        self.inner.clearance(q)
    }
    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        self.distance_queries.set(self.distance_queries.get() + 1);
        self.inner.link_distances(q, out)
    }
    fn motion_bound(&self) -> Option<&MotionBound> {
        self.inner.motion_bound()
    }
    fn ccd_covers_self_collision(&self) -> bool {
        self.inner.ccd_covers_self_collision()
    }
    fn are_valid(&self, qs: &[f64], out: &mut [bool]) {
        self.checks.set(self.checks.get() + out.len() as u64);
        self.inner.are_valid(qs, out)
    }
    fn residual_valid(&self, q: &[f64]) -> Option<bool> {
        // A partial check: counted as a check.
        let r = self.inner.residual_valid(q);
        if r.is_some() {
            self.checks.set(self.checks.get() + 1);
        }
        r
    }
    /// Counts the states the verdict needed (as many `is_valid` calls as the one-by-one
    /// check would make), however the inner checker batches them.
    fn check_motion(&self, a: &[f64], b: &[f64], step: f64) -> (bool, u64) {
        let (valid, checked) = self.inner.check_motion(a, b, step);
        self.checks.set(self.checks.get() + checked);
        (valid, checked)
    }
}
