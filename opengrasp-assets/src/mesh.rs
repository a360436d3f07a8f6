//! Procedural, deterministic mesh builders: ring stacks (extrusions, lathes, tapered bottles),
//! swept tubes (handles) and polyhedral mass properties.
//!
//! Every builder returns a closed, consistently outward-oriented shell. Objects made of several
//! parts (a cup body and its handle) are several closed shells in one [`TriangleMesh`]; the shells
//! may overlap (a handle's ends are buried in the cup wall). Each shell is watertight on its own,
//! so the union mesh passes [`TriangleMesh::is_watertight`], and its signed volume counts the
//! (small) overlap twice.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use nalgebra::{Point3, Vector3};
use opengrasp_core::model::TriangleMesh;

use crate::error::Result;

/// Vertices and triangles of one or more closed shells, before validation.
#[derive(Clone, Debug, Default)]
pub struct MeshBuilder {
    vertices: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
}

impl MeshBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    fn push(&mut self, p: Point3<f64>) -> u32 {
        self.vertices.push(p);
        (self.vertices.len() - 1) as u32
    }

    /// Adds a closed shell through a stack of rings, each ring a closed polygon with the same
    /// number of points, counter-clockwise when seen from the side the stack advances to; the
    /// first and last rings are closed by fans around their centroids.
    ///
    /// Walls between consecutive rings face "outward" (ring tangent × advance direction), so an
    /// outer wall going up followed by an inner wall going down (a cup) stays consistently
    /// oriented.
    pub fn ring_stack(&mut self, rings: &[Vec<Point3<f64>>]) -> &mut Self {
        self.ring_stack_capped(rings, None, None)
    }

    /// Like [`MeshBuilder::ring_stack`], with the fan centres of the first and last caps given
    /// explicitly (e.g. the poles of a sphere); `None` uses the ring's centroid.
    pub fn ring_stack_capped(
        &mut self,
        rings: &[Vec<Point3<f64>>],
        first_cap: Option<Point3<f64>>,
        last_cap: Option<Point3<f64>>,
    ) -> &mut Self {
        let n = rings.first().map_or(0, Vec::len);
        if rings.is_empty() || n < 3 || rings.iter().any(|r| r.len() != n) {
            return self;
        }
        let centroid = |r: &[Point3<f64>]| Point3::from(r.iter().map(|p| p.coords).sum::<Vector3<f64>>() / n as f64);
        let c0 = self.push(first_cap.unwrap_or_else(|| centroid(&rings[0])));
        let base = self.vertices.len() as u32;
        for r in rings {
            for p in r {
                self.push(*p);
            }
        }
        let cn = self.push(last_cap.unwrap_or_else(|| centroid(&rings[rings.len() - 1])));
        let n32 = n as u32;
        let idx = |k: usize, i: usize| base + k as u32 * n32 + (i % n) as u32;
        for i in 0..n {
            self.triangles.push([c0, idx(0, i + 1), idx(0, i)]);
        }
        for k in 0..rings.len() - 1 {
            for i in 0..n {
                let (a, b, c, d) = (idx(k, i), idx(k, i + 1), idx(k + 1, i + 1), idx(k + 1, i));
                self.triangles.push([a, b, c]);
                self.triangles.push([a, c, d]);
            }
        }
        let last = rings.len() - 1;
        for i in 0..n {
            self.triangles.push([cn, idx(last, i), idx(last, i + 1)]);
        }
        self
    }

    /// Adds a closed tube of circular cross-section `radius` (with `sides` vertices) swept
    /// along `path`; `normals[k]` is a unit vector perpendicular to the path at point `k`
    /// (the first cross-section vertex lies along it). Both ends are capped.
    pub fn tube(&mut self, path: &[Point3<f64>], normals: &[Vector3<f64>], radius: f64, sides: usize) -> &mut Self {
        let rings: Vec<Vec<Point3<f64>>> = (0..path.len())
            .map(|k| {
                let t = if k + 1 < path.len() { path[k + 1] - path[k] } else { path[k] - path[k - 1] }.normalize();
                let nrm = normals[k];
                let b = t.cross(&nrm);
                (0..sides)
                    .map(|i| {
                        let phi = TAU * i as f64 / sides as f64;
                        path[k] + (nrm * phi.cos() + b * phi.sin()) * radius
                    })
                    .collect()
            })
            .collect();
        self.ring_stack(&rings)
    }

    /// Validates and returns the mesh.
    ///
    /// # Errors
    /// [`opengrasp_core::CoreError::DegenerateMesh`] if a face has zero area.
    pub fn build(self) -> Result<TriangleMesh> {
        Ok(TriangleMesh::new(self.vertices, self.triangles)?)
    }
}

/// A ring of `n` points on the superellipse `|x/a|^e + |y/b|^e = 1` at height `z`, centred at
/// `(cx, cy)`, counter-clockwise seen from +z, first point on +x. `e = 2` is an ellipse, larger
/// exponents approach a rectangle with rounded corners. With `n` a multiple of 4 the ring
/// reaches exactly `±a` and `±b`.
pub fn superellipse_ring(a: f64, b: f64, e: f64, z: f64, n: usize) -> Vec<Point3<f64>> {
    (0..n)
        .map(|i| {
            let th = TAU * i as f64 / n as f64;
            let (s, c) = th.sin_cos();
            let f = |v: f64| v.signum() * v.abs().powf(2.0 / e);
            Point3::new(a * f(c), b * f(s), z)
        })
        .collect()
}

/// A circle of radius `r` at height `z` (`n` points, first on +x, counter-clockwise from +z).
pub fn circle_ring(r: f64, z: f64, n: usize) -> Vec<Point3<f64>> {
    superellipse_ring(r, r, 2.0, z, n)
}

/// A closed solid of revolution about z through the profile `(radius, z)`, first and last
/// profile points capped (e.g. `[(r, 0), (r, h)]` is a cylinder).
///
/// A first or last profile point on the axis (radius 0) becomes a pole: the cap fan meets there.
pub fn lathe(profile: &[(f64, f64)], segments: usize) -> MeshBuilder {
    let pole = |p: Option<&(f64, f64)>| p.filter(|(r, _)| *r == 0.0).map(|&(_, z)| Point3::new(0.0, 0.0, z));
    let (first, last) = (pole(profile.first()), pole(profile.last()));
    let lo = usize::from(first.is_some());
    let hi = profile.len().saturating_sub(usize::from(last.is_some()));
    let rings: Vec<_> = profile[lo..hi.max(lo)].iter().map(|&(r, z)| circle_ring(r, z, segments)).collect();
    let mut m = MeshBuilder::new();
    m.ring_stack_capped(&rings, first, last);
    m
}

/// An axis-aligned box of full size `size`, bottom face centred at the origin.
pub fn box_shell(m: &mut MeshBuilder, size: Vector3<f64>, offset: Vector3<f64>) {
    let (hx, hy) = (size.x / 2.0, size.y / 2.0);
    let ring = |z: f64| {
        [(hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)]
            .iter()
            .map(|&(x, y)| Point3::new(x, y, z) + offset)
            .collect::<Vec<_>>()
    };
    m.ring_stack(&[ring(0.0), ring(size.z)]);
}

/// A handle: a tube of radius `tube_radius` along a half circle of radius `arc_radius` in the
/// x–z plane, centred at `(x0, 0, zc)` and bulging towards +x, with straight stubs of length
/// `embed` pointing back towards -x at both ends (buried in the wall the handle sits on).
/// The hole between the arc and the wall goes right through.
pub fn handle_shell(m: &mut MeshBuilder, x0: f64, zc: f64, arc_radius: f64, tube_radius: f64, embed: f64) {
    const ARC_SEGMENTS: usize = 16; // even: a path point sits at the apex
    let mut path = vec![Point3::new(x0 - embed, 0.0, zc + arc_radius)];
    let mut normals = vec![Vector3::z()];
    for k in 0..=ARC_SEGMENTS {
        let phi = FRAC_PI_2 - PI * k as f64 / ARC_SEGMENTS as f64;
        path.push(Point3::new(x0 + arc_radius * phi.cos(), 0.0, zc + arc_radius * phi.sin()));
        normals.push(Vector3::new(phi.cos(), 0.0, phi.sin()));
    }
    path.push(Point3::new(x0 - embed, 0.0, zc - arc_radius));
    normals.push(-Vector3::z());
    m.tube(&path, &normals, tube_radius, 16);
}
