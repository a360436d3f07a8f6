//! Benchmark scenes.
//!
//! The seed paper's scenes use an ARMAR-III humanoid in a kitchen:
//!
//! - [`armar_standard_scene`] (scene 1): the ARMAR-III-like humanoid of `opengrasp-assets` in
//!   its kitchen, planning for hip yaw + right arm (group `hip_right_arm`, 8 DoF) from the arm
//!   hanging at its side to the hand above the red table's front edge left of the body (fixed
//!   start and goal; the straight segment between them is in collision).
//!
//! - [`armar_ik_scene`] (scene 2): the same humanoid, a box at a seeded random position on the
//!   red table in front of it, goal = the palm above the box (IK then plan, or IK-RRT).
//!
//! Both plan on a conservative sphere model of the humanoid and the kitchen
//! ([`SceneSphereModel`], the instance's `planning_checker`, built by [`planning_model_for`]):
//! every state it accepts is collision-free under the exact geometry, which stays the judge
//! (validators, metrics and post-processing use the exact checker).
//!
//! Clean the Table (scene 3) is a sequence of queries: see [`crate::clean_table`].
//!
//! Stand-ins on core's 7-DoF sample arm ([`samples::seven_dof_arm`]) in a small "kitchen
//! cupboard" (a table, a shelf board above it and a vertical divider splitting the space
//! between them into a left and a right compartment):
//!
//! - [`standard_scene`] (scene 1, "standard"): fixed start (hand in the left compartment) and
//!   goal (hand in the right compartment) for all seven joints; the arm must leave one
//!   compartment and enter the other.
//! - [`ik_scene`] (scene 2, "IK-based"): a box object at a seeded random position on the table
//!   in front of the robot; the goal is a top-down grasp pose of the hand above it.

use std::sync::Arc;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::kinematics::{solve_ik, IkOptions, IkStatus};
use opengrasp_core::model::{samples, Geometry, JointGroup, Robot, Shape};
use opengrasp_core::scene::{Scene, SceneObject, StaticBody};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use opengrasp_motion::benchmark::{BenchmarkScene, SceneInstance};
use opengrasp_motion::certify::SphereCertifier;
use opengrasp_motion::problem::{Goal, PoseGoal};
use opengrasp_motion::scene_spheres::{SceneModelOptions, SceneSphereModel};
use opengrasp_motion::validity::{CollisionChecker, ObstacleBox, SphereWorld, StateValidityChecker};
use opengrasp_motion::Result;

/// Which collision checker a stand-in scene uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CheckerKind {
    /// Exact checks on core's parry-based collision world (default).
    #[default]
    Exact,
    /// The conservative sphere model ([`SphereWorld`]).
    Spheres,
}

/// The cupboard obstacles of the stand-in scenes (world frame, robot base at the origin).
pub fn cupboard() -> Vec<ObstacleBox> {
    vec![
        ObstacleBox::new("table", Isometry3::translation(0.65, 0.0, 0.225), Vector3::new(0.6, 1.2, 0.05)),
        ObstacleBox::new("shelf", Isometry3::translation(0.65, 0.0, 0.85), Vector3::new(0.6, 1.2, 0.04)),
        ObstacleBox::new("divider", Isometry3::translation(0.7, 0.0, 0.54), Vector3::new(0.5, 0.04, 0.58)),
        ObstacleBox::new("back", Isometry3::translation(0.97, 0.0, 0.54), Vector3::new(0.04, 1.2, 0.58)),
    ]
}

/// Start configuration of the standard stand-in scene (hand in the left compartment).
pub const STANDARD_START: [f64; 7] = [1.4175, 1.026, -1.5041, 1.5464, -0.1228, -0.1075, 1.1446];
/// Goal configuration of the standard stand-in scene (hand in the right compartment).
pub const STANDARD_GOAL: [f64; 7] = [-1.4175, 1.026, 1.5041, 1.5464, 0.1228, -0.1075, -1.1446];

/// Base pose (x, y, yaw) of the humanoid in [`armar_standard_scene`]: 10 cm closer to the red
/// table than the kitchen's start pose, so that the hand reaches over its edge.
pub const ARMAR_BASE: [f64; 3] = [2.0, 1.45, std::f64::consts::FRAC_PI_2];
/// Start of [`armar_standard_scene`] (group `hip_right_arm`: hip yaw, then the right arm):
/// the arm hanging.
pub const ARMAR_START: [f64; 8] = [0.0; 8];
/// World position of the right palm at the goal of [`armar_standard_scene`]: above the red
/// table's front edge, left of the body.
pub const ARMAR_GOAL_PALM: [f64; 3] = [1.85, 1.95, 1.0];

/// The goal configuration of [`armar_standard_scene`]: the first collision-free, converged
/// position-only IK solution for [`ARMAR_GOAL_PALM`] over IK seeds 0, 1, 2, … (deterministic;
/// computed rather than stored so that it follows changes of the asset models).
///
/// # Errors
/// [`opengrasp_motion::MotionError::InvalidState`] if no seed up to 50 gives a valid solution, or core
/// errors.
pub fn armar_standard_goal(
    robot: &Robot,
    group: &JointGroup,
    q_full: &[f64],
    checker: &dyn StateValidityChecker,
) -> Result<Vec<f64>> {
    let tip = robot.link_id("right_hand_palm")?;
    let target = Isometry3::translation(ARMAR_GOAL_PALM[0], ARMAR_GOAL_PALM[1], ARMAR_GOAL_PALM[2]);
    for seed in 0..50 {
        let options = IkOptions { seed, max_restarts: 5, position_only: true, ..IkOptions::default() };
        let sol = solve_ik(robot, group, tip, &target, q_full, &options)?;
        let g = group.extract(&sol.q);
        if sol.status == IkStatus::Converged && checker.is_valid(&g) {
            return Ok(g);
        }
    }
    Err(opengrasp_motion::MotionError::InvalidState { what: "goal" })
}

/// The kitchen with the humanoid at [`ARMAR_BASE`], its collision checker for `group` and the
/// full configuration.
///
/// # Errors
/// Errors from the assets, the scene or the collision world.
pub fn armar_kitchen_checker(group: &str) -> Result<(Arc<Robot>, JointGroup, Vec<f64>, CollisionChecker)> {
    armar_kitchen_checker_with(group, |_| Ok(()))
}

/// As [`armar_kitchen_checker`], after `edit` has changed the kitchen scene (e.g. added an
/// object).
///
/// # Errors
/// Errors from the assets, `edit`, the scene or the collision world.
pub fn armar_kitchen_checker_with(
    group: &str,
    edit: impl FnOnce(&mut Scene) -> Result<()>,
) -> Result<(Arc<Robot>, JointGroup, Vec<f64>, CollisionChecker)> {
    kitchen_parts(group, edit).map(|k| (k.robot, k.group, k.q_full, k.checker))
}

/// What a kitchen instance is made of.
struct KitchenParts {
    robot: Arc<Robot>,
    group: JointGroup,
    q_full: Vec<f64>,
    checker: CollisionChecker,
    certifier: SphereCertifier,
    /// The conservative sphere model the planners search on.
    model: SceneSphereModel,
}

fn kitchen_parts(group: &str, edit: impl FnOnce(&mut Scene) -> Result<()>) -> Result<KitchenParts> {
    let kitchen = opengrasp_assets::scenes::kitchen().map_err(|e| opengrasp_motion::MotionError::Scene(Box::new(e)))?;
    let mut scene = kitchen.scene.clone();
    edit(&mut scene)?;
    let robot = scene.robot(kitchen.robot)?.robot.clone();
    let mut q_full = kitchen.start_configuration.clone();
    for (joint, v) in ["base_x", "base_y", "base_yaw"].iter().zip(ARMAR_BASE) {
        q_full[robot.dof_index(joint)?] = v;
    }
    scene.set_robot_configuration(kitchen.robot, &q_full)?;
    let world = Arc::new(CollisionWorld::new(&scene)?);
    let group = robot.group(group)?.clone();
    let checker = CollisionChecker::new(world, kitchen.robot, robot.clone(), group.clone(), q_full.clone())?;
    let certifier = certifier_for(&scene, kitchen.robot, &group, &q_full, &checker)?;
    let model = planning_model_for(&scene, kitchen.robot, &group, &q_full, &checker)?;
    Ok(KitchenParts { robot, group, q_full, checker, certifier, model })
}

/// The planning model of `checker`'s scene (built from `scene`, which must be the scene of the
/// checker's world): the conservative sphere model ([`SceneSphereModel`], default options)
/// with the checker's allowed pairs. Planners search on it; the exact `checker` judges.
///
/// # Errors
/// As [`SceneSphereModel::new`].
pub fn planning_model_for(
    scene: &Scene,
    robot: opengrasp_core::scene::RobotId,
    group: &JointGroup,
    q_full: &[f64],
    checker: &CollisionChecker,
) -> Result<SceneSphereModel> {
    SceneSphereModel::new(scene, robot, group, q_full, checker.world(), &SceneModelOptions::default())
}

/// The post-processing certifier of `checker`'s scene (built from `scene`, which must be the
/// scene of the checker's world): the robot's and the obstacles' conservative model with the
/// checker's motion bound and allowed pairs, refined by the checker's exact distances where
/// the model cannot clear a link.
///
/// # Errors
/// As [`SphereCertifier::new`].
pub fn certifier_for(
    scene: &Scene,
    robot: opengrasp_core::scene::RobotId,
    group: &JointGroup,
    q_full: &[f64],
    checker: &CollisionChecker,
) -> Result<SphereCertifier> {
    let bound = checker
        .motion_bound()
        .ok_or(opengrasp_motion::MotionError::InvalidParameter { name: "checker", reason: "no motion bound".into() })?;
    SphereCertifier::new(scene, robot, group, q_full, bound, checker.world())?.with_exact(checker)
}

/// Scene 1: the ARMAR-III-like humanoid in the kitchen, hip yaw + right arm, fixed start
/// ([`ARMAR_START`]) and goal ([`armar_standard_goal`]); end effector `right_hand_palm`.
pub fn armar_standard_scene() -> BenchmarkScene {
    BenchmarkScene {
        name: "standard (ARMAR-III kitchen)".into(),
        shared_environment: true,
        generate: Box::new(|_seed| {
            let KitchenParts { robot, group, q_full, checker, certifier, model } =
                kitchen_parts("hip_right_arm", |_| Ok(()))?;
            let tip = robot.link_id("right_hand_palm")?;
            let goal = armar_standard_goal(&robot, &group, &q_full, &checker)?;
            Ok(SceneInstance {
                robot,
                group,
                q_full,
                tip: Some(tip),
                start: ARMAR_START.to_vec(),
                goal: Goal::Configuration(goal),
                checker: Box::new(checker),
                planning_checker: Some(Box::new(model)),
                certifier: Some(Box::new(certifier)),
            })
        }),
    }
}

/// Scene 2: the humanoid of [`armar_standard_scene`] and a 6 cm box at a seeded random
/// position on the red table's front strip in front of it (x in [1.8, 2.35] m, y in
/// [1.86, 1.95] m, random yaw; the kitchen's own objects stand farther back). Goal: the right
/// palm 12 cm above the box's centre, any orientation (position tolerance 1 mm), solved by
/// IK then planning or by IK-RRT; start: the arm hanging.
///
/// The far end of the strip is at the edge of the right arm's reach, so a box position is
/// kept only if the goal has a collision-free IK solution (found within
/// [`REACHABILITY_ATTEMPTS`] seeded IK descents); otherwise the position is redrawn from the
/// same seeded stream (at most [`MAX_PLACEMENTS`] times). Every instance is therefore solvable
/// in principle, and a failed run is the planner's. (Without this, about 5 % of the seeds put
/// the box out of reach and every planner timed out on them.)
pub fn armar_ik_scene() -> BenchmarkScene {
    BenchmarkScene {
        name: "IK-based (ARMAR-III kitchen)".into(),
        shared_environment: false,
        generate: Box::new(|seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut last = None;
            for _ in 0..MAX_PLACEMENTS {
                let x = rng.random_range(1.8..2.35);
                let y = rng.random_range(1.86..1.95);
                let yaw = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
                let instance = armar_ik_instance(x, y, yaw)?;
                if has_reachable_goal(&instance, rng.random()) {
                    return Ok(instance);
                }
                last = Some(instance);
            }
            // Not reached for the stock kitchen (checked by the tests); keep the last draw.
            last.ok_or_else(|| opengrasp_motion::MotionError::InvalidParameter {
                name: "placements",
                reason: "no placement drawn".into(),
            })
        }),
    }
}

/// Seeded IK descents tried per box placement of [`armar_ik_scene`] to find a collision-free
/// goal configuration.
pub const REACHABILITY_ATTEMPTS: usize = 300;

/// Box placements drawn at most per seed of [`armar_ik_scene`].
pub const MAX_PLACEMENTS: usize = 20;

/// The scene-2 instance with the box at `(x, y)` on the table, turned by `yaw`.
fn armar_ik_instance(x: f64, y: f64, yaw: f64) -> Result<SceneInstance> {
    let z = 0.75 + 0.03;
    let pose = Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(0.0, 0.0, yaw));
    let KitchenParts { robot, group, q_full, checker, certifier, model } = kitchen_parts("hip_right_arm", |scene| {
        let shape = Shape::at_origin(Geometry::cuboid(0.06, 0.06, 0.06));
        scene.add_object(SceneObject::new("target_box", pose, vec![shape], 0.2))?;
        Ok(())
    })?;
    let tip = robot.link_id("right_hand_palm")?;
    let target = Isometry3::translation(x, y, z + 0.12);
    let goal =
        Goal::Pose(PoseGoal { tip, target, position_tolerance: 1e-3, orientation_tolerance: std::f64::consts::PI });
    Ok(SceneInstance {
        robot,
        group,
        q_full,
        tip: Some(tip),
        start: ARMAR_START.to_vec(),
        goal,
        checker: Box::new(checker),
        planning_checker: Some(Box::new(model)),
        certifier: Some(Box::new(certifier)),
    })
}

/// True if the instance's goal can be reached by a valid configuration: for a pose goal, one
/// of [`REACHABILITY_ATTEMPTS`] seeded IK descents (from uniform random configurations) ends
/// collision-free within the limits and the goal's tolerances; for configuration goals, a goal
/// configuration is valid.
pub fn has_reachable_goal(instance: &SceneInstance, seed: u64) -> bool {
    let problem = instance.problem(
        &*instance.checker,
        std::time::Duration::from_secs(1),
        seed,
        opengrasp_motion::validate::DEFAULT_STEP,
    );
    match &instance.goal {
        Goal::Pose(_) => {
            let limits = problem.limits();
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            (0..REACHABILITY_ATTEMPTS).any(|_| problem.sample_ik_goal(&mut rng, &limits).is_some())
        }
        Goal::Configuration(g) => instance.checker.is_valid(g),
        Goal::ConfigurationSet(set) => set.iter().any(|g| instance.checker.is_valid(g)),
    }
}

fn scene_of(robot: &Arc<Robot>, boxes: &[ObstacleBox]) -> Result<Scene> {
    let mut scene = Scene::new("cupboard");
    scene.add_robot("arm", robot.clone(), Isometry3::identity())?;
    for b in boxes {
        let shape = Shape::at_origin(Geometry::Box { half_extents: b.half_extents });
        scene.add_body(StaticBody::new(b.name.clone(), b.pose, vec![shape]))?;
    }
    Ok(scene)
}

/// A checker for the 7-DoF arm (group `arm`) among `boxes`.
///
/// # Errors
/// Errors from building the robot, scene or collision world.
pub fn arm_checker(kind: CheckerKind, boxes: Vec<ObstacleBox>) -> Result<(Arc<Robot>, Box<dyn StateValidityChecker>)> {
    let robot = Arc::new(samples::seven_dof_arm()?);
    let group = robot.group("arm")?.clone();
    let q_full = robot.home_configuration();
    let checker: Box<dyn StateValidityChecker> = match kind {
        CheckerKind::Exact => {
            let scene = scene_of(&robot, &boxes)?;
            let world = Arc::new(CollisionWorld::new(&scene)?);
            Box::new(CollisionChecker::new(world, opengrasp_core::scene::RobotId(0), robot.clone(), group, q_full)?)
        }
        CheckerKind::Spheres => Box::new(SphereWorld::new(robot.clone(), group, q_full, Isometry3::identity(), boxes)?),
    };
    Ok((robot, checker))
}

fn instance(kind: CheckerKind, boxes: Vec<ObstacleBox>, start: Vec<f64>, goal: Goal) -> Result<SceneInstance> {
    let (robot, checker) = arm_checker(kind, boxes)?;
    let group: JointGroup = robot.group("arm")?.clone();
    let tip = robot.link_id("tool")?;
    Ok(SceneInstance {
        q_full: robot.home_configuration(),
        robot,
        group,
        tip: Some(tip),
        start,
        goal,
        checker,
        planning_checker: None,
        certifier: None,
    })
}

/// Scene 1 stand-in: fixed start and goal of the 7-DoF arm in the cupboard.
pub fn standard_scene(kind: CheckerKind) -> BenchmarkScene {
    BenchmarkScene {
        name: match kind {
            CheckerKind::Exact => "standard (7-DoF stand-in)".into(),
            CheckerKind::Spheres => "standard (7-DoF stand-in, spheres)".into(),
        },
        shared_environment: true,
        generate: Box::new(move |_seed| {
            instance(kind, cupboard(), STANDARD_START.to_vec(), Goal::Configuration(STANDARD_GOAL.to_vec()))
        }),
    }
}

/// Scene 2 stand-in: a 6 cm box object at a seeded random position on the table (x in
/// [0.42, 0.6] m, y in [-0.35, -0.12] ∪ [0.12, 0.35] m, random yaw, all within reach); goal:
/// the hand's `tool` frame 12 cm above the object's centre pointing down (position tolerance
/// 1 mm, orientation 0.01 rad); start: the arm upright (all zeros).
pub fn ik_scene(kind: CheckerKind) -> BenchmarkScene {
    BenchmarkScene {
        name: "IK-based (7-DoF stand-in)".into(),
        shared_environment: false,
        generate: Box::new(move |seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let x = rng.random_range(0.42..0.6);
            let side = if rng.random::<bool>() { 1.0 } else { -1.0 };
            let y = side * rng.random_range(0.12..0.35);
            let yaw = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
            let z = 0.25 + 0.03;
            let mut boxes = cupboard();
            boxes.push(ObstacleBox::new(
                "object",
                Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(0.0, 0.0, yaw)),
                Vector3::new(0.06, 0.06, 0.06),
            ));
            let down = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, yaw);
            let target = Isometry3::from_parts(Translation3::new(x, y, z + 0.12), down);
            let robot = samples::seven_dof_arm()?;
            let tip = robot.link_id("tool")?;
            let goal = Goal::Pose(PoseGoal { tip, target, position_tolerance: 1e-3, orientation_tolerance: 1e-2 });
            instance(kind, boxes, vec![0.0; 7], goal)
        }),
    }
}
