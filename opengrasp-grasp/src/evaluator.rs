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
//! queries grows with the logarithm of the travel, not with a fixed step size.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3, Unit, Vector3};
use opengrasp_core::collision::{CollisionOptions, CollisionWorld, Contact as CoreContact, MeshRepresentation};
use opengrasp_core::hand::Hand;
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::model::{JointKind, LinkId, Shape, TriangleMesh};
use opengrasp_core::physics::{PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::{ObjectId, RobotId, Scene, SceneObject};
use serde::{Deserialize, Serialize};

use crate::contact::{Contact, ObjectFrame};
use crate::error::{GraspError, Result};
use crate::planners::{any_perpendicular, GraspCandidate, HandInfo, Preshape};
use crate::quality::hull::{ConvexHull, HullOptions};
use crate::quality::{GraspQuality, QualityOptions, QualityReport, RobustEpsilon, RobustOptions};
use opengrasp_core::object::ObjectModel;

/// Options of the [`GraspEvaluator`].
#[derive(Clone, Debug, PartialEq)]
pub struct EvaluatorOptions {
    /// The hand approaches until it is this close to the object (m). Default: 2.5e-4.
    pub approach_tolerance: f64,
    /// Largest number of conservative-advancement steps along the approach. Default: 100.
    pub max_approach_steps: usize,
    /// How far (m) the hand may travel past the candidate pose before the candidate counts as
    /// missing the object. Default: 0.5.
    pub max_advance: f64,
    /// A finger stops when its links are closer than this to the object (m). Default: 1e-3.
    pub touch_distance: f64,
    /// Contacts are collected within this distance (m). Default: 2e-3.
    pub contact_margin: f64,
    /// Maximum conservative-advancement iterations while closing. Default: 60.
    pub max_close_iterations: usize,
    /// Smallest closing step per iteration (rad or m of the driving joint). Default: 2e-3.
    pub min_close_step: f64,
    /// Friction coefficient between hand and object; `None` uses the object's. Default: `None`.
    pub friction: Option<f64>,
    /// Quality metrics options; its friction is replaced by `friction` (or the object's).
    /// Default: [`QualityOptions::default`] (8-edge cones, hull for epsilon and volume).
    pub quality: QualityOptions,
    /// Also compute GraspNet's friction score (smallest μ in 0.2..1.2 giving force closure).
    /// Default: `false`.
    pub friction_score: bool,
    /// Also compute Dex-Net's robust epsilon under contact perturbations (expensive: one hull
    /// per sample). Default: `None`.
    pub robust: Option<RobustOptions>,
}

impl Default for EvaluatorOptions {
    fn default() -> Self {
        Self {
            approach_tolerance: 2.5e-4,
            max_approach_steps: 100,
            max_advance: 0.5,
            touch_distance: 1e-3,
            contact_margin: 2e-3,
            max_close_iterations: 60,
            min_close_step: 2e-3,
            friction: None,
            quality: QualityOptions::default(),
            friction_score: false,
            robust: None,
        }
    }
}

impl EvaluatorOptions {
    fn validate(&self) -> Result<()> {
        let positive = [
            ("approach_tolerance", self.approach_tolerance),
            ("max_advance", self.max_advance),
            ("touch_distance", self.touch_distance),
            ("contact_margin", self.contact_margin),
            ("min_close_step", self.min_close_step),
        ];
        for (name, v) in positive {
            crate::planners::check_positive(name, v)?;
        }
        self.quality.validate()?;
        if let Some(mu) = self.friction {
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(GraspError::InvalidParameter {
                    name: "friction",
                    reason: format!("must be >= 0, got {mu}"),
                });
            }
        }
        Ok(())
    }
}

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
    /// True if a palm link touches the object.
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

/// Radius of a ball about the palm frame origin containing the hand in its open preshapes.
fn hand_radius(hand: &Hand, data: &HandData) -> Result<f64> {
    let robot = hand.robot();
    let mut r: f64 = 0.0;
    for (q, rfp) in data.preshape_q.iter().zip(&data.root_from_palm) {
        let fk = forward_kinematics(robot, q)?;
        let to_palm = rfp.inverse();
        for (l, link) in robot.links().iter().enumerate() {
            for s in &link.collisions {
                for c in s.aabb_corners() {
                    r = r.max((to_palm * (fk.as_slice()[l] * c)).coords.norm());
                }
            }
        }
    }
    Ok(r)
}

/// Static data of a hand the evaluator needs (derived once per hand).
#[derive(Clone, Debug)]
struct HandData {
    info: HandInfo,
    /// Pose of the palm frame in the robot root frame, per preshape (palm rigid with root).
    root_from_palm: Vec<Isometry3<f64>>,
    /// Full open configurations, per preshape.
    preshape_q: Vec<Vec<f64>>,
    /// Closing dofs with velocity, links they move and speed bound `R_d`.
    closing: Vec<ClosingDof>,
    /// Finger index of each link (`None` if not in a finger).
    link_finger: Vec<Option<usize>>,
    /// Links that count as palm.
    palm_links: Vec<bool>,
}

#[derive(Clone, Debug)]
struct ClosingDof {
    dof: usize,
    velocity: f64,
    links: Vec<usize>,
    speed_bounds: Vec<f64>,
}

/// Derives the planner-facing description of a hand: approach and closing axes in the palm
/// frame and the widest graspable object.
///
/// The closing axis is the principal direction (perpendicular to the approach) of the
/// fingertip displacements when all fingers close fully from the default preshape; the
/// aperture is the extent of the open hand's geometry along it.
///
/// # Errors
/// [`GraspError::Core`] if the hand's model cannot be evaluated.
pub fn hand_info(hand: &Hand) -> Result<HandInfo> {
    Ok(hand_data(hand)?.info)
}

fn hand_data(hand: &Hand) -> Result<HandData> {
    let robot = hand.robot();
    let n_links = robot.links().len();
    let open = hand.open_configuration();
    let fk = forward_kinematics(robot, &open)?;
    let palm_root = fk.as_slice()[hand.palm().0] * hand.palm_frame();
    let approach = hand.approach();
    let mut link_finger = vec![None; n_links];
    for (f, finger) in hand.fingers().iter().enumerate() {
        for l in &finger.links {
            link_finger[l.0] = Some(f);
        }
    }
    // The palm assembly: links with geometry that no closing joint moves (the palm and, e.g.,
    // the Barrett knuckles on the spread joint).
    let closing_v = hand.closing_velocity();
    let palm_links: Vec<bool> = (0..n_links)
        .map(|l| {
            !robot.links()[l].collisions.is_empty()
                && robot.chain_to(LinkId(l)).iter().all(|&j| {
                    robot.driving_dof(j).is_none_or(|(d, m)| m == 0.0 || closing_v.get(d).is_none_or(|&v| v == 0.0))
                })
        })
        .collect();
    // Closing axis from fingertip velocities.
    let v = hand.closing_velocity();
    let mut q2 = open.clone();
    for (d, vd) in v.iter().enumerate() {
        q2[d] += 10.0 * vd.signum();
    }
    robot.clamp_configuration(&mut q2);
    let fk2 = forward_kinematics(robot, &q2)?;
    let to_palm = palm_root.inverse();
    let a = approach.into_inner();
    let mut scatter = nalgebra::Matrix3::zeros();
    for finger in hand.fingers() {
        if let Some(tip) = finger.links.last() {
            let p1 = to_palm * fk.as_slice()[tip.0].translation.vector;
            let p2 = to_palm * fk2.as_slice()[tip.0].translation.vector;
            let mut dv = p2 - p1;
            dv -= a * a.dot(&dv);
            scatter += dv * dv.transpose();
        }
    }
    let eig = nalgebra::SymmetricEigen::new(scatter);
    let k = eig.eigenvalues.imax();
    let mut closing = eig.eigenvectors.column(k).into_owned();
    closing -= a * a.dot(&closing);
    if closing.norm() < 1e-9 || eig.eigenvalues[k] < 1e-16 {
        closing = any_perpendicular(&a);
    }
    let closing = closing.normalize();
    let kk = closing.iamax();
    let closing = Unit::new_unchecked(if closing[kk] < 0.0 { -closing } else { closing });
    // Aperture: extent of the hand's geometry along the closing axis at the open preshape.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (l, link) in robot.links().iter().enumerate() {
        for s in &link.collisions {
            for c in s.aabb_corners() {
                let t = (to_palm * (fk.as_slice()[l] * c)).coords.dot(&closing);
                lo = lo.min(t);
                hi = hi.max(t);
            }
        }
    }
    let max_aperture = if hi > lo { hi - lo } else { 0.0 };
    // Closing dofs: the links each moves, with a bound on each link's speed per unit of dof
    // motion (sum over the joints the dof drives of |multiplier| × the link's farthest reach
    // from that joint's axis point; 1 per unit for prismatic joints), plus 20 % slack.
    let mut closing_dofs = Vec::new();
    for (d, &vd) in v.iter().enumerate() {
        if vd == 0.0 {
            continue;
        }
        let mut links: Vec<usize> = Vec::new();
        let mut bounds: Vec<f64> = Vec::new();
        for (jid, joint) in robot.joints().iter().enumerate() {
            let jid = opengrasp_core::model::JointId(jid);
            let Some((dd, m)) = robot.driving_dof(jid) else { continue };
            if dd != d || m == 0.0 {
                continue;
            }
            let origin = fk.as_slice()[joint.child.0].translation.vector;
            for (l, link) in robot.links().iter().enumerate() {
                if link.collisions.is_empty() || !robot.chain_to(LinkId(l)).contains(&jid) {
                    continue;
                }
                let mut reach: f64 = 0.0;
                for s in &link.collisions {
                    for c in s.aabb_corners() {
                        reach = reach.max(((fk.as_slice()[l] * c).coords - origin).norm());
                    }
                }
                let speed = m.abs() * if joint.kind == JointKind::Prismatic { 1.0 } else { reach };
                match links.iter().position(|&x| x == l) {
                    Some(k) => bounds[k] += speed,
                    None => {
                        links.push(l);
                        bounds.push(speed);
                    }
                }
            }
        }
        if !links.is_empty() {
            let speed_bounds = bounds.iter().map(|b| (b * 1.2).max(1e-6)).collect();
            closing_dofs.push(ClosingDof { dof: d, velocity: vd, links, speed_bounds });
        }
    }
    let mut root_from_palm = Vec::new();
    let mut preshape_q = Vec::new();
    let home = robot.home_configuration();
    for p in hand.preshapes() {
        let q = hand.preshape_configuration(&p.name, &home)?;
        let fkp = forward_kinematics(robot, &q)?;
        root_from_palm.push(fkp.as_slice()[hand.palm().0] * hand.palm_frame());
        preshape_q.push(q);
    }
    if preshape_q.is_empty() {
        root_from_palm.push(palm_root);
        preshape_q.push(open);
    }
    let info = HandInfo {
        name: hand.name().to_string(),
        approach,
        closing,
        preshapes: hand.preshapes().iter().map(|p| p.name.clone()).collect(),
        max_aperture,
    };
    Ok(HandData { info, root_from_palm, preshape_q, closing: closing_dofs, link_finger, palm_links })
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

    fn place(&mut self, palm: &Isometry3<f64>, root_from_palm: &Isometry3<f64>) -> Result<()> {
        let base = palm * root_from_palm.inverse();
        self.world.set_robot_base_pose(self.robot, base)?;
        self.hull_world.set_robot_base_pose(self.robot, base)?;
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
        for _ in 0..o.max_approach_steps {
            self.place(&at(s), &rfp)?;
            // The hull distance bounds the exact one from below and is cheap: use it while
            // the hand is far from the hull.
            let mut d = self.hull_world.distance(self.robot, &q_open)?.distance;
            if d <= HULL_SWITCH_DISTANCE && !self.convex {
                d = self.world.distance(self.robot, &q_open)?.distance;
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
        self.place(&palm, &rfp)?;
        // 2. Close the fingers by conservative advancement.
        let q = self.close(q_open)?;
        // 3. Contacts in the object frame (= world frame), inward normals.
        let raw = self.world.contacts_with_object(self.robot, &q, self.object, o.contact_margin)?;
        let mut evaluation = self.collect(palm, q, &raw, retraction);
        // 4. Quality: force closure for every grasp; the 6-D hull (epsilon, volume) only for
        // force-closure grasps (it is the expensive part, and epsilon is 0 otherwise).
        let contacts: Vec<Contact> = evaluation.contacts.iter().map(|c| c.contact).collect();
        let mut light = self.quality.clone();
        light.compute_hull = false;
        let report = GraspQuality::evaluate_hull_if_closure(&contacts, &self.frame, &self.quality)?;
        evaluation.quality = Some(report);
        if self.options.friction_score {
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
            self.place(&at(next), rfp)?;
            if self.world.in_collision_unchecked(self.robot, q) {
                let mut hit = next;
                while free - hit > tolerance {
                    let mid = 0.5 * (free + hit);
                    self.place(&at(mid), rfp)?;
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

    /// Replaces hull distances in `dist` by exact ones wherever the closing step reads them:
    /// the result gives every active closing dof exactly the step and stop decision it would
    /// get from exact distances for all its links, without querying links whose hull bound
    /// already proves they cannot be the limiting one.
    ///
    /// Every link within [`HULL_SWITCH_DISTANCE`] of the hull gets its exact distance (it may
    /// stop its finger); the farther links are refined in rounds, per dof, only while their hull
    /// bound on the step `(d − touch/2) / R` is below the smallest exact-based step found so
    /// far (the exact distance is at least the hull bound, so a skipped link never lowers the
    /// minimum, and it is farther than the touch distance).
    fn refine_exact(
        &self,
        q: &[f64],
        active: &[bool],
        dist: &mut [f64],
        known: &mut [bool],
        mask: &mut [bool],
        exact: &mut Vec<f64>,
    ) -> Result<()> {
        let half_touch = 0.5 * self.options.touch_distance;
        known.iter_mut().for_each(|k| *k = false);
        let mut first = true;
        loop {
            mask.iter_mut().for_each(|m| *m = false);
            let mut any = false;
            for (c, _) in self.data.closing.iter().zip(active).filter(|(_, &act)| act) {
                let bound = |l: usize, r: f64| (dist[l] - half_touch) / r;
                let mut current = f64::INFINITY;
                for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                    if known[l] || (first && dist[l] <= HULL_SWITCH_DISTANCE) {
                        current = current.min(bound(l, r));
                    }
                }
                if first {
                    for &l in &c.links {
                        if dist[l] <= HULL_SWITCH_DISTANCE {
                            mask[l] = true;
                            any = true;
                        }
                    }
                }
                if current == f64::INFINITY {
                    // Nothing exact yet for this dof: start with its most limiting link.
                    let pick = c
                        .links
                        .iter()
                        .zip(&c.speed_bounds)
                        .filter(|(&l, _)| !known[l])
                        .min_by(|a, b| bound(*a.0, *a.1).total_cmp(&bound(*b.0, *b.1)));
                    if let Some((&l, _)) = pick {
                        mask[l] = true;
                        any = true;
                    }
                } else if !first {
                    for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                        if !known[l] && bound(l, r) < current {
                            mask[l] = true;
                            any = true;
                        }
                    }
                }
            }
            if !any {
                return Ok(());
            }
            self.world.selected_link_distances_into(self.robot, q, mask, exact)?;
            for l in 0..dist.len() {
                if mask[l] && !known[l] {
                    dist[l] = exact[l];
                    known[l] = true;
                }
            }
            first = false;
        }
    }

    fn close(&self, mut q: Vec<f64>) -> Result<Vec<f64>> {
        let o = &self.options;
        let robot = self.hand.robot();
        let mut active: Vec<bool> = vec![true; self.data.closing.len()];
        let mut dist = Vec::new();
        let mut exact = Vec::new();
        let mut near = vec![false; robot.links().len()];
        let mut known = vec![false; robot.links().len()];
        let mut moving = vec![false; robot.links().len()];
        for _ in 0..o.max_close_iterations {
            if !active.iter().any(|&x| x) {
                break;
            }
            // Only the links of active closing dofs matter (the palm and stopped fingers are
            // never read): query those alone.
            moving.iter_mut().for_each(|x| *x = false);
            for (c, _) in self.data.closing.iter().zip(&active).filter(|(_, &act)| act) {
                for &l in &c.links {
                    moving[l] = true;
                }
            }
            // Distances to the object's convex hull are lower bounds of the true ones and far
            // cheaper for non-convex meshes; near the hull, the exact distances are needed.
            self.hull_world.selected_link_distances_into(self.robot, &q, &moving, &mut dist)?;
            if !self.convex {
                let any_near = moving.iter().zip(&dist).any(|(&m, &d)| m && d <= HULL_SWITCH_DISTANCE);
                if any_near {
                    self.refine_exact(&q, &active, &mut dist, &mut known, &mut near, &mut exact)?;
                }
            }
            for (c, act) in self.data.closing.iter().zip(active.iter_mut()) {
                if !*act {
                    continue;
                }
                let mut gap = f64::INFINITY;
                let mut advance = f64::INFINITY;
                for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                    gap = gap.min(dist[l]);
                    advance = advance.min((dist[l] - 0.5 * o.touch_distance) / r);
                }
                if gap <= o.touch_distance {
                    *act = false;
                    continue;
                }
                let ds = advance.max(o.min_close_step);
                let (lo, hi) = robot.dof_limits(c.dof);
                let next = (q[c.dof] + c.velocity.signum() * ds).clamp(lo, hi);
                if next == q[c.dof] {
                    *act = false;
                }
                q[c.dof] = next;
            }
        }
        Ok(q)
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
            } else if self.data.palm_links[l] {
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

/// Options of the physics check ([`physics_check`]).
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicsCheckOptions {
    /// Directions of gravity tried one after the other, each in a fresh simulation (object
    /// frame). Default: the six axis directions ±x, ±y, ±z.
    pub directions: Vec<Vector3<f64>>,
    /// Magnitude of gravity (m/s²). Default: 9.81.
    pub gravity: f64,
    /// Time (s) the fingers squeeze without gravity before it is switched on. Default: 0.2.
    pub settle: f64,
    /// Simulated time per direction with gravity on (s). Default: 0.5.
    pub duration: f64,
    /// The closing joints (those with a non-zero closing velocity) are commanded this far (rad
    /// or m) beyond the closed configuration, so the motors keep pressing the fingers against
    /// the object (with the simulator's joint stiffness, capped at the joints' effort limits).
    /// Default: 0.05.
    pub squeeze: f64,
    /// The object counts as held if gravity moves it less than this (m): the distance between
    /// its pose after `settle + duration` with gravity and its pose after the same time in a
    /// gravity-free control run (which cancels any squeeze-induced creep of the simulator).
    /// Default: 0.02.
    pub max_translation: f64,
    /// ... and turns it less than this (rad), measured the same way. Default: 0.35 (20°).
    pub max_rotation: f64,
    /// Simulator settings (gravity is overridden; the hand's link friction is replaced by the
    /// object's friction coefficient, so the contacts have the μ the evaluator assumed).
    /// Default: [`PhysicsOptions::default`] with `contact_frequency` 30 Hz (rapier's own
    /// default): with stiffer contacts an object squeezed hard creeps through the grip by
    /// centimetres per second (a solver artefact, measured with rapier 0.30).
    pub physics: PhysicsOptions,
}

impl Default for PhysicsCheckOptions {
    fn default() -> Self {
        Self {
            directions: vec![Vector3::x(), -Vector3::x(), Vector3::y(), -Vector3::y(), Vector3::z(), -Vector3::z()],
            gravity: 9.81,
            settle: 0.2,
            duration: 0.5,
            squeeze: 0.05,
            max_translation: 0.02,
            max_rotation: 0.35,
            physics: PhysicsOptions { contact_frequency: 30.0, ..PhysicsOptions::default() },
        }
    }
}

/// Result of a physics check: how far the object moved under each gravity direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicsOutcome {
    /// Object displacement (m) per gravity direction.
    pub translations: Vec<f64>,
    /// Object rotation (rad) per gravity direction.
    pub rotations: Vec<f64>,
    /// Whether the object stayed in the hand, per gravity direction.
    pub held_per_direction: Vec<bool>,
}

impl PhysicsOutcome {
    /// True if the object stayed in the hand for every gravity direction.
    pub fn held(&self) -> bool {
        !self.held_per_direction.is_empty() && self.held_per_direction.iter().all(|&h| h)
    }
}

/// Checks a closed grasp in the rapier simulator: see [`physics_check_with`].
///
/// # Errors
/// As [`physics_check_with`].
pub fn physics_check(
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    options: &PhysicsCheckOptions,
) -> Result<PhysicsOutcome> {
    physics_check_with::<RapierBackend>(hand, object, evaluation, options)
}

/// Checks a closed grasp on physics backend `E`.
///
/// The hand is fixed at the evaluated pose in its closed configuration; the closing joints
/// (non-zero closing velocity; spread and other joints hold their value) are commanded
/// `squeeze` beyond it, so the motors press the fingers against the object up to the joints'
/// effort limits. The fingers squeeze for `settle` seconds without gravity, then gravity is
/// switched on for `duration`. The object (free, with its mass, inertia and friction, which
/// also replaces the links' friction) is held for a direction if its final pose differs from
/// the final pose of a gravity-free control run of the same length by at most
/// `max_translation` and `max_rotation`: the difference is what gravity did, while slow
/// squeeze-induced creep of the simulator, present in both runs, cancels out.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for bad options or an evaluation without a closed hand;
/// [`GraspError::Core`] from the simulator.
pub fn physics_check_with<E: PhysicsEngine>(
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    options: &PhysicsCheckOptions,
) -> Result<PhysicsOutcome> {
    if evaluation.status != EvaluationStatus::Closed {
        return Err(GraspError::InvalidParameter { name: "evaluation", reason: "the hand did not close".into() });
    }
    for (name, v) in [
        ("gravity", options.gravity),
        ("duration", options.duration),
        ("max_translation", options.max_translation),
        ("max_rotation", options.max_rotation),
    ] {
        crate::planners::check_positive(name, v)?;
    }
    for (name, v) in [("settle", options.settle), ("squeeze", options.squeeze)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(GraspError::InvalidParameter { name, reason: format!("must be finite and >= 0, got {v}") });
        }
    }
    let robot = hand.robot();
    let q = &evaluation.q;
    let fk = forward_kinematics(robot, q)?;
    let root_from_palm = fk.as_slice()[hand.palm().0] * hand.palm_frame();
    let base = evaluation.hand_pose * root_from_palm.inverse();
    let mut target = q.clone();
    for (d, &v) in hand.closing_velocity().iter().enumerate() {
        // `0.0_f64.signum()` is 1: joints that do not close must hold their value.
        if v != 0.0 {
            target[d] += options.squeeze * v.signum();
        }
    }
    robot.clamp_configuration(&mut target);
    let mut scene = Scene::new("physics check");
    let oid = scene.add_object(object.to_scene_object(Isometry3::identity()))?;
    let rid = scene.add_robot("hand", hand.robot_arc(), base)?;
    scene.set_robot_configuration(rid, q)?;
    let physics =
        PhysicsOptions { gravity: Vector3::zeros(), link_friction: object.friction, ..options.physics.clone() };
    let dt = physics.timestep;
    let (settle_steps, steps) = ((options.settle / dt).ceil() as usize, (options.duration / dt).ceil() as usize);
    // Settle the squeezing fingers without gravity, then run with `gravity` (zero: control).
    let run = |gravity: Vector3<f64>| -> Result<Isometry3<f64>> {
        let mut engine = E::from_scene(&scene, &physics)?;
        engine.set_joint_position_targets(rid, &target)?;
        engine.step_n(settle_steps, dt)?;
        engine.set_gravity(gravity)?;
        engine.step_n(steps, dt)?;
        Ok(engine.object_pose(oid)?)
    };
    let mut gravities = Vec::with_capacity(options.directions.len());
    for dir in &options.directions {
        let n = dir.norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(GraspError::InvalidParameter { name: "directions", reason: format!("bad direction {dir:?}") });
        }
        gravities.push(dir * (options.gravity / n));
    }
    let control = run(Vector3::zeros())?;
    let mut out = PhysicsOutcome { translations: Vec::new(), rotations: Vec::new(), held_per_direction: Vec::new() };
    for g in gravities {
        let pose = run(g)?;
        let translation = (pose.translation.vector - control.translation.vector).norm();
        let rotation = pose.rotation.angle_to(&control.rotation);
        out.translations.push(translation);
        out.rotations.push(rotation);
        out.held_per_direction.push(translation <= options.max_translation && rotation <= options.max_rotation);
    }
    Ok(out)
}
