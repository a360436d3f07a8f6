//! Obstacles of a [`SphereWorld`](super::SphereWorld): closed-form solids with exact signed
//! distances (boxes, spheres, cylinders, capsules).

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::model::Geometry;

use super::soa::ObstacleFrame;
use crate::error::{MotionError, Result};

/// An oriented box obstacle of a [`SphereWorld`](super::SphereWorld).
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleBox {
    /// Name, for reports.
    pub name: String,
    /// Pose of the box centre in the world frame.
    pub pose: Isometry3<f64>,
    /// Half extents along the box axes (m).
    pub half_extents: Vector3<f64>,
}

impl ObstacleBox {
    /// A box from its name, world pose and full size.
    pub fn new(name: impl Into<String>, pose: Isometry3<f64>, size: Vector3<f64>) -> Self {
        Self { name: name.into(), pose, half_extents: size * 0.5 }
    }

    /// Signed distance from a world point to the box surface (negative inside).
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        ObstacleFrame::new(&self.pose, ObstacleShape::Box { half_extents: self.half_extents })
            .signed_distance(p.x, p.y, p.z)
    }
}

/// The closed-form shape of an [`ObstaclePrimitive`], centred in its own frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ObstacleShape {
    /// A box of these half extents (m).
    Box {
        /// Half extents along the local axes (m).
        half_extents: Vector3<f64>,
    },
    /// A ball.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A solid cylinder along the local z axis.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Half the length along z (m).
        half_length: f64,
    },
    /// A capsule along the local z axis: the points within `radius` of the segment
    /// `z ∈ [−half_length, half_length]`.
    Capsule {
        /// Radius (m).
        radius: f64,
        /// Half the distance between the hemisphere centres (m).
        half_length: f64,
    },
}

/// An obstacle of a [`SphereWorld`](super::SphereWorld): a solid shape at a world pose. A
/// robot sphere hits it when the signed distance of the sphere's centre is at most the
/// sphere's radius — exact for these convex solids.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstaclePrimitive {
    /// Name, for reports.
    pub name: String,
    /// Pose of the shape's frame in the world frame.
    pub pose: Isometry3<f64>,
    /// The shape.
    pub shape: ObstacleShape,
}

impl ObstaclePrimitive {
    /// An obstacle from its name, world pose and shape.
    pub fn new(name: impl Into<String>, pose: Isometry3<f64>, shape: ObstacleShape) -> Self {
        Self { name: name.into(), pose, shape }
    }

    /// The obstacle of a core shape: `geometry` (a box, sphere, cylinder or capsule) placed at
    /// `pose` (the pose of the geometry's own frame in the world).
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`] naming the obstacle for a mesh (not a closed-form
    /// solid: the caller chooses how to bound it).
    pub fn from_geometry(name: impl Into<String>, pose: Isometry3<f64>, geometry: &Geometry) -> Result<Self> {
        let shape = match geometry {
            Geometry::Box { half_extents } => ObstacleShape::Box { half_extents: *half_extents },
            Geometry::Sphere { radius } => ObstacleShape::Sphere { radius: *radius },
            Geometry::Cylinder { radius, length } => {
                ObstacleShape::Cylinder { radius: *radius, half_length: length * 0.5 }
            }
            Geometry::Capsule { radius, length } => {
                ObstacleShape::Capsule { radius: *radius, half_length: length * 0.5 }
            }
            Geometry::Mesh(_) => {
                return Err(MotionError::InvalidParameter {
                    name: "obstacle",
                    reason: format!(
                        "`{}`: a mesh; the sphere model takes boxes, spheres, cylinders and capsules",
                        name.into()
                    ),
                })
            }
        };
        Ok(Self { name: name.into(), pose, shape })
    }

    /// Signed distance from a world point to the surface (negative inside).
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        ObstacleFrame::new(&self.pose, self.shape).signed_distance(p.x, p.y, p.z)
    }

    /// Checks that every size is finite and positive (a capsule's half length may be zero)
    /// and the pose finite.
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`] naming the obstacle.
    pub fn validate(&self) -> Result<()> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let ok = match self.shape {
            ObstacleShape::Box { half_extents: h } => positive(h.x) && positive(h.y) && positive(h.z),
            ObstacleShape::Sphere { radius } => positive(radius),
            ObstacleShape::Cylinder { radius, half_length } => positive(radius) && positive(half_length),
            ObstacleShape::Capsule { radius, half_length } => {
                positive(radius) && half_length.is_finite() && half_length >= 0.0
            }
        };
        if !ok {
            return Err(self.invalid(format!("{:?} has a size that is not a positive length", self.shape)));
        }
        let t = self.pose.translation.vector;
        let q = self.pose.rotation.coords;
        if !(t.iter().chain(q.iter()).all(|v| v.is_finite())) {
            return Err(self.invalid("the pose is not finite".into()));
        }
        Ok(())
    }

    fn invalid(&self, reason: String) -> MotionError {
        MotionError::InvalidParameter { name: "obstacle", reason: format!("`{}`: {reason}", self.name) }
    }
}

impl From<ObstacleBox> for ObstaclePrimitive {
    fn from(b: ObstacleBox) -> Self {
        Self { name: b.name, pose: b.pose, shape: ObstacleShape::Box { half_extents: b.half_extents } }
    }
}
