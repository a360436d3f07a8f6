//! Tests of the balanced grip torques (`grip_torques`) and the physics check's balanced mode.

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use opengrasp_assets::hands;
use opengrasp_core::kinematics::{forward_kinematics, jacobian};
use opengrasp_core::model::{JointId, LinkId};
use opengrasp_grasp::evaluator::{
    grip_torques, physics_check, EvaluatorOptions, GraspEvaluation, GraspEvaluator, HoldResult, PhysicsCheckOptions,
};
use opengrasp_grasp::planners::{palm_pose, GraspCandidate, Preshape};
use opengrasp_grasp::GraspError;

/// The Barrett wrap of the salt can of the evaluator tests: palm on the can's side at mid-height.
fn barrett_salt_can_wrap() -> (opengrasp_core::hand::Hand, opengrasp_assets::objects::ObjectModel, GraspEvaluation) {
    let hand = hands::barrett();
    let object = opengrasp_assets::objects::by_name("salt_can").unwrap();
    let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).unwrap();
    let info = ev.hand_info().clone();
    let approach = Unit::new_normalize(-Vector3::x());
    let mut hand_pose = palm_pose(&info, &Point3::origin(), &approach, &Vector3::y());
    hand_pose.translation.vector.z = 0.07;
    let e = ev.evaluate(&GraspCandidate { hand_pose, preshape: Preshape::Default, approach, standoff: 0.0 }).unwrap();
    assert!(e.palm_contact && e.force_closure(), "{:?}", e.quality);
    (hand, object, e)
}

#[test]
fn grip_torques_are_a_static_equilibrium_of_the_barrett_salt_can_wrap() {
    let (hand, object, e) = barrett_salt_can_wrap();
    let (margin, fraction) = (0.5, 1.0);
    let grip = grip_torques(&hand, &object, &e, fraction, margin, true).unwrap();
    assert_eq!(grip.contact_forces.len(), e.contacts.len());
    // Every finger contact squeezes; the three fingers press with tens of newtons.
    assert!(grip.min_normal > 1.0, "{grip:?}");
    // Zero net force and moment on the object (object frame, about its centre of mass).
    let com = object.center_of_mass();
    let scale = grip.contact_forces.iter().map(|f| f.norm()).sum::<f64>();
    let net: Vector3<f64> = grip.contact_forces.iter().sum();
    let moment: Vector3<f64> =
        e.contacts.iter().zip(&grip.contact_forces).map(|(c, f)| (c.contact.point - com).cross(f)).sum();
    assert!(net.norm() < 1e-6 * scale, "net force {net:?} of {scale} N");
    assert!(moment.norm() < 1e-6 * scale, "net moment {moment:?}");
    // Inside the friction cones shrunk by the margin.
    let mu = object.friction * margin;
    for (c, f) in e.contacts.iter().zip(&grip.contact_forces) {
        let n = f.dot(&c.contact.normal);
        let t = (f - c.contact.normal.into_inner() * n).norm();
        assert!(n >= -1e-6 && t <= mu * n + 1e-6 * scale, "normal {n}, tangential {t}");
    }
    // Joint torques within their caps, and per actuator equal to Jᵀ f of the core Jacobian
    // (coupled joints summed by their mimic multipliers, by virtual work).
    let robot = hand.robot();
    for j in &grip.joints {
        assert!(j.torque.abs() <= j.limit * (1.0 + 1e-6), "{j:?}");
    }
    let fk = forward_kinematics(robot, &e.q).unwrap();
    let root_from_object: Isometry3<f64> = fk.as_slice()[hand.palm().0] * hand.palm_frame() * e.hand_pose.inverse();
    let dofs: Vec<usize> = (0..robot.dof()).collect();
    let mut jtf = vec![0.0; robot.dof()];
    for (c, f) in e.contacts.iter().zip(&grip.contact_forces) {
        let p = fk.as_slice()[c.link].inverse_transform_point(&(root_from_object * c.contact.point));
        let jac = jacobian(robot, &e.q, LinkId(c.link), &p, &dofs).unwrap();
        let f_root = root_from_object.rotation * f;
        for (d, v) in jtf.iter_mut().enumerate() {
            *v += jac.fixed_view::<3, 1>(0, d).dot(&f_root);
        }
    }
    let mut pressed = 0;
    for (d, &expected) in jtf.iter().enumerate() {
        let sum: f64 = grip
            .joints
            .iter()
            .filter(|j| j.dof == d)
            .map(|j| robot.driving_dof(JointId(j.joint)).unwrap().1 * j.torque)
            .sum();
        assert!((sum - expected).abs() < 1e-6 * (1.0 + expected.abs()), "dof {d}: {sum} vs Jᵀf {expected}");
        pressed += usize::from(expected.abs() > 0.1);
    }
    assert!(pressed >= 3, "{jtf:?}");
    // Deterministic, and bad parameters are typed errors.
    assert_eq!(grip_torques(&hand, &object, &e, fraction, margin, true).unwrap(), grip);
    for (f, m) in [(f64::NAN, 0.5), (-1.0, 0.5), (1.0, 0.0), (1.0, 1.5), (1.0, f64::NAN)] {
        assert!(matches!(grip_torques(&hand, &object, &e, f, m, true), Err(GraspError::InvalidParameter { .. })));
    }
}

#[test]
fn balanced_grip_holds_the_barrett_salt_can_wrap_in_all_six_directions() {
    let (hand, object, e) = barrett_salt_can_wrap();
    let defaults = PhysicsCheckOptions::default();
    let options = PhysicsCheckOptions {
        balanced: Some(1.0),
        physics: opengrasp_core::physics::PhysicsOptions { contact_frequency: 1000.0, ..defaults.physics.clone() },
        ..defaults
    };
    // Balanced stall torques (1 kHz contacts): held in every direction, gravity moving the
    // can by at most 4.2 mm (measured 0.6–4.2 mm since the closing's exact speed bounds; it
    // was 0.3–2.4 mm from the slightly different touch of the 20 %-slack bounds) relative to
    // the gravity-free control run.
    let out = physics_check(&hand, &object, &e, &options).unwrap();
    assert_eq!(out.results, vec![HoldResult::Held; 6], "{out:?}");
    assert!(out.translations.iter().all(|&t| t < 0.005), "{out:?}");
    // Deterministic to the last bit.
    assert_eq!(physics_check(&hand, &object, &e, &options).unwrap(), out);
    // Without friction nothing squeezes the can along its axis: the grip's contact forces are
    // all normal, and gravity along the axis pulls it out.
    let slippery = opengrasp_assets::objects::ObjectModel { friction: 0.0, ..object.clone() };
    let axial = PhysicsCheckOptions { directions: vec![-Vector3::z()], ..options.clone() };
    let dropped = physics_check(&hand, &slippery, &e, &axial).unwrap();
    assert!(dropped.translations[0] > 0.05, "{dropped:?}");
}

/// `effort` and `balanced` exclude each other, and `grip_compliance` needs `balanced` and a
/// positive value: typed errors from `validate` and from the check itself.
#[test]
fn physics_check_rejects_conflicting_actuator_modes() {
    let (hand, object, e) = barrett_salt_can_wrap();
    let defaults = PhysicsCheckOptions::default();
    assert!(defaults.validate().is_ok());
    let bad = [
        PhysicsCheckOptions { effort: Some(0.5), balanced: Some(1.0), ..defaults.clone() },
        PhysicsCheckOptions { grip_compliance: Some(0.05), ..defaults.clone() },
        PhysicsCheckOptions { balanced: Some(1.0), grip_compliance: Some(0.0), ..defaults.clone() },
        PhysicsCheckOptions { balanced: Some(1.0), grip_compliance: Some(f64::NAN), ..defaults.clone() },
        PhysicsCheckOptions { regrip: Some(0.01), ..defaults.clone() },
        PhysicsCheckOptions { balanced: Some(1.0), regrip: Some(0.0), ..defaults.clone() },
        PhysicsCheckOptions { balanced: Some(1.0), regrip: Some(f64::INFINITY), ..defaults.clone() },
    ];
    for options in bad {
        assert!(matches!(options.validate(), Err(GraspError::InvalidParameter { .. })), "{options:?}");
        assert!(
            matches!(physics_check(&hand, &object, &e, &options), Err(GraspError::InvalidParameter { .. })),
            "{options:?}"
        );
    }
    assert!(PhysicsCheckOptions { balanced: Some(1.0), grip_compliance: Some(0.05), ..defaults }.validate().is_ok());
}

/// A grasp whose balanced grip is all zero (one fingertip contact alone cannot squeeze: nothing
/// balances it) is checked as without `balanced`: the same outcome to the last bit.
#[test]
fn a_grasp_without_a_balanced_grip_is_checked_under_position_control() {
    let (hand, object, mut e) = barrett_salt_can_wrap();
    let finger = e.contacts.iter().position(|c| c.link != hand.palm().0).unwrap();
    e.contacts = vec![e.contacts[finger]];
    let grip = grip_torques(&hand, &object, &e, 1.0, 0.5, true).unwrap();
    assert!(grip.joints.iter().all(|j| j.torque.abs() <= 1e-6 * j.limit), "{grip:?}");
    let position = PhysicsCheckOptions { directions: vec![-Vector3::z(), Vector3::x()], ..Default::default() };
    let balanced = PhysicsCheckOptions { balanced: Some(1.0), ..position.clone() };
    let springs = PhysicsCheckOptions { grip_compliance: Some(0.05), ..balanced.clone() };
    let expected = physics_check(&hand, &object, &e, &position).unwrap();
    for options in [balanced, springs] {
        let out = physics_check(&hand, &object, &e, &options).unwrap();
        assert_eq!(
            out.translations.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
            expected.translations.iter().map(|t| t.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(out, expected);
    }
}

/// The balanced grip turned into joint springs at the end of the squeeze (`grip_compliance`)
/// holds the Barrett salt-can wrap in all six directions too, deterministically.
#[test]
fn balanced_grip_springs_hold_the_barrett_salt_can_wrap() {
    let (hand, object, e) = barrett_salt_can_wrap();
    let options = PhysicsCheckOptions { balanced: Some(1.0), grip_compliance: Some(0.05), ..Default::default() };
    let out = physics_check(&hand, &object, &e, &options).unwrap();
    println!("{out:?}");
    assert_eq!(out.results, vec![HoldResult::Held; 6], "{out:?}");
    assert!(out.translations.iter().all(|&t| t < 0.004), "{out:?}");
    assert_eq!(physics_check(&hand, &object, &e, &options).unwrap(), out);
}

/// Without a contact that a motorised joint moves (no contact at all, or only the palm's, as
/// the simulated contacts a grip controller re-solves on can be once the fingers lost the
/// object) nothing squeezes: the grip is all zero, not a solver failure.
#[test]
fn a_grip_without_finger_contacts_is_zero() {
    let (hand, object, mut e) = barrett_salt_can_wrap();
    // A finger contact moved onto the palm link, which no joint moves.
    let palm = opengrasp_grasp::evaluator::GraspContact { link: hand.palm().0, finger: None, ..e.contacts[0] };
    for contacts in [Vec::new(), vec![palm]] {
        e.contacts = contacts;
        let grip = grip_torques(&hand, &object, &e, 1.0, 0.5, true).unwrap();
        assert!(!grip.squeezes(), "{grip:?}");
        assert_eq!(grip.min_normal, 0.0);
        assert_eq!(grip.contact_forces.len(), e.contacts.len());
        assert!(grip.contact_forces.iter().all(|f| f.norm() == 0.0), "{grip:?}");
    }
}

/// The grip controller (`regrip`: the balanced grip re-solved on the simulated contacts every
/// 20 ms of the squeeze) holds the Barrett salt-can wrap in all six directions at 1 kHz
/// contacts, with torques of its own (another outcome than the grip solved once),
/// deterministically.
#[test]
fn regripping_holds_the_barrett_salt_can_wrap() {
    let (hand, object, e) = barrett_salt_can_wrap();
    let defaults = PhysicsCheckOptions::default();
    let once = PhysicsCheckOptions {
        balanced: Some(1.0),
        physics: opengrasp_core::physics::PhysicsOptions { contact_frequency: 1000.0, ..defaults.physics.clone() },
        ..defaults
    };
    let regrip = PhysicsCheckOptions { regrip: Some(0.02), ..once.clone() };
    let out = physics_check(&hand, &object, &e, &regrip).unwrap();
    println!("{out:?}");
    assert_eq!(out.results, vec![HoldResult::Held; 6], "{out:?}");
    assert!(out.translations.iter().all(|&t| t < 0.005), "{out:?}");
    assert_ne!(out, physics_check(&hand, &object, &e, &once).unwrap());
    assert_eq!(physics_check(&hand, &object, &e, &regrip).unwrap(), out);
}

/// The check drives the fingers as the hand's actuators act: the ARMAR-III hand's fluidic
/// actuators are compliant, so with no actuator model chosen in the options its grasps are
/// checked with the balanced grip pressed through joint springs (bit for bit the explicit
/// settings), while the Barrett's position servos and any model the options choose stay as set.
#[test]
fn the_physics_check_drives_each_hand_as_its_actuation_says() {
    use opengrasp_core::hand::Actuation;
    let armar = hands::armar3_hand();
    let barrett = hands::barrett();
    let compliance = hands::ARMAR3_COMPLIANCE;
    assert_eq!(armar.actuation(), Actuation::Compliant { compliance });
    assert_eq!(barrett.actuation(), Actuation::Position);
    assert_eq!(hands::sdh().actuation(), Actuation::Position);
    let defaults = PhysicsCheckOptions::default();
    assert!(defaults.hand_actuation);
    let applied = defaults.for_hand(&armar);
    assert_eq!((applied.balanced, applied.grip_compliance), (Some(1.0), Some(compliance)));
    assert_eq!(defaults.for_hand(&barrett), defaults);
    let off = PhysicsCheckOptions { hand_actuation: false, ..defaults.clone() };
    assert_eq!(off.for_hand(&armar), off);
    let chosen = PhysicsCheckOptions { effort: Some(0.5), ..defaults.clone() };
    assert_eq!(chosen.for_hand(&armar), chosen);
    let spring = PhysicsCheckOptions { spring: Some(0.4), ..defaults.clone() };
    assert_eq!(spring.for_hand(&armar), spring);
    // The check applies it: the hand's model gives exactly the explicit settings' outcome.
    let object = opengrasp_assets::objects::by_name("salt_can").unwrap();
    let mut ev = GraspEvaluator::new(&armar, &object, EvaluatorOptions::default()).unwrap();
    let info = ev.hand_info().clone();
    let approach = Unit::new_normalize(-Vector3::x());
    let mut hand_pose = palm_pose(&info, &Point3::origin(), &approach, &Vector3::y());
    hand_pose.translation.vector.z = 0.07;
    let e = ev.evaluate(&GraspCandidate { hand_pose, preshape: Preshape::Default, approach, standoff: 0.0 }).unwrap();
    let two = PhysicsCheckOptions { directions: vec![-Vector3::z(), Vector3::y()], ..defaults };
    let by_hand = physics_check(&armar, &object, &e, &two).unwrap();
    let explicit = PhysicsCheckOptions {
        balanced: Some(1.0),
        grip_compliance: Some(compliance),
        hand_actuation: false,
        ..two.clone()
    };
    assert_eq!(physics_check(&armar, &object, &e, &explicit).unwrap(), by_hand);
    let servo = physics_check(&armar, &object, &e, &PhysicsCheckOptions { hand_actuation: false, ..two }).unwrap();
    assert_ne!(servo, by_hand);
}
