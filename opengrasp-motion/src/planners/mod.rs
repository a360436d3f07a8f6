//! Reference planners: [`RrtConnect`], [`Prm`] and [`IkRrt`].
//!
//! All three sample uniformly within the group's joint limits with a seeded `ChaCha8Rng`,
//! check segments discretely at [`PlanningProblem::step`](crate::PlanningProblem::step), and
//! find nearest neighbours by a linear scan over flat `Vec<f64>` storage (fast enough for the
//! thousands of nodes these problems need).

mod prm;
mod rrt;

pub use prm::{Prm, PrmOptions};
pub use rrt::{IkRrt, IkRrtOptions, RrtConnect, RrtConnectOptions};

/// Flat storage of configurations with a linear-scan nearest-neighbour query.
#[derive(Clone, Debug, Default)]
pub(crate) struct Nodes {
    pub dim: usize,
    pub data: Vec<f64>,
}

impl Nodes {
    pub fn new(dim: usize) -> Self {
        Self { dim, data: Vec::new() }
    }
    pub fn len(&self) -> usize {
        self.data.len() / self.dim.max(1)
    }
    pub fn get(&self, i: usize) -> &[f64] {
        &self.data[i * self.dim..(i + 1) * self.dim]
    }
    pub fn push(&mut self, q: &[f64]) -> usize {
        self.data.extend_from_slice(q);
        self.len() - 1
    }
    fn sq_dist(&self, i: usize, q: &[f64]) -> f64 {
        self.get(i).iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum()
    }
    /// Index of the nearest node (None if empty).
    pub fn nearest(&self, q: &[f64]) -> Option<usize> {
        let mut best = None;
        let mut best_d = f64::INFINITY;
        for i in 0..self.len() {
            let d = self.sq_dist(i, q);
            if d < best_d {
                best_d = d;
                best = Some(i);
            }
        }
        best
    }
    /// Up to `k` nearest nodes with their distances, closest first, skipping `exclude`.
    pub fn k_nearest(&self, q: &[f64], k: usize, exclude: Option<usize>) -> Vec<(usize, f64)> {
        let mut all: Vec<(usize, f64)> =
            (0..self.len()).filter(|&i| Some(i) != exclude).map(|i| (i, self.sq_dist(i, q))).collect();
        if all.len() > k {
            all.select_nth_unstable_by(k, |a, b| a.1.total_cmp(&b.1));
            all.truncate(k);
        }
        all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        for e in &mut all {
            e.1 = e.1.sqrt();
        }
        all
    }
}
