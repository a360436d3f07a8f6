//! Robots as rapier multibodies: building them, their motors and joint measurements.

use std::f64::consts::PI;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rapier3d_f64::parry::mass_properties::MassProperties;
use rapier3d_f64::prelude::{
    ActiveHooks, ColliderBuilder, FixedJointBuilder, GenericJointBuilder, JointAxesMask, JointAxis, Multibody,
    RigidBodyBuilder, RigidBodyHandle,
};

use super::{advance_reference, velocity_limit, ContactBody, JointTarget};
use crate::error::{CoreError, Result};
use crate::kinematics::forward_kinematics_into;
use crate::model::{JointId, JointKind, LinkId, Robot, Shape};
use crate::scene::{ObjectId, RobotId, Scene};

use super::colliders::{convert, encode};
use super::{DofState, JointEntry, RapierBackend, RobotEntry};

impl RapierBackend {
    /// Adds colliders for `shapes` (placed at `offset` in the body) to `body`.
    pub(super) fn add_colliders(
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

    pub(super) fn add_robot(&mut self, id: RobotId, scene: &Scene) -> Result<()> {
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
            mass += armature(&robot, LinkId(c), self.options.joint_armature, mass.local_com);
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

        // Multibody joints with motors, in topological order. With `independent_chains` each
        // chain hanging from the fixed root gets its own multibody, rooted at a fixed anchor
        // body at the root's pose.
        let (k, c) = (self.options.joint_stiffness, self.options.joint_damping);
        let mut joints = vec![None; robot.joints().len()];
        let root_body = link_body[robot.root().0].0;
        let mut root_taken = false;
        for &j in robot.joints_topological() {
            let joint = robot.joint(j);
            if joint.kind == JointKind::Fixed {
                continue;
            }
            let prismatic = joint.kind == JointKind::Prismatic;
            let axis_rot = UnitQuaternion::rotation_between(&Vector3::x(), &joint.axis)
                .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI));
            let frame2 = Isometry3::from_parts(Translation3::identity(), axis_rot);
            let (mut parent_body, parent_off) = link_body[joint.parent.0];
            if parent_body == root_body && self.options.independent_chains {
                if root_taken {
                    parent_body = self.bodies.insert(RigidBodyBuilder::fixed().pose(sr.base_pose * fk[robot.root().0]));
                }
                root_taken = true;
            }
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
            }
            if let Some(effort) = motor_effort(&robot, j, self.options.coupled_actuators) {
                builder = builder.motor_max_force(axis, effort);
            }
            let child_body = link_body[joint.child.0].0;
            let handle =
                self.multibody_joints.insert(parent_body, child_body, builder.build(), true).ok_or_else(|| {
                    CoreError::Physics { reason: format!("rapier rejected multibody joint `{}`", joint.name) }
                })?;
            joints[j.0] = Some(JointEntry {
                handle,
                prismatic,
                frame1,
                frame2,
                parent: parent_body,
                child: child_body,
                spring: None,
            });
        }

        // Move the multibodies to the scene configuration.
        let mut multibodies = Vec::new();
        for e in joints.iter().flatten() {
            let link = self.multibody_joints.rigid_body_link(e.child).copied();
            let index = link.ok_or_else(|| CoreError::Physics { reason: "multibody vanished".into() })?.multibody;
            if !multibodies.contains(&index) {
                multibodies.push(index);
            }
        }
        for index in multibodies {
            let mb = self
                .multibody_joints
                .get_multibody_mut(index)
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
                let Some(e) = entry else { continue };
                match self.multibody_joints.rigid_body_link(e.child) {
                    Some(link) if link.multibody == index => {
                        disp[assembly[link.id]] = robot.joint_position(&sr.q, JointId(ji));
                    }
                    _ => {}
                }
            }
            let mb = self
                .multibody_joints
                .get_multibody_mut(index)
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
        self.robots.push(RobotEntry {
            robot,
            link_body,
            joints,
            dofs,
            q: sr.q.clone(),
            qd: vec![0.0; n],
            pushing: false,
        });
        Ok(())
    }

    /// Attaches with a fixed joint; `offset` is the object pose in the link frame.
    pub(super) fn attach_with_offset(
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

    /// Updates motor targets from the references for one substep of length `h`, and applies
    /// the torques of effort targets.
    pub(super) fn drive_motors(&mut self, h: f64) {
        let (k, c) = (self.options.joint_stiffness, self.options.joint_damping);
        let coupled = self.options.coupled_actuators;
        for r in &mut self.robots {
            if r.pushing {
                for &(body, _) in &r.link_body {
                    if let Some(b) = self.bodies.get_mut(body) {
                        b.reset_forces(false);
                        b.reset_torques(false);
                    }
                }
                r.pushing = false;
            }
            for (i, d) in r.dofs.iter_mut().enumerate() {
                let limits = r.robot.dof_limits(i);
                let next = match d.target {
                    JointTarget::Position(_) => advance_reference(d.reference, d.target, d.vmax, limits, h),
                    JointTarget::Velocity(_) => advance_reference(r.q[i], d.target, d.vmax, limits, h),
                    JointTarget::Effort(_) => r.q[i],
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
                let axis = if e.prismatic { JointAxis::LinX } else { JointAxis::AngX };
                let Some((mb, link_id)) = self.multibody_joints.get_mut(e.handle) else { continue };
                let speed = mb.link(link_id).map_or(0.0, |l| mb.joint_velocity(l).get(0).copied().unwrap_or(0.0));
                let vmax = d.vmax * factor.abs();
                let torque = if let Some((s, limit)) = e.spring {
                    // An explicit joint torque (rapier's multibody motors, solved without warm
                    // start in one iteration per substep, fall far short of their force limit
                    // in a multi-joint finger), with the damping that keeps it stable.
                    set_damping(mb, link_id, Some(s.stiffness * h));
                    let Some(link) = mb.link(link_id) else { continue };
                    let q = joint_value(e, &link.joint().body_to_parent(), s.position);
                    Some((s.stiffness * (s.position - q)).clamp(-limit, limit))
                } else if let JointTarget::Effort(effort) = d.target {
                    Some(joint_effort(&r.robot, j, effort, coupled))
                } else {
                    None
                };
                if let Some(torque) = torque {
                    let Some(link) = mb.link_mut(link_id) else { continue };
                    link.joint.data.motor_axes.remove(axis.into());
                    // Full torque up to the velocity limit, none beyond twice it.
                    let taper = if vmax > 0.0 { (2.0 - speed * torque.signum() / vmax).clamp(0.0, 1.0) } else { 1.0 };
                    apply_joint_effort(&mut self.bodies, e, torque * taper);
                    r.pushing = true;
                    continue;
                }
                let pos = r.robot.joint_position(&refs, j);
                let vel = factor * d.reference_velocity;
                // A dof under velocity control has no position spring; mimic joints always do.
                let velocity_mode = matches!(d.target, JointTarget::Velocity(_)) && r.robot.joint(j).dof.is_some();
                let stiffness = if velocity_mode { 0.0 } else { k };
                if let Some(link) = mb.link_mut(link_id) {
                    link.joint.data.set_motor(axis, pos, vel, stiffness, c);
                }
            }
        }
    }

    /// Records the warm-start impulses the solver will count again in its next step.
    ///
    /// rapier 0.30 adds a contact's warm-start impulse (the previous step's last-substep impulse)
    /// into the total impulse it reports, so [`PhysicsEngine::contacts`] subtracts it.
    pub(super) fn snapshot_warmstart(&mut self) {
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
    pub(super) fn measure_joints(&mut self) {
        for r in &mut self.robots {
            for i in 0..r.q.len() {
                let j = r.robot.dof_joint(i);
                let Some(e) = r.joints[j.0] else { continue };
                let Some((mb, link_id)) = self.multibody_joints.get(e.handle) else { continue };
                let Some(link) = mb.link(link_id) else { continue };
                r.q[i] = joint_value(&e, &link.joint().body_to_parent(), r.q[i]);
                r.qd[i] = mb.joint_velocity(link).get(0).copied().unwrap_or(0.0);
            }
        }
    }
}

/// Sets the viscous damping of the dof of link `link_id` of `mb` to rapier's default (0.1
/// N·m·s/rad for a revolute joint, none for a prismatic one) plus `extra`. A spring of stiffness
/// `k` whose torque is applied once per substep `h` gets `extra = k h`: rapier's damping is
/// implicit (in the multibody's mass matrix), so the spring's step then contracts whatever the
/// link's inertia (`k h² < 2 (I + c h)`; without inertia `q ← q + h k (rest − q) / c`).
/// Called every substep for every spring joint, so it writes the multibody's damping in place
/// (`default_damping` sets only the non-zero entries, hence the fill).
pub(super) fn set_damping(mb: &mut Multibody, link_id: usize, extra: Option<f64>) {
    let Some(joint) = mb.link(link_id).map(|link| *link.joint()) else { return };
    let ndofs = joint.ndofs();
    let start: usize = mb.links().take(link_id).map(|l| l.joint().ndofs()).sum();
    let mut damping = mb.damping_mut().rows_mut(start, ndofs);
    damping.fill(0.0);
    joint.default_damping(&mut damping);
    if let Some(c) = extra {
        damping.add_scalar_mut(c);
    }
}

/// The armature `I_a` of the actuated revolute joint moving `link` (if any) as massless mass
/// properties at `com` in the link's body frame: the rotational inertia `I_a a aᵀ` about the
/// joint axis `a` (the joint's frame is the child link's, whose body this is).
fn armature(robot: &Robot, link: LinkId, armature: f64, com: Point3<f64>) -> MassProperties {
    let revolute = |kind| matches!(kind, JointKind::Revolute | JointKind::Continuous);
    let joint = robot.parent_joint(link).filter(|&j| revolute(robot.joint(j).kind) && robot.driving_dof(j).is_some());
    match joint.and_then(|j| robot.joint(j).axis.try_normalize(1e-12)) {
        Some(a) if armature > 0.0 => MassProperties::with_inertia_matrix(com, 0.0, a * a.transpose() * armature),
        _ => MassProperties::default(),
    }
}

/// Joint `e`'s position (m, or rad unwrapped to the turn nearest `near`) from its multibody
/// link's `body_to_parent` transform.
fn joint_value(e: &JointEntry, body_to_parent: &Isometry3<f64>, near: f64) -> f64 {
    let rel = e.frame1.inverse() * body_to_parent * e.frame2;
    if e.prismatic {
        rel.translation.vector.x
    } else {
        let q = rel.rotation.quaternion();
        let angle = 2.0 * q.i.atan2(q.w);
        angle + 2.0 * PI * ((near - angle) / (2.0 * PI)).round()
    }
}

/// The force limit of joint `j`'s motor: its share of the actuator that drives it.
///
/// One actuator (a configuration dof, with the effort limit of its own joint) drives every joint
/// coupled to it by mimic multipliers `m_i` (`dq_i = m_i dq`). By virtual work the actuator's
/// torque is `τ = Σ m_i τ_i`, so joint `i` gets `τ_i = τ |m_i| / Σ m_k²`: the coupled chain
/// together delivers the actuator's torque, not one full torque per joint. A dof driving a single
/// joint keeps that joint's effort limit. Without `coupled`, every joint has its own effort limit.
/// `None` when the limit is not finite and positive.
pub(super) fn motor_effort(robot: &Robot, j: JointId, coupled: bool) -> Option<f64> {
    if !coupled {
        let effort = robot.joint(j).limits?.effort;
        return (effort.is_finite() && effort > 0.0).then_some(effort);
    }
    let (dof, factor) = robot.driving_dof(j)?;
    let effort = robot.joint(robot.dof_joint(dof)).limits?.effort;
    if !(effort.is_finite() && effort > 0.0) {
        return None;
    }
    let sum_sq: f64 = (0..robot.joints().len())
        .filter_map(|i| robot.driving_dof(JointId(i)))
        .filter(|&(d, _)| d == dof)
        .map(|(_, m)| m * m)
        .sum();
    (sum_sq > 0.0).then(|| effort * factor.abs() / sum_sq)
}

/// The torque (N·m, or force in N) joint `j` exerts when its actuator is commanded `effort`:
/// the command clamped to the actuator's effort limit, then shared as [`JointTarget::Effort`]
/// describes (virtual work with `coupled`, else the full command within the joint's own limit).
pub(super) fn joint_effort(robot: &Robot, j: JointId, effort: f64, coupled: bool) -> f64 {
    let Some((dof, factor)) = robot.driving_dof(j) else { return 0.0 };
    let limit = |joint: JointId| match robot.joint(joint).limits {
        Some(l) if l.effort.is_finite() && l.effort > 0.0 => l.effort,
        _ => f64::INFINITY,
    };
    let leader = limit(robot.dof_joint(dof));
    let command = effort.clamp(-leader, leader);
    if !coupled {
        let own = limit(j);
        return (command * factor.signum()).clamp(-own, own);
    }
    let sum_sq: f64 = (0..robot.joints().len())
        .filter_map(|i| robot.driving_dof(JointId(i)))
        .filter(|&(d, _)| d == dof)
        .map(|(_, m)| m * m)
        .sum();
    if sum_sq > 0.0 {
        command * factor / sum_sq
    } else {
        0.0
    }
}

/// Applies a joint torque (revolute: equal and opposite torques about the world joint axis on the
/// child and parent bodies) or force (prismatic: equal and opposite forces along the axis at the
/// child's centre of mass). Fixed bodies ignore theirs.
fn apply_joint_effort(bodies: &mut rapier3d_f64::prelude::RigidBodySet, e: &JointEntry, effort: f64) {
    let Some(child) = bodies.get(e.child) else { return };
    let axis = (child.position() * e.frame2).rotation * Vector3::x();
    let point = *child.center_of_mass();
    if e.prismatic {
        if let Some(b) = bodies.get_mut(e.child) {
            b.add_force(axis * effort, false);
        }
        if let Some(b) = bodies.get_mut(e.parent) {
            b.add_force_at_point(-axis * effort, point, false);
        }
    } else {
        if let Some(b) = bodies.get_mut(e.child) {
            b.add_torque(axis * effort, false);
        }
        if let Some(b) = bodies.get_mut(e.parent) {
            b.add_torque(-axis * effort, false);
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::motor_effort;
    use crate::model::{JointKind, JointSpec, Link, RobotBuilder};

    /// One 6 N·m actuator drives `a` directly, `b` at 0.5 × and `c` at −2 × `b` (a chain of
    /// mimics); `d` has its own 3 N·m actuator.
    #[test]
    fn coupled_joints_share_their_actuators_effort_by_virtual_work() {
        let revolute = |name: &str, child: &str, effort: f64| {
            JointSpec::new(name, JointKind::Revolute, "base", child).axis(Vector3::z()).limits(-1.0, 1.0, 1.0, effort)
        };
        let robot = RobotBuilder::new("coupled")
            .link(Link::new("base"))
            .link(Link::new("la"))
            .link(Link::new("lb"))
            .link(Link::new("lc"))
            .link(Link::new("ld"))
            .joint(revolute("a", "la", 6.0))
            .joint(revolute("b", "lb", 6.0).mimic("a", 0.5, 0.0))
            .joint(revolute("c", "lc", 6.0).mimic("b", -2.0, 0.1))
            .joint(revolute("d", "ld", 3.0))
            .build()
            .unwrap();
        let id = |n: &str| robot.joint_id(n).unwrap();
        let share = |n: &str| motor_effort(&robot, id(n), true).unwrap();
        // Σ m² = 1 + 0.25 + 1 = 2.25: shares 6/2.25 · (1, 0.5, 1).
        for (n, expected) in [("a", 6.0 / 2.25), ("b", 3.0 / 2.25), ("c", 6.0 / 2.25), ("d", 3.0)] {
            assert!((share(n) - expected).abs() < 1e-12, "{n}: {} N·m, expected {expected}", share(n));
        }
        // The coupled chain delivers the actuator's torque: Σ |m_i| τ_i = τ.
        let total = share("a") + 0.5 * share("b") + share("c");
        assert!((total - 6.0).abs() < 1e-12, "{total}");
        // Uncoupled: every joint its own full limit.
        for n in ["a", "b", "c"] {
            assert_eq!(motor_effort(&robot, id(n), false), Some(6.0));
        }
    }
}
