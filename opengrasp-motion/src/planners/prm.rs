//! PRM (Kavraki, Švestka, Latombe & Overmars 1996) with a roadmap reused across queries.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{NeighborStructure, Nodes};
use crate::error::{MotionError, Result};
use crate::problem::{Deadline, Goal, MotionPlanner, PlanningProblem, SetupContext, Solution};

use crate::validity::StateValidityChecker;

/// Options of [`Prm`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrmOptions {
    /// Valid samples in the roadmap built by `setup` (default 600).
    pub nodes: usize,
    /// Neighbours each sample (and each query configuration) tries to connect to (default 10).
    pub k: usize,
    /// Samples added per growth round when a query is not connected (default 100).
    pub growth: usize,
    /// For pose goals: valid IK solutions to connect to the roadmap (default 3).
    pub ik_goals: usize,
    /// For pose goals: maximum IK attempts (default 200).
    pub ik_attempts: usize,
}

impl Default for PrmOptions {
    fn default() -> Self {
        Self { nodes: 600, k: 10, growth: 100, ik_goals: 3, ik_attempts: 200 }
    }
}

/// Probabilistic roadmap: `setup` samples [`PrmOptions::nodes`] valid configurations and
/// connects each to its `k` nearest neighbours by valid straight segments (checked with
/// [`StateValidityChecker::is_motion_valid_between`] and the vertices'
/// [`StateValidityChecker::state_certificate`]s: the verdicts of
/// [`StateValidityChecker::is_motion_valid`], fewer state tests); each query connects
/// start and goals to the roadmap and runs Dijkstra. If they are not connected, the roadmap
/// grows by [`PrmOptions::growth`] samples per round until the time limit. The roadmap
/// (including growth) is kept for later queries in the same scene; calling `setup` again
/// rebuilds it.
#[derive(Clone, Debug, Default)]
pub struct Prm {
    /// Options.
    pub options: PrmOptions,
    /// Nearest-neighbour structure of the roadmap (default: kd-tree; same roadmap either way).
    pub neighbors: NeighborStructure,
    nodes: Nodes,
    edges: Vec<Vec<(usize, f64)>>,
    limits: Vec<(f64, f64)>,
}

impl Prm {
    /// A PRM planner with the given options (the roadmap is built by `setup`).
    pub fn new(options: PrmOptions) -> Self {
        Self { options, ..Self::default() }
    }

    /// Number of roadmap nodes.
    pub fn roadmap_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Number of (undirected) roadmap edges.
    pub fn roadmap_edges(&self) -> usize {
        self.edges.iter().map(Vec::len).sum::<usize>() / 2
    }

    /// The roadmap edges of `node` as `(neighbour, length)`, in the order they were added
    /// (empty for an unknown node).
    pub fn roadmap_neighbours(&self, node: usize) -> &[(usize, f64)] {
        self.edges.get(node).map_or(&[], Vec::as_slice)
    }

    /// A valid sample into `out`; with `cert`, checked by
    /// [`StateValidityChecker::state_certificate`] (same verdict), its certificate in `cert`.
    fn sample_valid(
        &self,
        checker: &dyn StateValidityChecker,
        rng: &mut ChaCha8Rng,
        out: &mut Vec<f64>,
        mut cert: Option<&mut Vec<f64>>,
    ) -> bool {
        use rand::Rng;
        for _ in 0..100 {
            out.clear();
            out.extend(self.limits.iter().map(|&(lo, hi)| lo + (hi - lo) * rng.random::<f64>()));
            let valid = match cert.as_deref_mut() {
                Some(c) => checker.state_certificate(out, c),
                None => checker.is_valid(out),
            };
            if valid {
                return true;
            }
        }
        false
    }

    /// Adds `q` and its valid edges to its k nearest nodes. With `certs` (one certificate per
    /// node, `q_cert` that of `q`), the edges are checked by
    /// [`StateValidityChecker::is_motion_valid_between`]: same edges, fewer state tests.
    fn add_node(
        &mut self,
        checker: &dyn StateValidityChecker,
        q: &[f64],
        step: f64,
        certs: Option<(&mut Vec<Vec<f64>>, Vec<f64>)>,
    ) -> Result<()> {
        let near = self.nodes.k_nearest(q, self.options.k)?;
        let i = self.nodes.push(q)?;
        self.edges.push(Vec::new());
        for (j, d) in near {
            let valid = match &certs {
                Some((all, q_cert)) => checker.is_motion_valid_between(self.nodes.get(j), &all[j], q, q_cert, step),
                None => checker.is_motion_valid(self.nodes.get(j), q, step),
            };
            if valid {
                self.edges[i].push((j, d));
                self.edges[j].push((i, d));
            }
        }
        if let Some((all, q_cert)) = certs {
            all.push(q_cert);
        }
        Ok(())
    }

    /// Adds up to `count` samples. `certs`: the certificates of every node so far (`setup`,
    /// which starts from an empty roadmap), kept up to date; queries grow without them, so
    /// that their checks are the one-by-one checks the benchmark counts.
    fn grow(
        &mut self,
        checker: &dyn StateValidityChecker,
        rng: &mut ChaCha8Rng,
        count: usize,
        step: f64,
        deadline: Option<&Deadline>,
        mut certs: Option<&mut Vec<Vec<f64>>>,
    ) -> Result<()> {
        let mut q = Vec::new();
        for _ in 0..count {
            if deadline.is_some_and(Deadline::expired) {
                break;
            }
            let mut q_cert = Vec::new();
            let with_cert = certs.is_some().then_some(&mut q_cert);
            if self.sample_valid(checker, rng, &mut q, with_cert) {
                let node_certs = certs.as_deref_mut().map(|all| (all, q_cert));
                self.add_node(checker, &q, step, node_certs)?;
            }
        }
        Ok(())
    }

    /// Valid connections `(node, cost)` from configuration `q` to its k nearest nodes.
    fn connections(&self, checker: &dyn StateValidityChecker, q: &[f64], step: f64) -> Result<Vec<(usize, f64)>> {
        let mut near = self.nodes.k_nearest(q, self.options.k)?;
        near.retain(|&(j, _)| checker.is_motion_valid(q, self.nodes.get(j), step));
        Ok(near)
    }

    /// Dijkstra from the start connections; returns (cost, goal index, node chain).
    fn search(&self, start: &[(usize, f64)], goals: &[Vec<(usize, f64)>]) -> Option<(usize, Vec<usize>)> {
        let n = self.nodes.len();
        let mut dist = vec![f64::INFINITY; n];
        let mut prev = vec![usize::MAX; n];
        let mut heap = BinaryHeap::new();
        for &(j, c) in start {
            if c < dist[j] {
                dist[j] = c;
                heap.push(State(c, j));
            }
        }
        while let Some(State(c, i)) = heap.pop() {
            if c > dist[i] {
                continue;
            }
            for &(j, w) in &self.edges[i] {
                let nc = c + w;
                if nc < dist[j] {
                    dist[j] = nc;
                    prev[j] = i;
                    heap.push(State(nc, j));
                }
            }
        }
        let mut best: Option<(f64, usize, usize)> = None;
        for (g, conns) in goals.iter().enumerate() {
            for &(j, c) in conns {
                let total = dist[j] + c;
                if total.is_finite() && best.is_none_or(|b| total < b.0) {
                    best = Some((total, g, j));
                }
            }
        }
        let (_, g, mut j) = best?;
        let mut chain = vec![j];
        while prev[j] != usize::MAX {
            j = prev[j];
            chain.push(j);
        }
        chain.reverse();
        Some((g, chain))
    }
}

#[derive(PartialEq)]
struct State(f64, usize);
impl Eq for State {}
impl PartialOrd for State {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for State {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl MotionPlanner for Prm {
    fn name(&self) -> &str {
        "PRM"
    }

    fn setup(&mut self, context: &SetupContext<'_>) -> Result<()> {
        if self.options.k == 0 {
            return Err(MotionError::InvalidParameter { name: "k", reason: "must be at least 1".into() });
        }
        self.limits = context.group.limits(context.robot);
        self.nodes = Nodes::new(self.neighbors, context.group.len());
        self.edges.clear();
        let mut rng = ChaCha8Rng::seed_from_u64(context.seed);
        let mut certs = Vec::with_capacity(self.options.nodes);
        self.grow(context.checker, &mut rng, self.options.nodes, context.step, None, Some(&mut certs))
    }

    fn plan(&mut self, problem: &PlanningProblem<'_>) -> Result<Solution> {
        problem.validate()?;
        if self.options.k == 0 {
            return Err(MotionError::InvalidParameter { name: "k", reason: "must be at least 1".into() });
        }
        let deadline = Deadline::after(problem.time_limit);
        let timeout = || MotionError::Timeout { seconds: problem.time_limit.as_secs_f64() };
        let mut rng = ChaCha8Rng::seed_from_u64(problem.seed);
        let checker = problem.checker;
        let step = problem.step;
        if self.nodes.dim() != problem.group.len() || self.limits.len() != problem.group.len() {
            // Not set up for this group: start an empty roadmap; growth fills it.
            self.limits = problem.limits();
            self.nodes = Nodes::new(self.neighbors, problem.group.len());
            self.edges.clear();
        }
        let mut iterations = 0;
        let goals: Vec<Vec<f64>> = match problem.goal {
            Goal::Configuration(q) => vec![q.clone()],
            Goal::ConfigurationSet(set) => set.iter().filter(|q| checker.is_valid(q)).cloned().collect(),
            Goal::Pose(_) => {
                let mut found = Vec::new();
                for _ in 0..self.options.ik_attempts {
                    if found.len() >= self.options.ik_goals || deadline.expired() {
                        break;
                    }
                    iterations += 1;
                    if let Some(g) = problem.sample_ik_goal(&mut rng, &self.limits) {
                        found.push(g);
                    }
                }
                found
            }
        };
        if goals.is_empty() {
            return Err(timeout());
        }
        for g in &goals {
            if checker.is_motion_valid(problem.start, g, step) {
                return Ok(Solution { path: vec![problem.start.to_vec(), g.clone()], iterations });
            }
        }
        loop {
            let start = self.connections(checker, problem.start, step)?;
            let goal_conns = goals.iter().map(|g| self.connections(checker, g, step)).collect::<Result<Vec<_>>>()?;
            if let Some((g, chain)) = self.search(&start, &goal_conns) {
                let mut path = vec![problem.start.to_vec()];
                path.extend(chain.iter().map(|&i| self.nodes.get(i).to_vec()));
                path.push(goals[g].clone());
                return Ok(Solution { path, iterations });
            }
            if deadline.expired() {
                return Err(timeout());
            }
            iterations += self.options.growth as u64;
            self.grow(checker, &mut rng, self.options.growth.max(1), step, Some(&deadline), None)?;
        }
    }
}
