//! Scenes: static environment bodies, movable objects, robots and attachments.
//!
//! A [`Scene`] is plain data. Collision queries build a `collision::CollisionWorld` from it,
//! and physics backends build their world from it too.

use std::sync::Arc;

use nalgebra::{Isometry3, Matrix3, Point3};

use crate::error::{CoreError, Result};
use crate::kinematics::link_pose_unchecked;
use crate::model::{LinkId, Robot, Shape};

/// Handle of a static body in a [`Scene`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub usize);
/// Handle of a movable object in a [`Scene`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ObjectId(pub usize);
/// Handle of a robot in a [`Scene`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RobotId(pub usize);

/// A fixed part of the environment (wall, table, cabinet).
#[derive(Clone, Debug, PartialEq)]
pub struct StaticBody {
    /// Unique name within the scene.
    pub name: String,
    /// Pose in the world frame.
    pub pose: Isometry3<f64>,
    /// Collision (and display) geometry in the body frame.
    pub shapes: Vec<Shape>,
    /// Coulomb friction coefficient.
    pub friction: f64,
}

impl StaticBody {
    /// A static body with friction 0.8.
    pub fn new(name: impl Into<String>, pose: Isometry3<f64>, shapes: Vec<Shape>) -> Self {
        Self { name: name.into(), pose, shapes, friction: 0.8 }
    }
}

/// A movable rigid object (a cup, a box) that can be grasped and carried.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneObject {
    /// Unique name within the scene.
    pub name: String,
    /// Pose of the object frame in the world frame.
    pub pose: Isometry3<f64>,
    /// Geometry in the object frame.
    pub shapes: Vec<Shape>,
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass in the object frame.
    pub center_of_mass: Point3<f64>,
    /// Inertia tensor about the centre of mass, object axes (kg·m²).
    pub inertia: Matrix3<f64>,
    /// Coulomb friction coefficient.
    pub friction: f64,
}

/// A robot placed in the scene with its base pose and current configuration.
#[derive(Clone, Debug)]
pub struct SceneRobot {
    /// Unique name within the scene.
    pub name: String,
    /// The model (shared, immutable).
    pub robot: Arc<Robot>,
    /// Pose of the robot's root link in the world frame.
    pub base_pose: Isometry3<f64>,
    /// Current configuration (one value per actuated joint).
    pub q: Vec<f64>,
}

/// An object rigidly carried by a robot link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attachment {
    /// The carried object.
    pub object: ObjectId,
    /// The carrying robot.
    pub robot: RobotId,
    /// The carrying link.
    pub link: LinkId,
    /// Pose of the object frame in the link frame.
    pub offset: Isometry3<f64>,
}

/// Environment, objects and robots in one world frame (z up, metres).
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// The scene's name.
    pub name: String,
    bodies: Vec<StaticBody>,
    objects: Vec<SceneObject>,
    robots: Vec<SceneRobot>,
    attachments: Vec<Attachment>,
}

fn check_unique<'a>(kind: &str, name: &str, mut existing: impl Iterator<Item = &'a str>) -> Result<()> {
    if existing.any(|n| n == name) {
        Err(CoreError::InvalidParameter {
            name: format!("{kind} name"),
            reason: format!("`{name}` already in the scene"),
        })
    } else {
        Ok(())
    }
}

impl Scene {
    /// An empty scene.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Self::default() }
    }

    /// Adds a static body.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for a duplicate name, [`CoreError::NonFinite`] for a bad
    /// pose, [`CoreError::InvalidGeometry`] for bad shapes.
    pub fn add_body(&mut self, body: StaticBody) -> Result<BodyId> {
        check_unique("body", &body.name, self.bodies.iter().map(|b| b.name.as_str()))?;
        crate::error::ensure_finite_pose(&format!("pose of body `{}`", body.name), &body.pose)?;
        for s in &body.shapes {
            s.geometry.validate()?;
        }
        self.bodies.push(body);
        Ok(BodyId(self.bodies.len() - 1))
    }

    /// Adds a movable object.
    ///
    /// # Errors
    /// As [`Scene::add_body`], plus [`CoreError::InvalidParameter`] for a non-positive mass or
    /// negative friction.
    pub fn add_object(&mut self, object: SceneObject) -> Result<ObjectId> {
        check_unique("object", &object.name, self.objects.iter().map(|o| o.name.as_str()))?;
        crate::error::ensure_finite_pose(&format!("pose of object `{}`", object.name), &object.pose)?;
        if !(object.mass.is_finite() && object.mass > 0.0) {
            return Err(CoreError::InvalidParameter {
                name: "mass".into(),
                reason: format!("object `{}` has mass {}", object.name, object.mass),
            });
        }
        if !(object.friction.is_finite() && object.friction >= 0.0) {
            return Err(CoreError::InvalidParameter {
                name: "friction".into(),
                reason: format!("object `{}` has friction {}", object.name, object.friction),
            });
        }
        for s in &object.shapes {
            s.geometry.validate()?;
        }
        self.objects.push(object);
        Ok(ObjectId(self.objects.len() - 1))
    }

    /// Adds a robot at `base_pose` in its home configuration.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for a duplicate name, [`CoreError::NonFinite`] for a bad
    /// pose.
    pub fn add_robot(
        &mut self,
        name: impl Into<String>,
        robot: Arc<Robot>,
        base_pose: Isometry3<f64>,
    ) -> Result<RobotId> {
        let name = name.into();
        check_unique("robot", &name, self.robots.iter().map(|r| r.name.as_str()))?;
        crate::error::ensure_finite_pose(&format!("base pose of robot `{name}`"), &base_pose)?;
        let q = robot.home_configuration();
        self.robots.push(SceneRobot { name, robot, base_pose, q });
        Ok(RobotId(self.robots.len() - 1))
    }

    /// Static bodies, indexed by [`BodyId`].
    pub fn bodies(&self) -> &[StaticBody] {
        &self.bodies
    }
    /// Movable objects, indexed by [`ObjectId`].
    pub fn objects(&self) -> &[SceneObject] {
        &self.objects
    }
    /// Robots, indexed by [`RobotId`].
    pub fn robots(&self) -> &[SceneRobot] {
        &self.robots
    }
    /// Current attachments.
    pub fn attachments(&self) -> &[Attachment] {
        &self.attachments
    }
    /// True if the scene has no bodies, objects or robots.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty() && self.objects.is_empty() && self.robots.is_empty()
    }

    /// One static body.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    pub fn body(&self, id: BodyId) -> Result<&StaticBody> {
        self.bodies.get(id.0).ok_or(CoreError::InvalidHandle { kind: "body", index: id.0 })
    }
    /// One object.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    pub fn object(&self, id: ObjectId) -> Result<&SceneObject> {
        self.objects.get(id.0).ok_or(CoreError::InvalidHandle { kind: "object", index: id.0 })
    }
    /// One robot.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    pub fn robot(&self, id: RobotId) -> Result<&SceneRobot> {
        self.robots.get(id.0).ok_or(CoreError::InvalidHandle { kind: "robot", index: id.0 })
    }

    /// A static body's handle by name (`None` if absent).
    pub fn body_id(&self, name: &str) -> Option<BodyId> {
        self.bodies.iter().position(|b| b.name == name).map(BodyId)
    }
    /// An object's handle by name (`None` if absent).
    pub fn object_id(&self, name: &str) -> Option<ObjectId> {
        self.objects.iter().position(|o| o.name == name).map(ObjectId)
    }
    /// A robot's handle by name (`None` if absent).
    pub fn robot_id(&self, name: &str) -> Option<RobotId> {
        self.robots.iter().position(|r| r.name == name).map(RobotId)
    }

    /// Sets a robot's configuration (validated against its limits); attached objects follow.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or the configuration errors of
    /// [`Robot::validate_configuration`].
    pub fn set_robot_configuration(&mut self, id: RobotId, q: &[f64]) -> Result<()> {
        self.robot(id)?.robot.validate_configuration(q)?;
        self.robots[id.0].q = q.to_vec();
        self.update_attached(id);
        Ok(())
    }

    /// Sets a robot's base pose; attached objects follow.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or [`CoreError::NonFinite`].
    pub fn set_robot_base_pose(&mut self, id: RobotId, pose: Isometry3<f64>) -> Result<()> {
        self.robot(id)?;
        crate::error::ensure_finite_pose("robot base pose", &pose)?;
        self.robots[id.0].base_pose = pose;
        self.update_attached(id);
        Ok(())
    }

    /// Sets an object's pose in the world frame (an attached object is detached first).
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or [`CoreError::NonFinite`].
    pub fn set_object_pose(&mut self, id: ObjectId, pose: Isometry3<f64>) -> Result<()> {
        self.object(id)?;
        crate::error::ensure_finite_pose("object pose", &pose)?;
        self.attachments.retain(|a| a.object != id);
        self.objects[id.0].pose = pose;
        Ok(())
    }

    /// World pose of a robot link at the robot's current configuration.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or [`CoreError::UnknownLink`].
    pub fn link_world_pose(&self, id: RobotId, link: &str) -> Result<Isometry3<f64>> {
        let r = self.robot(id)?;
        let l = r.robot.link_id(link)?;
        Ok(r.base_pose * link_pose_unchecked(&r.robot, &r.q, l))
    }

    /// Rigidly attaches an object to a robot link at their current relative pose (for carrying).
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`], [`CoreError::UnknownLink`], or
    /// [`CoreError::InvalidParameter`] if the object is already attached.
    pub fn attach(&mut self, object: ObjectId, robot: RobotId, link: &str) -> Result<()> {
        let obj_pose = self.object(object)?.pose;
        if self.attachments.iter().any(|a| a.object == object) {
            return Err(CoreError::InvalidParameter {
                name: "object".into(),
                reason: format!("object {} is already attached", object.0),
            });
        }
        let link_pose = self.link_world_pose(robot, link)?;
        let link_id = self.robots[robot.0].robot.link_id(link)?;
        self.attachments.push(Attachment { object, robot, link: link_id, offset: link_pose.inverse() * obj_pose });
        Ok(())
    }

    /// Detaches an object; it stays where the link left it.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] if the object does not exist or is not attached.
    pub fn detach(&mut self, object: ObjectId) -> Result<()> {
        self.object(object)?;
        let before = self.attachments.len();
        self.attachments.retain(|a| a.object != object);
        if self.attachments.len() == before {
            return Err(CoreError::InvalidHandle { kind: "attachment", index: object.0 });
        }
        Ok(())
    }

    /// The attachment carrying `object`, if any.
    pub fn attachment_of(&self, object: ObjectId) -> Option<&Attachment> {
        self.attachments.iter().find(|a| a.object == object)
    }

    fn update_attached(&mut self, id: RobotId) {
        let r = &self.robots[id.0];
        for a in self.attachments.iter().filter(|a| a.robot == id) {
            let pose = r.base_pose * link_pose_unchecked(&r.robot, &r.q, a.link) * a.offset;
            self.objects[a.object.0].pose = pose;
        }
    }
}

impl SceneObject {
    /// An object with uniform density: mass properties computed from its first shape's volume
    /// (inertia of the bounding box), friction 0.5.
    pub fn new(name: impl Into<String>, pose: Isometry3<f64>, shapes: Vec<Shape>, mass: f64) -> Self {
        let (center_of_mass, inertia) = match shapes.first() {
            Some(s) => {
                let (lo, hi) = s.geometry.local_aabb();
                let size = hi - lo;
                let centre = s.origin * nalgebra::center(&lo, &hi);
                let box_inertia = crate::model::Inertial::solid_box(mass, size, Isometry3::identity()).inertia;
                let r = s.origin.rotation.to_rotation_matrix();
                (centre, r.matrix() * box_inertia * r.matrix().transpose())
            }
            None => (Point3::origin(), Matrix3::identity() * 1e-6),
        };
        Self { name: name.into(), pose, shapes, mass, center_of_mass, inertia, friction: 0.5 }
    }
}
