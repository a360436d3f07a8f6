//! Sphere covers of triangle meshes with a guaranteed bound: every point of the mesh surface
//! lies inside some sphere.
//!
//! - [`voxel_cover`]: one sphere per grid cell the surface touches, of radius half the cell
//!   diagonal (plus a rounding margin). No sphere reaches farther than `2√3 · cell` from the
//!   surface (a kept cell meets the bounding box of a surface piece no wider than `cell`), so
//!   the cover tightens with the cell size.
//! - [`adaptive_cover`]: the voxel cover with cells merged octree-wise into larger spheres
//!   wherever a larger sphere stays within a given overhang: far fewer spheres, same guarantee.
//! - [`greedy_cover`]: spheres placed freely (centres on a grid inside the mesh or on the
//!   surface), chosen by greedy set cover of small surface pieces, each radius certified as
//!   the farthest corner of the pieces it covers: the fewest spheres for an overhang budget.
//! - [`bounding_box_cover`]: the cover [`SphereWorld`](super::SphereWorld) uses for meshes: a
//!   grid of spheres over the mesh's bounding box (cells as wide as its thinnest side).
//!   Guaranteed as well, but it fills the whole box.
//!
//! [`SphereCover::overhang`] measures how far a cover reaches beyond the surface.

use std::collections::BTreeSet;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::model::TriangleMesh;

use crate::error::{MotionError, Result};

pub use super::greedy::{greedy_cover, signed_depth, GreedyCoverOptions, MAX_CANDIDATES};

/// Most sub-triangles [`voxel_cover`] generates before refusing the cell size.
pub const MAX_COVER_PIECES: usize = 4_000_000;

/// Spheres `(centre, radius)` in the mesh frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SphereCover {
    /// The spheres.
    pub spheres: Vec<(Point3<f64>, f64)>,
}

impl SphereCover {
    /// Whether `p` lies in some sphere.
    pub fn contains(&self, p: &Point3<f64>) -> bool {
        self.spheres.iter().any(|(c, r)| (p - c).norm_squared() <= r * r)
    }

    /// An upper bound on how far the cover reaches beyond `mesh`: the largest
    /// `distance(centre, surface) + radius` over the spheres (m).
    pub fn overhang(&self, mesh: &TriangleMesh) -> f64 {
        self.spheres.iter().map(|(c, r)| surface_distance(mesh, c) + r).fold(0.0, f64::max)
    }
}

/// Distance from `p` to the surface of `mesh` (closest point on each triangle, Ericson,
/// *Real-Time Collision Detection*, 5.1.5).
pub fn surface_distance(mesh: &TriangleMesh, p: &Point3<f64>) -> f64 {
    let v = mesh.vertices();
    mesh.triangles()
        .iter()
        .map(|t| (closest_on_triangle(p, &v[t[0] as usize], &v[t[1] as usize], &v[t[2] as usize]) - p).norm())
        .fold(f64::INFINITY, f64::min)
}

pub(super) fn closest_on_triangle(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> Point3<f64> {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Covers every point of `mesh`'s surface by spheres centred on the cells of a grid of edge
/// `cell` (m) that the surface touches, each of radius `√3/2 · cell` plus a rounding margin.
///
/// Each triangle is split at its edge midpoints until no edge is longer than `cell`; every
/// cell a piece's bounding box overlaps is kept (a superset of the touched cells, so the
/// bound holds with floating-point rounding).
///
/// # Errors
/// [`MotionError::InvalidParameter`] if `cell` is not a positive finite length or would need
/// more than [`MAX_COVER_PIECES`] triangle pieces.
pub fn voxel_cover(mesh: &TriangleMesh, cell: f64) -> Result<SphereCover> {
    let grid = Grid::new(mesh, cell)?;
    let spheres = grid.cells.iter().map(|&c| (grid.centre(c, 0), grid.radius(0))).collect();
    Ok(SphereCover { spheres })
}

/// Like [`voxel_cover`], but merges cells octree-wise into larger spheres wherever the
/// larger sphere reaches at most `max_overhang` (m) past the surface (measured exactly:
/// distance from its centre to the surface plus its radius). Every surface point stays
/// covered; the overhang is at most `max_overhang.max(2√3 · cell)`.
///
/// # Errors
/// As [`voxel_cover`]; [`MotionError::InvalidParameter`] for a negative or non-finite
/// `max_overhang`.
pub fn adaptive_cover(mesh: &TriangleMesh, cell: f64, max_overhang: f64) -> Result<SphereCover> {
    if !(max_overhang.is_finite() && max_overhang >= 0.0) {
        return Err(MotionError::InvalidParameter {
            name: "max_overhang",
            reason: format!("{max_overhang} is not a length ≥ 0"),
        });
    }
    let grid = Grid::new(mesh, cell)?;
    // Occupied cells per level: level `l` cells are 2^l fine cells wide.
    let extent = grid.cells.iter().map(|c| c.0.max(c.1).max(c.2)).max().unwrap_or(0).max(1);
    let top = (u64::BITS - (extent as u64).leading_zeros()) as usize;
    let mut levels = vec![grid.cells.clone()];
    for l in 1..=top {
        levels.push(levels[l - 1].iter().map(|&(i, j, k)| (i >> 1, j >> 1, k >> 1)).collect());
    }
    let mut spheres = Vec::new();
    let mut stack: Vec<(usize, Cell)> = levels[top].iter().map(|&c| (top, c)).collect();
    while let Some((l, c)) = stack.pop() {
        let (centre, r) = (grid.centre(c, l), grid.radius(l));
        if l == 0 || surface_distance(mesh, &centre) + r <= max_overhang {
            spheres.push((centre, r));
            continue;
        }
        for d in 0..8 {
            let child = (2 * c.0 + (d & 1), 2 * c.1 + ((d >> 1) & 1), 2 * c.2 + ((d >> 2) & 1));
            if levels[l - 1].contains(&child) {
                stack.push((l - 1, child));
            }
        }
    }
    Ok(SphereCover { spheres })
}

/// The triangles of `mesh`, each split at its edge midpoints until no edge is longer than
/// `max_edge` (m): pieces whose union is the surface (up to rounding of the midpoints).
/// `bisect`: split only the longest edge each time (two pieces; far fewer pieces for long,
/// thin triangles) instead of all three (four pieces).
///
/// # Errors
/// [`MotionError::InvalidParameter`] (named `name`) if `max_edge` is not a positive finite
/// length or would need more than [`MAX_COVER_PIECES`] pieces.
pub(super) fn split_triangles(
    mesh: &TriangleMesh,
    max_edge: f64,
    name: &'static str,
    bisect: bool,
) -> Result<Vec<[Point3<f64>; 3]>> {
    let invalid = |reason: String| MotionError::InvalidParameter { name, reason };
    if !(max_edge.is_finite() && max_edge > 0.0) {
        return Err(invalid(format!("{max_edge} is not a positive length")));
    }
    let v = mesh.vertices();
    let edges = |t: &[Point3<f64>; 3]| [(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()];
    let longest = |t: &[Point3<f64>; 3]| edges(t).into_iter().fold(0.0, f64::max);
    let tris: Vec<[Point3<f64>; 3]> =
        mesh.triangles().iter().map(|t| [v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]]).collect();
    // Four-way splitting halves every edge per level: an upper bound on the count.
    let mut pieces = 0usize;
    for t in &tris {
        let levels = (longest(t) / max_edge).log2().ceil().max(0.0);
        pieces = pieces.saturating_add(4usize.saturating_pow(levels.min(31.0) as u32));
    }
    if bisect {
        // Bisection leaves pieces of about a quarter of `max_edge`² each or more.
        pieces = (4.0 * mesh.surface_area() / (max_edge * max_edge)).min(usize::MAX as f64) as usize;
    }
    if pieces > MAX_COVER_PIECES {
        return Err(invalid(format!("{max_edge} m needs {pieces} triangle pieces, more than {MAX_COVER_PIECES}")));
    }
    let mut out = Vec::new();
    let mut stack = tris;
    while let Some(t) = stack.pop() {
        let e = edges(&t);
        if e.iter().all(|&l| l <= max_edge) {
            out.push(t);
            if out.len() > MAX_COVER_PIECES {
                return Err(invalid(format!("{max_edge} m needs more than {MAX_COVER_PIECES} triangle pieces")));
            }
        } else if bisect {
            // Split the longest edge (i, i + 1) at its midpoint.
            let i = if e[0] >= e[1] && e[0] >= e[2] {
                0
            } else if e[1] >= e[2] {
                1
            } else {
                2
            };
            let (a, b, c) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
            let m = nalgebra::center(&a, &b);
            stack.extend([[a, m, c], [m, b, c]]);
        } else {
            let m = [nalgebra::center(&t[0], &t[1]), nalgebra::center(&t[1], &t[2]), nalgebra::center(&t[2], &t[0])];
            stack.extend([[t[0], m[0], m[2]], [m[0], t[1], m[1]], [m[2], m[1], t[2]], m]);
        }
    }
    Ok(out)
}

type Cell = (i64, i64, i64);

/// The cells of edge `cell` from the mesh's bounding-box minimum that its surface touches
/// (a superset: cells meeting the bounding box of a surface piece no wider than a cell).
struct Grid {
    origin: Point3<f64>,
    cell: f64,
    margin: f64,
    cells: BTreeSet<Cell>,
}

impl Grid {
    fn new(mesh: &TriangleMesh, cell: f64) -> Result<Self> {
        let pieces = split_triangles(mesh, cell, "cell", false)?;
        let (lo, hi) = mesh.aabb();
        let index = |x: f64, o: f64| ((x - o) / cell).floor() as i64;
        let mut cells = BTreeSet::new();
        for t in &pieces {
            let a = t[0].coords.inf(&t[1].coords).inf(&t[2].coords);
            let b = t[0].coords.sup(&t[1].coords).sup(&t[2].coords);
            for i in index(a.x, lo.x).max(0)..=index(b.x, lo.x) {
                for j in index(a.y, lo.y).max(0)..=index(b.y, lo.y) {
                    for k in index(a.z, lo.z).max(0)..=index(b.z, lo.z) {
                        cells.insert((i, j, k));
                    }
                }
            }
        }
        let margin = 1e-9 * (lo.coords.amax().max(hi.coords.amax()) + cell);
        Ok(Self { origin: lo, cell, margin, cells })
    }

    /// Centre of cell `c` of level `l` (2^l fine cells wide).
    fn centre(&self, c: Cell, l: usize) -> Point3<f64> {
        let w = self.cell * (1u64 << l) as f64;
        self.origin + Vector3::new(c.0 as f64 + 0.5, c.1 as f64 + 0.5, c.2 as f64 + 0.5) * w
    }

    /// Radius of the sphere through the corners of a level-`l` cell, plus the rounding margin.
    fn radius(&self, l: usize) -> f64 {
        self.cell * (1u64 << l) as f64 * 0.5 * 3f64.sqrt() + self.margin
    }
}

/// The bounding-box grid cover [`SphereWorld`](super::SphereWorld) uses for meshes.
pub fn bounding_box_cover(mesh: &TriangleMesh) -> SphereCover {
    let (lo, hi) = mesh.aabb();
    let centre = nalgebra::center(&lo, &hi);
    let mut spheres = Vec::new();
    cover_box(&((hi - lo) * 0.5), &Isometry3::translation(centre.x, centre.y, centre.z), &mut spheres);
    SphereCover { spheres }
}

/// Balls covering the side of a solid cylinder of `radius` whose axis runs along the local z
/// axis of `origin` over `[-length/2, length/2]`: the axis cut into `n` slices of height
/// `s = length / n`, each slice inside the ball of radius `√(r² + s²/4)` about its middle
/// point (centres in `origin`'s parent frame). With end balls of the radius this covers a
/// capsule; alone, a cylinder.
pub(crate) fn slice_balls(
    origin: &Isometry3<f64>,
    radius: f64,
    length: f64,
    n: usize,
) -> impl Iterator<Item = (Point3<f64>, f64)> + '_ {
    let s = length / n as f64;
    let r = (radius * radius + 0.25 * s * s).sqrt();
    (0..n).map(move |k| (origin * Point3::new(0.0, 0.0, -0.5 * length + (k as f64 + 0.5) * s), r))
}

/// Spheres covering a box of half extents `h` at `origin`: a grid of cells as wide as the
/// thinnest side, each covered by the sphere through its corners.
pub(crate) fn cover_box(h: &Vector3<f64>, origin: &Isometry3<f64>, out: &mut Vec<(Point3<f64>, f64)>) {
    let cell = h.min().max(1e-3) * 2.0;
    let n = h.map(|e| ((2.0 * e / cell).ceil().max(1.0)) as usize);
    let size = Vector3::new(2.0 * h.x / n.x as f64, 2.0 * h.y / n.y as f64, 2.0 * h.z / n.z as f64);
    let r = size.norm() * 0.5;
    for i in 0..n.x {
        for j in 0..n.y {
            for k in 0..n.z {
                let c = Point3::new(
                    -h.x + size.x * (i as f64 + 0.5),
                    -h.y + size.y * (j as f64 + 0.5),
                    -h.z + size.z * (k as f64 + 0.5),
                );
                out.push((origin * c, r));
            }
        }
    }
}
