//! Sphere covers of triangle meshes with a guaranteed bound: every point of the mesh surface
//! lies inside some sphere.
//!
//! - [`voxel_cover`]: one sphere per grid cell the surface touches, of radius half the cell
//!   diagonal (plus a rounding margin). No sphere reaches farther than `2√3 · cell` from the
//!   surface (a kept cell meets the bounding box of a surface piece no wider than `cell`), so
//!   the cover tightens with the cell size.
//! - [`bounding_box_cover`]: the cover [`SphereWorld`](super::SphereWorld) uses for meshes: a
//!   grid of spheres over the mesh's bounding box (cells as wide as its thinnest side).
//!   Guaranteed as well, but it fills the whole box.
//!
//! [`SphereCover::overhang`] measures how far a cover reaches beyond the surface.

use std::collections::BTreeSet;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::model::TriangleMesh;

use crate::error::{MotionError, Result};

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

fn closest_on_triangle(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> Point3<f64> {
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
    let invalid = |reason: String| MotionError::InvalidParameter { name: "cell", reason };
    if !(cell.is_finite() && cell > 0.0) {
        return Err(invalid(format!("{cell} is not a positive length")));
    }
    let v = mesh.vertices();
    let longest = |t: &[Point3<f64>; 3]| (t[1] - t[0]).norm().max((t[2] - t[1]).norm()).max((t[0] - t[2]).norm());
    let tris: Vec<[Point3<f64>; 3]> =
        mesh.triangles().iter().map(|t| [v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]]).collect();
    let mut pieces = 0usize;
    for t in &tris {
        let levels = (longest(t) / cell).log2().ceil().max(0.0);
        pieces = pieces.saturating_add(4usize.saturating_pow(levels.min(31.0) as u32));
    }
    if pieces > MAX_COVER_PIECES {
        return Err(invalid(format!("{cell} m needs {pieces} triangle pieces, more than {MAX_COVER_PIECES}")));
    }
    let (lo, hi) = mesh.aabb();
    let index = |x: f64, o: f64| ((x - o) / cell).floor() as i64;
    let mut cells = BTreeSet::new();
    let mut stack = tris;
    while let Some(t) = stack.pop() {
        if longest(&t) > cell {
            let m = [nalgebra::center(&t[0], &t[1]), nalgebra::center(&t[1], &t[2]), nalgebra::center(&t[2], &t[0])];
            stack.extend([[t[0], m[0], m[2]], [m[0], t[1], m[1]], [m[2], m[1], t[2]], m]);
            continue;
        }
        let a = t[0].coords.inf(&t[1].coords).inf(&t[2].coords);
        let b = t[0].coords.sup(&t[1].coords).sup(&t[2].coords);
        for i in index(a.x, lo.x)..=index(b.x, lo.x) {
            for j in index(a.y, lo.y)..=index(b.y, lo.y) {
                for k in index(a.z, lo.z)..=index(b.z, lo.z) {
                    cells.insert((i, j, k));
                }
            }
        }
    }
    let scale = lo.coords.amax().max(hi.coords.amax()) + cell;
    let r = cell * 0.5 * 3f64.sqrt() + 1e-9 * scale;
    let spheres = cells
        .into_iter()
        .map(|(i, j, k)| {
            let centre = Vector3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * cell;
            (lo + centre, r)
        })
        .collect();
    Ok(SphereCover { spheres })
}

/// The bounding-box grid cover [`SphereWorld`](super::SphereWorld) uses for meshes.
pub fn bounding_box_cover(mesh: &TriangleMesh) -> SphereCover {
    let (lo, hi) = mesh.aabb();
    let centre = nalgebra::center(&lo, &hi);
    let mut spheres = Vec::new();
    cover_box(&((hi - lo) * 0.5), &Isometry3::translation(centre.x, centre.y, centre.z), &mut spheres);
    SphereCover { spheres }
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
