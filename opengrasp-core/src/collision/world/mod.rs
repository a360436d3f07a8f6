//! The collision world: construction and synchronisation with a scene ([`queries`] answers
//! the queries, [`narrow`] tests shape pairs).

mod bounded;
mod distances;
mod gaps;
mod mesh_distance;
mod narrow;
mod queries;

pub use distances::NearestTriangles;

use std::cell::RefCell;
use std::sync::{Arc, Weak};

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::shape::Shape as ParryShape;

use super::shapes::{shapes_to_parts, Part};
use super::{Collider, CollisionOptions};
use crate::error::{CoreError, Result};
use crate::kinematics::forward_kinematics_into;
use crate::model::{JointKind, LinkId, Robot};
use crate::scene::{BodyId, ObjectId, RobotId, Scene};

pub use gaps::GapTest;

/// A part of a static body, placed in the world.
#[derive(Clone, Debug)]
struct EnvPart {
    body: BodyId,
    pose: Isometry3<f64>,
    part: Part,
    aabb: Aabb,
}

/// An object carried by a robot link.
#[derive(Clone, Debug)]
struct AttachInfo {
    robot: RobotId,
    link: LinkId,
    /// Object frame in the link frame.
    offset: Isometry3<f64>,
    /// Links the object may touch (the carrying link, plus any added with
    /// [`CollisionWorld::allow_touch`]).
    touch: Vec<LinkId>,
}

#[derive(Clone, Debug)]
struct ObjectEntry {
    pose: Isometry3<f64>,
    parts: Vec<Part>,
    /// World pose and AABB of each part at `pose`.
    world: Vec<(Isometry3<f64>, Aabb)>,
    attached: Option<AttachInfo>,
}

impl ObjectEntry {
    fn update_world(&mut self) {
        self.world.clear();
        for p in &self.parts {
            let pose = self.pose * p.local;
            self.world.push((pose, p.shape.compute_aabb(&pose)));
        }
    }
}

#[derive(Clone, Debug)]
struct RobotEntry {
    robot: Arc<Robot>,
    base_pose: Isometry3<f64>,
    q: Vec<f64>,
    /// All collision parts of all links, link by link.
    parts: Vec<Part>,
    /// The link of each part.
    part_link: Vec<LinkId>,
    /// The range of each link's parts in `parts`, by link.
    link_parts: Vec<(u32, u32)>,
    /// Allowed-collision matrix, `n_links × n_links`, row-major.
    allowed: Vec<bool>,
    /// Part pairs `(i, j)`, `i < j`, checked for self-collision (different, non-allowed links).
    self_pairs: Vec<(u32, u32)>,
    /// World pose and AABB of each part at `(base_pose, q)`, for use as an obstacle of other
    /// robots.
    world: Vec<(Isometry3<f64>, Aabb)>,
    /// Link poses in the base frame at `q` (forward kinematics), kept so that moving the base
    /// alone (a floating hand placed at many poses) does not redo the kinematics.
    link_poses: Vec<Isometry3<f64>>,
    /// Per link: only fixed joints between it and the root, so its pose (in `link_poses`) and
    /// its parts' world poses and boxes (in `world`) are the same at every configuration;
    /// queries copy them instead of recomputing them (the same operations gave them).
    fixed_link: Vec<bool>,
}

impl RobotEntry {
    fn n_links(&self) -> usize {
        self.robot.links().len()
    }

    fn is_allowed(&self, a: LinkId, b: LinkId) -> bool {
        self.allowed[a.0 * self.n_links() + b.0]
    }

    fn rebuild_self_pairs(&mut self) {
        self.self_pairs.clear();
        for i in 0..self.parts.len() {
            for j in i + 1..self.parts.len() {
                let (a, b) = (self.part_link[i], self.part_link[j]);
                if a != b && !self.is_allowed(a, b) {
                    self.self_pairs.push((i as u32, j as u32));
                }
            }
        }
    }

    /// Recomputes the link poses at `q` and the parts' world poses and boxes.
    fn update_world(&mut self) {
        forward_kinematics_into(&self.robot, &self.q, &mut self.link_poses);
        self.place_world();
    }

    /// Recomputes the parts' world poses and boxes from `base_pose` and the stored link poses
    /// (all that changes when only the base moves).
    fn place_world(&mut self) {
        self.world.clear();
        for (p, l) in self.parts.iter().zip(&self.part_link) {
            let pose = self.base_pose * self.link_poses[l.0] * p.local;
            self.world.push((pose, p.shape.compute_aabb(&pose)));
        }
    }

    fn link_world_pose(&self, link: LinkId) -> Isometry3<f64> {
        self.base_pose * crate::kinematics::link_pose_unchecked(&self.robot, &self.q, link)
    }
}

/// Per link: true if every joint between the link and the root is fixed (the root included).
fn fixed_links(robot: &Robot) -> Vec<bool> {
    let mut fixed = vec![true; robot.links().len()];
    for &j in robot.joints_topological() {
        let joint = robot.joint(j);
        fixed[joint.child.0] = fixed[joint.parent.0] && joint.kind == JointKind::Fixed;
    }
    fixed
}

/// Who a moving item (a shape that follows the queried robot) belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Owner {
    /// Part `part` of the robot (on link `link`).
    Link { part: u32 },
    /// Part `part` of an attached object.
    Attached { object: u32, part: u32 },
}

/// A shape that moves with the queried robot, placed at the query configuration.
#[derive(Clone, Copy, Debug)]
struct Item {
    owner: Owner,
    /// The robot link (the carrying link for attached objects).
    link: LinkId,
    pose: Isometry3<f64>,
    aabb: Aabb,
}

/// Reusable per-thread buffers.
#[derive(Default)]
struct Scratch {
    link_poses: Vec<Isometry3<f64>>,
    /// Per link: placed by the current query (see `CollisionWorld::place_links`).
    links: Vec<bool>,
    /// Per joint: on the chain of a placed link.
    joints: Vec<bool>,
    items: Vec<Item>,
    /// `(lower bound, item index)` for the distance search.
    order: Vec<(f64, u32)>,
    /// The robot (held weakly, so its address is not reused while it is remembered) and the
    /// configuration `link_poses` holds root-frame poses of, and per link whether its entry
    /// holds that pose: `place_links` computes only the missing ones (the same operations on
    /// the same inputs would give the same bits), so queries of several worlds or rounds at
    /// one configuration share the forward kinematics.
    fk_robot: Weak<Robot>,
    fk_q: Vec<f64>,
    fk_posed: Vec<bool>,
}

/// The nearest obstacle found by a distance search.
struct Nearest<'a> {
    distance: f64,
    id: Collider,
    pose: Isometry3<f64>,
    shape: &'a dyn ParryShape,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut s) => f(&mut s),
        // Only reachable by re-entrance; fall back to fresh buffers.
        Err(_) => f(&mut Scratch::default()),
    })
}

/// An obstacle seen by the queried robot.
struct Obstacle<'a> {
    id: Collider,
    pose: &'a Isometry3<f64>,
    shape: &'a dyn ParryShape,
    /// The convex hull of a triangle-mesh shape (see `Part::hull`).
    hull: Option<&'a dyn ParryShape>,
    aabb: &'a Aabb,
}

impl<'a> Obstacle<'a> {
    fn placed(&self) -> narrow::Placed<'a> {
        narrow::Placed { pose: self.pose, shape: self.shape, hull: self.hull }
    }
}

/// Collision, distance and contact queries against a [`Scene`].
///
/// Built from a scene with [`CollisionWorld::new`]; it then holds its own copy of every pose,
/// configuration and attachment. Keep it in sync with the scene through the mirrors of the
/// scene's setters — [`set_object_pose`](Self::set_object_pose),
/// [`set_robot_base_pose`](Self::set_robot_base_pose),
/// [`set_robot_configuration`](Self::set_robot_configuration), [`attach`](Self::attach),
/// [`detach`](Self::detach) — or by calling [`sync`](Self::sync) after editing the scene.
/// Queries take the queried robot's configuration as an argument; other robots stand at their
/// stored configuration and are obstacles like the objects.
///
/// What each robot query covers, for robot `R` at configuration `q`:
/// * `R`'s links against the static bodies, the objects not carried by `R`, and the links of
///   other robots;
/// * `R`'s links against each other, except allowed pairs (same link, adjacent links and the
///   robot's explicitly allowed pairs, plus pairs allowed with
///   [`allow_collision`](Self::allow_collision));
/// * objects carried by `R` (they follow their link) against the same obstacles, and against
///   `R`'s links except their carrying link (and links added with
///   [`allow_touch`](Self::allow_touch)).
#[derive(Clone, Debug)]
pub struct CollisionWorld {
    options: CollisionOptions,
    /// World pose of each static body (to detect changes in [`CollisionWorld::sync`]).
    body_poses: Vec<Isometry3<f64>>,
    env: Vec<EnvPart>,
    env_bvh: Bvh,
    objects: Vec<ObjectEntry>,
    robots: Vec<RobotEntry>,
}

impl CollisionWorld {
    /// Builds the world from a scene with default options.
    ///
    /// # Errors
    /// [`CoreError::InvalidGeometry`] or [`CoreError::DegenerateMesh`] if a shape cannot be
    /// converted; [`CoreError::InvalidHandle`] for an attachment referring to a missing robot or
    /// object.
    pub fn new(scene: &Scene) -> Result<Self> {
        Self::with_options(scene, CollisionOptions::default())
    }

    /// Builds the world from a scene.
    ///
    /// # Errors
    /// As [`CollisionWorld::new`].
    pub fn with_options(scene: &Scene, options: CollisionOptions) -> Result<Self> {
        let mut env = Vec::new();
        for (i, body) in scene.bodies().iter().enumerate() {
            for part in shapes_to_parts(&body.shapes, options.meshes)? {
                let pose = body.pose * part.local;
                let aabb = part.shape.compute_aabb(&pose);
                env.push(EnvPart { body: BodyId(i), pose, part, aabb });
            }
        }
        let env_bvh = Bvh::from_iter(BvhBuildStrategy::Binned, env.iter().enumerate().map(|(i, p)| (i, p.aabb)));
        let mut objects = Vec::with_capacity(scene.objects().len());
        for o in scene.objects() {
            let mut entry = ObjectEntry {
                pose: o.pose,
                parts: shapes_to_parts(&o.shapes, options.meshes)?,
                world: Vec::new(),
                attached: None,
            };
            entry.update_world();
            objects.push(entry);
        }
        let mut robots = Vec::with_capacity(scene.robots().len());
        for r in scene.robots() {
            let robot = r.robot.clone();
            let n = robot.links().len();
            let mut parts = Vec::new();
            let mut part_link = Vec::new();
            let mut link_parts = Vec::with_capacity(n);
            for (l, link) in robot.links().iter().enumerate() {
                let start = parts.len() as u32;
                for p in shapes_to_parts(&link.collisions, options.meshes)? {
                    parts.push(p);
                    part_link.push(LinkId(l));
                }
                link_parts.push((start, parts.len() as u32));
            }
            let mut allowed = vec![false; n * n];
            for a in 0..n {
                for b in 0..n {
                    allowed[a * n + b] = robot.is_collision_allowed(LinkId(a), LinkId(b));
                }
            }
            let mut entry = RobotEntry {
                robot,
                base_pose: r.base_pose,
                q: r.q.clone(),
                parts,
                part_link,
                link_parts,
                allowed,
                self_pairs: Vec::new(),
                world: Vec::new(),
                link_poses: Vec::new(),
                fixed_link: fixed_links(&r.robot),
            };
            entry.rebuild_self_pairs();
            entry.update_world();
            robots.push(entry);
        }
        let body_poses = scene.bodies().iter().map(|b| b.pose).collect();
        let mut world = Self { options, body_poses, env, env_bvh, objects, robots };
        for a in scene.attachments() {
            world.robot_entry(a.robot)?;
            world.object_entry(a.object)?;
            world.objects[a.object.0].attached =
                Some(AttachInfo { robot: a.robot, link: a.link, offset: a.offset, touch: vec![a.link] });
        }
        for r in 0..world.robots.len() {
            world.update_attached(RobotId(r));
        }
        Ok(world)
    }

    /// The options the world was built with.
    pub fn options(&self) -> &CollisionOptions {
        &self.options
    }

    /// Number of static collision parts (leaves of the bounding-volume hierarchy).
    pub fn static_part_count(&self) -> usize {
        self.env.len()
    }

    fn robot_entry(&self, id: RobotId) -> Result<&RobotEntry> {
        self.robots.get(id.0).ok_or(CoreError::InvalidHandle { kind: "robot", index: id.0 })
    }

    fn object_entry(&self, id: ObjectId) -> Result<&ObjectEntry> {
        self.objects.get(id.0).ok_or(CoreError::InvalidHandle { kind: "object", index: id.0 })
    }

    fn check_link(&self, robot: RobotId, link: LinkId) -> Result<()> {
        let n = self.robot_entry(robot)?.n_links();
        if link.0 < n {
            Ok(())
        } else {
            Err(CoreError::InvalidHandle { kind: "link", index: link.0 })
        }
    }

    fn update_attached(&mut self, robot: RobotId) {
        let Self { objects, robots, .. } = self;
        let r = &robots[robot.0];
        for o in objects.iter_mut() {
            if let Some(a) = o.attached.as_ref().filter(|a| a.robot == robot) {
                o.pose = r.link_world_pose(a.link) * a.offset;
                o.update_world();
            }
        }
    }

    // ----------------------------------------------------------------------------------------
    // Synchronisation
    // ----------------------------------------------------------------------------------------

    /// Moves an object (mirror of [`Scene::set_object_pose`]): an attached object is detached
    /// first.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or [`CoreError::NonFinite`].
    pub fn set_object_pose(&mut self, object: ObjectId, pose: Isometry3<f64>) -> Result<()> {
        self.object_entry(object)?;
        crate::error::ensure_finite_pose("object pose", &pose)?;
        let o = &mut self.objects[object.0];
        o.attached = None;
        o.pose = pose;
        o.update_world();
        Ok(())
    }

    /// Moves a robot's base (mirror of [`Scene::set_robot_base_pose`]); its attached objects
    /// follow.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or [`CoreError::NonFinite`].
    pub fn set_robot_base_pose(&mut self, robot: RobotId, pose: Isometry3<f64>) -> Result<()> {
        self.robot_entry(robot)?;
        crate::error::ensure_finite_pose("robot base pose", &pose)?;
        let r = &mut self.robots[robot.0];
        r.base_pose = pose;
        r.place_world();
        self.update_attached(robot);
        Ok(())
    }

    /// Sets a robot's stored configuration (mirror of [`Scene::set_robot_configuration`]): the
    /// pose of the robot as an obstacle of other robots, and of its attached objects.
    /// Queries on this robot take their own `q` and ignore the stored one.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or the errors of [`Robot::validate_configuration`].
    pub fn set_robot_configuration(&mut self, robot: RobotId, q: &[f64]) -> Result<()> {
        self.robot_entry(robot)?.robot.validate_configuration(q)?;
        let r = &mut self.robots[robot.0];
        r.q.clear();
        r.q.extend_from_slice(q);
        r.update_world();
        self.update_attached(robot);
        Ok(())
    }

    /// Rigidly attaches an object to a robot link at their current relative pose (mirror of
    /// [`Scene::attach`], with the link by id). The object then moves with the link in queries
    /// and may touch the carrying link.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for a bad robot, object or link, or
    /// [`CoreError::InvalidParameter`] if the object is already attached.
    pub fn attach(&mut self, object: ObjectId, robot: RobotId, link: LinkId) -> Result<()> {
        self.check_link(robot, link)?;
        let o = self.object_entry(object)?;
        if o.attached.is_some() {
            return Err(CoreError::InvalidParameter {
                name: "object".into(),
                reason: format!("object {} is already attached", object.0),
            });
        }
        let offset = self.robots[robot.0].link_world_pose(link).inverse() * o.pose;
        self.objects[object.0].attached = Some(AttachInfo { robot, link, offset, touch: vec![link] });
        Ok(())
    }

    /// Detaches an object; it stays where its link left it (mirror of [`Scene::detach`]).
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] if the object does not exist or is not attached.
    pub fn detach(&mut self, object: ObjectId) -> Result<()> {
        self.object_entry(object)?;
        match self.objects[object.0].attached.take() {
            Some(_) => Ok(()),
            None => Err(CoreError::InvalidHandle { kind: "attachment", index: object.0 }),
        }
    }

    /// Lets an attached object touch another link of its carrier besides the carrying link
    /// (e.g. the fingers holding it). The permission ends when the object is detached.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] if the object is not attached or the link does not exist.
    pub fn allow_touch(&mut self, object: ObjectId, link: LinkId) -> Result<()> {
        let robot = match self.object_entry(object)?.attached.as_ref() {
            Some(a) => a.robot,
            None => return Err(CoreError::InvalidHandle { kind: "attachment", index: object.0 }),
        };
        self.check_link(robot, link)?;
        if let Some(a) = self.objects[object.0].attached.as_mut() {
            if !a.touch.contains(&link) {
                a.touch.push(link);
            }
        }
        Ok(())
    }

    /// Allows collisions between two links of a robot in this world (on top of the robot's own
    /// allowed pairs), e.g. for a pair that always touches.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for a bad robot or link.
    pub fn allow_collision(&mut self, robot: RobotId, a: LinkId, b: LinkId) -> Result<()> {
        self.check_link(robot, a)?;
        self.check_link(robot, b)?;
        let r = &mut self.robots[robot.0];
        let n = r.n_links();
        r.allowed[a.0 * n + b.0] = true;
        r.allowed[b.0 * n + a.0] = true;
        r.rebuild_self_pairs();
        Ok(())
    }

    /// True if collisions between two links of a robot are ignored in this world.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for a bad robot or link.
    pub fn is_collision_allowed(&self, robot: RobotId, a: LinkId, b: LinkId) -> Result<bool> {
        self.check_link(robot, a)?;
        self.check_link(robot, b)?;
        Ok(self.robots[robot.0].is_allowed(a, b))
    }

    /// Number of link-part pairs checked for self-collision of a robot (after removing
    /// allowed pairs).
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    pub fn self_collision_pair_count(&self, robot: RobotId) -> Result<usize> {
        Ok(self.robot_entry(robot)?.self_pairs.len())
    }

    /// Brings the world up to date with `scene` after it was edited: object poses, robot base
    /// poses, stored configurations and attachments are copied (touch links added with
    /// [`allow_touch`](Self::allow_touch) are kept for attachments that did not change). If the
    /// scene's structure differs — bodies, objects or robots added, a body moved, an object's
    /// shape count or a robot model changed — the world is rebuilt from scratch instead, which
    /// drops pairs allowed with [`allow_collision`](Self::allow_collision) and touch links.
    ///
    /// # Errors
    /// As [`CollisionWorld::new`].
    pub fn sync(&mut self, scene: &Scene) -> Result<()> {
        let same_structure = scene.bodies().len() == self.body_poses.len()
            && scene.bodies().iter().zip(&self.body_poses).all(|(b, p)| b.pose == *p)
            && scene.bodies().iter().map(|b| b.shapes.len()).sum::<usize>() == self.env.len()
            && scene.objects().len() == self.objects.len()
            && scene.objects().iter().zip(&self.objects).all(|(s, w)| s.shapes.len() == w.parts.len())
            && scene.robots().len() == self.robots.len()
            && scene.robots().iter().zip(&self.robots).all(|(s, w)| Arc::ptr_eq(&s.robot, &w.robot));
        if !same_structure {
            *self = Self::with_options(scene, self.options)?;
            return Ok(());
        }
        for (i, (o, so)) in self.objects.iter_mut().zip(scene.objects()).enumerate() {
            let old = o.attached.take();
            o.pose = so.pose;
            o.update_world();
            if let Some(a) = scene.attachments().iter().find(|a| a.object.0 == i) {
                let touch = match old {
                    Some(old) if old.robot == a.robot && old.link == a.link => old.touch,
                    _ => vec![a.link],
                };
                o.attached = Some(AttachInfo { robot: a.robot, link: a.link, offset: a.offset, touch });
            }
        }
        for (r, sr) in self.robots.iter_mut().zip(scene.robots()) {
            r.base_pose = sr.base_pose;
            r.q.clone_from(&sr.q);
            r.update_world();
        }
        for r in 0..self.robots.len() {
            self.update_attached(RobotId(r));
        }
        Ok(())
    }
}

// The world is shared between threads (benchmarks, parallel planners).
const _: fn() = || {
    fn is_send_sync<T: Send + Sync>() {}
    is_send_sync::<CollisionWorld>();
};

#[cfg(test)]
mod tests;
