//! Struct-of-arrays kernels of the sphere model: sphere centres placed per link, sphere-vs-box
//! and sphere-vs-sphere tests over contiguous `f64` arrays (loops the compiler vectorises),
//! each link culled first by its bounding sphere. No allocation per query: buffers live in a
//! per-thread scratch.

use std::cell::RefCell;

use nalgebra::{Isometry3, Point3};

use super::ObstacleBox;

/// A box in the form the kernels use: world-to-box rotation (row-major), centre, half extents.
#[derive(Clone, Debug)]
struct BoxFrame {
    r: [f64; 9],
    t: [f64; 3],
    h: [f64; 3],
}

impl BoxFrame {
    fn new(b: &ObstacleBox) -> Self {
        let m = b.pose.rotation.to_rotation_matrix();
        let m = m.matrix();
        // Rows of Rᵀ are the columns of R.
        let r = [m[(0, 0)], m[(1, 0)], m[(2, 0)], m[(0, 1)], m[(1, 1)], m[(2, 1)], m[(0, 2)], m[(1, 2)], m[(2, 2)]];
        let t = b.pose.translation.vector;
        Self { r, t: [t.x, t.y, t.z], h: [b.half_extents.x, b.half_extents.y, b.half_extents.z] }
    }

    /// Signed distance from `(x, y, z)` to the box surface (negative inside), as
    /// [`ObstacleBox::signed_distance`].
    #[inline(always)]
    fn signed_distance(&self, x: f64, y: f64, z: f64) -> f64 {
        let (px, py, pz) = (x - self.t[0], y - self.t[1], z - self.t[2]);
        let r = &self.r;
        let lx = r[0] * px + r[1] * py + r[2] * pz;
        let ly = r[3] * px + r[4] * py + r[5] * pz;
        let lz = r[6] * px + r[7] * py + r[8] * pz;
        let (dx, dy, dz) = (lx.abs() - self.h[0], ly.abs() - self.h[1], lz.abs() - self.h[2]);
        let (ox, oy, oz) = (dx.max(0.0), dy.max(0.0), dz.max(0.0));
        (ox * ox + oy * oy + oz * oz).sqrt() + dx.max(dy).max(dz).min(0.0)
    }
}

/// Sphere centres of one state, struct of arrays, plus each link's bounding-sphere centre.
#[derive(Debug, Default)]
pub(super) struct Centres {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    link: Vec<[f64; 3]>,
}

/// Per-thread buffers of the sphere model's state checks.
#[derive(Debug, Default)]
pub(super) struct Scratch {
    pub full: Vec<f64>,
    pub poses: Vec<Isometry3<f64>>,
    pub centres: Centres,
    pub q: Vec<f64>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Runs `f` with this thread's scratch (fresh buffers on re-entrance).
pub(super) fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut s) => f(&mut s),
        Err(_) => f(&mut Scratch::default()),
    })
}

/// The spheres of a [`SphereWorld`](super::SphereWorld) as arrays, grouped by link, with one
/// bounding sphere per link and the boxes in kernel form.
#[derive(Clone, Debug)]
pub(super) struct SphereSoa {
    /// Centres in the link frame, and radii.
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    r: Vec<f64>,
    /// Range of spheres of each link.
    ranges: Vec<(usize, usize)>,
    /// Bounding sphere of each link (centre in the link frame, radius).
    link_centre: Vec<Point3<f64>>,
    link_radius: Vec<f64>,
    boxes: Vec<BoxFrame>,
}

impl SphereSoa {
    /// From `(link index, centre, radius)` triples grouped by link (`ranges`) and the boxes.
    pub fn new(spheres: &[(usize, Point3<f64>, f64)], ranges: &[(usize, usize)], boxes: &[ObstacleBox]) -> Self {
        let mut link_centre = Vec::with_capacity(ranges.len());
        let mut link_radius = Vec::with_capacity(ranges.len());
        for &(s, e) in ranges {
            let n = (e - s).max(1) as f64;
            let c = spheres[s..e].iter().fold(Point3::origin(), |acc, (_, c, _)| acc + c.coords / n);
            let r = spheres[s..e].iter().map(|(_, p, r)| (p - c).norm() + r).fold(0.0, f64::max);
            link_centre.push(c);
            // A little slack: the culling must never skip a sphere the exact test would hit.
            link_radius.push(r * (1.0 + 1e-9) + 1e-12);
        }
        Self {
            x: spheres.iter().map(|s| s.1.x).collect(),
            y: spheres.iter().map(|s| s.1.y).collect(),
            z: spheres.iter().map(|s| s.1.z).collect(),
            r: spheres.iter().map(|s| s.2).collect(),
            ranges: ranges.to_vec(),
            link_centre,
            link_radius,
            boxes: boxes.iter().map(BoxFrame::new).collect(),
        }
    }

    /// Places the spheres with the world poses of the links (in `ranges` order).
    pub fn place(&self, link_poses: impl Iterator<Item = Isometry3<f64>>, out: &mut Centres) {
        let n = self.x.len();
        out.x.resize(n, 0.0);
        out.y.resize(n, 0.0);
        out.z.resize(n, 0.0);
        out.link.clear();
        for ((&(s, e), pose), lc) in self.ranges.iter().zip(link_poses).zip(&self.link_centre) {
            let m = pose.rotation.to_rotation_matrix();
            let m = m.matrix();
            let t = pose.translation.vector;
            let c = pose * lc;
            out.link.push([c.x, c.y, c.z]);
            let (xs, ys, zs) = (&self.x[s..e], &self.y[s..e], &self.z[s..e]);
            let (ox, oy, oz) = (&mut out.x[s..e], &mut out.y[s..e], &mut out.z[s..e]);
            for i in 0..xs.len() {
                let (x, y, z) = (xs[i], ys[i], zs[i]);
                ox[i] = m[(0, 0)] * x + m[(0, 1)] * y + m[(0, 2)] * z + t.x;
                oy[i] = m[(1, 0)] * x + m[(1, 1)] * y + m[(1, 2)] * z + t.y;
                oz[i] = m[(2, 0)] * x + m[(2, 1)] * y + m[(2, 2)] * z + t.z;
            }
        }
    }

    /// True if no sphere touches a box (signed distance of the centre > radius for all).
    pub fn free_of_boxes(&self, c: &Centres) -> bool {
        for b in &self.boxes {
            for (k, &(s, e)) in self.ranges.iter().enumerate() {
                let [lx, ly, lz] = c.link[k];
                if b.signed_distance(lx, ly, lz) > self.link_radius[k] {
                    continue;
                }
                let (xs, ys, zs, rs) = (&c.x[s..e], &c.y[s..e], &c.z[s..e], &self.r[s..e]);
                // Branch-free over the link's spheres, so the loop vectorises.
                let hit = (0..xs.len()).fold(false, |acc, i| acc | (b.signed_distance(xs[i], ys[i], zs[i]) <= rs[i]));
                if hit {
                    return false;
                }
            }
        }
        true
    }

    /// True if no sphere of link `a` touches one of link `b` (all gaps > 0).
    pub fn pair_clear(&self, c: &Centres, a: usize, b: usize) -> bool {
        let (ca, cb) = (c.link[a], c.link[b]);
        let d = ((ca[0] - cb[0]).powi(2) + (ca[1] - cb[1]).powi(2) + (ca[2] - cb[2]).powi(2)).sqrt();
        if d - self.link_radius[a] - self.link_radius[b] > 0.0 {
            return true;
        }
        let ((sa, ea), (sb, eb)) = (self.ranges[a], self.ranges[b]);
        for i in sa..ea {
            let (x, y, z, r) = (c.x[i], c.y[i], c.z[i], self.r[i]);
            let (xs, ys, zs, rs) = (&c.x[sb..eb], &c.y[sb..eb], &c.z[sb..eb], &self.r[sb..eb]);
            let hit = (0..xs.len()).fold(false, |acc, j| {
                let gap = ((xs[j] - x).powi(2) + (ys[j] - y).powi(2) + (zs[j] - z).powi(2)).sqrt() - r - rs[j];
                acc | (gap <= 0.0)
            });
            if hit {
                return false;
            }
        }
        true
    }
}
