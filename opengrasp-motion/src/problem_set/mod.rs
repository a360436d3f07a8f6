//! Motion problem sets from files: a documented JSON format and a loader for
//! MotionBenchMaker's (MBM) published problems (MoveIt planning-scene + request YAML files).
//!
//! A **problem set** is many planning problems sharing one robot. Each problem has its own
//! obstacles, start and goal. [`load`] reads a set from any of:
//!
//! - a **JSON problem-set file** (`*.json`, the format below);
//! - an **MBM set directory** holding `sceneNNNN.yaml` and `requestNNNN.yaml` files (MoveIt
//!   `PlanningScene` and `MotionPlanRequest` messages, as MotionBenchMaker writes them), see
//!   [`mbm`];
//! - a directory of MBM set directories (e.g. MBM's `problems/`): one set per directory.
//!
//! [`LoadedProblemSet::new`] then loads the robot once and
//! [`LoadedProblemSet::instance`] turns problem *i* into a
//! [`SceneInstance`](crate::benchmark::SceneInstance) validated by the exact
//! [`CollisionChecker`](crate::validity::CollisionChecker) over core's collision world — the
//! input of [`run_benchmark`](crate::benchmark::run_benchmark).
//!
//! # The JSON format (version 1)
//!
//! ```json
//! {
//!   "format": "opengrasp-problem-set",
//!   "version": 1,
//!   "name": "two boxes",
//!   "robot": {
//!     "urdf": "panda/panda.urdf",
//!     "srdf": "panda/panda.srdf",
//!     "group": "panda_arm",
//!     "packages": { "meshes": "panda/meshes" }
//!   },
//!   "tip": "panda_hand",
//!   "base_pose": { "position": [0, 0, 0], "orientation": [0, 0, 0, 1] },
//!   "problems": [
//!     {
//!       "name": "reach over the box",
//!       "obstacles": [
//!         { "name": "table", "type": "box", "size": [1.2, 2.0, 0.04],
//!           "pose": { "position": [0.6, 0, 0.2], "orientation": [0, 0, 0, 1] } },
//!         { "name": "can", "type": "cylinder", "radius": 0.03, "length": 0.12,
//!           "pose": { "position": [0.5, 0.2, 0.28] } },
//!         { "name": "rail", "type": "capsule", "radius": 0.02, "length": 0.5 },
//!         { "name": "ball", "type": "sphere", "radius": 0.05, "pose": { "position": [0.4, -0.3, 0.5] } },
//!         { "name": "bowl", "type": "mesh", "path": "meshes/bowl.stl", "scale": [0.001, 0.001, 0.001] },
//!         { "name": "wedge", "type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]],
//!           "triangles": [[0,2,1],[0,1,3],[0,3,2],[1,2,3]] }
//!       ],
//!       "start": [0, -0.785, 0, -2.356, 0, 1.571, 0.785],
//!       "goal": { "configuration": [1.0, 0.2, 0, -1.5, 0, 1.8, 0.8] },
//!       "joints": { "panda_finger_joint1": 0.04 },
//!       "allowed_collisions": [["panda_hand", "table"]]
//!     }
//!   ]
//! }
//! ```
//!
//! - `format` and `version` are optional (the values above); other versions are rejected.
//! - `robot`: `urdf` (+ optional `srdf`) or `stock` (`"seven_dof_arm"` or
//!   `"planar_arm"`, core's sample robots); `group` names a group of the SRDF (or of the
//!   robot); omitted, the group is every degree of freedom. `packages` maps ROS package names
//!   to directories for `package://` mesh URIs. Relative paths are relative to the JSON file.
//! - `tip` (optional): the end-effector link whose workspace path length is measured.
//! - `base_pose` (optional): the robot root's pose in the world frame.
//! - Poses: `position` (m, default 0) and `orientation` as a quaternion `[x, y, z, w]`
//!   (default identity; normalised, a zero quaternion is an error), in the world frame.
//! - Obstacles: `box` with its **full** `size` (edge lengths; the project's convention for
//!   every size-taking constructor), `sphere` (`radius`), `cylinder` and `capsule` (`radius`,
//!   `length` along the local z axis, centred; a capsule's `length` is between its hemisphere
//!   centres), `mesh` (a `path` to an STL / OBJ / COLLADA file, or inline `vertices` and
//!   `triangles`; optional `scale`). Names must be unique within a problem.
//! - `start`: group values in group order, or an object of values by joint name
//!   (`{"panda_joint1": 0.0, ...}`: every group joint named; other named degrees of freedom
//!   set the joints outside the group; joints the model does not move are ignored). `goal`: `{"configuration": [...]}`,
//!   `{"configurations": [[...], ...]}` (any of them) or `{"pose": {"link": "panda_hand",
//!   "position": [...], "orientation": [...], "position_tolerance": 0.001,
//!   "orientation_tolerance": 0.01}}` (tolerances default to 1 mm and 0.01 rad).
//! - `joints` (optional): values of joints outside the group, by name (others at the robot's
//!   home configuration). `allowed_collisions` (optional): pairs of robot link names whose
//!   contact is allowed in this problem (the SRDF's pairs always are).
//! - Instead of `problems`, `"mbm": "dir"` reads the problems from an MBM set directory
//!   (the robot then comes from this file, not from discovery).
//!
//! Bad files give typed errors, never a panic: [`MotionError::ProblemSetIo`],
//! [`MotionError::ProblemSetTooLarge`] (more than [`MAX_FILE_BYTES`]),
//! [`MotionError::ProblemSetSyntax`] and [`MotionError::ProblemSetInvalid`] (naming the field,
//! e.g. `problems[3].obstacles[1].size`); robot files fail with core's errors.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{MotionError, Result};

mod instance;
pub mod mbm;
mod validate;
pub mod yaml;

pub use instance::{LoadedProblemSet, PlanningModel};

/// The value of the `format` field.
pub const FORMAT: &str = "opengrasp-problem-set";
/// The format version this build reads and writes.
pub const VERSION: u32 = 1;
/// Largest problem-set, scene or request file read (bytes).
pub const MAX_FILE_BYTES: u64 = 64 * 1024 * 1024;
/// Most problems in one set.
pub const MAX_PROBLEMS: usize = 100_000;

fn default_format() -> String {
    FORMAT.to_string()
}
fn default_version() -> u32 {
    VERSION
}

/// A problem set: one robot, many problems.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProblemSet {
    /// Always [`FORMAT`].
    #[serde(default = "default_format")]
    pub format: String,
    /// Format version ([`VERSION`]).
    #[serde(default = "default_version")]
    pub version: u32,
    /// Name of the set (the benchmark scene's name).
    pub name: String,
    /// The robot and planning group.
    pub robot: RobotSpec,
    /// End-effector link for the workspace path length (optional).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip: Option<String>,
    /// Pose of the robot's root link in the world frame (default: identity).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_pose: Option<PoseSpec>,
    /// The problems.
    #[serde(default)]
    pub problems: Vec<Problem>,
    /// An MBM set directory to read the problems from (instead of `problems`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mbm: Option<PathBuf>,
    /// Where the set was read from (file or directory); relative paths in the set are resolved
    /// against its directory. Not part of the file.
    #[serde(skip)]
    pub source: PathBuf,
}

/// The robot of a set.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// URDF file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<PathBuf>,
    /// SRDF file (groups, allowed collisions).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub srdf: Option<PathBuf>,
    /// A stock robot instead of a URDF: `"seven_dof_arm"` or `"planar_arm"` (core's samples;
    /// the planar arm has links of 0.5 m and 0.4 m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stock: Option<String>,
    /// The planning group (default: every degree of freedom).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
    /// ROS packages for `package://` URIs: name → directory.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub packages: BTreeMap<String, PathBuf>,
}

/// A pose in the world frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSpec {
    /// Position (m).
    #[serde(default)]
    pub position: [f64; 3],
    /// Orientation quaternion `[x, y, z, w]` (normalised on use).
    #[serde(default = "identity_quaternion")]
    pub orientation: [f64; 4],
}

fn identity_quaternion() -> [f64; 4] {
    [0.0, 0.0, 0.0, 1.0]
}

impl Default for PoseSpec {
    fn default() -> Self {
        Self { position: [0.0; 3], orientation: identity_quaternion() }
    }
}

/// An obstacle: a named shape at a pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Obstacle {
    /// Name (unique within the problem).
    pub name: String,
    /// Pose of the shape's frame in the world.
    #[serde(default)]
    pub pose: PoseSpec,
    /// The shape.
    #[serde(flatten)]
    pub shape: ShapeSpec,
}

/// An obstacle's shape (field `type`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ShapeSpec {
    /// A box centred at its frame.
    Box {
        /// Full size (edge lengths) along x, y, z (m).
        size: [f64; 3],
    },
    /// A sphere.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A cylinder along local z, centred.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length along z (m).
        length: f64,
    },
    /// A capsule along local z, centred.
    Capsule {
        /// Radius (m).
        radius: f64,
        /// Distance between the hemisphere centres (m).
        length: f64,
    },
    /// A triangle mesh: a file, or inline vertices and triangles.
    Mesh {
        /// Mesh file (STL, OBJ, COLLADA), relative to the set's file.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        path: Option<PathBuf>,
        /// Inline vertices (m).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        vertices: Vec<[f64; 3]>,
        /// Inline triangles (vertex indices).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        triangles: Vec<[u32; 3]>,
        /// Scale along x, y, z (default 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        scale: Option<[f64; 3]>,
    },
}

/// One planning problem of a set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Problem {
    /// Name (default: the index).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Obstacles.
    #[serde(default)]
    pub obstacles: Vec<Obstacle>,
    /// Start configuration.
    pub start: Configuration,
    /// The goal.
    pub goal: GoalSpec,
    /// Values of joints outside the group, by joint name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub joints: BTreeMap<String, f64>,
    /// Robot link pairs allowed to touch in this problem.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub allowed_collisions: Vec<[String; 2]>,
}

/// A problem's goal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GoalSpec {
    /// One goal configuration.
    Configuration(Configuration),
    /// Any of several goal configurations.
    Configurations(Vec<Configuration>),
    /// A pose of a link, reached through IK.
    Pose(PoseGoalSpec),
}

/// A configuration: group values in group order, or values by joint name (every group joint
/// named; other named degrees of freedom set the joints outside the group; named joints the
/// model has but does not move, such as fixed fingers, are ignored).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Configuration {
    /// Group values in group order.
    Values(Vec<f64>),
    /// Values by joint name.
    Named(BTreeMap<String, f64>),
}

impl Configuration {
    /// The numbers of the configuration (in order, or by joint name).
    pub fn numbers(&self) -> Vec<f64> {
        match self {
            Configuration::Values(v) => v.clone(),
            Configuration::Named(m) => m.values().copied().collect(),
        }
    }
}

/// A pose goal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseGoalSpec {
    /// The link that must reach the pose.
    pub link: String,
    /// Target position (m, world frame).
    #[serde(default)]
    pub position: [f64; 3],
    /// Target orientation `[x, y, z, w]`.
    #[serde(default = "identity_quaternion")]
    pub orientation: [f64; 4],
    /// Accepted position error (m, default 0.001).
    #[serde(default = "default_position_tolerance")]
    pub position_tolerance: f64,
    /// Accepted orientation error (rad, default 0.01; π or more: any orientation).
    #[serde(default = "default_orientation_tolerance")]
    pub orientation_tolerance: f64,
}

fn default_position_tolerance() -> f64 {
    1e-3
}
fn default_orientation_tolerance() -> f64 {
    1e-2
}

impl ProblemSet {
    /// Parses a JSON problem set; `source` is the file it came from (relative paths resolve
    /// against its directory). An `mbm` directory is read here.
    ///
    /// # Errors
    /// [`MotionError::ProblemSetSyntax`] for bad JSON or a wrong shape,
    /// [`MotionError::ProblemSetInvalid`] for a wrong format or version, bad numbers or names,
    /// errors of [`mbm::read_problems`] for its `mbm` directory.
    pub fn from_json_str(text: &str, source: impl Into<PathBuf>) -> Result<Self> {
        let source = source.into();
        let mut set: ProblemSet = serde_json::from_str(text)
            .map_err(|e| MotionError::ProblemSetSyntax { path: source.clone(), reason: e.to_string() })?;
        set.source = source;
        if let Some(dir) = set.mbm.clone() {
            if !set.problems.is_empty() {
                return Err(set.invalid("mbm", "give `problems` or `mbm`, not both"));
            }
            let read = mbm::read_problems(&set.resolve(&dir))?;
            set.problems = read.problems;
            if set.robot.group.is_none() && !read.group.is_empty() {
                set.robot.group = Some(read.group);
            }
            if set.base_pose.is_none() {
                set.base_pose = read.base_pose;
            }
        }
        set.validate()?;
        Ok(set)
    }

    /// The set as pretty-printed JSON (the documented format).
    ///
    /// # Errors
    /// [`MotionError::ProblemSetSyntax`] if a number cannot be written (not expected: loaded
    /// sets are finite).
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string_pretty(self)
            .map_err(|e| MotionError::ProblemSetSyntax { path: self.source.clone(), reason: e.to_string() })
    }

    /// `path` resolved against the directory of [`ProblemSet::source`] (absolute paths as is).
    pub fn resolve(&self, path: &Path) -> PathBuf {
        if path.is_absolute() {
            return path.to_path_buf();
        }
        let base =
            if self.source.is_dir() { self.source.as_path() } else { self.source.parent().unwrap_or(Path::new("")) };
        base.join(path)
    }

    pub(crate) fn invalid(&self, field: impl Into<String>, reason: impl Into<String>) -> MotionError {
        MotionError::ProblemSetInvalid { path: self.source.clone(), field: field.into(), reason: reason.into() }
    }
}

/// Reads the file at `path` as text, at most [`MAX_FILE_BYTES`].
pub(crate) fn read_text(path: &Path) -> Result<String> {
    let io = |source| MotionError::ProblemSetIo { path: path.to_path_buf(), source };
    let size = std::fs::metadata(path).map_err(io)?.len();
    if size > MAX_FILE_BYTES {
        return Err(MotionError::ProblemSetTooLarge { path: path.to_path_buf(), limit: MAX_FILE_BYTES, actual: size });
    }
    std::fs::read_to_string(path).map_err(io)
}

/// Loads the problem sets at `path`: a JSON problem-set file, an MBM set directory or a
/// directory of MBM set directories (sets sorted by name).
///
/// # Errors
/// [`MotionError::ProblemSetIo`] if `path` cannot be read, [`MotionError::ProblemSetInvalid`]
/// for a directory holding no problem set, and the errors of [`ProblemSet::from_json_str`]
/// and [`mbm::load_dir`].
pub fn load(path: impl AsRef<Path>) -> Result<Vec<ProblemSet>> {
    let path = path.as_ref();
    let meta = std::fs::metadata(path).map_err(|source| MotionError::ProblemSetIo { path: path.into(), source })?;
    if !meta.is_dir() {
        let text = read_text(path)?;
        return Ok(vec![ProblemSet::from_json_str(&text, path)?]);
    }
    if mbm::is_set_dir(path)? {
        return Ok(vec![mbm::load_dir(path)?]);
    }
    let mut dirs = Vec::new();
    for entry in std::fs::read_dir(path).map_err(|source| MotionError::ProblemSetIo { path: path.into(), source })? {
        let entry = entry.map_err(|source| MotionError::ProblemSetIo { path: path.into(), source })?;
        let p = entry.path();
        if p.is_dir() && mbm::is_set_dir(&p)? {
            dirs.push(p);
        }
    }
    dirs.sort();
    if dirs.is_empty() {
        return Err(MotionError::ProblemSetInvalid {
            path: path.into(),
            field: "directory".into(),
            reason: "holds no MBM set (sceneNNNN.yaml + requestNNNN.yaml files) nor set directories".into(),
        });
    }
    dirs.iter().map(|d| mbm::load_dir(d)).collect()
}
