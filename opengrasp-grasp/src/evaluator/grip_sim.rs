//! The balanced grip after the squeeze: re-solved on the simulator's own contacts and turned
//! into joint springs ([`PhysicsCheckOptions::resolve_grip`], [`PhysicsCheckOptions::grip_compliance`]).

use nalgebra::{Point3, Unit, Vector3};
use opengrasp_core::hand::Hand;
use opengrasp_core::model::{JointKind, LinkId};
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
/// `engine`; clamped into their limits) and its contacts with `object`, one per touching link
/// as the evaluator's own: the normal-force-weighted centre and mean inward normal of the link's
/// manifold points ([`simulated_contacts`]), at their deepest penetration (a link whose
/// normals cancel is left out). (The balanced grip asks every finger contact to press; a link's
/// separate manifold points, some on the rim of the patch, rarely can all be pressed at once,
/// so on the unmerged contacts it finds no grip.)
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
    let contacts = merged_per_link(&simulated_contacts(engine, robot, object, evaluation)?);
    // The solver lets joints overshoot their limits by micro-radians: clamp into the model's.
    let mut q = engine.joint_positions(robot)?;
    hand.robot().clamp_configuration(&mut q);
    Ok(GraspEvaluation { q, contacts, ..evaluation.clone() })
}

/// The simulated evaluation ([`simulated_evaluation`]) the balanced grip is re-solved on. With
/// `fixture` (the object clamped at its evaluated pose while the fingers squeeze) it also keeps
/// the evaluator's contacts on links no joint moves, where the simulator has none on that link:
/// rapier makes no contacts between two fixed bodies, so the palm's would be missing although
/// it touches the clamped object exactly where the evaluator found it.
fn regrip_evaluation<E: PhysicsEngine + ?Sized>(
    engine: &E,
    hand: &Hand,
    robot: RobotId,
    evaluation: &GraspEvaluation,
    fixture: bool,
) -> Result<GraspEvaluation> {
    let mut simulated = simulated_evaluation(engine, hand, robot, ObjectId(0), evaluation)?;
    if fixture {
        let model = hand.robot();
        let rigid = |link: usize| model.chain_to(LinkId(link)).iter().all(|&j| model.joint(j).kind == JointKind::Fixed);
        let palm: Vec<GraspContact> = evaluation
            .contacts
            .iter()
            .filter(|c| rigid(c.link) && !simulated.contacts.iter().any(|s| s.link == c.link))
            .copied()
            .collect();
        simulated.contacts.extend(palm);
    }
    Ok(simulated)
}

/// One contact per link of `contacts` (in the order the links first appear): the
/// normal-force-weighted centre and mean normal of the link's points, the deepest penetration.
fn merged_per_link(contacts: &[(GraspContact, f64)]) -> Vec<GraspContact> {
    // Per link: the first contact, Σ f p, Σ f n, Σ f.
    let mut links: Vec<(GraspContact, Vector3<f64>, Vector3<f64>, f64)> = Vec::new();
    for &(c, force) in contacts {
        let (p, n) = (c.contact.point.coords * force, c.contact.normal.into_inner() * force);
        match links.iter_mut().find(|l| l.0.link == c.link) {
            Some(l) => {
                l.0.depth = l.0.depth.max(c.depth);
                l.1 += p;
                l.2 += n;
                l.3 += force;
            }
            None => links.push((c, p, n, force)),
        }
    }
    // A link pressed equally from opposite sides (its normals cancel) pushes the object nowhere.
    let merged = links.into_iter().filter_map(|(c, p, n, force)| {
        let normal = Unit::try_new(n, 1e-9 * force)?;
        Some(GraspContact { contact: Contact::from_unit(Point3::from(p / force), normal), ..c })
    });
    merged.collect()
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
    if options.resolve_grip {
        resolve_on_simulated(engine, robot, hand, object, evaluation, options, &mut grip)?;
    }
    if let Some(theta) = options.grip_compliance {
        stiffen_grip(engine, robot, hand, &grip, theta)?;
    }
    Ok(grip)
}

/// The squeeze of the physics check under a grip controller
/// ([`PhysicsCheckOptions::regrip`]): `settle_steps` steps of `options.physics.timestep`, and
/// after every `interval` seconds of them (the last chunk shorter) the balanced grip solved
/// again on the simulated contacts and commanded as stall torques where it squeezes at all.
/// Returns the grip in force at the end.
///
/// # Errors
/// As [`simulated_evaluation`] and [`grip_torques`]; [`crate::GraspError::Core`] from the engine.
#[allow(clippy::too_many_arguments)]
pub fn regrip_while_settling<E: PhysicsEngine + ?Sized>(
    engine: &mut E,
    robot: RobotId,
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    grip: &GripTorques,
    options: &PhysicsCheckOptions,
    interval: f64,
    settle_steps: usize,
) -> Result<GripTorques> {
    let dt = options.physics.timestep;
    let chunk = ((interval / dt).round() as usize).max(1);
    let mut grip = grip.clone();
    let mut done = 0;
    while done < settle_steps {
        let n = chunk.min(settle_steps - done);
        engine.step_n(n, dt)?;
        done += n;
        resolve_on_simulated(engine, robot, hand, object, evaluation, options, &mut grip)?;
    }
    Ok(grip)
}

/// With `options.balanced`: the balanced grip solved again on the simulated contacts
/// ([`regrip_evaluation`]) and, if it squeezes at all, commanded as stall torques
/// ([`command_grip`]) and stored in `grip` (else `grip` stays).
fn resolve_on_simulated<E: PhysicsEngine + ?Sized>(
    engine: &mut E,
    robot: RobotId,
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    options: &PhysicsCheckOptions,
    grip: &mut GripTorques,
) -> Result<()> {
    if let Some(fraction) = options.balanced {
        let simulated = regrip_evaluation(&*engine, hand, robot, evaluation, options.fixture)?;
        let coupled = options.physics.coupled_actuators;
        let again = grip_torques(hand, object, &simulated, fraction, options.grip_margin, coupled)?;
        if again.squeezes() {
            command_grip(engine, robot, hand, &again)?;
            *grip = again;
        }
    }
    Ok(())
}
