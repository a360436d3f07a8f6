//! A problem set with its robot loaded: problems as benchmark scene instances.

use std::sync::Arc;

use nalgebra::Isometry3;
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{samples, JointGroup, LinkId, Robot};
use opengrasp_core::scene::{RobotId, Scene, StaticBody};
use opengrasp_core::srdf::Srdf;
use opengrasp_core::urdf::{self, LoadOptions, Visuals};

use super::{Configuration, GoalSpec, PoseSpec, ProblemSet};
use crate::benchmark::SceneInstance;
use crate::error::{MotionError, Result};
use crate::problem::{Goal, PoseGoal};
use crate::validity::cover::GreedyCoverOptions;
use crate::validity::{
    CollisionChecker, MeshCover, ObstaclePrimitive, SelfCollisionPairs, SphereWorld, StateValidityChecker,
};

/// What the planner of a problem-set instance checks states with. The benchmark's
/// validators always use the exact checker.
#[derive(Clone, Debug, Default)]
pub enum PlanningModel {
    /// The exact checker (default).
    #[default]
    Exact,
    /// A sphere model of the robot ([`LoadedProblemSet::sphere_model`]), placed in each
    /// problem by [`SphereWorld::for_problem`]. Problems with mesh obstacles are refused.
    Spheres(Arc<SphereWorld>),
}

/// One problem, checked against the robot.
#[derive(Clone, Debug)]
struct Resolved {
    name: String,
    bodies: Vec<StaticBody>,
    q_full: Vec<f64>,
    start: Vec<f64>,
    goal: Goal,
    allowed: Vec<(LinkId, LinkId)>,
}

/// A problem set with its robot loaded and every problem checked against it (group
/// dimensions, joint and link names, shapes, mesh files), ready to become
/// [`SceneInstance`]s.
#[derive(Clone, Debug)]
pub struct LoadedProblemSet {
    name: String,
    robot: Arc<Robot>,
    group: JointGroup,
    tip: Option<LinkId>,
    base_pose: Isometry3<f64>,
    problems: Vec<Resolved>,
}

impl LoadedProblemSet {
    /// Loads the set's robot (URDF without visuals, SRDF applied; or a stock robot) and
    /// resolves every problem.
    ///
    /// The end-effector link (`tip`) is the set's, or else the `parent_link` of the SRDF's
    /// first end effector whose parent group is the planning group.
    ///
    /// # Errors
    /// [`MotionError::Core`](crate::MotionError::Core) for robot files that do not load or an
    /// unknown group; [`MotionError::ProblemSetInvalid`](crate::MotionError::ProblemSetInvalid)
    /// for configurations of the wrong length, unknown joints or links, bad shapes;
    /// [`MotionError::ProblemSetIo`](crate::MotionError::ProblemSetIo) for missing mesh files.
    pub fn new(set: &ProblemSet) -> Result<Self> {
        set.validate()?;
        let spec = &set.robot;
        let mut srdf_tip = None;
        let robot = match (&spec.urdf, spec.stock.as_deref()) {
            (Some(path), _) => {
                let options = LoadOptions {
                    visuals: Visuals::Skip,
                    packages: spec.packages.iter().map(|(n, d)| (n.clone(), set.resolve(d))).collect(),
                    ..LoadOptions::default()
                };
                let mut robot = urdf::load_file_with(set.resolve(path), &options)?.robot;
                if let Some(srdf) = &spec.srdf {
                    let srdf = Srdf::load_file(set.resolve(srdf))?;
                    srdf.apply(&mut robot)?;
                    srdf_tip = srdf
                        .end_effectors
                        .iter()
                        .find(|e| e.parent_group.is_some() && e.parent_group == spec.group)
                        .map(|e| e.parent_link.clone());
                }
                robot
            }
            (None, Some("seven_dof_arm")) => samples::seven_dof_arm()?,
            (None, Some("planar_arm")) => samples::planar_arm(&[0.5, 0.4])?,
            (None, other) => {
                return Err(
                    set.invalid("robot.stock", format!("unknown stock robot {other:?} (seven_dof_arm, planar_arm)"))
                )
            }
        };
        let group = match &spec.group {
            Some(g) => robot.group(g)?.clone(),
            None => JointGroup::all(&robot, "all")?,
        };
        let tip = match set.tip.as_ref().or(srdf_tip.as_ref()) {
            Some(name) => Some(robot.link_id(name).map_err(|_| set.invalid("tip", format!("no link `{name}`")))?),
            None => None,
        };
        let base_pose = set.pose(&set.base_pose.unwrap_or_default(), "base_pose")?;
        let mut loaded =
            Self { name: set.name.clone(), robot: Arc::new(robot), group, tip, base_pose, problems: Vec::new() };
        for i in 0..set.problems.len() {
            let r = loaded.resolve(set, i)?;
            loaded.problems.push(r);
        }
        Ok(loaded)
    }

    fn resolve(&self, set: &ProblemSet, i: usize) -> Result<Resolved> {
        let p = &set.problems[i];
        let field = |s: &str| format!("problems[{i}].{s}");
        let robot = &*self.robot;
        let mut q_full = robot.home_configuration();
        for (name, &v) in &p.joints {
            let d = robot
                .dof_index(name)
                .map_err(|_| set.invalid(field(&format!("joints.{name}")), "not a joint the robot moves"))?;
            q_full[d] = v;
        }
        let start = self.configuration(set, &p.start, &field("start"), Some(&mut q_full))?;
        let goal = match &p.goal {
            GoalSpec::Configuration(c) => {
                Goal::Configuration(self.configuration(set, c, &field("goal.configuration"), None)?)
            }
            GoalSpec::Configurations(cs) => Goal::ConfigurationSet(
                cs.iter()
                    .enumerate()
                    .map(|(k, c)| self.configuration(set, c, &field(&format!("goal.configurations[{k}]")), None))
                    .collect::<Result<_>>()?,
            ),
            GoalSpec::Pose(g) => {
                let f = field("goal.pose.link");
                let tip = robot.link_id(&g.link).map_err(|_| set.invalid(f, format!("no link `{}`", g.link)))?;
                let world =
                    set.pose(&PoseSpec { position: g.position, orientation: g.orientation }, &field("goal.pose"))?;
                Goal::Pose(PoseGoal {
                    tip,
                    target: self.base_pose.inverse() * world,
                    position_tolerance: g.position_tolerance,
                    orientation_tolerance: g.orientation_tolerance,
                })
            }
        };
        let bodies = p
            .obstacles
            .iter()
            .enumerate()
            .map(|(k, o)| set.body(o, &field(&format!("obstacles[{k}]"))))
            .collect::<Result<_>>()?;
        // Pairs naming something other than two robot links (e.g. world objects in a MoveIt
        // matrix) are ignored; pairs the robot already allows are skipped.
        let allowed = p
            .allowed_collisions
            .iter()
            .filter_map(|[a, b]| Some((robot.link_id(a).ok()?, robot.link_id(b).ok()?)))
            .filter(|&(a, b)| a != b && !robot.is_collision_allowed(a, b))
            .collect();
        Ok(Resolved { name: p.name.clone().unwrap_or_else(|| format!("{i}")), bodies, q_full, start, goal, allowed })
    }

    /// Group values of `c`; named values outside the group go to `q_full` when given.
    fn configuration(
        &self,
        set: &ProblemSet,
        c: &Configuration,
        field: &str,
        mut q_full: Option<&mut Vec<f64>>,
    ) -> Result<Vec<f64>> {
        let robot = &*self.robot;
        match c {
            Configuration::Values(v) => {
                if v.len() != self.group.len() {
                    return Err(set.invalid(field, format!("{} values, the group has {}", v.len(), self.group.len())));
                }
                Ok(v.clone())
            }
            Configuration::Named(m) => {
                let mut out = Vec::with_capacity(self.group.len());
                for name in self.group.dofs().iter().map(|&d| robot.joints()[robot.dof_joint(d).0].name.as_str()) {
                    let v =
                        m.get(name).ok_or_else(|| set.invalid(field, format!("no value for group joint `{name}`")))?;
                    out.push(*v);
                }
                for (name, &v) in m {
                    match robot.dof_index(name) {
                        Ok(d) => {
                            if let Some(q) = q_full.as_deref_mut() {
                                if !self.group.dofs().contains(&d) {
                                    q[d] = v;
                                }
                            }
                        }
                        Err(_) if robot.joint_id(name).is_ok() => {}
                        Err(_) => return Err(set.invalid(format!("{field}.{name}"), "the robot has no such joint")),
                    }
                }
                Ok(out)
            }
        }
    }

    /// The set's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Number of problems.
    pub fn len(&self) -> usize {
        self.problems.len()
    }

    /// True if the set has no problem (never, for a loaded set).
    pub fn is_empty(&self) -> bool {
        self.problems.is_empty()
    }

    /// The robot.
    pub fn robot(&self) -> &Arc<Robot> {
        &self.robot
    }

    /// The planning group.
    pub fn group(&self) -> &JointGroup {
        &self.group
    }

    /// The end-effector link, if known.
    pub fn tip(&self) -> Option<LinkId> {
        self.tip
    }

    /// Name of problem `i` (its number for MBM sets), or `None` past the end.
    pub fn problem_name(&self, i: usize) -> Option<&str> {
        self.problems.get(i).map(|p| p.name.as_str())
    }

    /// The goal of problem `i`, or `None` past the end.
    pub fn goal(&self, i: usize) -> Option<&Goal> {
        self.problems.get(i).map(|p| &p.goal)
    }

    /// Problem `i`'s world: the robot (at the base pose, in the problem's start
    /// configuration) among the problem's obstacles — what a viewer or exporter draws.
    ///
    /// # Errors
    /// As [`LoadedProblemSet::instance`].
    pub fn scene(&self, i: usize) -> Result<Scene> {
        Ok(self.world(self.problem(i)?)?.0)
    }

    fn problem(&self, i: usize) -> Result<&Resolved> {
        self.problems.get(i).ok_or_else(|| crate::MotionError::InvalidParameter {
            name: "problem",
            reason: format!("index {i} out of range (the set has {})", self.problems.len()),
        })
    }

    fn world(&self, p: &Resolved) -> Result<(Scene, RobotId)> {
        let mut scene = Scene::new(format!("{} / {}", self.name, p.name));
        let id = scene.add_robot(self.robot.name(), self.robot.clone(), self.base_pose)?;
        scene.set_robot_configuration(id, &p.q_full)?;
        for b in &p.bodies {
            scene.add_body(b.clone())?;
        }
        Ok((scene, id))
    }

    /// The set's robot as a sphere model for planning: its collision shapes covered as
    /// `cover` says (meshes with a guaranteed cover such as [`MeshCover::Greedy`]), at the
    /// set's base pose, self-collision checked exactly on the pairs the robot's SRDF does not
    /// disable ([`SelfCollisionPairs::Robot`]), no obstacles (they come per problem).
    ///
    /// # Errors
    /// As [`SphereWorld::with_mesh_cover`].
    pub fn sphere_model(&self, cover: MeshCover) -> Result<SphereWorld> {
        let q_full = self.robot.home_configuration();
        let world = SphereWorld::with_mesh_cover(
            self.robot.clone(),
            self.group.clone(),
            q_full,
            self.base_pose,
            Vec::new(),
            cover,
        )?;
        Ok(world.with_self_collision(SelfCollisionPairs::Robot))
    }

    /// The set's robot as a layered sphere model for planning: the greedy cover of
    /// `options` ([`MeshCover::Greedy`]), with a coarse greedy cover of three times its
    /// overhang budget tried first ([`SphereWorld::with_coarse_cover`]) and its pair distance
    /// tables built ([`SphereWorld::with_pair_tables`]: every problem of the set shares them);
    /// see [`LoadedProblemSet::sphere_model`].
    ///
    /// # Errors
    /// As [`LoadedProblemSet::sphere_model`].
    pub fn layered_sphere_model(&self, options: GreedyCoverOptions) -> Result<SphereWorld> {
        let coarse = GreedyCoverOptions { max_overhang: 3.0 * options.max_overhang, ..options };
        let layered = self.sphere_model(MeshCover::Greedy(options))?.with_coarse_cover(MeshCover::Greedy(coarse))?;
        Ok(layered.with_pair_tables(true))
    }

    /// Problem `i` in the sphere model `model` (from [`LoadedProblemSet::sphere_model`]):
    /// its obstacles as closed-form solids, its joints outside the group and its allowed
    /// link pairs.
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`] for `i` out of range or a mesh obstacle (the sphere
    /// model takes boxes, spheres, cylinders and capsules).
    pub fn sphere_world(&self, i: usize, model: &SphereWorld) -> Result<SphereWorld> {
        let p = self.problem(i)?;
        let mut obstacles = Vec::new();
        for b in &p.bodies {
            for shape in &b.shapes {
                let solid = ObstaclePrimitive::from_geometry(b.name.clone(), b.pose * shape.origin, &shape.geometry)
                    .map_err(|_| MotionError::InvalidParameter {
                        name: "obstacle",
                        reason: format!(
                            "`{}` of problem `{}` is a mesh; the sphere model takes boxes, spheres, cylinders and \
                             capsules",
                            b.name, p.name
                        ),
                    })?;
                obstacles.push(solid);
            }
        }
        model.for_problem(p.q_full.clone(), obstacles, &p.allowed)
    }

    /// Problem `i` as a scene instance whose planner checks states with `model` (graded by
    /// the exact checker either way, see [`LoadedProblemSet::instance`]).
    ///
    /// # Errors
    /// As [`LoadedProblemSet::instance`] and [`LoadedProblemSet::sphere_world`].
    pub fn instance_with(&self, i: usize, model: &PlanningModel) -> Result<SceneInstance> {
        let mut instance = self.instance(i)?;
        if let PlanningModel::Spheres(world) = model {
            let planning: Box<dyn StateValidityChecker> = Box::new(self.sphere_world(i, world)?);
            instance.planning_checker = Some(planning);
        }
        Ok(instance)
    }

    /// Problem `i` as a scene instance: the robot at the base pose among the problem's
    /// obstacles, validated by the exact [`CollisionChecker`] (the problem's allowed pairs
    /// added to the robot's).
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`](crate::MotionError::InvalidParameter) for `i` out of
    /// range; core errors building the scene or collision world (e.g. a configuration outside
    /// the joints outside the group's limits).
    pub fn instance(&self, i: usize) -> Result<SceneInstance> {
        let p = self.problem(i)?;
        let (scene, id) = self.world(p)?;
        let mut world = CollisionWorld::new(&scene)?;
        for &(a, b) in &p.allowed {
            world.allow_collision(id, a, b)?;
        }
        let checker =
            CollisionChecker::new(Arc::new(world), id, self.robot.clone(), self.group.clone(), p.q_full.clone())?;
        Ok(SceneInstance {
            robot: self.robot.clone(),
            group: self.group.clone(),
            q_full: p.q_full.clone(),
            tip: self.tip,
            start: p.start.clone(),
            goal: p.goal.clone(),
            checker: Box::new(checker),
            planning_checker: None,
            certifier: None,
        })
    }
}
