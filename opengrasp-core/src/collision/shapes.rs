//! Conversion of [`Geometry`] (URDF conventions) to parry shapes.

use std::f64::consts::FRAC_PI_2;

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use parry3d_f64::shape::{SharedShape, TriMeshFlags};

use super::climbing::ClimbingHull;
use crate::error::{CoreError, Result};
use crate::model::{Geometry, Shape, TriangleMesh};

/// How triangle meshes become collision shapes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeshRepresentation {
    /// The exact surface as a parry `TriMesh`. Faithful for non-convex objects (cups, shelves),
    /// but a mesh is a surface: a small shape entirely inside a closed mesh does not touch it,
    /// and penetration depths are measured to the nearest triangle.
    TriMesh,
    /// The convex hull as a parry `ConvexPolyhedron`: fast GJK/EPA queries and proper
    /// penetration depths, conservative (larger) for non-convex meshes.
    ConvexHull,
    /// The convex hull when the mesh is closed and (nearly) convex — its volume is within 0.1 %
    /// of its hull's — otherwise the exact `TriMesh`. This is the default.
    #[default]
    Auto,
    /// As [`ConvexHull`](Self::ConvexHull), wrapped in a [`ClimbingHull`] when the hull has 64
    /// vertices or more: the same polyhedron and the same support points, found by hill
    /// climbing on the vertex graph instead of a linear scan (much faster GJK on hulls of
    /// hundreds of vertices). A parry custom shape: fine for the queries of
    /// [`super::CollisionWorld`], not meant for physics engines.
    ClimbingHull,
    /// As [`Auto`](Self::Auto), with [`ClimbingHull`](Self::ClimbingHull) for convex meshes.
    AutoClimbing,
}

/// Relative volume difference under which a closed mesh counts as convex for
/// [`MeshRepresentation::Auto`].
const CONVEX_VOLUME_TOLERANCE: f64 = 1e-3;

/// Converts one geometry to a parry shape.
///
/// Returns the shape and a correction pose to compose on the right of the geometry's pose
/// (`world_pose_of_shape = parent_pose * shape.origin * correction`): parry's cylinder is
/// along its local y axis while URDF's is along z, so a cylinder gets a +90° rotation about x
/// (mapping parry's y onto our z); every other geometry gets the identity (capsules are built
/// along z directly, boxes and spheres are symmetric, meshes keep their vertices).
///
/// # Errors
/// [`CoreError::InvalidGeometry`] for non-positive or non-finite dimensions,
/// [`CoreError::DegenerateMesh`] if parry rejects the mesh or its hull is flat.
pub fn geometry_to_parry(geometry: &Geometry, meshes: MeshRepresentation) -> Result<(Isometry3<f64>, SharedShape)> {
    geometry.validate()?;
    let identity = Isometry3::identity();
    Ok(match geometry {
        Geometry::Box { half_extents } => {
            (identity, SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z))
        }
        Geometry::Sphere { radius } => (identity, SharedShape::ball(*radius)),
        Geometry::Capsule { radius, length } => (identity, SharedShape::capsule_z(length * 0.5, *radius)),
        Geometry::Cylinder { radius, length } => {
            let y_to_z = Isometry3::from_parts(
                nalgebra::Translation3::identity(),
                UnitQuaternion::from_axis_angle(&Vector3::x_axis(), FRAC_PI_2),
            );
            (y_to_z, SharedShape::cylinder(length * 0.5, *radius))
        }
        Geometry::Mesh(mesh) => (identity, mesh_to_parry(mesh, meshes)?),
    })
}

fn trimesh(mesh: &TriangleMesh) -> Result<SharedShape> {
    let flags = if mesh.is_watertight() { TriMeshFlags::ORIENTED } else { TriMeshFlags::empty() };
    SharedShape::trimesh_with_flags(mesh.vertices().to_vec(), mesh.triangles().to_vec(), flags)
        .map_err(|e| CoreError::DegenerateMesh { reason: format!("parry rejected the mesh: {e:?}") })
}

fn hull(mesh: &TriangleMesh) -> Result<SharedShape> {
    SharedShape::convex_hull(mesh.vertices())
        .ok_or_else(|| CoreError::DegenerateMesh { reason: "the mesh's convex hull is flat".into() })
}

/// Hulls with fewer vertices than this keep parry's linear scan (cheaper than seeding a climb).
const CLIMBING_MIN_VERTICES: usize = 64;

fn climbing(shape: SharedShape) -> SharedShape {
    match shape.as_convex_polyhedron() {
        Some(poly) if poly.points().len() >= CLIMBING_MIN_VERTICES => {
            SharedShape(std::sync::Arc::new(ClimbingHull::new(poly.clone())))
        }
        _ => shape,
    }
}

fn mesh_to_parry(mesh: &TriangleMesh, meshes: MeshRepresentation) -> Result<SharedShape> {
    match meshes {
        MeshRepresentation::TriMesh => trimesh(mesh),
        MeshRepresentation::ConvexHull => hull(mesh),
        MeshRepresentation::ClimbingHull => hull(mesh).map(climbing),
        MeshRepresentation::Auto | MeshRepresentation::AutoClimbing => {
            if mesh.is_watertight() {
                if let Ok(h) = hull(mesh) {
                    let hull_volume = h.mass_properties(1.0).mass();
                    let volume = mesh.signed_volume();
                    if hull_volume > 0.0 && (hull_volume - volume).abs() <= CONVEX_VOLUME_TOLERANCE * hull_volume {
                        return Ok(if meshes == MeshRepresentation::AutoClimbing { climbing(h) } else { h });
                    }
                }
            }
            trimesh(mesh)
        }
    }
}

/// A collision part: one parry shape at a pose in its owner's frame (link, body or object).
#[derive(Clone)]
pub(crate) struct Part {
    /// Pose of the parry shape in the owner frame (geometry origin with the axis correction).
    pub local: Isometry3<f64>,
    /// The shape.
    pub shape: SharedShape,
    /// For a triangle-mesh shape, the convex hull of its vertices (which contains it): a cheap
    /// conservative stand-in that rules out far or separated pairs before the exact
    /// triangle-by-triangle query; a [`ClimbingHull`] from 64 vertices on (the same support
    /// points, so the same GJK results, without scanning every vertex). `None` for convex
    /// shapes.
    pub hull: Option<SharedShape>,
}

impl Part {
    /// A part, with the hull of a triangle-mesh shape.
    pub fn new(local: Isometry3<f64>, shape: SharedShape) -> Self {
        let hull = shape.as_trimesh().and_then(|m| SharedShape::convex_hull(m.vertices())).map(climbing);
        Self { local, shape, hull }
    }
}

impl std::fmt::Debug for Part {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Part").field("local", &self.local).field("shape", &self.shape.shape_type()).finish()
    }
}

/// Converts a list of shapes (a link's, a body's or an object's) to parts.
pub(crate) fn shapes_to_parts(shapes: &[Shape], meshes: MeshRepresentation) -> Result<Vec<Part>> {
    shapes
        .iter()
        .map(|s| {
            let (correction, shape) = geometry_to_parry(&s.geometry, meshes)?;
            Ok(Part::new(s.origin * correction, shape))
        })
        .collect()
}

/// Converts a list of shapes to one parry shape: the shape itself (with its pose folded in
/// through a one-part compound when it is not the identity) or a parry `Compound`.
///
/// Compounds cannot nest composite shapes, so with several shapes meshes are taken as convex
/// hulls whatever `meshes` says; a single mesh follows `meshes` with its pose baked in. [`super::CollisionWorld`] does not use this
/// function: it keeps each part separately (its own compound with per-part bounding boxes, which
/// also allows triangle-mesh parts).
///
/// # Errors
/// [`CoreError::InvalidGeometry`] for an empty list or bad dimensions,
/// [`CoreError::DegenerateMesh`] for unusable meshes.
pub fn shapes_to_parry(shapes: &[Shape], meshes: MeshRepresentation) -> Result<SharedShape> {
    if let [Shape { origin, geometry: Geometry::Mesh(mesh) }] = shapes {
        // Bake the pose into the vertices so that a triangle mesh need not sit in a compound.
        let baked = Geometry::Mesh(std::sync::Arc::new(mesh.transformed(origin)));
        return Ok(geometry_to_parry(&baked, meshes)?.1);
    }
    let parts = shapes_to_parts(shapes, MeshRepresentation::ConvexHull)?;
    match parts.as_slice() {
        [] => Err(CoreError::InvalidGeometry { reason: "no shapes to convert".into() }),
        [p] if p.local == Isometry3::identity() => Ok(p.shape.clone()),
        _ => Ok(SharedShape::compound(parts.into_iter().map(|p| (p.local, p.shape)).collect())),
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Point3, Vector3};
    use parry3d_f64::query;
    use parry3d_f64::shape::Cuboid;
    use rand::{Rng, SeedableRng};

    use super::*;

    /// A closed prism over a star of `n` points (non-convex), as a parry triangle mesh.
    fn star_prism(n: u32) -> SharedShape {
        let mut pts = Vec::new();
        for z in [0.0, 0.1] {
            for k in 0..n {
                let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
                let r = if k % 2 == 0 { 0.05 } else { 0.035 };
                pts.push(Point3::new(r * a.cos(), r * a.sin(), z));
            }
        }
        pts.extend([Point3::new(0.0, 0.0, 0.0), Point3::new(0.0, 0.0, 0.1)]);
        let mut tris = Vec::new();
        for k in 0..n {
            let j = (k + 1) % n;
            tris.extend([[k, j, n + j], [k, n + j, n + k], [2 * n, j, k], [2 * n + 1, n + k, n + j]]);
        }
        SharedShape::trimesh(pts, tris).expect("mesh")
    }

    /// A mesh part's hull is a climbing hull from 64 vertices on, with the distances and
    /// intersection answers of parry's plain hull bit for bit; below 64, the plain hull.
    #[test]
    fn mesh_hull_climbs_with_the_plain_hulls_answers() {
        let mesh = star_prism(80);
        let part = Part::new(Isometry3::identity(), mesh.clone());
        let hull = part.hull.as_ref().expect("hull");
        assert!(hull.as_shape::<ClimbingHull>().is_some());
        let plain = SharedShape::convex_hull(mesh.as_trimesh().unwrap().vertices()).unwrap();
        let cuboid = Cuboid::new(Vector3::new(0.02, 0.01, 0.004));
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let (mut hits, mut misses) = (0, 0);
        let id = Isometry3::identity();
        for _ in 0..500 {
            let t =
                Vector3::new(rng.random_range(-0.1..0.1), rng.random_range(-0.1..0.1), rng.random_range(-0.05..0.15));
            let r = Vector3::new(rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0));
            let pose = Isometry3::new(t, r);
            let d = query::distance(&pose, &cuboid, &id, &**hull).unwrap();
            assert_eq!(d.to_bits(), query::distance(&pose, &cuboid, &id, &*plain).unwrap().to_bits());
            let hit = query::intersection_test(&pose, &cuboid, &id, &**hull).unwrap();
            assert_eq!(hit, query::intersection_test(&pose, &cuboid, &id, &*plain).unwrap());
            if hit {
                hits += 1;
            } else {
                misses += 1;
            }
        }
        assert!(hits >= 50 && misses >= 50, "{hits} hits, {misses} misses");
        // Hull vertices: the 2 x 40 outer points above, 2 x 12 here (the plain hull).
        let small = Part::new(Isometry3::identity(), star_prism(24));
        assert!(small.hull.as_ref().unwrap().as_convex_polyhedron().is_some());
    }
}
