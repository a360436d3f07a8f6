//! Reference planners: [`RrtConnect`], [`Prm`] and [`IkRrt`].
//!
//! All three sample uniformly within the group's joint limits with a seeded `ChaCha8Rng`,
//! check segments discretely at [`PlanningProblem::step`](crate::PlanningProblem::step), and
//! find nearest neighbours with a [`NearestNeighbors`] structure chosen by
//! [`NeighborStructure`] (a kd-tree by default; the linear scan gives the same answers).

mod prm;
mod rrt;

pub use prm::{Prm, PrmOptions};
pub use rrt::{IkRrt, IkRrtOptions, RrtConnect, RrtConnectOptions};

use crate::error::Result;
use crate::nearest::{KdTree, LinearScan, NearestNeighbors};

/// The nearest-neighbour structure a planner stores its configurations in. Both give the same
/// answers (see [`crate::nearest`]), so the choice changes only the planning time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NeighborStructure {
    /// [`KdTree`] (default).
    #[default]
    KdTree,
    /// [`LinearScan`], the reference.
    LinearScan,
}

impl NeighborStructure {
    /// An empty structure of this kind for `dim`-dimensional configurations.
    pub fn build(self, dim: usize) -> Box<dyn NearestNeighbors> {
        match self {
            Self::KdTree => Box::new(KdTree::new(dim)),
            Self::LinearScan => Box::new(LinearScan::new(dim)),
        }
    }
}

/// A planner's configurations: a [`NearestNeighbors`] structure with infallible access to
/// the indices it handed out.
pub(crate) struct Nodes(NeighborStructure, Box<dyn NearestNeighbors>);

impl Nodes {
    pub fn new(kind: NeighborStructure, dim: usize) -> Self {
        Self(kind, kind.build(dim))
    }
    pub fn dim(&self) -> usize {
        self.1.dim()
    }
    pub fn len(&self) -> usize {
        self.1.len()
    }
    /// Configuration `i` (an index returned by `push`).
    pub fn get(&self, i: usize) -> &[f64] {
        self.1.get(i).unwrap_or_default()
    }
    pub fn push(&mut self, q: &[f64]) -> Result<usize> {
        self.1.add(q)
    }
    pub fn nearest(&self, q: &[f64]) -> Result<Option<usize>> {
        self.1.nearest(q)
    }
    /// Up to `k` nearest nodes with their distances, closest first.
    pub fn k_nearest(&self, q: &[f64], k: usize) -> Result<Vec<(usize, f64)>> {
        let mut out = Vec::with_capacity(k);
        self.1.k_nearest(q, k, &mut out)?;
        Ok(out)
    }
}

impl Default for Nodes {
    fn default() -> Self {
        Self::new(NeighborStructure::default(), 0)
    }
}

impl Clone for Nodes {
    fn clone(&self) -> Self {
        let mut copy = Self::new(self.0, self.dim());
        for i in 0..self.len() {
            // Same dimension, finite values: cannot fail.
            let _ = copy.push(self.get(i));
        }
        copy
    }
}

impl std::fmt::Debug for Nodes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Nodes").field("kind", &self.0).field("dim", &self.dim()).field("len", &self.len()).finish()
    }
}
