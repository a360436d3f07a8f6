//! Building and validating a robot from links and joint specs.

//! Links, joints and the robot tree.

use std::collections::{HashMap, HashSet};

use nalgebra::{Unit, Vector3};

use super::{ordered, Robot};
use crate::error::{CoreError, Result};
use crate::model::{Joint, JointId, JointKind, JointSpec, Link, LinkId, Mimic};

/// Builds a [`Robot`] from links and joints, validating the tree on [`RobotBuilder::build`].
#[derive(Clone, Debug, Default)]
pub struct RobotBuilder {
    name: String,
    links: Vec<Link>,
    joints: Vec<JointSpec>,
    allowed: Vec<(String, String)>,
}

impl RobotBuilder {
    /// Starts a robot called `name`.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Self::default() }
    }

    /// Adds a link.
    pub fn link(mut self, link: Link) -> Self {
        self.links.push(link);
        self
    }

    /// Adds a joint.
    pub fn joint(mut self, joint: JointSpec) -> Self {
        self.joints.push(joint);
        self
    }

    /// Allows collisions between two links (besides adjacent ones, which are always allowed).
    pub fn allow_collision(mut self, a: impl Into<String>, b: impl Into<String>) -> Self {
        self.allowed.push((a.into(), b.into()));
        self
    }

    /// Validates and builds the robot.
    ///
    /// # Errors
    /// [`CoreError::InvalidModel`] for duplicate names, dangling link references, links with
    /// two parents, cycles, more than one root, missing limits on revolute/prismatic joints,
    /// zero axes or invalid mimic couplings; [`CoreError::InvalidGeometry`] for bad shapes.
    pub fn build(self) -> Result<Robot> {
        let invalid = |reason: String| CoreError::InvalidModel { reason };
        if self.links.is_empty() {
            return Err(invalid(format!("robot `{}` has no links", self.name)));
        }
        let mut link_by_name = HashMap::new();
        for (i, l) in self.links.iter().enumerate() {
            if link_by_name.insert(l.name.clone(), LinkId(i)).is_some() {
                return Err(invalid(format!("duplicate link name `{}`", l.name)));
            }
            for s in l.collisions.iter().chain(&l.visuals) {
                s.geometry.validate()?;
                crate::error::ensure_finite(
                    &format!("shape origin of link `{}`", l.name),
                    s.origin.to_homogeneous().iter().copied(),
                )?;
            }
            if let Some(inertial) = &l.inertial {
                if !(inertial.mass.is_finite() && inertial.mass >= 0.0) {
                    return Err(invalid(format!("link `{}` has invalid mass {}", l.name, inertial.mass)));
                }
            }
        }
        let mut joint_by_name = HashMap::new();
        let mut joints = Vec::with_capacity(self.joints.len());
        let mut parent_joint: Vec<Option<JointId>> = vec![None; self.links.len()];
        let mut child_joints: Vec<Vec<JointId>> = vec![Vec::new(); self.links.len()];
        for (i, spec) in self.joints.iter().enumerate() {
            if joint_by_name.insert(spec.name.clone(), JointId(i)).is_some() {
                return Err(invalid(format!("duplicate joint name `{}`", spec.name)));
            }
            let find = |n: &str| {
                link_by_name
                    .get(n)
                    .copied()
                    .ok_or_else(|| invalid(format!("joint `{}` references unknown link `{n}`", spec.name)))
            };
            let (parent, child) = (find(&spec.parent)?, find(&spec.child)?);
            if parent == child {
                return Err(invalid(format!("joint `{}` connects link `{}` to itself", spec.name, spec.parent)));
            }
            if parent_joint[child.0].is_some() {
                return Err(invalid(format!("link `{}` has more than one parent joint", spec.child)));
            }
            parent_joint[child.0] = Some(JointId(i));
            child_joints[parent.0].push(JointId(i));
            crate::error::ensure_finite(
                &format!("origin of joint `{}`", spec.name),
                spec.origin.to_homogeneous().iter().copied(),
            )?;
            let norm = spec.axis.norm();
            if spec.kind != JointKind::Fixed && !(norm.is_finite() && norm > 1e-12) {
                return Err(invalid(format!("joint `{}` has a zero or non-finite axis", spec.name)));
            }
            let axis =
                if norm.is_finite() && norm > 1e-12 { Unit::new_normalize(spec.axis) } else { Vector3::z_axis() };
            let limits = match spec.kind {
                JointKind::Revolute | JointKind::Prismatic => {
                    let l =
                        spec.limits.ok_or_else(|| invalid(format!("joint `{}` needs position limits", spec.name)))?;
                    if !(l.lower.is_finite() && l.upper.is_finite() && l.lower <= l.upper) {
                        return Err(invalid(format!(
                            "joint `{}` has invalid limits [{}, {}]",
                            spec.name, l.lower, l.upper
                        )));
                    }
                    Some(l)
                }
                JointKind::Continuous | JointKind::Fixed => None,
            };
            joints.push(Joint {
                name: spec.name.clone(),
                kind: spec.kind,
                parent,
                child,
                origin: spec.origin,
                axis,
                limits,
                mimic: None,
                dof: None,
            });
        }
        // Mimic couplings.
        for (i, spec) in self.joints.iter().enumerate() {
            if let Some((leader, multiplier, offset)) = &spec.mimic {
                let lid = *joint_by_name
                    .get(leader)
                    .ok_or_else(|| invalid(format!("joint `{}` mimics unknown joint `{leader}`", spec.name)))?;
                if lid.0 == i || !multiplier.is_finite() || !offset.is_finite() || spec.kind == JointKind::Fixed {
                    return Err(invalid(format!("joint `{}` has an invalid mimic coupling", spec.name)));
                }
                joints[i].mimic = Some(Mimic { leader: lid, multiplier: *multiplier, offset: *offset });
            }
        }
        // Mimic chains must end at a non-mimic joint (no cycles).
        for j in &joints {
            let mut cur = j.mimic;
            let mut steps = 0;
            while let Some(m) = cur {
                steps += 1;
                if steps > joints.len() {
                    return Err(invalid(format!("mimic cycle through joint `{}`", j.name)));
                }
                cur = joints[m.leader.0].mimic;
            }
        }
        let roots: Vec<usize> = (0..self.links.len()).filter(|&i| parent_joint[i].is_none()).collect();
        if roots.len() != 1 {
            let names: Vec<&str> = roots.iter().map(|&i| self.links[i].name.as_str()).collect();
            return Err(invalid(format!("expected exactly one root link, found {names:?}")));
        }
        let root = LinkId(roots[0]);
        // Topological order by breadth-first search from the root; unreachable links mean a cycle.
        let mut topo = Vec::with_capacity(joints.len());
        let mut queue = std::collections::VecDeque::from([root]);
        let mut seen = 1;
        while let Some(l) = queue.pop_front() {
            for &j in &child_joints[l.0] {
                topo.push(j);
                queue.push_back(joints[j.0].child);
                seen += 1;
            }
        }
        if seen != self.links.len() {
            return Err(invalid("the joints form a cycle".to_string()));
        }
        // Configuration order is declaration order, so a URDF's joint order is kept.
        let mut dof_joints = Vec::new();
        for (i, joint) in joints.iter_mut().enumerate() {
            if joint.kind != JointKind::Fixed && joint.mimic.is_none() {
                joint.dof = Some(dof_joints.len());
                dof_joints.push(JointId(i));
            }
        }
        let mut allowed_pairs: HashSet<(LinkId, LinkId)> = joints.iter().map(|j| ordered(j.parent, j.child)).collect();
        for (a, b) in &self.allowed {
            let find =
                |n: &str| link_by_name.get(n).copied().ok_or_else(|| CoreError::UnknownLink { name: n.to_string() });
            allowed_pairs.insert(ordered(find(a)?, find(b)?));
        }
        Ok(Robot {
            name: self.name,
            links: self.links,
            joints,
            root,
            parent_joint,
            child_joints,
            topo_joints: topo,
            dof_joints,
            link_by_name,
            joint_by_name,
            groups: Vec::new(),
            allowed_pairs,
        })
    }
}
