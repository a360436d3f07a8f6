//! Scene 3, "Clean the Table": the humanoid carries the objects of the red table to the green
//! sideboard, planning over base + hip + right arm (group `base_hip_right_arm`, 11 DoF).
//!
//! The kitchen's four table objects (white cup, green cup, salt can, measuring cup) are placed
//! at seeded random positions on the red table. For each object in turn: a **grasp** query
//! (goal: the right palm 12 cm above the object's top, any orientation), then the object is
//! lifted 2 cm and attached to the palm, then a **place** query carrying it (goal: the palm
//! above a free slot of the sideboard so that the object hangs 2 cm above it), then the object
//! is detached and set down by undoing the lift in the palm frame. The goals constrain the
//! palm's position only, so the object keeps its grasp-time pose relative to the palm and may
//! arrive tilted. Every query is one [`RunRecord`] produced by the same harness as
//! the other scenes ([`run_once`]), so per-object and total metrics come out graded alike.
//! While carrying, the motion bound of the continuous validator includes the object's
//! bounding box. Grasping itself (fingers) is not simulated: the object is attached rigidly.

use std::sync::Arc;

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::scene::ObjectId;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::scenes::certifier_for;
use opengrasp_motion::benchmark::{run_once, timed_setup, BenchmarkOptions, RunRecord, RunStatus, SceneInstance};
use opengrasp_motion::problem::{Goal, MotionPlanner, PoseGoal};
use opengrasp_motion::validity::{CollisionChecker, MotionBound};
use opengrasp_motion::{MotionError, Result};

/// Scene name under which benchmark harnesses file the queries of Clean the Table episodes.
pub const SCENE_NAME: &str = "clean the table";

/// The kitchen objects standing on the red table.
pub const TABLE_OBJECTS: [&str; 4] = ["white_cup", "green_cup", "salt_can", "measuring_cup"];

/// Options of [`clean_the_table`].
#[derive(Clone, Debug, PartialEq)]
pub struct CleanTheTableOptions {
    /// Objects to carry, at most [`TABLE_OBJECTS`]`.len()` (default 4).
    pub objects: usize,
    /// Seed of the object placement and of the queries (query `k` uses `seed + k`; default 0).
    pub seed: u64,
    /// Harness options of each query (defaults of [`BenchmarkOptions`], 20 s time limit).
    pub benchmark: BenchmarkOptions,
}

impl Default for CleanTheTableOptions {
    fn default() -> Self {
        Self {
            objects: 4,
            seed: 0,
            benchmark: BenchmarkOptions {
                time_limit: std::time::Duration::from_secs(20),
                ..BenchmarkOptions::default()
            },
        }
    }
}

/// The grasp and place queries of one object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObjectReport {
    /// The object's name.
    pub object: String,
    /// The grasp query.
    pub grasp: RunRecord,
    /// The place query (absent if the grasp failed).
    pub place: Option<RunRecord>,
}

/// What an episode achieved, summed over its queries (also the figures of a results file's
/// episode records).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeTotals {
    /// Objects placed on the sideboard.
    pub cleaned: usize,
    /// Sum of setup times (s).
    pub setup_time: f64,
    /// Sum of planning times (s).
    pub planning_time: f64,
    /// Sum of post-processing times (s).
    pub postprocessing_time: f64,
    /// Sum of post-processed C-space lengths.
    pub length: f64,
    /// Sum of post-processed end-effector lengths (m).
    pub ee_length: f64,
    /// True if every post-processed path passed every validator.
    pub all_valid: bool,
}

impl EpisodeTotals {
    /// Nothing done yet (and nothing invalid yet).
    pub fn empty() -> Self {
        Self {
            cleaned: 0,
            setup_time: 0.0,
            planning_time: 0.0,
            postprocessing_time: 0.0,
            length: 0.0,
            ee_length: 0.0,
            all_valid: true,
        }
    }
}

/// Outcome of one "Clean the Table" episode.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CleanTheTableReport {
    /// Planner name.
    pub planner: String,
    /// Seed of the episode.
    pub seed: u64,
    /// Per-object queries, in order.
    pub objects: Vec<ObjectReport>,
    /// Sums over the queries.
    #[serde(flatten)]
    pub totals: EpisodeTotals,
}

fn top_of(scene: &opengrasp_core::scene::Scene, id: ObjectId) -> Result<f64> {
    let object = scene.object(id)?;
    let mut top = 0.0f64;
    for shape in &object.shapes {
        for p in shape.aabb_corners() {
            top = top.max(p.z);
        }
    }
    Ok(top)
}

/// Runs one "Clean the Table" episode with `planner`; see the [module docs](self).
///
/// # Errors
/// [`MotionError::InvalidParameter`] for more objects than [`TABLE_OBJECTS`], and errors from
/// the assets, the scene or the collision world. Planning failures are not errors: the episode
/// stops and the report says how many objects were cleaned.
pub fn clean_the_table(planner: &mut dyn MotionPlanner, options: &CleanTheTableOptions) -> Result<CleanTheTableReport> {
    if options.objects > TABLE_OBJECTS.len() {
        return Err(MotionError::InvalidParameter {
            name: "objects",
            reason: format!("at most {} objects stand on the table", TABLE_OBJECTS.len()),
        });
    }
    let kitchen = opengrasp_assets::scenes::kitchen().map_err(|e| MotionError::Scene(Box::new(e)))?;
    let mut scene = kitchen.scene.clone();
    let rid = kitchen.robot;
    let robot = scene.robot(rid)?.robot.clone();
    let group = robot.group("base_hip_right_arm")?.clone();
    let palm = robot.link_id("right_hand_palm")?;
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    // Seeded placement on the red table (top 1.2 x 0.8 m at 0.75 m, centre (2.0, 2.2)).
    let mut ids = Vec::new();
    let mut placed: Vec<(f64, f64)> = Vec::new();
    for name in TABLE_OBJECTS {
        let id = scene
            .object_id(name)
            .ok_or(MotionError::InvalidParameter { name: "objects", reason: format!("the kitchen has no `{name}`") })?;
        let (mut x, mut y) = (2.0, 2.2);
        for _ in 0..1000 {
            x = rng.random_range(1.55..2.45);
            y = rng.random_range(1.95..2.45);
            if placed.iter().all(|&(px, py)| (px - x).hypot(py - y) > 0.18) {
                break;
            }
        }
        placed.push((x, y));
        let yaw = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        let pose =
            Isometry3::from_parts(Translation3::new(x, y, 0.75), UnitQuaternion::from_euler_angles(0.0, 0.0, yaw));
        scene.set_object_pose(id, pose)?;
        ids.push((name, id));
    }
    let slots = [1.75, 2.05, 2.35, 2.65];
    let mut q = kitchen.start_configuration.clone();
    let mut report = CleanTheTableReport {
        planner: planner.name().to_string(),
        seed: options.seed,
        objects: Vec::new(),
        totals: EpisodeTotals::empty(),
    };
    let position_goal = |target: Isometry3<f64>| {
        Goal::Pose(PoseGoal {
            tip: palm,
            target,
            position_tolerance: 1e-3,
            orientation_tolerance: std::f64::consts::PI,
        })
    };
    let query = |planner: &mut dyn MotionPlanner,
                 scene: &opengrasp_core::scene::Scene,
                 q: &[f64],
                 goal: Goal,
                 bound: Option<MotionBound>,
                 name: String,
                 k: usize|
     -> Result<RunRecord> {
        let world = Arc::new(CollisionWorld::new(scene)?);
        let mut checker = CollisionChecker::new(world, rid, robot.clone(), group.clone(), q.to_vec())?;
        if let Some(b) = bound {
            checker = checker.with_bound(b);
        }
        let certifier = certifier_for(scene, rid, &group, q, &checker)?;
        let instance = SceneInstance {
            robot: robot.clone(),
            group: group.clone(),
            q_full: q.to_vec(),
            tip: Some(palm),
            start: group.extract(q),
            goal,
            checker: Box::new(checker),
            planning_checker: None,
            certifier: Some(Box::new(certifier)),
        };
        let seed = options.seed.wrapping_add(k as u64);
        let setup = timed_setup(planner, &instance, seed, &options.benchmark).unwrap_or(0.0);
        Ok(run_once(planner, &instance, &name, k, seed, setup, &options.benchmark))
    };
    let account = |report: &mut CleanTheTableReport, r: &RunRecord| {
        report.totals.setup_time += r.setup_time;
        report.totals.planning_time += r.planning_time;
        report.totals.postprocessing_time += r.postprocessing_time.unwrap_or(0.0);
        if let Some(p) = &r.processed {
            report.totals.length += p.metrics.length;
            report.totals.ee_length += p.metrics.ee_length.unwrap_or(0.0);
            let v = p.validity;
            report.totals.all_valid &= v.discrete && v.strict && v.continuous != Some(false);
        } else {
            report.totals.all_valid = false;
        }
    };
    let final_full = |q: &[f64], r: &RunRecord| -> Option<Vec<f64>> {
        let _ = r.processed.as_ref()?;
        let last = r.final_state.as_ref()?;
        let mut full = q.to_vec();
        group.insert(&mut full, last).ok()?;
        Some(full)
    };
    for (k, &(name, id)) in ids.iter().take(options.objects).enumerate() {
        // Grasp.
        scene.set_robot_configuration(rid, &q)?;
        let pose = scene.object(id)?.pose;
        let top = top_of(&scene, id)?;
        let target = Isometry3::translation(pose.translation.x, pose.translation.y, pose.translation.z + top + 0.12);
        let grasp =
            query(planner, &scene, &q, position_goal(target), None, format!("clean the table: grasp {name}"), 2 * k)?;
        account(&mut report, &grasp);
        let Some(q_grasp) = (grasp.status == RunStatus::Solved).then(|| final_full(&q, &grasp)).flatten() else {
            report.objects.push(ObjectReport { object: name.to_string(), grasp, place: None });
            break;
        };
        q = q_grasp;
        // Lift 2 cm and attach.
        scene.set_robot_configuration(rid, &q)?;
        let palm_at_grasp = scene.link_world_pose(rid, "right_hand_palm")?;
        let lifted = Isometry3::from_parts(
            Translation3::new(pose.translation.x, pose.translation.y, pose.translation.z + 0.02),
            pose.rotation,
        );
        scene.set_object_pose(id, lifted)?;
        scene.attach(id, rid, "right_hand_palm")?;
        let offset = scene.attachment_of(id).map(|a| a.offset).unwrap_or_else(Isometry3::identity);
        let mut corners = Vec::new();
        for shape in &scene.object(id)?.shapes {
            corners.extend(shape.aabb_corners().map(|p| offset * p));
        }
        let bound = MotionBound::from_robot_with(&robot, &group, &[(palm, corners)])?;
        // Place above a sideboard slot (top at 0.85 m, centre x = 5.73 m).
        let place_target = Isometry3::translation(5.73, slots[k], 0.85 + 0.02 + top + 0.12);
        let place = query(
            planner,
            &scene,
            &q,
            position_goal(place_target),
            Some(bound),
            format!("clean the table: place {name}"),
            2 * k + 1,
        )?;
        account(&mut report, &place);
        let solved = place.status == RunStatus::Solved;
        let q_place = solved.then(|| final_full(&q, &place)).flatten();
        report.objects.push(ObjectReport { object: name.to_string(), grasp, place: Some(place) });
        let Some(q_place) = q_place else { break };
        q = q_place;
        scene.set_robot_configuration(rid, &q)?;
        scene.detach(id)?;
        // Undo the lift in the palm frame: the object ends where it sat relative to the palm
        // when it was grasped (a collision-free relative pose).
        let palm_at_place = scene.link_world_pose(rid, "right_hand_palm")?;
        scene.set_object_pose(id, palm_at_place * palm_at_grasp.inverse() * pose)?;
        report.totals.cleaned += 1;
    }
    Ok(report)
}
