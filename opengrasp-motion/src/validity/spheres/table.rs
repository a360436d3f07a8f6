//! Conservative tables for self-collision pairs whose relative pose depends on at most two
//! joints (on the Panda: link 5 against link 7 and the hand, through joints 6 and 7).
//!
//! If link `b` rides on a chain frame reached from link `a`'s frame through one or two
//! revolute joints, the distance between their sphere sets is a function of those joints'
//! values alone. A [`PairTable`] holds per cell of a grid over those values a sound lower
//! bound of that distance over the whole cell, for the better of the two covers: at the cell
//! centre, each sphere pair's gap minus how far the sphere of `b` can move relative to `a`
//! within the cell. Moving the distal joint by `θ_v` then the proximal one by `θ_u` moves a
//! point by at most `θ_v ρ_v + θ_u ρ_u` (chords are shorter than arcs; rigid motions keep
//! distances), `ρ_v` its distance from the distal axis, `ρ_u` that of its position at the
//! centre's distal value from the proximal axis. A positive entry settles the pair's test
//! with that gap; other cells, and values outside the joint limits, fall back to the direct
//! test, so verdicts never change.
//!
//! A table is built on first use, adaptively: a block of cells whose bound is positive and
//! at least half its centre's gap gets that bound at once, a block in collision at every
//! point is left unknown, other blocks are split down to single cells.

use std::fmt;
use std::sync::OnceLock;

use nalgebra::Point3;
use opengrasp_core::kinematics::forward_kinematics_into;
use opengrasp_core::model::LinkId;

use super::super::chain::{compose, Chain, Mat34, IDENTITY};
use super::super::soa::SphereSoa;

/// Largest loss (m) of a cell's bound to the motion within it, from the spheres' largest
/// distances from the axes (the closest spheres usually lose much less): sets the grid.
const MARGIN: f64 = 2e-3;
/// Most cells per table.
const MAX_CELLS: usize = 1 << 20;
/// Absolute slack (m) against the rounding of the kinematics, as the certificates'.
const SLACK: f64 = 1e-9;

/// One revolute joint between the two links' frames.
#[derive(Clone, Debug, PartialEq)]
struct Step {
    frame: usize,
    dof: usize,
    axis: [f64; 3],
    /// `|scale|`: joint angle per unit of group value.
    scale: f64,
    lo: f64,
    width: f64,
    cells: usize,
}

/// Spheres of link `a` by cluster (bounding sphere `[x, y, z, r]`, members as arrays of
/// `x`, `y`, `z`, `r`) in `a`'s frame, and of link `b` by cluster (bounding sphere, members
/// `[x, y, z, r]`) in `b`'s frame, of one cover.
type Cover = (Vec<([f64; 4], [Vec<f64>; 4])>, Vec<([f64; 4], Vec<[f64; 4]>)>);

/// A conservative distance table of one link pair (see the module documentation).
pub(in crate::validity) struct PairTable {
    /// The joints from `a`'s frame to `b`'s, proximal first.
    steps: Vec<Step>,
    covers: Vec<Cover>,
    /// Everything the table depends on, to share it between worlds that agree.
    key: Vec<f64>,
    /// Per cell (first joint outermost), the lower bound minus slack, rounded down; `≤ 0`
    /// unknown.
    cells: OnceLock<Vec<f32>>,
}

impl fmt::Debug for PairTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PairTable").field("steps", &self.steps).field("built", &self.cells.get().is_some()).finish()
    }
}

impl PairTable {
    /// The table of links `a` and `b` (indices of `covers`' links), if one's chain frame is
    /// reached from the other's through one or two revolute joints driven by distinct group
    /// values with finite `limits`.
    pub fn new(chain: &Chain, covers: &[&SphereSoa], a: usize, b: usize, limits: &[(f64, f64)]) -> Option<Self> {
        let soa = covers.first()?;
        Self::oriented(chain, covers, a, b, limits)
            .or_else(|| (soa.frame_of(a) != soa.frame_of(b)).then(|| Self::oriented(chain, covers, b, a, limits))?)
    }

    /// [`PairTable::new`] with `b`'s frame below `a`'s.
    fn oriented(chain: &Chain, covers: &[&SphereSoa], a: usize, b: usize, limits: &[(f64, f64)]) -> Option<Self> {
        let (fa, mut f) = (covers[0].frame_of(a), covers[0].frame_of(b));
        let mut steps = Vec::new();
        while f != fa {
            if f == 0 || steps.len() == 2 {
                return None;
            }
            let (parent, dof, revolute) = chain.joint(f);
            let (axis, scale) = revolute?;
            // The kinematics rotate about unit axes; anything else is left to the direct test.
            if (norm(&axis) - 1.0).abs() > 1e-9 {
                return None;
            }
            let (lo, hi) = *limits.get(dof)?;
            if !(lo.is_finite() && hi.is_finite() && hi > lo && scale != 0.0) {
                return None;
            }
            steps.push(Step { frame: f, dof, axis, scale: scale.abs(), lo, width: hi - lo, cells: 1 });
            f = parent;
        }
        steps.reverse();
        if steps.is_empty() || steps.windows(2).any(|w| w[0].dof == w[1].dof) {
            return None;
        }
        let covers: Vec<Cover> = covers
            .iter()
            .map(|soa| {
                let clusters = soa
                    .link_clusters(a)
                    .into_iter()
                    .map(|(c, m)| (c, std::array::from_fn(|i| m.iter().map(|s| s[i]).collect())));
                (clusters.collect(), soa.link_clusters(b))
            })
            .collect();
        // Grid: each joint loses at most MARGIN / joints at the spheres' largest distances.
        let reach =
            covers.iter().flat_map(|c| &c.1).flat_map(|c| &c.1).map(|s| norm(&[s[0], s[1], s[2]])).fold(0.0, f64::max);
        let (mut offset, joints) = (0.0, steps.len() as f64);
        for s in steps.iter_mut().rev() {
            let rho = reach + offset;
            let width = 2.0 * MARGIN / (joints * rho.max(1e-9) * s.scale);
            s.cells = ((s.width / width).ceil() as usize).clamp(1, MAX_CELLS);
            offset += norm(&translation(&chain.local(s.frame, 0.0)));
        }
        while steps.iter().map(|s| s.cells).product::<usize>() > MAX_CELLS {
            for s in &mut steps {
                s.cells = s.cells.div_ceil(2);
            }
        }
        for s in &mut steps {
            s.width /= s.cells as f64;
        }
        let mut key = vec![a as f64, b as f64];
        for s in &steps {
            key.extend(chain.joint_key(s.frame).chain([s.dof as f64, s.lo, s.width, s.cells as f64]));
        }
        for (ca, cb) in &covers {
            key.extend(ca.iter().flat_map(|(c, m)| c.iter().chain(m.iter().flatten())));
            key.extend(cb.iter().flat_map(|(c, m)| c.iter().chain(m.iter().flatten())));
        }
        Some(Self { steps, covers, key, cells: OnceLock::new() })
    }

    /// True if both tables hold the same numbers (so either serves both worlds).
    pub fn same_as(&self, other: &Self) -> bool {
        self.key == other.key
    }

    /// Builds the table now if it is not built yet (it is built on first use otherwise).
    pub fn ensure_built(&self, chain: &Chain) {
        self.cells.get_or_init(|| self.build(chain));
    }

    /// The table's lower bound on the pair's sphere distance at group values `q`, if positive
    /// (the pair is clear); `None` if the table cannot tell.
    #[inline]
    pub fn gap(&self, chain: &Chain, q: &[f64]) -> Option<f64> {
        let cells = self.cells.get_or_init(|| self.build(chain));
        let mut index = 0;
        for s in &self.steps {
            // The upper limit itself is in the last cell (cells are inflated against rounding).
            let t = (q[s.dof] - s.lo) / s.width;
            if !(t >= 0.0 && t <= s.cells as f64) {
                return None;
            }
            index = index * s.cells + (t as usize).min(s.cells - 1);
        }
        let g = cells[index];
        (g > 0.0).then_some(f64::from(g))
    }

    fn build(&self, chain: &Chain) -> Vec<f32> {
        let total = self.steps.iter().map(|s| s.cells).product();
        let mut out = vec![f32::NEG_INFINITY; total];
        let lo = [0; 2];
        let hi = [self.steps[0].cells, self.steps.get(1).map_or(1, |s| s.cells)];
        self.fill(chain, &mut out, lo, hi);
        out
    }

    /// Fills the block of cells `[lo, hi)` (per joint; a second index of `0..1` for one joint).
    fn fill(&self, chain: &Chain, out: &mut [f32], lo: [usize; 2], hi: [usize; 2]) {
        let single = hi[0] - lo[0] == 1 && hi[1] - lo[1] == 1;
        let (lb, ub) = self.bounds(chain, lo, hi, single);
        if ub <= 0.0 {
            return;
        }
        if single || (lb > 0.0 && ub - lb <= 2.0 * lb) {
            let v = lb - SLACK;
            let mut g = v as f32;
            if f64::from(g) > v {
                g = g.next_down();
            }
            let inner = self.steps.get(1).map_or(1, |s| s.cells);
            for i in lo[0]..hi[0] {
                out[i * inner + lo[1]..i * inner + hi[1]].fill(g);
            }
            return;
        }
        let d = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
        let mid = (lo[d] + hi[d]) / 2;
        let (mut hi_a, mut lo_b) = (hi, lo);
        hi_a[d] = mid;
        lo_b[d] = mid;
        self.fill(chain, out, lo, hi_a);
        self.fill(chain, out, lo_b, hi);
    }

    /// Over the block `[lo, hi)`: a lower bound on the pair's sphere distance (of the better
    /// cover) at every point, and an upper bound (if `≤ 0`, every point is in collision).
    /// With `single` (one cell) a cover is left as soon as its lower bound is not positive,
    /// and the upper bound may be larger.
    fn bounds(&self, chain: &Chain, lo: [usize; 2], hi: [usize; 2], single: bool) -> (f64, f64) {
        // Per joint: value at the block centre, half angle (inflated against rounding).
        let mut poses = [IDENTITY; 2];
        let mut half = [0.0; 2];
        for (k, s) in self.steps.iter().enumerate() {
            let centre = s.lo + 0.5 * (lo[k] + hi[k]) as f64 * s.width;
            poses[k] = chain.local(s.frame, centre);
            half[k] = 0.5 * (hi[k] - lo[k]) as f64 * s.width * s.scale * (1.0 + 1e-6);
        }
        let (mut lb, mut ub) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        // The coarse cover (last) first: it alone often settles a block.
        for (clusters, b_clusters) in self.covers.iter().rev() {
            let (mut clb, mut cub) = (f64::INFINITY, f64::INFINITY);
            // A sphere of `b` within `extra` of `p` in `b`'s frame: where `p` is at the block
            // centre (in `a`'s frame), and how far such a sphere's centre moves in the block.
            let place = |p: &[f64; 4], extra: f64| {
                let (mut p, mut reach) = ([p[0], p[1], p[2]], 0.0);
                for (k, s) in self.steps.iter().enumerate().rev() {
                    reach += half[k] * (off_axis(&p, &s.axis) + extra);
                    p = apply(&poses[k], &p);
                }
                (p, reach * (1.0 + 1e-9) + 1e-12)
            };
            for (cb, spheres) in b_clusters {
                // A cluster pair whose bounding spheres cannot lower either bound is skipped
                // (the cluster's spheres move at most `reach` and lie within its sphere).
                let (p, reach) = place(cb, cb[3]);
                let near = |c: &[f64; 4]| {
                    let g = dist(&p, c) - c[3] - cb[3];
                    g - reach < clb || g < cub
                };
                if !clusters.iter().any(|(c, _)| near(c)) {
                    continue;
                }
                for sb in spheres {
                    let (p, reach) = place(sb, 0.0);
                    for (c, members) in clusters {
                        let g = dist(&p, c) - c[3] - sb[3];
                        if g - reach >= clb && g + reach >= cub {
                            continue;
                        }
                        let [xs, ys, zs, rs] = members;
                        let n = xs.len().min(ys.len()).min(zs.len()).min(rs.len());
                        // The least member gap, branch-free so it vectorises.
                        let g = (0..n).fold(f64::INFINITY, |acc, i| {
                            let v = ((xs[i] - p[0]).powi(2) + (ys[i] - p[1]).powi(2) + (zs[i] - p[2]).powi(2)).sqrt()
                                - rs[i];
                            if v < acc {
                                v
                            } else {
                                acc
                            }
                        }) - sb[3];
                        clb = clb.min(g - reach);
                        cub = cub.min(g + reach);
                    }
                }
                if single && clb <= 0.0 {
                    break;
                }
            }
            lb = lb.max(clb);
            ub = ub.max(cub);
            if lb > 0.0 && ub - lb <= 2.0 * lb {
                break;
            }
        }
        (lb, ub)
    }
}

fn translation(m: &Mat34) -> [f64; 3] {
    [m[3], m[7], m[11]]
}

fn norm(p: &[f64; 3]) -> f64 {
    (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
}

/// Distance from `p` to the point `c[..3]`.
fn dist(p: &[f64; 3], c: &[f64; 4]) -> f64 {
    norm(&[p[0] - c[0], p[1] - c[1], p[2] - c[2]])
}

/// Distance of `p` from the line through the origin along the unit vector `u`.
fn off_axis(p: &[f64; 3], u: &[f64; 3]) -> f64 {
    let along = p[0] * u[0] + p[1] * u[1] + p[2] * u[2];
    norm(&[p[0] - along * u[0], p[1] - along * u[1], p[2] - along * u[2]])
}

/// `m · p`.
fn apply(m: &Mat34, p: &[f64; 3]) -> [f64; 3] {
    let t = compose(m, &[1.0, 0.0, 0.0, p[0], 0.0, 1.0, 0.0, p[1], 0.0, 0.0, 1.0, p[2]]);
    translation(&t)
}

impl super::SphereWorld {
    /// This world settling the self-collision tests of link pairs whose relative pose depends
    /// on at most two joints from a conservative table over those joints' values first
    /// (`true`; see `validity/spheres/table.rs`): a table entry only ever passes a test whose
    /// sphere distance it bounds from below by a positive number, so the verdicts and counts
    /// are those without tables (`false`, the default of [`SphereWorld::new`](super::SphereWorld::new)). The tables
    /// are built here (about 0.5 s for the Panda's four wrist pairs, release build), so a
    /// timed plan never pays for them, and shared by the worlds of
    /// [`SphereWorld::for_problem`](super::SphereWorld::for_problem): they pay off for a
    /// model that checks many problems (a problem set), not for a world built per plan.
    pub fn with_pair_tables(mut self, tables: bool) -> Self {
        self.use_tables = tables;
        self.settle();
        for table in self.tables.iter().flatten() {
            table.ensure_built(&self.chain);
        }
        self
    }

    /// Number of link pairs settled by a table first.
    pub fn pair_table_count(&self) -> usize {
        self.tables.iter().flatten().count()
    }

    /// For each link pair with a table at group values `q`: the pair, its sphere distance
    /// (the larger of the two covers' with a coarse cover; from the robot's own forward
    /// kinematics) and the table's lower bound on it where the table settles the pair.
    pub fn pair_table_bounds(&self, q: &[f64]) -> Vec<(LinkId, LinkId, f64, Option<f64>)> {
        let mut poses = Vec::new();
        forward_kinematics_into(&self.robot, &self.full_configuration(q), &mut poses);
        let distance = |spheres: &[(usize, Point3<f64>, f64)], a: usize, b: usize| {
            let place = |k: usize, c: &Point3<f64>| self.base_pose * poses[self.links[k].0] * c;
            let (sa, sb) = (spheres.iter().filter(|s| s.0 == a), spheres.iter().filter(|s| s.0 == b));
            sa.flat_map(|x| sb.clone().map(move |y| (x, y)))
                .map(|(x, y)| (place(a, &x.1) - place(b, &y.1)).norm() - x.2 - y.2)
                .fold(f64::INFINITY, f64::min)
        };
        let coarse = self.coarse.as_ref().map(|(c, _)| c.spheres.as_slice());
        self.moving_pairs
            .iter()
            .enumerate()
            .filter(|&(p, _)| self.tables[p].is_some())
            .map(|(p, &(a, b))| {
                let d = distance(&self.spheres, a, b).max(coarse.map_or(f64::NEG_INFINITY, |c| distance(c, a, b)));
                (self.links[a], self.links[b], d, self.table_gap(p, q))
            })
            .collect()
    }

    /// The tables of `moving_pairs` (reusing this world's where they agree).
    pub(super) fn pair_tables(&self) -> Vec<Option<std::sync::Arc<PairTable>>> {
        if !self.use_tables {
            return vec![None; self.moving_pairs.len()];
        }
        let limits = self.group.limits(&self.robot);
        let mut covers = vec![&self.soa];
        covers.extend(self.coarse.as_ref().map(|(_, soa)| soa));
        self.moving_pairs
            .iter()
            .map(|&(a, b)| {
                let table = PairTable::new(&self.chain, &covers, a, b, &limits)?;
                let old = self.tables.iter().flatten().find(|t| t.same_as(&table)).cloned();
                Some(old.unwrap_or_else(|| std::sync::Arc::new(table)))
            })
            .collect()
    }

    /// The table's verdict on moving pair `p` at group values `q`: its gap if it settles it.
    #[inline]
    pub(super) fn table_gap(&self, p: usize, q: &[f64]) -> Option<f64> {
        self.tables.get(p)?.as_ref()?.gap(&self.chain, q)
    }
}
