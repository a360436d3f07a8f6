//! Balanced grip torques: joint torques that squeeze the object without pushing it anywhere.
//!
//! For a closed grasp, [`grip_torques`] solves the second-order cone program
//!
//! ```text
//! maximise   t + ε Σ_c f_c·n_c / n
//! subject to Σ_c f_c = 0,   Σ_c (p_c − c) × f_c = 0               (zero net wrench)
//!            ‖f_c − (f_c·n_c) n_c‖ ≤ μ_g (f_c·n_c)                 (friction cones, μ_g = margin·μ)
//!            t ≤ f_c·n_c ≤ cap                                       (grip on every finger contact)
//!            0 ≤ f_c·n_c ≤ cap on contacts no motorised joint moves (the palm's)
//!            |τ_i| ≤ fraction · share_i,  τ_i = Σ_c J_{c,i}ᵀ f_c    (every motorised joint)
//!            τ_i · closing_i ≥ 0                                     (closing joints press closed)
//! ```
//!
//! A joint standing at the limit of its closing direction (as the evaluator's closing leaves
//! joints whose fingers close fully, or are pressed closed by their contacts) keeps only
//! `τ_i · closing_i ≤ fraction · share_i`: its stop takes any torque that would close it
//! further, so its contacts may press it closed (or it presses with less than nothing). Its
//! reported torque is its motor's part, `max(τ_i · closing_i, 0)` in the closing direction.
//! Without the rule, the benchmark grasps whose fingertips or thumb base rest at a stop had no
//! balanced grip at all (ARMAR-III: 59 of 80 without it, 35 with it; `physics_classes` example).
//!
//! per **joint** `i` (not per actuator): the simulator drives coupled joints with separate
//! motors, so each joint must balance its own contacts. `share_i` is the joint's part of its
//! actuator's effort limit (with coupling, `limit |m_i| / Σ m_k²`, as
//! [`opengrasp_core::physics::PhysicsOptions::coupled_actuators`]), `J_{c,i}` the velocity of
//! contact `c` per unit motion of joint `i` alone. The physics check commands these torques as
//! stall torques (position targets beyond contact with motor force caps `|τ_i|`), so the fingers
//! press with an internal force that is an equilibrium of the object.

use nalgebra::{Isometry3, Matrix3, Vector3};
use opengrasp_core::hand::Hand;
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::model::{JointId, JointKind, LinkId, Robot};
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::{JointSpring, PhysicsEngine};
use opengrasp_core::scene::RobotId;
use serde::{Deserialize, Serialize};

use clarabel::solver::SupportedConeT;

use super::{EvaluationStatus, GraspEvaluation};
use crate::error::{GraspError, Result};

/// Weight of the mean normal force in the objective (breaks ties when one contact cannot be
/// loaded and the minimum normal force is zero).
const EPSILON: f64 = 0.01;
/// Cap on any contact's normal force (N): palm contacts have no actuator limit.
const CAP: f64 = 1000.0;

/// Torque of one motorised joint in a [`GripTorques`] solution.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointTorque {
    /// Joint index in the hand's robot.
    pub joint: usize,
    /// Configuration dof (actuator) driving it.
    pub dof: usize,
    /// Torque (N·m, or N) the joint applies, positive along its axis.
    pub torque: f64,
    /// Its cap: `fraction` times its share of the actuator's effort limit.
    pub limit: f64,
}

/// Balanced grip of a closed grasp ([`grip_torques`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GripTorques {
    /// Force (N, object frame) each contact applies to the object, in the evaluation's order.
    pub contact_forces: Vec<Vector3<f64>>,
    /// Every motorised joint's torque (zero for joints without contacts beyond them).
    pub joints: Vec<JointTorque>,
    /// Smallest normal force (N) over the finger contacts (palm contacts are not counted).
    pub min_normal: f64,
}

impl GripTorques {
    /// True if some joint presses (a torque above 1e-6 of its cap): a grip to command. All
    /// torques zero means no squeeze of the finger contacts fits the cones and signs.
    pub fn squeezes(&self) -> bool {
        self.joints.iter().any(|j| j.torque.abs() > 1e-6 * j.limit)
    }
}

/// Per-joint effort caps: the joint's share of its actuator's limit (see the module docs).
fn joint_share(robot: &Robot, j: JointId, coupled: bool) -> Option<(usize, f64, f64)> {
    let (dof, factor) = robot.driving_dof(j)?;
    let own = robot.joint(j).limits.map(|l| l.effort);
    let leader = robot.joint(robot.dof_joint(dof)).limits.map(|l| l.effort)?;
    if !(leader.is_finite() && leader > 0.0) || robot.joint(j).kind == JointKind::Fixed {
        return None;
    }
    let share = if coupled {
        let sum_sq: f64 = (0..robot.joints().len())
            .filter_map(|i| robot.driving_dof(JointId(i)))
            .filter(|&(d, _)| d == dof)
            .map(|(_, m)| m * m)
            .sum();
        leader * factor.abs() / sum_sq
    } else {
        own.filter(|e| e.is_finite() && *e > 0.0).unwrap_or(leader)
    };
    Some((dof, factor, share))
}

/// Solves the balanced grip of `evaluation` (see the module docs): friction `margin × μ` (μ the
/// object's), joint torques within `fraction` of their shares, coupled shares if `coupled`.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for an evaluation that did not close, a contact on a link the
/// hand does not have, or a `fraction` / `margin` that is not finite and positive (margin ≤ 1);
/// [`GraspError::Core`] from kinematics; [`GraspError::Solver`] if the conic solver fails.
pub fn grip_torques(
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    fraction: f64,
    margin: f64,
    coupled: bool,
) -> Result<GripTorques> {
    if evaluation.status != EvaluationStatus::Closed {
        return Err(GraspError::InvalidParameter { name: "evaluation", reason: "the hand did not close".into() });
    }
    crate::planners::check_positive("fraction", fraction)?;
    if !(margin.is_finite() && margin > 0.0 && margin <= 1.0) {
        return Err(GraspError::InvalidParameter {
            name: "margin",
            reason: format!("must be in (0, 1], got {margin}"),
        });
    }
    let robot = hand.robot();
    let q = &evaluation.q;
    let fk = forward_kinematics(robot, q)?;
    let poses = fk.as_slice();
    let root_from_object: Isometry3<f64> = poses[hand.palm().0] * hand.palm_frame() * evaluation.hand_pose.inverse();
    let closing = hand.closing_velocity();
    let joints: Vec<(JointId, usize, f64, f64)> = (0..robot.joints().len())
        .filter_map(|i| joint_share(robot, JointId(i), coupled).map(|(d, m, s)| (JointId(i), d, m, s * fraction)))
        .collect();
    // Joints at the end of their closing range: the stop takes any torque that would close them
    // further, so they press with at most their cap but need not press at all.
    let stopped: Vec<bool> =
        joints.iter().map(|&(j, dof, m, _)| at_closing_stop(robot, q, j, closing, dof, m)).collect();
    let nc = evaluation.contacts.len();
    // torque[c][i][k]: torque on joint i per newton of contact c's local component k.
    let mut frames = Vec::with_capacity(nc);
    let mut levers = Vec::with_capacity(nc);
    let mut torque = vec![vec![[0.0; 3]; joints.len()]; nc];
    let com = object.center_of_mass();
    for (c, gc) in evaluation.contacts.iter().enumerate() {
        if gc.link >= robot.links().len() {
            return Err(GraspError::InvalidParameter {
                name: "evaluation",
                reason: format!("contact on link {} of a hand with {}", gc.link, robot.links().len()),
            });
        }
        let (t1, t2) = gc.contact.tangents();
        let frame = Matrix3::from_columns(&[gc.contact.normal.into_inner(), t1, t2]);
        let root_frame = root_from_object.rotation.to_rotation_matrix().into_inner() * frame;
        let p = root_from_object * gc.contact.point;
        let mut l = LinkId(gc.link);
        while let Some(jid) = robot.parent_joint(l) {
            let joint = robot.joint(jid);
            if let Some(i) = joints.iter().position(|x| x.0 == jid) {
                let child = poses[l.0];
                let axis = child.rotation * joint.axis.into_inner();
                let v = match joint.kind {
                    JointKind::Prismatic => axis,
                    _ => axis.cross(&(p - child.translation.vector).coords),
                };
                torque[c][i] = [0, 1, 2].map(|k| v.dot(&root_frame.column(k)));
            }
            l = joint.parent;
        }
        frames.push(frame);
        levers.push(gc.contact.point - com);
    }
    let radius = (object.size().norm() / 2.0).max(1e-3);
    let mu = object.friction * margin;
    let driven = |c: usize| torque[c].iter().any(|t| t.iter().any(|&v| v != 0.0));
    // No contact a motorised joint moves (none at all, or only the palm's, as the simulator's
    // contacts after a finger lost its object): nothing to squeeze with, and the program's
    // smallest driven normal force would be unbounded.
    let x = if (0..nc).any(driven) {
        solve(&frames, &levers, &torque, &joints, &stopped, closing, mu, radius)?
    } else {
        vec![0.0; 3 * nc + 1]
    };
    let contact_forces =
        frames.iter().enumerate().map(|(c, f)| f * Vector3::new(x[3 * c], x[3 * c + 1], x[3 * c + 2])).collect();
    let joints = joints
        .iter()
        .enumerate()
        .map(|(i, &(j, dof, m, limit))| {
            let total: f64 = (0..nc).map(|c| (0..3).map(|k| torque[c][i][k] * x[3 * c + k]).sum::<f64>()).sum();
            // A stopped joint's motor presses with the closing part of it, its stop takes the rest.
            let s = closing_sign(closing, dof, m);
            let torque = if stopped[i] { s * (s * total).max(0.0) } else { total };
            JointTorque { joint: j.0, dof, torque, limit }
        })
        .collect();
    let min_normal = (0..nc).filter(|&c| driven(c)).map(|c| x[3 * c]).fold(f64::INFINITY, f64::min);
    Ok(GripTorques { contact_forces, joints, min_normal: if min_normal.is_finite() { min_normal } else { 0.0 } })
}

/// +1 / −1: the direction in which joint `m`-coupled to `dof` closes; 0 for joints whose dof
/// does not close (spread joints).
fn closing_sign(closing: &[f64], dof: usize, m: f64) -> f64 {
    match closing.get(dof) {
        Some(&v) if v != 0.0 => v.signum() * m.signum(),
        _ => 0.0,
    }
}

/// Joints within this (rad or m) of a limit are on it: the evaluator's closing stops a joint
/// exactly at its limit.
const STOP_TOLERANCE: f64 = 1e-6;

/// True if joint `j` (driven by `dof` with factor `m`) closes and stands at the limit of its
/// closing direction in configuration `q`: its stop, not its motor, resists any further closing.
fn at_closing_stop(robot: &Robot, q: &[f64], j: JointId, closing: &[f64], dof: usize, m: f64) -> bool {
    let Some(limits) = robot.joint(j).limits else { return false };
    let position = robot.joint_position(q, j);
    match closing_sign(closing, dof, m) {
        s if s > 0.0 => position >= limits.upper - STOP_TOLERANCE,
        s if s < 0.0 => position <= limits.lower + STOP_TOLERANCE,
        _ => false,
    }
}

/// The grip of a hand that simply closes: every joint driven by a closing actuator (non-zero
/// closing velocity) presses in its closing direction with `fraction` of its effort share (with
/// `coupled`, `limit |m_i| / Σ m_k²` as in [`grip_torques`]), whatever the contacts. With
/// [`stiffen_grip`] it becomes a position controller with a physical gain: each joint presses
/// with its full share where it stands and less as it closes further (see
/// [`super::PhysicsCheckOptions::spring`]). The contact forces are left empty.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for a `fraction` that is not finite and positive.
pub fn closing_grip(hand: &Hand, fraction: f64, coupled: bool) -> Result<GripTorques> {
    crate::planners::check_positive("fraction", fraction)?;
    let robot = hand.robot();
    let closing = hand.closing_velocity();
    let joints = (0..robot.joints().len())
        .filter_map(|i| joint_share(robot, JointId(i), coupled).map(|(d, m, s)| (i, d, m, s)))
        .filter(|&(_, d, _, _)| closing.get(d).is_some_and(|&v| v != 0.0))
        .map(|(joint, dof, m, share)| JointTorque {
            joint,
            dof,
            torque: fraction * share * (m * closing[dof]).signum(),
            limit: fraction * share,
        })
        .collect();
    Ok(GripTorques { contact_forces: Vec::new(), joints, min_normal: 0.0 })
}

/// Commands `grip` as stall torques on the hand `robot` of `engine`: the closing joints'
/// motors (position targets beyond contact) are capped at `|τᵢ|`, so each presses with its
/// balanced torque while stalled.
///
/// # Errors
/// [`GraspError::Core`] from the engine.
pub fn command_grip<E: PhysicsEngine + ?Sized>(
    engine: &mut E,
    robot: RobotId,
    hand: &Hand,
    grip: &GripTorques,
) -> Result<()> {
    let closing = hand.closing_velocity();
    for jt in grip.joints.iter().filter(|jt| closing.get(jt.dof).is_some_and(|&v| v != 0.0)) {
        engine.set_joint_force_limit(robot, JointId(jt.joint), jt.torque.abs())?;
    }
    Ok(())
}

/// Turns the stall torques of [`command_grip`] into springs around the positions the joints
/// have reached: every joint of `grip` becomes a force-based spring ([`JointSpring`]) of
/// stiffness `kᵢ = limitᵢ / θ` (`θ = compliance`: full effort share at θ of deflection)
/// resting `τᵢ / kᵢ` past its current simulated position `qᵢ`. At
/// `qᵢ` it presses with exactly `τᵢ` as before, and with `τᵢ + kᵢ (qᵢ − q)` elsewhere, so an
/// object pushed into one finger meets more force from it: a stable equilibrium instead of the
/// neutral one of constant torques. Call it after the fingers have closed on the object
/// (the check's clamped squeeze), where their simulated contacts are.
///
/// # Errors
/// [`GraspError::InvalidParameter`] for a non-positive or non-finite `compliance`;
/// [`GraspError::Core`] from the engine.
pub fn stiffen_grip<E: PhysicsEngine + ?Sized>(
    engine: &mut E,
    robot: RobotId,
    hand: &Hand,
    grip: &GripTorques,
    compliance: f64,
) -> Result<()> {
    crate::planners::check_positive("grip_compliance", compliance)?;
    let model = hand.robot();
    for jt in grip.joints.iter().filter(|jt| jt.limit > 0.0) {
        let j = JointId(jt.joint);
        let joint = model.joint(j);
        // The joint's own motion: parent frame × origin × motion(q) = child frame.
        let rel =
            (engine.link_pose(robot, joint.parent)? * joint.origin).inverse() * engine.link_pose(robot, joint.child)?;
        let q = match joint.kind {
            JointKind::Prismatic => rel.translation.vector.dot(&joint.axis),
            _ => {
                let r = rel.rotation.quaternion();
                2.0 * r.imag().dot(&joint.axis).atan2(r.w)
            }
        };
        let stiffness = jt.limit / compliance;
        let spring = JointSpring { position: q + jt.torque / stiffness, stiffness };
        engine.set_joint_spring(robot, j, Some(spring))?;
    }
    Ok(())
}

/// The program of the module docs; returns the local force components (3 per contact) and `t`.
#[allow(clippy::too_many_arguments)]
fn solve(
    frames: &[Matrix3<f64>],
    levers: &[Vector3<f64>],
    torque: &[Vec<[f64; 3]>],
    joints: &[(JointId, usize, f64, f64)],
    stopped: &[bool],
    closing: &[f64],
    mu: f64,
    radius: f64,
) -> Result<Vec<f64>> {
    let nc = frames.len();
    let nj = joints.len();
    let nx = 3 * nc + 1;
    // Rows: 6 equilibrium (zero cone); nonnegative: 2 per joint (limits), 1 per joint (sign),
    // 2 per contact (t ≤ fₙ ≤ cap), 1 (t ≥ 0); then a 3-row cone per contact.
    let nonneg = 3 * nj + 2 * nc + 1;
    let rows = 6 + nonneg + 3 * nc;
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nx];
    let mut b = vec![0.0; rows];
    // +1 / −1: the joint must press in its closing direction; 0: spread joints (either way).
    let sign: Vec<f64> = joints.iter().map(|&(_, dof, m, _)| closing_sign(closing, dof, m)).collect();
    for c in 0..nc {
        for k in 0..3 {
            let col = &mut cols[3 * c + k];
            let f = frames[c].column(k).into_owned();
            let m = levers[c].cross(&f) / radius;
            for r in 0..3 {
                col.push((r, f[r]));
                col.push((3 + r, m[r]));
            }
            for i in 0..nj {
                let t = torque[c][i][k];
                // A stopped joint keeps only its cap in the closing direction (sign[i] · τ ≤ cap).
                if !stopped[i] || sign[i] > 0.0 {
                    col.push((6 + 3 * i, t));
                }
                if !stopped[i] || sign[i] < 0.0 {
                    col.push((6 + 3 * i + 1, -t));
                }
                if !stopped[i] {
                    col.push((6 + 3 * i + 2, -sign[i] * t));
                }
            }
            col.push((6 + nonneg + 3 * c + k, if k == 0 { -mu } else { -1.0 }));
        }
        // Contacts no motorised joint moves (the palm's) need not squeeze: they balance the
        // fingers (a wrap pulls the object into the palm).
        let driven = torque[c].iter().any(|t| t.iter().any(|&v| v != 0.0));
        let base = 6 + 3 * nj + 2 * c;
        if driven {
            cols[3 * c].push((base, -1.0));
            cols[3 * nc].push((base, 1.0));
        }
        cols[3 * c].push((base + 1, 1.0));
        b[base + 1] = CAP;
    }
    cols[3 * nc].push((6 + 3 * nj + 2 * nc, -1.0));
    for (i, j) in joints.iter().enumerate() {
        b[6 + 3 * i] = j.3;
        b[6 + 3 * i + 1] = j.3;
    }
    let mut q = vec![0.0; nx];
    for c in 0..nc {
        q[3 * c] = -EPSILON / nc as f64;
    }
    q[3 * nc] = -1.0;
    let mut cones = vec![SupportedConeT::ZeroConeT(6), SupportedConeT::NonnegativeConeT(nonneg)];
    cones.extend((0..nc).map(|_| SupportedConeT::SecondOrderConeT(3)));
    super::static_hold::solve_conic("grip torques socp", rows, cols, &q, &b, &cones)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two contacts pinching the object along x, 3 cm either side of its centre: contact 0 (at
    /// +x, pressing towards −x) on joint 0, whose lever makes a pressing contact *open* it
    /// (−5 cm per newton of normal force), contact 1 (at −x) on joint 1, which presses it
    /// closed (+5 cm). Both joints close in the positive direction, caps 1 N·m.
    fn pinch(stopped: [bool; 2]) -> Vec<f64> {
        let frame = |n: f64| Matrix3::from_columns(&[Vector3::x() * n, Vector3::y(), Vector3::z() * n]);
        let frames = [frame(-1.0), frame(1.0)];
        let levers = [Vector3::x() * 0.03, -Vector3::x() * 0.03];
        let torque = vec![vec![[-0.05, 0.0, 0.0], [0.0; 3]], vec![[0.0; 3], [0.05, 0.0, 0.0]]];
        let joints = [(JointId(0), 0, 1.0, 1.0), (JointId(1), 1, 1.0, 1.0)];
        solve(&frames, &levers, &torque, &joints, &stopped, &[1.0, 1.0], 0.5, 0.05).unwrap()
    }

    #[test]
    fn a_joint_that_would_open_cannot_squeeze_off_its_stop() {
        // Joint 0 may only press closed: its contact cannot press, so nothing balances the other.
        let x = pinch([false, false]);
        assert!(x[0].abs() < 1e-6 && x[3].abs() < 1e-6, "{x:?}");
    }

    #[test]
    fn a_joint_on_its_closing_stop_lets_the_stop_take_the_opening_torque() {
        // On its stop, joint 0's contact presses with whatever joint 1 can balance: 1 N·m over
        // 5 cm, 20 N on both contacts.
        let x = pinch([true, false]);
        assert!((x[0] - 20.0).abs() < 1e-4 && (x[3] - 20.0).abs() < 1e-4, "{x:?}");
        assert!((x[6] - 20.0).abs() < 1e-4, "t = {}", x[6]);
        // The stop does not lift the cap in the closing direction: joint 1 on its stop still
        // presses with at most 1 N·m.
        let x = pinch([true, true]);
        assert!((x[3] - 20.0).abs() < 1e-4, "{x:?}");
    }
}
