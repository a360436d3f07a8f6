//! The shared grasp evaluator: the one criterion every planner is graded by.
//!
//! Following the OpenGRASP benchmark (Ulbrich et al. 2011, section IV-A), a candidate is tested
//! by placing the hand at the candidate pose (where it normally collides with the object),
//! retracting it along the approach direction until it is collision-free, closing the fingers
//! until they touch the object or reach their limits, collecting the contacts and computing the
//! grasp quality metrics on them. The evaluator also records whether the palm touches the
//! object (the seed paper counts only such grasps) and, optionally, checks the grasp in a
//! physics simulation.
//!
//! Geometry queries go through [`opengrasp_core::collision::CollisionWorld`]; the hand is a
//! floating robot whose base is moved to each candidate pose, the object sits at the world
//! origin (object frame = world frame).
//!
//! Closing uses conservative advancement: every closing degree of freedom `d` advances by
//! `(gap − touch_distance / 2) / R_d`, where the gap is the smallest distance of the links it
//! moves to the object and `R_d` bounds how fast any point of those links moves per unit of
//! `d`. Each step is thus safe (no tunnelling through thin walls) and the number of distance
//! queries grows with the logarithm of the travel, not with a fixed step size. A link is
//! queried only when its lower bound (its last distance minus how far the step may have moved
//! it) could set its finger's step or stop it; the steps are exactly those of querying every
//! link.

mod balance;
mod closing;
mod grip;
mod grip_sim;
mod hand_data;
mod options;
mod physics;
mod physics_options;
mod release;
mod static_hold;
mod stepping;

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3};
use opengrasp_core::collision::{
    CollisionOptions, CollisionWorld, Contact as CoreContact, MeshRepresentation, NearestTriangles,
};
use opengrasp_core::hand::Hand;
use opengrasp_core::model::{Shape, TriangleMesh};
use opengrasp_core::scene::{ObjectId, RobotId, Scene, SceneObject};
use serde::{Deserialize, Serialize};

use crate::contact::{Contact, ObjectFrame};
use crate::error::{GraspError, Result};
use crate::planners::{GraspCandidate, HandInfo, Preshape};
use crate::quality::hull::{ConvexHull, HullOptions};
use crate::quality::{GraspQuality, QualityOptions, QualityReport, RobustEpsilon};
use opengrasp_core::object::ObjectModel;

pub use balance::release_imbalance;
pub use grip::{closing_grip, command_grip, grip_torques, stiffen_grip, GripTorques, JointTorque};
pub use grip_sim::{after_squeeze, simulated_contacts, simulated_evaluation};
pub use hand_data::hand_info;
use hand_data::{hand_data, hand_radius, HandData};
pub use options::EvaluatorOptions;
pub use physics::{physics_check, physics_check_with, settle_grip, HoldResult, PhysicsOutcome, SettledGrip};
pub use physics_options::PhysicsCheckOptions;
pub use release::{fixture_wrench, release_gradually, undamp_gradually, ReleaseWindow};
pub use static_hold::{static_hold, ActuatorLoad, StaticDirection, StaticHoldOptions, StaticHoldOutcome};
pub use stepping::AdaptiveStep;

/// How an evaluation ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum EvaluationStatus {
    /// The fingers closed and touched the object (see the contacts for how well).
    Closed,
    /// The hand never touched the object moving along the approach direction.
    Missed,
}

/// A contact of the closed hand with the object.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraspContact {
    /// The hand link touching the object (index into the hand robot's links).
    pub link: usize,
    /// Finger index in the hand's finger list, `None` for the palm or other links.
    pub finger: Option<usize>,
    /// The contact (object frame, inward normal).
    pub contact: Contact,
    /// Penetration depth (m, negative for a gap within the contact margin).
    pub depth: f64,
}

/// The result of evaluating one candidate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraspEvaluation {
    /// How the evaluation ended.
    pub status: EvaluationStatus,
    /// Final palm pose in the object frame (after retraction and standoff).
    pub hand_pose: Isometry3<f64>,
    /// Final hand configuration (after closing).
    pub q: Vec<f64>,
    /// Contacts with the object.
    pub contacts: Vec<GraspContact>,
    /// True if a palm link touches the object: closer than
    /// [`EvaluatorOptions::touch_distance`] (contacts farther than that but within the contact
    /// margin are still collected, but do not count as the palm touching).
    pub palm_contact: bool,
    /// Number of fingers touching the object.
    pub fingers_in_contact: usize,
    /// Distance (m) from the candidate pose back along the approach to the touching pose
    /// (negative if the hand moved past the candidate pose).
    pub retraction: f64,
    /// Quality metrics of the contacts (`None` if the hand did not close on the object).
    pub quality: Option<QualityReport>,
    /// GraspNet friction score, if requested and the hand closed: `Some(None)` if the grasp is
    /// not force closure even at μ = 1.2.
    pub friction_score: Option<Option<f64>>,
    /// Robust epsilon, if requested and the hand closed.
    pub robust_epsilon: Option<RobustEpsilon>,
}

impl GraspEvaluation {
    /// True if the grasp is force closure.
    pub fn force_closure(&self) -> bool {
        self.quality.is_some_and(|q| q.force_closure)
    }

    /// Ferrari-Canny epsilon (0 without force closure or quality).
    pub fn epsilon(&self) -> f64 {
        self.quality.map_or(0.0, |q| q.epsilon)
    }
}

/// Below this distance (m) to the object's convex hull, closing switches to exact distances.
const HULL_SWITCH_DISTANCE: f64 = 0.005;

/// Below this distance (m) the approach stops trusting conservative advancement (which crawls
/// when a link grazes the object) and marches with collision tests.
const GRAZE_DISTANCE: f64 = 0.002;

/// Step (m) of the marching approach; thinner than any finger plus wall, so nothing tunnels.
const MARCH_STEP: f64 = 0.003;

/// The collision worlds of a [`GraspEvaluator`] a placement of the hand applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Worlds {
    /// The object's convex hull only (the approach far from the object).
    Hull,
    /// The exact object only (the marching approach, near or non-convex steps).
    Exact,
    /// Both (closing reads both).
    Both,
}

/// Grades candidate grasps of one hand on one object (see the module docs for the procedure).
///
/// Deterministic: the same candidate always gives the same evaluation.
#[derive(Clone, Debug)]
pub struct GraspEvaluator {
    hand: Hand,
    data: HandData,
    world: CollisionWorld,
    hull_world: CollisionWorld,
    /// The object is convex: hull distances are exact.
    convex: bool,
    /// Radius of a ball about the object origin containing the object (m).
    object_radius: f64,
    /// Radius of a ball about the palm frame containing the open hand (m).
    hand_radius: f64,
    robot: RobotId,
    object: ObjectId,
    frame: ObjectFrame,
    quality: QualityOptions,
    options: EvaluatorOptions,
}

impl GraspEvaluator {
    /// An evaluator for `hand` grasping `object` (its mesh, centre of mass and friction).
    ///
    /// # Errors
    /// As [`GraspEvaluator::from_mesh`].
    pub fn new(hand: &Hand, object: &ObjectModel, options: EvaluatorOptions) -> Result<Self> {
        Self::from_mesh(hand, object.mesh.clone(), object.center_of_mass(), object.friction, options)
    }

    /// An evaluator for `hand` grasping the closed mesh `object` (object frame = world frame)
    /// with centre of mass `com` and friction coefficient `friction` (used unless the options
    /// override it).
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] / [`GraspError::NonFinite`] for bad options, friction or
    /// centre of mass; [`GraspError::Core`] if the hand or object geometry cannot be used for
    /// collision queries.
    pub fn from_mesh(
        hand: &Hand,
        object: Arc<TriangleMesh>,
        com: Point3<f64>,
        friction: f64,
        options: EvaluatorOptions,
    ) -> Result<Self> {
        options.validate()?;
        let data = hand_data(hand)?;
        let frame = ObjectFrame::from_points(com, object.vertices())?;
        let mut quality = options.quality.clone();
        quality.contact.friction = options.friction.unwrap_or(friction);
        quality.validate()?;
        let mut scene = Scene::new("grasp evaluation");
        let object_mesh = object.clone();
        let shape = Shape::at_origin(opengrasp_core::model::Geometry::Mesh(object));
        let object = scene.add_object(SceneObject::new("object", Isometry3::identity(), vec![shape], 1.0))?;
        let far = Isometry3::translation(1e3, 0.0, 0.0);
        let robot = scene.add_robot("hand", hand.robot_arc(), far)?;
        let world =
            CollisionWorld::with_options(&scene, CollisionOptions { meshes: MeshRepresentation::AutoClimbing })?;
        let hull_world =
            CollisionWorld::with_options(&scene, CollisionOptions { meshes: MeshRepresentation::ClimbingHull })?;
        let object_radius = object_mesh.vertices().iter().map(|v| v.coords.norm()).fold(0.0, f64::max);
        let hand_radius = hand_radius(hand, &data)?;
        // Convex if the mesh fills its hull (the same 0.1 % rule as the collision world's
        // automatic mesh representation).
        let coords: Vec<f64> = object_mesh.vertices().iter().flat_map(|v| v.coords.iter().copied()).collect();
        let hull_volume =
            ConvexHull::from_flat(3, &coords, &HullOptions::default()).map_or(f64::INFINITY, |h| h.volume());
        let convex = object_mesh.signed_volume() >= hull_volume * (1.0 - 1e-3);
        Ok(Self {
            hand: hand.clone(),
            data,
            world,
            hull_world,
            convex,
            object_radius,
            hand_radius,
            robot,
            object,
            frame,
            quality,
            options,
        })
    }

    /// The hand being evaluated.
    pub fn hand(&self) -> &Hand {
        &self.hand
    }

    /// The planner-facing description of the hand.
    pub fn hand_info(&self) -> &HandInfo {
        &self.data.info
    }

    /// The evaluator's options.
    pub fn options(&self) -> &EvaluatorOptions {
        &self.options
    }

    /// Full configuration and preshape index for a candidate's preshape.
    fn preshape(&self, preshape: &Preshape) -> Result<(usize, Vec<f64>)> {
        match preshape {
            Preshape::Default => Ok((0, self.data.preshape_q[0].clone())),
            Preshape::Named(name) => {
                let i = self.data.info.preshapes.iter().position(|p| p == name).ok_or_else(|| {
                    GraspError::InvalidParameter { name: "preshape", reason: format!("hand has no preshape `{name}`") }
                })?;
                Ok((i, self.data.preshape_q[i].clone()))
            }
            Preshape::Joints(values) => {
                if values.len() != self.data.closing.len() {
                    return Err(GraspError::InvalidParameter {
                        name: "preshape",
                        reason: format!("{} values for {} closing joints", values.len(), self.data.closing.len()),
                    });
                }
                crate::error::ensure_finite("preshape", values.iter().copied())?;
                let mut q = self.data.preshape_q[0].clone();
                for (c, v) in self.data.closing.iter().zip(values) {
                    q[c.dof] = *v;
                }
                self.hand.robot().clamp_configuration(&mut q);
                Ok((0, q))
            }
        }
    }

    /// Moves the hand's palm to `palm` in the collision worlds `worlds` (only those the next
    /// queries read: each placement redoes the hand's world boxes).
    fn place(&mut self, palm: &Isometry3<f64>, root_from_palm: &Isometry3<f64>, worlds: Worlds) -> Result<()> {
        let base = palm * root_from_palm.inverse();
        if worlds != Worlds::Hull {
            self.world.set_robot_base_pose(self.robot, base)?;
        }
        if worlds != Worlds::Exact {
            self.hull_world.set_robot_base_pose(self.robot, base)?;
        }
        Ok(())
    }

    /// Evaluates one candidate: approach, close, collect contacts, score.
    ///
    /// The hand is placed at the candidate pose and moved back along the approach direction
    /// far enough to clear the object (by bounding balls), then advanced towards the candidate
    /// pose by conservative advancement (each step the hand's distance to the object's convex
    /// hull while farther than 5 mm from it, then the exact distance) until it touches; once
    /// closer than 2 mm without touching (a link grazing the object), it marches in 3 mm steps
    /// with collision tests and bisects the colliding step. For a convex object this is the seed's "retract until collision-free"
    /// from a colliding pose; for non-convex objects (cups, handles) it also works when the
    /// candidate pose lies in a cavity, where a triangle-surface collision test would report no
    /// collision.
    ///
    /// # Errors
    /// [`GraspError::NonFinite`] for a non-finite pose, approach or standoff,
    /// [`GraspError::InvalidParameter`] for an unknown preshape, [`GraspError::Core`] from the
    /// collision queries, quality errors on numerical breakdown.
    pub fn evaluate(&mut self, candidate: &GraspCandidate) -> Result<GraspEvaluation> {
        let t = &candidate.hand_pose;
        crate::error::ensure_finite(
            "candidate",
            t.translation.vector.iter().chain(t.rotation.coords.iter()).chain(candidate.approach.iter()).copied(),
        )?;
        crate::error::ensure_finite("standoff", [candidate.standoff])?;
        let (pi, q_open) = self.preshape(&candidate.preshape)?;
        let rfp = self.data.root_from_palm[pi];
        let a = candidate.approach.into_inner();
        let at = |s: f64| Isometry3::from_parts(Translation3::from(t.translation.vector - a * s), t.rotation);
        let o = self.options.clone();
        // 1. Back off until the bounding balls of hand and object are apart along the approach,
        // then advance by the exact distance until touching.
        let mut s = t.translation.vector.norm() + self.object_radius + self.hand_radius + 0.01;
        let mut touched = false;
        // Warm starts of the exact distances' mesh searches along the approach (the same
        // distances, fewer triangle tests).
        let mut hints = NearestTriangles::new();
        for _ in 0..o.max_approach_steps {
            let pose = at(s);
            self.place(&pose, &rfp, Worlds::Hull)?;
            // The hull distance bounds the exact one from below and is cheap: use it while
            // the hand is far from the hull.
            // (The separation alone: a touching or penetrating hand gives 0, which stops the
            // approach just as the penetration depth did, without the witness-point query.)
            let mut d = self.hull_world.min_distance(self.robot, &q_open)?;
            if d <= HULL_SWITCH_DISTANCE && !self.convex {
                self.place(&pose, &rfp, Worlds::Exact)?;
                d = self.world.min_distance_hinted(self.robot, &q_open, &mut hints)?;
            }
            if d <= o.approach_tolerance {
                touched = true;
                break;
            }
            if d < GRAZE_DISTANCE {
                // A link slides past the object (a finger along its side): the distance stays
                // small while the hand moves on, so march with collision tests instead.
                touched = self.march(&at, &rfp, &q_open, &mut s)?;
                break;
            }
            s -= d - 0.5 * o.approach_tolerance;
            if s < -o.max_advance {
                break;
            }
        }
        if !touched {
            return Ok(self.failed(EvaluationStatus::Missed, at(0.0), q_open, 0.0));
        }
        let retraction = s + candidate.standoff.max(0.0);
        let palm = at(retraction);
        self.place(&palm, &rfp, Worlds::Both)?;
        // 2. Close the fingers by conservative advancement.
        let q = self.close(q_open)?;
        // 3. Contacts in the object frame (= world frame), inward normals.
        let raw = self.world.contacts_with_object(self.robot, &q, self.object, o.contact_margin)?;
        let mut evaluation = self.collect(palm, q, &raw, retraction);
        // 4. Quality: force closure for every grasp; epsilon (and the opt-in hull statistics)
        // only for force-closure grasps (epsilon is 0 otherwise).
        let contacts: Vec<Contact> = evaluation.contacts.iter().map(|c| c.contact).collect();
        let report = GraspQuality::evaluate_hull_if_closure(&contacts, &self.frame, &self.quality)?;
        evaluation.quality = Some(report);
        if self.options.friction_score {
            let mut light = self.quality.clone();
            light.compute_hull = false;
            evaluation.friction_score = Some(GraspQuality::friction_score(&contacts, &self.frame, &light)?);
        }
        if let Some(robust) = &self.options.robust {
            evaluation.robust_epsilon =
                Some(GraspQuality::robust_epsilon(&contacts, &self.frame, &self.quality, robust)?);
        }
        Ok(evaluation)
    }

    /// From a collision-free offset `s`, moves the hand forward in steps of
    /// [`MARCH_STEP`] until it collides, then bisects the last step down to the approach
    /// tolerance; leaves `s` at the last collision-free offset. Returns false if the hand
    /// travels `max_advance` past the candidate pose without collision.
    fn march(
        &mut self,
        at: &impl Fn(f64) -> Isometry3<f64>,
        rfp: &Isometry3<f64>,
        q: &[f64],
        s: &mut f64,
    ) -> Result<bool> {
        let tolerance = self.options.approach_tolerance;
        let mut free = *s;
        loop {
            let next = free - MARCH_STEP;
            if next < -self.options.max_advance {
                *s = free;
                return Ok(false);
            }
            self.place(&at(next), rfp, Worlds::Exact)?;
            if self.world.in_collision_unchecked(self.robot, q) {
                let mut hit = next;
                while free - hit > tolerance {
                    let mid = 0.5 * (free + hit);
                    self.place(&at(mid), rfp, Worlds::Exact)?;
                    if self.world.in_collision_unchecked(self.robot, q) {
                        hit = mid;
                    } else {
                        free = mid;
                    }
                }
                *s = free;
                return Ok(true);
            }
            free = next;
        }
    }

    fn failed(
        &self,
        status: EvaluationStatus,
        hand_pose: Isometry3<f64>,
        q: Vec<f64>,
        retraction: f64,
    ) -> GraspEvaluation {
        GraspEvaluation {
            status,
            hand_pose,
            q,
            contacts: Vec::new(),
            palm_contact: false,
            fingers_in_contact: 0,
            retraction,
            quality: None,
            friction_score: None,
            robust_epsilon: None,
        }
    }

    fn collect(&self, palm: Isometry3<f64>, q: Vec<f64>, raw: &[CoreContact], retraction: f64) -> GraspEvaluation {
        let mut contacts = Vec::with_capacity(raw.len());
        let mut fingers = vec![false; self.hand.fingers().len()];
        let mut palm_contact = false;
        for c in raw {
            let l = c.link.0;
            let finger = self.data.link_finger[l];
            if let Some(f) = finger {
                fingers[f] = true;
            } else if self.data.palm_links[l] && c.depth >= -self.options.touch_distance {
                // The palm touches (as the paper requires, "in direct contact"): within the
                // distance at which a finger counts as touching, not merely within the wider
                // contact margin used to collect contacts.
                palm_contact = true;
            }
            // The core normal points from the object towards the link: inward is its opposite.
            contacts.push(GraspContact {
                link: l,
                finger,
                contact: Contact::from_unit(c.point_on_other, -c.normal),
                depth: c.depth,
            });
        }
        GraspEvaluation {
            status: EvaluationStatus::Closed,
            hand_pose: palm,
            q,
            contacts,
            palm_contact,
            fingers_in_contact: fingers.iter().filter(|&&f| f).count(),
            retraction,
            quality: None,
            friction_score: None,
            robust_epsilon: None,
        }
    }
}
