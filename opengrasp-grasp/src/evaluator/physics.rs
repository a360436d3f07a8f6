//! The physics hold check: does the closed hand keep the object under gravity?

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::hand::Hand;
use opengrasp_core::physics::{PhysicsEngine, RapierBackend};
use opengrasp_core::scene::{ObjectId, RobotId};
use serde::{Deserialize, Serialize};

use crate::error::{GraspError, Result};
use crate::tactile::sources::{squeeze_engine, TactileSeriesOptions};
use opengrasp_core::object::ObjectModel;

use super::stepping::{self, DropBound, EarlyStop};
use super::{EvaluationStatus, GraspEvaluation, PhysicsCheckOptions};

/// What gravity did to the grasped object in one direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub enum HoldResult {
    /// Moved less than `max_translation` and turned less than `max_rotation`.
    Held,
    /// Moved or turned more, but stayed within `drop_translation` (the grasp shifted).
    Slipped,
    /// Moved farther than `drop_translation`: the object left the hand.
    Dropped,
}

/// Result of a physics check: how far the object moved under each gravity direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicsOutcome {
    /// Object displacement (m) per gravity direction, relative to the gravity-free control run
    /// (for a run stopped early, [`PhysicsCheckOptions::early_drop`], at the stop).
    pub translations: Vec<f64>,
    /// Object rotation (rad) per gravity direction, relative to the control run (at the stop
    /// likewise).
    pub rotations: Vec<f64>,
    /// Whether the object stayed in the hand, per gravity direction.
    pub held_per_direction: Vec<bool>,
    /// Held, slipped or dropped, per gravity direction.
    #[serde(default)]
    pub results: Vec<HoldResult>,
    /// How far (m) the squeeze alone moved the object from its evaluated pose in the
    /// gravity-free control run: a few centimetres of creep are a solver artefact (see
    /// [`PhysicsCheckOptions::physics`]); more than `drop_translation` means the simulated grip
    /// pushes the object out by itself.
    #[serde(default)]
    pub grip_translation: f64,
    /// How far (rad) the squeeze alone turned the object in the control run.
    #[serde(default)]
    pub grip_rotation: f64,
    /// The grip's own imbalance at the release, in object weights: the least net wrench the
    /// simulated contacts' traced normal forces put on the object with the best friction inside
    /// the cones and free palm contacts ([`super::release_imbalance`]). Diagnostic: the object
    /// is pushed with at least this force the moment the fixture lets go.
    #[serde(default)]
    pub release_push: f64,
    /// The squeeze alone (the gravity-free control run) moved the object farther than
    /// `max_translation` or turned it more than `max_rotation`: the simulated grip does not
    /// keep the evaluated grasp even without gravity, so a failure to hold is the hand's
    /// actuation (its traced forces at the release push by [`Self::release_push`] weights),
    /// not the grasp's resistance to gravity.
    #[serde(default)]
    pub grip_escapes: bool,
}

impl PhysicsOutcome {
    /// True if the object stayed in the hand for every gravity direction.
    pub fn held(&self) -> bool {
        !self.held_per_direction.is_empty() && self.held_per_direction.iter().all(|&h| h)
    }

    /// The worst result over the gravity directions (`None` without directions).
    pub fn result(&self) -> Option<HoldResult> {
        self.results.iter().copied().max()
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
/// (non-zero closing velocity; spread and other joints hold their value) push with `effort`
/// times their actuators' effort limits (or, without `effort`, are commanded `squeeze` beyond
/// the closed configuration). The fingers squeeze for `settle` seconds without gravity, then gravity is
/// switched on for `duration`. The object (free, with its mass, inertia and friction, which
/// also replaces the links' friction) is held for a direction if its final pose differs from
/// the final pose of a gravity-free control run of the same length by at most
/// `max_translation` and `max_rotation`: the difference is what gravity did, while slow
/// squeeze-induced creep of the simulator, present in both runs, cancels out. A direction that
/// is not held is [`HoldResult::Dropped`] beyond `drop_translation`, else
/// [`HoldResult::Slipped`]; the control run's own motion is reported as the grip displacement.
/// The runs after the release split their steps while the object moves
/// ([`PhysicsCheckOptions::adaptive_step`]), and a gravity run ends once its object is
/// certainly dropped ([`PhysicsCheckOptions::early_drop`]).
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
    options.validate()?;
    let options = &options.for_hand(hand);
    let dt = options.physics.timestep;
    let steps = (options.duration / dt).ceil() as usize;
    let mut gravities = Vec::with_capacity(options.directions.len());
    for dir in &options.directions {
        let n = dir.norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(GraspError::InvalidParameter { name: "directions", reason: format!("bad direction {dir:?}") });
        }
        gravities.push(dir * (options.gravity / n));
    }
    // Settled once: each run continues from a snapshot of it (bitwise what settling afresh
    // gives), or from a fresh settle on a backend without snapshots.
    let start = settle_grip::<E>(hand, object, evaluation, options)?;
    let imbalance = start.release_imbalance;
    let oid = ObjectId(0);
    let adaptive = options.adaptive_step.as_ref();
    let run = |gravity: Vector3<f64>, bound: Option<&DropBound>| -> Result<Isometry3<f64>> {
        let mut engine = match start.engine.snapshot() {
            Some(engine) => engine,
            None => settle_grip::<E>(hand, object, evaluation, options)?.engine,
        };
        engine.set_gravity(gravity)?;
        let stop = bound.map(|bound| EarlyStop { bound, gravity });
        stepping::run(&mut engine, oid, steps, dt, adaptive, stop.as_ref())?;
        Ok(engine.object_pose(oid)?)
    };
    let control = run(Vector3::zeros(), None)?;
    let bound = if options.early_drop {
        DropBound::new(
            &start.engine,
            start.robot,
            hand,
            object,
            &control,
            options.drop_translation,
            options.max_translation,
        )?
    } else {
        None
    };
    let mut out = PhysicsOutcome {
        translations: Vec::new(),
        rotations: Vec::new(),
        held_per_direction: Vec::new(),
        results: Vec::new(),
        grip_translation: control.translation.vector.norm(),
        grip_rotation: control.rotation.angle(),
        release_push: imbalance / (object.inertial.mass * options.gravity),
        grip_escapes: control.translation.vector.norm() > options.max_translation
            || control.rotation.angle() > options.max_rotation,
    };
    for &g in &gravities {
        let pose = run(g, bound.as_ref())?;
        let translation = (pose.translation.vector - control.translation.vector).norm();
        let rotation = pose.rotation.angle_to(&control.rotation);
        let held = translation <= options.max_translation && rotation <= options.max_rotation;
        out.translations.push(translation);
        out.rotations.push(rotation);
        out.held_per_direction.push(held);
        out.results.push(if held {
            HoldResult::Held
        } else if translation > options.drop_translation {
            HoldResult::Dropped
        } else {
            HoldResult::Slipped
        });
    }
    Ok(out)
}

/// The state every run of the physics check starts from ([`settle_grip`]).
pub struct SettledGrip<E> {
    /// The simulation at the end of the release: gravity off, the object free.
    pub engine: E,
    /// The hand's robot in `engine` (the object is `ObjectId(0)`).
    pub robot: RobotId,
    /// The least net wrench (N) the traced contact forces put on the object at the end of the
    /// clamped squeeze ([`super::release_imbalance`]).
    pub release_imbalance: f64,
}

/// The physics check's settle on backend `E`, as [`physics_check_with`] runs it for `options`
/// (with the hand's actuator model, [`PhysicsCheckOptions::for_hand`]): the fingers squeeze for
/// `settle` seconds without gravity (the object clamped with `fixture`), then the object is
/// released. Every gravity run and the control run of the check continue from this state.
///
/// # Errors
/// As [`physics_check_with`].
pub fn settle_grip<E: PhysicsEngine>(
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    options: &PhysicsCheckOptions,
) -> Result<SettledGrip<E>> {
    if evaluation.status != EvaluationStatus::Closed {
        return Err(GraspError::InvalidParameter { name: "evaluation", reason: "the hand did not close".into() });
    }
    options.validate()?;
    let options = &options.for_hand(hand);
    // The hand fixed at its pose, the closing joints commanded `squeeze` past the closed
    // configuration, the object (the scene's only one) free, its friction on the links.
    // Balanced grip: torques per joint, pressed through position targets `squeeze` past the
    // closed configuration with the motor forces capped at the torques.
    let grip = match options.balanced {
        Some(f) => Some(super::grip::grip_torques(
            hand,
            object,
            evaluation,
            f,
            options.grip_margin,
            options.physics.coupled_actuators,
        )?),
        None => None,
    }
    // No balanced grip at all (every torque zero): the grasp is checked as without `balanced`.
    .filter(super::grip::GripTorques::squeezes);
    let squeeze = TactileSeriesOptions {
        squeeze: options.squeeze,
        effort: if grip.is_some() { None } else { options.effort },
        gravity: Vector3::zeros(),
        physics: options.physics.clone(),
        ..TactileSeriesOptions::default()
    };
    let oid = ObjectId(0);
    let dt = options.physics.timestep;
    // With a release window, its `before` of the settle is simulated in it, at its own step.
    let window = options.release_window;
    let coarse_settle = options.settle - window.map_or(0.0, |w| w.before);
    let settle_steps = (coarse_settle / dt).ceil() as usize;
    // The squeezing fingers settle without gravity (the object clamped with `fixture`), the
    // object is released: the state every run starts from.
    let (mut engine, rid) = squeeze_engine::<E>(hand, object, evaluation, &squeeze)?;
    if let Some(grip) = &grip {
        super::grip::command_grip(&mut engine, rid, hand, grip)?;
    }
    if let Some(theta) = options.spring {
        let closing = super::grip::closing_grip(hand, 1.0, options.physics.coupled_actuators)?;
        super::grip::stiffen_grip(&mut engine, rid, hand, &closing, theta)?;
    }
    if options.fixture {
        engine.set_object_fixed(oid, true)?;
    }
    if let Some(tau) = options.closing_damping {
        engine.set_object_damping(oid, 1.0 / tau, 1.0 / tau)?;
    }
    let grip = match (options.regrip, &grip) {
        (Some(interval), Some(grip)) => Some(super::grip_sim::regrip_while_settling(
            &mut engine,
            rid,
            hand,
            object,
            evaluation,
            grip,
            options,
            interval,
            settle_steps,
        )?),
        _ => {
            engine.step_n(settle_steps, dt)?;
            grip.clone()
        }
    };
    // Inside the window: its step and contacts until its end.
    let dt = match window {
        Some(w) => {
            engine.set_contact_frequency(w.contact_frequency)?;
            engine.step_n((w.before / w.timestep).ceil() as usize, w.timestep)?;
            w.timestep
        }
        None => dt,
    };
    let imbalance = super::release_imbalance(&engine, hand, rid, oid, object, evaluation)?;
    if let Some(grip) = &grip {
        super::grip_sim::after_squeeze(&mut engine, rid, hand, object, evaluation, grip, options)?;
    }
    if options.fixture {
        super::release::release_gradually(&mut engine, oid, object, options.release, dt)?;
    }
    if let Some(tau) = options.closing_damping {
        super::release::undamp_gradually(&mut engine, oid, 1.0 / tau, options.damping_ramp, dt)?;
    }
    if let Some(w) = window {
        engine.step_n((w.after / w.timestep).ceil() as usize, w.timestep)?;
        engine.set_contact_frequency(options.physics.contact_frequency)?;
    }
    Ok(SettledGrip { engine, robot: rid, release_imbalance: imbalance })
}
