//! A deterministic kinematic stand-in for a physics engine.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};

use super::{
    advance_reference, check_target, check_vec, substeps, velocity_limit, BodyVelocity, JointTarget, PhysicsEngine,
    PhysicsOptions,
};
use crate::error::{CoreError, Result};
use crate::kinematics::link_pose_unchecked;
use crate::model::{LinkId, Robot};
use crate::scene::{ObjectId, RobotId, Scene};

/// A fast, deterministic backend without dynamics or contacts.
///
/// - Joints move towards their position targets at their velocity limit (or follow their
///   velocity targets), integrated exactly and clamped to the joint limits; a target within
///   reach of one step is hit exactly. An effort target moves its joint at the velocity limit
///   in the direction of the force (nothing resists it).
/// - Objects do not fall: gravity, external forces and impulses are validated and then ignored,
///   so a free object stays where it is. Attached objects follow their link rigidly.
/// - [`PhysicsEngine::contacts`] is always empty.
///
/// Use it to test code built on [`PhysicsEngine`] quickly; use
/// [`super::RapierBackend`] when contact forces matter.
#[derive(Clone, Debug)]
pub struct MockBackend {
    options: PhysicsOptions,
    gravity: Vector3<f64>,
    time: f64,
    robots: Vec<MockRobot>,
    objects: Vec<MockObject>,
}

#[derive(Clone, Debug)]
struct MockRobot {
    robot: Arc<Robot>,
    base_pose: Isometry3<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    targets: Vec<JointTarget>,
    vmax: Vec<f64>,
}

#[derive(Clone, Debug)]
struct MockObject {
    pose: Isometry3<f64>,
    center_of_mass: Point3<f64>,
    velocity: BodyVelocity,
    /// Carrying robot, link and object pose in the link frame.
    attachment: Option<(RobotId, LinkId, Isometry3<f64>)>,
}

impl MockBackend {
    fn robot(&self, id: RobotId) -> Result<&MockRobot> {
        self.robots.get(id.0).ok_or(CoreError::InvalidHandle { kind: "robot", index: id.0 })
    }

    /// `InvalidHandle` unless `joint` is a joint of `robot` driven by one of its dofs.
    fn driven_joint(&self, robot: RobotId, joint: crate::model::JointId) -> Result<()> {
        let r = self.robot(robot)?;
        if joint.0 >= r.robot.joints().len() || r.robot.driving_dof(joint).is_none() {
            return Err(CoreError::InvalidHandle { kind: "joint", index: joint.0 });
        }
        Ok(())
    }

    fn object(&self, id: ObjectId) -> Result<&MockObject> {
        self.objects.get(id.0).ok_or(CoreError::InvalidHandle { kind: "object", index: id.0 })
    }

    fn link_world_pose(&self, robot: RobotId, link: LinkId) -> Isometry3<f64> {
        let r = &self.robots[robot.0];
        r.base_pose * link_pose_unchecked(&r.robot, &r.q, link)
    }
}

impl PhysicsEngine for MockBackend {
    fn from_scene(scene: &Scene, options: &PhysicsOptions) -> Result<Self> {
        options.validate()?;
        let robots = scene
            .robots()
            .iter()
            .map(|r| {
                let n = r.robot.dof();
                MockRobot {
                    robot: Arc::clone(&r.robot),
                    base_pose: r.base_pose,
                    q: r.q.clone(),
                    qd: vec![0.0; n],
                    targets: r.q.iter().map(|&v| JointTarget::Position(v)).collect(),
                    vmax: (0..n).map(|i| velocity_limit(&r.robot, i, options)).collect(),
                }
            })
            .collect();
        let objects = scene
            .objects()
            .iter()
            .enumerate()
            .map(|(i, o)| MockObject {
                pose: o.pose,
                center_of_mass: o.center_of_mass,
                velocity: BodyVelocity::default(),
                attachment: scene.attachment_of(ObjectId(i)).map(|a| (a.robot, a.link, a.offset)),
            })
            .collect();
        Ok(Self { options: options.clone(), gravity: options.gravity, time: 0.0, robots, objects })
    }

    fn name(&self) -> &str {
        "mock"
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn step(&mut self, dt: f64) -> Result<()> {
        substeps(dt, self.options.timestep)?;
        for r in &mut self.robots {
            for i in 0..r.q.len() {
                let limits = r.robot.dof_limits(i);
                let next = advance_reference(r.q[i], r.targets[i], r.vmax[i], limits, dt);
                r.qd[i] = (next - r.q[i]) / dt;
                r.q[i] = next;
            }
        }
        for i in 0..self.objects.len() {
            let Some((robot, link, offset)) = self.objects[i].attachment else {
                self.objects[i].velocity = BodyVelocity::default();
                continue;
            };
            let pose = self.link_world_pose(robot, link) * offset;
            let o = &mut self.objects[i];
            let (c0, c1) = (o.pose * o.center_of_mass, pose * o.center_of_mass);
            o.velocity = BodyVelocity {
                linear: (c1 - c0) / dt,
                angular: (pose.rotation * o.pose.rotation.inverse()).scaled_axis() / dt,
            };
            o.pose = pose;
        }
        self.time += dt;
        Ok(())
    }

    fn snapshot(&self) -> Option<Self> {
        Some(self.clone())
    }

    fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<()> {
        check_vec("gravity", &gravity)?;
        self.gravity = gravity;
        Ok(())
    }

    fn set_joint_target(&mut self, robot: RobotId, dof: usize, target: JointTarget) -> Result<()> {
        let r = self.robot(robot)?;
        if dof >= r.q.len() {
            return Err(CoreError::InvalidHandle { kind: "dof", index: dof });
        }
        check_target(target)?;
        self.robots[robot.0].targets[dof] = target;
        Ok(())
    }

    fn set_joint_force_limit(&mut self, robot: RobotId, joint: crate::model::JointId, limit: f64) -> Result<()> {
        self.driven_joint(robot, joint)?;
        super::check_force_limit(limit)
    }

    fn set_joint_spring(
        &mut self,
        robot: RobotId,
        joint: crate::model::JointId,
        spring: Option<super::JointSpring>,
    ) -> Result<()> {
        self.driven_joint(robot, joint)?;
        spring.map_or(Ok(()), |s| s.validate())
    }

    fn joint_positions(&self, robot: RobotId) -> Result<Vec<f64>> {
        Ok(self.robot(robot)?.q.clone())
    }

    fn joint_velocities(&self, robot: RobotId) -> Result<Vec<f64>> {
        Ok(self.robot(robot)?.qd.clone())
    }

    fn link_pose(&self, robot: RobotId, link: LinkId) -> Result<Isometry3<f64>> {
        if link.0 >= self.robot(robot)?.robot.links().len() {
            return Err(CoreError::InvalidHandle { kind: "link", index: link.0 });
        }
        Ok(self.link_world_pose(robot, link))
    }

    fn object_pose(&self, object: ObjectId) -> Result<Isometry3<f64>> {
        Ok(self.object(object)?.pose)
    }

    fn object_velocity(&self, object: ObjectId) -> Result<BodyVelocity> {
        Ok(self.object(object)?.velocity)
    }

    fn set_object_pose(&mut self, object: ObjectId, pose: Isometry3<f64>) -> Result<()> {
        self.object(object)?;
        crate::error::ensure_finite_pose("object pose", &pose)?;
        let o = &mut self.objects[object.0];
        o.pose = pose;
        o.velocity = BodyVelocity::default();
        o.attachment = None;
        Ok(())
    }

    /// Validated; free objects of the mock stay put anyway.
    fn set_object_fixed(&mut self, object: ObjectId, fixed: bool) -> Result<()> {
        let _ = fixed;
        self.object(object).map(|_| ())
    }

    /// Validated, then ignored (the mock has no dynamics).
    fn set_object_damping(&mut self, object: ObjectId, linear: f64, angular: f64) -> Result<()> {
        self.object(object)?;
        super::check_damping(linear, angular)
    }

    /// Validated, then ignored (the mock has no dynamics).
    fn apply_object_impulse(&mut self, object: ObjectId, impulse: Vector3<f64>, point: Point3<f64>) -> Result<()> {
        self.object(object)?;
        check_vec("impulse", &impulse)?;
        check_vec("impulse point", &point.coords)
    }

    /// Validated, then ignored (the mock has no dynamics).
    fn set_object_force(&mut self, object: ObjectId, force: Vector3<f64>, torque: Vector3<f64>) -> Result<()> {
        self.object(object)?;
        check_vec("force", &force)?;
        check_vec("torque", &torque)
    }

    fn attach(&mut self, object: ObjectId, robot: RobotId, link: LinkId) -> Result<()> {
        let link_pose = self.link_pose(robot, link)?;
        let o = self.object(object)?;
        if o.attachment.is_some() {
            return Err(CoreError::InvalidParameter {
                name: "object".into(),
                reason: format!("object {} is already attached", object.0),
            });
        }
        let offset = link_pose.inverse() * o.pose;
        self.objects[object.0].attachment = Some((robot, link, offset));
        Ok(())
    }

    fn detach(&mut self, object: ObjectId) -> Result<()> {
        let o = self.object(object)?;
        if o.attachment.is_none() {
            return Err(CoreError::InvalidHandle { kind: "attachment", index: object.0 });
        }
        let o = &mut self.objects[object.0];
        o.attachment = None;
        o.velocity = BodyVelocity::default();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use nalgebra::Isometry3;

    use super::MockBackend;
    use crate::model::samples::planar_arm;
    use crate::physics::{velocity_limit, JointTarget, PhysicsEngine, PhysicsOptions};
    use crate::scene::Scene;

    /// Nothing resists an effort target on the kinematic backend: the joint moves at its
    /// velocity limit in the direction of the force; a zero force holds it.
    #[test]
    fn effort_targets_move_at_the_velocity_limit_towards_the_force() {
        let robot = Arc::new(planar_arm(&[0.5, 0.4]).unwrap());
        let mut scene = Scene::new("effort");
        let arm = scene.add_robot("arm", Arc::clone(&robot), Isometry3::identity()).unwrap();
        let options = PhysicsOptions::default();
        let mut engine = MockBackend::from_scene(&scene, &options).unwrap();
        engine.set_joint_target(arm, 0, JointTarget::Effort(-3.0)).unwrap();
        engine.set_joint_target(arm, 1, JointTarget::Effort(0.0)).unwrap();
        engine.step_n(10, 0.01).unwrap();
        let q = engine.joint_positions(arm).unwrap();
        let expected = -0.1 * velocity_limit(&robot, 0, &options);
        assert!((q[0] - expected).abs() < 1e-12, "{q:?}, expected {expected}");
        assert_eq!(q[1], 0.0);
    }
}
