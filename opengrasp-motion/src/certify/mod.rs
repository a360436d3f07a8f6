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
//!   `s`, which contains the capsule), a cylinder by itself, every other shape (box, mesh) by
//!   the oriented box of its local bounding box; objects carried by the robot likewise, on
//!   their link;
//! - **obstacles**: every static body's and free object's shape likewise;
//! - **distances**: lower bounds only — ball–box and ball–ball exactly, box–box by the largest
//!   separating-axis gap over the 15 axes of the pair (the gap along a unit axis never exceeds
//!   the distance), cylinder–box by the gap over a few axes with the cylinder's own support
//!   function (exact for an upright cylinder beside a box face or vertical edge, e.g. a mobile
//!   base passing furniture);
//! - **motion**: conservative advancement (as [`segment_valid_continuous`]) with the same
//!   per-link [`MotionBound`] as the exact validator: link `i` is certified against an
//!   obstacle on `[t, t + (d̃ᵢ − m) / Bᵢ]` where `d̃ᵢ` is its lower bound and `m` the margin;
//!   pairs of the robot's own parts with the bound of their relative motion;
//! - **vertical gaps**: a link entirely above (or below) an obstacle is also certified on
//!   `[t, t + (g − m) / Vᵢ]` with `g` the vertical gap and `Vᵢ` a bound on its vertical speed,
//!   in which a mobile base sliding or turning on the floor and a torso turning about a
//!   vertical axis count for nothing (so a base 2 cm above the floor crosses the room);
//! - **exact refinement** ([`SphereCertifier::with_exact`]): a link whose model bounds allow
//!   less than [`EXACT_BELOW`] of the segment per step gets the exact distance of the checker's
//!   collision world (the very distance the exact continuous validator measures, so also a
//!   lower bound).
//!
//! [`segment_valid_continuous`]: crate::validate::segment_valid_continuous

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{JointGroup, LinkId, Robot};
use opengrasp_core::scene::{RobotId, Scene};

use crate::error::{MotionError, Result};
use crate::validity::{CollisionChecker, MotionBound};
use geometry::{shape_prims, Placed, Prim};
use vertical::vertical_radii;

/// A link whose model bounds allow less than this fraction of the segment per advancement
/// step gets an exact distance query (when the certifier has the exact world).
pub const EXACT_BELOW: f64 = 0.002;

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

    /// [`SegmentCertifier::certify`] in two stages of `(first_steps, max_steps)`: if the first
    /// `first_steps` steps run out while the proof is still advancing, `proceed` decides
    /// whether it goes on (`None` if it says no); if it does, the answer is that of `certify`
    /// with `max_steps` steps (at least `first_steps`). Without exhaustion, the answer is that
    /// of `certify` with `first_steps`.
    ///
    /// The default runs `certify` twice; a certifier may resume the first stage's proof
    /// instead of restarting it, with the same answer.
    fn certify_staged(
        &self,
        a: &[f64],
        b: &[f64],
        bound: &MotionBound,
        margin: f64,
        (first_steps, max_steps): (usize, usize),
        proceed: &mut dyn FnMut() -> bool,
    ) -> Option<Certificate> {
        match self.certify(a, b, bound, margin, first_steps) {
            Certificate::Unknown { exhausted: true, .. } => {
                proceed().then(|| self.certify(a, b, bound, margin, max_steps.max(first_steps)))
            }
            c => Some(c),
        }
    }
}

/// The answer of a [`SegmentCertifier`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Certificate {
    /// The motion is proven free (see [`SegmentCertifier::certify`]).
    Free,
    /// Not proven; `near` is the motion parameter `t ∈ [0, 1]` (state `a + t (b − a)`) where
    /// a lower bound fell to the margin or the step budget ran out (advancement slows down
    /// near contacts), if that is why: a good place to look for a collision.
    Unknown {
        /// Where the proof got stuck, if it got anywhere.
        near: Option<f64>,
        /// Whether the step budget ran out while the proof was still advancing (rather than
        /// a bound falling to the margin): a larger budget may prove the motion.
        exhausted: bool,
    },
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
    /// Per pair, one weight per group value: the pair's relative motion is at most
    /// `Σⱼ |Δqⱼ| wⱼ` (`pairs.len() × dim`). Only the group joints on one model's chain and not
    /// the other's move them apart (joints on both chains move both rigidly), each by at most
    /// `|Δqⱼ| rᵢⱼ` (see [`MotionBound`]).
    pair_weights: Vec<f64>,
    obstacles: Vec<Placed>,
    /// Bounding ball of each obstacle.
    obstacle_balls: Vec<(Vector3<f64>, f64)>,
    /// Lowest and highest z of each obstacle.
    obstacle_z: Vec<(f64, f64)>,
    /// The motion bound the model was built for.
    bound: MotionBound,
    /// Vertical speed radii (see [`vertical_radii`]), like the bound's radii.
    vertical: Vec<f64>,
    robot_id: RobotId,
    /// The joints on the models' chains in topological order, with the transform from parent
    /// link to child link of those the group does not move (`None`: computed per state).
    chain: Vec<(opengrasp_core::model::JointId, Option<Isometry3<f64>>)>,
    /// The exact checker whose world refines the links the model cannot clear.
    exact: Option<CollisionChecker>,
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
        let obstacles: Vec<Placed> = obstacles.iter().map(|p| Placed::new(p, &Isometry3::identity())).collect();
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
        let mut needed = vec![false; robot.joints().len()];
        for m in &models {
            for j in robot.chain_to(m.link) {
                needed[j.0] = true;
            }
        }
        let chain = robot
            .joints_topological()
            .iter()
            .filter(|j| needed[j.0])
            .map(|&j| {
                let joint = robot.joint(j);
                let moved = robot.driving_dof(j).is_some_and(|(d, _)| group.dofs().contains(&d));
                (j, (!moved).then(|| joint.origin * joint.motion(robot.joint_position(q_full, j))))
            })
            .collect();
        let pair_weights = pairs
            .iter()
            .flat_map(|&(i, j)| {
                let (a, b) = (models[i].slot, models[j].slot);
                bound.pair_radii(&robot, group, a, b)
            })
            .collect();
        Ok(Self {
            chain,
            pair_weights,
            limits: group.limits(&robot),
            dofs: group.dofs().to_vec(),
            q_full: q_full.to_vec(),
            base_pose: entry.base_pose,
            vertical: vertical_radii(&robot, group, &entry.base_pose, q_full, bound),
            robot,
            models,
            pairs,
            obstacle_z: obstacles.iter().map(Placed::z_range).collect(),
            obstacles,
            obstacle_balls,
            bound: bound.clone(),
            robot_id,
            exact: None,
        })
    }

    /// Lets the certifier refine the links its model cannot clear by exact distance queries in
    /// `checker`'s collision world (see the [module docs](self)). `checker` must be the exact
    /// checker of the scene the certifier was built from (same robot, group, `q_full` and
    /// motion bound).
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`] if `checker`'s motion bound is not the certifier's.
    pub fn with_exact(mut self, checker: &CollisionChecker) -> Result<Self> {
        use crate::validity::StateValidityChecker;
        if checker.motion_bound() != Some(&self.bound) || checker.dim() != self.dofs.len() {
            return Err(MotionError::InvalidParameter {
                name: "checker",
                reason: "its motion bound or group differs from the certifier's".into(),
            });
        }
        self.exact = Some(checker.clone());
        Ok(self)
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

    /// Bound on the vertical distance any point of link index `i` (of the motion bound) moves
    /// along the straight motion `dq` (group values): `Σ_j |dq_j| v_ij`, where base and torso
    /// joints that keep heights (prismatic along horizontal axes, revolute about vertical
    /// ones) count for nothing. `None` for an index or a `dq` that does not fit.
    pub fn vertical_bound(&self, i: usize, dq: &[f64]) -> Option<f64> {
        let n = self.dofs.len();
        let row = self.vertical.get(i * n..(i + 1) * n).filter(|_| dq.len() == n)?;
        Some(row.iter().zip(dq).map(|(v, d)| v * d.abs()).sum())
    }
}

mod advance;
mod geometry;
#[cfg(test)]
mod tests;
mod vertical;
