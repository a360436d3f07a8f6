//! Physics simulation behind one trait, in the spirit of the Physics Abstraction Layer (PAL).
//!
//! [`PhysicsEngine`] is built from a [`Scene`] and then driven by joint targets, external
//! forces and [`PhysicsEngine::step`]; it reports object poses, link poses, joint states and
//! contacts. Two backends ship with the crate:
//!
//! - [`RapierBackend`] (feature `rapier`, on by default): rigid-body dynamics with contacts and
//!   friction on `rapier3d-f64`; robots are reduced-coordinate multibodies driven by joint
//!   motors.
//! - [`MockBackend`]: deterministic kinematics without dynamics, for fast tests of code built on
//!   the trait.
//!
//! The same program runs on either backend by switching one type:
//!
//! ```
//! use std::sync::Arc;
//! use opengrasp_core::model::samples::planar_arm;
//! use opengrasp_core::nalgebra::Isometry3;
//! use opengrasp_core::physics::{MockBackend, PhysicsEngine, PhysicsOptions};
//! use opengrasp_core::scene::Scene;
//!
//! fn reach<E: PhysicsEngine>() -> opengrasp_core::Result<Vec<f64>> {
//!     let mut scene = Scene::new("demo");
//!     let arm = scene.add_robot("arm", Arc::new(planar_arm(&[0.5, 0.4])?), Isometry3::identity())?;
//!     let mut engine = E::from_scene(&scene, &PhysicsOptions::default())?;
//!     engine.set_joint_position_targets(arm, &[0.5, -0.5])?;
//!     engine.step_n(120, 1.0 / 120.0)?;
//!     engine.joint_positions(arm)
//! }
//!
//! let q = reach::<MockBackend>()?;
//! assert!((q[0] - 0.5).abs() < 1e-12 && (q[1] + 0.5).abs() < 1e-12);
//! # Ok::<(), opengrasp_core::CoreError>(())
//! ```

mod mock;
#[cfg(feature = "rapier")]
mod rapier;

use nalgebra::{Isometry3, Point3, Vector3};

pub use mock::MockBackend;
#[cfg(feature = "rapier")]
pub use rapier::RapierBackend;

use crate::error::{CoreError, Result};
use crate::model::{JointId, LinkId};
use crate::scene::{BodyId, ObjectId, RobotId, Scene};

/// Settings shared by all physics backends.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicsOptions {
    /// Gravity in the world frame (m/s²). Default `(0, 0, -9.81)`.
    pub gravity: Vector3<f64>,
    /// Largest internal integration step (s): `step(dt)` with a larger `dt` is split into
    /// `ceil(dt / timestep)` equal substeps. Default `1/240` s.
    pub timestep: f64,
    /// Constraint-solver iterations per substep (rapier). Default 8.
    pub solver_iterations: usize,
    /// Joint motor stiffness (s⁻²): commanded joint acceleration per unit of position error,
    /// independent of the link masses. Default `1e4` (natural frequency 100 rad/s).
    pub joint_stiffness: f64,
    /// Joint motor damping (s⁻¹): commanded joint acceleration per unit of velocity error; also
    /// the gain of velocity targets. Default 200 (critical damping for the default stiffness).
    pub joint_damping: f64,
    /// Velocity limit (rad/s or m/s) for joints whose model gives none or a non-positive one
    /// (continuous joints). Default 1.
    pub default_joint_velocity: f64,
    /// Robot links feel no gravity (ideal gravity compensation of the controllers); objects
    /// always do. Default `true`.
    pub gravity_compensation: bool,
    /// Contacts between links of the same robot, except pairs the robot allows
    /// ([`crate::model::Robot::is_collision_allowed`]). Default `false` (as most simulators).
    pub self_collisions: bool,
    /// Density (kg/m³) giving mass to robot links that have collision shapes but no
    /// [`crate::model::Inertial`]. Default 1000.
    pub link_density: f64,
    /// Mass (kg) of a moving robot link with neither inertial nor collision geometry.
    /// Default 0.01.
    pub min_link_mass: f64,
    /// Coulomb friction coefficient of robot links (combined with the other body's by
    /// averaging). Default 0.8.
    pub link_friction: f64,
    /// Natural frequency of the soft contact constraints (Hz): higher is stiffer. A link pushed
    /// by a motor into an object penetrates about `F / (m (2π f)²)` for effective mass `m`, so
    /// light fingers squeezing hard need a high value. Default 120 (rapier's own is 30).
    pub contact_frequency: f64,
    /// Contact penetration tolerated without correction (m); resting contacts settle at about
    /// this depth plus a few tenths of a millimetre. Default `1e-4`.
    pub allowed_penetration: f64,
    /// Coupled joints share one actuator (rapier): the effort limit `τ` of a configuration dof is
    /// split over the joints it drives so that joint `i` with mimic multiplier `m_i` may exert
    /// `τ |m_i| / Σ m_k²`, hence `Σ m_i τ_i = τ` (virtual work). When `false` every mimic joint
    /// has a motor with its own full effort limit, so a chain of `n` coupled joints acts with
    /// about `n` actuators' torque. Joints driven alone are unaffected. Default `false` (the
    /// motion benchmarks' records); the grasp physics check turns it on.
    pub coupled_actuators: bool,
    /// Each chain hanging from a robot's fixed root (a hand's fingers) is its own rapier
    /// multibody instead of all chains forming one. The dynamics are the same (with the root
    /// fixed the chains' mass matrices are decoupled), but rapier's dense multibody algebra
    /// (mass matrix, its LU factors, constraint Jacobians) then scales with a chain's dofs
    /// rather than the robot's: the grasp physics check runs about twice as fast. The
    /// trajectories are not bitwise those of one multibody (floating-point sums group
    /// differently), so marginal grasps may end differently. Default `false` (the motion
    /// benchmarks' and tactile series' records); the grasp physics check turns it on.
    pub independent_chains: bool,
    /// Armature (kg·m²) of every actuated revolute joint: the reflected inertia of its motor and
    /// gearbox (rotor inertia × gear ratio², MuJoCo's `armature`), which dominates a geared
    /// finger joint's inertia. Backends with dynamics add it to the joint child's rotational
    /// inertia about the joint axis (rapier: a massless `I_a a aᵀ` in the link body), so a joint
    /// driven alone by torque `τ` accelerates at `τ / (I_link + I_a)`; in a serial chain the
    /// distal armatures also turn with the proximal joints (a motor mounted in the parent link
    /// would not), an approximation good while `I_a` dominates. Contacts see the larger
    /// effective mass, so the same `contact_frequency` is stiffer. Prismatic joints get none.
    /// Default 0.
    pub joint_armature: f64,
}

impl Default for PhysicsOptions {
    fn default() -> Self {
        Self {
            gravity: Vector3::new(0.0, 0.0, -9.81),
            timestep: 1.0 / 240.0,
            solver_iterations: 8,
            joint_stiffness: 1e4,
            joint_damping: 200.0,
            default_joint_velocity: 1.0,
            gravity_compensation: true,
            self_collisions: false,
            link_density: 1000.0,
            min_link_mass: 0.01,
            link_friction: 0.8,
            contact_frequency: 120.0,
            allowed_penetration: 1e-4,
            coupled_actuators: false,
            independent_chains: false,
            joint_armature: 0.0,
        }
    }
}

impl PhysicsOptions {
    /// Checks every field.
    ///
    /// # Errors
    /// [`CoreError::NonFinite`] for a non-finite gravity, [`CoreError::InvalidParameter`] for a
    /// non-positive timestep, zero solver iterations, or negative/non-finite gains, densities,
    /// tolerances or armature.
    pub fn validate(&self) -> Result<()> {
        crate::error::ensure_finite("gravity", self.gravity.iter().copied())?;
        let positive = |name: &str, v: f64| check_param(name, v, v.is_finite() && v > 0.0, "must be finite and > 0");
        let non_negative =
            |name: &str, v: f64| check_param(name, v, v.is_finite() && v >= 0.0, "must be finite and >= 0");
        positive("timestep", self.timestep)?;
        non_negative("joint_stiffness", self.joint_stiffness)?;
        non_negative("joint_damping", self.joint_damping)?;
        positive("default_joint_velocity", self.default_joint_velocity)?;
        positive("link_density", self.link_density)?;
        positive("min_link_mass", self.min_link_mass)?;
        non_negative("link_friction", self.link_friction)?;
        positive("contact_frequency", self.contact_frequency)?;
        non_negative("allowed_penetration", self.allowed_penetration)?;
        non_negative("joint_armature", self.joint_armature)?;
        if self.solver_iterations == 0 {
            return Err(CoreError::InvalidParameter {
                name: "solver_iterations".into(),
                reason: "must be >= 1".into(),
            });
        }
        Ok(())
    }
}

fn check_param(name: &str, value: f64, ok: bool, reason: &str) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(CoreError::InvalidParameter { name: name.into(), reason: format!("{reason}, got {value}") })
    }
}

/// What a joint motor tracks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointTarget {
    /// Move to this position (rad or m, clamped into the joint limits) at no more than the
    /// joint's velocity limit, then hold it.
    Position(f64),
    /// Move at this velocity (rad/s or m/s, clamped to the velocity limit) until a joint limit.
    Velocity(f64),
    /// Push with this generalized force (N·m or N, its sign the direction), clamped to the
    /// actuator's effort limit: a stall-torque actuator such as a real hand's motor, which
    /// presses with its torque whatever the position. Dynamic backends apply it as an explicit
    /// joint torque (rapier: equal and opposite torques on the joint's two bodies each substep),
    /// tapered to zero between one and two times the joint's velocity limit so an unloaded joint
    /// does not run away. Mimic joints get their share of the actuator: with
    /// [`PhysicsOptions::coupled_actuators`] joint `i` with multiplier `m_i` gets `τ m_i / Σ m_k²`
    /// (so `Σ m_i τ_i = τ`), otherwise `τ sign(m_i)` within its own effort limit. Kinematic
    /// backends move the joint at its velocity limit in the direction of the force.
    Effort(f64),
}

/// A joint spring ([`PhysicsEngine::set_joint_spring`]): the joint presses towards `position`
/// with torque `stiffness |position − q|`, capped at its motor's force limit, whatever its
/// actuator's target. Unlike a position target (per configuration dof) it is per joint, so
/// coupled joints get rest positions of their own, and its stiffness is absolute (N·m/rad)
/// rather than scaled by the links' inertia. Dynamic backends apply it as an explicit joint
/// torque each step (rapier: as [`JointTarget::Effort`], equal and opposite torques on the
/// joint's two bodies tapered off between one and two times the velocity limit, so a stalled
/// joint presses with exactly the spring's torque however many joints its finger has), with
/// the viscous damping `stiffness · h` for the substep `h` that keeps it stable (rapier:
/// implicit, in the multibody's mass matrix).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointSpring {
    /// Rest position (rad or m).
    pub position: f64,
    /// Stiffness (N·m/rad, or N/m for a prismatic joint), ≥ 0.
    pub stiffness: f64,
}

impl JointSpring {
    /// Checks that the position is finite and the stiffness finite and non-negative.
    ///
    /// # Errors
    /// [`CoreError::NonFinite`] for a non-finite position, [`CoreError::InvalidParameter`] for
    /// a negative or non-finite stiffness.
    pub fn validate(&self) -> Result<()> {
        crate::error::ensure_finite("spring position", [self.position])?;
        check_param(
            "stiffness",
            self.stiffness,
            self.stiffness.is_finite() && self.stiffness >= 0.0,
            "must be finite and >= 0",
        )
    }
}

/// Linear and angular velocity of a rigid body in the world frame.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct BodyVelocity {
    /// Velocity of the centre of mass (m/s).
    pub linear: Vector3<f64>,
    /// Angular velocity (rad/s).
    pub angular: Vector3<f64>,
}

/// A body that takes part in a contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ContactBody {
    /// A static body of the scene.
    Static(BodyId),
    /// A movable object.
    Object(ObjectId),
    /// A robot link.
    Link {
        /// The robot.
        robot: RobotId,
        /// The link.
        link: LinkId,
    },
}

/// One contact point found during the last step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicsContact {
    /// First body.
    pub body1: ContactBody,
    /// Second body.
    pub body2: ContactBody,
    /// Contact point in the world frame (midway between the two surfaces).
    pub point: Point3<f64>,
    /// Unit contact normal in the world frame, pointing from `body1` towards `body2`.
    pub normal: Vector3<f64>,
    /// Signed distance between the surfaces along the normal (m); negative when penetrating.
    pub distance: f64,
    /// Normal impulse applied during the last substep (N·s).
    pub normal_impulse: f64,
    /// Magnitude of the friction impulse applied during the last substep (N·s).
    pub friction_impulse: f64,
    /// Average normal force over the last substep (N): `normal_impulse / substep`.
    pub normal_force: f64,
}

/// A physics simulator holding a world built from a [`Scene`].
///
/// Handles ([`RobotId`], [`ObjectId`], [`LinkId`]) are those of the scene the engine was built
/// from. Bad input (unknown handles, non-finite values, non-positive `dt`) is reported as a
/// [`CoreError`], never a panic. Apart from [`PhysicsEngine::from_scene`] the trait is object
/// safe, so a harness can hold a `Box<dyn PhysicsEngine>`.
pub trait PhysicsEngine: Send {
    /// Builds the world from `scene`: static bodies fixed, objects free, robots fixed at their
    /// base pose in their current configuration (which is also the initial position target),
    /// attachments honoured.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for bad options (or, for dynamic backends, an object
    /// whose inertia is not symmetric positive definite), geometry errors for shapes the backend
    /// cannot represent.
    fn from_scene(scene: &Scene, options: &PhysicsOptions) -> Result<Self>
    where
        Self: Sized;

    /// The backend's name.
    fn name(&self) -> &str {
        "physics engine"
    }

    /// Simulated time since construction (s).
    fn time(&self) -> f64;

    /// Advances the simulation by `dt` seconds (split into substeps no longer than
    /// [`PhysicsOptions::timestep`]).
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] if `dt` is not finite and positive;
    /// [`CoreError::SimulationDiverged`] if a body left the plausible range (the rapier backend).
    fn step(&mut self, dt: f64) -> Result<()>;

    /// Calls [`PhysicsEngine::step`] `n` times.
    ///
    /// # Errors
    /// As [`PhysicsEngine::step`].
    fn step_n(&mut self, n: usize, dt: f64) -> Result<()> {
        for _ in 0..n {
            self.step(dt)?;
        }
        Ok(())
    }

    /// A copy of the whole simulation state, or `None` if the backend cannot copy it (the
    /// default). Stepping the copy and stepping `self` with the same inputs give the same
    /// trajectory (bitwise on the rapier and mock backends), so a common prefix of
    /// several simulations (a grasp settling before gravity is switched on in different
    /// directions) can be simulated once and continued from copies.
    fn snapshot(&self) -> Option<Self>
    where
        Self: Sized,
    {
        None
    }

    /// Current gravity (m/s², world frame).
    fn gravity(&self) -> Vector3<f64>;

    /// Sets gravity (m/s², world frame).
    ///
    /// # Errors
    /// [`CoreError::NonFinite`].
    fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<()>;

    /// Sets the motor target of configuration index `dof` of `robot`.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for an unknown robot or dof index, [`CoreError::NonFinite`]
    /// for a non-finite target.
    fn set_joint_target(&mut self, robot: RobotId, dof: usize, target: JointTarget) -> Result<()>;

    /// Caps the force (N·m, or N for a prismatic joint) of joint `joint`'s motor at `limit`,
    /// replacing its share of the actuator's effort limit: a position target beyond contact then
    /// presses with exactly `limit` while the joint is stalled (an implicit, stable stall
    /// torque). Coupled joints keep their own caps. Kinematic backends check and ignore it.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for an unknown robot or a joint without a motor (fixed or
    /// unknown), [`CoreError::InvalidParameter`] for a negative or non-finite limit.
    fn set_joint_force_limit(&mut self, robot: RobotId, joint: JointId, limit: f64) -> Result<()>;

    /// Replaces joint `joint`'s motor by `spring` (see [`JointSpring`]; its force stays capped
    /// by the motor's limit, [`PhysicsEngine::set_joint_force_limit`]); `None` returns the joint
    /// to its actuator's target. Kinematic backends check and ignore it.
    ///
    /// # Errors
    /// As [`PhysicsEngine::set_joint_force_limit`] for the robot and joint; the spring's
    /// [`JointSpring::validate`] errors.
    fn set_joint_spring(&mut self, robot: RobotId, joint: JointId, spring: Option<JointSpring>) -> Result<()>;

    /// Sets position targets for every dof of `robot` (one value per configuration index).
    /// Nothing changes if any value is invalid.
    ///
    /// # Errors
    /// As [`PhysicsEngine::set_joint_target`], plus [`CoreError::DimensionMismatch`].
    fn set_joint_position_targets(&mut self, robot: RobotId, q: &[f64]) -> Result<()> {
        set_all(self, robot, q, JointTarget::Position)
    }

    /// Sets velocity targets for every dof of `robot`. Nothing changes if any value is invalid.
    ///
    /// # Errors
    /// As [`PhysicsEngine::set_joint_position_targets`].
    fn set_joint_velocity_targets(&mut self, robot: RobotId, qd: &[f64]) -> Result<()> {
        set_all(self, robot, qd, JointTarget::Velocity)
    }

    /// Number of dofs of `robot`.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    fn dof(&self, robot: RobotId) -> Result<usize> {
        self.joint_positions(robot).map(|q| q.len())
    }

    /// Joint positions of `robot`, one per configuration index (rad or m).
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    fn joint_positions(&self, robot: RobotId) -> Result<Vec<f64>>;

    /// Joint velocities of `robot`, one per configuration index (rad/s or m/s).
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    fn joint_velocities(&self, robot: RobotId) -> Result<Vec<f64>>;

    /// World pose of a robot link.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for an unknown robot or link.
    fn link_pose(&self, robot: RobotId, link: LinkId) -> Result<Isometry3<f64>>;

    /// World pose of an object's frame.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    fn object_pose(&self, object: ObjectId) -> Result<Isometry3<f64>>;

    /// World velocity of an object.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`].
    fn object_velocity(&self, object: ObjectId) -> Result<BodyVelocity>;

    /// Teleports an object (detaching it if attached) and sets its velocity to zero.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or [`CoreError::NonFinite`].
    fn set_object_pose(&mut self, object: ObjectId, pose: Isometry3<f64>) -> Result<()>;

    /// Clamps an object in place (`fixed = true`: it keeps its pose and zero velocity, and
    /// contacts push against it as against a static body) or frees it again (`false`: it
    /// moves with its mass and inertia, from rest). A fixture that holds an object while a
    /// hand closes on it, so the first finger to touch does not push it away.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for an unknown object, [`CoreError::Physics`] if the
    /// backend cannot clamp objects (the default).
    fn set_object_fixed(&mut self, object: ObjectId, fixed: bool) -> Result<()> {
        let _ = (object, fixed);
        Err(CoreError::Physics { reason: format!("{} cannot clamp objects", self.name()) })
    }

    /// Sets the viscous damping of a free object, as rates (s⁻¹): without other forces its
    /// linear and angular velocities decay as `exp(−rate t)`, i.e. it feels the force
    /// `−m · linear · v` and the torque `−I · angular · ω` of a viscous medium (time constant
    /// `τ = 1 / rate`; viscous coefficient `c = m / τ`). Zeros (the initial state) remove it.
    /// A hand closing on a heavily damped object moves it quasi-statically to where the
    /// fingers' forces balance, as a table's friction lets it slide.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for an unknown object, [`CoreError::InvalidParameter`] for a
    /// negative or non-finite rate, [`CoreError::Physics`] if the backend cannot damp objects
    /// (the default).
    fn set_object_damping(&mut self, object: ObjectId, linear: f64, angular: f64) -> Result<()> {
        check_damping(linear, angular)?;
        let _ = object;
        Err(CoreError::Physics { reason: format!("{} cannot damp objects", self.name()) })
    }

    /// Sets the natural frequency (Hz) of the soft contact constraints from now on
    /// ([`PhysicsOptions::contact_frequency`] at construction), e.g. stiffer contacts for a
    /// short window of a simulation.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for a frequency that is not finite and positive,
    /// [`CoreError::Physics`] if the backend has no soft contacts to tune (the default).
    fn set_contact_frequency(&mut self, hz: f64) -> Result<()> {
        check_param("contact_frequency", hz, hz.is_finite() && hz > 0.0, "must be finite and > 0")?;
        Err(CoreError::Physics { reason: format!("{} has no soft contacts to tune", self.name()) })
    }

    /// Applies an instantaneous impulse (N·s) at a world point of an object.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or [`CoreError::NonFinite`].
    fn apply_object_impulse(&mut self, object: ObjectId, impulse: Vector3<f64>, point: Point3<f64>) -> Result<()>;

    /// Sets a constant external force (N, at the centre of mass) and torque (N·m) on an object,
    /// applied during every following step until replaced; zeros remove it.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] or [`CoreError::NonFinite`].
    fn set_object_force(&mut self, object: ObjectId, force: Vector3<f64>, torque: Vector3<f64>) -> Result<()>;

    /// Contact points of the last step (empty for backends without contacts).
    fn contacts(&self) -> Vec<PhysicsContact> {
        Vec::new()
    }

    /// Rigidly attaches an object to a robot link at their current relative pose.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`], [`CoreError::InvalidParameter`] if already attached, or
    /// [`CoreError::Physics`] if the backend does not support attachments (the default).
    fn attach(&mut self, object: ObjectId, robot: RobotId, link: LinkId) -> Result<()> {
        let _ = (object, robot, link);
        Err(CoreError::Physics { reason: format!("{} does not support attachments", self.name()) })
    }

    /// Releases an attached object.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] if the object is unknown or not attached, or
    /// [`CoreError::Physics`] if the backend does not support attachments (the default).
    fn detach(&mut self, object: ObjectId) -> Result<()> {
        let _ = object;
        Err(CoreError::Physics { reason: format!("{} does not support attachments", self.name()) })
    }
}

fn set_all<E: PhysicsEngine + ?Sized>(
    engine: &mut E,
    robot: RobotId,
    values: &[f64],
    make: fn(f64) -> JointTarget,
) -> Result<()> {
    let dof = engine.dof(robot)?;
    if values.len() != dof {
        return Err(CoreError::DimensionMismatch { expected: dof, actual: values.len() });
    }
    crate::error::ensure_finite("joint targets", values.iter().copied())?;
    for (i, &v) in values.iter().enumerate() {
        engine.set_joint_target(robot, i, make(v))?;
    }
    Ok(())
}

/// Number of substeps and their length for `step(dt)`.
pub(crate) fn substeps(dt: f64, timestep: f64) -> Result<(usize, f64)> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(CoreError::InvalidParameter {
            name: "dt".into(),
            reason: format!("must be finite and > 0, got {dt}"),
        });
    }
    let n = (dt / timestep - 1e-9).ceil().max(1.0);
    if n > 1e7 {
        return Err(CoreError::InvalidParameter {
            name: "dt".into(),
            reason: format!("{dt} s needs more than 1e7 substeps of {timestep} s"),
        });
    }
    Ok((n as usize, dt / n))
}

pub(crate) fn check_vec(what: &str, v: &Vector3<f64>) -> Result<()> {
    crate::error::ensure_finite(what, v.iter().copied())
}

/// Velocity limit of configuration index `dof`, falling back to the option's default.
pub(crate) fn velocity_limit(robot: &crate::model::Robot, dof: usize, options: &PhysicsOptions) -> f64 {
    match robot.joint(robot.dof_joint(dof)).limits {
        Some(l) if l.velocity.is_finite() && l.velocity > 0.0 => l.velocity,
        _ => options.default_joint_velocity,
    }
}

/// Advances a velocity-limited reference towards `target` over `dt`; returns the new reference.
pub(crate) fn advance_reference(reference: f64, target: JointTarget, vmax: f64, limits: (f64, f64), dt: f64) -> f64 {
    let next = match target {
        JointTarget::Position(t) => {
            let t = t.clamp(limits.0, limits.1);
            let max_step = vmax * dt;
            if (t - reference).abs() <= max_step {
                t
            } else {
                reference + (t - reference).signum() * max_step
            }
        }
        JointTarget::Velocity(v) => reference + v.clamp(-vmax, vmax) * dt,
        JointTarget::Effort(0.0) => reference,
        JointTarget::Effort(f) => reference + f.signum() * vmax * dt,
    };
    next.clamp(limits.0, limits.1)
}

/// Checks object damping rates (finite, >= 0).
pub(crate) fn check_damping(linear: f64, angular: f64) -> Result<()> {
    let ok = |v: f64| v.is_finite() && v >= 0.0;
    check_param("linear damping", linear, ok(linear), "must be finite and >= 0")?;
    check_param("angular damping", angular, ok(angular), "must be finite and >= 0")
}

/// Checks a motor force limit (finite, >= 0).
pub(crate) fn check_force_limit(limit: f64) -> Result<()> {
    check_param("limit", limit, limit.is_finite() && limit >= 0.0, "must be finite and >= 0")
}

pub(crate) fn check_target(target: JointTarget) -> Result<()> {
    let v = match target {
        JointTarget::Position(v) | JointTarget::Velocity(v) | JointTarget::Effort(v) => v,
    };
    crate::error::ensure_finite("joint target", [v])
}
