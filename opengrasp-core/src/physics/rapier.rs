//! The rapier3d (f64) backend.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector2, Vector3};
use rapier3d_f64::parry::mass_properties::MassProperties;
use rapier3d_f64::prelude::{
    ActiveHooks, BroadPhaseBvh, CCDSolver, ColliderBuilder, ColliderHandle, ColliderSet, FixedJointBuilder,
    GenericJointBuilder, ImpulseJointHandle, ImpulseJointSet, IntegrationParameters, IslandManager, JointAxesMask,
    JointAxis, MultibodyJointHandle, MultibodyJointSet, NarrowPhase, PairFilterContext, PhysicsHooks, PhysicsPipeline,
    RigidBodyBuilder, RigidBodyHandle, RigidBodySet, SharedShape, SolverFlags,
};

use super::{
    advance_reference, check_pose, check_target, check_vec, substeps, velocity_limit, BodyVelocity, ContactBody,
    JointTarget, PhysicsContact, PhysicsEngine, PhysicsOptions,
};
use crate::error::{CoreError, Result};
use crate::kinematics::forward_kinematics_into;
use crate::model::{Geometry, JointId, JointKind, LinkId, Robot, Shape};
use crate::scene::{BodyId, ObjectId, RobotId, Scene};

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
///   enforced. Mimic joints track `multiplier * leader reference + offset` with their own motor.
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

struct ObjectEntry {
    body: RigidBodyHandle,
    /// Carrying robot, link and the joint holding the object.
    attachment: Option<(RobotId, LinkId, ImpulseJointHandle)>,
}

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
}

#[derive(Clone, Copy)]
struct JointEntry {
    handle: MultibodyJointHandle,
    prismatic: bool,
    /// Joint frames in the parent and child bodies (x = joint axis).
    frame1: Isometry3<f64>,
    frame2: Isometry3<f64>,
}

#[derive(Clone, Copy)]
struct DofState {
    target: JointTarget,
    vmax: f64,
    reference: f64,
    reference_velocity: f64,
}

/// Collider user data: what the collider belongs to.
fn encode(body: ContactBody) -> u128 {
    match body {
        ContactBody::Static(b) => (1u128 << 126) | b.0 as u128,
        ContactBody::Object(o) => (2u128 << 126) | o.0 as u128,
        ContactBody::Link { robot, link } => (3u128 << 126) | ((robot.0 as u128) << 63) | link.0 as u128,
    }
}

fn decode(data: u128) -> Option<ContactBody> {
    let low = (data & ((1u128 << 63) - 1)) as usize;
    match data >> 126 {
        1 => Some(ContactBody::Static(BodyId(low))),
        2 => Some(ContactBody::Object(ObjectId(low))),
        3 => {
            Some(ContactBody::Link { robot: RobotId(((data >> 63) & ((1u128 << 63) - 1)) as usize), link: LinkId(low) })
        }
        _ => None,
    }
}

/// Filters contacts between links of the same robot.
struct ContactFilter {
    robots: Vec<Arc<Robot>>,
    self_collisions: bool,
}

impl PhysicsHooks for ContactFilter {
    fn filter_contact_pair(&self, context: &PairFilterContext) -> Option<SolverFlags> {
        let body = |h: ColliderHandle| context.colliders.get(h).and_then(|c| decode(c.user_data));
        if let (Some(ContactBody::Link { robot: r1, link: l1 }), Some(ContactBody::Link { robot: r2, link: l2 })) =
            (body(context.collider1), body(context.collider2))
        {
            if r1 == r2 && (!self.self_collisions || self.robots[r1.0].is_collision_allowed(l1, l2)) {
                return None;
            }
        }
        Some(SolverFlags::COMPUTE_IMPULSES)
    }
}

/// Rotation taking parry's y axis (cylinders) to URDF's z axis.
fn y_to_z() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI / 2.0)
}

/// A rapier shape and its pose in the geometry frame, for a geometry.
fn convert(geometry: &Geometry, is_static: bool) -> Result<(SharedShape, Isometry3<f64>)> {
    geometry.validate()?;
    Ok(match geometry {
        Geometry::Box { half_extents } => {
            (SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z), Isometry3::identity())
        }
        Geometry::Sphere { radius } => (SharedShape::ball(*radius), Isometry3::identity()),
        Geometry::Cylinder { radius, length } => {
            (SharedShape::cylinder(length * 0.5, *radius), Isometry3::from_parts(Translation3::identity(), y_to_z()))
        }
        Geometry::Capsule { radius, length } => (
            SharedShape::capsule(Point3::new(0.0, 0.0, -length * 0.5), Point3::new(0.0, 0.0, length * 0.5), *radius),
            Isometry3::identity(),
        ),
        Geometry::Mesh(mesh) => {
            let shape = if is_static {
                SharedShape::trimesh(mesh.vertices().to_vec(), mesh.triangles().to_vec()).map_err(|e| {
                    CoreError::DegenerateMesh { reason: format!("rapier rejects the triangle mesh: {e:?}") }
                })?
            } else {
                SharedShape::convex_hull(mesh.vertices())
                    .ok_or_else(|| CoreError::DegenerateMesh { reason: "mesh has no 3-d convex hull".into() })?
            };
            (shape, Isometry3::identity())
        }
    })
}

impl RapierBackend {
    fn robot(&self, id: RobotId) -> Result<&RobotEntry> {
        self.robots.get(id.0).ok_or(CoreError::InvalidHandle { kind: "robot", index: id.0 })
    }

    fn object(&self, id: ObjectId) -> Result<&ObjectEntry> {
        self.objects.get(id.0).ok_or(CoreError::InvalidHandle { kind: "object", index: id.0 })
    }

    /// Adds colliders for `shapes` (placed at `offset` in the body) to `body`.
    fn add_colliders(
        &mut self,
        body: RigidBodyHandle,
        shapes: &[Shape],
        offset: &Isometry3<f64>,
        is_static: bool,
        friction: f64,
        owner: ContactBody,
    ) -> Result<()> {
        for s in shapes {
            let (shape, local) = convert(&s.geometry, is_static)?;
            let mut builder = ColliderBuilder::new(shape)
                .position(offset * s.origin * local)
                .density(0.0)
                .friction(friction)
                .user_data(encode(owner));
            if matches!(owner, ContactBody::Link { .. }) {
                builder = builder.active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
            }
            self.colliders.insert_with_parent(builder.build(), body, &mut self.bodies);
        }
        Ok(())
    }

    fn add_robot(&mut self, id: RobotId, scene: &Scene) -> Result<()> {
        let sr = scene.robot(id)?;
        let robot = Arc::clone(&sr.robot);
        sr.robot.validate_configuration(&sr.q)?;
        let mut fk = Vec::new();
        forward_kinematics_into(&robot, &sr.q, &mut fk);
        let n_links = robot.links().len();

        // Which link's body carries each link (fixed joints merge into the parent's body).
        let mut carrier: Vec<LinkId> = (0..n_links).map(LinkId).collect();
        for &j in robot.joints_topological() {
            let joint = robot.joint(j);
            if joint.kind == JointKind::Fixed {
                carrier[joint.child.0] = carrier[joint.parent.0];
            }
        }
        let offset = |l: usize| fk[carrier[l].0].inverse() * fk[l];

        // One rigid body per carrier link, with the merged mass properties.
        let mut handles: Vec<Option<RigidBodyHandle>> = vec![None; n_links];
        for c in 0..n_links {
            if carrier[c].0 != c {
                continue;
            }
            let is_root = c == robot.root().0;
            let mut mass = MassProperties::default();
            for l in (0..n_links).filter(|&l| carrier[l].0 == c) {
                let link = robot.link(LinkId(l));
                let off = offset(l);
                match &link.inertial {
                    Some(i) if i.is_physical() => {
                        let frame = off * i.origin;
                        let r = frame.rotation.to_rotation_matrix();
                        let inertia = r.matrix() * i.inertia * r.matrix().transpose();
                        mass += MassProperties::with_inertia_matrix(
                            Point3::from(frame.translation.vector),
                            i.mass,
                            inertia,
                        );
                    }
                    _ => {
                        for s in &link.collisions {
                            let (shape, local) = convert(&s.geometry, false)?;
                            mass += shape
                                .mass_properties(self.options.link_density)
                                .transform_by(&(off * s.origin * local));
                        }
                    }
                }
            }
            if mass.mass().is_nan() || mass.mass() <= 0.0 {
                let m = self.options.min_link_mass;
                mass = MassProperties::new(Point3::origin(), m, Vector3::repeat(0.4 * m * 0.02 * 0.02));
            }
            let builder = if is_root { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic() };
            let body = builder
                .pose(sr.base_pose * fk[c])
                .additional_mass_properties(mass)
                .gravity_scale(if self.options.gravity_compensation { 0.0 } else { 1.0 })
                .can_sleep(false)
                .build();
            handles[c] = Some(self.bodies.insert(body));
        }
        let mut link_body = Vec::with_capacity(n_links);
        for l in 0..n_links {
            let body =
                handles[carrier[l].0].ok_or_else(|| CoreError::Physics { reason: "link without body".into() })?;
            let off = offset(l);
            let owner = ContactBody::Link { robot: id, link: LinkId(l) };
            let shapes = robot.link(LinkId(l)).collisions.clone();
            self.add_colliders(body, &shapes, &off, false, self.options.link_friction, owner)?;
            link_body.push((body, off));
        }

        // Multibody joints with motors, in topological order.
        let (k, c) = (self.options.joint_stiffness, self.options.joint_damping);
        let mut joints = vec![None; robot.joints().len()];
        for &j in robot.joints_topological() {
            let joint = robot.joint(j);
            if joint.kind == JointKind::Fixed {
                continue;
            }
            let prismatic = joint.kind == JointKind::Prismatic;
            let axis_rot = UnitQuaternion::rotation_between(&Vector3::x(), &joint.axis)
                .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI));
            let frame2 = Isometry3::from_parts(Translation3::identity(), axis_rot);
            let (parent_body, parent_off) = link_body[joint.parent.0];
            let frame1 = parent_off * joint.origin * frame2;
            let axis = if prismatic { JointAxis::LinX } else { JointAxis::AngX };
            let locked =
                if prismatic { JointAxesMask::LOCKED_PRISMATIC_AXES } else { JointAxesMask::LOCKED_REVOLUTE_AXES };
            let q0 = robot.joint_position(&sr.q, j);
            let mut builder = GenericJointBuilder::new(locked)
                .local_frame1(frame1)
                .local_frame2(frame2)
                .contacts_enabled(false)
                .set_motor(axis, q0, 0.0, k, c);
            if let Some(l) = joint.limits {
                if joint.kind != JointKind::Continuous {
                    builder = builder.limits(axis, [l.lower, l.upper]);
                }
                if l.effort.is_finite() && l.effort > 0.0 {
                    builder = builder.motor_max_force(axis, l.effort);
                }
            }
            let child_body = link_body[joint.child.0].0;
            let handle =
                self.multibody_joints.insert(parent_body, child_body, builder.build(), true).ok_or_else(|| {
                    CoreError::Physics { reason: format!("rapier rejected multibody joint `{}`", joint.name) }
                })?;
            joints[j.0] = Some(JointEntry { handle, prismatic, frame1, frame2 });
        }

        // Move the multibody to the scene configuration.
        if let Some(first) = joints.iter().flatten().next() {
            let (mb, _) = self
                .multibody_joints
                .get_mut(first.handle)
                .ok_or_else(|| CoreError::Physics { reason: "multibody vanished".into() })?;
            mb.forward_kinematics(&self.bodies, true);
            let mut assembly = Vec::with_capacity(mb.num_links());
            let mut acc = 0;
            for link in mb.links() {
                assembly.push(acc);
                acc += link.joint().ndofs();
            }
            let mut disp = vec![0.0; mb.ndofs()];
            for (ji, entry) in joints.iter().enumerate() {
                if let Some(e) = entry {
                    let link_id = self.multibody_joints.get(e.handle).map(|(_, l)| l).unwrap_or(0);
                    disp[assembly[link_id]] = robot.joint_position(&sr.q, JointId(ji));
                }
            }
            let (mb, _) = self
                .multibody_joints
                .get_mut(first.handle)
                .ok_or_else(|| CoreError::Physics { reason: "multibody vanished".into() })?;
            mb.apply_displacements(&disp);
            mb.forward_kinematics(&self.bodies, true);
            mb.update_rigid_bodies(&mut self.bodies, true);
        }

        let dofs = (0..robot.dof())
            .map(|i| DofState {
                target: JointTarget::Position(sr.q[i]),
                vmax: velocity_limit(&robot, i, &self.options),
                reference: sr.q[i],
                reference_velocity: 0.0,
            })
            .collect();
        let n = robot.dof();
        self.robots.push(RobotEntry { robot, link_body, joints, dofs, q: sr.q.clone(), qd: vec![0.0; n] });
        Ok(())
    }

    /// Attaches with a fixed joint; `offset` is the object pose in the link frame.
    fn attach_with_offset(
        &mut self,
        object: ObjectId,
        robot: RobotId,
        link: LinkId,
        offset: Isometry3<f64>,
    ) -> Result<()> {
        let (link_body, link_off) = self.robots[robot.0].link_body[link.0];
        // rapier 0.30 anchors an impulse joint on a multibody link at the link's centre of mass
        // rather than its frame (measured: the object ends up offset by exactly the link's local
        // centre of mass), so shift the frame by it. A fixed *multibody* joint would avoid this,
        // but rapier cannot append one to a multibody whose root is already fixed.
        let com = self.bodies[link_body].mass_properties().local_mprops.local_com;
        let frame = Translation3::from(com.coords) * link_off * offset;
        let joint = FixedJointBuilder::new().local_frame2(frame).contacts_enabled(false).build();
        let handle = self.impulse_joints.insert(self.objects[object.0].body, link_body, joint, true);
        self.objects[object.0].attachment = Some((robot, link, handle));
        Ok(())
    }

    /// Updates motor targets from the references for one substep of length `h`.
    fn drive_motors(&mut self, h: f64) {
        let (k, c) = (self.options.joint_stiffness, self.options.joint_damping);
        for r in &mut self.robots {
            for (i, d) in r.dofs.iter_mut().enumerate() {
                let limits = r.robot.dof_limits(i);
                let next = match d.target {
                    JointTarget::Position(_) => advance_reference(d.reference, d.target, d.vmax, limits, h),
                    JointTarget::Velocity(_) => advance_reference(r.q[i], d.target, d.vmax, limits, h),
                };
                let base = if matches!(d.target, JointTarget::Position(_)) { d.reference } else { r.q[i] };
                d.reference_velocity = (next - base) / h;
                d.reference = next;
            }
            let refs: Vec<f64> = r.dofs.iter().map(|d| d.reference).collect();
            for (ji, entry) in r.joints.iter().enumerate() {
                let Some(e) = entry else { continue };
                let j = JointId(ji);
                let Some((dof, factor)) = r.robot.driving_dof(j) else { continue };
                let d = r.dofs[dof];
                let pos = r.robot.joint_position(&refs, j);
                let vel = factor * d.reference_velocity;
                // A dof under velocity control has no position spring; mimic joints always do.
                let velocity_mode = matches!(d.target, JointTarget::Velocity(_)) && r.robot.joint(j).dof.is_some();
                let stiffness = if velocity_mode { 0.0 } else { k };
                let axis = if e.prismatic { JointAxis::LinX } else { JointAxis::AngX };
                if let Some(link) = self.multibody_joints.get_mut(e.handle).and_then(|(mb, l)| mb.link_mut(l)) {
                    link.joint.data.set_motor(axis, pos, vel, stiffness, c);
                }
            }
        }
    }

    /// Records the warm-start impulses the solver will count again in its next step.
    ///
    /// rapier 0.30 adds a contact's warm-start impulse (the previous step's last-substep impulse)
    /// into the total impulse it reports, so [`PhysicsEngine::contacts`] subtracts it.
    fn snapshot_warmstart(&mut self) {
        self.warmstart.clear();
        for pair in self.narrow_phase.contact_pairs() {
            for m in &pair.manifolds {
                for p in &m.points {
                    let key = (pair.collider1, pair.collider2, p.fid1.0, p.fid2.0);
                    self.warmstart.insert(key, (p.data.warmstart_impulse, p.data.warmstart_tangent_impulse));
                }
            }
        }
    }

    /// Reads joint positions (unwrapping revolute angles) and velocities after a substep.
    fn measure_joints(&mut self) {
        for r in &mut self.robots {
            for i in 0..r.q.len() {
                let j = r.robot.dof_joint(i);
                let Some(e) = r.joints[j.0] else { continue };
                let Some((mb, link_id)) = self.multibody_joints.get(e.handle) else { continue };
                let Some(link) = mb.link(link_id) else { continue };
                let rel = e.frame1.inverse() * link.joint().body_to_parent() * e.frame2;
                let value = if e.prismatic {
                    rel.translation.vector.x
                } else {
                    let q = rel.rotation.quaternion();
                    let angle = 2.0 * q.i.atan2(q.w);
                    let prev = r.q[i];
                    angle + 2.0 * PI * ((prev - angle) / (2.0 * PI)).round()
                };
                r.q[i] = value;
                r.qd[i] = mb.joint_velocity(link).get(0).copied().unwrap_or(0.0);
            }
        }
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
        }
        self.last_substep = h;
        self.time += dt;
        Ok(())
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
        if matches!(target, JointTarget::Position(_)) && matches!(r.dofs[dof].target, JointTarget::Velocity(_)) {
            r.dofs[dof].reference = r.q[dof];
        }
        r.dofs[dof].target = target;
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
        check_pose("object pose", &pose)?;
        if self.objects[object.0].attachment.is_some() {
            self.detach(object)?;
        }
        let b = &mut self.bodies[self.objects[object.0].body];
        b.set_position(pose, true);
        b.set_linvel(Vector3::zeros(), true);
        b.set_angvel(Vector3::zeros(), true);
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
