//! Where contact forces come from: the static grasp evaluator and a physics engine.
//!
//! **Static source** ([`evaluation_contacts`]). The evaluator finds contact points but no
//! forces. The forces are the grasp's internal force distribution from the force-closure
//! solvers of [`crate::quality::solver`]: every primitive wrench of a contact (a friction cone
//! edge) has a unit normal component, so convex weights `λ` with `Σ λ w = 0` (the strict LP's
//! maximally spread zero combination, when the grasp is force closure) or the min-norm QP's
//! weights (the best-balanced combination, otherwise) give contact normal forces
//! `fᵢ = G · Σ_{j ∈ i} λⱼ` summing to the grip force `G`: the fingers squeeze with `G` newtons
//! of total normal force and the object stays in equilibrium (exactly for force-closure
//! grasps, as nearly as the contacts allow otherwise).
//!
//! **Physics source** ([`PhysicsTactile`]). Each step the engine reports contact points with
//! their normal force (impulse over the substep); those on links carrying a pad are expressed
//! in the link frame, and the points one link shares with one other body form one contact
//! patch (the manifold: a flat face gives its corners, read as the rectangle between them).
//! [`physics_tactile_series`] squeezes an evaluated grasp in simulation and records a frame
//! every few steps.

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::hand::Hand;
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::model::LinkId;
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::{ContactBody, JointTarget, PhysicsContact, PhysicsEngine, PhysicsOptions};
use opengrasp_core::scene::{RobotId, Scene};

use super::{LinkContact, TactileArray, TactileFrame};
use crate::contact::{Contact, ContactModel, GraspWrenchSpace, ObjectFrame};
use crate::error::{GraspError, Result};
use crate::evaluator::{EvaluationStatus, GraspEvaluation};
use crate::quality::solver;

/// Default grip force (N): total normal force of the fingers in static frames (nominal).
pub const DEFAULT_GRIP_FORCE: f64 = 10.0;

/// Contact forces of an evaluated grasp for a grip force of `grip_force` newtons (see the
/// module docs), as [`LinkContact`]s in the hand's link frames. `frame` and `model` should be
/// those the evaluator used (object centre of mass and radius, friction). Empty if the hand did
/// not touch the object.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for a non-positive or non-finite grip force or an
/// evaluation whose configuration does not fit the hand; solver errors.
pub fn evaluation_contacts(
    hand: &Hand,
    evaluation: &GraspEvaluation,
    frame: &ObjectFrame,
    model: &ContactModel,
    grip_force: f64,
) -> Result<Vec<LinkContact>> {
    crate::planners::check_positive("grip_force", grip_force)?;
    if evaluation.contacts.is_empty() {
        return Ok(Vec::new());
    }
    let contacts: Vec<Contact> = evaluation.contacts.iter().map(|c| c.contact).collect();
    let ws = GraspWrenchSpace::new(&contacts, frame, model)?;
    let per = model.wrenches_per_contact();
    let strict = solver::strict_combination(ws.wrenches())?;
    let weights = match strict.weights {
        Some(w) if strict.margin > 0.0 => w,
        _ => solver::min_norm_point(ws.wrenches())?.weights,
    };
    let sum: f64 = weights.iter().map(|w| w.max(0.0)).sum();
    if !(sum > 0.0 && sum.is_finite()) {
        return Err(GraspError::Solver { problem: "tactile force distribution", status: "zero weights".into() });
    }
    let robot = hand.robot();
    let fk = forward_kinematics(robot, &evaluation.q)?;
    let poses = fk.as_slice();
    let base = evaluation.hand_pose * (poses[hand.palm().0] * hand.palm_frame()).inverse();
    Ok(evaluation
        .contacts
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let lambda: f64 = weights[i * per..(i + 1) * per].iter().map(|w| w.max(0.0)).sum();
            let link_pose = base * poses[c.link];
            LinkContact::point(
                LinkId(c.link),
                link_pose.inverse_transform_point(&c.contact.point),
                grip_force * lambda / sum,
            )
        })
        .collect())
}

/// Reads an array's frame from physics contacts, reusing its buffers between steps.
#[derive(Debug, Default)]
pub struct PhysicsTactile {
    contacts: Vec<LinkContact>,
    poses: Vec<(LinkId, Isometry3<f64>)>,
    patches: Vec<(LinkId, ContactBody)>,
}

impl PhysicsTactile {
    /// A reader with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// The link contacts of the last [`PhysicsTactile::read`].
    pub fn link_contacts(&self) -> &[LinkContact] {
        &self.contacts
    }

    /// Reads `array` (on robot `robot` of the engine's scene) from the engine's `contacts` of
    /// the last step into `out` (time = the engine's time). Contacts with non-finite values
    /// are skipped.
    ///
    /// # Errors
    /// The engine's errors for an unknown robot or link.
    pub fn read<E: PhysicsEngine + ?Sized>(
        &mut self,
        array: &TactileArray,
        engine: &E,
        robot: RobotId,
        contacts: &[PhysicsContact],
        out: &mut TactileFrame,
    ) -> Result<()> {
        self.contacts.clear();
        self.poses.clear();
        self.patches.clear();
        for c in contacts {
            let (link, other) = match (c.body1, c.body2) {
                (ContactBody::Link { robot: r, link }, other) if r == robot => (link, other),
                (other, ContactBody::Link { robot: r, link }) if r == robot => (link, other),
                _ => continue,
            };
            if !array.sensors().iter().any(|s| s.link() == link) {
                continue;
            }
            let pose = match self.poses.iter().find(|(l, _)| *l == link) {
                Some((_, p)) => *p,
                None => {
                    let p = engine.link_pose(robot, link)?;
                    self.poses.push((link, p));
                    p
                }
            };
            let patch = match self.patches.iter().position(|&(l, o)| l == link && o == other) {
                Some(i) => i,
                None => {
                    self.patches.push((link, other));
                    self.patches.len() - 1
                }
            };
            self.contacts.push(LinkContact {
                link,
                point: pose.inverse_transform_point(&c.point),
                force: c.normal_force,
                patch: patch as u32 + 1,
            });
        }
        array.read_into(&self.contacts, out);
        out.time = engine.time();
        Ok(())
    }
}

/// Options of [`physics_tactile_series`].
#[derive(Clone, Debug, PartialEq)]
pub struct TactileSeriesOptions {
    /// Simulated time (s). Default: 0.3.
    pub duration: f64,
    /// The closing joints are commanded this far (rad or m) beyond the closed configuration
    /// (as in the physics hold check). Default: 0.05.
    pub squeeze: f64,
    /// Gravity in the object frame (m/s²). Default: zero (the fingers squeeze a floating object).
    pub gravity: Vector3<f64>,
    /// `Some(f)`: the closing joints are stall-torque actuators instead
    /// ([`JointTarget::Effort`]), each actuator pressing in its closing direction with `f` times
    /// its effort limit (coupled joints share it), and `squeeze` is not used. `None`: position
    /// control `squeeze` past the closed configuration. Default: `None`.
    pub effort: Option<f64>,
    /// Record a frame every this many steps of `physics.timestep` (≥ 1). Default: 6 (40 Hz at
    /// the default 240 Hz step).
    pub every: usize,
    /// Simulator settings (gravity overridden; link friction = the object's). Default: as the
    /// physics hold check (contact frequency 30 Hz).
    pub physics: PhysicsOptions,
}

impl Default for TactileSeriesOptions {
    fn default() -> Self {
        Self {
            duration: 0.3,
            squeeze: 0.05,
            gravity: Vector3::zeros(),
            effort: None,
            every: 6,
            physics: PhysicsOptions { contact_frequency: 30.0, ..PhysicsOptions::default() },
        }
    }
}

/// The simulation of [`physics_tactile_series`] before its first step: the hand fixed at the
/// evaluated pose with its closing joints commanded `squeeze` beyond the closed configuration
/// (or pushing with `options.effort` times their effort limits), the object free (its friction
/// replacing the links'), gravity `options.gravity`. Returns the engine and the hand's robot id.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for a negative or non-finite effort fraction, or a closing
/// joint without a finite positive effort limit under effort control; [`GraspError::Core`]
/// from the simulator.
pub fn squeeze_engine<E: PhysicsEngine>(
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    options: &TactileSeriesOptions,
) -> Result<(E, RobotId)> {
    let robot = hand.robot();
    let q = &evaluation.q;
    let fk = forward_kinematics(robot, q)?;
    let base = evaluation.hand_pose * (fk.as_slice()[hand.palm().0] * hand.palm_frame()).inverse();
    let mut target = q.clone();
    for (d, &v) in hand.closing_velocity().iter().enumerate() {
        if v != 0.0 {
            target[d] += options.squeeze * v.signum();
        }
    }
    robot.clamp_configuration(&mut target);
    let mut scene = Scene::new("tactile series");
    scene.add_object(object.to_scene_object(Isometry3::identity()))?;
    let rid = scene.add_robot("hand", hand.robot_arc(), base)?;
    scene.set_robot_configuration(rid, q)?;
    let physics =
        PhysicsOptions { gravity: options.gravity, link_friction: object.friction, ..options.physics.clone() };
    let mut engine = E::from_scene(&scene, &physics)?;
    engine.set_joint_position_targets(rid, &target)?;
    if let Some(fraction) = options.effort {
        for (d, target) in closing_efforts(hand, fraction)? {
            engine.set_joint_target(rid, d, target)?;
        }
    }
    Ok((engine, rid))
}

/// Effort targets of the closing dofs: `fraction` of each one's effort limit in its closing
/// direction.
fn closing_efforts(hand: &Hand, fraction: f64) -> Result<Vec<(usize, JointTarget)>> {
    crate::planners::check_non_negative("effort", fraction)?;
    let robot = hand.robot();
    let mut out = Vec::new();
    for (d, &v) in hand.closing_velocity().iter().enumerate() {
        if v == 0.0 {
            continue;
        }
        let joint = robot.joint(robot.dof_joint(d));
        match joint.limits {
            Some(l) if l.effort.is_finite() && l.effort > 0.0 => {
                out.push((d, JointTarget::Effort(fraction * l.effort * v.signum())));
            }
            _ => {
                return Err(GraspError::InvalidParameter {
                    name: "effort",
                    reason: format!("closing joint `{}` has no finite positive effort limit", joint.name),
                })
            }
        }
    }
    Ok(out)
}

/// Squeezes an evaluated grasp in simulation on backend `E` (the hand fixed at its pose, the
/// closing joints commanded `squeeze` beyond the closed configuration, the object free) and
/// records the tactile frame every `every` steps: a tactile time series.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for bad options or an evaluation without a closed hand;
/// [`GraspError::Core`] from the simulator.
pub fn physics_tactile_series<E: PhysicsEngine>(
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    array: &TactileArray,
    options: &TactileSeriesOptions,
) -> Result<Vec<TactileFrame>> {
    if evaluation.status != EvaluationStatus::Closed {
        return Err(GraspError::InvalidParameter { name: "evaluation", reason: "the hand did not close".into() });
    }
    crate::planners::check_positive("duration", options.duration)?;
    crate::error::ensure_finite("gravity", options.gravity.iter().copied())?;
    if !(options.squeeze.is_finite() && options.squeeze >= 0.0) || options.every == 0 {
        return Err(GraspError::InvalidParameter {
            name: "squeeze",
            reason: format!("squeeze {} must be >= 0 and every {} >= 1", options.squeeze, options.every),
        });
    }
    let (mut engine, rid) = squeeze_engine::<E>(hand, object, evaluation, options)?;
    let dt = options.physics.timestep;
    let steps = (options.duration / dt).ceil() as usize;
    let mut reader = PhysicsTactile::new();
    let mut frames = Vec::with_capacity(steps / options.every + 1);
    for k in 1..=steps {
        engine.step(dt)?;
        if k % options.every == 0 || k == steps {
            let mut frame = TactileFrame::default();
            reader.read(array, &engine, rid, &engine.contacts(), &mut frame)?;
            frames.push(frame);
        }
    }
    Ok(frames)
}
