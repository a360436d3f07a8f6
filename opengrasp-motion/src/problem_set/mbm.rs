//! MotionBenchMaker (MBM) problems: MoveIt `PlanningScene` + `MotionPlanRequest` YAML files.
//!
//! An MBM set directory (e.g. `problems/table_pick_panda/` of MBM's archives, as shipped in
//! the `vamp-planner` source package's `resources/<robot>/problems.tar.bz2`) holds
//! `sceneNNNN.yaml` and `requestNNNN.yaml` files; problem *i* of the set is the pair with
//! the *i*-th smallest number (a scene without its request, or the reverse, is an error).
//!
//! What is read:
//!
//! - scene: `robot_model_name`; `world.collision_objects[*]` with their `id`, optional
//!   object `pose`, `primitives` (`box` — full size, `sphere`, `cylinder` — `[height,
//!   radius]`, `cone` is rejected) with `primitive_poses`, and `meshes` (inline `vertices` and
//!   `triangles`) with `mesh_poses`; an object with several shapes becomes one obstacle per
//!   shape (`id`, `id#1`, ...). Object frames (`header.frame_id`) other than empty or `world`
//!   are rejected. `allowed_collision_matrix` entries that allow a pair of robot links are
//!   kept as the problem's allowed pairs (other names are ignored, as are entries
//!   disallowing a pair: the SRDF's pairs stay allowed). The `virtual_joint` transform of
//!   `robot_state.multi_dof_joint_state`, if not the identity, is the robot's base pose.
//! - request: `group_name`; `start_state.joint_state` (names and positions); the first goal
//!   constraint's `joint_constraints` (a configuration goal), or its first
//!   `position_constraints` + `orientation_constraints` (a pose goal: the position
//!   constraint region's first primitive pose plus the link's `target_point_offset`, tolerance
//!   the region's first primitive's radius or half size; the orientation's largest axis
//!   tolerance).
//!
//! The robot is found from `robot_model_name` (say `panda`): the nearest ancestor directory
//! of the set (itself and four levels up) holding `panda.urdf` or `panda/panda.urdf`, with
//! `panda.srdf` beside it; its folder is also registered as the ROS package of its `meshes`
//! folder (`package://meshes/...`), as MBM's robots use. The group is the requests'
//! `group_name`. To use another robot file, write a JSON problem set naming the robot and
//! `"mbm": "path/to/set"`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use super::{
    read_text, yaml, Configuration, GoalSpec, Obstacle, PoseGoalSpec, PoseSpec, Problem, ProblemSet, RobotSpec,
    ShapeSpec, FORMAT, MAX_PROBLEMS, VERSION,
};
use crate::error::{MotionError, Result};

/// How far up from a set directory the robot's URDF is looked for.
pub const ROBOT_SEARCH_LEVELS: usize = 4;

fn numbered(name: &str, prefix: &str) -> Option<u64> {
    let digits = name.strip_prefix(prefix)?.strip_suffix(".yaml")?;
    if digits.is_empty() || digits.len() > 12 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

fn list(dir: &Path) -> Result<(BTreeMap<u64, PathBuf>, BTreeMap<u64, PathBuf>)> {
    let io = |source| MotionError::ProblemSetIo { path: dir.to_path_buf(), source };
    let (mut scenes, mut requests) = (BTreeMap::new(), BTreeMap::new());
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let Some(name) = path.file_name().and_then(|n| n.to_str()) else { continue };
        if let Some(i) = numbered(name, "scene") {
            scenes.insert(i, path);
        } else if let Some(i) = numbered(name, "request") {
            requests.insert(i, path);
        }
        if scenes.len() + requests.len() > 2 * MAX_PROBLEMS {
            return Err(MotionError::ProblemSetInvalid {
                path: dir.to_path_buf(),
                field: "directory".into(),
                reason: format!("more than {MAX_PROBLEMS} problems"),
            });
        }
    }
    Ok((scenes, requests))
}

/// True if `dir` holds MBM scene or request files.
///
/// # Errors
/// [`MotionError::ProblemSetIo`] if the directory cannot be listed.
pub fn is_set_dir(dir: &Path) -> Result<bool> {
    let (s, r) = list(dir)?;
    Ok(!s.is_empty() || !r.is_empty())
}

/// One MoveIt planning scene, as far as a problem needs it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MbmScene {
    /// `robot_model_name`.
    pub robot_model_name: String,
    /// Obstacles, one per primitive or mesh.
    pub obstacles: Vec<Obstacle>,
    /// Robot link pairs the scene's allowed-collision matrix allows.
    pub allowed_pairs: Vec<[String; 2]>,
    /// Base pose from the virtual joint, if not the identity.
    pub base_pose: Option<PoseSpec>,
}

/// One MoveIt motion plan request, as far as a problem needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct MbmRequest {
    /// `group_name`.
    pub group: String,
    /// Start joint values by name.
    pub start: BTreeMap<String, f64>,
    /// The goal.
    pub goal: GoalSpec,
}

struct Doc<'a> {
    path: &'a Path,
}

impl Doc<'_> {
    fn err(&self, field: &str, reason: impl Into<String>) -> MotionError {
        MotionError::ProblemSetInvalid { path: self.path.to_path_buf(), field: field.into(), reason: reason.into() }
    }
    fn get<'v>(&self, v: &'v Value, key: &str, field: &str) -> Result<&'v Value> {
        v.get(key).ok_or_else(|| self.err(field, format!("missing `{key}`")))
    }
    fn array<'v>(&self, v: &'v Value, field: &str) -> Result<&'v Vec<Value>> {
        v.as_array().ok_or_else(|| self.err(field, "expected a list"))
    }
    fn num(&self, v: &Value, field: &str) -> Result<f64> {
        match v.as_f64() {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(self.err(field, format!("expected a finite number, got {v}"))),
        }
    }
    fn nums<const N: usize>(&self, v: &Value, field: &str) -> Result<[f64; N]> {
        let a = self.array(v, field)?;
        if a.len() != N {
            return Err(self.err(field, format!("expected {N} numbers, got {}", a.len())));
        }
        let mut out = [0.0; N];
        for (k, x) in a.iter().enumerate() {
            out[k] = self.num(x, &format!("{field}[{k}]"))?;
        }
        Ok(out)
    }
    fn text<'v>(&self, v: &'v Value, field: &str) -> Result<&'v str> {
        v.as_str().ok_or_else(|| self.err(field, "expected text"))
    }
    /// A `geometry_msgs/Pose` (`position`, `orientation` as `[x, y, z, w]` lists or
    /// `{x, y, z, w}` maps); missing parts are the identity.
    fn pose(&self, v: &Value, field: &str) -> Result<PoseSpec> {
        let mut pose = PoseSpec::default();
        if let Some(p) = v.get("position").or_else(|| v.get("translation")) {
            pose.position = self.xyz(p, &format!("{field}.position"))?;
        }
        if let Some(o) = v.get("orientation").or_else(|| v.get("rotation")) {
            pose.orientation = if o.is_object() {
                let f = |k: &str| self.num(self.get(o, k, field)?, &format!("{field}.orientation.{k}"));
                [f("x")?, f("y")?, f("z")?, f("w")?]
            } else {
                self.nums::<4>(o, &format!("{field}.orientation"))?
            };
        }
        Ok(pose)
    }
    fn xyz(&self, v: &Value, field: &str) -> Result<[f64; 3]> {
        if v.is_object() {
            let f = |k: &str| self.num(self.get(v, k, field)?, &format!("{field}.{k}"));
            Ok([f("x")?, f("y")?, f("z")?])
        } else {
            self.nums::<3>(v, field)
        }
    }
}

fn compose(a: &PoseSpec, b: &PoseSpec) -> PoseSpec {
    use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
    let iso = |p: &PoseSpec| {
        let [x, y, z, w] = p.orientation;
        Isometry3::from_parts(
            Translation3::new(p.position[0], p.position[1], p.position[2]),
            UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)),
        )
    };
    let c = iso(a) * iso(b);
    let q = c.rotation.coords;
    PoseSpec { position: c.translation.vector.into(), orientation: [q[0], q[1], q[2], q[3]] }
}

/// Parses a MoveIt planning scene (YAML text) read from `path`.
///
/// # Errors
/// [`MotionError::ProblemSetSyntax`] for bad YAML, [`MotionError::ProblemSetInvalid`] for
/// missing or malformed fields and unsupported shapes or frames.
pub fn parse_scene(text: &str, path: &Path) -> Result<MbmScene> {
    let v = yaml::parse(text).map_err(|reason| MotionError::ProblemSetSyntax { path: path.into(), reason })?;
    let d = Doc { path };
    let mut scene = MbmScene {
        robot_model_name: v.get("robot_model_name").and_then(Value::as_str).unwrap_or("").to_string(),
        ..MbmScene::default()
    };
    let empty = Vec::new();
    let objects = match v.get("world").and_then(|w| w.get("collision_objects")) {
        Some(o) => d.array(o, "world.collision_objects")?,
        None => &empty,
    };
    for (i, co) in objects.iter().enumerate() {
        let f = format!("world.collision_objects[{i}]");
        let id = d.text(d.get(co, "id", &f)?, &format!("{f}.id"))?;
        if let Some(frame) = co.get("header").and_then(|h| h.get("frame_id")).and_then(Value::as_str) {
            if !matches!(frame.trim_start_matches('/'), "" | "world") {
                return Err(d.err(&format!("{f}.header.frame_id"), format!("frame `{frame}` is not supported")));
            }
        }
        let base = match co.get("pose") {
            Some(p) => d.pose(p, &format!("{f}.pose"))?,
            None => PoseSpec::default(),
        };
        let mut shapes = Vec::new();
        let list_of = |key: &str| -> Result<&Vec<Value>> {
            match co.get(key) {
                Some(x) if !x.is_null() => d.array(x, &format!("{f}.{key}")),
                _ => Ok(&empty),
            }
        };
        let (prims, prim_poses) = (list_of("primitives")?, list_of("primitive_poses")?);
        if prims.len() != prim_poses.len() {
            return Err(d.err(&f, format!("{} primitives but {} primitive poses", prims.len(), prim_poses.len())));
        }
        for (k, (p, pose)) in prims.iter().zip(prim_poses).enumerate() {
            let pf = format!("{f}.primitives[{k}]");
            let kind = d.text(d.get(p, "type", &pf)?, &format!("{pf}.type"))?;
            let dims = d.array(d.get(p, "dimensions", &pf)?, &format!("{pf}.dimensions"))?;
            let dim = |n: usize| -> Result<f64> {
                let x =
                    dims.get(n).ok_or_else(|| d.err(&format!("{pf}.dimensions"), format!("too few for a {kind}")))?;
                d.num(x, &format!("{pf}.dimensions[{n}]"))
            };
            let shape = match kind.to_ascii_lowercase().as_str() {
                "box" | "1" => ShapeSpec::Box { size: [dim(0)?, dim(1)?, dim(2)?] },
                "sphere" | "2" => ShapeSpec::Sphere { radius: dim(0)? },
                "cylinder" | "3" => ShapeSpec::Cylinder { length: dim(0)?, radius: dim(1)? },
                other => return Err(d.err(&format!("{pf}.type"), format!("primitive `{other}` is not supported"))),
            };
            shapes.push((shape, d.pose(pose, &format!("{f}.primitive_poses[{k}]"))?));
        }
        let (meshes, mesh_poses) = (list_of("meshes")?, list_of("mesh_poses")?);
        if meshes.len() != mesh_poses.len() {
            return Err(d.err(&f, format!("{} meshes but {} mesh poses", meshes.len(), mesh_poses.len())));
        }
        for (k, (m, pose)) in meshes.iter().zip(mesh_poses).enumerate() {
            let mf = format!("{f}.meshes[{k}]");
            let vertices = d.array(d.get(m, "vertices", &mf)?, &format!("{mf}.vertices"))?;
            let vertices = vertices
                .iter()
                .enumerate()
                .map(|(n, x)| d.xyz(x, &format!("{mf}.vertices[{n}]")))
                .collect::<Result<_>>()?;
            let tris = d.array(d.get(m, "triangles", &mf)?, &format!("{mf}.triangles"))?;
            let mut triangles = Vec::with_capacity(tris.len());
            for (n, t) in tris.iter().enumerate() {
                let tf = format!("{mf}.triangles[{n}]");
                let idx = t.get("vertex_indices").unwrap_or(t);
                let [a, b, c] = d.nums::<3>(idx, &tf)?;
                let ok = |x: f64| x >= 0.0 && x <= f64::from(u32::MAX) && x.fract() == 0.0;
                if !(ok(a) && ok(b) && ok(c)) {
                    return Err(d.err(&tf, "vertex indices must be non-negative integers"));
                }
                triangles.push([a as u32, b as u32, c as u32]);
            }
            let shape = ShapeSpec::Mesh { path: None, vertices, triangles, scale: None };
            shapes.push((shape, d.pose(pose, &format!("{f}.mesh_poses[{k}]"))?));
        }
        if co.get("planes").and_then(Value::as_array).is_some_and(|p| !p.is_empty()) {
            return Err(d.err(&format!("{f}.planes"), "planes are not supported"));
        }
        let single = shapes.len() == 1;
        for (k, (shape, pose)) in shapes.into_iter().enumerate() {
            let name = if single { id.to_string() } else { format!("{id}#{k}") };
            scene.obstacles.push(Obstacle { name, pose: compose(&base, &pose), shape });
        }
    }
    if let Some(acm) = v.get("allowed_collision_matrix") {
        let names =
            d.array(d.get(acm, "entry_names", "allowed_collision_matrix")?, "allowed_collision_matrix.entry_names")?;
        let rows =
            d.array(d.get(acm, "entry_values", "allowed_collision_matrix")?, "allowed_collision_matrix.entry_values")?;
        if rows.len() != names.len() {
            return Err(d.err("allowed_collision_matrix", "entry_values is not square with entry_names"));
        }
        for (i, row) in rows.iter().enumerate() {
            let row = d.array(row, &format!("allowed_collision_matrix.entry_values[{i}]"))?;
            if row.len() != names.len() {
                return Err(d.err("allowed_collision_matrix", "entry_values is not square with entry_names"));
            }
            for (j, allowed) in row.iter().enumerate().skip(i + 1) {
                if allowed.as_bool() == Some(true) {
                    let a = d.text(&names[i], "allowed_collision_matrix.entry_names")?;
                    let b = d.text(&names[j], "allowed_collision_matrix.entry_names")?;
                    scene.allowed_pairs.push([a.to_string(), b.to_string()]);
                }
            }
        }
    }
    if let Some(mdj) = v.get("robot_state").and_then(|r| r.get("multi_dof_joint_state")) {
        let names = mdj.get("joint_names").and_then(Value::as_array).cloned().unwrap_or_default();
        let transforms = mdj.get("transforms").and_then(Value::as_array).cloned().unwrap_or_default();
        if let Some(t) = transforms.first().filter(|_| !names.is_empty()) {
            let pose = d.pose(t, "robot_state.multi_dof_joint_state.transforms[0]")?;
            if pose != PoseSpec::default() {
                scene.base_pose = Some(pose);
            }
        }
    }
    Ok(scene)
}

/// Parses a MoveIt motion plan request (YAML text) read from `path`.
///
/// # Errors
/// [`MotionError::ProblemSetSyntax`] for bad YAML, [`MotionError::ProblemSetInvalid`] for
/// missing or malformed fields, or a goal that is neither joint nor pose constraints.
pub fn parse_request(text: &str, path: &Path) -> Result<MbmRequest> {
    let v = yaml::parse(text).map_err(|reason| MotionError::ProblemSetSyntax { path: path.into(), reason })?;
    let d = Doc { path };
    let group = d.text(d.get(&v, "group_name", "")?, "group_name")?.to_string();
    let js = d.get(d.get(&v, "start_state", "")?, "joint_state", "start_state")?;
    let names = d.array(d.get(js, "name", "start_state.joint_state")?, "start_state.joint_state.name")?;
    let positions = d.array(d.get(js, "position", "start_state.joint_state")?, "start_state.joint_state.position")?;
    if names.len() != positions.len() {
        return Err(
            d.err("start_state.joint_state", format!("{} names but {} positions", names.len(), positions.len()))
        );
    }
    let mut start = BTreeMap::new();
    for (k, (n, p)) in names.iter().zip(positions).enumerate() {
        let name = d.text(n, &format!("start_state.joint_state.name[{k}]"))?;
        start.insert(name.to_string(), d.num(p, &format!("start_state.joint_state.position[{k}]"))?);
    }
    let goals = d.array(d.get(&v, "goal_constraints", "")?, "goal_constraints")?;
    let g = goals.first().ok_or_else(|| d.err("goal_constraints", "no goal"))?;
    let nonempty = |key: &str| g.get(key).and_then(Value::as_array).filter(|a| !a.is_empty());
    let goal = if let Some(jcs) = nonempty("joint_constraints") {
        let mut q = BTreeMap::new();
        for (k, jc) in jcs.iter().enumerate() {
            let f = format!("goal_constraints[0].joint_constraints[{k}]");
            let name = d.text(d.get(jc, "joint_name", &f)?, &format!("{f}.joint_name"))?;
            q.insert(name.to_string(), d.num(d.get(jc, "position", &f)?, &format!("{f}.position"))?);
        }
        GoalSpec::Configuration(Configuration::Named(q))
    } else if let Some(pcs) = nonempty("position_constraints") {
        let f = "goal_constraints[0].position_constraints[0]";
        let pc = &pcs[0];
        let link = d.text(d.get(pc, "link_name", f)?, &format!("{f}.link_name"))?.to_string();
        let region = d.get(pc, "constraint_region", f)?;
        let poses = d.array(d.get(region, "primitive_poses", f)?, &format!("{f}.constraint_region.primitive_poses"))?;
        let centre = d.pose(poses.first().ok_or_else(|| d.err(f, "empty constraint region"))?, f)?;
        let tolerance = region
            .get("primitives")
            .and_then(Value::as_array)
            .and_then(|p| p.first())
            .and_then(|p| p.get("dimensions"))
            .and_then(Value::as_array)
            .and_then(|dims| {
                let v: Vec<f64> = dims.iter().filter_map(Value::as_f64).collect();
                let is_sphere = v.len() == 1;
                v.into_iter().reduce(f64::min).map(|x| if is_sphere { x } else { x * 0.5 })
            })
            .filter(|t| t.is_finite() && *t > 0.0)
            .unwrap_or(1e-3);
        let mut goal = PoseGoalSpec {
            link,
            position: centre.position,
            orientation: [0.0, 0.0, 0.0, 1.0],
            position_tolerance: tolerance,
            orientation_tolerance: std::f64::consts::PI,
        };
        if let Some(oc) = nonempty("orientation_constraints").and_then(|o| o.first()) {
            let f = "goal_constraints[0].orientation_constraints[0]";
            goal.orientation =
                d.pose(&serde_json::json!({ "orientation": d.get(oc, "orientation", f)? }), f)?.orientation;
            let tol = ["absolute_x_axis_tolerance", "absolute_y_axis_tolerance", "absolute_z_axis_tolerance"]
                .iter()
                .filter_map(|k| oc.get(*k).and_then(Value::as_f64))
                .fold(0.0, f64::max);
            goal.orientation_tolerance = if tol > 0.0 && tol.is_finite() { tol } else { 1e-2 };
        }
        GoalSpec::Pose(goal)
    } else {
        return Err(d.err("goal_constraints[0]", "neither joint nor position constraints"));
    };
    Ok(MbmRequest { group, start, goal })
}

fn find_robot(dir: &Path, name: &str) -> Option<(PathBuf, Option<PathBuf>)> {
    if name.is_empty() || name.contains(['/', '\\']) || name == ".." {
        return None;
    }
    // Absolute, so the search can climb above the working directory and the paths found do
    // not depend on it (a relative path would be resolved against the set's directory again).
    let dir = std::path::absolute(dir).ok()?;
    let mut at = Some(dir.as_path());
    for _ in 0..=ROBOT_SEARCH_LEVELS {
        let d = at?;
        for urdf in [d.join(format!("{name}.urdf")), d.join(name).join(format!("{name}.urdf"))] {
            if urdf.is_file() {
                let srdf = urdf.with_extension("srdf");
                return Some((urdf.clone(), srdf.is_file().then_some(srdf)));
            }
        }
        at = d.parent();
    }
    None
}

/// The problems of an MBM set directory and what they say about the robot.
#[derive(Clone, Debug, PartialEq)]
pub struct MbmProblems {
    /// The problems, in file-number order (named by their number, `0001`, ...).
    pub problems: Vec<Problem>,
    /// The scenes' `robot_model_name`.
    pub robot_model_name: String,
    /// The requests' `group_name`.
    pub group: String,
    /// The robot's base pose, if the scenes move it.
    pub base_pose: Option<PoseSpec>,
}

/// Reads the scene/request pairs of an MBM set directory.
///
/// # Errors
/// [`MotionError::ProblemSetIo`] / [`MotionError::ProblemSetTooLarge`] for unreadable files,
/// [`MotionError::ProblemSetInvalid`] for unpaired files, an empty directory, requests naming
/// different groups, scenes naming different robots or base poses; the errors of
/// [`parse_scene`] and [`parse_request`].
pub fn read_problems(dir: &Path) -> Result<MbmProblems> {
    let (scenes, requests) = list(dir)?;
    let invalid = |field: &str, reason: String| MotionError::ProblemSetInvalid {
        path: dir.to_path_buf(),
        field: field.into(),
        reason,
    };
    if scenes.is_empty() {
        return Err(invalid("directory", "no sceneNNNN.yaml / requestNNNN.yaml files".into()));
    }
    if let Some(i) = scenes.keys().find(|i| !requests.contains_key(i)) {
        return Err(invalid("directory", format!("scene {i} has no request file")));
    }
    if let Some(i) = requests.keys().find(|i| !scenes.contains_key(i)) {
        return Err(invalid("directory", format!("request {i} has no scene file")));
    }
    let mut problems = Vec::with_capacity(scenes.len());
    let (mut robot_name, mut group, mut base_pose) = (None::<String>, None::<String>, None);
    for (i, scene_path) in &scenes {
        let scene = parse_scene(&read_text(scene_path)?, scene_path)?;
        let request_path = &requests[i];
        let request = parse_request(&read_text(request_path)?, request_path)?;
        match &robot_name {
            None => robot_name = Some(scene.robot_model_name.clone()),
            Some(r) if *r != scene.robot_model_name => {
                return Err(invalid(
                    "robot_model_name",
                    format!("scene {i} is for `{}`, not `{r}`", scene.robot_model_name),
                ))
            }
            _ => {}
        }
        match &group {
            None => group = Some(request.group.clone()),
            Some(g) if *g != request.group => {
                return Err(invalid("group_name", format!("request {i} plans for `{}`, not `{g}`", request.group)))
            }
            _ => {}
        }
        if problems.is_empty() {
            base_pose = scene.base_pose;
        } else if scene.base_pose != base_pose {
            return Err(invalid("robot_state", format!("scene {i} moves the robot's base")));
        }
        problems.push(Problem {
            name: Some(format!("{i:04}")),
            obstacles: scene.obstacles,
            start: Configuration::Named(request.start),
            goal: request.goal,
            joints: BTreeMap::new(),
            allowed_collisions: scene.allowed_pairs,
        });
    }
    Ok(MbmProblems {
        problems,
        robot_model_name: robot_name.unwrap_or_default(),
        group: group.unwrap_or_default(),
        base_pose,
    })
}

/// Reads an MBM set directory: problems from its scene/request pairs ([`read_problems`]),
/// the robot found as in the [module docs](self) (the set's name is the directory's name).
///
/// # Errors
/// As [`read_problems`]; [`MotionError::ProblemSetInvalid`] if no robot is found.
pub fn load_dir(dir: &Path) -> Result<ProblemSet> {
    let read = read_problems(dir)?;
    let robot_name = &read.robot_model_name;
    let (urdf, srdf) = find_robot(dir, robot_name).ok_or_else(|| MotionError::ProblemSetInvalid {
        path: dir.to_path_buf(),
        field: "robot_model_name".into(),
        reason: format!(
            "no `{robot_name}.urdf` in the set's directory or {ROBOT_SEARCH_LEVELS} levels up (write a JSON problem set \
             naming the robot and `\"mbm\": \"{}\"`)",
            dir.display()
        ),
    })?;
    let mut packages = BTreeMap::new();
    if let Some(meshes) = urdf.parent().map(|p| p.join("meshes")).filter(|m| m.is_dir()) {
        packages.insert("meshes".to_string(), meshes);
    }
    let name = dir.file_name().and_then(|n| n.to_str()).unwrap_or("mbm").to_string();
    let set = ProblemSet {
        format: FORMAT.into(),
        version: VERSION,
        name,
        robot: RobotSpec { urdf: Some(urdf), srdf, stock: None, group: Some(read.group), packages },
        tip: None,
        base_pose: read.base_pose,
        problems: read.problems,
        mbm: None,
        source: dir.to_path_buf(),
    };
    set.validate()?;
    Ok(set)
}
