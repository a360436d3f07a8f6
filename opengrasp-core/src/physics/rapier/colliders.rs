//! Rapier colliders from our geometry, and the contact filter that tells them apart.

use std::f64::consts::PI;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rapier3d_f64::prelude::{ColliderHandle, PairFilterContext, PhysicsHooks, SharedShape, SolverFlags};

use super::ContactBody;
use crate::error::{CoreError, Result};
use crate::model::{Geometry, LinkId, Robot};
use crate::scene::{BodyId, ObjectId, RobotId};

/// Collider user data: what the collider belongs to.
pub(super) fn encode(body: ContactBody) -> u128 {
    match body {
        ContactBody::Static(b) => (1u128 << 126) | b.0 as u128,
        ContactBody::Object(o) => (2u128 << 126) | o.0 as u128,
        ContactBody::Link { robot, link } => (3u128 << 126) | ((robot.0 as u128) << 63) | link.0 as u128,
    }
}

pub(super) fn decode(data: u128) -> Option<ContactBody> {
    let low = (data & ((1u128 << 63) - 1)) as usize;
    match data >> 126 {
        1 => Some(ContactBody::Static(BodyId(low))),
        2 => Some(ContactBody::Object(ObjectId(low))),
        3 => {
            Some(ContactBody::Link { robot: RobotId(((data >> 63) & ((1u128 << 63) - 1)) as usize), link: LinkId(low) })
        }
        _ => None,
    }
}

/// Filters contacts between links of the same robot.
#[derive(Clone)]
pub(super) struct ContactFilter {
    pub(super) robots: Vec<Arc<Robot>>,
    pub(super) self_collisions: bool,
}

impl PhysicsHooks for ContactFilter {
    fn filter_contact_pair(&self, context: &PairFilterContext) -> Option<SolverFlags> {
        let body = |h: ColliderHandle| context.colliders.get(h).and_then(|c| decode(c.user_data));
        if let (Some(ContactBody::Link { robot: r1, link: l1 }), Some(ContactBody::Link { robot: r2, link: l2 })) =
            (body(context.collider1), body(context.collider2))
        {
            if r1 == r2 && (!self.self_collisions || self.robots[r1.0].is_collision_allowed(l1, l2)) {
                return None;
            }
        }
        Some(SolverFlags::COMPUTE_IMPULSES)
    }
}

/// Rotation taking parry's y axis (cylinders) to URDF's z axis.
pub(super) fn y_to_z() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI / 2.0)
}

/// A rapier shape and its pose in the geometry frame, for a geometry.
pub(super) fn convert(geometry: &Geometry, is_static: bool) -> Result<(SharedShape, Isometry3<f64>)> {
    geometry.validate()?;
    Ok(match geometry {
        Geometry::Box { half_extents } => {
            (SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z), Isometry3::identity())
        }
        Geometry::Sphere { radius } => (SharedShape::ball(*radius), Isometry3::identity()),
        Geometry::Cylinder { radius, length } => {
            (SharedShape::cylinder(length * 0.5, *radius), Isometry3::from_parts(Translation3::identity(), y_to_z()))
        }
        Geometry::Capsule { radius, length } => (
            SharedShape::capsule(Point3::new(0.0, 0.0, -length * 0.5), Point3::new(0.0, 0.0, length * 0.5), *radius),
            Isometry3::identity(),
        ),
        Geometry::Mesh(mesh) => {
            let shape = if is_static {
                SharedShape::trimesh(mesh.vertices().to_vec(), mesh.triangles().to_vec()).map_err(|e| {
                    CoreError::DegenerateMesh { reason: format!("rapier rejects the triangle mesh: {e:?}") }
                })?
            } else {
                SharedShape::convex_hull(mesh.vertices())
                    .ok_or_else(|| CoreError::DegenerateMesh { reason: "mesh has no 3-d convex hull".into() })?
            };
            (shape, Isometry3::identity())
        }
    })
}
