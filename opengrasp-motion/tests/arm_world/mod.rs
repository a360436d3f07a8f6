//! The sample arm among every closed-form obstacle shape, shared by the motion-check tests.

use std::sync::Arc;

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use opengrasp_core::model::{samples, JointGroup, Robot};
use opengrasp_motion::validity::{MeshCover, ObstacleBox, ObstaclePrimitive, ObstacleShape, SphereWorld};

/// The 7-DoF sample arm among a box, a ball, a cylinder and a capsule (tilted), on its plain
/// sphere cover and with a coarse layer (the meshes' bounding boxes) tried first.
pub fn arm_among_shapes() -> (Arc<Robot>, JointGroup, SphereWorld, SphereWorld) {
    let robot = Arc::new(samples::seven_dof_arm().unwrap());
    let group = robot.group("arm").unwrap().clone();
    let tilt = UnitQuaternion::from_euler_angles(0.3, -0.4, 0.7);
    let at = |x: f64, y: f64, z: f64| Isometry3::from_parts(Vector3::new(x, y, z).into(), tilt);
    let boxes = vec![ObstacleBox::new("box", at(0.5, 0.0, 0.4), Vector3::new(0.2, 0.5, 0.1))];
    let others = [
        ObstaclePrimitive::new("ball", at(0.0, 0.5, 0.6), ObstacleShape::Sphere { radius: 0.15 }),
        ObstaclePrimitive::new("can", at(-0.4, 0.0, 0.5), ObstacleShape::Cylinder { radius: 0.1, half_length: 0.3 }),
        ObstaclePrimitive::new("pill", at(0.0, -0.5, 0.8), ObstacleShape::Capsule { radius: 0.08, half_length: 0.2 }),
    ];
    let world =
        SphereWorld::new(robot.clone(), group.clone(), robot.home_configuration(), Isometry3::identity(), boxes)
            .unwrap()
            .with_obstacles(others)
            .unwrap();
    let layered = world.clone().with_coarse_cover(MeshCover::default()).unwrap();
    (robot, group, world, layered)
}
