//! What the evaluator precomputes about a hand: closing dofs, palm frames per preshape, reach.

use nalgebra::{Isometry3, Unit};
use opengrasp_core::hand::Hand;
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::model::{JointKind, LinkId};

use crate::error::Result;
use crate::planners::{any_perpendicular, HandInfo};

/// Radius of a ball about the palm frame origin containing the hand in its open preshapes.
pub(super) fn hand_radius(hand: &Hand, data: &HandData) -> Result<f64> {
    let robot = hand.robot();
    let mut r: f64 = 0.0;
    for (q, rfp) in data.preshape_q.iter().zip(&data.root_from_palm) {
        let fk = forward_kinematics(robot, q)?;
        let to_palm = rfp.inverse();
        for (l, link) in robot.links().iter().enumerate() {
            for s in &link.collisions {
                for c in s.aabb_corners() {
                    r = r.max((to_palm * (fk.as_slice()[l] * c)).coords.norm());
                }
            }
        }
    }
    Ok(r)
}

/// Static data of a hand the evaluator needs (derived once per hand).
#[derive(Clone, Debug)]
pub(super) struct HandData {
    pub(super) info: HandInfo,
    /// Pose of the palm frame in the robot root frame, per preshape (palm rigid with root).
    pub(super) root_from_palm: Vec<Isometry3<f64>>,
    /// Full open configurations, per preshape.
    pub(super) preshape_q: Vec<Vec<f64>>,
    /// Closing dofs with velocity, links they move and speed bound `R_d`.
    pub(super) closing: Vec<ClosingDof>,
    /// Finger index of each link (`None` if not in a finger).
    pub(super) link_finger: Vec<Option<usize>>,
    /// Links that count as palm.
    pub(super) palm_links: Vec<bool>,
}

#[derive(Clone, Debug)]
pub(super) struct ClosingDof {
    pub(super) dof: usize,
    pub(super) velocity: f64,
    pub(super) links: Vec<usize>,
    pub(super) speed_bounds: Vec<f64>,
}

/// Derives the planner-facing description of a hand: approach and closing axes in the palm
/// frame and the widest graspable object.
///
/// The closing axis is the principal direction (perpendicular to the approach) of the
/// fingertip displacements when all fingers close fully from the default preshape; the
/// aperture is the extent of the open hand's geometry along it.
///
/// # Errors
/// [`GraspError::Core`](crate::GraspError::Core) if the hand's model cannot be evaluated.
pub fn hand_info(hand: &Hand) -> Result<HandInfo> {
    Ok(hand_data(hand)?.info)
}

pub(super) fn hand_data(hand: &Hand) -> Result<HandData> {
    let robot = hand.robot();
    let n_links = robot.links().len();
    let open = hand.open_configuration();
    let fk = forward_kinematics(robot, &open)?;
    let palm_root = fk.as_slice()[hand.palm().0] * hand.palm_frame();
    let approach = hand.approach();
    let mut link_finger = vec![None; n_links];
    for (f, finger) in hand.fingers().iter().enumerate() {
        for l in &finger.links {
            link_finger[l.0] = Some(f);
        }
    }
    // The palm assembly: links with geometry that no closing joint moves (the palm and, e.g.,
    // the Barrett knuckles on the spread joint).
    let closing_v = hand.closing_velocity();
    let palm_links: Vec<bool> = (0..n_links)
        .map(|l| {
            !robot.links()[l].collisions.is_empty()
                && robot.chain_to(LinkId(l)).iter().all(|&j| {
                    robot.driving_dof(j).is_none_or(|(d, m)| m == 0.0 || closing_v.get(d).is_none_or(|&v| v == 0.0))
                })
        })
        .collect();
    // Closing axis from fingertip velocities.
    let v = hand.closing_velocity();
    let mut q2 = open.clone();
    for (d, vd) in v.iter().enumerate() {
        q2[d] += 10.0 * vd.signum();
    }
    robot.clamp_configuration(&mut q2);
    let fk2 = forward_kinematics(robot, &q2)?;
    let to_palm = palm_root.inverse();
    let a = approach.into_inner();
    let mut scatter = nalgebra::Matrix3::zeros();
    for finger in hand.fingers() {
        if let Some(tip) = finger.links.last() {
            let p1 = to_palm * fk.as_slice()[tip.0].translation.vector;
            let p2 = to_palm * fk2.as_slice()[tip.0].translation.vector;
            let mut dv = p2 - p1;
            dv -= a * a.dot(&dv);
            scatter += dv * dv.transpose();
        }
    }
    let eig = nalgebra::SymmetricEigen::new(scatter);
    let k = eig.eigenvalues.imax();
    let mut closing = eig.eigenvectors.column(k).into_owned();
    closing -= a * a.dot(&closing);
    if closing.norm() < 1e-9 || eig.eigenvalues[k] < 1e-16 {
        closing = any_perpendicular(&a);
    }
    let closing = closing.normalize();
    let kk = closing.iamax();
    let closing = Unit::new_unchecked(if closing[kk] < 0.0 { -closing } else { closing });
    // Aperture: extent of the hand's geometry along the closing axis at the open preshape.
    let max_aperture = aperture(robot, fk.as_slice(), &to_palm, &closing);
    // Closing dofs: the links each moves, with a bound on each link's speed per unit of dof
    // motion: the sum over the joints the dof drives of |multiplier| × the link's farthest
    // reach from that joint's axis point (1 per unit for prismatic joints). The reach is
    // bounded for every configuration along the kinematic chain (see `chain_reach`); only
    // below a prismatic joint, where no such bound exists, is it the open hand's reach plus
    // 20 % slack.
    let mut closing_dofs = Vec::new();
    for (d, &vd) in v.iter().enumerate() {
        if vd == 0.0 {
            continue;
        }
        let mut links: Vec<usize> = Vec::new();
        let mut bounds: Vec<f64> = Vec::new();
        for (jid, joint) in robot.joints().iter().enumerate() {
            let jid = opengrasp_core::model::JointId(jid);
            let Some((dd, m)) = robot.driving_dof(jid) else { continue };
            if dd != d || m == 0.0 {
                continue;
            }
            let origin = fk.as_slice()[joint.child.0].translation.vector;
            for (l, link) in robot.links().iter().enumerate() {
                let chain = robot.chain_to(LinkId(l));
                let Some(at) = chain.iter().position(|&j| j == jid) else { continue };
                if link.collisions.is_empty() {
                    continue;
                }
                let reach = chain_reach(robot, &chain[at + 1..], link).unwrap_or_else(|| {
                    let mut reach: f64 = 0.0;
                    for s in &link.collisions {
                        for c in s.aabb_corners() {
                            reach = reach.max(((fk.as_slice()[l] * c).coords - origin).norm());
                        }
                    }
                    1.2 * reach
                });
                let speed = m.abs() * if joint.kind == JointKind::Prismatic { 1.0 } else { reach };
                match links.iter().position(|&x| x == l) {
                    Some(k) => bounds[k] += speed,
                    None => {
                        links.push(l);
                        bounds.push(speed);
                    }
                }
            }
        }
        if !links.is_empty() {
            let speed_bounds = bounds.iter().map(|b| b.max(1e-6)).collect();
            closing_dofs.push(ClosingDof { dof: d, velocity: vd, links, speed_bounds });
        }
    }
    let mut root_from_palm = Vec::new();
    let mut preshape_q = Vec::new();
    let mut preshape_apertures = Vec::new();
    let home = robot.home_configuration();
    for p in hand.preshapes() {
        let q = hand.preshape_configuration(&p.name, &home)?;
        let fkp = forward_kinematics(robot, &q)?;
        let rfp = fkp.as_slice()[hand.palm().0] * hand.palm_frame();
        preshape_apertures.push(aperture(robot, fkp.as_slice(), &rfp.inverse(), &closing));
        root_from_palm.push(rfp);
        preshape_q.push(q);
    }
    if preshape_q.is_empty() {
        root_from_palm.push(palm_root);
        preshape_q.push(open);
    }
    let info = HandInfo {
        name: hand.name().to_string(),
        approach,
        closing,
        preshapes: hand.preshapes().iter().map(|p| p.name.clone()).collect(),
        max_aperture,
        preshape_apertures,
    };
    Ok(HandData { info, root_from_palm, preshape_q, closing: closing_dofs, link_finger, palm_links })
}

/// A bound, valid in every configuration, on the distance from a joint's axis point (its
/// child frame's origin) to the collision geometry of `link`, the joints `below` (after
/// that joint on the chain to `link`) all revolute, continuous or fixed: each rotates its
/// child frame about that frame's origin, which thus stays at the joint origin's offset from
/// the previous one, so the triangle inequality bounds the distance by the sum of those
/// offsets and the link's farthest bounding-box corner from its own frame origin. `None` if
/// a joint below is prismatic (its offset is not fixed).
fn chain_reach(
    robot: &opengrasp_core::model::Robot,
    below: &[opengrasp_core::model::JointId],
    link: &opengrasp_core::model::Link,
) -> Option<f64> {
    let mut reach = 0.0;
    for &j in below {
        let joint = robot.joint(j);
        if joint.kind == JointKind::Prismatic {
            return None;
        }
        reach += joint.origin.translation.vector.norm();
    }
    let corner = link.collisions.iter().flat_map(|s| s.aabb_corners()).map(|c| c.coords.norm()).fold(0.0, f64::max);
    Some(reach + corner)
}

/// Extent (m) of the robot's collision geometry (link poses `fk` in the root frame) along
/// `axis` of the palm frame (`to_palm` maps root to palm coordinates).
fn aperture(
    robot: &opengrasp_core::model::Robot,
    fk: &[Isometry3<f64>],
    to_palm: &Isometry3<f64>,
    axis: &Unit<nalgebra::Vector3<f64>>,
) -> f64 {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (l, link) in robot.links().iter().enumerate() {
        for s in &link.collisions {
            for c in s.aabb_corners() {
                let t = (to_palm * (fk[l] * c)).coords.dot(axis);
                lo = lo.min(t);
                hi = hi.max(t);
            }
        }
    }
    if hi > lo {
        hi - lo
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use opengrasp_assets::hands;
    use opengrasp_core::kinematics::forward_kinematics;

    use super::hand_data;

    /// The Barrett's flexion bounds are the phalanges' exact reaches (no slack): the proximal
    /// box (18 × 24 mm, from 16 to 70 mm along the finger) reaches its far corner at
    /// √(9² + 12² + 70²) mm from the flexion axis point; the distal one (16.2 × 21.6 mm, 10 to
    /// 58 mm) moves with the flexion (70 mm on, then its own far corner) and with the coupled
    /// distal joint (48/140 of it).
    #[test]
    fn barrett_speed_bounds_are_the_phalanx_reaches() {
        let hand = hands::barrett();
        let data = hand_data(&hand).unwrap();
        let names: Vec<&str> = hand.robot().links().iter().map(|l| l.name.as_str()).collect();
        let proximal = (0.009f64.powi(2) + 0.012f64.powi(2) + 0.07f64.powi(2)).sqrt();
        let distal = (0.0081f64.powi(2) + 0.0108f64.powi(2) + 0.058f64.powi(2)).sqrt();
        let mut fingers = 0;
        for c in &data.closing {
            for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                let expected = if names[l].ends_with("_proximal") {
                    proximal
                } else if names[l].ends_with("_distal") {
                    0.07 + distal + 48.0 / 140.0 * distal
                } else {
                    continue;
                };
                assert!((r - expected).abs() < 1e-12, "{}: {r} vs {expected}", names[l]);
                fingers += 1;
            }
        }
        assert_eq!(fingers, 6, "three fingers of two phalanges");
    }

    /// The bounds hold in every configuration, not only the open one: on both stock hands, at
    /// configurations spread over the joint limits, no bounding-box corner of a link moves
    /// faster per unit of its closing dof than the link's bound.
    #[test]
    fn speed_bounds_hold_across_the_joint_limits() {
        for hand in [hands::barrett(), hands::armar3_hand()] {
            let robot = hand.robot();
            let data = hand_data(&hand).unwrap();
            let n = robot.dof();
            let mut worst: f64 = 0.0;
            for k in 0..40 {
                let mut q: Vec<f64> = (0..n)
                    .map(|d| {
                        let (lo, hi) = robot.dof_limits(d);
                        let t = ((k * 7 + d * 13) % 40) as f64 / 39.0;
                        lo + t * (hi - lo)
                    })
                    .collect();
                robot.clamp_configuration(&mut q);
                for c in &data.closing {
                    let h = 1e-6;
                    let mut q2 = q.clone();
                    q2[c.dof] += if q[c.dof] + h <= robot.dof_limits(c.dof).1 { h } else { -h };
                    let (a, b) = (forward_kinematics(robot, &q).unwrap(), forward_kinematics(robot, &q2).unwrap());
                    for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                        for s in &robot.links()[l].collisions {
                            for p in s.aabb_corners() {
                                let speed = (a.as_slice()[l] * p - b.as_slice()[l] * p).norm() / h;
                                worst = worst.max(speed / r);
                            }
                        }
                    }
                }
            }
            assert!(worst <= 1.0 + 1e-6, "{}: a corner moves {worst} × its bound", hand.name());
            // The bounds are tight somewhere (a straight finger's tip).
            assert!(worst > 0.9, "{}: bounds loose everywhere ({worst})", hand.name());
        }
    }
}
