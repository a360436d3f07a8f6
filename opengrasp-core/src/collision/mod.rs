//! Collision, distance and contact queries on parry3d.
//!
//! A [`CollisionWorld`] is built once from a [`crate::scene::Scene`] and answers queries for a
//! robot at any configuration `q` without touching the scene:
//!
//! * [`CollisionWorld::in_collision`] / [`CollisionWorld::in_collision_unchecked`] — boolean
//!   check of the robot against the environment, free objects, other robots, itself (with the
//!   allowed-collision matrix) and of its attached objects;
//! * [`CollisionWorld::distance`] and [`CollisionWorld::link_distances`] — clearance with the
//!   closest pair and witness points;
//! * [`CollisionWorld::contacts`] and [`CollisionWorld::contacts_with_object`] — contact points,
//!   normals and depths for grasp evaluation.
//!
//! Queries take `&self` and the world is `Send + Sync`, so many threads can share one world;
//! per-thread scratch buffers are reused between calls. Static bodies sit in a parry
//! bounding-volume hierarchy ([`parry3d_f64::partitioning::Bvh`]); robot links and the few
//! movable objects are pruned by their bounding boxes before any exact test.
//!
//! Geometry follows URDF conventions (cylinders and capsules along local z); see
//! [`geometry_to_parry`] for the conversion and [`MeshRepresentation`] for meshes.
//!
//! ```
//! use std::sync::Arc;
//! use nalgebra::Isometry3;
//! use opengrasp_core::collision::CollisionWorld;
//! use opengrasp_core::model::{samples, Geometry, Shape};
//! use opengrasp_core::scene::{Scene, StaticBody};
//!
//! # fn main() -> opengrasp_core::Result<()> {
//! let mut scene = Scene::new("demo");
//! let arm = scene.add_robot("arm", Arc::new(samples::seven_dof_arm()?), Isometry3::identity())?;
//! let wall = Shape::at_origin(Geometry::cuboid(0.1, 2.0, 2.0));
//! scene.add_body(StaticBody::new("wall", Isometry3::translation(0.6, 0.0, 1.0), vec![wall]))?;
//! let world = CollisionWorld::new(&scene)?;
//! let q = [0.0; 7];
//! assert!(!world.in_collision(arm, &q)?);
//! let report = world.distance(arm, &q)?;
//! assert!((report.distance - (0.55 - 0.08)).abs() < 1e-6); // wall face at x = 0.55, base radius 0.08
//! # Ok(())
//! # }
//! ```

mod climbing;
mod shapes;
mod world;

use nalgebra::{Point3, Unit, Vector3};

use crate::model::LinkId;
use crate::scene::{BodyId, ObjectId, RobotId};

pub use climbing::ClimbingHull;
pub use shapes::{geometry_to_parry, shapes_to_parry, MeshRepresentation};
pub use world::{CollisionWorld, GapTest, NearestTriangles};

/// Something a robot can touch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Collider {
    /// A static body of the environment.
    Body(BodyId),
    /// A movable object (free, or carried by another robot).
    Object(ObjectId),
    /// A robot link: another link of the same robot (self-collision) or a link of another robot.
    Link(RobotId, LinkId),
}

/// Options of [`CollisionWorld::with_options`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollisionOptions {
    /// How triangle meshes are represented. Default: [`MeshRepresentation::Auto`] (convex hull
    /// for closed convex meshes, exact triangle mesh otherwise).
    pub meshes: MeshRepresentation,
}

impl Default for CollisionOptions {
    fn default() -> Self {
        Self { meshes: MeshRepresentation::Auto }
    }
}

/// One contact between a robot link and something else, in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The robot link.
    pub link: LinkId,
    /// What it touches.
    pub other: Collider,
    /// Contact point on the link's surface (world frame).
    pub point_on_robot: Point3<f64>,
    /// Contact point on the other surface (world frame).
    pub point_on_other: Point3<f64>,
    /// Unit normal pointing from the other body towards the robot link (world frame): moving
    /// the link along it separates the pair.
    pub normal: Unit<Vector3<f64>>,
    /// Penetration depth: `> 0` when the shapes overlap, `< 0` (minus the gap) when they are
    /// separated by less than the query margin.
    pub depth: f64,
}

/// The robot's minimum distance to its obstacles, with the closest pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceReport {
    /// Signed distance (m): the gap when separated, `0` when touching, minus the penetration
    /// depth of the most deeply penetrating pair when the robot overlaps an obstacle.
    pub distance: f64,
    /// The robot link of the closest pair (for an attached object: its carrying link).
    pub link: LinkId,
    /// `Some(object)` when the robot side of the closest pair is an attached object.
    pub attached: Option<ObjectId>,
    /// The obstacle of the closest pair.
    pub other: Collider,
    /// Witness point on the robot side (world frame). Witness points come from parry's
    /// `query::contact` (GJK/EPA, accurate to about 1e-5 m); `distance` itself is exact for
    /// capsule–box pairs.
    pub point_on_robot: Point3<f64>,
    /// Witness point on the obstacle (world frame).
    pub point_on_other: Point3<f64>,
}
