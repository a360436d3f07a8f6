//! The balanced grip after the squeeze: re-solved on the simulator's own contacts and turned
//! into joint springs ([`PhysicsCheckOptions::resolve_grip`], [`PhysicsCheckOptions::grip_compliance`]).

use opengrasp_core::hand::Hand;
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::{ContactBody, PhysicsEngine};
use opengrasp_core::scene::{ObjectId, RobotId};

use super::grip::{command_grip, grip_torques, stiffen_grip, GripTorques};
use super::{GraspContact, GraspEvaluation, PhysicsCheckOptions};
use crate::contact::Contact;
use crate::error::Result;

/// Contacts weaker than this (N) are not counted as touching.
const MIN_FORCE: f64 = 1e-6;

/// The contacts of `hand` (robot `robot` in `engine`) with `object` as the simulator holds them,
/// each with its normal force (N): every point of a contact manifold pressing with more than
/// 1 µN, in the object frame with inward normals and depth = penetration, its finger taken from
/// `evaluation`'s contact on the same link.
///
/// # Errors
/// [`crate::GraspError::Core`] from the engine, [`crate::GraspError::NonFinite`] for a
/// non-finite contact.
pub fn simulated_contacts<E: PhysicsEngine + ?Sized>(
    engine: &E,
    robot: RobotId,
    object: ObjectId,
    evaluation: &GraspEvaluation,
) -> Result<Vec<(GraspContact, f64)>> {
    let to_object = engine.object_pose(object)?.inverse();
    let mut contacts = Vec::new();
    for c in engine.contacts().iter().filter(|c| c.normal_force > MIN_FORCE) {
        // The normal points from body1 to body2: from the link into the object when body1 is
        // the link.
        let (link, inward) = match (c.body1, c.body2) {
            (ContactBody::Link { robot: r, link }, ContactBody::Object(o)) if r == robot && o == object => {
                (link, c.normal)
            }
            (ContactBody::Object(o), ContactBody::Link { robot: r, link }) if r == robot && o == object => {
                (link, -c.normal)
            }
            _ => continue,
        };
        let finger = evaluation.contacts.iter().find(|g| g.link == link.0).and_then(|g| g.finger);
        let contact = Contact::new(to_object * c.point, to_object * inward)?;
        contacts.push((GraspContact { link: link.0, finger, contact, depth: -c.distance }, c.normal_force));
    }
    Ok(contacts)
}

/// `evaluation` as the simulator holds it: the joint positions of `hand` (robot `robot` in
/// `engine`; clamped into their limits) and its contacts with `object`
/// ([`simulated_contacts`], without their forces).
///
/// # Errors
/// As [`simulated_contacts`].
pub fn simulated_evaluation<E: PhysicsEngine + ?Sized>(
    engine: &E,
    hand: &Hand,
    robot: RobotId,
    object: ObjectId,
    evaluation: &GraspEvaluation,
) -> Result<GraspEvaluation> {
    let contacts = simulated_contacts(engine, robot, object, evaluation)?.into_iter().map(|(c, _)| c).collect();
    // The solver lets joints overshoot their limits by micro-radians: clamp into the model's.
    let mut q = engine.joint_positions(robot)?;
    hand.robot().clamp_configuration(&mut q);
    Ok(GraspEvaluation { q, contacts, ..evaluation.clone() })
}

/// What the physics check does at the end of its squeeze, before the release: with
/// `options.resolve_grip`, the balanced grip is solved again on the simulated contacts
/// ([`simulated_evaluation`]) and commanded as stall torques ([`command_grip`]) if it squeezes
/// at all (else `grip` stays); with `options.grip_compliance`, the grip becomes joint springs
/// ([`stiffen_grip`]). Returns the grip in force.
///
/// # Errors
/// As [`simulated_evaluation`], [`grip_torques`] and [`stiffen_grip`].
pub fn after_squeeze<E: PhysicsEngine + ?Sized>(
    engine: &mut E,
    robot: RobotId,
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    grip: &GripTorques,
    options: &PhysicsCheckOptions,
) -> Result<GripTorques> {
    let mut grip = grip.clone();
    if let (true, Some(fraction)) = (options.resolve_grip, options.balanced) {
        let simulated = simulated_evaluation(&*engine, hand, robot, ObjectId(0), evaluation)?;
        let coupled = options.physics.coupled_actuators;
        let again = grip_torques(hand, object, &simulated, fraction, options.grip_margin, coupled)?;
        if again.squeezes() {
            command_grip(engine, robot, hand, &again)?;
            grip = again;
        }
    }
    if let Some(theta) = options.grip_compliance {
        stiffen_grip(engine, robot, hand, &grip, theta)?;
    }
    Ok(grip)
}
