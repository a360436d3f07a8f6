//! Nearest-neighbour structures over joint space, in the spirit of OMPL's `NearestNeighbors`:
//! [`NearestNeighbors`] (add, nearest, k nearest, within a radius), a linear scan
//! ([`LinearScan`], the reference) and a bucket kd-tree ([`KdTree`], the planners' default).
//!
//! The metric is the planners' one: the Euclidean norm over the group's joint values
//! ([`crate::validate::distance`]; joints are sampled within their limits, so there is no
//! wrap-around). Both structures return exactly the same answers, ties included: neighbours are
//! ordered by squared distance, then by index (the order of `add`), and the squared distance of
//! a point is computed the same way by both. The kd-tree prunes a subtree only when a lower
//! bound on its squared distances, computed with the same rounding, is strictly larger than the
//! current candidate's, so pruning never changes an answer.
//!
//! ```
//! use opengrasp_motion::nearest::{KdTree, NearestNeighbors};
//! # fn main() -> opengrasp_motion::Result<()> {
//! let mut nn = KdTree::new(2);
//! for q in [[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]] {
//!     nn.add(&q)?;
//! }
//! assert_eq!(nn.nearest(&[0.9, 0.1])?, Some(1));
//! let mut out = Vec::new();
//! nn.within_radius(&[0.0, 0.0], 1.0, &mut out)?;
//! assert_eq!(out, vec![(0, 0.0), (1, 1.0)]);
//! # Ok(())
//! # }
//! ```

use crate::error::{MotionError, Result};

/// Squared Euclidean distance, summed in joint order (the value both structures compare).
pub fn squared_distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

/// [`squared_distance`] of `a` and `b` if it is at most `bound`, else a value above `bound`:
/// the sum stops once it passes `bound` (its terms are not negative, so the rounded partial
/// sums never decrease and the full sum would pass it too). A point farther than the current
/// bound is refused by the collectors either way, so answers (ties included) are unchanged.
fn squared_distance_within(a: &[f64], b: &[f64], bound: f64) -> f64 {
    let mut sum = 0.0;
    for (x, y) in a.iter().zip(b) {
        sum += (x - y) * (x - y);
        if sum > bound {
            break;
        }
    }
    sum
}

/// A set of configurations answering nearest-neighbour queries. Points are numbered in the
/// order they were added, from 0. Results are ordered by distance, then by index.
pub trait NearestNeighbors: Send + Sync {
    /// Number of joint values per configuration.
    fn dim(&self) -> usize;
    /// Number of stored configurations.
    fn len(&self) -> usize;
    /// True if no configuration is stored.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The configuration with index `i`, if there is one.
    fn get(&self, i: usize) -> Option<&[f64]>;
    /// Removes every configuration (the dimension stays).
    fn clear(&mut self);
    /// Stores `q` and returns its index.
    ///
    /// # Errors
    /// [`MotionError::DimensionMismatch`] or [`MotionError::NonFinite`] for a bad `q`.
    fn add(&mut self, q: &[f64]) -> Result<usize>;
    /// Index of the configuration nearest to `q` (the lowest index among equally near
    /// ones), or `None` if the set is empty.
    ///
    /// # Errors
    /// As [`NearestNeighbors::add`] for a bad `q`.
    fn nearest(&self, q: &[f64]) -> Result<Option<usize>>;
    /// The `k` configurations nearest to `q` as `(index, distance)`, nearest first, into `out`
    /// (cleared first).
    ///
    /// # Errors
    /// As [`NearestNeighbors::add`] for a bad `q`.
    fn k_nearest(&self, q: &[f64], k: usize, out: &mut Vec<(usize, f64)>) -> Result<()>;
    /// Every configuration within distance `radius` of `q` (inclusive) as `(index, distance)`,
    /// nearest first, into `out` (cleared first).
    ///
    /// # Errors
    /// As [`NearestNeighbors::add`] for a bad `q`; [`MotionError::InvalidParameter`] if
    /// `radius` is negative or not finite.
    fn within_radius(&self, q: &[f64], radius: f64, out: &mut Vec<(usize, f64)>) -> Result<()>;
}

fn check_query(dim: usize, q: &[f64]) -> Result<()> {
    if q.len() != dim {
        return Err(MotionError::DimensionMismatch { expected: dim, actual: q.len() });
    }
    if q.iter().any(|v| !v.is_finite()) {
        return Err(MotionError::NonFinite { what: "nearest-neighbour query" });
    }
    Ok(())
}

fn check_radius(radius: f64) -> Result<f64> {
    if radius.is_finite() && radius >= 0.0 {
        Ok(radius * radius)
    } else {
        Err(MotionError::InvalidParameter {
            name: "radius", reason: format!("{radius} is not a finite distance ≥ 0")
        })
    }
}

/// `(a, i) < (b, j)` in the order of answers: squared distance, then index.
fn before(a: (f64, usize), b: (f64, usize)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1)
}

/// Sorts `(squared distance, index)` pairs into answers `(index, distance)`.
fn finish(found: &mut [(f64, usize)], out: &mut Vec<(usize, f64)>) {
    found.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    out.clear();
    out.extend(found.iter().map(|&(d, i)| (i, d.sqrt())));
}

/// Flat, row-major storage of configurations.
#[derive(Clone, Debug, Default)]
struct Points {
    dim: usize,
    data: Vec<f64>,
}

impl Points {
    fn len(&self) -> usize {
        self.data.len().checked_div(self.dim).unwrap_or(0)
    }
    fn row(&self, i: usize) -> &[f64] {
        &self.data[i * self.dim..(i + 1) * self.dim]
    }
    fn get(&self, i: usize) -> Option<&[f64]> {
        (i < self.len()).then(|| self.row(i))
    }
    fn push(&mut self, q: &[f64]) -> Result<usize> {
        check_query(self.dim, q)?;
        self.data.extend_from_slice(q);
        Ok(self.len() - 1)
    }
}

/// The `k` best `(squared distance, index)` pairs seen so far, sorted.
struct Best {
    k: usize,
    items: Vec<(f64, usize)>,
}

/// What a kd-tree search collects: candidates offered, and the squared distance a subtree
/// must not exceed to still matter.
trait Collect {
    fn offer(&mut self, d: f64, i: usize);
    fn bound(&self) -> f64;
}

/// The single best pair (the `k = 1` case of [`Best`], without allocation).
struct Nearest(Option<(f64, usize)>);

impl Collect for Nearest {
    fn offer(&mut self, d: f64, i: usize) {
        if self.0.is_none_or(|w| before((d, i), w)) {
            self.0 = Some((d, i));
        }
    }
    fn bound(&self) -> f64 {
        self.0.map_or(f64::INFINITY, |w| w.0)
    }
}

impl Collect for Best {
    fn offer(&mut self, d: f64, i: usize) {
        if self.items.len() == self.k && !self.items.last().is_some_and(|&w| before((d, i), w)) {
            return;
        }
        let at = self.items.partition_point(|&e| before(e, (d, i)));
        self.items.insert(at, (d, i));
        self.items.truncate(self.k);
    }
    fn bound(&self) -> f64 {
        if self.items.len() < self.k {
            f64::INFINITY
        } else {
            self.items.last().map_or(f64::INFINITY, |w| w.0)
        }
    }
}

/// The reference structure: every query scans all configurations.
#[derive(Clone, Debug, Default)]
pub struct LinearScan {
    points: Points,
}

impl LinearScan {
    /// An empty set of `dim`-dimensional configurations.
    pub fn new(dim: usize) -> Self {
        Self { points: Points { dim, data: Vec::new() } }
    }
}

impl NearestNeighbors for LinearScan {
    fn dim(&self) -> usize {
        self.points.dim
    }
    fn len(&self) -> usize {
        self.points.len()
    }
    fn get(&self, i: usize) -> Option<&[f64]> {
        self.points.get(i)
    }
    fn clear(&mut self) {
        self.points.data.clear();
    }
    fn add(&mut self, q: &[f64]) -> Result<usize> {
        self.points.push(q)
    }
    fn nearest(&self, q: &[f64]) -> Result<Option<usize>> {
        check_query(self.dim(), q)?;
        let mut best = None;
        let mut best_d = f64::INFINITY;
        for i in 0..self.len() {
            let d = squared_distance(self.points.row(i), q);
            if d < best_d || best.is_none() {
                best_d = d;
                best = Some(i);
            }
        }
        Ok(best)
    }
    fn k_nearest(&self, q: &[f64], k: usize, out: &mut Vec<(usize, f64)>) -> Result<()> {
        check_query(self.dim(), q)?;
        let mut all: Vec<(f64, usize)> =
            (0..self.len()).map(|i| (squared_distance(self.points.row(i), q), i)).collect();
        let order = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        if all.len() > k {
            if k > 0 {
                all.select_nth_unstable_by(k - 1, order);
            }
            all.truncate(k);
        }
        finish(&mut all, out);
        Ok(())
    }
    fn within_radius(&self, q: &[f64], radius: f64, out: &mut Vec<(usize, f64)>) -> Result<()> {
        check_query(self.dim(), q)?;
        let r2 = check_radius(radius)?;
        let mut found: Vec<(f64, usize)> =
            (0..self.len()).map(|i| (squared_distance(self.points.row(i), q), i)).filter(|&(d, _)| d <= r2).collect();
        finish(&mut found, out);
        Ok(())
    }
}

/// Points per leaf before it splits.
const BUCKET: usize = 16;

#[derive(Clone, Debug)]
enum KdNode {
    Leaf(Vec<usize>),
    /// Points with `q[axis] < value` are under `left`, the others under `right`.
    Split {
        axis: usize,
        value: f64,
        left: usize,
        right: usize,
    },
}

/// A bucket kd-tree grown by insertion: a leaf of more than 16 points splits at the median of
/// its widest axis. Exact answers, equal to [`LinearScan`]'s (see the module docs).
#[derive(Clone, Debug)]
pub struct KdTree {
    points: Points,
    nodes: Vec<KdNode>,
}

impl Default for KdTree {
    fn default() -> Self {
        Self::new(0)
    }
}

impl KdTree {
    /// An empty tree of `dim`-dimensional configurations.
    pub fn new(dim: usize) -> Self {
        Self { points: Points { dim, data: Vec::new() }, nodes: vec![KdNode::Leaf(Vec::new())] }
    }

    /// Depth of the deepest leaf (the root alone has depth 0).
    pub fn depth(&self) -> usize {
        fn walk(nodes: &[KdNode], n: usize) -> usize {
            match &nodes[n] {
                KdNode::Leaf(_) => 0,
                KdNode::Split { left, right, .. } => 1 + walk(nodes, *left).max(walk(nodes, *right)),
            }
        }
        walk(&self.nodes, 0)
    }

    /// Widest axis of `ids` and a split value leaving both sides non-empty (`None` if all
    /// points are equal).
    fn choose_split(&self, ids: &[usize]) -> Option<(usize, f64)> {
        let pts = &self.points;
        let spread = |a: usize| {
            let (lo, hi) = ids
                .iter()
                .map(|&i| pts.row(i)[a])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
            hi - lo
        };
        let axis = (0..pts.dim).max_by(|&a, &b| spread(a).total_cmp(&spread(b)).then(b.cmp(&a)))?;
        if spread(axis) <= 0.0 {
            return None;
        }
        let mut values: Vec<f64> = ids.iter().map(|&i| pts.row(i)[axis]).collect();
        values.sort_unstable_by(f64::total_cmp);
        let mut value = values[values.len() / 2];
        if value == values[0] {
            // Keep both sides non-empty: split just above the minimum.
            value = values.iter().copied().find(|&v| v > values[0])?;
        }
        Some((axis, value))
    }

    /// Makes node `slot` a balanced subtree over `ids`.
    fn build(&mut self, slot: usize, ids: Vec<usize>) {
        let split = if ids.len() > BUCKET { self.choose_split(&ids) } else { None };
        let Some((axis, value)) = split else {
            self.nodes[slot] = KdNode::Leaf(ids);
            return;
        };
        let (l, r): (Vec<usize>, Vec<usize>) = ids.iter().partition(|&&i| self.points.row(i)[axis] < value);
        let left = self.nodes.len();
        self.nodes.push(KdNode::Leaf(Vec::new()));
        self.nodes.push(KdNode::Leaf(Vec::new()));
        self.nodes[slot] = KdNode::Split { axis, value, left, right: left + 1 };
        self.build(left, l);
        self.build(left + 1, r);
    }

    /// Depth beyond which insertion rebuilds the whole tree (three times a balanced tree's
    /// depth, plus slack): keeps queries fast and the recursion shallow for any input order.
    fn max_depth(&self) -> usize {
        3 * (usize::BITS - (self.len() / BUCKET).leading_zeros()) as usize + 8
    }

    /// Visits the leaves whose region may hold a point within squared distance `bound()` of
    /// `q`, nearest region first; `off` holds the per-axis distances from `q` to the region and
    /// `rd` their squared sum, kept incrementally (the classic kd-tree "incremental distance").
    fn search(&self, n: usize, q: &[f64], off: &mut [f64], rd: f64, best: &mut impl Collect) {
        match &self.nodes[n] {
            KdNode::Leaf(ids) => {
                for &i in ids {
                    best.offer(squared_distance_within(self.points.row(i), q, best.bound()), i);
                }
            }
            &KdNode::Split { axis, value, left, right } => {
                let diff = q[axis] - value;
                let (near, far) = if diff < 0.0 { (left, right) } else { (right, left) };
                self.search(near, q, off, rd, best);
                let old = off[axis];
                off[axis] = diff.abs();
                let far_rd = rd - old * old + diff * diff;
                // The incremental sum only decides visits (visiting more never changes an
                // answer); a prune is confirmed by the bound summed in joint order like
                // `squared_distance`, each term no larger than the point's own term: a lower
                // bound, with rounding, on every point under `far`.
                let bound = best.bound();
                if far_rd <= bound || off.iter().map(|o| o * o).sum::<f64>() <= bound {
                    self.search(far, q, off, far_rd, best);
                }
                off[axis] = old;
            }
        }
    }

    fn query(&self, q: &[f64], k: usize) -> Best {
        let mut best = Best { k, items: Vec::with_capacity(k.min(64) + 1) };
        if k > 0 {
            let mut off = vec![0.0; self.points.dim];
            self.search(0, q, &mut off, 0.0, &mut best);
        }
        best
    }
}

impl NearestNeighbors for KdTree {
    fn dim(&self) -> usize {
        self.points.dim
    }
    fn len(&self) -> usize {
        self.points.len()
    }
    fn get(&self, i: usize) -> Option<&[f64]> {
        self.points.get(i)
    }
    fn clear(&mut self) {
        self.points.data.clear();
        self.nodes = vec![KdNode::Leaf(Vec::new())];
    }
    fn add(&mut self, q: &[f64]) -> Result<usize> {
        let i = self.points.push(q)?;
        let (mut n, mut depth) = (0, 0);
        while let KdNode::Split { axis, value, left, right } = self.nodes[n] {
            n = if q[axis] < value { left } else { right };
            depth += 1;
        }
        let KdNode::Leaf(ids) = &mut self.nodes[n] else { unreachable!("the descent ends at a leaf") };
        ids.push(i);
        if ids.len() > BUCKET {
            let ids = std::mem::take(ids);
            self.build(n, ids);
            if depth + 1 > self.max_depth() {
                self.nodes = vec![KdNode::Leaf(Vec::new())];
                self.build(0, (0..self.len()).collect());
            }
        }
        Ok(i)
    }
    fn nearest(&self, q: &[f64]) -> Result<Option<usize>> {
        check_query(self.dim(), q)?;
        // No allocation per query: the per-axis offsets live on the stack up to 32 axes.
        let mut best = Nearest(None);
        let dim = self.points.dim;
        let mut stack = [0.0; 32];
        let mut heap = Vec::new();
        let off = if dim <= stack.len() {
            &mut stack[..dim]
        } else {
            heap.resize(dim, 0.0);
            &mut heap[..]
        };
        self.search(0, q, off, 0.0, &mut best);
        Ok(best.0.map(|e| e.1))
    }
    fn k_nearest(&self, q: &[f64], k: usize, out: &mut Vec<(usize, f64)>) -> Result<()> {
        check_query(self.dim(), q)?;
        let k = k.min(self.len());
        finish(&mut self.query(q, k).items, out);
        Ok(())
    }
    fn within_radius(&self, q: &[f64], radius: f64, out: &mut Vec<(usize, f64)>) -> Result<()> {
        check_query(self.dim(), q)?;
        let r2 = check_radius(radius)?;
        let mut found = Vec::new();
        let mut off = vec![0.0; self.points.dim];
        self.within(0, q, r2, &mut off, &mut found);
        finish(&mut found, out);
        Ok(())
    }
}

impl KdTree {
    fn within(&self, n: usize, q: &[f64], r2: f64, off: &mut [f64], found: &mut Vec<(f64, usize)>) {
        match &self.nodes[n] {
            KdNode::Leaf(ids) => {
                found.extend(ids.iter().map(|&i| (squared_distance(self.points.row(i), q), i)).filter(|e| e.0 <= r2));
            }
            &KdNode::Split { axis, value, left, right } => {
                let diff = q[axis] - value;
                let (near, far) = if diff < 0.0 { (left, right) } else { (right, left) };
                self.within(near, q, r2, off, found);
                let old = off[axis];
                off[axis] = diff.abs();
                if off.iter().map(|o| o * o).sum::<f64>() <= r2 {
                    self.within(far, q, r2, off, found);
                }
                off[axis] = old;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{squared_distance, squared_distance_within, KdTree, LinearScan, NearestNeighbors};
    use proptest::prelude::*;

    #[test]
    fn stops_once_past_the_bound() {
        let (a, b) = ([0.0, 0.0, 0.0], [3.0, 4.0, 12.0]);
        assert_eq!(squared_distance_within(&a, &b, 169.0), 169.0);
        assert_eq!(squared_distance_within(&a, &b, f64::INFINITY), 169.0);
        // 9 + 16 = 25 passes 20: the sum stops before the last term.
        assert_eq!(squared_distance_within(&a, &b, 20.0), 25.0);
        assert_eq!(squared_distance_within(&a, &b, 0.0), 9.0);
    }

    proptest! {
        /// Ties under rounding: coordinates on a 0.1 grid (not exact in binary) with duplicates,
        /// queried at stored points and with the radius exactly a stored point's distance. The
        /// kd-tree's incrementally summed lower bound must prune exactly like the linear scan.
        #[test]
        fn kd_tree_keeps_rounded_ties(
            dim in 1usize..7,
            cells in prop::collection::vec(prop::collection::vec(-4i32..=4, 6), 1..400),
            pick in any::<prop::sample::Index>(),
            k in 1usize..30,
        ) {
            let points: Vec<Vec<f64>> = cells
                .iter()
                .map(|c| c[..dim].iter().map(|&v| f64::from(v) * 0.1).collect())
                .collect();
            let (mut kd, mut lin) = (KdTree::new(dim), LinearScan::new(dim));
            for p in &points {
                kd.add(p).unwrap();
                lin.add(p).unwrap();
            }
            let q: Vec<f64> = points[pick.index(points.len())].iter().map(|v| v + 0.05).collect();
            prop_assert_eq!(kd.nearest(&q).unwrap(), lin.nearest(&q).unwrap());
            let (mut a, mut b) = (Vec::new(), Vec::new());
            kd.k_nearest(&q, k, &mut a).unwrap();
            lin.k_nearest(&q, k, &mut b).unwrap();
            prop_assert_eq!(&a, &b);
            let r = squared_distance(&points[pick.index(points.len()) / 2], &q).sqrt();
            kd.within_radius(&q, r, &mut a).unwrap();
            lin.within_radius(&q, r, &mut b).unwrap();
            prop_assert_eq!(a, b);
        }

        /// At or above the full sum the result is the full sum to the bit; below it, a value
        /// above the bound (never at or below it, where a tie could be taken).
        #[test]
        fn within_agrees_with_the_full_sum(
            pairs in prop::collection::vec((-3.0f64..3.0, -3.0f64..3.0), 1..10),
            scale in 0.0f64..2.0,
        ) {
            let (a, b): (Vec<f64>, Vec<f64>) = pairs.into_iter().unzip();
            let full = squared_distance(&a, &b);
            prop_assert_eq!(squared_distance_within(&a, &b, full).to_bits(), full.to_bits());
            let bound = full * scale;
            let got = squared_distance_within(&a, &b, bound);
            if bound >= full {
                prop_assert_eq!(got.to_bits(), full.to_bits());
            } else {
                prop_assert!(got > bound && got <= full);
            }
        }
    }
}
