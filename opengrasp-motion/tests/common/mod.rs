//! Meshes shared by the sphere-cover tests.

use std::f64::consts::TAU;

use nalgebra::{Point3, Vector3};
use opengrasp_core::model::TriangleMesh;

/// A closed cylinder of radius `r` and length `l` along z, `n` facets around (outward).
pub fn cylinder(r: f64, l: f64, n: u32) -> TriangleMesh {
    let mut v = vec![Point3::new(0.0, 0.0, -l / 2.0), Point3::new(0.0, 0.0, l / 2.0)];
    for i in 0..n {
        let a = TAU * f64::from(i) / f64::from(n);
        v.push(Point3::new(r * a.cos(), r * a.sin(), -l / 2.0));
        v.push(Point3::new(r * a.cos(), r * a.sin(), l / 2.0));
    }
    let mut t = Vec::new();
    for i in 0..n {
        let (b0, t0, b1, t1) = (2 + 2 * i, 3 + 2 * i, 2 + 2 * ((i + 1) % n), 3 + 2 * ((i + 1) % n));
        t.extend([[0, b1, b0], [1, t0, t1], [b0, b1, t1], [b0, t1, t0]]);
    }
    TriangleMesh::new(v, t).unwrap()
}

/// The triangles `tris` shifted by `shift`, degenerate ones (area < 5e-7) dropped; `None` if
/// none is left.
pub fn soup(tris: &[(Point3<f64>, Point3<f64>, Point3<f64>)], shift: Vector3<f64>) -> Option<TriangleMesh> {
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (a, b, c) in tris {
        if (b - a).cross(&(c - a)).norm() < 1e-6 {
            continue;
        }
        let k = vertices.len() as u32;
        vertices.extend([a + shift, b + shift, c + shift]);
        triangles.push([k, k + 1, k + 2]);
    }
    (!triangles.is_empty()).then(|| TriangleMesh::new(vertices, triangles).unwrap())
}
