//! The broad phase of a link's obstacle test: which obstacles the link's bounding sphere
//! alone clears, and by how much, all obstacles at once.
//!
//! When every obstacle is an upright box or cylinder (turned about z only, as every
//! MotionBenchMaker obstacle is), the bounding sphere's centre is tested against the
//! obstacles' exact shapes in one branch-free loop over arrays: the signed distance `d` of
//! the centre, cleared when `d` exceeds the sphere's radius. Otherwise each obstacle's
//! bounding sphere goes first and the exact distance follows for those it does not clear.
//! Either way an obstacle is cleared exactly when the exact distance clears it (the
//! bounding spheres only skip work), with a gap that is at most every sphere's distance.

use super::{ObstacleFrame, FAR_BATCH};
use crate::validity::ObstacleShape;

/// The obstacles as arrays of upright boxes and cylinders (see the module documentation).
#[derive(Clone, Debug, Default)]
pub(super) struct UprightSolids {
    /// The world-to-local rotation entries of an upright frame (`r[0]`, `r[1]`, `r[3]`,
    /// `r[4]`, `r[8]` of [`ObstacleFrame`]).
    r0: Vec<f64>,
    r1: Vec<f64>,
    r3: Vec<f64>,
    r4: Vec<f64>,
    r8: Vec<f64>,
    /// Half extents; for a cylinder its radius, ∞ and its half length.
    hx: Vec<f64>,
    hy: Vec<f64>,
    hz: Vec<f64>,
    /// Whether each is a cylinder (its radial distance replaces the box's x distance), and
    /// whether any is.
    round: Vec<bool>,
    any_round: bool,
}

impl UprightSolids {
    /// The obstacles' arrays, if every one is an upright box or cylinder.
    pub fn new(obstacles: &[ObstacleFrame]) -> Option<Self> {
        let mut out = Self::default();
        for o in obstacles {
            let (h, round) = match o.shape {
                _ if !o.upright => return None,
                ObstacleShape::Box { half_extents: h } => ([h.x, h.y, h.z], false),
                ObstacleShape::Cylinder { radius, half_length } => ([radius, f64::INFINITY, half_length], true),
                ObstacleShape::Sphere { .. } | ObstacleShape::Capsule { .. } => return None,
            };
            for (v, x) in
                [&mut out.r0, &mut out.r1, &mut out.r3, &mut out.r4, &mut out.r8].into_iter().zip([0, 1, 3, 4, 8])
            {
                v.push(o.r[x]);
            }
            for (v, x) in [&mut out.hx, &mut out.hy, &mut out.hz].into_iter().zip(h) {
                v.push(x);
            }
            out.round.push(round);
            out.any_round |= round;
        }
        Some(out)
    }

    /// For the sphere `(x, y, z)`, `radius` against the obstacles `from..to` (centres `ts`,
    /// at most [`FAR_BATCH`]; `d` a buffer): the least `d − radius` over those whose signed distance `d` of
    /// the centre exceeds the radius (∞ for none), and the bit `o − from` set for every other
    /// obstacle `o`. The distances are [`ObstacleFrame::signed_distance`]'s, bit for bit (for
    /// a cylinder the box formula with its radial distance as `x` and `y` dropped: adding
    /// `0²` and taking the maximum with `−∞` change nothing).
    #[inline(always)]
    pub fn clear_of(
        &self,
        centre: [f64; 3],
        radius: f64,
        ts: [&[f64]; 3],
        (from, to): (usize, usize),
        d: &mut Vec<f64>,
    ) -> (f64, u64) {
        let n = to.saturating_sub(from).min(FAR_BATCH);
        // A reused buffer: clearing a fresh batch-sized one would cost more than the tests.
        d.resize(FAR_BATCH, 0.0);
        // The distances first, a loop over arrays that vectorises, then the decisions.
        if self.any_round {
            self.distances::<true>(centre, ts, from, &mut d[..n]);
        } else {
            self.distances::<false>(centre, ts, from, &mut d[..n]);
        }
        let (mut least, mut near) = (f64::INFINITY, 0u64);
        for (i, &d) in d[..n].iter().enumerate() {
            let clear = d > radius;
            let gap = d - radius;
            least = if clear && gap < least { gap } else { least };
            near |= u64::from(!clear) << i;
        }
        (least, near)
    }

    /// The signed distances of `centre` to the obstacles `from..from + out.len()` into `out`;
    /// `ROUND`: some may be cylinders.
    #[inline(always)]
    fn distances<const ROUND: bool>(&self, [x, y, z]: [f64; 3], ts: [&[f64]; 3], from: usize, out: &mut [f64]) {
        let n = out.len();
        let (tx, ty, tz) = (&ts[0][from..][..n], &ts[1][from..][..n], &ts[2][from..][..n]);
        let (r0, r1, r3) = (&self.r0[from..][..n], &self.r1[from..][..n], &self.r3[from..][..n]);
        let (r4, r8) = (&self.r4[from..][..n], &self.r8[from..][..n]);
        let (hx, hy, hz) = (&self.hx[from..][..n], &self.hy[from..][..n], &self.hz[from..][..n]);
        let round = &self.round[from..][..n];
        for i in 0..n {
            let (px, py, pz) = (x - tx[i], y - ty[i], z - tz[i]);
            let (lx, ly, lz) = (r0[i] * px + r1[i] * py, r3[i] * px + r4[i] * py, r8[i] * pz);
            let ax = if ROUND && round[i] { (lx * lx + ly * ly).sqrt() } else { lx.abs() };
            let (dx, dy, dz) = (ax - hx[i], ly.abs() - hy[i], lz.abs() - hz[i]);
            let (ox, oy, oz) = (dx.max(0.0), dy.max(0.0), dz.max(0.0));
            out[i] = (ox * ox + oy * oy + oz * oz).sqrt() + dx.max(dy).max(dz).min(0.0);
        }
    }
}
