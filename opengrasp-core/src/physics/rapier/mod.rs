//! The rapier3d (f64) backend.

mod colliders;
mod robots;

use std::collections::HashMap;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector2, Vector3};
use rapier3d_f64::parry::mass_properties::MassProperties;
use rapier3d_f64::prelude::{
    BroadPhaseBvh, CCDSolver, ColliderHandle, ColliderSet, ImpulseJointHandle, ImpulseJointSet, IntegrationParameters,
    IslandManager, JointAxis, MultibodyJointHandle, MultibodyJointSet, NarrowPhase, PhysicsPipeline, RigidBodyBuilder,
    RigidBodyHandle, RigidBodySet, RigidBodyType,
};

use super::{
    advance_reference, check_target, check_vec, substeps, velocity_limit, BodyVelocity, ContactBody, JointTarget,
    PhysicsContact, PhysicsEngine, PhysicsOptions,
};
use crate::error::{CoreError, Result};
use crate::model::{LinkId, Robot};
use crate::scene::{BodyId, ObjectId, RobotId, Scene};

use colliders::{decode, ContactFilter};

/// A dynamic body farther than this from the origin (m) means the simulation diverged.
pub const DIVERGED_DISTANCE: f64 = 1.0e6;
/// A dynamic body faster than this (m/s) means the simulation diverged.
pub const DIVERGED_SPEED: f64 = 1.0e6;

/// Rigid-body dynamics with contacts and friction on `rapier3d-f64`.
///
/// Modelling choices:
/// - Static bodies are fixed rigid bodies; objects are dynamic bodies with the mass, centre of
///   mass and inertia of their [`crate::scene::SceneObject`] (their colliders add no mass).
/// - Each robot is one reduced-coordinate *multibody* rooted at a fixed body at its base pose, so
///   joints never drift apart. Links joined by fixed joints are merged into one rigid body.
///   Links without [`crate::model::Inertial`] get their mass from their collision shapes at
///   [`PhysicsOptions::link_density`]. Robot links feel no gravity by default
///   ([`PhysicsOptions::gravity_compensation`]).
/// - Each actuated joint has a motor (stiffness/damping from [`PhysicsOptions`], force limit from
///   the joint's effort limit) tracking a reference that moves towards the position target at the
///   joint's velocity limit, with the reference velocity as feed-forward; joint limits are
///   enforced. Under a [`JointTarget::Effort`] target the motor is switched off and the torque
///   is applied explicitly each substep (equal and opposite torques on the joint's two bodies,
///   or forces for a prismatic joint): a stall-torque actuator, whatever the position. Mimic joints track `multiplier * leader reference + offset` with their own motor.
///   With [`PhysicsOptions::coupled_actuators`] a coupled chain is one actuator: the leader's
///   effort limit `τ` is shared so that joint `i` with multiplier `m_i` may exert
///   `τ |m_i| / Σ m_k²`, hence `Σ m_i τ_i = τ` (virtual work).
/// - Geometry: boxes, spheres and capsules map to the same primitives; cylinders are rotated
///   from parry's y axis to the URDF z axis; meshes become convex hulls on moving bodies and
///   triangle meshes on static bodies.
/// - Attachments are fixed (impulse) joints between the link's body and the object, which keeps
///   its mass and gravity; contacts between the object and the carrying link are off.
/// - Contacts between links of the same robot are off unless [`PhysicsOptions::self_collisions`].
/// - Objects at rest may fall asleep; forces, impulses, teleports and gravity changes wake them.
///   Robot links never sleep.
///
/// Runs single-threaded: the same scene and inputs give bitwise the same trajectory.
pub struct RapierBackend {
    options: PhysicsOptions,
    gravity: Vector3<f64>,
    time: f64,
    last_substep: f64,
    params: IntegrationParameters,
    pipeline: PhysicsPipeline,
    islands: IslandManager,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    ccd: CCDSolver,
    hooks: ContactFilter,
    objects: Vec<ObjectEntry>,
    robots: Vec<RobotEntry>,
    /// Warm-start impulses (normal, friction) of the contacts before the last substep.
    warmstart: HashMap<ContactKey, (f64, Vector2<f64>)>,
}

/// A contact point: collider pair and the two features in contact.
type ContactKey = (ColliderHandle, ColliderHandle, u32, u32);

impl std::fmt::Debug for RapierBackend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RapierBackend")
            .field("time", &self.time)
            .field("bodies", &self.bodies.len())
            .field("colliders", &self.colliders.len())
            .field("robots", &self.robots.len())
            .field("objects", &self.objects.len())
            .finish_non_exhaustive()
    }
}

#[derive(Clone)]
struct ObjectEntry {
    body: RigidBodyHandle,
    /// Carrying robot, link and the joint holding the object.
    attachment: Option<(RobotId, LinkId, ImpulseJointHandle)>,
}

#[derive(Clone)]
struct RobotEntry {
    robot: Arc<Robot>,
    /// Per link: the rigid body carrying it and the link's pose in that body's frame.
    link_body: Vec<(RigidBodyHandle, Isometry3<f64>)>,
    /// Per movable joint (by joint index): its multibody joint.
    joints: Vec<Option<JointEntry>>,
    /// Per dof: target, velocity limit, current reference and its velocity.
    dofs: Vec<DofState>,
    /// Measured joint positions (unwrapped) and velocities, per dof.
    q: Vec<f64>,
    qd: Vec<f64>,
    /// Effort targets put forces on the link bodies during the last substep (cleared before
    /// the next).
    pushing: bool,
}

#[derive(Clone, Copy)]
struct JointEntry {
    handle: MultibodyJointHandle,
    prismatic: bool,
    /// Joint frames in the parent and child bodies (x = joint axis).
    frame1: Isometry3<f64>,
    frame2: Isometry3<f64>,
    /// Parent and child rigid bodies.
    parent: RigidBodyHandle,
    child: RigidBodyHandle,
    /// A spring replacing the actuator's target ([`PhysicsEngine::set_joint_spring`]), with the
    /// motor's force limit it is capped at.
    spring: Option<(super::JointSpring, f64)>,
}

#[derive(Clone, Copy)]
struct DofState {
    target: JointTarget,
    vmax: f64,
    reference: f64,
    reference_velocity: f64,
}

impl RapierBackend {
    /// [`CoreError::SimulationDiverged`] once the simulation has blown up: a dynamic body farther than
    /// [`DIVERGED_DISTANCE`] from the origin, faster than [`DIVERGED_SPEED`], or not finite.
    /// Stepping such a world further panics inside parry's broad phase (its BVH bins overflow),
    /// so `step` stops at the first substep that leaves a body there.
    fn check_diverged(&self) -> Result<()> {
        for (_, body) in self.bodies.iter().filter(|(_, b)| b.is_dynamic()) {
            let (p, v) = (body.translation(), body.linvel());
            let (distance, speed) = (p.norm(), v.norm());
            if !(distance <= DIVERGED_DISTANCE && speed <= DIVERGED_SPEED) {
                return Err(CoreError::SimulationDiverged { time: self.time, distance, speed });
            }
        }
        Ok(())
    }

    fn robot(&self, id: RobotId) -> Result<&RobotEntry> {
        self.robots.get(id.0).ok_or(CoreError::InvalidHandle { kind: "robot", index: id.0 })
    }

    /// The multibody entry of `joint` of `robot` if a dof drives it, with the error a
    /// vanished multibody link reports; else `InvalidHandle`.
    fn driven_joint(&self, robot: RobotId, joint: crate::model::JointId) -> Result<(JointEntry, CoreError)> {
        let r = self.robot(robot)?;
        let bad = || CoreError::InvalidHandle { kind: "joint", index: joint.0 };
        match r.joints.get(joint.0).copied() {
            Some(Some(e)) if r.robot.driving_dof(joint).is_some() => Ok((e, bad())),
            _ => Err(bad()),
        }
    }

    fn object(&self, id: ObjectId) -> Result<&ObjectEntry> {
        self.objects.get(id.0).ok_or(CoreError::InvalidHandle { kind: "object", index: id.0 })
    }
}

impl PhysicsEngine for RapierBackend {
    fn from_scene(scene: &Scene, options: &PhysicsOptions) -> Result<Self> {
        options.validate()?;
        let params = IntegrationParameters {
            dt: options.timestep,
            num_solver_iterations: options.solver_iterations,
            normalized_allowed_linear_error: options.allowed_penetration,
            contact_natural_frequency: options.contact_frequency,
            ..IntegrationParameters::default()
        };
        let mut engine = Self {
            options: options.clone(),
            gravity: options.gravity,
            time: 0.0,
            last_substep: options.timestep,
            params,
            pipeline: PhysicsPipeline::new(),
            islands: IslandManager::new(),
            broad_phase: BroadPhaseBvh::new(),
            narrow_phase: NarrowPhase::new(),
            bodies: RigidBodySet::new(),
            colliders: ColliderSet::new(),
            impulse_joints: ImpulseJointSet::new(),
            multibody_joints: MultibodyJointSet::new(),
            ccd: CCDSolver::new(),
            hooks: ContactFilter {
                robots: scene.robots().iter().map(|r| Arc::clone(&r.robot)).collect(),
                self_collisions: options.self_collisions,
            },
            objects: Vec::new(),
            robots: Vec::new(),
            warmstart: HashMap::new(),
        };
        for (i, b) in scene.bodies().iter().enumerate() {
            let body = engine.bodies.insert(RigidBodyBuilder::fixed().pose(b.pose).build());
            engine.add_colliders(
                body,
                &b.shapes,
                &Isometry3::identity(),
                true,
                b.friction,
                ContactBody::Static(BodyId(i)),
            )?;
        }
        for (i, o) in scene.objects().iter().enumerate() {
            crate::error::ensure_finite(
                &format!("mass properties of object `{}`", o.name),
                o.inertia.iter().chain(o.center_of_mass.coords.iter()).copied(),
            )?;
            let symmetric = (o.inertia - o.inertia.transpose()).norm() <= 1e-9 * o.inertia.norm();
            if !symmetric || o.inertia.symmetric_eigenvalues().iter().any(|&l| l <= 0.0) {
                return Err(CoreError::InvalidParameter {
                    name: "inertia".into(),
                    reason: format!("object `{}` needs a symmetric positive definite inertia tensor", o.name),
                });
            }
            let mass = MassProperties::with_inertia_matrix(o.center_of_mass, o.mass, o.inertia);
            let body =
                engine.bodies.insert(RigidBodyBuilder::dynamic().pose(o.pose).additional_mass_properties(mass).build());
            engine.add_colliders(
                body,
                &o.shapes,
                &Isometry3::identity(),
                false,
                o.friction,
                ContactBody::Object(ObjectId(i)),
            )?;
            engine.objects.push(ObjectEntry { body, attachment: None });
        }
        for i in 0..scene.robots().len() {
            engine.add_robot(RobotId(i), scene)?;
        }
        for a in scene.attachments() {
            engine.attach_with_offset(a.object, a.robot, a.link, a.offset)?;
        }
        Ok(engine)
    }

    fn name(&self) -> &str {
        "rapier"
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn step(&mut self, dt: f64) -> Result<()> {
        let (n, h) = substeps(dt, self.options.timestep)?;
        self.params.dt = h;
        for i in 0..n {
            if i + 1 == n {
                self.snapshot_warmstart();
            }
            self.drive_motors(h);
            self.pipeline.step(
                &self.gravity,
                &self.params,
                &mut self.islands,
                &mut self.broad_phase,
                &mut self.narrow_phase,
                &mut self.bodies,
                &mut self.colliders,
                &mut self.impulse_joints,
                &mut self.multibody_joints,
                &mut self.ccd,
                &self.hooks,
                &(),
            );
            self.measure_joints();
            self.check_diverged()?;
        }
        self.last_substep = h;
        self.time += dt;
        Ok(())
    }

    /// Clones every set of the world (bodies, colliders, joints, islands, broad and narrow
    /// phase with their contact manifolds and warm-start impulses); the copy gets a fresh
    /// [`PhysicsPipeline`], which holds only per-step workspace.
    fn snapshot(&self) -> Option<Self> {
        Some(Self {
            options: self.options.clone(),
            gravity: self.gravity,
            time: self.time,
            last_substep: self.last_substep,
            params: self.params,
            pipeline: PhysicsPipeline::new(),
            islands: self.islands.clone(),
            broad_phase: self.broad_phase.clone(),
            narrow_phase: self.narrow_phase.clone(),
            bodies: self.bodies.clone(),
            colliders: self.colliders.clone(),
            impulse_joints: self.impulse_joints.clone(),
            multibody_joints: self.multibody_joints.clone(),
            ccd: self.ccd.clone(),
            hooks: self.hooks.clone(),
            objects: self.objects.clone(),
            robots: self.robots.clone(),
            warmstart: self.warmstart.clone(),
        })
    }

    fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<()> {
        check_vec("gravity", &gravity)?;
        self.gravity = gravity;
        for o in &self.objects {
            if let Some(b) = self.bodies.get_mut(o.body) {
                b.wake_up(true);
            }
        }
        Ok(())
    }

    fn set_joint_target(&mut self, robot: RobotId, dof: usize, target: JointTarget) -> Result<()> {
        let r = self.robot(robot)?;
        if dof >= r.dofs.len() {
            return Err(CoreError::InvalidHandle { kind: "dof", index: dof });
        }
        check_target(target)?;
        let r = &mut self.robots[robot.0];
        if matches!(target, JointTarget::Position(_)) && !matches!(r.dofs[dof].target, JointTarget::Position(_)) {
            r.dofs[dof].reference = r.q[dof];
        }
        r.dofs[dof].target = target;
        Ok(())
    }

    fn set_joint_force_limit(&mut self, robot: RobotId, joint: crate::model::JointId, limit: f64) -> Result<()> {
        let (e, bad) = self.driven_joint(robot, joint)?;
        super::check_force_limit(limit)?;
        let axis = if e.prismatic { JointAxis::LinX } else { JointAxis::AngX };
        let Some((mb, link_id)) = self.multibody_joints.get_mut(e.handle) else { return Err(bad) };
        if let Some(link) = mb.link_mut(link_id) {
            link.joint.data.set_motor_max_force(axis, limit);
        }
        if let Some(Some(JointEntry { spring: Some((_, cap)), .. })) = self.robots[robot.0].joints.get_mut(joint.0) {
            *cap = limit;
        }
        Ok(())
    }

    fn set_joint_spring(
        &mut self,
        robot: RobotId,
        joint: crate::model::JointId,
        spring: Option<super::JointSpring>,
    ) -> Result<()> {
        let (e, bad) = self.driven_joint(robot, joint)?;
        if let Some(s) = spring {
            s.validate()?;
        }
        let axis = if e.prismatic { JointAxis::LinX } else { JointAxis::AngX };
        let Some((mb, link_id)) = self.multibody_joints.get_mut(e.handle) else { return Err(bad) };
        let Some(link) = mb.link(link_id) else { return Err(bad) };
        // The motor's own force limit: kept while a spring caps it, restored without one.
        let limit = match e.spring {
            Some((_, cap)) => cap,
            None => link.joint.data.motors[axis as usize].max_force,
        };
        if spring.is_none() {
            robots::set_damping(mb, link_id, None);
            if let Some(link) = mb.link_mut(link_id) {
                link.joint.data.set_motor_max_force(axis, limit);
            }
        }
        if let Some(Some(entry)) = self.robots[robot.0].joints.get_mut(joint.0) {
            entry.spring = spring.map(|s| (s, limit));
        }
        Ok(())
    }

    fn joint_positions(&self, robot: RobotId) -> Result<Vec<f64>> {
        Ok(self.robot(robot)?.q.clone())
    }

    fn joint_velocities(&self, robot: RobotId) -> Result<Vec<f64>> {
        Ok(self.robot(robot)?.qd.clone())
    }

    fn link_pose(&self, robot: RobotId, link: LinkId) -> Result<Isometry3<f64>> {
        let r = self.robot(robot)?;
        let (body, off) = r.link_body.get(link.0).ok_or(CoreError::InvalidHandle { kind: "link", index: link.0 })?;
        let b = self.bodies.get(*body).ok_or_else(|| CoreError::Physics { reason: "link body vanished".into() })?;
        Ok(b.position() * off)
    }

    fn object_pose(&self, object: ObjectId) -> Result<Isometry3<f64>> {
        let o = self.object(object)?;
        Ok(*self.bodies[o.body].position())
    }

    fn object_velocity(&self, object: ObjectId) -> Result<BodyVelocity> {
        let b = &self.bodies[self.object(object)?.body];
        Ok(BodyVelocity { linear: *b.linvel(), angular: *b.angvel() })
    }

    fn set_object_pose(&mut self, object: ObjectId, pose: Isometry3<f64>) -> Result<()> {
        self.object(object)?;
        crate::error::ensure_finite_pose("object pose", &pose)?;
        if self.objects[object.0].attachment.is_some() {
            self.detach(object)?;
        }
        let b = &mut self.bodies[self.objects[object.0].body];
        b.set_position(pose, true);
        b.set_linvel(Vector3::zeros(), true);
        b.set_angvel(Vector3::zeros(), true);
        Ok(())
    }

    fn set_object_fixed(&mut self, object: ObjectId, fixed: bool) -> Result<()> {
        if fixed && self.object(object)?.attachment.is_some() {
            self.detach(object)?;
        }
        let body = self.object(object)?.body;
        let b = &mut self.bodies[body];
        let kind = if fixed { RigidBodyType::Fixed } else { RigidBodyType::Dynamic };
        if b.body_type() != kind {
            b.set_body_type(kind, true);
            b.set_linvel(Vector3::zeros(), true);
            b.set_angvel(Vector3::zeros(), true);
        }
        Ok(())
    }

    /// Rapier's own body damping (implicit: each substep `h` divides the velocities by
    /// `1 + h · rate`, stable for any rate).
    fn set_object_damping(&mut self, object: ObjectId, linear: f64, angular: f64) -> Result<()> {
        let body = self.object(object)?.body;
        super::check_damping(linear, angular)?;
        let b = &mut self.bodies[body];
        b.set_linear_damping(linear);
        b.set_angular_damping(angular);
        b.wake_up(true);
        Ok(())
    }

    fn set_contact_frequency(&mut self, hz: f64) -> Result<()> {
        super::check_param("contact_frequency", hz, hz.is_finite() && hz > 0.0, "must be finite and > 0")?;
        self.params.contact_natural_frequency = hz;
        self.options.contact_frequency = hz;
        Ok(())
    }

    fn apply_object_impulse(&mut self, object: ObjectId, impulse: Vector3<f64>, point: Point3<f64>) -> Result<()> {
        let body = self.object(object)?.body;
        check_vec("impulse", &impulse)?;
        check_vec("impulse point", &point.coords)?;
        self.bodies[body].apply_impulse_at_point(impulse, point, true);
        Ok(())
    }

    fn set_object_force(&mut self, object: ObjectId, force: Vector3<f64>, torque: Vector3<f64>) -> Result<()> {
        let body = self.object(object)?.body;
        check_vec("force", &force)?;
        check_vec("torque", &torque)?;
        let b = &mut self.bodies[body];
        b.reset_forces(true);
        b.reset_torques(true);
        b.add_force(force, true);
        b.add_torque(torque, true);
        Ok(())
    }

    fn contacts(&self) -> Vec<PhysicsContact> {
        let mut out = Vec::new();
        for pair in self.narrow_phase.contact_pairs() {
            if !pair.has_any_active_contact {
                continue;
            }
            let (Some(c1), Some(c2)) = (self.colliders.get(pair.collider1), self.colliders.get(pair.collider2)) else {
                continue;
            };
            let (Some(body1), Some(body2)) = (decode(c1.user_data), decode(c2.user_data)) else { continue };
            for m in &pair.manifolds {
                let pos1 = m.subshape_pos1.map_or(*c1.position(), |p| c1.position() * p);
                let pos2 = m.subshape_pos2.map_or(*c2.position(), |p| c2.position() * p);
                for p in &m.points {
                    if p.data.impulse <= 0.0 && p.dist > 0.0 {
                        continue;
                    }
                    let key = (pair.collider1, pair.collider2, p.fid1.0, p.fid2.0);
                    let (warm_n, warm_t) = self.warmstart.get(&key).copied().unwrap_or_default();
                    let coeff = self.params.warmstart_coefficient;
                    let normal_impulse = (p.data.impulse - coeff * warm_n).max(0.0);
                    let friction_impulse = (p.data.tangent_impulse - coeff * warm_t).norm();
                    out.push(PhysicsContact {
                        body1,
                        body2,
                        point: nalgebra::center(&(pos1 * p.local_p1), &(pos2 * p.local_p2)),
                        normal: m.data.normal,
                        distance: p.dist,
                        normal_impulse,
                        friction_impulse,
                        normal_force: normal_impulse / self.last_substep,
                    });
                }
            }
        }
        out
    }

    fn attach(&mut self, object: ObjectId, robot: RobotId, link: LinkId) -> Result<()> {
        let link_pose = self.link_pose(robot, link)?;
        if self.object(object)?.attachment.is_some() {
            return Err(CoreError::InvalidParameter {
                name: "object".into(),
                reason: format!("object {} is already attached", object.0),
            });
        }
        let offset = link_pose.inverse() * self.object_pose(object)?;
        self.attach_with_offset(object, robot, link, offset)
    }

    fn detach(&mut self, object: ObjectId) -> Result<()> {
        let Some((_, _, handle)) = self.object(object)?.attachment else {
            return Err(CoreError::InvalidHandle { kind: "attachment", index: object.0 });
        };
        self.impulse_joints.remove(handle, true);
        self.objects[object.0].attachment = None;
        Ok(())
    }
}
