//! Per-link motion bounds for certified continuous collision checking.

use nalgebra::Point3;
use opengrasp_core::model::{JointGroup, JointKind, LinkId, Robot};

use crate::error::{MotionError, Result};

/// Per-link bounds on how far any point of a link can move when the group joints move by
/// `Δq` (Schwarzer, Saha & Latombe 2005):
/// `B_i(Δq) = Σ_j |Δq_j| · r_ij`, where for a revolute joint `j` before link `i`, `r_ij` is a
/// configuration-independent upper bound on the distance of any point of link `i` from joint
/// `j`'s axis, and for a prismatic joint `r_ij = 1`. Joints after link `i` (and joints outside
/// the group) contribute nothing.
///
/// `r_ij` is computed from the kinematic tree: the distance from joint `j`'s origin to every
/// later joint origin along the chain (with prismatic joints at their largest extension), plus
/// the largest distance of a geometry vertex of link `i` (the corners of each shape's bounding
/// box, which contain the shape) from link `i`'s frame origin. Mimic joints driven by a group
/// joint contribute with their multiplier.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionBound {
    links: Vec<LinkId>,
    dim: usize,
    /// Row-major `links.len() × dim`.
    radii: Vec<f64>,
}

impl MotionBound {
    /// Bounds for `links` of `robot` moved by the joints of `group`; the geometry of each link
    /// is given by points in its frame (`link_points[k]` for `links[k]`) whose convex hull
    /// contains it.
    ///
    /// # Errors
    /// [`MotionError::DimensionMismatch`] if `link_points` and `links` differ in length.
    pub fn new(robot: &Robot, group: &JointGroup, links: &[LinkId], link_points: &[Vec<Point3<f64>>]) -> Result<Self> {
        if links.len() != link_points.len() {
            return Err(MotionError::DimensionMismatch { expected: links.len(), actual: link_points.len() });
        }
        let extents: Vec<f64> =
            link_points.iter().map(|points| points.iter().map(|p| p.coords.norm()).fold(0.0, f64::max)).collect();
        Self::with_extents(robot, group, links, &extents)
    }

    /// As [`MotionBound::new`], with each link's geometry given by its extent: the largest
    /// distance of a point of link `links[k]` from its frame origin (`extents[k]`).
    ///
    /// # Errors
    /// [`MotionError::DimensionMismatch`] if `extents` and `links` differ in length.
    pub fn with_extents(robot: &Robot, group: &JointGroup, links: &[LinkId], extents: &[f64]) -> Result<Self> {
        if links.len() != extents.len() {
            return Err(MotionError::DimensionMismatch { expected: links.len(), actual: extents.len() });
        }
        let dim = group.len();
        let mut radii = vec![0.0; links.len() * dim];
        for (k, (&link, &extent)) in links.iter().zip(extents).enumerate() {
            let chain = robot.chain_to(link);
            // reach[c]: bound on the distance from joint chain[c]'s origin to any point of the link.
            let mut reach = vec![0.0; chain.len()];
            let mut acc = extent;
            for c in (0..chain.len()).rev() {
                let joint = robot.joint(chain[c]);
                if joint.kind == JointKind::Prismatic {
                    let ext = joint.limits.map(|l| l.lower.abs().max(l.upper.abs())).unwrap_or(0.0);
                    acc += ext;
                }
                reach[c] = acc;
                acc += joint.origin.translation.vector.norm();
            }
            for (c, &jid) in chain.iter().enumerate() {
                let joint = robot.joint(jid);
                let Some((dof, mult)) = robot.driving_dof(jid) else { continue };
                let Some(gi) = group.dofs().iter().position(|&d| d == dof) else { continue };
                let r = match joint.kind {
                    JointKind::Prismatic => 1.0,
                    JointKind::Fixed => 0.0,
                    JointKind::Revolute | JointKind::Continuous => reach[c],
                };
                radii[k * dim + gi] += mult.abs() * r;
            }
        }
        Ok(Self { links: links.to_vec(), dim, radii })
    }

    /// Bounds for every link of `robot` that has collision geometry, from the bounding-box
    /// corners of its collision shapes.
    ///
    /// # Errors
    /// As [`MotionBound::new`] (never in practice).
    pub fn from_robot(robot: &Robot, group: &JointGroup) -> Result<Self> {
        Self::from_robot_with(robot, group, &[])
    }

    /// As [`MotionBound::from_robot`], with extra geometry points (in the link frame) carried by
    /// some links, e.g. the bounding-box corners of an attached object.
    ///
    /// # Errors
    /// As [`MotionBound::new`] (never in practice).
    pub fn from_robot_with(robot: &Robot, group: &JointGroup, extra: &[(LinkId, Vec<Point3<f64>>)]) -> Result<Self> {
        let mut links = Vec::new();
        let mut points = Vec::new();
        for (i, link) in robot.links().iter().enumerate() {
            let carried: Vec<Point3<f64>> =
                extra.iter().filter(|(l, _)| l.0 == i).flat_map(|(_, p)| p.iter().copied()).collect();
            if link.collisions.is_empty() && carried.is_empty() {
                continue;
            }
            let mut pts = carried;
            for shape in &link.collisions {
                pts.extend(shape.aabb_corners());
            }
            links.push(LinkId(i));
            points.push(pts);
        }
        Self::new(robot, group, &links, &points)
    }

    /// The links the bounds refer to, in order.
    pub fn links(&self) -> &[LinkId] {
        &self.links
    }
    /// Group dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// `r_ij` for link index `i` (into [`MotionBound::links`]) and group joint `j`.
    pub fn radius(&self, i: usize, j: usize) -> f64 {
        self.radii[i * self.dim + j]
    }
    /// True if some group joint moves link index `i` (some `r_ij > 0`).
    pub fn is_moving(&self, i: usize) -> bool {
        self.radii[i * self.dim..(i + 1) * self.dim].iter().any(|&r| r > 0.0)
    }
    /// `B_i(Δq) = Σ_j |Δq_j| r_ij` for link index `i`.
    pub fn bound(&self, i: usize, dq: &[f64]) -> f64 {
        self.radii[i * self.dim..(i + 1) * self.dim].iter().zip(dq).map(|(r, d)| r * d.abs()).sum()
    }
}
