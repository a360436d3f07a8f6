//! Bounds on how fast links move *vertically*: a mobile base sliding on the floor or turning
//! about a vertical axis (and a torso turning about one) moves every link, but changes no
//! link's height, so the vertical gap to a floor or a table top certifies long base motions
//! that the direction-free [`MotionBound`] cannot.

use nalgebra::Isometry3;
use opengrasp_core::kinematics::forward_kinematics_into;
use opengrasp_core::model::{JointGroup, JointKind, Robot};

use crate::validity::MotionBound;

/// Tilts (rad) at most this small count as vertical axes; their tilt is carried as slack.
const VERTICAL: f64 = 1e-9;

/// `v_ij` (row-major, `bound.links().len() × group.len()`): for the straight motion `Δq`,
/// no point of link `i` (of `bound`) moves vertically faster than `Σ_j |Δq_j| v_ij`.
///
/// `v_ij = s_ij r_ij` with `r_ij` the direction-free radius of `bound` and `s_ij ≤ 1` the
/// largest vertical factor of the chain joints of link `i` that group joint `j` drives: at a
/// joint whose axis `a` makes the angle `θ` with the world's z axis, a revolute joint moves a
/// point at distance `w` from it vertically at most `|q̇| sin θ · w` (the z part of
/// `q̇ a × w`) and a prismatic joint at `|q̇| |cos θ|`. The angle is taken at `q_full`
/// (`base_pose` places the robot); it is the same at every configuration while every group
/// joint before it on the chain is prismatic or turns about a vertical axis (those move the
/// joint's axis by translations and rotations about z, which keep its angle to z). Past the
/// first group joint with a tilted rotation axis, `s_ij = 1`. Near-vertical axes (tilt under
/// [`VERTICAL`]) keep the property up to their tilt, which is added to the later factors.
pub(super) fn vertical_radii(
    robot: &Robot,
    group: &JointGroup,
    base_pose: &Isometry3<f64>,
    q_full: &[f64],
    bound: &MotionBound,
) -> Vec<f64> {
    let mut poses = Vec::new();
    forward_kinematics_into(robot, q_full, &mut poses);
    let dim = bound.dim();
    let mut out = vec![0.0; bound.links().len() * dim];
    for (i, &link) in bound.links().iter().enumerate() {
        let mut factor = vec![0.0f64; dim];
        // The summed tilt of the near-vertical group axes so far; `None` once a tilted
        // group axis has turned the rest of the chain.
        let mut slack = Some(0.0f64);
        for jid in robot.chain_to(link) {
            let joint = robot.joint(jid);
            let driver = robot.driving_dof(jid).and_then(|(d, _)| group.dofs().iter().position(|&g| g == d));
            let axis = (base_pose * poses[joint.parent.0] * joint.origin).rotation * joint.axis.into_inner();
            let tilt = axis.x.hypot(axis.y).min(1.0);
            let f = match (slack, joint.kind) {
                (_, JointKind::Fixed) => 0.0,
                (None, _) => 1.0,
                (Some(s), JointKind::Prismatic) => (axis.z.abs() + s).min(1.0),
                (Some(s), JointKind::Revolute | JointKind::Continuous) => (tilt + s).min(1.0),
            };
            let Some(g) = driver else { continue };
            factor[g] = factor[g].max(f);
            if matches!(joint.kind, JointKind::Revolute | JointKind::Continuous) {
                slack = slack.filter(|_| tilt <= VERTICAL).map(|s| s + tilt);
            }
        }
        for (g, f) in factor.iter().enumerate() {
            out[i * dim + g] = f * bound.radius(i, g);
        }
    }
    out
}
