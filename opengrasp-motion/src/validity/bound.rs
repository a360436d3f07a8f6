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
    /// Per group joint `j`, the weight of link pair `(a, b)` (indices into
    /// [`MotionBound::links`]) in a bound on how much their distance changes: `r_aj` if `j`
    /// drives a joint on `a`'s chain that is not on `b`'s (it moves `a` relative to `b`), plus
    /// the same for `b`. A group joint that drives only common ancestors moves the pair rigidly
    /// and weighs 0; one coupled to joints on both chains (a mimic) weighs `r_aj + r_bj`.
    /// `robot` and `group` are the ones the bound was built for.
    pub fn pair_radii(&self, robot: &Robot, group: &JointGroup, a: usize, b: usize) -> Vec<f64> {
        let own = |link: LinkId, other: LinkId| {
            let theirs = robot.chain_to(other);
            let mut own = vec![false; self.dim];
            for j in robot.chain_to(link).into_iter().filter(|j| !theirs.contains(j)) {
                if let Some(g) = robot.driving_dof(j).and_then(|(d, _)| group.dofs().iter().position(|&x| x == d)) {
                    own[g] = true;
                }
            }
            own
        };
        let (link_a, link_b) = (self.links[a], self.links[b]);
        let (own_a, own_b) = (own(link_a, link_b), own(link_b, link_a));
        (0..self.dim)
            .map(|j| {
                let wa = if own_a[j] { self.radius(a, j) } else { 0.0 };
                let wb = if own_b[j] { self.radius(b, j) } else { 0.0 };
                wa + wb
            })
            .collect()
    }
    /// `B_i(Δq) = Σ_j |Δq_j| r_ij` for link index `i`.
    pub fn bound(&self, i: usize, dq: &[f64]) -> f64 {
        self.radii[i * self.dim..(i + 1) * self.dim].iter().zip(dq).map(|(r, d)| r * d.abs()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Vector3};
    use opengrasp_core::model::{Geometry, JointSpec, Link, RobotBuilder, Shape};

    /// A turning palm with two sliding fingers, the right one mimicking the left in mirror
    /// (a parallel gripper's coupled jaws); group = palm yaw and the left jaw.
    fn gripper() -> (Robot, JointGroup) {
        let jaw = || Shape::at_origin(Geometry::cuboid(0.02, 0.02, 0.05));
        let mut robot = RobotBuilder::new("gripper")
            .link(Link::new("base"))
            .link(Link::new("palm").with_shape(Shape::at_origin(Geometry::cuboid(0.1, 0.1, 0.02))))
            .link(Link::new("left").with_shape(jaw()))
            .link(Link::new("right").with_shape(jaw()))
            .joint(
                JointSpec::new("yaw", JointKind::Revolute, "base", "palm")
                    .axis(Vector3::z())
                    .limits(-3.0, 3.0, 1.0, 10.0),
            )
            .joint(
                JointSpec::new("left", JointKind::Prismatic, "palm", "left")
                    .origin(Isometry3::translation(0.0, 0.05, 0.05))
                    .axis(-Vector3::y())
                    .limits(0.0, 0.04, 0.1, 10.0),
            )
            .joint(
                JointSpec::new("right", JointKind::Prismatic, "palm", "right")
                    .origin(Isometry3::translation(0.0, -0.05, 0.05))
                    .axis(Vector3::y())
                    .limits(0.0, 0.04, 0.1, 10.0)
                    .mimic("left", 1.0, 0.0),
            )
            .build()
            .unwrap();
        robot.add_group("hand", &["yaw", "left"]).unwrap();
        let group = JointGroup::all(&robot, "hand").unwrap();
        (robot, group)
    }

    #[test]
    fn pair_radii_count_coupled_jaws_and_not_shared_ancestors() {
        let (robot, group) = gripper();
        let bound = MotionBound::from_robot(&robot, &group).unwrap();
        let slot = |name: &str| bound.links().iter().position(|&l| robot.link(l).name == name).unwrap();
        let (palm, left, right) = (slot("palm"), slot("left"), slot("right"));
        // Jaws against each other: the yaw turns both rigidly (0); the left jaw's dof drives a
        // joint on each chain, so the jaws close on each other at twice its speed (1 + 1).
        assert_eq!(bound.pair_radii(&robot, &group, left, right), vec![0.0, 2.0]);
        assert_eq!(bound.pair_radii(&robot, &group, right, left), vec![0.0, 2.0]);
        // A jaw against the palm it slides on: only its own slide moves it (r = 1).
        assert_eq!(bound.pair_radii(&robot, &group, palm, left), vec![0.0, 1.0]);
        assert_eq!(bound.pair_radii(&robot, &group, right, palm), vec![0.0, 1.0]);
        // The yaw alone moves each jaw by its radius relative to the world, not to the palm.
        assert!(bound.radius(left, 0) > 0.05 && bound.radius(right, 0) > 0.05);
        // The bound is tight for the jaws' relative motion: closing by Δ brings their origins
        // 2Δ closer, the bound allows Σ |Δq| w = 2Δ (plus 0 for any yaw).
        let index = |name: &str| robot.links().iter().position(|l| l.name == name).unwrap();
        let gap = |q: &[f64]| {
            let poses = opengrasp_core::kinematics::forward_kinematics(&robot, q).unwrap();
            let p = poses.as_slice();
            (p[index("left")].translation.vector - p[index("right")].translation.vector).norm()
        };
        let (open, closed) = (gap(&[0.4, 0.0]), gap(&[1.1, 0.03]));
        let weights = bound.pair_radii(&robot, &group, left, right);
        let allowed = weights[0] * 0.7 + weights[1] * 0.03;
        assert!((open - closed - 0.06).abs() < 1e-12, "jaws closed by {}", open - closed);
        assert!(allowed >= open - closed - 1e-12, "bound {allowed} below the closing {}", open - closed);
    }
}
