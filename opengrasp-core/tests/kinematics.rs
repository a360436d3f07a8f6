//! Forward kinematics, Jacobians and inverse kinematics against closed forms, finite
//! differences and round trips.

use std::f64::consts::PI;

use nalgebra::{Isometry3, Matrix6xX, Point3, Translation3, UnitQuaternion, Vector3, Vector6};
use opengrasp_core::kinematics::{
    forward_kinematics, jacobian, jacobian_into, link_pose, solve_ik, IkOptions, IkSolution, IkStatus,
};
use opengrasp_core::model::samples::{planar_arm, serial_chain, seven_dof_arm};
use opengrasp_core::model::{JointGroup, JointKind, JointSpec, Link, LinkId, Robot, RobotBuilder};
use opengrasp_core::CoreError;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Finite-difference step and the agreement required between FD and analytic Jacobians.
const FD_STEP: f64 = 1e-6;
const FD_TOL: f64 = 1e-6;

/// A configuration sampled uniformly within the limits shrunk by `margin` (continuous joints:
/// within ±π).
fn random_q(robot: &Robot, rng: &mut ChaCha8Rng, margin: f64) -> Vec<f64> {
    (0..robot.dof())
        .map(|d| {
            let (lo, hi) = robot.dof_limits(d);
            let (lo, hi) = if lo.is_finite() { (lo + margin, hi - margin) } else { (-PI, PI) };
            lo + (hi - lo) * rng.random::<f64>()
        })
        .collect()
}

/// Pose of a point on `link` (link orientation, origin at the point).
fn point_pose(robot: &Robot, q: &[f64], link: LinkId, point: &Point3<f64>) -> Isometry3<f64> {
    link_pose(robot, q, link).unwrap() * Translation3::from(point.coords)
}

/// Central finite-difference Jacobian: position by differences, orientation by the log map of
/// `R(q + h) R(q − h)ᵀ`.
fn fd_jacobian(robot: &Robot, q: &[f64], link: LinkId, point: &Point3<f64>, dofs: &[usize]) -> Matrix6xX<f64> {
    let mut out = Matrix6xX::zeros(dofs.len());
    for (k, &d) in dofs.iter().enumerate() {
        let (mut qp, mut qm) = (q.to_vec(), q.to_vec());
        qp[d] += FD_STEP;
        qm[d] -= FD_STEP;
        let (pp, pm) = (point_pose(robot, &qp, link, point), point_pose(robot, &qm, link, point));
        let v = (pp.translation.vector - pm.translation.vector) / (2.0 * FD_STEP);
        let w = (pp.rotation * pm.rotation.inverse()).scaled_axis() / (2.0 * FD_STEP);
        out.set_column(k, &Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z));
    }
    out
}

fn assert_jacobian_matches_fd(robot: &Robot, q: &[f64], link: LinkId, point: &Point3<f64>, dofs: &[usize]) {
    let j = jacobian(robot, q, link, point, dofs).unwrap();
    let fd = fd_jacobian(robot, q, link, point, dofs);
    let err = (&j - &fd).amax();
    assert!(err < FD_TOL, "jacobian differs from finite differences by {err}\nanalytic {j}\nfd {fd}");
    let mut out = Matrix6xX::zeros(0);
    let pose = jacobian_into(robot, q, link, point, dofs, &mut out);
    assert_eq!(out, j);
    assert!((pose.translation.vector - point_pose(robot, q, link, point).translation.vector).norm() < 1e-12);
}

/// base → j0 (revolute z) → l1 → j1 (revolute y) → l2 → j2 (mimics j1, ×0.5 + 0.1) → l3
/// → j3 (prismatic x) → l4 → j4 (continuous z) → l5 → fixed → tool.
fn mimic_robot() -> Robot {
    RobotBuilder::new("mimic")
        .link(Link::new("base"))
        .link(Link::new("l1"))
        .link(Link::new("l2"))
        .link(Link::new("l3"))
        .link(Link::new("l4"))
        .link(Link::new("l5"))
        .link(Link::new("tool"))
        .joint(JointSpec::new("j0", JointKind::Revolute, "base", "l1").axis(Vector3::z()).limits(-3.0, 3.0, 1.0, 1.0))
        .joint(
            JointSpec::new("j1", JointKind::Revolute, "l1", "l2")
                .origin(Isometry3::translation(0.0, 0.0, 0.3))
                .axis(Vector3::y())
                .limits(-2.0, 2.0, 1.0, 1.0),
        )
        .joint(
            JointSpec::new("j2", JointKind::Revolute, "l2", "l3")
                .origin(Isometry3::new(Vector3::new(0.2, 0.0, 0.1), Vector3::new(0.3, 0.0, 0.2)))
                .axis(Vector3::new(1.0, 1.0, 0.0))
                .limits(-3.0, 3.0, 1.0, 1.0)
                .mimic("j1", 0.5, 0.1),
        )
        .joint(
            JointSpec::new("j3", JointKind::Prismatic, "l3", "l4")
                .origin(Isometry3::translation(0.0, 0.1, 0.2))
                .axis(Vector3::x())
                .limits(-0.2, 0.3, 1.0, 1.0),
        )
        .joint(
            JointSpec::new("j4", JointKind::Continuous, "l4", "l5")
                .origin(Isometry3::translation(0.1, 0.0, 0.0))
                .axis(Vector3::new(0.0, 1.0, 1.0)),
        )
        .joint(
            JointSpec::new("tool_joint", JointKind::Fixed, "l5", "tool").origin(Isometry3::translation(0.0, 0.0, 0.15)),
        )
        .build()
        .unwrap()
}

fn pose_errors(robot: &Robot, q: &[f64], tip: LinkId, offset: &Isometry3<f64>, target: &Isometry3<f64>) -> (f64, f64) {
    let pose = link_pose(robot, q, tip).unwrap() * offset;
    let ep = (target.translation.vector - pose.translation.vector).norm();
    let eo = (target.rotation * pose.rotation.inverse()).angle();
    (ep, eo)
}

/// Checks the invariants of an IK solution: limits respected, joints outside the group
/// untouched, reported errors matching an independent FK, tolerances met when converged.
fn check_solution(
    robot: &Robot,
    group: &JointGroup,
    tip: LinkId,
    target: &Isometry3<f64>,
    q_start: &[f64],
    options: &IkOptions,
    sol: &IkSolution,
) {
    robot.validate_configuration(&sol.q).unwrap();
    for d in (0..robot.dof()).filter(|d| !group.dofs().contains(d)) {
        assert_eq!(sol.q[d], q_start[d], "joint {d} outside the group moved");
    }
    let (ep, eo) = pose_errors(robot, &sol.q, tip, &options.tip_offset, target);
    assert!((ep - sol.position_error).abs() < 1e-9, "{ep} vs {}", sol.position_error);
    assert!((eo - sol.orientation_error).abs() < 1e-7, "{eo} vs {}", sol.orientation_error);
    if sol.status == IkStatus::Converged {
        assert!(ep <= options.position_tolerance + 1e-12, "position error {ep}");
        if !options.position_only {
            assert!(eo <= options.orientation_tolerance + 1e-9, "orientation error {eo}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn planar_arm_fk_matches_closed_form(
        l1 in 0.1..1.5f64, l2 in 0.1..1.5f64, a in -PI..PI, b in -PI..PI,
    ) {
        let robot = planar_arm(&[l1, l2]).unwrap();
        let tool = robot.link_id("tool").unwrap();
        let pose = forward_kinematics(&robot, &[a, b]).unwrap()[tool];
        let expected = Vector3::new(l1 * a.cos() + l2 * (a + b).cos(), l1 * a.sin() + l2 * (a + b).sin(), 0.0);
        prop_assert!((pose.translation.vector - expected).norm() < 1e-12);
        let rot = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), a + b);
        prop_assert!(pose.rotation.angle_to(&rot) < 1e-9);
    }

    #[test]
    fn seven_dof_jacobian_matches_finite_differences(
        seed in any::<u64>(), px in -0.1..0.1f64, py in -0.1..0.1f64, pz in -0.1..0.2f64,
    ) {
        let robot = seven_dof_arm().unwrap();
        let q = random_q(&robot, &mut ChaCha8Rng::seed_from_u64(seed), 1e-3);
        let tool = robot.link_id("tool").unwrap();
        let dofs: Vec<usize> = (0..7).collect();
        assert_jacobian_matches_fd(&robot, &q, tool, &Point3::new(px, py, pz), &dofs);
        // A middle link, dofs permuted: the wrist joints do not move link4.
        let link4 = robot.link_id("link4").unwrap();
        let permuted = [6, 2, 0, 5, 3, 1, 4];
        assert_jacobian_matches_fd(&robot, &q, link4, &Point3::new(px, py, pz), &permuted);
        let j = jacobian(&robot, &q, link4, &Point3::new(px, py, pz), &permuted).unwrap();
        for k in [0, 3, 6] {
            prop_assert_eq!(j.column(k).amax(), 0.0);
        }
    }

    #[test]
    fn serial_chain_jacobian_matches_finite_differences(
        seed in any::<u64>(), px in -0.1..0.1f64, py in -0.1..0.1f64, pz in -0.1..0.1f64,
    ) {
        let robot = serial_chain(10).unwrap();
        let q = random_q(&robot, &mut ChaCha8Rng::seed_from_u64(seed), 1e-3);
        let dofs: Vec<usize> = (0..10).collect();
        let point = Point3::new(px, py, pz);
        assert_jacobian_matches_fd(&robot, &q, robot.link_id("tool").unwrap(), &point, &dofs);
        // link3 is moved by joints 0..=3 only: the other six columns are zero.
        let link3 = robot.link_id("link3").unwrap();
        assert_jacobian_matches_fd(&robot, &q, link3, &point, &dofs);
        let j = jacobian(&robot, &q, link3, &point, &dofs).unwrap();
        for k in 4..10 {
            prop_assert_eq!(j.column(k).amax(), 0.0);
        }
        prop_assert!(j.column(3).amax() > 0.0);
    }

    #[test]
    fn mimic_jacobian_matches_finite_differences(
        seed in any::<u64>(), px in -0.1..0.1f64, py in -0.1..0.1f64, pz in -0.1..0.1f64,
    ) {
        let robot = mimic_robot();
        prop_assert_eq!(robot.dof(), 4);
        let q = random_q(&robot, &mut ChaCha8Rng::seed_from_u64(seed), 1e-3);
        let point = Point3::new(px, py, pz);
        assert_jacobian_matches_fd(&robot, &q, robot.link_id("tool").unwrap(), &point, &[0, 1, 2, 3]);
        // l3 hangs below the mimic joint: only dofs 0 and 1 (leader) move it.
        assert_jacobian_matches_fd(&robot, &q, robot.link_id("l3").unwrap(), &point, &[3, 1, 0, 2]);
    }

    #[test]
    fn ik_round_trip_seven_dof(seed in any::<u64>()) {
        let robot = seven_dof_arm().unwrap();
        let group = robot.group("arm").unwrap().clone();
        let tool = robot.link_id("tool").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let q_goal = random_q(&robot, &mut rng, 0.0);
        let q_seed = random_q(&robot, &mut rng, 0.0);
        let target = forward_kinematics(&robot, &q_goal).unwrap()[tool];
        let options = IkOptions { seed, ..IkOptions::default() };
        let sol = solve_ik(&robot, &group, tool, &target, &q_seed, &options).unwrap();
        check_solution(&robot, &group, tool, &target, &q_seed, &options, &sol);
    }
}

/// Fraction of random reachable targets solved from random seeds.
fn convergence_rate(robot: &Robot, group: &JointGroup, tip: LinkId, options: &IkOptions, samples: usize) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut converged = 0;
    for i in 0..samples {
        let q_goal = random_q(robot, &mut rng, 0.0);
        let q_seed = random_q(robot, &mut rng, 0.0);
        let target = link_pose(robot, &q_goal, tip).unwrap() * options.tip_offset;
        let options = IkOptions { seed: i as u64, ..options.clone() };
        let sol = solve_ik(robot, group, tip, &target, &q_seed, &options).unwrap();
        check_solution(robot, group, tip, &target, &q_seed, &options, &sol);
        converged += usize::from(sol.status == IkStatus::Converged);
    }
    converged as f64 / samples as f64
}

#[test]
fn ik_seven_dof_converges_on_95_percent_of_random_targets() {
    let robot = seven_dof_arm().unwrap();
    let group = robot.group("arm").unwrap().clone();
    let tool = robot.link_id("tool").unwrap();
    let rate = convergence_rate(&robot, &group, tool, &IkOptions::default(), 200);
    println!("7-dof full-pose IK convergence rate: {rate}");
    assert!(rate >= 0.95, "convergence rate {rate}");
}

#[test]
fn ik_serial_chain_position_only_and_tip_offset_converge() {
    let robot = serial_chain(10).unwrap();
    let group = JointGroup::all(&robot, "all").unwrap();
    let tool = robot.link_id("tool").unwrap();
    let offset = Isometry3::new(Vector3::new(0.02, -0.03, 0.05), Vector3::new(0.1, 0.2, -0.3));
    let full = IkOptions { tip_offset: offset, ..IkOptions::default() };
    let rate = convergence_rate(&robot, &group, tool, &full, 100);
    println!("10-joint chain full-pose IK convergence rate: {rate}");
    assert!(rate >= 0.95, "convergence rate {rate}");
    let position_only = IkOptions { position_only: true, ..full };
    let rate = convergence_rate(&robot, &group, tool, &position_only, 100);
    println!("10-joint chain position-only IK convergence rate: {rate}");
    assert!(rate >= 0.95, "convergence rate {rate}");
}

#[test]
fn ik_planar_arm_position_only_matches_closed_form() {
    let (l1, l2) = (0.7, 0.4);
    let robot = planar_arm(&[l1, l2]).unwrap();
    let group = JointGroup::all(&robot, "arm").unwrap();
    let tool = robot.link_id("tool").unwrap();
    // Target at distance r: the elbow angle is ±acos((r² − l1² − l2²) / (2 l1 l2)).
    let target = Isometry3::translation(0.5, 0.6, 0.0);
    let r2: f64 = 0.5 * 0.5 + 0.6 * 0.6;
    let elbow = ((r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)).acos();
    let options = IkOptions { position_only: true, ..IkOptions::default() };
    let sol = solve_ik(&robot, &group, tool, &target, &[0.3, 0.5], &options).unwrap();
    assert_eq!(sol.status, IkStatus::Converged);
    assert!(sol.position_error <= 1e-6);
    assert!((sol.q[1].abs() - elbow).abs() < 1e-5, "elbow {} vs ±{elbow}", sol.q[1]);
    assert_eq!(sol.restarts, 0);
    assert!(sol.iterations > 0 && sol.iterations < 100);
}

#[test]
fn ik_subgroup_keeps_other_joints() {
    let robot = serial_chain(10).unwrap();
    let names: Vec<String> = (2..10).map(|i| format!("joint{i}")).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let group = JointGroup::new(&robot, "upper", &names).unwrap();
    let tool = robot.link_id("tool").unwrap();
    let mut q_goal = random_q(&robot, &mut ChaCha8Rng::seed_from_u64(3), 0.0);
    let q_start: Vec<f64> = (0..10).map(|i| if i < 2 { q_goal[i] } else { 0.1 }).collect();
    q_goal[..2].copy_from_slice(&q_start[..2]);
    let target = link_pose(&robot, &q_goal, tool).unwrap();
    let options = IkOptions::default();
    let sol = solve_ik(&robot, &group, tool, &target, &q_start, &options).unwrap();
    assert_eq!(sol.status, IkStatus::Converged);
    check_solution(&robot, &group, tool, &target, &q_start, &options, &sol);
    assert_eq!(sol.q[..2], q_start[..2]);
}

#[test]
fn ik_is_deterministic_for_a_seed() {
    let robot = seven_dof_arm().unwrap();
    let group = robot.group("arm").unwrap().clone();
    let tool = robot.link_id("tool").unwrap();
    let target = link_pose(&robot, &[0.4, 1.0, -0.3, -1.2, 0.2, 0.9, 0.1], tool).unwrap();
    // A seed far away so that restarts are likely to be used.
    let q_start = [2.9, -2.0, 2.9, 2.0, -2.9, -2.0, 3.0];
    let options = IkOptions { seed: 11, max_iterations: 20, ..IkOptions::default() };
    let a = solve_ik(&robot, &group, tool, &target, &q_start, &options).unwrap();
    let b = solve_ik(&robot, &group, tool, &target, &q_start, &options).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.status, IkStatus::Converged);
    println!("far seed: {} restarts, {} iterations", a.restarts, a.iterations);
}

#[test]
fn ik_unreachable_target_reports_best_effort() {
    let robot = seven_dof_arm().unwrap();
    let group = robot.group("arm").unwrap().clone();
    let tool = robot.link_id("tool").unwrap();
    let q_start = robot.home_configuration();
    let target = Isometry3::translation(10.0, 0.0, 0.5);
    let options = IkOptions { max_restarts: 5, ..IkOptions::default() };
    let sol = solve_ik(&robot, &group, tool, &target, &q_start, &options).unwrap();
    assert!(matches!(sol.status, IkStatus::Unreachable | IkStatus::AtJointLimits), "{:?}", sol.status);
    assert_eq!(sol.restarts, 5);
    // The tool reaches at most 0.97 m from the shoulder at (0, 0, 0.31); the position error
    // cannot be smaller than the target's distance to that sphere (the solver also weighs the
    // orientation error, so it may stay slightly above).
    let bound = Vector3::new(10.0, 0.0, 0.5 - 0.31).norm() - 0.97;
    assert!(sol.position_error >= bound - 1e-9 && sol.position_error < bound + 0.1, "{}", sol.position_error);
    check_solution(&robot, &group, tool, &target, &q_start, &options, &sol);

    // The planar arm cannot leave its plane: stretched towards a point above it.
    let arm = planar_arm(&[0.7, 0.4]).unwrap();
    let group = JointGroup::all(&arm, "arm").unwrap();
    let tool = arm.link_id("tool").unwrap();
    let target = Isometry3::translation(0.0, 0.0, 2.0);
    let sol = solve_ik(&arm, &group, tool, &target, &[0.1, 0.1], &options).unwrap();
    assert_ne!(sol.status, IkStatus::Converged);
    assert!(sol.position_error >= 2.0 - 1e-9);
}

#[test]
fn ik_stretched_to_a_limit_reports_at_joint_limits() {
    // A one-joint arm limited to [0, 1] rad asked to reach an angle of 2 rad.
    let robot = RobotBuilder::new("one")
        .link(Link::new("base"))
        .link(Link::new("l1"))
        .link(Link::new("tool"))
        .joint(JointSpec::new("j0", JointKind::Revolute, "base", "l1").axis(Vector3::z()).limits(0.0, 1.0, 1.0, 1.0))
        .joint(
            JointSpec::new("tool_joint", JointKind::Fixed, "l1", "tool").origin(Isometry3::translation(0.5, 0.0, 0.0)),
        )
        .build()
        .unwrap();
    let group = JointGroup::all(&robot, "all").unwrap();
    let tool = robot.link_id("tool").unwrap();
    let target = Isometry3::new(Vector3::new(0.5 * 2f64.cos(), 0.5 * 2f64.sin(), 0.0), Vector3::z() * 2.0);
    let options = IkOptions { max_restarts: 3, ..IkOptions::default() };
    let sol = solve_ik(&robot, &group, tool, &target, &[0.5], &options).unwrap();
    assert_eq!(sol.status, IkStatus::AtJointLimits);
    assert!((sol.q[0] - 1.0).abs() < 1e-9);
    assert!((sol.orientation_error - 1.0).abs() < 1e-6);
}

#[test]
fn ik_rejects_bad_input_with_typed_errors() {
    let robot = seven_dof_arm().unwrap();
    let group = robot.group("arm").unwrap().clone();
    let tool = robot.link_id("tool").unwrap();
    let q = robot.home_configuration();
    let ok = Isometry3::translation(0.3, 0.0, 0.8);
    let opts = IkOptions::default();
    let nan = Isometry3::translation(f64::NAN, 0.0, 0.8);
    assert!(matches!(solve_ik(&robot, &group, tool, &nan, &q, &opts), Err(CoreError::NonFinite { .. })));
    let mut inf = ok;
    inf.rotation = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(f64::INFINITY, 0.0, 0.0, 0.0));
    assert!(matches!(solve_ik(&robot, &group, tool, &inf, &q, &opts), Err(CoreError::NonFinite { .. })));
    assert!(matches!(solve_ik(&robot, &group, tool, &ok, &q[..6], &opts), Err(CoreError::DimensionMismatch { .. })));
    let mut bad_q = q.clone();
    bad_q[2] = f64::NAN;
    assert!(matches!(solve_ik(&robot, &group, tool, &ok, &bad_q, &opts), Err(CoreError::NonFiniteJointValue { .. })));
    bad_q[2] = 5.0;
    assert!(matches!(solve_ik(&robot, &group, tool, &ok, &bad_q, &opts), Err(CoreError::JointOutOfLimits { .. })));
    let bad_options = [
        IkOptions { position_tolerance: 0.0, ..IkOptions::default() },
        IkOptions { orientation_tolerance: f64::NAN, ..IkOptions::default() },
        IkOptions { damping: -1.0, ..IkOptions::default() },
        IkOptions { max_iterations: 0, ..IkOptions::default() },
    ];
    for o in &bad_options {
        assert!(matches!(solve_ik(&robot, &group, tool, &ok, &q, o), Err(CoreError::InvalidParameter { .. })), "{o:?}");
    }
    let nan_offset = IkOptions { tip_offset: Isometry3::translation(f64::NAN, 0.0, 0.0), ..IkOptions::default() };
    assert!(matches!(solve_ik(&robot, &group, tool, &ok, &q, &nan_offset), Err(CoreError::NonFinite { .. })));
    assert!(matches!(solve_ik(&robot, &group, LinkId(99), &ok, &q, &opts), Err(CoreError::InvalidParameter { .. })));
    // A group of a bigger robot.
    let chain = serial_chain(10).unwrap();
    let foreign = JointGroup::all(&chain, "all").unwrap();
    assert!(matches!(solve_ik(&robot, &foreign, tool, &ok, &q, &opts), Err(CoreError::InvalidParameter { .. })));
}

#[test]
fn jacobian_rejects_bad_input_with_typed_errors() {
    let robot = seven_dof_arm().unwrap();
    let tool = robot.link_id("tool").unwrap();
    let q = robot.home_configuration();
    let p = Point3::origin();
    assert!(matches!(jacobian(&robot, &q[..5], tool, &p, &[0]), Err(CoreError::DimensionMismatch { .. })));
    let mut bad = q.clone();
    bad[0] = f64::INFINITY;
    assert!(matches!(jacobian(&robot, &bad, tool, &p, &[0]), Err(CoreError::NonFiniteJointValue { .. })));
    assert!(matches!(jacobian(&robot, &q, tool, &p, &[0, 7]), Err(CoreError::InvalidParameter { .. })));
    assert!(matches!(jacobian(&robot, &q, LinkId(42), &p, &[0]), Err(CoreError::InvalidParameter { .. })));
    let nan = Point3::new(0.0, f64::NAN, 0.0);
    assert!(matches!(jacobian(&robot, &q, tool, &nan, &[0]), Err(CoreError::NonFinite { .. })));
    assert_eq!(jacobian(&robot, &q, tool, &p, &[]).unwrap().ncols(), 0);
}

#[test]
fn planar_jacobian_matches_closed_form() {
    let (l1, l2) = (0.7, 0.4);
    let robot = planar_arm(&[l1, l2]).unwrap();
    let tool = robot.link_id("tool").unwrap();
    let (a, b) = (0.3, -1.1);
    let j = jacobian(&robot, &[a, b], tool, &Point3::origin(), &[0, 1]).unwrap();
    let (s1, c1, s12, c12) = (a.sin(), a.cos(), (a + b).sin(), (a + b).cos());
    #[rustfmt::skip]
    let expected = Matrix6xX::from_column_slice(&[
        -l1 * s1 - l2 * s12, l1 * c1 + l2 * c12, 0.0, 0.0, 0.0, 1.0,
        -l2 * s12, l2 * c12, 0.0, 0.0, 0.0, 1.0,
    ]);
    assert!((j - expected).amax() < 1e-12);
}
