//! Planning problems, goals, solutions and the [`MotionPlanner`] trait users implement.

use std::time::{Duration, Instant};

use nalgebra::Isometry3;
use opengrasp_core::kinematics::{link_pose_unchecked, solve_ik, IkOptions, IkStatus};
use opengrasp_core::model::{JointGroup, LinkId, Robot};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::error::{MotionError, Result};
use crate::validity::StateValidityChecker;

/// What the robot must reach.
#[derive(Clone, Debug, PartialEq)]
pub enum Goal {
    /// One goal configuration (group values).
    Configuration(Vec<f64>),
    /// Any of several goal configurations (group values), e.g. precomputed IK solutions.
    ConfigurationSet(Vec<Vec<f64>>),
    /// A pose of a link (e.g. a grasp pose of the hand), reached through inverse kinematics.
    Pose(PoseGoal),
}

impl Goal {
    /// A short name of the goal kind ("configuration", "configuration set", "pose").
    pub fn kind(&self) -> &'static str {
        match self {
            Goal::Configuration(_) => "configuration",
            Goal::ConfigurationSet(_) => "configuration set",
            Goal::Pose(_) => "pose",
        }
    }
}

/// A workspace goal: link `tip` at `target` (in the robot's root frame).
#[derive(Clone, Debug, PartialEq)]
pub struct PoseGoal {
    /// The link that must reach the target (e.g. the hand's TCP link).
    pub tip: LinkId,
    /// Target pose of the tip in the robot's root frame.
    pub target: Isometry3<f64>,
    /// Accepted position error (m).
    pub position_tolerance: f64,
    /// Accepted orientation error (rad); `π` or more means any orientation (position-only
    /// goal, solved with position-only IK).
    pub orientation_tolerance: f64,
}

impl PoseGoal {
    /// Position and orientation error of the tip at full configuration `q_full`.
    pub fn error(&self, robot: &Robot, q_full: &[f64]) -> (f64, f64) {
        let pose = link_pose_unchecked(robot, q_full, self.tip);
        let dp = (pose.translation.vector - self.target.translation.vector).norm();
        let dr = pose.rotation.angle_to(&self.target.rotation);
        (dp, dr)
    }
}

/// Everything a planner needs to plan one motion.
pub struct PlanningProblem<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// The joints to plan for; configurations are group vectors.
    pub group: &'a JointGroup,
    /// Full configuration ([`Robot::dof`] values) holding the joints outside the group.
    pub q_full: &'a [f64],
    /// Start configuration (group values).
    pub start: &'a [f64],
    /// The goal.
    pub goal: &'a Goal,
    /// The validity checker (group configurations).
    pub checker: &'a dyn StateValidityChecker,
    /// Wall-clock budget of [`MotionPlanner::plan`].
    pub time_limit: Duration,
    /// Seed of the planner's random generator (`ChaCha8Rng::seed_from_u64`).
    pub seed: u64,
    /// Discrete checking step along path segments (C-space norm, default
    /// [`DEFAULT_STEP`](crate::validate::DEFAULT_STEP) = 0.02).
    pub step: f64,
}

impl PlanningProblem<'_> {
    /// Group joint limits `(lower, upper)`.
    pub fn limits(&self) -> Vec<(f64, f64)> {
        self.group.limits(self.robot)
    }

    /// Checks dimensions, finiteness, limits and validity of start and goal configurations.
    ///
    /// # Errors
    /// [`MotionError::DimensionMismatch`], [`MotionError::NonFinite`],
    /// [`MotionError::OutOfLimits`], [`MotionError::InvalidState`] or
    /// [`MotionError::InvalidParameter`] (step, full configuration).
    pub fn validate(&self) -> Result<()> {
        if !(self.step > 0.0 && self.step.is_finite()) {
            return Err(MotionError::InvalidParameter { name: "step", reason: format!("{} is not > 0", self.step) });
        }
        if self.q_full.len() != self.robot.dof() {
            return Err(MotionError::DimensionMismatch { expected: self.robot.dof(), actual: self.q_full.len() });
        }
        if self.checker.dim() != self.group.len() {
            return Err(MotionError::DimensionMismatch { expected: self.group.len(), actual: self.checker.dim() });
        }
        self.check_configuration("start", self.start)?;
        if !self.checker.is_valid(self.start) {
            return Err(MotionError::InvalidState { what: "start" });
        }
        match self.goal {
            Goal::Configuration(q) => {
                self.check_configuration("goal", q)?;
                if !self.checker.is_valid(q) {
                    return Err(MotionError::InvalidState { what: "goal" });
                }
            }
            Goal::ConfigurationSet(set) => {
                if set.is_empty() {
                    return Err(MotionError::InvalidParameter { name: "goal", reason: "empty goal set".into() });
                }
                for q in set {
                    self.check_configuration("goal", q)?;
                }
                if !set.iter().any(|q| self.checker.is_valid(q)) {
                    return Err(MotionError::InvalidState { what: "goal" });
                }
            }
            Goal::Pose(p) => {
                if p.tip.0 >= self.robot.links().len() {
                    return Err(MotionError::InvalidParameter { name: "goal", reason: "tip link out of range".into() });
                }
                let v = p.target.to_homogeneous();
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(MotionError::NonFinite { what: "goal pose" });
                }
            }
        }
        Ok(())
    }

    fn check_configuration(&self, what: &'static str, q: &[f64]) -> Result<()> {
        if q.len() != self.group.len() {
            return Err(MotionError::DimensionMismatch { expected: self.group.len(), actual: q.len() });
        }
        for (index, (&value, (lower, upper))) in q.iter().zip(self.limits()).enumerate() {
            if !value.is_finite() {
                return Err(MotionError::NonFinite { what });
            }
            if value < lower - 1e-9 || value > upper + 1e-9 {
                return Err(MotionError::OutOfLimits { what, index, value, lower, upper });
            }
        }
        Ok(())
    }

    /// The full configuration for group values `q`.
    pub fn full_configuration(&self, q: &[f64]) -> Vec<f64> {
        let mut full = self.q_full.to_vec();
        for (&d, &v) in self.group.dofs().iter().zip(q) {
            full[d] = v;
        }
        full
    }

    /// A uniformly random configuration within the group limits.
    pub fn sample_uniform(&self, rng: &mut ChaCha8Rng, limits: &[(f64, f64)], out: &mut Vec<f64>) {
        out.clear();
        out.extend(limits.iter().map(|&(lo, hi)| lo + (hi - lo) * rng.random::<f64>()));
    }

    /// True if the group configuration `q` satisfies the goal (configurations within `1e-6`,
    /// poses within the goal's tolerances).
    pub fn satisfies_goal(&self, q: &[f64]) -> bool {
        match self.goal {
            Goal::Configuration(g) => crate::validate::distance(g, q) <= 1e-6,
            Goal::ConfigurationSet(set) => set.iter().any(|g| crate::validate::distance(g, q) <= 1e-6),
            Goal::Pose(p) => {
                let (dp, dr) = p.error(self.robot, &self.full_configuration(q));
                dp <= p.position_tolerance && dr <= p.orientation_tolerance
            }
        }
    }

    /// One attempt at a valid goal configuration for a pose goal: IK (one descent, no
    /// restarts) from a uniformly random start, accepted if converged and collision-free.
    /// Returns `None` for other goal kinds or failed attempts.
    pub fn sample_ik_goal(&self, rng: &mut ChaCha8Rng, limits: &[(f64, f64)]) -> Option<Vec<f64>> {
        let Goal::Pose(p) = self.goal else { return None };
        let mut q = Vec::new();
        self.sample_uniform(rng, limits, &mut q);
        let start = self.full_configuration(&q);
        let options = IkOptions {
            position_tolerance: p.position_tolerance * 0.5,
            orientation_tolerance: p.orientation_tolerance * 0.5,
            max_iterations: 60,
            max_restarts: 0,
            seed: rng.random(),
            position_only: p.orientation_tolerance >= std::f64::consts::PI,
            ..IkOptions::default()
        };
        let sol = solve_ik(self.robot, self.group, p.tip, &p.target, &start, &options).ok()?;
        if sol.status != IkStatus::Converged {
            return None;
        }
        let g = self.group.extract(&sol.q);
        if g.iter().zip(limits).any(|(v, (lo, hi))| v < lo || v > hi) || !self.checker.is_valid(&g) {
            return None;
        }
        Some(g)
    }
}

/// Data available to [`MotionPlanner::setup`]: the scene without a query.
pub struct SetupContext<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// The planning group.
    pub group: &'a JointGroup,
    /// Full configuration holding the joints outside the group.
    pub q_full: &'a [f64],
    /// The validity checker of the scene.
    pub checker: &'a dyn StateValidityChecker,
    /// Seed for randomised setup (e.g. roadmap sampling).
    pub seed: u64,
    /// Discrete checking step along segments (default 0.02).
    pub step: f64,
}

/// A planner's answer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// Waypoints (group values) from the start to a goal configuration; consecutive waypoints
    /// are joined by straight C-space segments.
    pub path: Vec<Vec<f64>>,
    /// Planner iterations (e.g. tree extensions or roadmap samples).
    pub iterations: u64,
}

/// A motion planner. Implement this trait (only [`MotionPlanner::plan`] is required) to enter
/// the benchmark; evaluation (validation, metrics, smoothing) is done by the harness.
///
/// `setup` builds what can be reused across queries in the same scene (roadmaps, caches) and is
/// timed separately from `plan`.
///
/// Threading: planners keep state (trees, roadmaps, random streams), so `setup` and `plan` take
/// `&mut self` and the harness gives every job its own instance from a factory; the trait only
/// requires `Send`, so a planner may hold `Cell`s or other non-`Sync` state. (A grasp planner is
/// a pure function of its request, takes `&self` and is shared, hence `Send + Sync`.)
pub trait MotionPlanner: Send {
    /// The planner's name in reports (default: [`opengrasp_core::short_type_name`]).
    fn name(&self) -> &str {
        opengrasp_core::short_type_name::<Self>()
    }

    /// Prepares for queries in a scene (default: nothing).
    ///
    /// # Errors
    /// Planner-specific.
    fn setup(&mut self, context: &SetupContext<'_>) -> Result<()> {
        let _ = context;
        Ok(())
    }

    /// Plans a path from `problem.start` to `problem.goal`, returning
    /// [`MotionError::Timeout`] when the time limit is exhausted.
    ///
    /// # Errors
    /// [`MotionError::Timeout`], invalid-input errors (see [`PlanningProblem::validate`]) or
    /// planner-specific errors.
    fn plan(&mut self, problem: &PlanningProblem<'_>) -> Result<Solution>;
}

impl<T: MotionPlanner + ?Sized> MotionPlanner for Box<T> {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn setup(&mut self, context: &SetupContext<'_>) -> Result<()> {
        (**self).setup(context)
    }
    fn plan(&mut self, problem: &PlanningProblem<'_>) -> Result<Solution> {
        (**self).plan(problem)
    }
}

impl<T: MotionPlanner + ?Sized> MotionPlanner for &mut T {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn setup(&mut self, context: &SetupContext<'_>) -> Result<()> {
        (**self).setup(context)
    }
    fn plan(&mut self, problem: &PlanningProblem<'_>) -> Result<Solution> {
        (**self).plan(problem)
    }
}

/// A deadline helper for planners.
#[derive(Clone, Copy, Debug)]
pub struct Deadline {
    end: Instant,
}

impl Deadline {
    /// A deadline `limit` from now.
    pub fn after(limit: Duration) -> Self {
        Self { end: Instant::now() + limit }
    }
    /// True once the deadline has passed.
    pub fn expired(&self) -> bool {
        Instant::now() >= self.end
    }
}
