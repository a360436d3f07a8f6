//! Joint groups: the named subsets of joints that planners work on.

use super::robot::Robot;
use crate::error::{CoreError, Result};

/// A named, ordered subset of a robot's actuated joints (e.g. "hip + right arm").
///
/// Planners sample and interpolate in group space; [`JointGroup::insert`] writes group values
/// into a full configuration so the rest of the robot keeps its pose.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JointGroup {
    name: String,
    joint_names: Vec<String>,
    dofs: Vec<usize>,
}

impl JointGroup {
    /// A group of the named actuated joints of `robot`, in the given order.
    ///
    /// # Errors
    /// [`CoreError::EmptyJointGroup`], [`CoreError::UnknownJoint`],
    /// [`CoreError::NotActuated`] (fixed or mimic joint), or [`CoreError::InvalidModel`] for a
    /// joint listed twice.
    pub fn new(robot: &Robot, name: &str, joints: &[&str]) -> Result<Self> {
        if joints.is_empty() {
            return Err(CoreError::EmptyJointGroup { name: name.to_string() });
        }
        let mut dofs = Vec::with_capacity(joints.len());
        for j in joints {
            let d = robot.dof_index(j)?;
            if dofs.contains(&d) {
                return Err(CoreError::InvalidModel { reason: format!("joint `{j}` listed twice in group `{name}`") });
            }
            dofs.push(d);
        }
        Ok(Self { name: name.to_string(), joint_names: joints.iter().map(|s| s.to_string()).collect(), dofs })
    }

    /// A group of every actuated joint of `robot`, in configuration order.
    ///
    /// # Errors
    /// [`CoreError::EmptyJointGroup`] if the robot has no actuated joints.
    pub fn all(robot: &Robot, name: &str) -> Result<Self> {
        let names: Vec<&str> = robot.dof_joints().iter().map(|&j| robot.joint(j).name.as_str()).collect();
        Self::new(robot, name, &names)
    }

    /// The group's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Names of the joints, in group order.
    pub fn joint_names(&self) -> &[String] {
        &self.joint_names
    }
    /// Configuration indices of the joints, in group order.
    pub fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    /// Number of joints.
    pub fn len(&self) -> usize {
        self.dofs.len()
    }
    /// Always false: groups are never empty.
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// The group's values taken from a full configuration.
    pub fn extract(&self, q_full: &[f64]) -> Vec<f64> {
        self.dofs.iter().map(|&d| q_full[d]).collect()
    }

    /// Writes group values into a full configuration.
    ///
    /// # Errors
    /// [`CoreError::DimensionMismatch`] if `q_group` does not have [`JointGroup::len`] values.
    pub fn insert(&self, q_full: &mut [f64], q_group: &[f64]) -> Result<()> {
        if q_group.len() != self.dofs.len() {
            return Err(CoreError::DimensionMismatch { expected: self.dofs.len(), actual: q_group.len() });
        }
        for (&d, &v) in self.dofs.iter().zip(q_group) {
            q_full[d] = v;
        }
        Ok(())
    }

    /// Position limits `(lower, upper)` of each joint of the group.
    pub fn limits(&self, robot: &Robot) -> Vec<(f64, f64)> {
        self.dofs.iter().map(|&d| robot.dof_limits(d)).collect()
    }
}
