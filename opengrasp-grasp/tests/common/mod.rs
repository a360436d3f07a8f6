//! Test meshes shared by the grasp integration tests.

use std::f64::consts::PI;

use nalgebra::Point3;
use opengrasp_core::model::TriangleMesh;

/// A closed cylinder mesh along z, centred at the origin, with `n` sides.
pub fn cylinder_mesh(radius: f64, length: f64, n: usize) -> TriangleMesh {
    let mut v = Vec::new();
    for k in 0..n {
        let a = 2.0 * PI * k as f64 / n as f64;
        v.push(Point3::new(radius * a.cos(), radius * a.sin(), -length / 2.0));
        v.push(Point3::new(radius * a.cos(), radius * a.sin(), length / 2.0));
    }
    let bottom = v.len() as u32;
    v.push(Point3::new(0.0, 0.0, -length / 2.0));
    let top = v.len() as u32;
    v.push(Point3::new(0.0, 0.0, length / 2.0));
    let mut t = Vec::new();
    for k in 0..n as u32 {
        let k2 = (k + 1) % n as u32;
        let (b0, t0, b1, t1) = (2 * k, 2 * k + 1, 2 * k2, 2 * k2 + 1);
        t.push([b0, b1, t1]);
        t.push([b0, t1, t0]);
        t.push([bottom, b1, b0]);
        t.push([top, t0, t1]);
    }
    TriangleMesh::new(v, t).unwrap()
}
