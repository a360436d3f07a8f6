//! Handing the object to the grip gradually: a fixture release
//! ([`PhysicsCheckOptions::release`]: the wrench the fixture put on the clamped object is
//! applied to the freed object and ramped to zero, so the squeezing fingers take the load over
//! quasi-statically instead of as a step), and the end of a damped closing
//! ([`PhysicsCheckOptions::closing_damping`]: the object's viscous damping ramped to zero).

use nalgebra::{Matrix3, Vector3};
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::PhysicsEngine;
use opengrasp_core::scene::ObjectId;

use crate::error::Result;

/// Fixed-point iterations of the fixture wrench estimate: each probes one substep with the
/// current estimate applied and adds what is left over.
const PROBES: usize = 3;

/// The wrench (force at the centre of mass, torque about it; world frame, N and N·m) the
/// fixture exerts on the clamped object `oid` of `engine`: minus the net wrench of everything
/// else (the contacts). Measured on copies of the engine: the object is freed for one substep
/// of `dt` with the estimate applied, and the velocity it gains from rest, times its mass
/// (inertia), is what the estimate missed. `None` if the backend cannot copy its state.
///
/// # Errors
/// [`crate::GraspError::Core`] from the engine.
pub fn fixture_wrench<E: PhysicsEngine>(
    engine: &E,
    oid: ObjectId,
    object: &ObjectModel,
    dt: f64,
) -> Result<Option<(Vector3<f64>, Vector3<f64>)>> {
    let rotation = engine.object_pose(oid)?.rotation.to_rotation_matrix();
    let inertia: Matrix3<f64> = rotation.matrix() * object.inertial.inertia * rotation.matrix().transpose();
    let (mut force, mut torque) = (Vector3::zeros(), Vector3::zeros());
    for _ in 0..PROBES {
        let Some(mut probe) = engine.snapshot() else { return Ok(None) };
        probe.set_object_fixed(oid, false)?;
        probe.set_object_force(oid, force, torque)?;
        probe.step(dt)?;
        let v = probe.object_velocity(oid)?;
        force -= v.linear * (object.inertial.mass / dt);
        torque -= inertia * v.angular / dt;
    }
    Ok(Some((force, torque)))
}

/// Frees the clamped object `oid` and ramps the fixture's wrench ([`fixture_wrench`]) from its
/// full value to zero linearly over `duration` (steps of `dt`); then no external wrench is
/// left. A `duration` of zero frees it at once, as does a backend without snapshots.
///
/// # Errors
/// [`crate::GraspError::Core`] from the engine.
pub fn release_gradually<E: PhysicsEngine>(
    engine: &mut E,
    oid: ObjectId,
    object: &ObjectModel,
    duration: f64,
    dt: f64,
) -> Result<()> {
    let steps = (duration / dt).ceil() as usize;
    let wrench = if steps > 0 { fixture_wrench(engine, oid, object, dt)? } else { None };
    engine.set_object_fixed(oid, false)?;
    let Some((force, torque)) = wrench else { return Ok(()) };
    for k in 0..steps {
        let s = 1.0 - (k as f64 + 0.5) / steps as f64;
        engine.set_object_force(oid, force * s, torque * s)?;
        engine.step(dt)?;
    }
    engine.set_object_force(oid, Vector3::zeros(), Vector3::zeros())?;
    Ok(())
}

/// Ramps the viscous damping of the free object `oid` ([`PhysicsEngine::set_object_damping`],
/// linear and angular `rate`, s⁻¹) linearly down to zero over `duration` (steps of `dt`), so
/// the object the damping kept quasi-static is handed to the grip's own forces gradually; then
/// no damping is left. A `duration` of zero removes it at once.
///
/// # Errors
/// [`crate::GraspError::Core`] from the engine.
pub fn undamp_gradually<E: PhysicsEngine>(
    engine: &mut E,
    oid: ObjectId,
    rate: f64,
    duration: f64,
    dt: f64,
) -> Result<()> {
    let steps = (duration / dt).ceil() as usize;
    for k in 0..steps {
        let r = rate * (1.0 - (k as f64 + 0.5) / steps as f64);
        engine.set_object_damping(oid, r, r)?;
        engine.step(dt)?;
    }
    engine.set_object_damping(oid, 0.0, 0.0)?;
    Ok(())
}

/// A window of fine simulation around the release ([`super::PhysicsCheckOptions::release_window`]):
/// the last `before` seconds of the clamped squeeze, the fixture's release and `after` seconds
/// of the gravity-free grip that follows run in steps of `timestep` with the contacts at
/// `contact_frequency` (Hz); then the check's own step and contacts come back for the control
/// run and the gravity runs, which all continue from the end of the window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReleaseWindow {
    /// Step (s) inside the window.
    pub timestep: f64,
    /// Natural frequency (Hz) of the soft contacts inside the window.
    pub contact_frequency: f64,
    /// Time (s) of the squeeze before the release simulated in the window (at most the
    /// check's `settle`).
    pub before: f64,
    /// Gravity-free time (s) after the release simulated in the window.
    pub after: f64,
}

impl ReleaseWindow {
    /// Checks the window's values.
    ///
    /// # Errors
    /// [`crate::GraspError::InvalidParameter`] for a step or contact frequency that is not finite
    /// and positive, or a `before` or `after` that is not finite and non-negative.
    pub fn validate(&self) -> Result<()> {
        crate::planners::check_positive("release_window.timestep", self.timestep)?;
        crate::planners::check_positive("release_window.contact_frequency", self.contact_frequency)?;
        crate::planners::check_non_negative("release_window.before", self.before)?;
        crate::planners::check_non_negative("release_window.after", self.after)
    }
}
