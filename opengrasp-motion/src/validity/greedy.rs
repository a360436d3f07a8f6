//! Greedy sphere cover of a mesh surface by freely placed spheres with certified radii.
//!
//! The surface is cut into small triangle pieces. Candidate centres are the points of a grid
//! over the mesh's bounding box and the pieces' centroids; a candidate of depth `d` below the
//! surface (negative outside) may grow to radius `d + max_overhang`, and covers the pieces
//! whose three corners lie within that radius (a ball is convex, so it then holds the whole
//! piece). Greedy set cover picks the candidate covering the most uncovered pieces, and the
//! sphere's radius is set to the farthest corner of the pieces it newly covers, plus a
//! rounding margin. Every piece is covered (each centroid candidate can reach its own piece),
//! so every surface point lies in a sphere.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use nalgebra::{Point3, Vector3};
use opengrasp_core::model::TriangleMesh;

use super::cover::{closest_on_triangle, split_triangles, SphereCover};
use crate::error::{MotionError, Result};

/// Most candidate centres [`greedy_cover`] evaluates before refusing the grid spacing.
pub const MAX_CANDIDATES: usize = 1_000_000;

/// Options of [`greedy_cover`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GreedyCoverOptions {
    /// Longest edge of the surface pieces a sphere must contain whole (m; default 0.01).
    /// Smaller pieces let spheres fit tighter, at a higher build cost.
    pub piece: f64,
    /// Spacing of the grid of candidate centres (m; default 0.015).
    pub grid: f64,
    /// Overhang budget (m; default 0.01): a sphere whose centre lies `d` below the surface
    /// gets a radius of at most `d + max_overhang`, so it reaches at most `max_overhang`
    /// beyond the solid (for a closed mesh; see [`SphereCover::solid_overhang`]). Spheres
    /// centred on a piece may exceed it when a piece is wider than the budget.
    pub max_overhang: f64,
}

impl Default for GreedyCoverOptions {
    fn default() -> Self {
        Self { piece: 0.01, grid: 0.015, max_overhang: 0.01 }
    }
}

/// Signed depth of `p` below the surface of `mesh`: the distance to the surface, positive
/// inside (generalised winding number above one half), negative outside.
pub fn signed_depth(mesh: &TriangleMesh, p: &Point3<f64>) -> f64 {
    Triangles::new(mesh).signed_depth(&[p.x, p.y, p.z])
}

/// A mesh's triangles as plain arrays, for the depth queries of the cover's candidates.
struct Triangles(Vec<[[f64; 3]; 3]>);

impl Triangles {
    fn new(mesh: &TriangleMesh) -> Self {
        let v = mesh.vertices();
        let p = |i: u32| [v[i as usize].x, v[i as usize].y, v[i as usize].z];
        Self(mesh.triangles().iter().map(|t| [p(t[0]), p(t[1]), p(t[2])]).collect())
    }

    fn signed_depth(&self, p: &[f64; 3]) -> f64 {
        let mut dist2 = f64::INFINITY;
        let mut solid_angle = 0.0;
        for t in &self.0 {
            let (pa, pb, pc) = (p3(t[0]), p3(t[1]), p3(t[2]));
            let q = p3(*p);
            dist2 = dist2.min((closest_on_triangle(&q, &pa, &pb, &pc) - q).norm_squared());
            // Van Oosterom & Strackee: tan(Ω/2) = a·(b×c) / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|).
            let (x, y, z) = (sub(&t[0], p), sub(&t[1], p), sub(&t[2], p));
            let (lx, ly, lz) = (norm(&x), norm(&y), norm(&z));
            let cross = [y[1] * z[2] - y[2] * z[1], y[2] * z[0] - y[0] * z[2], y[0] * z[1] - y[1] * z[0]];
            let num = dot(&x, &cross);
            let den = lx * ly * lz + dot(&x, &y) * lz + dot(&x, &z) * ly + dot(&y, &z) * lx;
            solid_angle += 2.0 * num.atan2(den);
        }
        let winding = solid_angle / (4.0 * std::f64::consts::PI);
        let d = dist2.sqrt();
        if winding.abs() > 0.5 {
            d
        } else {
            -d
        }
    }
}

fn p3(a: [f64; 3]) -> Point3<f64> {
    Point3::new(a[0], a[1], a[2])
}
fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: &[f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

impl SphereCover {
    /// How far the cover reaches beyond the solid a closed `mesh` bounds: the largest
    /// `radius − depth(centre)` over the spheres (m), an upper bound on the distance from any
    /// point of a sphere to the solid (the ball of radius `depth` around an inner centre lies
    /// in the solid). For an open mesh the sign of the depth is meaningless; use
    /// [`SphereCover::overhang`].
    pub fn solid_overhang(&self, mesh: &TriangleMesh) -> f64 {
        self.spheres.iter().map(|(c, r)| r - signed_depth(mesh, c)).fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Covers every point of `mesh`'s surface with few spheres, each reaching about
/// `options.max_overhang` beyond the solid (see the module documentation of
/// [`cover`](super::cover) and [`GreedyCoverOptions`]).
///
/// # Errors
/// [`MotionError::InvalidParameter`] for a non-positive or non-finite `piece` or `grid`, a
/// negative or non-finite `max_overhang`, more than
/// [`MAX_COVER_PIECES`](super::cover::MAX_COVER_PIECES) pieces or more than
/// [`MAX_CANDIDATES`] grid points.
pub fn greedy_cover(mesh: &TriangleMesh, options: &GreedyCoverOptions) -> Result<SphereCover> {
    let GreedyCoverOptions { piece, grid, max_overhang } = *options;
    if !(max_overhang.is_finite() && max_overhang >= 0.0) {
        return Err(MotionError::InvalidParameter {
            name: "max_overhang",
            reason: format!("{max_overhang} is not a length ≥ 0"),
        });
    }
    if !(grid.is_finite() && grid > 0.0) {
        return Err(MotionError::InvalidParameter { name: "grid", reason: format!("{grid} is not a positive length") });
    }
    let pieces = split_triangles(mesh, piece, "piece", true)?;
    let (lo, hi) = mesh.aabb();
    let counts = (hi - lo).map(|e| (e / grid).floor() as usize + 1);
    let total = counts.x.saturating_mul(counts.y).saturating_mul(counts.z);
    if total > MAX_CANDIDATES {
        return Err(MotionError::InvalidParameter {
            name: "grid",
            reason: format!("{grid} m needs {total} candidate centres, more than {MAX_CANDIDATES}"),
        });
    }
    // Rounding margin, as the voxel cover's: relative to the coordinates' magnitude.
    let margin = 1e-9 * (lo.coords.amax().max(hi.coords.amax()).max(-lo.coords.min()) + piece);
    // Pieces as plain arrays, bucketed by centroid (candidates scan the buckets their ball's
    // box meets).
    let buckets = Buckets::new(pieces.iter().map(Piece::new).collect(), &lo, &hi, 2.0 * grid.max(piece));
    let tris = &buckets.pieces;
    // Candidates: (centre, largest allowed radius). Grid points inside or within the budget
    // of the surface, then the pieces' centroids (on the surface: depth 0).
    let mut candidates: Vec<([f64; 3], f64)> = Vec::new();
    let surface = Triangles::new(mesh);
    let offset = ((hi - lo) - (counts.map(|n| n as f64) - Vector3::repeat(1.0)) * grid) * 0.5;
    for i in 0..counts.x {
        for j in 0..counts.y {
            for k in 0..counts.z {
                let c = lo + offset + Vector3::new(i as f64, j as f64, k as f64) * grid;
                let r = surface.signed_depth(&[c.x, c.y, c.z]) + max_overhang;
                if r > 0.0 {
                    candidates.push(([c.x, c.y, c.z], r));
                }
            }
        }
    }
    candidates.extend(tris.iter().map(|t| (t.centre, max_overhang.max(t.reach))));
    // Which pieces each candidate holds whole.
    let holds: Vec<Vec<u32>> = candidates
        .iter()
        .map(|&(c, r)| {
            let mut held = Vec::new();
            buckets.near(&c, r, |p| {
                let t = &tris[p];
                let d = dist(&t.centre, &c);
                if d + t.reach <= r || (d - t.reach <= r && t.farthest(&c) <= r) {
                    held.push(p as u32);
                }
            });
            held
        })
        .collect();
    // Greedy set cover with exact gains: covering a piece lowers the gain of every candidate
    // holding it; stale heap entries are re-pushed with their current gain (ties: lowest index).
    let mut held_by: Vec<Vec<u32>> = vec![Vec::new(); tris.len()];
    for (k, h) in holds.iter().enumerate() {
        for &p in h {
            held_by[p as usize].push(k as u32);
        }
    }
    let mut gain: Vec<usize> = holds.iter().map(Vec::len).collect();
    let mut covered = vec![false; tris.len()];
    let mut left = tris.len();
    let mut heap: BinaryHeap<(usize, Reverse<usize>)> =
        gain.iter().enumerate().map(|(k, &g)| (g, Reverse(k))).collect();
    let mut spheres = Vec::new();
    while left > 0 {
        let Some((g, Reverse(k))) = heap.pop() else { break };
        if g != gain[k] {
            if gain[k] > 0 {
                heap.push((gain[k], Reverse(k)));
            }
            continue;
        }
        let c = candidates[k].0;
        let mut r: f64 = 0.0;
        for &p in &holds[k] {
            if !covered[p as usize] {
                covered[p as usize] = true;
                left -= 1;
                r = r.max(tris[p as usize].farthest(&c));
                for &j in &held_by[p as usize] {
                    gain[j as usize] -= 1;
                }
            }
        }
        spheres.push((Point3::new(c[0], c[1], c[2]), r * (1.0 + 1e-9) + margin));
    }
    debug_assert_eq!(left, 0, "every piece's centroid candidate holds it");
    Ok(SphereCover { spheres: drop_redundant(spheres, &buckets) })
}

/// Drops spheres (latest picked first) whose pieces all lie whole in other kept spheres.
fn drop_redundant(spheres: Vec<(Point3<f64>, f64)>, buckets: &Buckets) -> Vec<(Point3<f64>, f64)> {
    let holds: Vec<Vec<usize>> = spheres
        .iter()
        .map(|(c, r)| {
            let c = [c.x, c.y, c.z];
            let mut held = Vec::new();
            buckets.near(&c, *r, |p| {
                if buckets.pieces[p].farthest(&c) <= *r {
                    held.push(p);
                }
            });
            held
        })
        .collect();
    let mut count = vec![0usize; buckets.pieces.len()];
    for h in &holds {
        for &p in h {
            count[p] += 1;
        }
    }
    let mut keep = vec![true; spheres.len()];
    for k in (0..spheres.len()).rev() {
        if holds[k].iter().all(|&p| count[p] >= 2) {
            keep[k] = false;
            for &p in &holds[k] {
                count[p] -= 1;
            }
        }
    }
    spheres.into_iter().zip(keep).filter(|(_, k)| *k).map(|(s, _)| s).collect()
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    norm(&sub(a, b))
}

/// A surface piece: corners, centroid and the centroid's distance to the farthest corner.
struct Piece {
    corners: [[f64; 3]; 3],
    centre: [f64; 3],
    reach: f64,
}

impl Piece {
    fn new(t: &[Point3<f64>; 3]) -> Self {
        let corners = [[t[0].x, t[0].y, t[0].z], [t[1].x, t[1].y, t[1].z], [t[2].x, t[2].y, t[2].z]];
        let centre = [0, 1, 2].map(|i| (corners[0][i] + corners[1][i] + corners[2][i]) / 3.0);
        let mut piece = Self { corners, centre, reach: 0.0 };
        piece.reach = piece.farthest(&centre);
        piece
    }

    /// Distance from `c` to the farthest corner: the radius a ball about `c` needs to hold
    /// the piece (a ball is convex, the piece the hull of its corners).
    fn farthest(&self, c: &[f64; 3]) -> f64 {
        dist(&self.corners[0], c).max(dist(&self.corners[1], c)).max(dist(&self.corners[2], c))
    }
}

/// Pieces sorted into a uniform grid of buckets by centroid (compressed rows).
struct Buckets {
    pieces: Vec<Piece>,
    lo: [f64; 3],
    size: f64,
    dims: [usize; 3],
    /// `start[b]..start[b + 1]` are the pieces of bucket `b`.
    start: Vec<usize>,
}

impl Buckets {
    fn new(mut pieces: Vec<Piece>, lo: &Point3<f64>, hi: &Point3<f64>, size: f64) -> Self {
        let lo = [lo.x, lo.y, lo.z];
        let dims = [0, 1, 2].map(|i| ((hi[i] - lo[i]) / size).floor() as usize + 1);
        let mut this = Self { pieces: Vec::new(), lo, size, dims, start: Vec::new() };
        pieces.sort_by_key(|p| this.bucket(&p.centre));
        let mut start = vec![0; dims[0] * dims[1] * dims[2] + 1];
        for p in &pieces {
            start[this.bucket(&p.centre) + 1] += 1;
        }
        for b in 1..start.len() {
            start[b] += start[b - 1];
        }
        this.pieces = pieces;
        this.start = start;
        this
    }

    fn cell(&self, x: f64, i: usize) -> usize {
        (((x - self.lo[i]) / self.size).floor().max(0.0) as usize).min(self.dims[i] - 1)
    }

    fn bucket(&self, c: &[f64; 3]) -> usize {
        (self.cell(c[0], 0) * self.dims[1] + self.cell(c[1], 1)) * self.dims[2] + self.cell(c[2], 2)
    }

    /// Calls `f` with every piece whose centroid may lie within `r` of `c` (a superset: the
    /// buckets meeting the ball's box; a held piece's centroid lies in the ball).
    fn near(&self, c: &[f64; 3], r: f64, mut f: impl FnMut(usize)) {
        let lo = [0, 1, 2].map(|i| self.cell(c[i] - r, i));
        let hi = [0, 1, 2].map(|i| self.cell(c[i] + r, i));
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                let row = (i * self.dims[1] + j) * self.dims[2];
                for p in self.start[row + lo[2]]..self.start[row + hi[2] + 1] {
                    f(p);
                }
            }
        }
    }
}
