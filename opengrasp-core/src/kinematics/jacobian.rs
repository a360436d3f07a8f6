//! Geometric Jacobians of points on links.
//!
//! The Jacobian maps joint velocities to the spatial velocity of a point rigidly attached to a
//! link: rows 0-2 are the point's linear velocity, rows 3-5 the link's angular velocity, both
//! expressed in the robot's root frame. A revolute or continuous joint with unit axis `ω`
//! through `o` contributes the column `[ω × (p − o); ω]`, a prismatic joint with axis `a` the
//! column `[a; 0]`. Mimic joints add `multiplier ×` their column to the column of the actuated
//! joint that drives them ([`Robot::driving_dof`]).

use nalgebra::{Isometry3, Matrix6xX, Point3, Translation3, Vector3};

use crate::error::{ensure_finite, CoreError, Result};
use crate::model::{JointKind, LinkId, Robot};

/// Geometric Jacobian of `point_in_link` (in the frame of `link`) with respect to the
/// configuration indices `dofs`, at configuration `q`.
///
/// Column `k` belongs to `dofs[k]`; a joint that does not move `link` gives a zero column, and
/// an index listed twice gives two equal columns. Rows 0-2: linear velocity of the point, rows
/// 3-5: angular velocity of the link, in the robot's root frame. Joint limits are not checked
/// (the Jacobian is defined everywhere).
///
/// # Errors
/// [`CoreError::DimensionMismatch`] or [`CoreError::NonFiniteJointValue`] for a bad `q`,
/// [`CoreError::NonFinite`] for a non-finite point, [`CoreError::InvalidParameter`] for a
/// `link` or a `dofs` entry that does not exist on this robot.
pub fn jacobian(
    robot: &Robot,
    q: &[f64],
    link: LinkId,
    point_in_link: &Point3<f64>,
    dofs: &[usize],
) -> Result<Matrix6xX<f64>> {
    robot.check_finite_configuration(q)?;
    check_link(robot, link)?;
    ensure_finite("point_in_link", point_in_link.coords.iter().copied())?;
    check_dofs(robot, dofs)?;
    let mut out = Matrix6xX::zeros(dofs.len());
    jacobian_into(robot, q, link, point_in_link, dofs, &mut out);
    Ok(out)
}

/// [`jacobian`] without validation, writing into `out`; for hot loops such as IK.
///
/// `out` is resized to `dofs.len()` columns only if its width differs (no allocation
/// otherwise). Returns the pose, in the root frame, of the frame with origin at the point and
/// the link's orientation (the link pose translated to the point).
///
/// # Panics
/// If `q` is shorter than [`Robot::dof`] or `link` is not a link of `robot`. Entries of `dofs`
/// that are not configuration indices simply give zero columns.
pub fn jacobian_into(
    robot: &Robot,
    q: &[f64],
    link: LinkId,
    point_in_link: &Point3<f64>,
    dofs: &[usize],
    out: &mut Matrix6xX<f64>,
) -> Isometry3<f64> {
    let start = Isometry3::from_parts(Translation3::from(point_in_link.coords), nalgebra::UnitQuaternion::identity());
    frame_jacobian_into(robot, q, link, &start, dofs, Some(out))
}

/// Pose in the root frame of `frame_in_link` (a frame on `link`), and optionally the Jacobian of
/// its origin with respect to `dofs` (see [`jacobian`]).
///
/// Walks the chain once, from the link up to the root, without allocating: columns are
/// accumulated in the frame being walked from and rotated into the root frame at the end.
pub(crate) fn frame_jacobian_into(
    robot: &Robot,
    q: &[f64],
    link: LinkId,
    frame_in_link: &Isometry3<f64>,
    dofs: &[usize],
    mut out: Option<&mut Matrix6xX<f64>>,
) -> Isometry3<f64> {
    if let Some(j) = out.as_deref_mut() {
        if j.ncols() != dofs.len() {
            *j = Matrix6xX::zeros(dofs.len());
        } else {
            j.fill(0.0);
        }
    }
    // Pose of the frame in the link currently visited (starts at `link`, ends at the root).
    let mut t = *frame_in_link;
    let mut l = link;
    while let Some(jid) = robot.parent_joint(l) {
        let joint = robot.joint(jid);
        if let Some(jac) = out.as_deref_mut() {
            if let Some((dof, factor)) = robot.driving_dof(jid) {
                // The joint axis passes through the child frame origin and is `axis` in it.
                let a = joint.axis.into_inner();
                let (lin, ang) = match joint.kind {
                    JointKind::Revolute | JointKind::Continuous => (a.cross(&t.translation.vector), a),
                    JointKind::Prismatic => (a, Vector3::zeros()),
                    JointKind::Fixed => (Vector3::zeros(), Vector3::zeros()),
                };
                // Express in the frame being tracked: R_frame_child = R_child_frame⁻¹.
                let lin = t.rotation.inverse_transform_vector(&lin) * factor;
                let ang = t.rotation.inverse_transform_vector(&ang) * factor;
                for (k, _) in dofs.iter().enumerate().filter(|(_, &d)| d == dof) {
                    let mut col = jac.column_mut(k);
                    let mut v = col.fixed_rows_mut::<3>(0);
                    v += lin;
                    let mut w = col.fixed_rows_mut::<3>(3);
                    w += ang;
                }
            }
        }
        t = joint.origin * joint.motion(robot.joint_position(q, jid)) * t;
        l = joint.parent;
    }
    if let Some(jac) = out {
        for mut col in jac.column_iter_mut() {
            let lin = t.rotation * Vector3::new(col[0], col[1], col[2]);
            let ang = t.rotation * Vector3::new(col[3], col[4], col[5]);
            col.fixed_rows_mut::<3>(0).copy_from(&lin);
            col.fixed_rows_mut::<3>(3).copy_from(&ang);
        }
    }
    t
}

/// `InvalidParameter` unless `link` is a link of `robot`.
pub(crate) fn check_link(robot: &Robot, link: LinkId) -> Result<()> {
    if link.0 < robot.links().len() {
        Ok(())
    } else {
        Err(CoreError::InvalidParameter {
            name: "link".into(),
            reason: format!("link index {} but the robot has {} links", link.0, robot.links().len()),
        })
    }
}

/// `InvalidParameter` unless every entry of `dofs` is a configuration index of `robot`.
pub(crate) fn check_dofs(robot: &Robot, dofs: &[usize]) -> Result<()> {
    match dofs.iter().find(|&&d| d >= robot.dof()) {
        None => Ok(()),
        Some(d) => Err(CoreError::InvalidParameter {
            name: "dofs".into(),
            reason: format!("configuration index {d} but the robot has {} degrees of freedom", robot.dof()),
        }),
    }
}
