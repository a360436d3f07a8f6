//! Geometric primitives and triangle meshes attached to links and bodies.

use std::collections::HashMap;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};

use crate::error::{CoreError, Result};

/// A geometric primitive or mesh, in its own local frame.
///
/// Conventions follow URDF: cylinders and capsules are aligned with the local z axis and centred
/// at the origin; boxes are centred at the origin.
///
/// **Box size convention:** [`Geometry::Box`] stores *half* extents (as parry does); every
/// constructor that takes a box size — [`Geometry::cuboid`], [`Shape::cuboid`], URDF's
/// `<box size>` — takes the *full* size (edge lengths). Obstacles between two points:
/// [`Shape::capsule_between`] and [`Shape::cylinder_between`].
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// Axis-aligned box given by its half extents (m).
    Box {
        /// Half of the box's size along x, y, z (m).
        half_extents: Vector3<f64>,
    },
    /// Sphere centred at the origin.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// Cylinder along local z, centred at the origin.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Total length along z (m).
        length: f64,
    },
    /// Capsule along local z, centred at the origin.
    Capsule {
        /// Radius (m).
        radius: f64,
        /// Distance between the two hemisphere centres (m).
        length: f64,
    },
    /// Triangle mesh (already scaled to metres).
    Mesh(Arc<TriangleMesh>),
}

impl Geometry {
    /// A box from its full size (m) along x, y and z.
    pub fn cuboid(x: f64, y: f64, z: f64) -> Self {
        Geometry::Box { half_extents: Vector3::new(x, y, z) * 0.5 }
    }

    /// Checks that every dimension is finite and positive.
    ///
    /// # Errors
    /// [`CoreError::InvalidGeometry`] naming the bad dimension.
    pub fn validate(&self) -> Result<()> {
        let bad = |what: &str, v: f64| -> Result<()> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(CoreError::InvalidGeometry { reason: format!("{what} must be finite and > 0, got {v}") })
            }
        };
        match self {
            Geometry::Box { half_extents } => {
                for v in half_extents.iter() {
                    bad("box half extent", *v)?;
                }
                Ok(())
            }
            Geometry::Sphere { radius } => bad("sphere radius", *radius),
            Geometry::Cylinder { radius, length } => {
                bad("cylinder radius", *radius)?;
                bad("cylinder length", *length)
            }
            Geometry::Capsule { radius, length } => {
                bad("capsule radius", *radius)?;
                if length.is_finite() && *length >= 0.0 {
                    Ok(())
                } else {
                    Err(CoreError::InvalidGeometry {
                        reason: format!("capsule length must be finite and >= 0, got {length}"),
                    })
                }
            }
            Geometry::Mesh(_) => Ok(()),
        }
    }

    /// Axis-aligned bounding box `(min, max)` in the geometry's local frame.
    pub fn local_aabb(&self) -> (Point3<f64>, Point3<f64>) {
        match self {
            Geometry::Box { half_extents } => (Point3::from(-half_extents), Point3::from(*half_extents)),
            Geometry::Sphere { radius } => {
                let r = Vector3::repeat(*radius);
                (Point3::from(-r), Point3::from(r))
            }
            Geometry::Cylinder { radius, length } => {
                let e = Vector3::new(*radius, *radius, length * 0.5);
                (Point3::from(-e), Point3::from(e))
            }
            Geometry::Capsule { radius, length } => {
                let e = Vector3::new(*radius, *radius, length * 0.5 + radius);
                (Point3::from(-e), Point3::from(e))
            }
            Geometry::Mesh(mesh) => mesh.aabb(),
        }
    }

    /// Enclosed volume (m³).
    pub fn volume(&self) -> f64 {
        use std::f64::consts::PI;
        match self {
            Geometry::Box { half_extents } => 8.0 * half_extents.x * half_extents.y * half_extents.z,
            Geometry::Sphere { radius } => 4.0 / 3.0 * PI * radius.powi(3),
            Geometry::Cylinder { radius, length } => PI * radius * radius * length,
            Geometry::Capsule { radius, length } => PI * radius * radius * length + 4.0 / 3.0 * PI * radius.powi(3),
            Geometry::Mesh(mesh) => mesh.signed_volume(),
        }
    }
}

/// A geometry placed in a parent frame (a link, a body or an object).
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// Pose of the geometry in the parent frame.
    pub origin: Isometry3<f64>,
    /// The geometry.
    pub geometry: Geometry,
}

impl Shape {
    /// The eight corners of the geometry's local bounding box, in the parent frame (a
    /// conservative hull of the shape: every point of it lies in their convex hull).
    pub fn aabb_corners(&self) -> [Point3<f64>; 8] {
        let (lo, hi) = self.geometry.local_aabb();
        parry3d_f64::bounding_volume::Aabb::new(lo, hi).vertices().map(|p| self.origin * p)
    }

    /// A geometry at `origin` in its parent frame.
    pub fn new(origin: Isometry3<f64>, geometry: Geometry) -> Self {
        Self { origin, geometry }
    }

    /// A geometry at the parent frame's origin.
    pub fn at_origin(geometry: Geometry) -> Self {
        Self { origin: Isometry3::identity(), geometry }
    }

    /// A box of full size `size` (edge lengths along x, y, z, m) at `origin`.
    ///
    /// # Errors
    /// [`CoreError::InvalidGeometry`] for a non-positive or non-finite size;
    /// [`CoreError::NonFinite`] for a non-finite pose.
    pub fn cuboid(origin: Isometry3<f64>, size: Vector3<f64>) -> Result<Self> {
        crate::error::ensure_finite(
            "box pose",
            origin.translation.vector.iter().chain(origin.rotation.coords.iter()).copied(),
        )?;
        let geometry = Geometry::cuboid(size.x, size.y, size.z);
        geometry.validate()?;
        Ok(Self { origin, geometry })
    }

    /// A capsule whose hemisphere centres are `a` and `b` (m), of radius `radius`: the swept
    /// sphere along the segment, e.g. a pole or a bar as an obstacle.
    ///
    /// # Errors
    /// [`CoreError::NonFinite`] for non-finite points; [`CoreError::InvalidGeometry`] if the
    /// points coincide or the radius is not positive and finite.
    pub fn capsule_between(a: Point3<f64>, b: Point3<f64>, radius: f64) -> Result<Self> {
        let (origin, length) = segment_frame(a, b)?;
        let geometry = Geometry::Capsule { radius, length };
        geometry.validate()?;
        Ok(Self { origin, geometry })
    }

    /// A cylinder whose end-face centres are `a` and `b` (m), of radius `radius`.
    ///
    /// # Errors
    /// As [`Shape::capsule_between`].
    pub fn cylinder_between(a: Point3<f64>, b: Point3<f64>, radius: f64) -> Result<Self> {
        let (origin, length) = segment_frame(a, b)?;
        let geometry = Geometry::Cylinder { radius, length };
        geometry.validate()?;
        Ok(Self { origin, geometry })
    }
}

/// The frame centred between `a` and `b` with its z axis along `b - a`, and the distance.
fn segment_frame(a: Point3<f64>, b: Point3<f64>) -> Result<(Isometry3<f64>, f64)> {
    crate::error::ensure_finite("segment end points", a.coords.iter().chain(b.coords.iter()).copied())?;
    let d = b - a;
    let length = d.norm();
    if length == 0.0 {
        return Err(CoreError::InvalidGeometry { reason: "segment end points coincide".to_string() });
    }
    let rotation = nalgebra::UnitQuaternion::rotation_between(&Vector3::z(), &d)
        // Anti-parallel to z: half a turn about x.
        .unwrap_or_else(|| nalgebra::UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI));
    Ok((Isometry3::from_parts(nalgebra::center(&a, &b).coords.into(), rotation), length))
}

/// An indexed triangle mesh in metres, validated on construction.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleMesh {
    vertices: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
}

/// Faces with an area below this (m²) are degenerate.
const MIN_TRIANGLE_AREA: f64 = 1e-16;

impl TriangleMesh {
    /// Builds a mesh, rejecting empty, non-finite, out-of-range or zero-area input.
    ///
    /// # Errors
    /// [`CoreError::DegenerateMesh`] describing the first problem found.
    pub fn new(vertices: Vec<Point3<f64>>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        let degenerate = |reason: String| Err(CoreError::DegenerateMesh { reason });
        if vertices.is_empty() || triangles.is_empty() {
            return degenerate(format!("{} vertices and {} triangles", vertices.len(), triangles.len()));
        }
        if let Some(i) = vertices.iter().position(|v| !v.coords.iter().all(|c| c.is_finite())) {
            return degenerate(format!("vertex {i} is not finite"));
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i as usize >= vertices.len()) {
                return degenerate(format!("triangle {t} references vertex {i} of {}", vertices.len()));
            }
            let [a, b, c] = tri.map(|i| vertices[i as usize]);
            if (b - a).cross(&(c - a)).norm() * 0.5 < MIN_TRIANGLE_AREA {
                return degenerate(format!("triangle {t} has zero area"));
            }
        }
        Ok(Self { vertices, triangles })
    }

    /// Like [`TriangleMesh::new`] but first drops zero-area faces (common in exported CAD
    /// files); fails only if nothing usable remains.
    ///
    /// # Errors
    /// [`CoreError::DegenerateMesh`] if the remaining mesh is empty or invalid.
    pub fn new_dropping_degenerate(vertices: Vec<Point3<f64>>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        let n = vertices.len();
        let kept: Vec<[u32; 3]> = triangles
            .into_iter()
            .filter(|tri| {
                if tri.iter().any(|&i| i as usize >= n) {
                    return true; // let `new` report it
                }
                let [a, b, c] = tri.map(|i| vertices[i as usize]);
                (b - a).cross(&(c - a)).norm() * 0.5 >= MIN_TRIANGLE_AREA
            })
            .collect();
        Self::new(vertices, kept)
    }

    /// A closed, outward-oriented box mesh of full size `size` (m) centred at the origin
    /// (12 triangles).
    ///
    /// # Errors
    /// [`CoreError::DegenerateMesh`] for a non-finite or non-positive size.
    pub fn cuboid(size: Vector3<f64>) -> Result<Self> {
        let h = size * 0.5;
        let vertices = (0..8)
            .map(|i| {
                let sign = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
                Point3::new(sign(1) * h.x, sign(2) * h.y, sign(4) * h.z)
            })
            .collect();
        // Two triangles per face, counter-clockwise seen from outside.
        let triangles = vec![
            [0, 2, 3],
            [0, 3, 1], // -z
            [4, 5, 7],
            [4, 7, 6], // +z
            [0, 1, 5],
            [0, 5, 4], // -y
            [2, 6, 7],
            [2, 7, 3], // +y
            [0, 4, 6],
            [0, 6, 2], // -x
            [1, 3, 7],
            [1, 7, 5], // +x
        ];
        Self::new(vertices, triangles)
    }

    /// The vertices (m).
    pub fn vertices(&self) -> &[Point3<f64>] {
        &self.vertices
    }

    /// The triangles as vertex-index triples, counter-clockwise seen from outside.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The mesh scaled per axis.
    ///
    /// # Errors
    /// [`CoreError::DegenerateMesh`] if the scale collapses faces (a zero or non-finite factor).
    pub fn scaled(&self, scale: &Vector3<f64>) -> Result<Self> {
        let vertices = self.vertices.iter().map(|v| Point3::from(v.coords.component_mul(scale))).collect();
        let mut triangles = self.triangles.clone();
        if scale.x * scale.y * scale.z < 0.0 {
            // A mirroring scale flips orientation; swap two indices to keep faces outward.
            for t in &mut triangles {
                t.swap(1, 2);
            }
        }
        Self::new(vertices, triangles)
    }

    /// The mesh with every vertex mapped through `pose`.
    pub fn transformed(&self, pose: &Isometry3<f64>) -> Self {
        Self { vertices: self.vertices.iter().map(|v| pose * v).collect(), triangles: self.triangles.clone() }
    }

    /// Axis-aligned bounding box `(min, max)`.
    pub fn aabb(&self) -> (Point3<f64>, Point3<f64>) {
        let mut lo = self.vertices[0];
        let mut hi = self.vertices[0];
        for v in &self.vertices {
            lo = lo.inf(v);
            hi = hi.sup(v);
        }
        (lo, hi)
    }

    /// Signed enclosed volume (m³): positive when faces are oriented outward.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize].coords);
                a.dot(&b.cross(&c))
            })
            .sum::<f64>()
            / 6.0
    }

    /// Total surface area (m²).
    pub fn surface_area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                (b - a).cross(&(c - a)).norm() * 0.5
            })
            .sum()
    }

    /// Centroid of the enclosed volume (assumes a closed, consistently oriented mesh).
    pub fn volume_centroid(&self) -> Point3<f64> {
        let mut acc = Vector3::zeros();
        let mut vol = 0.0;
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.vertices[i as usize].coords);
            let v = a.dot(&b.cross(&c)) / 6.0;
            acc += (a + b + c) * (v / 4.0);
            vol += v;
        }
        Point3::from(acc / vol)
    }

    /// True if every edge is shared by exactly two faces traversing it in opposite directions
    /// (closed, manifold and consistently oriented).
    pub fn is_watertight(&self) -> bool {
        let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(self.triangles.len() * 3);
        for t in &self.triangles {
            for k in 0..3 {
                *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        directed.iter().all(|(&(a, b), &n)| n == 1 && directed.get(&(b, a)) == Some(&1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> TriangleMesh {
        let v = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        TriangleMesh::new(v, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]).unwrap()
    }

    #[test]
    fn tetrahedron_volume_and_watertightness() {
        let t = tetrahedron();
        assert!((t.signed_volume() - 1.0 / 6.0).abs() < 1e-12);
        assert!(t.is_watertight());
        let c = t.volume_centroid();
        assert!((c - Point3::new(0.25, 0.25, 0.25)).norm() < 1e-12);
        let mirrored = t.scaled(&Vector3::new(-2.0, 1.0, 1.0)).unwrap();
        assert!((mirrored.signed_volume() - 2.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn degenerate_meshes_are_rejected() {
        let v = vec![Point3::origin(), Point3::new(1.0, 0.0, 0.0), Point3::new(2.0, 0.0, 0.0)];
        assert!(matches!(TriangleMesh::new(v.clone(), vec![[0, 1, 2]]), Err(CoreError::DegenerateMesh { .. })));
        assert!(matches!(TriangleMesh::new(v.clone(), vec![[0, 1, 7]]), Err(CoreError::DegenerateMesh { .. })));
        assert!(matches!(TriangleMesh::new(vec![], vec![]), Err(CoreError::DegenerateMesh { .. })));
        assert!(matches!(
            TriangleMesh::new_dropping_degenerate(v, vec![[0, 1, 2]]),
            Err(CoreError::DegenerateMesh { .. })
        ));
        let nan = vec![Point3::new(f64::NAN, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)];
        assert!(matches!(TriangleMesh::new(nan, vec![[0, 1, 2]]), Err(CoreError::DegenerateMesh { .. })));
    }

    #[test]
    fn primitive_validation() {
        assert!(Geometry::Sphere { radius: 0.1 }.validate().is_ok());
        assert!(Geometry::Sphere { radius: -0.1 }.validate().is_err());
        assert!(Geometry::Cylinder { radius: 0.1, length: f64::NAN }.validate().is_err());
        assert!((Geometry::cuboid(1.0, 2.0, 3.0).volume() - 6.0).abs() < 1e-12);
    }
}
