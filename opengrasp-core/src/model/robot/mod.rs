//! Links, joints and the robot tree.

use std::collections::{HashMap, HashSet};

use crate::error::{CoreError, Result};
use crate::model::{Joint, JointId, Link, LinkId};

mod builder;

pub use builder::RobotBuilder;

/// A kinematic tree of links and joints, with named joint groups and allowed collision pairs.
///
/// Build one with [`RobotBuilder`] or load it from URDF (`crate::urdf`). Joint values are passed
/// as a configuration vector `q` with one entry per actuated joint ([`Robot::dof`]); mimic
/// joints are derived from their leaders.
#[derive(Clone, Debug)]
pub struct Robot {
    name: String,
    links: Vec<Link>,
    joints: Vec<Joint>,
    root: LinkId,
    parent_joint: Vec<Option<JointId>>,
    child_joints: Vec<Vec<JointId>>,
    /// Joints ordered so that every joint comes after the joint of its parent link.
    topo_joints: Vec<JointId>,
    dof_joints: Vec<JointId>,
    link_by_name: HashMap<String, LinkId>,
    joint_by_name: HashMap<String, JointId>,
    groups: Vec<super::JointGroup>,
    allowed_pairs: HashSet<(LinkId, LinkId)>,
}

fn ordered(a: LinkId, b: LinkId) -> (LinkId, LinkId) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

impl Robot {
    /// The robot's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// All links, indexed by [`LinkId`].
    pub fn links(&self) -> &[Link] {
        &self.links
    }
    /// All joints, indexed by [`JointId`].
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }
    /// One link.
    pub fn link(&self, id: LinkId) -> &Link {
        &self.links[id.0]
    }
    /// One joint.
    pub fn joint(&self, id: JointId) -> &Joint {
        &self.joints[id.0]
    }
    /// The root link (the robot's base frame).
    pub fn root(&self) -> LinkId {
        self.root
    }
    /// The joint whose child is `link` (`None` for the root).
    pub fn parent_joint(&self, link: LinkId) -> Option<JointId> {
        self.parent_joint[link.0]
    }
    /// The joints whose parent is `link`.
    pub fn child_joints(&self, link: LinkId) -> &[JointId] {
        &self.child_joints[link.0]
    }
    /// Joints in topological order (parents before children).
    pub fn joints_topological(&self) -> &[JointId] {
        &self.topo_joints
    }
    /// Number of actuated degrees of freedom (the length of a configuration vector).
    pub fn dof(&self) -> usize {
        self.dof_joints.len()
    }
    /// The joint behind configuration index `dof`.
    pub fn dof_joint(&self, dof: usize) -> JointId {
        self.dof_joints[dof]
    }
    /// Joints in configuration-vector order.
    pub fn dof_joints(&self) -> &[JointId] {
        &self.dof_joints
    }

    /// Looks a link up by name.
    ///
    /// # Errors
    /// [`CoreError::UnknownLink`].
    pub fn link_id(&self, name: &str) -> Result<LinkId> {
        self.link_by_name.get(name).copied().ok_or_else(|| CoreError::UnknownLink { name: name.to_string() })
    }

    /// Looks a joint up by name.
    ///
    /// # Errors
    /// [`CoreError::UnknownJoint`].
    pub fn joint_id(&self, name: &str) -> Result<JointId> {
        self.joint_by_name.get(name).copied().ok_or_else(|| CoreError::UnknownJoint { name: name.to_string() })
    }

    /// Configuration index of an actuated joint, by name.
    ///
    /// # Errors
    /// [`CoreError::UnknownJoint`], or [`CoreError::NotActuated`] for fixed or mimic joints.
    pub fn dof_index(&self, joint_name: &str) -> Result<usize> {
        let j = self.joint(self.joint_id(joint_name)?);
        j.dof.ok_or_else(|| CoreError::NotActuated { name: joint_name.to_string() })
    }

    /// Position limits `(lower, upper)` of configuration index `dof`; continuous joints
    /// report `(-inf, inf)`.
    pub fn dof_limits(&self, dof: usize) -> (f64, f64) {
        match self.joint(self.dof_joints[dof]).limits {
            Some(l) => (l.lower, l.upper),
            None => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }

    /// A configuration with every joint at zero, clamped into its limits.
    pub fn home_configuration(&self) -> Vec<f64> {
        (0..self.dof())
            .map(|i| {
                let (lo, hi) = self.dof_limits(i);
                0.0_f64.clamp(lo, hi)
            })
            .collect()
    }

    /// Checks that `q` has [`Robot::dof`] finite values within the joint limits
    /// (with a tolerance of 1e-9).
    ///
    /// # Errors
    /// [`CoreError::DimensionMismatch`], [`CoreError::NonFiniteJointValue`] or
    /// [`CoreError::JointOutOfLimits`].
    pub fn validate_configuration(&self, q: &[f64]) -> Result<()> {
        self.check_finite_configuration(q)?;
        for (i, &v) in q.iter().enumerate() {
            let (lo, hi) = self.dof_limits(i);
            if v < lo - 1e-9 || v > hi + 1e-9 {
                let joint = self.joint(self.dof_joints[i]).name.clone();
                return Err(CoreError::JointOutOfLimits { joint, value: v, lower: lo, upper: hi });
            }
        }
        Ok(())
    }

    /// Checks that `q` has [`Robot::dof`] finite values (limits are not checked).
    ///
    /// # Errors
    /// [`CoreError::DimensionMismatch`] or [`CoreError::NonFiniteJointValue`].
    pub fn check_finite_configuration(&self, q: &[f64]) -> Result<()> {
        if q.len() != self.dof() {
            return Err(CoreError::DimensionMismatch { expected: self.dof(), actual: q.len() });
        }
        if let Some(i) = q.iter().position(|v| !v.is_finite()) {
            let joint = self.joint(self.dof_joints[i]).name.clone();
            return Err(CoreError::NonFiniteJointValue { joint, value: q[i] });
        }
        Ok(())
    }

    /// Clamps every value of `q` into its joint limits.
    pub fn clamp_configuration(&self, q: &mut [f64]) {
        for (i, v) in q.iter_mut().enumerate() {
            let (lo, hi) = self.dof_limits(i);
            *v = v.clamp(lo, hi);
        }
    }

    /// Position of joint `id` for configuration `q` (0 for fixed joints; derived for mimic
    /// joints). `q` must have [`Robot::dof`] entries.
    pub fn joint_position(&self, q: &[f64], id: JointId) -> f64 {
        let j = &self.joints[id.0];
        if let Some(d) = j.dof {
            q[d]
        } else if let Some(m) = j.mimic {
            m.multiplier * self.joint_position(q, m.leader) + m.offset
        } else {
            0.0
        }
    }

    /// The actuated joint that drives `id` and the factor `d q_id / d q_dof`
    /// (`None` for fixed joints).
    pub fn driving_dof(&self, id: JointId) -> Option<(usize, f64)> {
        let j = &self.joints[id.0];
        if let Some(d) = j.dof {
            Some((d, 1.0))
        } else if let Some(m) = j.mimic {
            self.driving_dof(m.leader).map(|(d, f)| (d, f * m.multiplier))
        } else {
            None
        }
    }

    /// Chain of joints from the root to `link`, root first.
    pub fn chain_to(&self, link: LinkId) -> Vec<JointId> {
        let mut chain = Vec::new();
        let mut l = link;
        while let Some(j) = self.parent_joint[l.0] {
            chain.push(j);
            l = self.joints[j.0].parent;
        }
        chain.reverse();
        chain
    }

    /// Named joint groups defined on this robot.
    pub fn groups(&self) -> &[super::JointGroup] {
        &self.groups
    }

    /// A joint group by name.
    ///
    /// # Errors
    /// [`CoreError::UnknownJointGroup`].
    pub fn group(&self, name: &str) -> Result<&super::JointGroup> {
        self.groups
            .iter()
            .find(|g| g.name() == name)
            .ok_or_else(|| CoreError::UnknownJointGroup { name: name.to_string() })
    }

    /// Defines (or replaces) a named joint group from joint names.
    ///
    /// # Errors
    /// As [`super::JointGroup::new`].
    pub fn add_group(&mut self, name: &str, joints: &[&str]) -> Result<()> {
        let group = super::JointGroup::new(self, name, joints)?;
        self.groups.retain(|g| g.name() != name);
        self.groups.push(group);
        Ok(())
    }

    /// True if collisions between links `a` and `b` are ignored: the same link, links joined
    /// by a joint (adjacent, as SRDF does by default), or a pair allowed explicitly.
    pub fn is_collision_allowed(&self, a: LinkId, b: LinkId) -> bool {
        a == b || self.allowed_pairs.contains(&ordered(a, b))
    }

    /// Allows collisions between two links by name (e.g. fingers touching the palm).
    ///
    /// # Errors
    /// [`CoreError::UnknownLink`].
    pub fn allow_collision(&mut self, a: &str, b: &str) -> Result<()> {
        let (a, b) = (self.link_id(a)?, self.link_id(b)?);
        self.allowed_pairs.insert(ordered(a, b));
        Ok(())
    }

    /// Explicitly allowed or adjacent link pairs, each ordered `(lower id, higher id)`.
    pub fn allowed_collision_pairs(&self) -> impl Iterator<Item = (LinkId, LinkId)> + '_ {
        self.allowed_pairs.iter().copied()
    }

    /// Mutable access to a link (e.g. to replace its geometry).
    pub fn link_mut(&mut self, id: LinkId) -> &mut Link {
        &mut self.links[id.0]
    }
}
