//! A replayed motion run as pictures: the states along its paths, where the end effector
//! goes, which states are invalid and which link pair collides there.

use nalgebra::Point3;
use opengrasp_core::collision::{Collider, CollisionWorld};
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::scene::Scene;
use opengrasp_motion::metrics::densify;

use crate::drawing::{Dot, Drawing, Kind, Polyline};
use crate::error::Result;
use crate::replay::ReplayedRun;
use crate::world::MotionWorld;

/// Colour of the planned path.
pub const PLANNED: [u8; 3] = [235, 140, 20];
/// Colour of the post-processed path.
pub const PROCESSED: [u8; 3] = [20, 150, 60];
/// Colour of invalid states.
pub const INVALID: [u8; 3] = [220, 20, 20];
/// Colour of a pose goal's target.
pub const GOAL: [u8; 3] = [120, 40, 200];

/// One state of a densified path.
#[derive(Clone, Debug, PartialEq)]
pub struct PathState {
    /// Group configuration.
    pub q: Vec<f64>,
    /// World position of the end effector (the instance's tip link, else the robot's last
    /// link).
    pub tip: Point3<f64>,
    /// False if the run's checker rejects the state.
    pub valid: bool,
}

/// The states of `path` at most `step` apart, with their tips and validity.
///
/// # Errors
/// [`crate::ViewerError::Core`] if a state does not fit the robot.
pub fn path_states(world: &MotionWorld, path: &[Vec<f64>], step: f64) -> Result<Vec<PathState>> {
    let inst = &world.instance;
    let tip = inst.tip.map_or(inst.robot.links().len().saturating_sub(1), |t| t.0);
    let base = world.world.robot(world.robot)?.base_pose;
    densify(path, step)
        .into_iter()
        .map(|q| -> Result<PathState> {
            let poses = forward_kinematics(&inst.robot, &world.full(&q)?)?;
            let tip = base * poses.as_slice()[tip] * Point3::origin();
            let valid = inst.checker.is_valid(&q);
            Ok(PathState { q, tip, valid })
        })
        .collect()
}

/// The names of the mesh pairs in collision at group configuration `q` (as in
/// [`opengrasp_assets::export::scene_meshes`]: `robot/link` and body or object names, a
/// shape index appended for multi-shape parts is not), deepest first.
///
/// # Errors
/// [`crate::ViewerError::Core`] if the world cannot be built or `q` does not fit.
pub fn colliding_pairs(world: &MotionWorld, q: &[f64]) -> Result<Vec<(String, String)>> {
    let scene = world.at(q)?;
    let collision = CollisionWorld::new(&scene)?;
    let full = world.full(q)?;
    let mut contacts = collision.contacts(world.robot, &full, 0.0)?;
    contacts.retain(|c| c.depth > 0.0);
    contacts.sort_by(|a, b| b.depth.total_cmp(&a.depth));
    let robot = scene.robot(world.robot)?;
    let link = |r: &str, l: usize| format!("{r}/{}", robot.robot.links()[l].name);
    let mut pairs: Vec<(String, String)> = Vec::new();
    for c in contacts {
        let other = match c.other {
            Collider::Body(b) => scene.body(b)?.name.clone(),
            Collider::Object(o) => scene.object(o)?.name.clone(),
            Collider::Link(r, l) => {
                let other = scene.robot(r)?;
                format!("{}/{}", other.name, other.robot.links()[l.0].name)
            }
        };
        let pair = (link(&robot.name, c.link.0), other);
        if !pairs.contains(&pair) {
            pairs.push(pair);
        }
    }
    Ok(pairs)
}

/// Mesh names of a part named `name` in a scene's meshes (`name`, or `name_0`, `name_1`, ...).
pub fn mesh_names_of(drawing: &Drawing, name: &str) -> Vec<String> {
    drawing
        .meshes
        .iter()
        .filter(|m| {
            m.name == name
                || m.name
                    .strip_prefix(name)
                    .and_then(|s| s.strip_prefix('_'))
                    .is_some_and(|s| s.parse::<usize>().is_ok())
        })
        .map(|m| m.name.clone())
        .collect()
}

/// The drawing of a world with the robot at `q`; parts in collision coloured
/// [`Kind::Colliding`].
///
/// # Errors
/// As [`colliding_pairs`].
pub fn state_drawing(world: &MotionWorld, q: &[f64]) -> Result<Drawing> {
    let scene: Scene = world.at(q)?;
    let mut drawing = Drawing::new();
    drawing.add_scene(&scene, Kind::Robot)?;
    for (a, b) in colliding_pairs(world, q)? {
        let names: Vec<String> = [a, b].iter().flat_map(|n| mesh_names_of(&drawing, n)).collect();
        drawing.mark_colliding(&names);
    }
    Ok(drawing)
}

/// The snapshot of a replayed run: the world with the robot at the start, a lighter robot at
/// the end of the post-processed path (or at the first invalid state of the planned path,
/// with the colliding parts in red, if it has one), the end effector's planned path in
/// orange, the post-processed one in green, invalid states as red dots and a pose goal's
/// target as a purple dot. `step` is the
/// densification step (rad).
///
/// # Errors
/// As [`path_states`] and [`colliding_pairs`].
pub fn run_drawing(run: &ReplayedRun, step: f64) -> Result<Drawing> {
    let world = &run.world;
    let mut drawing = Drawing::new();
    drawing.add_scene(&world.at(&world.instance.start)?, Kind::Robot)?;
    let planned = path_states(world, &run.planned, step)?;
    let processed = path_states(world, &run.processed, step)?;
    let first_invalid = planned.iter().find(|s| !s.valid);
    let second = first_invalid.map(|s| s.q.clone()).or_else(|| run.processed.last().cloned());
    if let Some(q) = second {
        let mut ghost = state_drawing(world, &q)?;
        ghost.meshes.retain(|m| m.kind != Kind::Environment && m.kind != Kind::Object);
        for m in &mut ghost.meshes {
            if m.kind == Kind::Robot {
                m.kind = Kind::Ghost;
                m.colour = Kind::Ghost.colour();
            }
            m.name = format!("ghost/{}", m.name);
        }
        // Environment parts in collision are recoloured in the main drawing.
        let hit: Vec<String> = colliding_pairs(world, &q)?.into_iter().map(|(_, b)| b).collect();
        let names: Vec<String> = hit.iter().flat_map(|n| mesh_names_of(&drawing, n)).collect();
        drawing.mark_colliding(&names);
        drawing.meshes.extend(ghost.meshes);
    }
    for (name, colour, states) in [("planned", PLANNED, &planned), ("processed", PROCESSED, &processed)] {
        if !states.is_empty() {
            drawing.lines.push(Polyline { name: name.into(), colour, points: states.iter().map(|s| s.tip).collect() });
        }
    }
    if let opengrasp_motion::problem::Goal::Pose(goal) = &world.instance.goal {
        let base = world.world.robot(world.robot)?.base_pose;
        let target = base * Point3::from(goal.target.translation.vector);
        drawing.dots.push(Dot { name: "goal".into(), colour: GOAL, position: target });
    }
    for (i, s) in planned.iter().enumerate().filter(|(_, s)| !s.valid) {
        drawing.dots.push(Dot { name: format!("invalid/{i}"), colour: INVALID, position: s.tip });
    }
    Ok(drawing)
}
