//! The analytic two-finger pinch of the physics calibration tests: a parallel gripper (two
//! prismatic pads pressing with their effort limit) closed on a box or a wedge.

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::hand::{FingerSpec, Hand, HandSpec};
use opengrasp_core::model::{Geometry, Inertial, JointKind, JointSpec, Link, RobotBuilder, Shape, TriangleMesh};
use opengrasp_core::object::ObjectModel;
use opengrasp_grasp::evaluator::{
    physics_check, EvaluationStatus, GraspEvaluation, PhysicsCheckOptions, PhysicsOutcome,
};

/// Pad force (N): the prismatic joints' effort limit.
pub const PAD_FORCE: f64 = 10.0;
/// Half-width (m) of the object at its mid-height, where the pads touch it.
pub const HALF_WIDTH: f64 = 0.025;
/// Height (m) of the object along the approach; the palm surface is 5 mm below it.
pub const HEIGHT: f64 = 0.04;
/// Pad thickness (m).
pub const PAD: f64 = 0.01;

/// A two-pad parallel gripper whose pads are tilted by `alpha` (rad) to lie flat on a wedge
/// of that half-angle, touching it at mid-height in the closed configuration `q = [0, 0]`
/// (palm frame = object frame shifted down by `HEIGHT / 2 + 5 mm`).
pub fn gripper(alpha: f64) -> Hand {
    let mid = HEIGHT / 2.0 + 0.005;
    let pad_size = Vector3::new(0.06, PAD, 0.05);
    let mut b = palm();
    for (name, side) in [("left", 1.0), ("right", -1.0)] {
        // The pad's inner face lies on the object face through (y, z) = (side·HALF_WIDTH, mid),
        // whose outward normal is (side·cos α, -sin α).
        let (s, c) = alpha.sin_cos();
        let centre = Vector3::new(0.0, side * (HALF_WIDTH + PAD / 2.0 * c), mid - PAD / 2.0 * s);
        let origin = Isometry3::new(centre, Vector3::x() * (-side * alpha));
        b = b
            .link(
                Link::new(name)
                    .with_shape(Shape::new(origin, Geometry::cuboid(pad_size.x, pad_size.y, pad_size.z)))
                    .with_inertial(Inertial::solid_box(0.05, pad_size, origin)),
            )
            .joint(
                JointSpec::new(format!("{name}_slide"), JointKind::Prismatic, "palm", name)
                    .axis(Vector3::y() * -side)
                    .limits(-0.02, 0.05, 0.1, PAD_FORCE),
            );
    }
    two_finger_hand(b, "slide")
}

/// The palm of both grippers: a 6 × 14 × 1 cm plate under the palm frame.
pub fn palm() -> RobotBuilder {
    RobotBuilder::new("two_finger_gripper").link(
        Link::new("palm")
            .with_shape(Shape::new(Isometry3::translation(0.0, 0.0, -0.005), Geometry::cuboid(0.06, 0.14, 0.01)))
            .with_inertial(Inertial::solid_box(0.3, Vector3::new(0.06, 0.14, 0.01), Isometry3::identity())),
    )
}

/// A hand from a gripper with fingers `left` and `right` closed by joints `left_{joint}` and
/// `right_{joint}`, palm normal +z.
pub fn two_finger_hand(b: RobotBuilder, joint: &str) -> Hand {
    let spec = HandSpec {
        urdf: None,
        palm_link: "palm".into(),
        palm_frame: Isometry3::identity(),
        approach: Vector3::z(),
        preshapes: Vec::new(),
        fingers: ["left", "right"]
            .iter()
            .map(|f| FingerSpec { name: f.to_string(), links: vec![f.to_string()] })
            .collect(),
        closing: vec![(format!("left_{joint}"), 1.0), (format!("right_{joint}"), 1.0)],
        tactile_links: Vec::new(),
        actuation: Default::default(),
    };
    Hand::from_robot(b.build().unwrap(), spec).unwrap()
}

/// A prism along x (10 cm) whose half-width grows from `HALF_WIDTH - tan α · HEIGHT / 2` at
/// the palm side to `HALF_WIDTH + tan α · HEIGHT / 2` at the far side.
pub fn wedge(alpha: f64, mass: f64, friction: f64) -> ObjectModel {
    let cube = TriangleMesh::cuboid(Vector3::new(0.1, 2.0 * HALF_WIDTH, HEIGHT)).unwrap();
    let vertices: Vec<Point3<f64>> = cube
        .vertices()
        .iter()
        .map(|v| Point3::new(v.x, v.y * (HALF_WIDTH + v.z * alpha.tan()) / HALF_WIDTH, v.z))
        .collect();
    let mesh = TriangleMesh::new(vertices, cube.triangles().to_vec()).unwrap();
    ObjectModel::from_mesh("wedge", mesh, mass, friction).unwrap()
}

/// The closed pinch: pads touching, palm 5 mm below the object.
pub fn pinch(hand: &Hand) -> GraspEvaluation {
    GraspEvaluation {
        status: EvaluationStatus::Closed,
        hand_pose: Isometry3::translation(0.0, 0.0, -HEIGHT / 2.0 - 0.005),
        q: vec![0.0; hand.robot().dof()],
        contacts: Vec::new(),
        palm_contact: false,
        fingers_in_contact: 2,
        retraction: 0.0,
        quality: None,
        friction_score: None,
        robust_epsilon: None,
    }
}

pub fn check(alpha: f64, mass: f64, friction: f64, options: &PhysicsCheckOptions) -> PhysicsOutcome {
    let hand = gripper(alpha);
    physics_check(&hand, &wedge(alpha, mass, friction), &pinch(&hand), options).unwrap()
}
