//! Struct-of-arrays kernels of the sphere model: sphere centres placed per link, sphere-vs-box
//! and sphere-vs-sphere tests over contiguous `f64` arrays (loops the compiler vectorises),
//! each link culled first by its bounding sphere. No allocation per query: buffers live in a
//! per-thread scratch.

use nalgebra::{Isometry3, Point3};

use super::chain::Mat34;
use super::ObstacleShape;
use far::UprightSolids;

mod far;
mod lanes;
mod scratch;
#[cfg(test)]
mod tests;

pub(super) use lanes::{and_not, any_lane, LaneCentres, Mask};
pub(super) use scratch::{with_scratch, Centres, Scratch};

/// An obstacle in the form the kernels use: world-to-local rotation (row-major), centre and
/// the closed-form shape.
#[derive(Clone, Debug)]
pub(super) struct ObstacleFrame {
    r: [f64; 9],
    t: [f64; 3],
    shape: ObstacleShape,
    /// Radius of a sphere about `t` holding the obstacle (for culling).
    bound: f64,
    /// True if the rotation turns about the z axis only (`r[2]`, `r[5]`, `r[6]`, `r[7]` are
    /// zero, as for every MotionBenchMaker obstacle): see [`ObstacleFrame::local_in`].
    upright: bool,
}

impl ObstacleFrame {
    pub fn new(pose: &Isometry3<f64>, shape: ObstacleShape) -> Self {
        let m = pose.rotation.to_rotation_matrix();
        let m = m.matrix();
        // Rows of Rᵀ are the columns of R.
        let r = [m[(0, 0)], m[(1, 0)], m[(2, 0)], m[(0, 1)], m[(1, 1)], m[(2, 1)], m[(0, 2)], m[(1, 2)], m[(2, 2)]];
        let t = pose.translation.vector;
        let bound = match shape {
            ObstacleShape::Box { half_extents: h } => h.norm(),
            ObstacleShape::Sphere { radius } => radius,
            ObstacleShape::Cylinder { radius, half_length } => radius.hypot(half_length),
            ObstacleShape::Capsule { radius, half_length } => radius + half_length,
        };
        let upright = r[2] == 0.0 && r[5] == 0.0 && r[6] == 0.0 && r[7] == 0.0;
        Self { r, t: [t.x, t.y, t.z], shape, bound: bound * (1.0 + 1e-9) + 1e-12, upright }
    }

    /// `(x, y, z)` in the obstacle's frame.
    #[inline(always)]
    fn local(&self, x: f64, y: f64, z: f64) -> (f64, f64, f64) {
        self.local_in::<false>(x, y, z)
    }

    /// [`ObstacleFrame::local`], with `UPRIGHT` (only for an upright obstacle) dropping the
    /// products with the zero entries `r[2]`, `r[5]`, `r[6]`, `r[7]`. For finite coordinates
    /// each is ±0, and adding ±0 leaves a sum unchanged but for the sign of a zero, which no
    /// distance below depends on (`abs`, squares, `z − clamp(z)`): the same distances, bit
    /// for bit, with 4 multiplications and 4 additions fewer.
    #[inline(always)]
    fn local_in<const UPRIGHT: bool>(&self, x: f64, y: f64, z: f64) -> (f64, f64, f64) {
        let (px, py, pz) = (x - self.t[0], y - self.t[1], z - self.t[2]);
        let r = &self.r;
        if UPRIGHT {
            (r[0] * px + r[1] * py, r[3] * px + r[4] * py, r[8] * pz)
        } else {
            (r[0] * px + r[1] * py + r[2] * pz, r[3] * px + r[4] * py + r[5] * pz, r[6] * px + r[7] * py + r[8] * pz)
        }
    }

    /// Signed distance from `(x, y, z)` to the obstacle's surface (negative inside), exact.
    #[inline(always)]
    pub fn signed_distance(&self, x: f64, y: f64, z: f64) -> f64 {
        if self.upright {
            self.signed_distance_in::<true>(x, y, z)
        } else {
            self.signed_distance_in::<false>(x, y, z)
        }
    }

    #[inline(always)]
    fn signed_distance_in<const UPRIGHT: bool>(&self, x: f64, y: f64, z: f64) -> f64 {
        match self.shape {
            ObstacleShape::Box { half_extents: h } => box_distance(self.local_in::<UPRIGHT>(x, y, z), [h.x, h.y, h.z]),
            ObstacleShape::Sphere { radius } => sphere_distance(&self.t, radius, x, y, z),
            ObstacleShape::Cylinder { radius, half_length } => {
                cylinder_distance(self.local_in::<UPRIGHT>(x, y, z), radius, half_length)
            }
            ObstacleShape::Capsule { radius, half_length } => {
                capsule_distance(self.local_in::<UPRIGHT>(x, y, z), radius, half_length)
            }
        }
    }

    /// True if some sphere `(xs[i], ys[i], zs[i], rs[i])` touches the obstacle.
    fn any_hit(&self, xs: &[f64], ys: &[f64], zs: &[f64], rs: &[f64]) -> bool {
        self.min_gap(xs, ys, zs, rs) <= 0.0
    }

    /// The smallest `signed distance − radius` over the spheres `(xs[i], ys[i], zs[i], rs[i])`
    /// (∞ for none): at most zero exactly when one touches the obstacle (`d − r ≤ 0 ⇔ d ≤ r`
    /// in IEEE arithmetic). Branch-free per shape, so each loop vectorises.
    fn min_gap(&self, xs: &[f64], ys: &[f64], zs: &[f64], rs: &[f64]) -> f64 {
        if self.upright {
            self.min_gap_in::<true>(xs, ys, zs, rs)
        } else {
            self.min_gap_in::<false>(xs, ys, zs, rs)
        }
    }

    #[inline(always)]
    fn min_gap_in<const UPRIGHT: bool>(&self, xs: &[f64], ys: &[f64], zs: &[f64], rs: &[f64]) -> f64 {
        let n = xs.len().min(ys.len()).min(zs.len()).min(rs.len());
        let (xs, ys, zs, rs) = (&xs[..n], &ys[..n], &zs[..n], &rs[..n]);
        let local = |i: usize| self.local_in::<UPRIGHT>(xs[i], ys[i], zs[i]);
        match self.shape {
            ObstacleShape::Box { half_extents: h } => {
                let h = [h.x, h.y, h.z];
                least(n, |i| box_distance(local(i), h) - rs[i])
            }
            ObstacleShape::Sphere { radius } => {
                least(n, |i| sphere_distance(&self.t, radius, xs[i], ys[i], zs[i]) - rs[i])
            }
            ObstacleShape::Cylinder { radius, half_length } => {
                least(n, |i| cylinder_distance(local(i), radius, half_length) - rs[i])
            }
            ObstacleShape::Capsule { radius, half_length } => {
                least(n, |i| capsule_distance(local(i), radius, half_length) - rs[i])
            }
        }
    }
}

/// The smallest `f(i)` for `i < n` (∞ for none): a branch-free fold the compiler vectorises.
#[inline(always)]
fn least(n: usize, f: impl Fn(usize) -> f64) -> f64 {
    // `v < acc` rather than `f64::min`: one vector minimum (a NaN `v` is skipped either way).
    (0..n).fold(f64::INFINITY, |acc, i| {
        let v = f(i);
        if v < acc {
            v
        } else {
            acc
        }
    })
}

#[inline(always)]
fn box_distance((lx, ly, lz): (f64, f64, f64), h: [f64; 3]) -> f64 {
    let (dx, dy, dz) = (lx.abs() - h[0], ly.abs() - h[1], lz.abs() - h[2]);
    let (ox, oy, oz) = (dx.max(0.0), dy.max(0.0), dz.max(0.0));
    (ox * ox + oy * oy + oz * oz).sqrt() + dx.max(dy).max(dz).min(0.0)
}

#[inline(always)]
fn sphere_distance(t: &[f64; 3], radius: f64, x: f64, y: f64, z: f64) -> f64 {
    let (px, py, pz) = (x - t[0], y - t[1], z - t[2]);
    (px * px + py * py + pz * pz).sqrt() - radius
}

#[inline(always)]
fn cylinder_distance((lx, ly, lz): (f64, f64, f64), radius: f64, half_length: f64) -> f64 {
    let dr = (lx * lx + ly * ly).sqrt() - radius;
    let dz = lz.abs() - half_length;
    let (or, oz) = (dr.max(0.0), dz.max(0.0));
    (or * or + oz * oz).sqrt() + dr.max(dz).min(0.0)
}

#[inline(always)]
fn capsule_distance((lx, ly, lz): (f64, f64, f64), radius: f64, half_length: f64) -> f64 {
    let dz = lz - lz.clamp(-half_length, half_length);
    (lx * lx + ly * ly + dz * dz).sqrt() - radius
}

/// The spheres of a [`SphereWorld`](super::SphereWorld) as arrays, grouped by link, with one
/// bounding sphere per link and the boxes in kernel form.
#[derive(Clone, Debug)]
pub(super) struct SphereSoa {
    /// Centres in the frame of their link's [`Chain`](super::chain::Chain) frame, and radii.
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    r: Vec<f64>,
    /// Range of spheres of each link.
    ranges: Vec<(usize, usize)>,
    /// Clusters of at most [`CLUSTER`] nearby spheres of one link: range of spheres, bounding
    /// sphere (centre in the chain frame, radius); `link_clusters[k]` is link `k`'s range.
    clusters: Vec<(usize, usize)>,
    cluster_centre: Vec<Point3<f64>>,
    cluster_radius: Vec<f64>,
    link_clusters: Vec<(usize, usize)>,
    /// Chain frame of each link.
    frame: Vec<usize>,
    /// Bounding sphere of each link (centre in the link frame, radius).
    link_centre: Vec<Point3<f64>>,
    link_radius: Vec<f64>,
    obstacles: Vec<ObstacleFrame>,
    /// The obstacles' bounding-sphere centres and radii as arrays (for
    /// [`SphereSoa::far_obstacles`]).
    obstacle_x: Vec<f64>,
    obstacle_y: Vec<f64>,
    obstacle_z: Vec<f64>,
    obstacle_bound: Vec<f64>,
    /// The obstacles as upright boxes and cylinders, if every one is (for
    /// [`SphereSoa::far_obstacles`]).
    solids: Option<UprightSolids>,
}

impl SphereSoa {
    /// From `(link index, centre, radius)` triples grouped by link (`ranges`), each link's
    /// chain frame and pose in it (`links`), and the obstacles.
    pub fn new(
        spheres: &[(usize, Point3<f64>, f64)],
        ranges: &[(usize, usize)],
        links: &[(usize, Mat34)],
        obstacles: Vec<ObstacleFrame>,
    ) -> Self {
        let at = |k: usize, p: &Point3<f64>| {
            let m = &links[k].1;
            Point3::new(
                m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
                m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11],
            )
        };
        let mut spheres: Vec<(usize, Point3<f64>, f64)> = spheres.iter().map(|&(k, c, r)| (k, at(k, &c), r)).collect();
        let mut link_centre = Vec::with_capacity(ranges.len());
        let mut link_radius = Vec::with_capacity(ranges.len());
        let (mut clusters, mut link_clusters) = (Vec::new(), Vec::new());
        for &(s, e) in ranges {
            let (c, r) = bounding(&spheres[s..e]);
            link_centre.push(c);
            link_radius.push(r);
            let first = clusters.len();
            split(&mut spheres, s, e, &mut clusters);
            link_clusters.push((first, clusters.len()));
        }
        let (cluster_centre, cluster_radius) = clusters.iter().map(|&(s, e)| bounding(&spheres[s..e])).unzip();
        Self {
            x: spheres.iter().map(|s| s.1.x).collect(),
            y: spheres.iter().map(|s| s.1.y).collect(),
            z: spheres.iter().map(|s| s.1.z).collect(),
            r: spheres.iter().map(|s| s.2).collect(),
            ranges: ranges.to_vec(),
            clusters,
            cluster_centre,
            cluster_radius,
            link_clusters,
            frame: links.iter().map(|l| l.0).collect(),
            link_centre,
            link_radius,
            obstacle_x: obstacles.iter().map(|o| o.t[0]).collect(),
            obstacle_y: obstacles.iter().map(|o| o.t[1]).collect(),
            obstacle_z: obstacles.iter().map(|o| o.t[2]).collect(),
            obstacle_bound: obstacles.iter().map(|o| o.bound).collect(),
            solids: UprightSolids::new(&obstacles),
            obstacles,
        }
    }

    /// Starts a state: the links' bounding-sphere centres from the world poses of the chain
    /// frames; the spheres themselves are placed per link when a test first needs them.
    pub fn begin(&self, frames: &[Mat34], out: &mut Centres) {
        self.begin_lazy(out);
        let epoch = out.epoch;
        let links = self.frame.iter().zip(&self.link_centre).zip(&mut out.link).zip(&mut out.linked);
        for (((&f, lc), at), linked) in links {
            *at = transform(&frames[f], lc.x, lc.y, lc.z);
            *linked = epoch;
        }
    }

    /// Starts a state placing nothing yet, not even the links' bounding-sphere centres
    /// (placed when a test first needs them): for a cover whose tests are only
    /// [`SphereSoa::link_gap`] and [`SphereSoa::pair_gap`] (and their `_clear` forms), not
    /// [`SphereSoa::link_near`] or [`SphereSoa::link_far`].
    pub fn begin_lazy(&self, out: &mut Centres) {
        out.restart(self.x.len(), self.ranges.len(), self.clusters.len());
    }

    /// Link `k`'s bounding-sphere centre, placed if not yet done.
    #[inline(always)]
    fn link_at(&self, frames: &[Mat34], out: &mut Centres, k: usize) -> [f64; 3] {
        if out.linked[k] != out.epoch {
            out.linked[k] = out.epoch;
            let lc = &self.link_centre[k];
            out.link[k] = transform(&frames[self.frame[k]], lc.x, lc.y, lc.z);
        }
        out.link[k]
    }

    /// Places the bounding-sphere centres of link `k`'s clusters if not yet done.
    #[inline]
    fn ensure(&self, frames: &[Mat34], out: &mut Centres, k: usize) {
        if out.placed[k] == out.epoch {
            return;
        }
        out.placed[k] = out.epoch;
        let m = &frames[self.frame[k]];
        let (cs, ce) = self.link_clusters[k];
        for j in cs..ce {
            let c = &self.cluster_centre[j];
            out.cluster[j] = transform(m, c.x, c.y, c.z);
        }
    }

    /// Places the spheres of cluster `j` (of link `k`) if not yet done.
    #[inline]
    fn fill(&self, frames: &[Mat34], out: &mut Centres, k: usize, j: usize) {
        if out.filled[j] == out.epoch {
            return;
        }
        out.filled[j] = out.epoch;
        let (s, e) = self.clusters[j];
        let m = &frames[self.frame[k]];
        let (xs, ys, zs) = (&self.x[s..e], &self.y[s..e], &self.z[s..e]);
        let (ox, oy, oz) = (&mut out.x[s..e], &mut out.y[s..e], &mut out.z[s..e]);
        for i in 0..xs.len() {
            let (x, y, z) = (xs[i], ys[i], zs[i]);
            ox[i] = m[0] * x + m[1] * y + m[2] * z + m[3];
            oy[i] = m[4] * x + m[5] * y + m[6] * z + m[7];
            oz[i] = m[8] * x + m[9] * y + m[10] * z + m[11];
        }
    }

    /// Link `k`'s chain frame.
    pub fn frame_of(&self, k: usize) -> usize {
        self.frame[k]
    }

    /// Link `k`'s spheres in its chain frame by cluster: each cluster's bounding sphere and
    /// its spheres, as `[x, y, z, radius]`.
    pub fn link_clusters(&self, k: usize) -> Vec<([f64; 4], Vec<[f64; 4]>)> {
        let (cs, ce) = self.link_clusters[k];
        (cs..ce)
            .map(|j| {
                let c = self.cluster_centre[j];
                let (s, e) = self.clusters[j];
                (
                    [c.x, c.y, c.z, self.cluster_radius[j]],
                    (s..e).map(|i| [self.x[i], self.y[i], self.z[i], self.r[i]]).collect(),
                )
            })
            .collect()
    }

    /// The obstacles.
    pub fn obstacles(&self) -> &[ObstacleFrame] {
        &self.obstacles
    }

    /// True if no sphere touches an obstacle (signed distance of the centre > radius for all),
    /// each link culled by its bounding sphere against the obstacle's.
    /// Links on frame 0 (fixed in the world) are skipped: see
    /// [`SphereSoa::static_free_of_obstacles`].
    pub fn free_of_obstacles(&self, frames: &[Mat34], c: &mut Centres) -> bool {
        for o in 0..self.obstacles.len() {
            for k in 0..self.ranges.len() {
                if self.frame[k] != 0 && self.link_near(o, k, c) && !self.link_clear(o, k, frames, c) {
                    return false;
                }
            }
        }
        true
    }

    /// False if link `k`'s bounding sphere is clear of obstacle `o` (after
    /// [`SphereSoa::begin`]).
    #[inline]
    pub fn link_near(&self, o: usize, k: usize, c: &Centres) -> bool {
        debug_assert!(c.linked[k] == c.epoch, "link_near after begin_lazy");
        let o = &self.obstacles[o];
        let [lx, ly, lz] = c.link[k];
        let d2 = (lx - o.t[0]).powi(2) + (ly - o.t[1]).powi(2) + (lz - o.t[2]).powi(2);
        let reach = self.link_radius[k] + o.bound;
        d2 <= reach * reach && o.signed_distance(lx, ly, lz) <= self.link_radius[k]
    }

    /// True if no sphere of link `k` touches obstacle `o`, clusters culled first.
    pub fn link_clear(&self, o: usize, k: usize, frames: &[Mat34], c: &mut Centres) -> bool {
        self.link_gap(o, k, frames, c).is_some()
    }

    /// [`SphereSoa::link_clear`] with a lower bound: `None` if a sphere of link `k` touches
    /// obstacle `o`, else `Some(g)` with `0 ≤ g ≤` every sphere's distance to it (culled
    /// clusters give the gap of their bounding sphere).
    pub fn link_gap(&self, o: usize, k: usize, frames: &[Mat34], c: &mut Centres) -> Option<f64> {
        self.ensure(frames, c, k);
        let o = &self.obstacles[o];
        let (cs, ce) = self.link_clusters[k];
        let mut lb = f64::INFINITY;
        for j in cs..ce {
            let [x, y, z] = c.cluster[j];
            let d = o.signed_distance(x, y, z);
            if d > self.cluster_radius[j] {
                lb = lb.min(d - self.cluster_radius[j]);
                continue;
            }
            self.fill(frames, c, k, j);
            let (s, e) = self.clusters[j];
            let g = o.min_gap(&c.x[s..e], &c.y[s..e], &c.z[s..e], &self.r[s..e]);
            if g <= 0.0 {
                return None;
            }
            lb = lb.min(g);
        }
        Some(lb.max(0.0))
    }

    /// Link `k`'s bounding sphere against the obstacles `from..` (at most [`FAR_BATCH`] of
    /// them) at once, placing the link's centre if not yet done: the least gap (at least 0,
    /// ∞ for none) over the obstacles the bounding sphere clears, which is at most the
    /// distance of every sphere of the link to them, and the bit `o − from` set for each
    /// other obstacle `o` (whose spheres decide). An obstacle is cleared when the signed
    /// distance `d` of the centre exceeds the radius `r` (gap `d − r`): for upright boxes
    /// and cylinders computed for all in one branch-free loop ([`far`]), else after the
    /// obstacles' bounding spheres, which clear the far ones with the gap `|c − t| − (r +
    /// bound)` first.
    #[inline(always)]
    pub fn far_obstacles(&self, k: usize, frames: &[Mat34], c: &mut Centres, from: usize) -> (f64, u64) {
        let centre = self.link_at(frames, c, k);
        let radius = self.link_radius[k];
        let to = self.obstacles.len().min(from.saturating_add(FAR_BATCH));
        let from = from.min(to);
        let ts = [self.obstacle_x.as_slice(), &self.obstacle_y, &self.obstacle_z];
        if let Some(solids) = &self.solids {
            let (least, near) = solids.clear_of(centre, radius, ts, (from, to), &mut c.distances);
            return (least.max(0.0), near);
        }
        let [lx, ly, lz] = centre;
        let (xs, ys, zs, bs) = (&ts[0][from..to], &ts[1][from..to], &ts[2][from..to], &self.obstacle_bound[from..to]);
        let (mut least, mut near) = (f64::INFINITY, 0u64);
        for (i, (((&x, &y), &z), &b)) in xs.iter().zip(ys).zip(zs).zip(bs).enumerate() {
            let d2 = (lx - x).powi(2) + (ly - y).powi(2) + (lz - z).powi(2);
            let reach = radius + b;
            let far = d2 > reach * reach;
            let gap = d2.sqrt() - reach;
            least = if far && gap < least { gap } else { least };
            near |= u64::from(!far) << i;
        }
        // The obstacles whose bounding sphere is not clear: the link's centre against the
        // exact shape.
        let mut rest = near;
        while rest != 0 {
            let i = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let d = self.obstacles[from + i].signed_distance(lx, ly, lz);
            if d > radius {
                least = least.min(d - radius);
                near &= !(1u64 << i);
            }
        }
        (least.max(0.0), near)
    }

    /// True if links `a` and `b` ride on the same chain frame (their relative pose never
    /// changes).
    pub fn rigidly_attached(&self, a: usize, b: usize) -> bool {
        self.frame[a] == self.frame[b]
    }

    /// True if link `k` is fixed in the world (its spheres never move).
    pub fn is_static(&self, k: usize) -> bool {
        self.frame[k] == 0
    }

    /// True if no sphere of a link fixed in the world touches an obstacle (the part of
    /// [`SphereSoa::free_of_obstacles`] that never changes; their centres are stored in world
    /// coordinates).
    pub fn static_free_of_obstacles(&self) -> bool {
        self.obstacles.iter().all(|o| {
            self.ranges
                .iter()
                .enumerate()
                .filter(|&(k, _)| self.frame[k] == 0)
                .all(|(_, &(s, e))| !o.any_hit(&self.x[s..e], &self.y[s..e], &self.z[s..e], &self.r[s..e]))
        })
    }

    /// True if no sphere of link `a` touches one of link `b` (all gaps > 0); each sphere of
    /// `a` is culled first by `b`'s bounding sphere.
    pub fn pair_clear(&self, frames: &[Mat34], c: &mut Centres, a: usize, b: usize) -> bool {
        self.pair_gap(frames, c, a, b).is_some()
    }

    /// [`SphereSoa::pair_clear`] with a lower bound: `None` if a sphere of link `a` touches
    /// one of link `b`, else `Some(g)` with `0 ≤ g ≤` every sphere gap between them (culled
    /// links and clusters give the gap of their bounding spheres).
    pub fn pair_gap(&self, frames: &[Mat34], c: &mut Centres, a: usize, b: usize) -> Option<f64> {
        let (ca, cb) = (self.link_at(frames, c, a), self.link_at(frames, c, b));
        let (ra, rb) = (self.link_radius[a], self.link_radius[b]);
        let g = gap(&ca, &cb, ra + rb);
        if g > 0.0 {
            return Some(g);
        }
        self.ensure(frames, c, a);
        self.ensure(frames, c, b);
        let ((ca0, ca1), (cb0, cb1)) = (self.link_clusters[a], self.link_clusters[b]);
        let mut lb = f64::INFINITY;
        for ja in ca0..ca1 {
            let (pa, qa) = (c.cluster[ja], self.cluster_radius[ja]);
            let g = gap(&pa, &cb, qa + rb);
            if g > 0.0 {
                lb = lb.min(g);
                continue;
            }
            for jb in cb0..cb1 {
                let g = gap(&pa, &c.cluster[jb], qa + self.cluster_radius[jb]);
                if g > 0.0 {
                    lb = lb.min(g);
                    continue;
                }
                self.fill(frames, c, a, ja);
                self.fill(frames, c, b, jb);
                let ((sa, ea), (sb, eb)) = (self.clusters[ja], self.clusters[jb]);
                let (xs, ys, zs, rs) = (&c.x[sb..eb], &c.y[sb..eb], &c.z[sb..eb], &self.r[sb..eb]);
                let n = xs.len().min(ys.len()).min(zs.len()).min(rs.len());
                let (ax, ay, az, ar) = (&c.x[sa..ea], &c.y[sa..ea], &c.z[sa..ea], &self.r[sa..ea]);
                let (pb, qb) = (c.cluster[jb], self.cluster_radius[jb]);
                for (((&x, &y), &z), &r) in ax.iter().zip(ay).zip(az).zip(ar) {
                    // The sphere against cluster `jb`'s bounding sphere first.
                    let g = gap(&[x, y, z], &pb, r + qb);
                    if g > 0.0 {
                        lb = lb.min(g);
                        continue;
                    }
                    let g = least(n, |j| {
                        ((xs[j] - x).powi(2) + (ys[j] - y).powi(2) + (zs[j] - z).powi(2)).sqrt() - r - rs[j]
                    });
                    if g <= 0.0 {
                        return None;
                    }
                    lb = lb.min(g);
                }
            }
        }
        Some(lb)
    }
}

/// Most spheres per cluster.
const CLUSTER: usize = 8;

/// Most obstacles one [`SphereSoa::far_obstacles`] call tests (one bit each).
pub(super) const FAR_BATCH: usize = 64;

/// The sphere about the centroid of `spheres` holding them all, with a little slack: culling
/// must never skip a sphere the exact test would hit.
fn bounding(spheres: &[(usize, Point3<f64>, f64)]) -> (Point3<f64>, f64) {
    let n = spheres.len().max(1) as f64;
    let c = spheres.iter().fold(Point3::origin(), |acc, (_, c, _)| acc + c.coords / n);
    let r = spheres.iter().map(|(_, p, r)| (p - c).norm() + r).fold(0.0, f64::max);
    (c, r * (1.0 + 1e-9) + 1e-12)
}

/// Orders `spheres[s..e]` into clusters of at most [`CLUSTER`] by median splits along the
/// widest axis, appending their ranges to `out`.
fn split(spheres: &mut [(usize, Point3<f64>, f64)], s: usize, e: usize, out: &mut Vec<(usize, usize)>) {
    if e - s <= CLUSTER {
        if e > s {
            out.push((s, e));
        }
        return;
    }
    let part = &mut spheres[s..e];
    let lo = part.iter().fold(Point3::from([f64::INFINITY; 3]), |a, p| a.inf(&p.1));
    let hi = part.iter().fold(Point3::from([f64::NEG_INFINITY; 3]), |a, p| a.sup(&p.1));
    let axis = (hi - lo).imax();
    part.sort_by(|a, b| a.1[axis].total_cmp(&b.1[axis]));
    let mid = s + (e - s) / 2;
    split(spheres, s, mid, out);
    split(spheres, mid, e, out);
}

/// `|a − b| − radii`.
#[inline(always)]
fn gap(a: &[f64; 3], b: &[f64; 3], radii: f64) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt() - radii
}

/// `m · (x, y, z)`.
#[inline(always)]
fn transform(m: &Mat34, x: f64, y: f64, z: f64) -> [f64; 3] {
    [
        m[0] * x + m[1] * y + m[2] * z + m[3],
        m[4] * x + m[5] * y + m[6] * z + m[7],
        m[8] * x + m[9] * y + m[10] * z + m[11],
    ]
}
