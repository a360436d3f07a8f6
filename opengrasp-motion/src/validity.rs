//! State validity checking: the one interface every planner, validator and metric uses.
//!
//! A [`StateValidityChecker`] answers "is this group configuration collision-free?" and,
//! optionally, how far the robot is from obstacles (for clearance metrics) and how far each
//! link is from everything it could hit (for certified continuous collision checking with a
//! [`MotionBound`]).
//!
//! Implementations shipped with the crate:
//! - [`CollisionChecker`]: exact checks on core's parry-based [`CollisionWorld`] (environment,
//!   objects, self-collision, attached objects).
//! - [`SphereWorld`]: the links of a core [`Robot`] covered by spheres, among oriented boxes.
//!   Closed-form distances, fast, conservative; used by the stand-in benchmark scenes and tests.
//! - [`CountingChecker`]: wraps any checker and counts the calls (the benchmark uses it to
//!   report collision checks per run).

use std::cell::Cell;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::kinematics::forward_kinematics_into;
use opengrasp_core::model::{Geometry, JointGroup, JointKind, LinkId, Robot};
use opengrasp_core::scene::RobotId;

use crate::error::{MotionError, Result};

/// Decides whether group configurations are valid (collision-free).
///
/// Configurations are *group* vectors: one value per joint of the planning group, in group
/// order. Only [`StateValidityChecker::dim`] and [`StateValidityChecker::is_valid`] are
/// required; the distance methods enable clearance metrics and continuous checking.
pub trait StateValidityChecker {
    /// Dimension of the group configurations this checker accepts.
    fn dim(&self) -> usize;

    /// True if `q` (group values) is collision-free. `q` has [`StateValidityChecker::dim`]
    /// finite entries; implementations may panic otherwise.
    fn is_valid(&self, q: &[f64]) -> bool;

    /// Distance from the robot (at least the parts the group moves) to the obstacles at `q`
    /// (negative or zero in collision), or `None` if the checker cannot compute distances
    /// (default).
    fn clearance(&self, q: &[f64]) -> Option<f64> {
        let _ = q;
        None
    }

    /// Writes into `out` one lower bound per entry of [`MotionBound::links`] on the distance
    /// from that link to everything it could hit, and returns true; returns false (default)
    /// if unsupported.
    ///
    /// If [`StateValidityChecker::ccd_covers_self_collision`] is true, each entry must also be
    /// at most half the distance to every link it may collide with, so that two links moving
    /// towards each other are certified by the same per-link bound.
    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        let _ = (q, out);
        false
    }

    /// The per-link motion bound matching [`StateValidityChecker::link_distances`], or `None`
    /// (default) if continuous checking is unsupported.
    fn motion_bound(&self) -> Option<&MotionBound> {
        None
    }

    /// True if [`StateValidityChecker::link_distances`] accounts for self-collision (see
    /// there). When false (default) the continuous validator adds a strict discrete check for
    /// self-collisions.
    fn ccd_covers_self_collision(&self) -> bool {
        false
    }
}

/// Forwards every method of [`StateValidityChecker`] through a pointer type.
macro_rules! forward_checker {
    ($($pointer:ty),*) => {$(
        impl<T: StateValidityChecker + ?Sized> StateValidityChecker for $pointer {
            fn dim(&self) -> usize {
                (**self).dim()
            }
            fn is_valid(&self, q: &[f64]) -> bool {
                (**self).is_valid(q)
            }
            fn clearance(&self, q: &[f64]) -> Option<f64> {
                (**self).clearance(q)
            }
            fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
                (**self).link_distances(q, out)
            }
            fn motion_bound(&self) -> Option<&MotionBound> {
                (**self).motion_bound()
            }
            fn ccd_covers_self_collision(&self) -> bool {
                (**self).ccd_covers_self_collision()
            }
        }
    )*};
}

forward_checker!(&T, Box<T>);

/// A checker that accepts every configuration of the given dimension (free space).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AlwaysValid(pub usize);

impl StateValidityChecker for AlwaysValid {
    fn dim(&self) -> usize {
        self.0
    }
    fn is_valid(&self, _q: &[f64]) -> bool {
        true
    }
}

/// Wraps a checker and counts validity checks and distance queries.
pub struct CountingChecker<'a> {
    inner: &'a dyn StateValidityChecker,
    checks: Cell<u64>,
    distance_queries: Cell<u64>,
}

impl<'a> CountingChecker<'a> {
    /// A counter around `inner`, starting at zero.
    pub fn new(inner: &'a dyn StateValidityChecker) -> Self {
        Self { inner, checks: Cell::new(0), distance_queries: Cell::new(0) }
    }
    /// Number of [`StateValidityChecker::is_valid`] calls so far.
    pub fn checks(&self) -> u64 {
        self.checks.get()
    }
    /// Number of clearance and link-distance queries so far.
    pub fn distance_queries(&self) -> u64 {
        self.distance_queries.get()
    }
    /// Resets both counters to zero.
    pub fn reset(&self) {
        self.checks.set(0);
        self.distance_queries.set(0);
    }
}

impl StateValidityChecker for CountingChecker<'_> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        self.checks.set(self.checks.get() + 1);
        self.inner.is_valid(q)
    }
    fn clearance(&self, q: &[f64]) -> Option<f64> {
        self.distance_queries.set(self.distance_queries.get() + 1);
        self.inner.clearance(q)
    }
    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        self.distance_queries.set(self.distance_queries.get() + 1);
        self.inner.link_distances(q, out)
    }
    fn motion_bound(&self) -> Option<&MotionBound> {
        self.inner.motion_bound()
    }
    fn ccd_covers_self_collision(&self) -> bool {
        self.inner.ccd_covers_self_collision()
    }
}

/// Per-link bounds on how far any point of a link can move when the group joints move by
/// `Δq` (Schwarzer, Saha & Latombe 2005):
/// `B_i(Δq) = Σ_j |Δq_j| · r_ij`, where for a revolute joint `j` before link `i`, `r_ij` is a
/// configuration-independent upper bound on the distance of any point of link `i` from joint
/// `j`'s axis, and for a prismatic joint `r_ij = 1`. Joints after link `i` (and joints outside
/// the group) contribute nothing.
///
/// `r_ij` is computed from the kinematic tree: the distance from joint `j`'s origin to every
/// later joint origin along the chain (with prismatic joints at their largest extension), plus
/// the largest distance of a geometry vertex of link `i` (the corners of each shape's bounding
/// box, which contain the shape) from link `i`'s frame origin. Mimic joints driven by a group
/// joint contribute with their multiplier.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionBound {
    links: Vec<LinkId>,
    dim: usize,
    /// Row-major `links.len() × dim`.
    radii: Vec<f64>,
}

impl MotionBound {
    /// Bounds for `links` of `robot` moved by the joints of `group`; the geometry of each link
    /// is given by points in its frame (`link_points[k]` for `links[k]`) whose convex hull
    /// contains it.
    ///
    /// # Errors
    /// [`MotionError::DimensionMismatch`] if `link_points` and `links` differ in length.
    pub fn new(robot: &Robot, group: &JointGroup, links: &[LinkId], link_points: &[Vec<Point3<f64>>]) -> Result<Self> {
        if links.len() != link_points.len() {
            return Err(MotionError::DimensionMismatch { expected: links.len(), actual: link_points.len() });
        }
        let dim = group.len();
        let mut radii = vec![0.0; links.len() * dim];
        for (k, (&link, points)) in links.iter().zip(link_points).enumerate() {
            let extent = points.iter().map(|p| p.coords.norm()).fold(0.0, f64::max);
            let chain = robot.chain_to(link);
            // reach[c]: bound on the distance from joint chain[c]'s origin to any point of the link.
            let mut reach = vec![0.0; chain.len()];
            let mut acc = extent;
            for c in (0..chain.len()).rev() {
                let joint = robot.joint(chain[c]);
                if joint.kind == JointKind::Prismatic {
                    let ext = joint.limits.map(|l| l.lower.abs().max(l.upper.abs())).unwrap_or(0.0);
                    acc += ext;
                }
                reach[c] = acc;
                acc += joint.origin.translation.vector.norm();
            }
            for (c, &jid) in chain.iter().enumerate() {
                let joint = robot.joint(jid);
                let Some((dof, mult)) = robot.driving_dof(jid) else { continue };
                let Some(gi) = group.dofs().iter().position(|&d| d == dof) else { continue };
                let r = match joint.kind {
                    JointKind::Prismatic => 1.0,
                    JointKind::Fixed => 0.0,
                    JointKind::Revolute | JointKind::Continuous => reach[c],
                };
                radii[k * dim + gi] += mult.abs() * r;
            }
        }
        Ok(Self { links: links.to_vec(), dim, radii })
    }

    /// Bounds for every link of `robot` that has collision geometry, from the bounding-box
    /// corners of its collision shapes.
    ///
    /// # Errors
    /// As [`MotionBound::new`] (never in practice).
    pub fn from_robot(robot: &Robot, group: &JointGroup) -> Result<Self> {
        Self::from_robot_with(robot, group, &[])
    }

    /// As [`MotionBound::from_robot`], with extra geometry points (in the link frame) carried by
    /// some links, e.g. the bounding-box corners of an attached object.
    ///
    /// # Errors
    /// As [`MotionBound::new`] (never in practice).
    pub fn from_robot_with(robot: &Robot, group: &JointGroup, extra: &[(LinkId, Vec<Point3<f64>>)]) -> Result<Self> {
        let mut links = Vec::new();
        let mut points = Vec::new();
        for (i, link) in robot.links().iter().enumerate() {
            let carried: Vec<Point3<f64>> =
                extra.iter().filter(|(l, _)| l.0 == i).flat_map(|(_, p)| p.iter().copied()).collect();
            if link.collisions.is_empty() && carried.is_empty() {
                continue;
            }
            let mut pts = carried;
            for shape in &link.collisions {
                pts.extend(shape.aabb_corners());
            }
            links.push(LinkId(i));
            points.push(pts);
        }
        Self::new(robot, group, &links, &points)
    }

    /// The links the bounds refer to, in order.
    pub fn links(&self) -> &[LinkId] {
        &self.links
    }
    /// Group dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// `r_ij` for link index `i` (into [`MotionBound::links`]) and group joint `j`.
    pub fn radius(&self, i: usize, j: usize) -> f64 {
        self.radii[i * self.dim + j]
    }
    /// True if some group joint moves link index `i` (some `r_ij > 0`).
    pub fn is_moving(&self, i: usize) -> bool {
        self.radii[i * self.dim..(i + 1) * self.dim].iter().any(|&r| r > 0.0)
    }
    /// `B_i(Δq) = Σ_j |Δq_j| r_ij` for link index `i`.
    pub fn bound(&self, i: usize, dq: &[f64]) -> f64 {
        self.radii[i * self.dim..(i + 1) * self.dim].iter().zip(dq).map(|(r, d)| r * d.abs()).sum()
    }
}

/// An oriented box obstacle of a [`SphereWorld`].
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
        let l = self.pose.inverse_transform_point(p);
        let h = &self.half_extents;
        let d = Vector3::new(l.x.abs() - h.x, l.y.abs() - h.y, l.z.abs() - h.z);
        let outside = Vector3::new(d.x.max(0.0), d.y.max(0.0), d.z.max(0.0)).norm();
        outside + d.x.max(d.y).max(d.z).min(0.0)
    }
}

/// A robot whose links are covered by spheres, among oriented boxes: closed-form, conservative
/// distances for tests and stand-in scenes.
///
/// Each collision shape is covered by spheres (a capsule or cylinder of radius `r` by spheres
/// along its axis at spacing `s ≤ r`, radius `√(r² + s²/4)`; a box by a grid of spheres; a mesh
/// by its bounding box), so the covered robot contains the real one and every distance is a
/// lower bound on the true distance. Self-collision is checked between sphere sets of link
/// pairs that are neither allowed by [`Robot::is_collision_allowed`] nor already overlapping at
/// the reference configuration (like an SRDF's "default" disabled pairs).
///
/// The clearance is the smallest distance from a link the group moves to a box. For continuous
/// checking, [`StateValidityChecker::link_distances`] reports per link the
/// minimum of its distance to the boxes and half its distance to every checked link, so the
/// bound of [`MotionBound`] certifies self-collision too.
#[derive(Clone, Debug)]
pub struct SphereWorld {
    robot: Arc<Robot>,
    group: JointGroup,
    q_full: Vec<f64>,
    base_pose: Isometry3<f64>,
    /// (index into `links`, centre in link frame, radius)
    spheres: Vec<(usize, Point3<f64>, f64)>,
    /// Range of `spheres` per entry of `links`.
    ranges: Vec<(usize, usize)>,
    links: Vec<LinkId>,
    pairs: Vec<(usize, usize)>,
    boxes: Vec<ObstacleBox>,
    bound: MotionBound,
}

fn cover_shape(geometry: &Geometry, origin: &Isometry3<f64>, out: &mut Vec<(Point3<f64>, f64)>) {
    match geometry {
        Geometry::Sphere { radius } => out.push((origin * Point3::origin(), *radius)),
        Geometry::Capsule { radius, length } | Geometry::Cylinder { radius, length } => {
            let n = (length / radius).ceil().max(1.0) as usize;
            let s = length / n as f64;
            let rr = (radius * radius + s * s * 0.25).sqrt();
            for k in 0..=n {
                let z = -length * 0.5 + s * k as f64;
                out.push((origin * Point3::new(0.0, 0.0, z), rr));
            }
        }
        Geometry::Box { half_extents } => cover_box(half_extents, origin, out),
        Geometry::Mesh(mesh) => {
            let (lo, hi) = mesh.aabb();
            let centre = nalgebra::center(&lo, &hi);
            let o = origin * Isometry3::translation(centre.x, centre.y, centre.z);
            cover_box(&((hi - lo) * 0.5), &o, out);
        }
    }
}

fn cover_box(h: &Vector3<f64>, origin: &Isometry3<f64>, out: &mut Vec<(Point3<f64>, f64)>) {
    let cell = h.min().max(1e-3) * 2.0;
    let n = h.map(|e| ((2.0 * e / cell).ceil().max(1.0)) as usize);
    let size = Vector3::new(2.0 * h.x / n.x as f64, 2.0 * h.y / n.y as f64, 2.0 * h.z / n.z as f64);
    let r = size.norm() * 0.5;
    for i in 0..n.x {
        for j in 0..n.y {
            for k in 0..n.z {
                let c = Point3::new(
                    -h.x + size.x * (i as f64 + 0.5),
                    -h.y + size.y * (j as f64 + 0.5),
                    -h.z + size.z * (k as f64 + 0.5),
                );
                out.push((origin * c, r));
            }
        }
    }
}

impl SphereWorld {
    /// A world for `robot` (root link at `base_pose` in the world) moving the joints of
    /// `group`, with the other joints held at `q_full`, among `boxes`.
    ///
    /// # Errors
    /// [`MotionError::Core`] if `q_full` is not a valid configuration of `robot`.
    pub fn new(
        robot: Arc<Robot>,
        group: JointGroup,
        q_full: Vec<f64>,
        base_pose: Isometry3<f64>,
        boxes: Vec<ObstacleBox>,
    ) -> Result<Self> {
        robot.validate_configuration(&q_full)?;
        let mut links = Vec::new();
        let mut spheres = Vec::new();
        let mut ranges = Vec::new();
        let mut points = Vec::new();
        let mut buf = Vec::new();
        for (i, link) in robot.links().iter().enumerate() {
            if link.collisions.is_empty() {
                continue;
            }
            buf.clear();
            for shape in &link.collisions {
                cover_shape(&shape.geometry, &shape.origin, &mut buf);
            }
            let k = links.len();
            let start = spheres.len();
            let mut pts = Vec::new();
            for &(c, r) in &buf {
                spheres.push((k, c, r));
                // The sphere's bounding-box corners contain it.
                for s in 0..8 {
                    let sign = |b: usize| if s & b == 0 { -r } else { r };
                    pts.push(c + Vector3::new(sign(1), sign(2), sign(4)));
                }
            }
            ranges.push((start, spheres.len()));
            links.push(LinkId(i));
            points.push(pts);
        }
        let bound = MotionBound::new(&robot, &group, &links, &points)?;
        let mut world =
            Self { robot, group, q_full, base_pose, spheres, ranges, links, pairs: Vec::new(), boxes, bound };
        let reference = world.q_full.clone();
        let centres = world.sphere_centres(&reference);
        let n = world.links.len();
        for a in 0..n {
            for b in a + 1..n {
                if world.robot.is_collision_allowed(world.links[a], world.links[b]) {
                    continue;
                }
                if world.pair_distance(&centres, a, b) > 0.0 {
                    world.pairs.push((a, b));
                }
            }
        }
        Ok(world)
    }

    /// The robot.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }
    /// The planning group.
    pub fn group(&self) -> &JointGroup {
        &self.group
    }
    /// The obstacles.
    pub fn boxes(&self) -> &[ObstacleBox] {
        &self.boxes
    }
    /// Number of covering spheres.
    pub fn sphere_count(&self) -> usize {
        self.spheres.len()
    }
    /// Link pairs checked for self-collision.
    pub fn self_collision_pairs(&self) -> Vec<(LinkId, LinkId)> {
        self.pairs.iter().map(|&(a, b)| (self.links[a], self.links[b])).collect()
    }
    /// The full configuration for group values `q` (other joints as given at construction).
    pub fn full_configuration(&self, q: &[f64]) -> Vec<f64> {
        let mut full = self.q_full.clone();
        for (&d, &v) in self.group.dofs().iter().zip(q) {
            full[d] = v;
        }
        full
    }

    fn sphere_centres(&self, q_full: &[f64]) -> Vec<Point3<f64>> {
        let mut poses = Vec::with_capacity(self.robot.links().len());
        forward_kinematics_into(&self.robot, q_full, &mut poses);
        let world: Vec<Isometry3<f64>> = self.links.iter().map(|l| self.base_pose * poses[l.0]).collect();
        self.spheres.iter().map(|(k, c, _)| world[*k] * c).collect()
    }

    fn centres_for(&self, q: &[f64]) -> Vec<Point3<f64>> {
        let full = self.full_configuration(q);
        self.sphere_centres(&full)
    }

    fn pair_distance(&self, centres: &[Point3<f64>], a: usize, b: usize) -> f64 {
        let (ra, rb) = (self.ranges[a], self.ranges[b]);
        let mut best = f64::INFINITY;
        for i in ra.0..ra.1 {
            for j in rb.0..rb.1 {
                let d = (centres[i] - centres[j]).norm() - self.spheres[i].2 - self.spheres[j].2;
                best = best.min(d);
            }
        }
        best
    }

    fn link_obstacle_distance(&self, centres: &[Point3<f64>], k: usize) -> f64 {
        let (s, e) = self.ranges[k];
        let mut best = f64::INFINITY;
        for (c, sphere) in centres[s..e].iter().zip(&self.spheres[s..e]) {
            for b in &self.boxes {
                best = best.min(b.signed_distance(c) - sphere.2);
            }
        }
        best
    }
}

impl StateValidityChecker for SphereWorld {
    fn dim(&self) -> usize {
        self.group.len()
    }

    fn is_valid(&self, q: &[f64]) -> bool {
        let centres = self.centres_for(q);
        for (i, c) in centres.iter().enumerate() {
            let r = self.spheres[i].2;
            if self.boxes.iter().any(|b| b.signed_distance(c) <= r) {
                return false;
            }
        }
        self.pairs.iter().all(|&(a, b)| self.pair_distance(&centres, a, b) > 0.0)
    }

    fn clearance(&self, q: &[f64]) -> Option<f64> {
        let centres = self.centres_for(q);
        Some(
            (0..self.links.len())
                .filter(|&k| self.bound.is_moving(k))
                .map(|k| self.link_obstacle_distance(&centres, k))
                .fold(f64::INFINITY, f64::min),
        )
    }

    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        let centres = self.centres_for(q);
        out.clear();
        out.extend((0..self.links.len()).map(|k| self.link_obstacle_distance(&centres, k)));
        for &(a, b) in &self.pairs {
            let half = 0.5 * self.pair_distance(&centres, a, b);
            out[a] = out[a].min(half);
            out[b] = out[b].min(half);
        }
        true
    }

    fn motion_bound(&self) -> Option<&MotionBound> {
        Some(&self.bound)
    }

    fn ccd_covers_self_collision(&self) -> bool {
        true
    }
}

/// A checker over core's [`CollisionWorld`]: one robot of the world moving the joints of
/// `group`, the other joints held at `q_full`.
///
/// Validity is [`CollisionWorld::in_collision_unchecked`] (environment, objects, other robots,
/// self-collision with the allowed-collision matrix, attached objects); per-link distances are
/// [`CollisionWorld::link_distances`] (environment only) and the clearance is their minimum over
/// the links the group moves (links it cannot move, such as a mobile base resting 2 cm above
/// the floor, would otherwise fix the clearance of every path), with a [`MotionBound`] from the
/// links' collision geometry. Because the link distances exclude self-distance, the continuous
/// validator checks self-collision by a fine discrete check
/// ([`CcdOptions::self_collision_step`](crate::validate::CcdOptions::self_collision_step)).
/// Objects attached to a link are not in the motion bound: pass your own bound with
/// [`CollisionChecker::with_bound`] when carrying objects.
#[derive(Clone, Debug)]
pub struct CollisionChecker {
    world: Arc<CollisionWorld>,
    robot_id: RobotId,
    robot: Arc<Robot>,
    group: JointGroup,
    q_full: Vec<f64>,
    bound: MotionBound,
}

impl CollisionChecker {
    /// A checker for robot `robot_id` of `world` (whose model is `robot`).
    ///
    /// # Errors
    /// [`MotionError::Core`] if `q_full` is not a valid configuration of `robot` or `robot_id`
    /// is not a robot of the world.
    pub fn new(
        world: Arc<CollisionWorld>,
        robot_id: RobotId,
        robot: Arc<Robot>,
        group: JointGroup,
        q_full: Vec<f64>,
    ) -> Result<Self> {
        world.in_collision(robot_id, &q_full)?;
        let bound = MotionBound::from_robot(&robot, &group)?;
        Ok(Self { world, robot_id, robot, group, q_full, bound })
    }

    /// Replaces the motion bound (e.g. one that includes carried objects).
    pub fn with_bound(mut self, bound: MotionBound) -> Self {
        self.bound = bound;
        self
    }

    /// The collision world.
    pub fn world(&self) -> &CollisionWorld {
        &self.world
    }

    fn full(&self, q: &[f64]) -> Vec<f64> {
        let mut full = self.q_full.clone();
        for (&d, &v) in self.group.dofs().iter().zip(q) {
            full[d] = v;
        }
        full
    }
}

impl StateValidityChecker for CollisionChecker {
    fn dim(&self) -> usize {
        self.group.len()
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        !self.world.in_collision_unchecked(self.robot_id, &self.full(q))
    }
    fn clearance(&self, q: &[f64]) -> Option<f64> {
        let mut d = Vec::new();
        if !self.link_distances(q, &mut d) {
            return None;
        }
        Some((0..d.len()).filter(|&i| self.bound.is_moving(i)).map(|i| d[i]).fold(f64::INFINITY, f64::min))
    }
    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        let mut full = self.full(q);
        self.robot.clamp_configuration(&mut full);
        match self.world.link_distances(self.robot_id, &full) {
            Ok(all) => {
                out.clear();
                out.extend(self.bound.links().iter().map(|l| all.get(l.0).copied().unwrap_or(f64::INFINITY)));
                true
            }
            Err(_) => false,
        }
    }
    fn motion_bound(&self) -> Option<&MotionBound> {
        Some(&self.bound)
    }
}
