//! The physics check settles a grasp once and continues every gravity direction from a snapshot
//! of the settled state: its outcome must be bitwise the one of settling afresh per direction
//! (what a backend without snapshots gets).

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use opengrasp_assets::hands;
use opengrasp_core::hand::Hand;
use opengrasp_core::model::{JointId, LinkId};
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::{
    BodyVelocity, JointSpring, JointTarget, MockBackend, PhysicsContact, PhysicsEngine, PhysicsOptions, RapierBackend,
};
use opengrasp_core::scene::{ObjectId, RobotId, Scene};
use opengrasp_core::Result;
use opengrasp_grasp::evaluator::{
    hand_info, physics_check_with, EvaluatorOptions, GraspEvaluation, GraspEvaluator, HoldResult, PhysicsCheckOptions,
    ReleaseWindow,
};
use opengrasp_grasp::planners::{palm_pose, GraspCandidate, Preshape};

mod common;
use common::cylinder_mesh;

/// Backend `E` without snapshots: the physics check settles afresh for every direction.
struct Fresh<E>(E);

impl<E: PhysicsEngine> PhysicsEngine for Fresh<E> {
    fn from_scene(scene: &Scene, options: &PhysicsOptions) -> Result<Self> {
        E::from_scene(scene, options).map(Self)
    }
    fn time(&self) -> f64 {
        self.0.time()
    }
    fn step(&mut self, dt: f64) -> Result<()> {
        self.0.step(dt)
    }
    fn gravity(&self) -> Vector3<f64> {
        self.0.gravity()
    }
    fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<()> {
        self.0.set_gravity(gravity)
    }
    fn set_joint_target(&mut self, robot: RobotId, dof: usize, target: JointTarget) -> Result<()> {
        self.0.set_joint_target(robot, dof, target)
    }
    fn set_joint_force_limit(&mut self, robot: RobotId, joint: JointId, limit: f64) -> Result<()> {
        self.0.set_joint_force_limit(robot, joint, limit)
    }
    fn set_joint_spring(&mut self, robot: RobotId, joint: JointId, spring: Option<JointSpring>) -> Result<()> {
        self.0.set_joint_spring(robot, joint, spring)
    }
    fn joint_positions(&self, robot: RobotId) -> Result<Vec<f64>> {
        self.0.joint_positions(robot)
    }
    fn joint_velocities(&self, robot: RobotId) -> Result<Vec<f64>> {
        self.0.joint_velocities(robot)
    }
    fn link_pose(&self, robot: RobotId, link: LinkId) -> Result<Isometry3<f64>> {
        self.0.link_pose(robot, link)
    }
    fn object_pose(&self, object: ObjectId) -> Result<Isometry3<f64>> {
        self.0.object_pose(object)
    }
    fn object_velocity(&self, object: ObjectId) -> Result<BodyVelocity> {
        self.0.object_velocity(object)
    }
    fn set_object_pose(&mut self, object: ObjectId, pose: Isometry3<f64>) -> Result<()> {
        self.0.set_object_pose(object, pose)
    }
    fn set_object_fixed(&mut self, object: ObjectId, fixed: bool) -> Result<()> {
        self.0.set_object_fixed(object, fixed)
    }
    fn set_contact_frequency(&mut self, hz: f64) -> Result<()> {
        self.0.set_contact_frequency(hz)
    }
    fn apply_object_impulse(&mut self, object: ObjectId, impulse: Vector3<f64>, point: Point3<f64>) -> Result<()> {
        self.0.apply_object_impulse(object, impulse, point)
    }
    fn set_object_force(&mut self, object: ObjectId, force: Vector3<f64>, torque: Vector3<f64>) -> Result<()> {
        self.0.set_object_force(object, force, torque)
    }
    fn contacts(&self) -> Vec<PhysicsContact> {
        self.0.contacts()
    }
}

/// A 20 cm, 0.1 kg cylinder of radius `radius` (m) with μ = 0.8.
fn cylinder(radius: f64) -> ObjectModel {
    ObjectModel::from_mesh("can", cylinder_mesh(radius, 0.2, 32), 0.1, 0.8).unwrap()
}

/// The hand on the +x side approaching along -x, its closing plane normal to `up`.
fn side_grasp(hand: &Hand, object: &ObjectModel, up: Vector3<f64>) -> GraspEvaluation {
    let info = hand_info(hand).unwrap();
    let approach = Unit::new_normalize(-Vector3::x());
    let candidate = GraspCandidate {
        hand_pose: palm_pose(&info, &Point3::origin(), &approach, &up),
        preshape: Preshape::Default,
        approach,
        standoff: 0.0,
    };
    GraspEvaluator::new(hand, object, EvaluatorOptions::default()).unwrap().evaluate(&candidate).unwrap()
}

/// The snapshot path and the fresh path agree bitwise, and repeating the check does too.
fn assert_same_outcome(hand: &Hand, object: &ObjectModel, grasp: &GraspEvaluation) -> Vec<HoldResult> {
    let options = PhysicsCheckOptions::default();
    let snapshot = physics_check_with::<RapierBackend>(hand, object, grasp, &options).unwrap();
    let fresh = physics_check_with::<Fresh<RapierBackend>>(hand, object, grasp, &options).unwrap();
    assert_eq!(snapshot, fresh, "snapshot continuation differs from settling afresh");
    assert_eq!(snapshot, physics_check_with::<RapierBackend>(hand, object, grasp, &options).unwrap());
    assert_eq!(snapshot.translations.len(), 6);
    snapshot.results
}

#[test]
fn wraps_hold_identically_from_a_snapshot() {
    // The ARMAR-III hand's wrap of a 6 cm cylinder and the Barrett's of a 4 cm one hold in all
    // six directions.
    for (hand, radius) in [(hands::armar3_hand(), 0.03), (hands::barrett(), 0.02)] {
        let object = cylinder(radius);
        let results = assert_same_outcome(&hand, &object, &side_grasp(&hand, &object, Vector3::y()));
        assert_eq!(results, vec![HoldResult::Held; 6], "{}", hand.name());
    }
}

#[test]
fn armar3_pinch_drops_identically_from_a_snapshot() {
    // Turned 90° the fingertips only pinch the cylinder's sides: it falls out in some
    // direction, after diverging from the control run by decimetres.
    let (hand, object) = (hands::armar3_hand(), cylinder(0.03));
    let results = assert_same_outcome(&hand, &object, &side_grasp(&hand, &object, Vector3::z()));
    assert!(results.contains(&HoldResult::Dropped), "{results:?}");
}

#[test]
fn armar3_pinch_drops_alike_with_and_without_the_early_stop() {
    // The early stop of a certainly dropped object (`early_drop`) gives the full run's verdict
    // in every direction; a run that ends with the object in the hand is the same either way.
    let (hand, object) = (hands::armar3_hand(), cylinder(0.03));
    let grasp = side_grasp(&hand, &object, Vector3::z());
    let check = |early_drop: bool| {
        let options = PhysicsCheckOptions { early_drop, ..PhysicsCheckOptions::default() };
        physics_check_with::<RapierBackend>(&hand, &object, &grasp, &options).unwrap()
    };
    let (early, full) = (check(true), check(false));
    assert_eq!(early.results, full.results);
    assert!(full.results.contains(&HoldResult::Dropped), "{full:?}");
    for (i, result) in full.results.iter().enumerate() {
        match result {
            HoldResult::Dropped => assert!(early.translations[i] > 0.1, "{early:?}"),
            _ => assert_eq!(early.translations[i], full.translations[i]),
        }
    }
}

#[test]
fn mock_check_is_the_same_with_and_without_snapshots() {
    // The mock has no dynamics: nothing moves the object, every direction holds with zero
    // displacement whichever path the check takes.
    let (hand, object) = (hands::barrett(), cylinder(0.02));
    let grasp = side_grasp(&hand, &object, Vector3::y());
    let options = PhysicsCheckOptions::default();
    let snapshot = physics_check_with::<MockBackend>(&hand, &object, &grasp, &options).unwrap();
    let fresh = physics_check_with::<Fresh<MockBackend>>(&hand, &object, &grasp, &options).unwrap();
    assert_eq!(snapshot, fresh);
    assert_eq!(snapshot.translations, vec![0.0; 6]);
    assert!(snapshot.held());
}

#[test]
fn balanced_grip_with_springs_is_the_same_from_a_snapshot() {
    // The balanced grip re-solved after the squeeze and turned into joint springs: motor caps
    // and springs set during the settle must be copied by the snapshot.
    let (hand, object) = (hands::barrett(), cylinder(0.02));
    let grasp = side_grasp(&hand, &object, Vector3::y());
    let options = PhysicsCheckOptions {
        balanced: Some(1.0),
        grip_compliance: Some(0.05),
        resolve_grip: true,
        ..PhysicsCheckOptions::default()
    };
    let snapshot = physics_check_with::<RapierBackend>(&hand, &object, &grasp, &options).unwrap();
    let fresh = physics_check_with::<Fresh<RapierBackend>>(&hand, &object, &grasp, &options).unwrap();
    assert_eq!(snapshot, fresh);
    assert_eq!(snapshot.translations.len(), 6);
    assert!(snapshot.translations.iter().all(|t| t.is_finite() && *t > 0.0), "{snapshot:?}");
}

#[test]
fn a_fine_release_window_is_deterministic_and_changes_the_trajectory() {
    // The Barrett wrap of a 4 cm cylinder with its release simulated in 1 ms steps at 120 Hz
    // contacts: the same outcome twice and from fresh settles, still held in all six
    // directions, and not the trajectory of the check without the window.
    let (hand, object) = (hands::barrett(), cylinder(0.02));
    let grasp = side_grasp(&hand, &object, Vector3::y());
    let window = ReleaseWindow { timestep: 1e-3, contact_frequency: 120.0, before: 0.02, after: 0.03 };
    let options = PhysicsCheckOptions { release_window: Some(window), ..PhysicsCheckOptions::default() };
    let first = physics_check_with::<RapierBackend>(&hand, &object, &grasp, &options).unwrap();
    assert_eq!(first, physics_check_with::<RapierBackend>(&hand, &object, &grasp, &options).unwrap());
    assert_eq!(first, physics_check_with::<Fresh<RapierBackend>>(&hand, &object, &grasp, &options).unwrap());
    assert_eq!(first.results, vec![HoldResult::Held; 6], "{first:?}");
    let plain = physics_check_with::<RapierBackend>(&hand, &object, &grasp, &PhysicsCheckOptions::default()).unwrap();
    assert_ne!(first.grip_translation, plain.grip_translation);
    // A backend without soft contacts cannot run the window: a typed error, not a silent no-op.
    assert!(matches!(
        physics_check_with::<MockBackend>(&hand, &object, &grasp, &options),
        Err(opengrasp_grasp::GraspError::Core(opengrasp_core::error::CoreError::Physics { .. }))
    ));
}
