//! The collision world: construction, synchronisation with a scene, and queries.

use std::cell::RefCell;
use std::ops::ControlFlow;
use std::sync::Arc;

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, TraversalAction};
use parry3d_f64::query;
use parry3d_f64::shape::Shape as ParryShape;

use super::shapes::{shapes_to_parts, Part};
use super::{Collider, CollisionOptions, Contact, DistanceReport};
use crate::error::{ensure_finite, CoreError, Result};
use crate::kinematics::forward_kinematics_into;
use crate::model::{LinkId, Robot};
use crate::scene::{BodyId, ObjectId, RobotId, Scene};

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
    /// Allowed-collision matrix, `n_links × n_links`, row-major.
    allowed: Vec<bool>,
    /// Part pairs `(i, j)`, `i < j`, checked for self-collision (different, non-allowed links).
    self_pairs: Vec<(u32, u32)>,
    /// World pose and AABB of each part at `(base_pose, q)`, for use as an obstacle of other
    /// robots.
    world: Vec<(Isometry3<f64>, Aabb)>,
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

    fn update_world(&mut self, link_poses: &mut Vec<Isometry3<f64>>) {
        forward_kinematics_into(&self.robot, &self.q, link_poses);
        self.world.clear();
        for (p, l) in self.parts.iter().zip(&self.part_link) {
            let pose = self.base_pose * link_poses[l.0] * p.local;
            self.world.push((pose, p.shape.compute_aabb(&pose)));
        }
    }

    fn link_world_pose(&self, link: LinkId) -> Isometry3<f64> {
        self.base_pose * crate::kinematics::link_pose_unchecked(&self.robot, &self.q, link)
    }
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
    items: Vec<Item>,
    /// `(lower bound, item index)` for the distance search.
    order: Vec<(f64, u32)>,
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

/// Euclidean distance between two AABBs (0 when they overlap): a lower bound of the distance
/// between anything they contain.
fn aabb_distance(a: &Aabb, b: &Aabb) -> f64 {
    let lo = b.mins - a.maxs;
    let hi = a.mins - b.maxs;
    let gap = lo.sup(&hi).sup(&nalgebra::Vector3::zeros());
    gap.norm()
}

/// Conservative intersection test: an unsupported shape pair falls back to the distance query,
/// and counts as colliding if that is unsupported too.
fn intersects(p1: &Isometry3<f64>, s1: &dyn ParryShape, p2: &Isometry3<f64>, s2: &dyn ParryShape) -> bool {
    match query::intersection_test(p1, s1, p2, s2) {
        Ok(hit) => hit,
        Err(_) => distance(p1, s1, p2, s2).is_none_or(|d| d <= 0.0),
    }
}

/// Exact distance (0 when overlapping), `None` for unsupported shape pairs.
///
/// parry3d 0.25.3's cuboid–cuboid distance (`distance_cuboid_cuboid`) transforms the second
/// witness point twice and over-estimates separations, so box pairs go through GJK instead.
/// Capsule–cuboid pairs (robot links against boxes, the common case) use the closed form of
/// [`capsule_cuboid_distance`], several times faster than GJK.
fn distance(p1: &Isometry3<f64>, s1: &dyn ParryShape, p2: &Isometry3<f64>, s2: &dyn ParryShape) -> Option<f64> {
    if let (Some(c1), Some(c2)) = (s1.as_cuboid(), s2.as_cuboid()) {
        return Some(query::details::distance_support_map_support_map(&p1.inv_mul(p2), c1, c2));
    }
    if let (Some(c), Some(b)) = (s1.as_capsule(), s2.as_cuboid()) {
        return Some(capsule_cuboid_distance(p1, c, p2, b));
    }
    if let (Some(b), Some(c)) = (s1.as_cuboid(), s2.as_capsule()) {
        return Some(capsule_cuboid_distance(p2, c, p1, b));
    }
    query::distance(p1, s1, p2, s2).ok()
}

/// Distance between a capsule and a cuboid (0 when they overlap), in closed form.
///
/// In the box frame, the squared distance from the capsule's axis point `p(t) = a + t d` to the
/// box is `Σᵢ max(|pᵢ(t)| − hᵢ, 0)²`: convex and quadratic between the parameters where a
/// coordinate crosses a face plane (`pᵢ(t) = ±hᵢ`). Minimising the quadratic on each of these
/// (at most seven) intervals gives the axis–box distance exactly; the capsule radius is then
/// subtracted.
fn capsule_cuboid_distance(
    capsule_pose: &Isometry3<f64>,
    capsule: &parry3d_f64::shape::Capsule,
    box_pose: &Isometry3<f64>,
    cuboid: &parry3d_f64::shape::Cuboid,
) -> f64 {
    let to_box = box_pose.inv_mul(capsule_pose);
    let a = to_box * capsule.segment.a;
    let d = to_box * capsule.segment.b - a;
    let h = cuboid.half_extents;
    let mut breaks = [0.0_f64; 8];
    let mut n = 0;
    breaks[n] = 0.0;
    n += 1;
    for i in 0..3 {
        if d[i] != 0.0 {
            for face in [-h[i], h[i]] {
                let t = (face - a[i]) / d[i];
                if t > 0.0 && t < 1.0 {
                    breaks[n] = t;
                    n += 1;
                }
            }
        }
    }
    breaks[n] = 1.0;
    n += 1;
    let breaks = &mut breaks[..n];
    breaks.sort_unstable_by(f64::total_cmp);
    let sq_dist = |t: f64| -> f64 {
        (0..3)
            .map(|i| {
                let excess = (a[i] + t * d[i]).abs() - h[i];
                if excess > 0.0 {
                    excess * excess
                } else {
                    0.0
                }
            })
            .sum()
    };
    let mut best = sq_dist(0.0).min(sq_dist(1.0));
    for w in breaks.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        if t1 <= t0 {
            continue;
        }
        // Active faces are fixed on the interval: g(t) = Σ (c + t e)² over active axes.
        let mid = 0.5 * (t0 + t1);
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..3 {
            let p = a[i] + mid * d[i];
            if p.abs() > h[i] {
                let sign = p.signum();
                let (c, e) = (sign * a[i] - h[i], sign * d[i]);
                num -= c * e;
                den += e * e;
            }
        }
        let t = if den > 0.0 { (num / den).clamp(t0, t1) } else { mid };
        best = best.min(sq_dist(t));
    }
    (best.sqrt() - capsule.radius).max(0.0)
}

fn check_pose(what: &str, pose: &Isometry3<f64>) -> Result<()> {
    ensure_finite(what, pose.translation.vector.iter().chain(pose.rotation.coords.iter()).copied())
}

/// An obstacle seen by the queried robot.
struct Obstacle<'a> {
    id: Collider,
    pose: &'a Isometry3<f64>,
    shape: &'a dyn ParryShape,
    aabb: &'a Aabb,
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
        let mut link_poses = Vec::new();
        for r in scene.robots() {
            let robot = r.robot.clone();
            let n = robot.links().len();
            let mut parts = Vec::new();
            let mut part_link = Vec::new();
            for (l, link) in robot.links().iter().enumerate() {
                for p in shapes_to_parts(&link.collisions, options.meshes)? {
                    parts.push(p);
                    part_link.push(LinkId(l));
                }
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
                allowed,
                self_pairs: Vec::new(),
                world: Vec::new(),
            };
            entry.rebuild_self_pairs();
            entry.update_world(&mut link_poses);
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
        check_pose("object pose", &pose)?;
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
        check_pose("robot base pose", &pose)?;
        let mut buf = Vec::new();
        let r = &mut self.robots[robot.0];
        r.base_pose = pose;
        r.update_world(&mut buf);
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
        let mut buf = Vec::new();
        let r = &mut self.robots[robot.0];
        r.q.clear();
        r.q.extend_from_slice(q);
        r.update_world(&mut buf);
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
        let mut buf = Vec::new();
        for (r, sr) in self.robots.iter_mut().zip(scene.robots()) {
            r.base_pose = sr.base_pose;
            r.q.clone_from(&sr.q);
            r.update_world(&mut buf);
        }
        for r in 0..self.robots.len() {
            self.update_attached(RobotId(r));
        }
        Ok(())
    }

    // ----------------------------------------------------------------------------------------
    // Query machinery
    // ----------------------------------------------------------------------------------------

    /// Places every part of robot `rid` (and of its attached objects) at configuration `q`.
    fn place(&self, rid: usize, q: &[f64], scratch: &mut Scratch) {
        let r = &self.robots[rid];
        forward_kinematics_into(&r.robot, q, &mut scratch.link_poses);
        scratch.items.clear();
        for (i, (p, l)) in r.parts.iter().zip(&r.part_link).enumerate() {
            let pose = r.base_pose * scratch.link_poses[l.0] * p.local;
            let aabb = p.shape.compute_aabb(&pose);
            scratch.items.push(Item { owner: Owner::Link { part: i as u32 }, link: *l, pose, aabb });
        }
        for (oi, o) in self.objects.iter().enumerate() {
            if let Some(a) = o.attached.as_ref().filter(|a| a.robot.0 == rid) {
                let obj_pose = r.base_pose * scratch.link_poses[a.link.0] * a.offset;
                for (pi, p) in o.parts.iter().enumerate() {
                    let pose = obj_pose * p.local;
                    let aabb = p.shape.compute_aabb(&pose);
                    scratch.items.push(Item {
                        owner: Owner::Attached { object: oi as u32, part: pi as u32 },
                        link: a.link,
                        pose,
                        aabb,
                    });
                }
            }
        }
    }

    fn item_shape(&self, rid: usize, item: &Item) -> &dyn ParryShape {
        match item.owner {
            Owner::Link { part } => &*self.robots[rid].parts[part as usize].shape,
            Owner::Attached { object, part } => &*self.objects[object as usize].parts[part as usize].shape,
        }
    }

    /// Visits the movable obstacles of robot `rid`: objects it does not carry and the parts of
    /// other robots.
    fn visit_dynamic<'a>(&'a self, rid: usize, mut f: impl FnMut(Obstacle<'a>) -> ControlFlow<()>) -> ControlFlow<()> {
        for (oi, o) in self.objects.iter().enumerate() {
            if o.attached.as_ref().is_some_and(|a| a.robot.0 == rid) {
                continue;
            }
            for (p, (pose, aabb)) in o.parts.iter().zip(&o.world) {
                f(Obstacle { id: Collider::Object(ObjectId(oi)), pose, shape: &*p.shape, aabb })?;
            }
        }
        for (ri, r) in self.robots.iter().enumerate() {
            if ri == rid {
                continue;
            }
            for ((p, l), (pose, aabb)) in r.parts.iter().zip(&r.part_link).zip(&r.world) {
                f(Obstacle { id: Collider::Link(RobotId(ri), *l), pose, shape: &*p.shape, aabb })?;
            }
        }
        ControlFlow::Continue(())
    }

    fn has_obstacles(&self, rid: usize) -> bool {
        !self.env.is_empty() || self.visit_dynamic(rid, |_| ControlFlow::Break(())).is_break()
    }

    /// Visits every obstacle (static or movable) whose AABB comes within `margin` of `aabb`.
    fn visit_near<'a>(
        &'a self,
        rid: usize,
        aabb: &Aabb,
        margin: f64,
        mut f: impl FnMut(Obstacle<'a>) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let query = aabb.loosened(margin);
        let mut flow = ControlFlow::Continue(());
        self.env_bvh.traverse(|node| {
            if !node.aabb().intersects(&query) {
                return TraversalAction::Prune;
            }
            if let Some(leaf) = node.leaf_data() {
                let e = &self.env[leaf as usize];
                if e.aabb.intersects(&query) {
                    let o =
                        Obstacle { id: Collider::Body(e.body), pose: &e.pose, shape: &*e.part.shape, aabb: &e.aabb };
                    if f(o).is_break() {
                        flow = ControlFlow::Break(());
                        return TraversalAction::EarlyExit;
                    }
                }
            }
            TraversalAction::Continue
        });
        flow?;
        self.visit_dynamic(rid, |o| if o.aabb.intersects(&query) { f(o) } else { ControlFlow::Continue(()) })
    }

    fn validate(&self, robot: RobotId, q: &[f64]) -> Result<()> {
        self.robot_entry(robot)?.robot.validate_configuration(q)
    }

    // ----------------------------------------------------------------------------------------
    // Boolean collision
    // ----------------------------------------------------------------------------------------

    /// True if the robot at configuration `q` collides with anything: see the
    /// [type-level documentation](CollisionWorld) for what is checked.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for a bad robot; [`CoreError::DimensionMismatch`],
    /// [`CoreError::NonFiniteJointValue`] or [`CoreError::JointOutOfLimits`] for a bad `q`.
    pub fn in_collision(&self, robot: RobotId, q: &[f64]) -> Result<bool> {
        self.validate(robot, q)?;
        Ok(self.in_collision_unchecked(robot, q))
    }

    /// [`in_collision`](Self::in_collision) without validating `q` (for planners' inner loops
    /// on configurations known to be valid; joint limits are not checked).
    ///
    /// # Panics
    /// If `robot` is not a robot of this world or `q` is shorter than the robot's DoF.
    pub fn in_collision_unchecked(&self, robot: RobotId, q: &[f64]) -> bool {
        let rid = robot.0;
        with_scratch(|s| {
            self.place(rid, q, s);
            let r = &self.robots[rid];
            // Self-collision first: the pair list is precomputed and short.
            for &(i, j) in &r.self_pairs {
                let (a, b) = (&s.items[i as usize], &s.items[j as usize]);
                if a.aabb.intersects(&b.aabb)
                    && intersects(&a.pose, &*r.parts[i as usize].shape, &b.pose, &*r.parts[j as usize].shape)
                {
                    return true;
                }
            }
            let n_parts = r.parts.len();
            for item in &s.items {
                let shape = self.item_shape(rid, item);
                let hit = self
                    .visit_near(rid, &item.aabb, 0.0, |o| {
                        if intersects(&item.pose, shape, o.pose, o.shape) {
                            ControlFlow::Break(())
                        } else {
                            ControlFlow::Continue(())
                        }
                    })
                    .is_break();
                if hit {
                    return true;
                }
                // Attached objects against the robot's own links.
                if let Owner::Attached { object, .. } = item.owner {
                    let touch = &self.objects[object as usize].attached.as_ref().map(|a| &a.touch[..]).unwrap_or(&[]);
                    for (p, link_item) in s.items[..n_parts].iter().enumerate() {
                        if !touch.contains(&link_item.link)
                            && link_item.aabb.intersects(&item.aabb)
                            && intersects(&item.pose, shape, &link_item.pose, &*r.parts[p].shape)
                        {
                            return true;
                        }
                    }
                }
            }
            false
        })
    }

    // ----------------------------------------------------------------------------------------
    // Distances
    // ----------------------------------------------------------------------------------------

    /// Lower bound of the distance from one item to the obstacles: the distance between its
    /// AABB and the nearest obstacle AABB (`+inf` without obstacles).
    fn item_lower_bound(&self, rid: usize, item: &Item) -> f64 {
        let mut lb = self
            .env_bvh
            .find_best(
                f64::INFINITY,
                |node, _| aabb_distance(&node.aabb(), &item.aabb),
                |leaf, _| Some(aabb_distance(&self.env[leaf as usize].aabb, &item.aabb)),
            )
            .map_or(f64::INFINITY, |(_, d)| d);
        let _ = self.visit_dynamic(rid, |o| {
            lb = lb.min(aabb_distance(o.aabb, &item.aabb));
            ControlFlow::Continue(())
        });
        lb
    }

    /// Nearest obstacle of one item if nearer than `bound` (branch and bound over the
    /// hierarchy, nearest AABB first); distances are ≥ 0 (0 when touching or overlapping).
    fn item_min_distance(&self, rid: usize, item: &Item, bound: f64) -> Option<Nearest<'_>> {
        let shape = self.item_shape(rid, item);
        let mut best: Option<Nearest<'_>> = None;
        let mut bound = bound;
        if let Some((leaf, d)) = self.env_bvh.find_best(
            bound,
            |node, _| aabb_distance(&node.aabb(), &item.aabb),
            |leaf, _| {
                let e = &self.env[leaf as usize];
                distance(&item.pose, shape, &e.pose, &*e.part.shape)
            },
        ) {
            bound = d;
            let e = &self.env[leaf as usize];
            best = Some(Nearest { distance: d, id: Collider::Body(e.body), pose: e.pose, shape: &*e.part.shape });
        }
        let _ = self.visit_dynamic(rid, |o| {
            if aabb_distance(o.aabb, &item.aabb) < bound {
                if let Some(d) = distance(&item.pose, shape, o.pose, o.shape) {
                    if d < bound {
                        bound = d;
                        best = Some(Nearest { distance: d, id: o.id, pose: *o.pose, shape: o.shape });
                    }
                }
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// Deepest penetration of one item into any obstacle: `(depth > 0, contact)` with the
    /// contact oriented item → obstacle.
    fn item_deepest_penetration(&self, rid: usize, item: &Item) -> Option<(Collider, query::Contact)> {
        let shape = self.item_shape(rid, item);
        let mut best: Option<(Collider, query::Contact)> = None;
        let _ = self.visit_near(rid, &item.aabb, 0.0, |o| {
            // Separated pairs are skipped with the (cheaper) distance before running EPA.
            if distance(&item.pose, shape, o.pose, o.shape).is_some_and(|d| d > 0.0) {
                return ControlFlow::Continue(());
            }
            if let Ok(Some(c)) = query::contact(&item.pose, shape, o.pose, o.shape, 0.0) {
                if c.dist <= 0.0 && best.as_ref().is_none_or(|(_, b)| c.dist < b.dist) {
                    best = Some((o.id, c));
                }
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// Minimum distance from the robot at `q` (links and attached objects) to its obstacles —
    /// static bodies, objects it does not carry, other robots — with the closest pair and
    /// witness points. Self-distance is not included.
    ///
    /// The distance is the gap when separated and `-depth` of the most deeply penetrating pair
    /// when the robot overlaps an obstacle (`0` when exactly touching). The search is
    /// branch-and-bound: links are visited with the best distance found so far as a bound, and
    /// any obstacle whose bounding box is farther than the bound is skipped without an exact
    /// query.
    ///
    /// # Errors
    /// [`CoreError::EmptyScene`] if the robot has no obstacle at all (no static body, no other
    /// object, no other robot) or no collision geometry — there is no pair to report
    /// ([`link_distances`](Self::link_distances) returns `+inf` instead); plus the errors of
    /// [`in_collision`](Self::in_collision).
    pub fn distance(&self, robot: RobotId, q: &[f64]) -> Result<DistanceReport> {
        self.validate(robot, q)?;
        let rid = robot.0;
        if !self.has_obstacles(rid) {
            return Err(CoreError::EmptyScene { reason: "the robot has no obstacle to measure a distance to".into() });
        }
        with_scratch(|s| {
            self.place(rid, q, s);
            // Items in increasing order of their AABB lower bound, so that the bound tightens
            // early and far links are pruned without exact queries.
            s.order.clear();
            for (k, item) in s.items.iter().enumerate() {
                s.order.push((self.item_lower_bound(rid, item), k as u32));
            }
            s.order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
            let mut best: Option<(usize, Nearest<'_>)> = None;
            let mut bound = f64::INFINITY;
            for &(lb, k) in &s.order {
                if lb >= bound {
                    break;
                }
                if let Some(n) = self.item_min_distance(rid, &s.items[k as usize], bound) {
                    bound = n.distance;
                    best = Some((k as usize, n));
                }
            }
            let Some((k, nearest)) = best else {
                return Err(CoreError::EmptyScene {
                    reason: "no obstacle within reach of the robot's geometry".into(),
                });
            };
            let d = nearest.distance;
            let (k, contact, other) = if d <= 0.0 {
                // Penetrating: report the deepest penetration over all items.
                let mut deepest: Option<(usize, Collider, query::Contact)> = None;
                for (k, item) in s.items.iter().enumerate() {
                    if let Some((id, c)) = self.item_deepest_penetration(rid, item) {
                        if deepest.as_ref().is_none_or(|(_, _, b)| c.dist < b.dist) {
                            deepest = Some((k, id, c));
                        }
                    }
                }
                match deepest {
                    Some((k, id, c)) => (k, Some(c), id),
                    None => (k, None, nearest.id),
                }
            } else {
                // Witness points of the nearest pair.
                let item = &s.items[k];
                let shape = self.item_shape(rid, item);
                // Generous: parry's GJK may find a slightly larger distance than the search.
                let prediction = 2.0 * d + 1e-6;
                let c = query::contact(&item.pose, shape, &nearest.pose, nearest.shape, prediction).ok().flatten();
                (k, c, nearest.id)
            };
            let item = &s.items[k];
            let attached = match item.owner {
                Owner::Attached { object, .. } => Some(ObjectId(object as usize)),
                Owner::Link { .. } => None,
            };
            let (distance, p1, p2) = match contact {
                // The searched distance is kept when separated, so that it equals the minimum
                // of `link_distances` exactly.
                Some(c) => (if d > 0.0 { d } else { c.dist }, c.point1, c.point2),
                None => (d.max(0.0), item.pose.translation.vector.into(), item.pose.translation.vector.into()),
            };
            Ok(DistanceReport { distance, link: item.link, attached, other, point_on_robot: p1, point_on_other: p2 })
        })
    }

    /// Minimum distance of each link (with the objects it carries) to the robot's obstacles,
    /// indexed by [`LinkId`]; self-distance is not included. Links without collision geometry,
    /// and every link when the robot has no obstacles, get `+inf`. Overlapping links get `0`
    /// (exact distance, not a penetration depth: use [`distance`](Self::distance) for depth).
    /// Each value is a safe bound for conservative-advancement collision checking.
    ///
    /// # Errors
    /// As [`in_collision`](Self::in_collision).
    pub fn link_distances(&self, robot: RobotId, q: &[f64]) -> Result<Vec<f64>> {
        let mut out = Vec::new();
        self.link_distances_into(robot, q, &mut out)?;
        Ok(out)
    }

    /// [`link_distances`](Self::link_distances) into a reused buffer (cleared and resized to
    /// the link count).
    ///
    /// # Errors
    /// As [`in_collision`](Self::in_collision).
    pub fn link_distances_into(&self, robot: RobotId, q: &[f64], out: &mut Vec<f64>) -> Result<()> {
        self.validate(robot, q)?;
        let rid = robot.0;
        out.clear();
        out.resize(self.robots[rid].n_links(), f64::INFINITY);
        with_scratch(|s| {
            self.place(rid, q, s);
            for item in &s.items {
                let l = item.link.0;
                if let Some(n) = self.item_min_distance(rid, item, out[l]) {
                    out[l] = out[l].min(n.distance);
                }
            }
        });
        Ok(())
    }

    /// [`link_distances_into`](Self::link_distances_into) restricted to the links with
    /// `selected[link] == true`: the others (and links beyond `selected`'s length) get `+inf`
    /// without any query. For callers that already hold cheaper lower bounds for most links
    /// and need exact distances for a few (e.g. a grasp evaluator refining the links near an
    /// object's convex hull).
    ///
    /// # Errors
    /// As [`in_collision`](Self::in_collision).
    pub fn selected_link_distances_into(
        &self,
        robot: RobotId,
        q: &[f64],
        selected: &[bool],
        out: &mut Vec<f64>,
    ) -> Result<()> {
        self.validate(robot, q)?;
        let rid = robot.0;
        out.clear();
        out.resize(self.robots[rid].n_links(), f64::INFINITY);
        with_scratch(|s| {
            self.place(rid, q, s);
            for item in &s.items {
                let l = item.link.0;
                if !selected.get(l).copied().unwrap_or(false) {
                    continue;
                }
                if let Some(n) = self.item_min_distance(rid, item, out[l]) {
                    out[l] = out[l].min(n.distance);
                }
            }
        });
        Ok(())
    }

    // ----------------------------------------------------------------------------------------
    // Contacts
    // ----------------------------------------------------------------------------------------

    fn check_margin(margin: f64) -> Result<()> {
        if margin.is_finite() && margin >= 0.0 {
            Ok(())
        } else {
            Err(CoreError::InvalidParameter {
                name: "margin".into(),
                reason: format!("must be finite and >= 0, got {margin}"),
            })
        }
    }

    /// Contacts of the robot's links at `q` with static bodies, objects it does not carry,
    /// other robots' links and its own links (non-allowed pairs, reported once with
    /// `other = Collider::Link(robot, _)`), including separated pairs closer than `margin`
    /// (negative depth). One contact (the deepest point, from parry's `query::contact`) per pair
    /// of collision parts. Objects the robot carries are not reported (see
    /// [`contacts_with_object`](Self::contacts_with_object)).
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for a negative or non-finite margin, plus the errors of
    /// [`in_collision`](Self::in_collision).
    pub fn contacts(&self, robot: RobotId, q: &[f64], margin: f64) -> Result<Vec<Contact>> {
        self.validate(robot, q)?;
        Self::check_margin(margin)?;
        let rid = robot.0;
        let r = &self.robots[rid];
        let mut out = Vec::new();
        with_scratch(|s| {
            self.place(rid, q, s);
            for item in s.items.iter().filter(|i| matches!(i.owner, Owner::Link { .. })) {
                let shape = self.item_shape(rid, item);
                let _ = self.visit_near(rid, &item.aabb, margin, |o| {
                    if let Ok(Some(c)) = query::contact(&item.pose, shape, o.pose, o.shape, margin) {
                        out.push(to_contact(item.link, o.id, &c));
                    }
                    ControlFlow::Continue(())
                });
            }
            for &(i, j) in &r.self_pairs {
                let (a, b) = (&s.items[i as usize], &s.items[j as usize]);
                if aabb_distance(&a.aabb, &b.aabb) <= margin {
                    let (sa, sb) = (&*r.parts[i as usize].shape, &*r.parts[j as usize].shape);
                    if let Ok(Some(c)) = query::contact(&a.pose, sa, &b.pose, sb, margin) {
                        out.push(to_contact(a.link, Collider::Link(robot, b.link), &c));
                    }
                }
            }
        });
        Ok(out)
    }

    /// Contacts of every link of the robot at `q` with one object, including separated pairs
    /// closer than `margin` (negative depth). An object carried by this robot is placed with
    /// its link at `q`, and every link (the carrying one included) is tested — this is what a
    /// grasp evaluator closing a hand on an object needs.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for a bad object, plus the errors of
    /// [`contacts`](Self::contacts).
    pub fn contacts_with_object(
        &self,
        robot: RobotId,
        q: &[f64],
        object: ObjectId,
        margin: f64,
    ) -> Result<Vec<Contact>> {
        self.validate(robot, q)?;
        Self::check_margin(margin)?;
        self.object_entry(object)?;
        let rid = robot.0;
        let o = &self.objects[object.0];
        let mut out = Vec::new();
        with_scratch(|s| {
            self.place(rid, q, s);
            let carried = o.attached.as_ref().filter(|a| a.robot == robot).map(|a| {
                let r = &self.robots[rid];
                r.base_pose * s.link_poses[a.link.0] * a.offset
            });
            let obj_parts: Vec<(Isometry3<f64>, Aabb)> = match carried {
                Some(pose) => o
                    .parts
                    .iter()
                    .map(|p| {
                        let w = pose * p.local;
                        (w, p.shape.compute_aabb(&w))
                    })
                    .collect(),
                None => o.world.clone(),
            };
            for item in s.items.iter().filter(|i| matches!(i.owner, Owner::Link { .. })) {
                let shape = self.item_shape(rid, item);
                for (p, (pose, aabb)) in o.parts.iter().zip(&obj_parts) {
                    if aabb_distance(aabb, &item.aabb) <= margin {
                        if let Ok(Some(c)) = query::contact(&item.pose, shape, pose, &*p.shape, margin) {
                            out.push(to_contact(item.link, Collider::Object(object), &c));
                        }
                    }
                }
            }
        });
        Ok(out)
    }
}

/// Converts a parry contact (shape 1 = robot link) to ours.
fn to_contact(link: LinkId, other: Collider, c: &query::Contact) -> Contact {
    Contact { link, other, point_on_robot: c.point1, point_on_other: c.point2, normal: -c.normal1, depth: -c.dist }
}

// The world is shared between threads (benchmarks, parallel planners).
const _: fn() = || {
    fn is_send_sync<T: Send + Sync>() {}
    is_send_sync::<CollisionWorld>();
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{samples, Geometry, Shape};
    use crate::scene::StaticBody;

    #[test]
    fn selected_link_distances_match_the_full_query() {
        let mut scene = Scene::new("selected");
        let arm = scene.add_robot("arm", Arc::new(samples::seven_dof_arm().unwrap()), Isometry3::identity()).unwrap();
        let wall = Shape::at_origin(Geometry::cuboid(0.05, 1.0, 1.0));
        scene.add_body(StaticBody::new("wall", Isometry3::translation(0.6, 0.0, 0.5), vec![wall])).unwrap();
        let world = CollisionWorld::new(&scene).unwrap();
        let q = [0.3, 0.8, -0.2, 0.5, 0.1, 0.4, 0.0];
        let full = world.link_distances(arm, &q).unwrap();
        let selected: Vec<bool> = (0..full.len()).map(|l| l % 2 == 1).collect();
        let mut out = Vec::new();
        world.selected_link_distances_into(arm, &q, &selected, &mut out).unwrap();
        assert_eq!(out.len(), full.len());
        for (l, (&a, &b)) in full.iter().zip(&out).enumerate() {
            if selected[l] {
                assert_eq!(a, b, "link {l}");
            } else {
                assert_eq!(b, f64::INFINITY, "link {l}");
            }
        }
        assert!(full.iter().any(|d| d.is_finite()));
        // A short mask leaves the remaining links unqueried; bad configurations are errors.
        world.selected_link_distances_into(arm, &q, &[true], &mut out).unwrap();
        assert_eq!(out[0], full[0]);
        assert!(out[1..].iter().all(|d| *d == f64::INFINITY));
        assert!(world.selected_link_distances_into(arm, &q[..3], &selected, &mut out).is_err());
    }
}
