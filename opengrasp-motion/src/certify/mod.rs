//! Cheap, sound certification of motions for post-processing.
//!
//! A [`SegmentCertifier`] proves that a straight motion `a → b` is collision-free with a
//! margin, on a conservative simplified world, so that post-processing
//! ([`crate::smoothing`]) can accept a shortcut without running the exact checks on it. The
//! proof must imply the verdict of every exact validator (discrete, strict and continuous,
//! [`crate::validate`]); when the certifier cannot prove it, the exact checks run as before, so
//! the verdicts, and therefore the post-processed paths, are exactly those of the exact
//! procedure.
//!
//! [`SphereCertifier`] is the implementation for core scenes:
//!
//! - **robot**: every collision shape of every link is replaced by primitives that contain it —
//!   a sphere by itself, a capsule by balls along its axis (radius `√(r² + (s/2)²)` at spacing
//!   `s`, which contains the capsule), every other shape (box, cylinder, mesh) by the oriented
//!   box of its local bounding box; objects carried by the robot likewise, on their link;
//! - **obstacles**: every static body's and free object's shape by its oriented bounding box;
//! - **distances**: lower bounds only — ball–box and ball–ball exactly, box–box by the largest
//!   separating-axis gap over the 15 axes of the pair (the gap along a unit axis never exceeds
//!   the distance);
//! - **motion**: conservative advancement (as [`segment_valid_continuous`]) with the same
//!   per-link [`MotionBound`] as the exact validator: link `i` is certified on
//!   `[t, t + (d̃ᵢ − m) / Bᵢ]` where `d̃ᵢ` is its lower bound (half the bound for pairs of the
//!   robot's own links, which may both move) and `m` the margin.
//!
//! [`segment_valid_continuous`]: crate::validate::segment_valid_continuous

use std::sync::Arc;

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::kinematics::forward_kinematics_into;
use opengrasp_core::model::{Geometry, JointGroup, LinkId, Robot, Shape};
use opengrasp_core::scene::{RobotId, Scene};

use crate::error::{MotionError, Result};
use crate::validity::MotionBound;

/// Proves motions collision-free on a conservative model (see the [module docs](self)).
pub trait SegmentCertifier {
    /// [`Certificate::Free`] only if, along the whole straight motion `a → b` (group values),
    /// every link of `bound` that the group moves, with the objects it carries, stays at least
    /// `margin` away from every obstacle, and no non-allowed pair of the robot's own parts
    /// (carried objects included) that the group's joints move relative to each other comes
    /// closer than `margin`. What no group joint moves (links the group does not move, and
    /// pairs that move rigidly together) never changes, so it is left to the caller to check
    /// once, at any state.
    ///
    /// `bound` is the motion bound of the exact continuous validator. A certifier may give up
    /// after `max_steps` advancement steps.
    fn certify(&self, a: &[f64], b: &[f64], bound: &MotionBound, margin: f64, max_steps: usize) -> Certificate;
}

/// The answer of a [`SegmentCertifier`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Certificate {
    /// The motion is proven free (see [`SegmentCertifier::certify`]).
    Free,
    /// Not proven; `near` is the motion parameter `t ∈ [0, 1]` (state `a + t (b − a)`) where
    /// a lower bound fell to the margin, if that is why: a good place to look for a collision.
    Unknown {
        /// Where the proof got stuck, if a bound fell to the margin.
        near: Option<f64>,
    },
}

/// Ball spacing along a capsule's axis, as a fraction of its radius: the balls reach at most
/// `r (√(1 + 0.75²/4) − 1)` = 6.8 % of the radius beyond the capsule.
const CAPSULE_SPACING: f64 = 0.75;

/// A convex primitive of the model.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Prim {
    /// Ball: centre, radius.
    Ball(Point3<f64>, f64),
    /// Oriented box: pose of its centre, half extents.
    Box(Isometry3<f64>, Vector3<f64>),
    /// Cylinder along the local z axis of its pose: pose of its centre, radius, half length.
    Cylinder(Isometry3<f64>, f64, f64),
}

impl Prim {
    fn transformed(&self, pose: &Isometry3<f64>) -> Prim {
        match self {
            Prim::Ball(c, r) => Prim::Ball(pose * c, *r),
            Prim::Box(p, h) => Prim::Box(pose * p, *h),
            Prim::Cylinder(p, r, l) => Prim::Cylinder(pose * p, *r, *l),
        }
    }

    /// Centre and radius of a ball containing the primitive.
    fn bounding_ball(&self) -> (Point3<f64>, f64) {
        match self {
            Prim::Ball(c, r) => (*c, *r),
            Prim::Box(p, h) => (p.translation.vector.into(), h.norm()),
            Prim::Cylinder(p, r, l) => (p.translation.vector.into(), r.hypot(*l)),
        }
    }
}

/// The primitives containing `shape` (in its parent frame).
fn shape_prims(shape: &Shape) -> Vec<Prim> {
    match &shape.geometry {
        Geometry::Sphere { radius } => vec![Prim::Ball(shape.origin * Point3::origin(), *radius)],
        Geometry::Cylinder { radius, length } => vec![Prim::Cylinder(shape.origin, *radius, 0.5 * length)],
        Geometry::Capsule { radius, length } => {
            let n = ((length / (CAPSULE_SPACING * radius)).ceil() as usize).max(1);
            let s = length / n as f64;
            let r = (radius * radius + 0.25 * s * s).sqrt();
            // The end caps are balls of the capsule's radius at the segment ends; the
            // cylinder between them is cut into n slices of height s, and each slice lies
            // within r of its middle point.
            [-0.5 * length, 0.5 * length]
                .into_iter()
                .map(|z| Prim::Ball(shape.origin * Point3::new(0.0, 0.0, z), *radius))
                .chain((0..n).map(|k| {
                    let z = -0.5 * length + (k as f64 + 0.5) * s;
                    Prim::Ball(shape.origin * Point3::new(0.0, 0.0, z), r)
                }))
                .collect()
        }
        g => {
            let (lo, hi) = g.local_aabb();
            let centre = nalgebra::center(&lo, &hi);
            vec![Prim::Box(shape.origin * Isometry3::translation(centre.x, centre.y, centre.z), 0.5 * (hi - lo))]
        }
    }
}

/// A primitive placed in the world: a ball (centre, radius) or an oriented box (centre,
/// rotation, half extents).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Placed {
    Ball(Vector3<f64>, f64),
    Box(Vector3<f64>, Matrix3<f64>, Vector3<f64>),
    /// Centre, rotation (axis: third column), radius, half length.
    Cylinder(Vector3<f64>, Matrix3<f64>, f64, f64),
}

impl Placed {
    fn new(prim: &Prim, pose: &Isometry3<f64>) -> Self {
        match prim {
            Prim::Ball(c, r) => Placed::Ball((pose * c).coords, *r),
            Prim::Box(p, h) => {
                let p = pose * p;
                Placed::Box(p.translation.vector, p.rotation.to_rotation_matrix().into_inner(), *h)
            }
            Prim::Cylinder(p, r, l) => {
                let p = pose * p;
                Placed::Cylinder(p.translation.vector, p.rotation.to_rotation_matrix().into_inner(), *r, *l)
            }
        }
    }
}

/// Distance from `p` to a box (0 inside).
fn point_box(p: &Vector3<f64>, c: &Vector3<f64>, r: &Matrix3<f64>, h: &Vector3<f64>) -> f64 {
    let l = r.tr_mul(&(p - c));
    Vector3::new((l.x.abs() - h.x).max(0.0), (l.y.abs() - h.y).max(0.0), (l.z.abs() - h.z).max(0.0)).norm()
}

/// Distance from `p` to a cylinder (0 inside).
fn point_cylinder(p: &Vector3<f64>, c: &Vector3<f64>, rot: &Matrix3<f64>, r: f64, l: f64) -> f64 {
    let q = rot.tr_mul(&(p - c));
    (q.x.hypot(q.y) - r).max(0.0).hypot((q.z.abs() - l).max(0.0))
}

/// Lower bound on the distance between two boxes: the largest gap along the 15 separating
/// axes (the gap along a unit axis never exceeds the distance). Stops at the first gap of at
/// least `enough`.
fn box_box(
    (ca, ra, ha): (&Vector3<f64>, &Matrix3<f64>, &Vector3<f64>),
    (cb, rb, hb): (&Vector3<f64>, &Matrix3<f64>, &Vector3<f64>),
    enough: f64,
) -> f64 {
    // Everything in A's frame: B's axes are the columns of c, the centre offset is t.
    let c = ra.tr_mul(rb);
    let t = ra.tr_mul(&(cb - ca));
    let abs = c.abs();
    let mut best = f64::NEG_INFINITY;
    for i in 0..3 {
        let gap = t[i].abs() - ha[i] - (hb.x * abs[(i, 0)] + hb.y * abs[(i, 1)] + hb.z * abs[(i, 2)]);
        best = best.max(gap);
        if best >= enough {
            return best;
        }
    }
    for j in 0..3 {
        let gap = t.dot(&c.column(j)).abs() - (ha.x * abs[(0, j)] + ha.y * abs[(1, j)] + ha.z * abs[(2, j)]) - hb[j];
        best = best.max(gap);
        if best >= enough {
            return best;
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let axis = Vector3::ith(i, 1.0).cross(&c.column(j));
            let n = axis.norm();
            if n > 1e-9 {
                let u = axis / n;
                let radius_a = ha.x * u.x.abs() + ha.y * u.y.abs() + ha.z * u.z.abs();
                let radius_b = hb.x * u.dot(&c.column(0)).abs()
                    + hb.y * u.dot(&c.column(1)).abs()
                    + hb.z * u.dot(&c.column(2)).abs();
                best = best.max(u.dot(&t).abs() - radius_a - radius_b);
                if best >= enough {
                    return best;
                }
            }
        }
    }
    best
}

/// Lower bound on the distance between two placed primitives (≤ 0 when they may overlap);
/// any value of at least `enough` may be returned once the bound reaches it.
fn distance(a: &Placed, b: &Placed, enough: f64) -> f64 {
    match (a, b) {
        (Placed::Ball(c1, r1), Placed::Ball(c2, r2)) => (c1 - c2).norm() - r1 - r2,
        (Placed::Ball(p, rad), Placed::Box(c, r, h)) | (Placed::Box(c, r, h), Placed::Ball(p, rad)) => {
            point_box(p, c, r, h) - rad
        }
        (Placed::Ball(p, rad), Placed::Cylinder(c, rot, r, l))
        | (Placed::Cylinder(c, rot, r, l), Placed::Ball(p, rad)) => point_cylinder(p, c, rot, *r, *l) - rad,
        (Placed::Cylinder(c, rot, r, l), other) | (other, Placed::Cylinder(c, rot, r, l)) => {
            // The cylinder's box, and the other shape's bounding ball against the cylinder.
            let (oc, or) = match other {
                Placed::Box(oc, _, h) => (oc, h.norm()),
                Placed::Cylinder(oc, _, r2, l2) => (oc, r2.hypot(*l2)),
                Placed::Ball(oc, or) => (oc, *or),
            };
            let ball = point_cylinder(oc, c, rot, *r, *l) - or;
            if ball >= enough {
                return ball;
            }
            let boxed = Placed::Box(*c, *rot, Vector3::new(*r, *r, *l));
            let other = match other {
                Placed::Cylinder(c2, rot2, r2, l2) => Placed::Box(*c2, *rot2, Vector3::new(*r2, *r2, *l2)),
                o => *o,
            };
            distance(&boxed, &other, enough).max(ball)
        }
        (Placed::Box(c1, r1, h1), Placed::Box(c2, r2, h2)) => {
            // The first box's bounding ball against the second box, then the axes.
            let ball = point_box(c1, c2, r2, h2) - h1.norm();
            if ball >= enough {
                ball
            } else {
                box_box((c1, r1, h1), (c2, r2, h2), enough).max(ball)
            }
        }
    }
}

/// The primitives of one link (or of the objects carried by one link), in the link frame.
#[derive(Clone, Debug)]
struct Model {
    /// The link (the carrying link for carried objects).
    link: LinkId,
    /// Index of `link` in the motion bound's links.
    slot: usize,
    /// Carried objects rather than the link's own shapes.
    carried: bool,
    prims: Vec<Prim>,
    /// Bounding ball of `prims` in the link frame.
    ball: (Point3<f64>, f64),
}

impl Model {
    fn new(link: LinkId, slot: usize, carried: bool, prims: Vec<Prim>) -> Option<Self> {
        if prims.is_empty() {
            return None;
        }
        let centre = prims.iter().fold(Vector3::zeros(), |s, p| s + p.bounding_ball().0.coords) / prims.len() as f64;
        let centre = Point3::from(centre);
        let radius = prims
            .iter()
            .map(|p| {
                let (c, r) = p.bounding_ball();
                (c - centre).norm() + r
            })
            .fold(0.0, f64::max);
        Some(Self { link, slot, carried, prims, ball: (centre, radius) })
    }
}

/// A [`SegmentCertifier`] for a robot of a core [`Scene`] (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct SphereCertifier {
    robot: Arc<Robot>,
    base_pose: Isometry3<f64>,
    dofs: Vec<usize>,
    limits: Vec<(f64, f64)>,
    q_full: Vec<f64>,
    models: Vec<Model>,
    /// Model index pairs to keep apart (the robot's non-allowed link pairs; carried objects
    /// against every link but their carrier).
    pairs: Vec<(usize, usize)>,
    obstacles: Vec<Placed>,
    /// Bounding ball of each obstacle.
    obstacle_balls: Vec<(Vector3<f64>, f64)>,
    bound_links: Vec<LinkId>,
}

impl SphereCertifier {
    /// The model of robot `robot_id` of `scene` (its link shapes and the objects attached to
    /// it) among the scene's static bodies and other objects, for motions of `group` from the
    /// full configuration `q_full`, with the links of `bound` (the exact validator's motion
    /// bound) and the allowed-collision matrix of `world` (the exact checker's world).
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`] if the scene holds other robots (not modelled) or a
    /// link with geometry is missing from `bound`; [`MotionError::DimensionMismatch`] for a
    /// `q_full` of the wrong length; core errors for a bad robot handle.
    pub fn new(
        scene: &Scene,
        robot_id: RobotId,
        group: &JointGroup,
        q_full: &[f64],
        bound: &MotionBound,
        world: &CollisionWorld,
    ) -> Result<Self> {
        if scene.robots().len() != 1 {
            return Err(MotionError::InvalidParameter {
                name: "scene",
                reason: "the certifier models scenes with one robot".into(),
            });
        }
        let entry = scene.robot(robot_id)?;
        let robot = entry.robot.clone();
        if q_full.len() != robot.dof() {
            return Err(MotionError::DimensionMismatch { expected: robot.dof(), actual: q_full.len() });
        }
        let slot_of = |link: LinkId| {
            bound.links().iter().position(|&l| l == link).ok_or_else(|| MotionError::InvalidParameter {
                name: "bound",
                reason: format!("link {} has geometry but no motion bound", link.0),
            })
        };
        let mut models = Vec::new();
        for (i, link) in robot.links().iter().enumerate() {
            let prims: Vec<Prim> = link.collisions.iter().flat_map(shape_prims).collect();
            if !prims.is_empty() {
                models.extend(Model::new(LinkId(i), slot_of(LinkId(i))?, false, prims));
            }
        }
        let mut obstacles = Vec::new();
        for body in scene.bodies() {
            for shape in &body.shapes {
                obstacles.extend(shape_prims(shape).iter().map(|p| p.transformed(&body.pose)));
            }
        }
        for (k, object) in scene.objects().iter().enumerate() {
            let prims = object.shapes.iter().flat_map(shape_prims);
            match scene.attachments().iter().find(|a| a.object.0 == k) {
                Some(att) if att.robot == robot_id => {
                    let prims = prims.map(|p| p.transformed(&att.offset)).collect();
                    models.extend(Model::new(att.link, slot_of(att.link)?, true, prims));
                }
                _ => obstacles.extend(prims.map(|p| p.transformed(&object.pose))),
            }
        }
        let obstacle_balls = obstacles
            .iter()
            .map(|p| {
                let (c, r) = p.bounding_ball();
                (c.coords, r)
            })
            .collect();
        let obstacles = obstacles.iter().map(|p| Placed::new(p, &Isometry3::identity())).collect();
        // Pairs that no group joint moves apart (the joints on their chains are the same)
        // keep their distance: they are the caller's (see `SegmentCertifier::certify`).
        let apart = |i: usize, j: usize| {
            let (a, b) = (models[i].slot, models[j].slot);
            (0..bound.dim()).any(|g| (bound.radius(a, g) > 0.0) != (bound.radius(b, g) > 0.0))
        };
        let mut pairs = Vec::new();
        for i in 0..models.len() {
            for j in i + 1..models.len() {
                let (a, b) = (&models[i], &models[j]);
                let kept = match (a.carried, b.carried) {
                    (false, false) => a.link != b.link && !world.is_collision_allowed(robot_id, a.link, b.link)?,
                    (true, true) => false,
                    _ => a.link != b.link,
                };
                if kept && apart(i, j) {
                    pairs.push((i, j));
                }
            }
        }
        Ok(Self {
            limits: group.limits(&robot),
            dofs: group.dofs().to_vec(),
            q_full: q_full.to_vec(),
            base_pose: entry.base_pose,
            robot,
            models,
            pairs,
            obstacles,
            obstacle_balls,
            bound_links: bound.links().to_vec(),
        })
    }

    /// Number of robot primitives (balls and boxes, carried objects included).
    pub fn primitive_count(&self) -> usize {
        self.models.iter().map(|m| m.prims.len()).sum()
    }

    /// Number of obstacle primitives.
    pub fn obstacle_count(&self) -> usize {
        self.obstacles.len()
    }

    /// Number of model pairs kept apart (self-collision and carried objects).
    pub fn pair_count(&self) -> usize {
        self.pairs.len()
    }

    /// Places the model at `q` (group values) into `scratch`.
    fn place(&self, q: &[f64], scratch: &mut Scratch) {
        scratch.full.clear();
        scratch.full.extend_from_slice(&self.q_full);
        for (&d, &v) in self.dofs.iter().zip(q) {
            scratch.full[d] = v;
        }
        forward_kinematics_into(&self.robot, &scratch.full, &mut scratch.poses);
        scratch.balls.clear();
        scratch.prims.clear();
        scratch.ranges.clear();
        for m in &self.models {
            let pose = self.base_pose * scratch.poses[m.link.0];
            scratch.balls.push(((pose * m.ball.0).coords, m.ball.1));
            let start = scratch.prims.len();
            scratch.prims.extend(m.prims.iter().map(|p| Placed::new(p, &pose)));
            scratch.ranges.push((start, scratch.prims.len()));
        }
    }

    /// One advancement step at the placed state: the largest `dt ≤ remaining` (or more) such
    /// that on `[t, t + dt]` every moving link (with what it carries) stays `margin` from the
    /// obstacles and every kept pair `margin` apart, from the lower bounds at `t`; `None` if
    /// some bound is at most `margin`. Links and pairs are visited in `order` (model indices,
    /// nearest first from the previous step), and each one is bounded only as far as needed
    /// against the smallest step found so far.
    fn step(&self, scratch: &mut Scratch, motion: &Motion<'_>, margin: f64, remaining: f64) -> Option<f64> {
        let mut dt = remaining;
        let mut order = std::mem::take(&mut scratch.order);
        for &k in &order {
            let m = &self.models[k];
            let rate = motion.rates[m.slot];
            if !motion.bound.is_moving(m.slot) {
                scratch.ttc[k] = f64::INFINITY;
                continue;
            }
            let enough = rate * dt + 2.0 * margin;
            let (c, r) = scratch.balls[k];
            let prims = &scratch.prims[scratch.ranges[k].0..scratch.ranges[k].1];
            let mut d = enough;
            for (o, (oc, or)) in self.obstacles.iter().zip(&self.obstacle_balls) {
                if (c - oc).norm() - r - or >= d || distance(&Placed::Ball(c, r), o, d) >= d {
                    continue;
                }
                for p in prims {
                    d = d.min(distance(p, o, d));
                }
            }
            if d <= margin {
                return None;
            }
            scratch.ttc[k] = if rate > 0.0 { (d - margin) / rate } else { f64::INFINITY };
            dt = dt.min(scratch.ttc[k]);
        }
        order.sort_by(|&i, &j| scratch.ttc[i].total_cmp(&scratch.ttc[j]));
        scratch.order = order;
        for (k, &(i, j)) in self.pairs.iter().enumerate() {
            let rate = motion.pair_rates[k];
            let enough = rate * dt + 2.0 * margin;
            let ((ca, ra), (cb, rb)) = (scratch.balls[i], scratch.balls[j]);
            if (ca - cb).norm() - ra - rb >= enough {
                continue;
            }
            let d = scratch.pair_distance(i, j, enough);
            if d <= margin {
                return None;
            }
            if rate > 0.0 {
                dt = dt.min((d - margin) / rate);
            }
        }
        Some(dt)
    }

    /// Bound on the relative motion of the two models of each pair for the motion `dq`: only
    /// the group joints on one model's chain and not the other's move them apart (joints on
    /// both chains move both rigidly), each by at most `|dq_j| r_ij` (see [`MotionBound`]).
    fn pair_rates(&self, bound: &MotionBound, dq: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.extend(self.pairs.iter().map(|&(i, j)| {
            let (a, b) = (self.models[i].slot, self.models[j].slot);
            dq.iter()
                .enumerate()
                .map(|(g, d)| {
                    let (ra, rb) = (bound.radius(a, g), bound.radius(b, g));
                    let r = if ra > 0.0 && rb > 0.0 { 0.0 } else { ra + rb };
                    r * d.abs()
                })
                .sum::<f64>()
        }));
    }
}

/// The motion being certified: its bound and per-link and per-pair rates.
struct Motion<'a> {
    bound: &'a MotionBound,
    rates: Vec<f64>,
    pair_rates: Vec<f64>,
}

/// Buffers of [`SphereCertifier::certify`].
#[derive(Default)]
struct Scratch {
    /// Model visiting order and each model's time to contact at the last step.
    order: Vec<usize>,
    ttc: Vec<f64>,
    full: Vec<f64>,
    poses: Vec<Isometry3<f64>>,
    balls: Vec<(Vector3<f64>, f64)>,
    prims: Vec<Placed>,
    ranges: Vec<(usize, usize)>,
}

impl Scratch {
    /// Lower bound on the distance between placed models `i` and `j`, at most `cap`.
    fn pair_distance(&self, i: usize, j: usize, cap: f64) -> f64 {
        let a = &self.prims[self.ranges[i].0..self.ranges[i].1];
        let b = &self.prims[self.ranges[j].0..self.ranges[j].1];
        let mut d = cap;
        for x in a {
            for y in b {
                d = d.min(distance(x, y, d));
            }
        }
        d
    }
}

impl SegmentCertifier for SphereCertifier {
    fn certify(&self, a: &[f64], b: &[f64], bound: &MotionBound, margin: f64, max_steps: usize) -> Certificate {
        let unknown = Certificate::Unknown { near: None };
        let n = self.dofs.len();
        let within = |q: &[f64]| q.len() == n && q.iter().zip(&self.limits).all(|(v, (lo, hi))| *v >= *lo && *v <= *hi);
        if bound.links() != self.bound_links.as_slice()
            || bound.dim() != n
            || !within(a)
            || !within(b)
            || margin.is_nan()
            || margin <= 0.0
        {
            return unknown;
        }
        let dq: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
        let mut motion = Motion {
            bound,
            rates: (0..self.bound_links.len()).map(|i| bound.bound(i, &dq)).collect(),
            pair_rates: Vec::new(),
        };
        self.pair_rates(bound, &dq, &mut motion.pair_rates);
        let mut scratch = Scratch {
            order: (0..self.models.len()).collect(),
            ttc: vec![0.0; self.models.len()],
            ..Scratch::default()
        };
        let mut q = a.to_vec();
        let mut t = 0.0f64;
        for _ in 0..max_steps {
            self.place(&q, &mut scratch);
            // A step reaching past the end by a little finishes the segment.
            let Some(dt) = self.step(&mut scratch, &motion, margin, 1.0 - t + 1e-9) else {
                return Certificate::Unknown { near: Some(t) };
            };
            t += dt;
            if t >= 1.0 {
                return Certificate::Free;
            }
            for ((x, &a0), &dv) in q.iter_mut().zip(a).zip(&dq) {
                *x = a0 + t * dv;
            }
        }
        unknown
    }
}

#[cfg(test)]
mod tests;
