//! Robots and hands: load, export/re-load through URDF, collision-free at home, hands close on
//! a 6 cm cylinder with every finger touching it.

use std::sync::Arc;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use opengrasp_assets::hands::{self, Hand};
use opengrasp_assets::robots;
use opengrasp_core::collision::{Collider, CollisionWorld};
use opengrasp_core::kinematics::link_pose;
use opengrasp_core::model::{Geometry, Robot, Shape};
use opengrasp_core::scene::{Scene, SceneObject};
use opengrasp_core::urdf;

fn all_hands() -> Vec<Hand> {
    vec![hands::barrett(), hands::armar3_hand(), hands::sdh()]
}

#[test]
fn dof_counts_and_groups() {
    let r = robots::armar3();
    assert_eq!(r.dof(), 34);
    assert_eq!(r.group("right_arm").unwrap().len(), 7);
    assert_eq!(r.group("hip_right_arm").unwrap().len(), 8);
    assert_eq!(r.group("base_hip_right_arm").unwrap().len(), 11);
    assert_eq!(r.group("right_hand").unwrap().len(), 8);
    let counts: Vec<usize> = all_hands().iter().map(|h| h.robot().dof()).collect();
    assert_eq!(counts, vec![4, 8, 7]);
    let fingers: Vec<usize> = all_hands().iter().map(|h| h.fingers().len()).collect();
    assert_eq!(fingers, vec![3, 5, 3]);
}

#[test]
fn link_masses_are_physical() {
    let r = robots::armar3();
    let mut hands_robots: Vec<Robot> = all_hands().iter().map(|h| h.robot().clone()).collect();
    hands_robots.push(r);
    for robot in &hands_robots {
        for l in robot.links() {
            if let Some(i) = &l.inertial {
                assert!(i.is_physical(), "{} / {}", robot.name(), l.name);
            }
        }
    }
}

#[test]
fn total_masses_match_the_documented_values() {
    let total = |r: &Robot| r.links().iter().filter_map(|l| l.inertial.as_ref()).map(|i| i.mass).sum::<f64>();
    let masses: Vec<f64> = all_hands().iter().map(|h| total(h.robot())).collect();
    for (m, expect) in masses.iter().zip([1.18, 0.25, 1.95]) {
        assert!((m - expect).abs() < 1e-9, "{m} vs {expect}");
    }
}

#[test]
fn arm_link_lengths_match_the_documented_values() {
    let r = robots::armar3();
    let q = r.home_configuration();
    let p = |n: &str| link_pose(&r, &q, r.link_id(n).unwrap()).unwrap().translation.vector;
    let upper = (p("right_forearm") - p("right_upper_arm")).norm();
    let fore = (p("right_wrist_link1") - p("right_forearm")).norm();
    assert!((upper - 0.311).abs() < 1e-9 && (fore - 0.276).abs() < 1e-9);
    assert!((p("right_shoulder_link").z - 1.30).abs() < 1e-9);
    // Mirror symmetry of the two arms at home.
    let (rw, lw) = (p("right_wrist_link1"), p("left_wrist_link1"));
    assert!((rw.x - lw.x).abs() < 1e-12 && (rw.y + lw.y).abs() < 1e-12 && (rw.z - lw.z).abs() < 1e-12);
}

#[test]
fn coupled_joints_follow_their_leaders() {
    let b = hands::barrett();
    assert_eq!(b.coupling("f2_spread").unwrap(), Some((0, 1.0)));
    let (dof, ratio) = b.coupling("f1_j3").unwrap().unwrap();
    assert_eq!(b.robot().dof_joint(dof), b.robot().joint_id("f1_j2").unwrap());
    assert!((ratio - 48.0 / 140.0).abs() < 1e-12);
    let a = hands::armar3_hand();
    let ring = a.robot().dof_index("ring_j1").unwrap();
    assert_eq!(a.coupling("pinky_j3").unwrap(), Some((ring, 1.0)));
    let s = hands::sdh();
    let (_, m) = s.coupling("f3_rotation").unwrap().unwrap();
    assert_eq!(m, 1.0);
}

fn roundtrip(robot: &Robot) {
    let doc = urdf::to_urdf_string(robot, &urdf::ExportOptions::default());
    let again = urdf::from_str(&doc.urdf, &doc.resolver()).unwrap();
    assert_eq!(again.joints().len(), robot.joints().len());
    for (a, b) in again.joints().iter().zip(robot.joints()) {
        assert_eq!((&a.name, a.kind, a.parent, a.child, a.dof), (&b.name, b.kind, b.parent, b.child, b.dof));
        assert!((a.origin.to_homogeneous() - b.origin.to_homogeneous()).norm() < 1e-12, "{}", a.name);
        assert!((a.axis.into_inner() - b.axis.into_inner()).norm() < 1e-12, "{}", a.name);
        assert_eq!(a.limits, b.limits, "{}", a.name);
        assert_eq!(a.mimic, b.mimic, "{}", a.name);
    }
    assert_eq!(again.links().len(), robot.links().len());
    for (a, b) in again.links().iter().zip(robot.links()) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.collisions.len(), b.collisions.len(), "{}", a.name);
        for (x, y) in a.collisions.iter().zip(&b.collisions) {
            assert_eq!(x.geometry, y.geometry, "{}", a.name);
            assert!((x.origin.to_homogeneous() - y.origin.to_homogeneous()).norm() < 1e-12, "{}", a.name);
        }
        match (&a.inertial, &b.inertial) {
            (Some(x), Some(y)) => {
                assert!((x.mass - y.mass).abs() < 1e-12);
                assert!((x.inertia - y.inertia).norm() < 1e-12);
            }
            (None, None) => {}
            _ => panic!("inertial of {} lost", a.name),
        }
    }
}

#[test]
fn robots_and_hands_roundtrip_through_urdf() {
    roundtrip(&robots::armar3());
    for h in all_hands() {
        roundtrip(h.robot());
    }
}

fn alone(robot: Arc<Robot>) -> (Scene, opengrasp_core::scene::RobotId) {
    let mut scene = Scene::new("alone");
    let id = scene.add_robot("r", robot, Isometry3::identity()).unwrap();
    (scene, id)
}

#[test]
fn home_configurations_are_self_collision_free() {
    let r = Arc::new(robots::armar3());
    let (scene, id) = alone(r.clone());
    let world = CollisionWorld::new(&scene).unwrap();
    let q = r.home_configuration();
    let bad: Vec<_> = world
        .contacts(id, &q, 0.0)
        .unwrap()
        .into_iter()
        .map(|c| (r.link(c.link).name.clone(), format!("{:?}", c.other), c.depth))
        .collect();
    assert!(bad.is_empty(), "{bad:?}");
    assert!(!world.in_collision(id, &q).unwrap());
    for h in all_hands() {
        let (scene, id) = alone(h.robot_arc());
        let world = CollisionWorld::new(&scene).unwrap();
        for p in h.preshapes() {
            let q = h.preshape_configuration(&p.name, &h.robot().home_configuration()).unwrap();
            assert!(!world.in_collision(id, &q).unwrap(), "{} {}", h.name(), p.name);
        }
    }
}

/// Places the hand so that a 6 cm cylinder (axis along the palm's y axis) lies just in front
/// of the palm, closes every finger stepwise until one of its links touches the cylinder, and
/// returns the number of fingers in contact.
fn close_on_cylinder(hand: &Hand, preshape: &str, standoff: f64) -> (usize, Vec<f64>) {
    let radius = 0.03;
    let palm_world = hand.palm_frame();
    let approach = hand.approach().into_inner();
    let centre = palm_world * nalgebra::Point3::from(approach * (radius + standoff));
    // Cylinder axis (URDF z) along the palm's y axis.
    let rot = UnitQuaternion::rotation_between(&Vector3::z(), &(palm_world.rotation * Vector3::y())).unwrap();
    let pose = Isometry3::from_parts(Translation3::from(centre.coords), rot);
    let mut scene = Scene::new("grasp");
    let id = scene.add_robot("hand", hand.robot_arc(), Isometry3::identity()).unwrap();
    let cyl = Shape::at_origin(Geometry::Cylinder { radius, length: 0.3 });
    let obj = scene.add_object(SceneObject::new("cylinder", pose, vec![cyl], 0.3)).unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    let mut q = hand.preshape_configuration(preshape, &hand.robot().home_configuration()).unwrap();
    assert!(world.contacts_with_object(id, &q, obj, 0.0).unwrap().is_empty(), "{} starts in contact", hand.name());
    let n = hand.fingers().len();
    let mut active = vec![true; n];
    let step = 0.01;
    for _ in 0..400 {
        let contacts = world.contacts_with_object(id, &q, obj, 0.001).unwrap();
        for (f, finger) in hand.fingers().iter().enumerate() {
            if contacts.iter().any(|c| finger.links.contains(&c.link) && c.other == Collider::Object(obj)) {
                active[f] = false;
            }
        }
        if active.iter().all(|a| !a) {
            break;
        }
        let next = hand.close_step(&q, step, &active).unwrap();
        if next == q {
            break; // every still-active finger is at its joint limit
        }
        q = next;
    }
    let deepest = world.contacts_with_object(id, &q, obj, 0.0).unwrap().iter().map(|c| c.depth).fold(0.0, f64::max);
    assert!(deepest < 0.003, "{} penetrates the cylinder by {deepest} m", hand.name());
    (active.iter().filter(|a| !**a).count(), q)
}

#[test]
fn every_finger_touches_a_6cm_cylinder() {
    // Stand-off of the cylinder from the palm surface: clear of the knuckles.
    for (h, preshape, standoff) in
        [(hands::barrett(), "open", 0.02), (hands::armar3_hand(), "open", 0.004), (hands::sdh(), "open", 0.05)]
    {
        let (touching, q) = close_on_cylinder(&h, preshape, standoff);
        assert_eq!(touching, h.fingers().len(), "{}: only {touching} fingers touch at q = {q:?}", h.name());
    }
}

#[test]
fn mounted_right_hand_matches_the_floating_hand() {
    let r = Arc::new(robots::armar3());
    let mounted = robots::armar3_right_hand(r.clone()).unwrap();
    let floating = hands::armar3_hand();
    assert_eq!(mounted.fingers().len(), floating.fingers().len());
    let dofs: Vec<usize> = mounted.fingers().iter().map(|f| f.closing_dofs.len()).collect();
    let dofs_f: Vec<usize> = floating.fingers().iter().map(|f| f.closing_dofs.len()).collect();
    assert_eq!(dofs, dofs_f);
    // Closing the mounted hand moves only hand joints.
    let q = r.home_configuration();
    let closed = mounted.close_step(&q, 0.1, &[true; 5]).unwrap();
    let arm = r.group("base_hip_right_arm").unwrap();
    assert_eq!(arm.extract(&closed), arm.extract(&q));
    assert!(closed != q);
}

#[test]
fn bad_hand_specs_and_inputs_are_errors() {
    let robot = hands::barrett().robot().clone();
    let mut spec = hands::barrett_spec("");
    spec.palm_link = "nope".into();
    assert!(Hand::from_robot(robot.clone(), spec).is_err());
    let mut spec = hands::barrett_spec("");
    spec.approach = Vector3::zeros();
    assert!(matches!(Hand::from_robot(robot.clone(), spec), Err(opengrasp_core::CoreError::InvalidParameter { .. })));
    let mut spec = hands::barrett_spec("");
    spec.closing.push(("f1_j3".into(), 1.0)); // a mimic joint is not actuated
    assert!(Hand::from_robot(robot.clone(), spec).is_err());
    let h = hands::barrett();
    assert!(matches!(
        h.preshape_configuration("fist", &h.open_configuration()),
        Err(opengrasp_core::CoreError::UnknownPreshape { .. })
    ));
    assert!(h.preshape_configuration("open", &[0.0; 2]).is_err());
    assert!(h.close_step(&h.open_configuration(), 0.1, &[true]).is_err());
    // Closing moves only the finger flexion dofs, by step x velocity, and stops at the limits.
    let q0 = h.open_configuration();
    let q1 = h.close_step(&q0, 0.1, &[true, false, true]).unwrap();
    let f1 = h.robot().dof_index("f1_j2").unwrap();
    let f2 = h.robot().dof_index("f2_j2").unwrap();
    assert!((q1[f1] - 0.1).abs() < 1e-12 && q1[f2] == 0.0 && q1[0] == q0[0]);
    let shut = h.close_step(&q0, 100.0, &[true; 3]).unwrap();
    assert!((shut[f1] - 140f64.to_radians()).abs() < 1e-3);
}
