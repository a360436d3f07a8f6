//! The kernels of [`SphereSoa`] over [`LANES`] states at once: sphere centres as
//! `[state lane]` arrays per sphere, each test computed for every lane with the lanes
//! innermost (loops the compiler vectorises), under a mask of the lanes still undecided.
//!
//! Every lane repeats the scalar kernels' arithmetic operation for operation and their culling
//! decisions test for test, so a lane's verdict is bit-identical to the scalar check of its
//! state; only which lanes share the work differs.

use super::super::chain::{Lanes, LANES};
use super::{box_distance, capsule_distance, cylinder_distance, sphere_distance, ObstacleFrame, SphereSoa};
use crate::validity::ObstacleShape;

/// One flag per lane.
pub(in crate::validity) type Mask = [bool; LANES];

/// True if some lane is set.
#[inline(always)]
pub(in crate::validity) fn any_lane(m: &Mask) -> bool {
    m.iter().any(|&b| b)
}

/// Lanes set in `a` and not in `b`.
#[inline(always)]
pub(in crate::validity) fn and_not(a: &Mask, b: &Mask) -> Mask {
    std::array::from_fn(|l| a[l] && !b[l])
}

/// Sphere centres of [`LANES`] states (see [`Centres`](super::Centres)).
#[derive(Debug, Default)]
pub(in crate::validity) struct LaneCentres {
    x: Vec<Lanes>,
    y: Vec<Lanes>,
    z: Vec<Lanes>,
    link: Vec<[Lanes; 3]>,
    cluster: Vec<[Lanes; 3]>,
    placed: Vec<bool>,
}

/// `m · (x, y, z)` in every lane (the scalar `transform`'s operations).
#[inline(always)]
fn transform_lanes(m: &[Lanes; 12], x: f64, y: f64, z: f64) -> [Lanes; 3] {
    let mut out = [[0.0; LANES]; 3];
    for (r, row) in out.iter_mut().enumerate() {
        for l in 0..LANES {
            row[l] = m[4 * r][l] * x + m[4 * r + 1][l] * y + m[4 * r + 2][l] * z + m[4 * r + 3][l];
        }
    }
    out
}

/// Per lane: `|a − b| − radii > 0` (the scalar `gap` test that culls).
#[inline(always)]
fn apart(a: &[Lanes; 3], b: &[Lanes; 3], radii: f64) -> Mask {
    std::array::from_fn(|l| {
        ((a[0][l] - b[0][l]).powi(2) + (a[1][l] - b[1][l]).powi(2) + (a[2][l] - b[2][l]).powi(2)).sqrt() - radii > 0.0
    })
}

impl ObstacleFrame {
    /// Per lane: signed distance from `(x, y, z)` to the obstacle
    /// ([`ObstacleFrame::signed_distance`] in every lane).
    #[inline(always)]
    fn distance_lanes(&self, x: &Lanes, y: &Lanes, z: &Lanes) -> Lanes {
        let mut d = [0.0; LANES];
        match self.shape {
            ObstacleShape::Box { half_extents: h } => {
                let h = [h.x, h.y, h.z];
                for l in 0..LANES {
                    d[l] = box_distance(self.local(x[l], y[l], z[l]), h);
                }
            }
            ObstacleShape::Sphere { radius } => {
                for l in 0..LANES {
                    d[l] = sphere_distance(&self.t, radius, x[l], y[l], z[l]);
                }
            }
            ObstacleShape::Cylinder { radius, half_length } => {
                for l in 0..LANES {
                    d[l] = cylinder_distance(self.local(x[l], y[l], z[l]), radius, half_length);
                }
            }
            ObstacleShape::Capsule { radius, half_length } => {
                for l in 0..LANES {
                    d[l] = capsule_distance(self.local(x[l], y[l], z[l]), radius, half_length);
                }
            }
        }
        d
    }
}

impl SphereSoa {
    /// [`SphereSoa::begin`] for [`LANES`] states: `frames[f][i][l]` as written by
    /// `Chain::frames_lanes`.
    pub fn begin_lanes(&self, frames: &[[Lanes; 12]], out: &mut LaneCentres) {
        let n = self.x.len();
        out.x.resize(n, [0.0; LANES]);
        out.y.resize(n, [0.0; LANES]);
        out.z.resize(n, [0.0; LANES]);
        out.link.clear();
        out.cluster.resize(self.clusters.len(), [[0.0; LANES]; 3]);
        out.placed.clear();
        out.placed.resize(self.ranges.len(), false);
        for (&f, lc) in self.frame.iter().zip(&self.link_centre) {
            out.link.push(transform_lanes(&frames[f], lc.x, lc.y, lc.z));
        }
    }

    /// Places link `k`'s spheres in every lane if not yet done.
    #[inline]
    fn ensure_lanes(&self, frames: &[[Lanes; 12]], out: &mut LaneCentres, k: usize) {
        if out.placed[k] {
            return;
        }
        out.placed[k] = true;
        let m = &frames[self.frame[k]];
        let (cs, ce) = self.link_clusters[k];
        for j in cs..ce {
            let c = &self.cluster_centre[j];
            out.cluster[j] = transform_lanes(m, c.x, c.y, c.z);
        }
        let (s, e) = self.ranges[k];
        for i in s..e {
            let [x, y, z] = transform_lanes(m, self.x[i], self.y[i], self.z[i]);
            (out.x[i], out.y[i], out.z[i]) = (x, y, z);
        }
    }

    /// Per lane: [`SphereSoa::link_near`].
    pub fn link_near_lanes(&self, o: usize, k: usize, c: &LaneCentres) -> Mask {
        let ob = &self.obstacles[o];
        let [lx, ly, lz] = &c.link[k];
        let reach = self.link_radius[k] + ob.bound;
        let d = ob.distance_lanes(lx, ly, lz);
        std::array::from_fn(|l| {
            let d2 = (lx[l] - ob.t[0]).powi(2) + (ly[l] - ob.t[1]).powi(2) + (lz[l] - ob.t[2]).powi(2);
            d2 <= reach * reach && d[l] <= self.link_radius[k]
        })
    }

    /// The lanes of `mask` in which some sphere of link `k` touches obstacle `o` (the
    /// negation of [`SphereSoa::link_clear`], clusters culled per lane the same way).
    pub fn link_hits_lanes(&self, o: usize, k: usize, frames: &[[Lanes; 12]], c: &mut LaneCentres, mask: Mask) -> Mask {
        let mut hits = [false; LANES];
        if !any_lane(&mask) {
            return hits;
        }
        self.ensure_lanes(frames, c, k);
        let ob = &self.obstacles[o];
        let (cs, ce) = self.link_clusters[k];
        for j in cs..ce {
            let [x, y, z] = &c.cluster[j];
            let d = ob.distance_lanes(x, y, z);
            // Culled exactly when the scalar kernel skips the cluster (`d > radius`).
            let culled: Mask = std::array::from_fn(|l| d[l] > self.cluster_radius[j]);
            let near = and_not(&and_not(&mask, &hits), &culled);
            if !any_lane(&near) {
                continue;
            }
            let (s, e) = self.clusters[j];
            let mut hit = [false; LANES];
            for i in s..e {
                let d = ob.distance_lanes(&c.x[i], &c.y[i], &c.z[i]);
                for l in 0..LANES {
                    hit[l] |= d[l] <= self.r[i];
                }
            }
            for l in 0..LANES {
                hits[l] |= near[l] && hit[l];
            }
        }
        hits
    }

    /// The lanes of `mask` in which some sphere of link `a` touches one of link `b` (the
    /// negation of [`SphereSoa::pair_clear`], culled per lane the same way).
    pub fn pair_hits_lanes(&self, frames: &[[Lanes; 12]], c: &mut LaneCentres, a: usize, b: usize, mask: Mask) -> Mask {
        let (ra, rb) = (self.link_radius[a], self.link_radius[b]);
        let far = apart(&c.link[a], &c.link[b], ra + rb);
        let near = and_not(&mask, &far);
        let mut hits = [false; LANES];
        if !any_lane(&near) {
            return hits;
        }
        self.ensure_lanes(frames, c, a);
        self.ensure_lanes(frames, c, b);
        let cb = c.link[b];
        let ((ca0, ca1), (cb0, cb1)) = (self.link_clusters[a], self.link_clusters[b]);
        for ja in ca0..ca1 {
            let (pa, qa) = (&c.cluster[ja], self.cluster_radius[ja]);
            let near_a = and_not(&and_not(&near, &hits), &apart(pa, &cb, qa + rb));
            if !any_lane(&near_a) {
                continue;
            }
            for jb in cb0..cb1 {
                let near_ab =
                    and_not(&and_not(&near_a, &hits), &apart(pa, &c.cluster[jb], qa + self.cluster_radius[jb]));
                if !any_lane(&near_ab) {
                    continue;
                }
                let ((sa, ea), (sb, eb)) = (self.clusters[ja], self.clusters[jb]);
                let mut hit = [false; LANES];
                for i in sa..ea {
                    let (x, y, z, r) = (&c.x[i], &c.y[i], &c.z[i], self.r[i]);
                    for j in sb..eb {
                        let (xs, ys, zs, rs) = (&c.x[j], &c.y[j], &c.z[j], self.r[j]);
                        for l in 0..LANES {
                            let d = ((xs[l] - x[l]).powi(2) + (ys[l] - y[l]).powi(2) + (zs[l] - z[l]).powi(2)).sqrt();
                            hit[l] |= d - r - rs <= 0.0;
                        }
                    }
                }
                for l in 0..LANES {
                    hits[l] |= near_ab[l] && hit[l];
                }
            }
        }
        hits
    }
}
