//! Links, joints and the robot tree.

use std::collections::{HashMap, HashSet};

use nalgebra::{Isometry3, Matrix3, Unit, Vector3};

use super::geometry::Shape;
use crate::error::{CoreError, Result};

/// Index of a link in [`Robot::links`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LinkId(pub usize);

/// Index of a joint in [`Robot::joints`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct JointId(pub usize);

/// Mass properties of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct Inertial {
    /// Pose of the centre of mass (and inertia frame) in the link frame.
    pub origin: Isometry3<f64>,
    /// Mass (kg).
    pub mass: f64,
    /// Inertia tensor about the centre of mass, in the inertial frame (kg·m²).
    pub inertia: Matrix3<f64>,
}

impl Inertial {
    /// Mass properties of a solid box of full size `size` and mass `mass`, centred at `origin`.
    pub fn solid_box(mass: f64, size: Vector3<f64>, origin: Isometry3<f64>) -> Self {
        let (x2, y2, z2) = (size.x * size.x, size.y * size.y, size.z * size.z);
        let inertia = Matrix3::from_diagonal(&Vector3::new(y2 + z2, x2 + z2, x2 + y2)) * (mass / 12.0);
        Self { origin, mass, inertia }
    }

    /// Mass properties of a solid cylinder along local z.
    pub fn solid_cylinder(mass: f64, radius: f64, length: f64, origin: Isometry3<f64>) -> Self {
        let ixx = mass * (3.0 * radius * radius + length * length) / 12.0;
        let izz = mass * radius * radius / 2.0;
        Self { origin, mass, inertia: Matrix3::from_diagonal(&Vector3::new(ixx, ixx, izz)) }
    }

    /// Mass properties of a solid sphere.
    pub fn solid_sphere(mass: f64, radius: f64, origin: Isometry3<f64>) -> Self {
        let i = 0.4 * mass * radius * radius;
        Self { origin, mass, inertia: Matrix3::from_diagonal_element(i) }
    }

    /// True if the mass is positive and the inertia tensor symmetric positive definite.
    pub fn is_physical(&self) -> bool {
        self.mass.is_finite()
            && self.mass > 0.0
            && (self.inertia - self.inertia.transpose()).norm() <= 1e-9 * self.inertia.norm().max(1e-12)
            && self.inertia.symmetric_eigenvalues().iter().all(|&l| l > 0.0)
    }
}

/// A rigid body of the robot.
#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    /// Unique name.
    pub name: String,
    /// Mass properties, if known.
    pub inertial: Option<Inertial>,
    /// Geometry for display.
    pub visuals: Vec<Shape>,
    /// Geometry for collision checking.
    pub collisions: Vec<Shape>,
}

impl Link {
    /// A link with no geometry and no mass.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), inertial: None, visuals: Vec::new(), collisions: Vec::new() }
    }

    /// Adds a shape used both for display and collision.
    pub fn with_shape(mut self, shape: Shape) -> Self {
        self.visuals.push(shape.clone());
        self.collisions.push(shape);
        self
    }

    /// Sets the mass properties.
    pub fn with_inertial(mut self, inertial: Inertial) -> Self {
        self.inertial = Some(inertial);
        self
    }
}

/// The kind of motion a joint allows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// No motion.
    Fixed,
    /// Rotation about the axis within limits.
    Revolute,
    /// Unlimited rotation about the axis.
    Continuous,
    /// Translation along the axis within limits.
    Prismatic,
}

/// Position, velocity and effort limits of a joint (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    /// Lowest position (rad or m).
    pub lower: f64,
    /// Highest position (rad or m).
    pub upper: f64,
    /// Maximum speed (rad/s or m/s).
    pub velocity: f64,
    /// Maximum effort (N·m or N).
    pub effort: f64,
}

/// A joint whose position follows another: `q = multiplier * q_leader + offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mimic {
    /// The joint followed.
    pub leader: JointId,
    /// Coupling ratio.
    pub multiplier: f64,
    /// Offset (rad or m).
    pub offset: f64,
}

/// A joint connecting a parent link to a child link.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Unique name.
    pub name: String,
    /// Kind of motion.
    pub kind: JointKind,
    /// Parent link.
    pub parent: LinkId,
    /// Child link.
    pub child: LinkId,
    /// Pose of the joint frame in the parent link frame (at zero joint position the child
    /// link frame coincides with it).
    pub origin: Isometry3<f64>,
    /// Unit axis of rotation/translation in the joint frame.
    pub axis: Unit<Vector3<f64>>,
    /// Limits (`None` for fixed and continuous joints).
    pub limits: Option<JointLimits>,
    /// Coupling to a leader joint, for mimic joints.
    pub mimic: Option<Mimic>,
    /// Index in the configuration vector, for actuated joints (movable and not mimic).
    pub dof: Option<usize>,
}

impl Joint {
    /// True for revolute, continuous and prismatic joints.
    pub fn is_movable(&self) -> bool {
        self.kind != JointKind::Fixed
    }

    /// The joint's motion for position `value`: the transform from joint frame to child frame.
    pub fn motion(&self, value: f64) -> Isometry3<f64> {
        match self.kind {
            JointKind::Fixed => Isometry3::identity(),
            JointKind::Revolute | JointKind::Continuous => Isometry3::from_parts(
                nalgebra::Translation3::identity(),
                nalgebra::UnitQuaternion::from_axis_angle(&self.axis, value),
            ),
            JointKind::Prismatic => {
                Isometry3::translation(self.axis.x * value, self.axis.y * value, self.axis.z * value)
            }
        }
    }
}

/// Description of a joint for [`RobotBuilder::joint`], using link and joint names.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpec {
    /// Unique name.
    pub name: String,
    /// Kind of motion.
    pub kind: JointKind,
    /// Parent link name.
    pub parent: String,
    /// Child link name.
    pub child: String,
    /// Pose of the joint frame in the parent link frame.
    pub origin: Isometry3<f64>,
    /// Axis in the joint frame (normalised by the builder).
    pub axis: Vector3<f64>,
    /// Limits; required for revolute and prismatic joints.
    pub limits: Option<JointLimits>,
    /// `(leader joint name, multiplier, offset)` for mimic joints.
    pub mimic: Option<(String, f64, f64)>,
}

impl JointSpec {
    /// A joint spec with identity origin, z axis and no limits.
    pub fn new(name: impl Into<String>, kind: JointKind, parent: impl Into<String>, child: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            kind,
            parent: parent.into(),
            child: child.into(),
            origin: Isometry3::identity(),
            axis: Vector3::z(),
            limits: None,
            mimic: None,
        }
    }

    /// Sets the joint origin in the parent frame.
    pub fn origin(mut self, origin: Isometry3<f64>) -> Self {
        self.origin = origin;
        self
    }

    /// Sets the axis.
    pub fn axis(mut self, axis: Vector3<f64>) -> Self {
        self.axis = axis;
        self
    }

    /// Sets position limits, with velocity and effort limits.
    pub fn limits(mut self, lower: f64, upper: f64, velocity: f64, effort: f64) -> Self {
        self.limits = Some(JointLimits { lower, upper, velocity, effort });
        self
    }

    /// Makes this joint follow `leader`.
    pub fn mimic(mut self, leader: impl Into<String>, multiplier: f64, offset: f64) -> Self {
        self.mimic = Some((leader.into(), multiplier, offset));
        self
    }
}

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
