//! Kitchen and table-top scenes: contents, named locations, collision-free start pose.

use opengrasp_assets::{objects, scenes};
use opengrasp_core::collision::CollisionWorld;

#[test]
fn kitchen_contains_furniture_objects_and_the_humanoid() {
    let k = scenes::kitchen().unwrap();
    for body in
        ["floor", "wall_back", "counter_left", "sink", "fridge", "red_table", "green_sideboard", "wall_cabinets"]
    {
        assert!(k.scene.body_id(body).is_some(), "missing {body}");
    }
    assert_eq!(k.scene.objects().len(), 9);
    for name in objects::NAMES {
        let id = k.scene.object_id(name).unwrap();
        let loc = k.location(name).unwrap();
        assert_eq!(k.scene.object(id).unwrap().pose, loc);
    }
    assert!(k.location("nowhere").is_err());
    let r = k.scene.robot(k.robot).unwrap();
    assert_eq!(r.q, k.start_configuration);
    let start = k.location("robot_start").unwrap();
    assert!((r.q[0] - start.translation.x).abs() < 1e-12 && (r.q[1] - start.translation.y).abs() < 1e-12);
}

#[test]
fn objects_rest_on_their_surfaces() {
    let k = scenes::kitchen().unwrap();
    let table = k.location("red_table_centre").unwrap().translation.z;
    assert!((table - 0.75).abs() < 1e-12);
    for name in ["white_cup", "green_cup", "salt_can", "measuring_cup"] {
        assert!((k.location(name).unwrap().translation.z - table).abs() < 1e-12);
    }
    let counter = k.location("counter_left").unwrap().translation.z;
    assert!((counter - 0.90).abs() < 1e-12);
}

#[test]
fn humanoid_start_pose_in_the_kitchen_is_collision_free() {
    let k = scenes::kitchen().unwrap();
    let world = CollisionWorld::new(&k.scene).unwrap();
    assert!(!world.in_collision(k.robot, &k.start_configuration).unwrap());
    let report = world.distance(k.robot, &k.start_configuration).unwrap();
    assert!(report.distance > 0.005, "clearance {} m", report.distance);
    // Sanity: driving the base into the red table is a collision.
    let mut q = k.start_configuration.clone();
    q[1] += 0.6;
    assert!(world.in_collision(k.robot, &q).unwrap());
}

#[test]
fn table_top_scene_holds_one_object_on_the_table() {
    let salt = objects::by_name("salt_can").unwrap();
    let scene = scenes::table_top(&salt).unwrap();
    assert_eq!(scene.bodies().len(), 1);
    assert_eq!(scene.objects().len(), 1);
    assert!((scene.objects()[0].pose.translation.z - 0.75).abs() < 1e-12);
    assert_eq!(scene.objects()[0].mass, salt.mass());
}

#[test]
fn kitchen_is_deterministic() {
    let (a, b) = (scenes::kitchen().unwrap(), scenes::kitchen().unwrap());
    assert_eq!(a.scene.bodies(), b.scene.bodies());
    assert_eq!(a.scene.objects(), b.scene.objects());
    assert_eq!(a.locations, b.locations);
}

/// The standard motion setup is feasible: from its start pose, the humanoid's `hip_right_arm`
/// group reaches a side grasp of the salt can on the red table (palm facing the can, fingers
/// forward, thumb up), and that configuration is collision-free in the kitchen.
#[test]
fn right_hand_reaches_the_salt_can_from_the_start_pose() {
    use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
    use opengrasp_core::kinematics::{solve_ik, IkOptions, IkStatus};

    let k = scenes::kitchen().unwrap();
    let r = k.scene.robot(k.robot).unwrap().robot.clone();
    let hand = opengrasp_assets::robots::armar3_right_hand(r.clone()).unwrap();
    let can = k.location("salt_can").unwrap().translation.vector;
    // Palm frame: x (approach) = -x world, z (fingers) = +y world, y (thumb side) = +z world.
    let rot = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[-Vector3::x(), Vector3::z(), Vector3::y()]));
    let target = Isometry3::from_parts(
        Translation3::from(can + Vector3::new(0.04 + 0.005, 0.0, 0.07)),
        UnitQuaternion::from_rotation_matrix(&rot),
    );
    let options = IkOptions {
        tip_offset: hand.palm_frame(),
        position_tolerance: 1e-4,
        orientation_tolerance: 1e-3,
        ..IkOptions::default()
    };
    let group = r.group("hip_right_arm").unwrap();
    let sol = solve_ik(&r, group, hand.palm(), &target, &k.start_configuration, &options).unwrap();
    assert_eq!(sol.status, IkStatus::Converged, "position error {} m", sol.position_error);
    let world = CollisionWorld::new(&k.scene).unwrap();
    assert!(!world.in_collision(k.robot, &sol.q).unwrap());
}

#[test]
fn a_user_robot_can_replace_the_humanoid() {
    let arm = std::sync::Arc::new(opengrasp_core::model::samples::seven_dof_arm().unwrap());
    let stock = scenes::kitchen().unwrap();
    let start = stock.location("robot_start").unwrap();
    let q = arm.home_configuration();
    let k = scenes::kitchen_with_robot(arm.clone(), start, &q).unwrap();
    assert_eq!(k.scene.robots().len(), 1);
    assert_eq!(k.scene.robot(k.robot).unwrap().base_pose, start);
    assert_eq!(k.scene.objects().len(), 9);
    assert!(scenes::kitchen_with_robot(arm, start, &[0.0; 3]).is_err());
}
