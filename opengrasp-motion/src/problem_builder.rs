//! [`ProblemBuilder`]: a planning query with defaults, so that a caller names only what
//! differs (start, goal) and never builds a full configuration by hand.

use std::time::Duration;

use opengrasp_core::model::{JointGroup, Robot};

use crate::error::{MotionError, Result};
use crate::problem::{Goal, PlanningProblem};
use crate::validity::StateValidityChecker;

/// An owned planning query with defaults, lent out as a [`PlanningProblem`] by
/// [`ProblemBuilder::problem`]. Made by [`PlanningProblem::builder`].
///
/// Defaults: joints outside the group at the robot's
/// [home configuration](Robot::home_configuration) (so a group that covers every joint needs
/// no full configuration at all), time limit 10 s, seed 0, discrete step
/// [`DEFAULT_STEP`](crate::validate::DEFAULT_STEP).
///
/// ```
/// use std::sync::Arc;
/// use nalgebra::{Isometry3, Vector3};
/// use opengrasp_core::model::{samples, JointGroup};
/// use opengrasp_motion::planners::RrtConnect;
/// use opengrasp_motion::validity::{ObstacleBox, SphereWorld};
/// use opengrasp_motion::{MotionPlanner, PlanningProblem};
///
/// # fn main() -> opengrasp_motion::Result<()> {
/// let robot = Arc::new(samples::planar_arm(&[0.5, 0.4])?);
/// let group = JointGroup::all(&robot, "arm")?;
/// let post = ObstacleBox::new("post", Isometry3::translation(0.6, 0.0, 0.0), Vector3::new(0.1, 0.1, 0.5));
/// let world = SphereWorld::new(robot.clone(), group.clone(), vec![0.0, 0.0], Isometry3::identity(), vec![post])?;
/// let query = PlanningProblem::builder(&robot, &group, &world).start([1.2, 0.3]).goal_configuration([-1.2, 0.3]).seed(7);
/// let solution = RrtConnect::default().plan(&query.problem()?)?;
/// assert_eq!(solution.path.last().map(Vec::as_slice), Some(&[-1.2, 0.3][..]));
/// # Ok(())
/// # }
/// ```
pub struct ProblemBuilder<'a> {
    robot: &'a Robot,
    group: &'a JointGroup,
    checker: &'a dyn StateValidityChecker,
    q_full: Vec<f64>,
    start: Option<Vec<f64>>,
    goal: Option<Goal>,
    time_limit: Duration,
    seed: u64,
    step: f64,
}

impl<'a> PlanningProblem<'a> {
    /// A [`ProblemBuilder`] for `group` of `robot` validated by `checker`.
    pub fn builder(
        robot: &'a Robot,
        group: &'a JointGroup,
        checker: &'a dyn StateValidityChecker,
    ) -> ProblemBuilder<'a> {
        ProblemBuilder {
            robot,
            group,
            checker,
            q_full: robot.home_configuration(),
            start: None,
            goal: None,
            time_limit: Duration::from_secs(10),
            seed: 0,
            step: crate::validate::DEFAULT_STEP,
        }
    }
}

impl ProblemBuilder<'_> {
    /// The start configuration (group values).
    pub fn start(mut self, q: impl Into<Vec<f64>>) -> Self {
        self.start = Some(q.into());
        self
    }

    /// The goal.
    pub fn goal(mut self, goal: Goal) -> Self {
        self.goal = Some(goal);
        self
    }

    /// A single goal configuration (group values).
    pub fn goal_configuration(self, q: impl Into<Vec<f64>>) -> Self {
        self.goal(Goal::Configuration(q.into()))
    }

    /// The full configuration holding the joints outside the group (default: home).
    pub fn q_full(mut self, q: impl Into<Vec<f64>>) -> Self {
        self.q_full = q.into();
        self
    }

    /// The planning time limit (default 10 s).
    pub fn time_limit(mut self, limit: Duration) -> Self {
        self.time_limit = limit;
        self
    }

    /// The planner's seed (default 0).
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The discrete checking step (default 0.02).
    pub fn step(mut self, step: f64) -> Self {
        self.step = step;
        self
    }

    /// The query as a [`PlanningProblem`] borrowing this builder, checked with
    /// [`PlanningProblem::validate`].
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`] if the start or the goal was not given; the errors
    /// of [`PlanningProblem::validate`].
    pub fn problem(&self) -> Result<PlanningProblem<'_>> {
        let missing = |name| MotionError::InvalidParameter { name, reason: "not given".into() };
        let problem = PlanningProblem {
            robot: self.robot,
            group: self.group,
            q_full: &self.q_full,
            start: self.start.as_deref().ok_or_else(|| missing("start"))?,
            goal: self.goal.as_ref().ok_or_else(|| missing("goal"))?,
            checker: self.checker,
            time_limit: self.time_limit,
            seed: self.seed,
            step: self.step,
        };
        problem.validate()?;
        Ok(problem)
    }
}
