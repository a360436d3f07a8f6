//! The benchmark scenes: the kitchen of the seed paper (Fig. 3) with the humanoid and the
//! objects at named locations, and a bare table top for grasp benchmarks.
//!
//! World frame: floor at z = 0, the room spans x ∈ [0, 6] m, y ∈ [0, 5] m, the counter runs
//! along the back wall (y = 5), the front (y = 0) is open.

use std::collections::BTreeMap;
use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

use nalgebra::Isometry3;
use opengrasp_core::model::{Geometry, Robot, Shape};
use opengrasp_core::scene::{RobotId, Scene, StaticBody};

use crate::error::{AssetError, Result};
use crate::hands::iso;
use crate::objects::{self, ObjectModel};
use crate::robots;

/// Key dimensions of the kitchen furniture (m).
pub mod dims {
    /// Worktop height of the counter and sink.
    pub const COUNTER_HEIGHT: f64 = 0.90;
    /// Counter depth.
    pub const COUNTER_DEPTH: f64 = 0.60;
    /// Table top height of the red table (and of [`super::table_top`]).
    pub const TABLE_HEIGHT: f64 = 0.75;
    /// Red table top size (x, y).
    pub const TABLE_SIZE: [f64; 2] = [1.2, 0.8];
    /// Table top thickness.
    pub const TABLE_THICKNESS: f64 = 0.03;
    /// Green sideboard size (x, y, z).
    pub const SIDEBOARD_SIZE: [f64; 3] = [0.5, 1.2, 0.85];
    /// Fridge size (x, y, z).
    pub const FRIDGE_SIZE: [f64; 3] = [0.6, 0.65, 1.8];
    /// Wall height.
    pub const WALL_HEIGHT: f64 = 2.6;
}

/// The kitchen scene with its named locations.
#[derive(Clone, Debug)]
pub struct Kitchen {
    /// Static furniture, the nine objects and the robot (stock: `armar3`) at its start pose.
    pub scene: Scene,
    /// The humanoid's handle in [`Kitchen::scene`].
    pub robot: RobotId,
    /// The humanoid's start configuration (base x, y, yaw in its joints), also set in the scene.
    pub start_configuration: Vec<f64>,
    /// Named places (world poses of an object frame resting on a surface): every object's
    /// initial place under its own name, plus `red_table_centre`, `sideboard_centre`,
    /// `counter_left`, `counter_right`, `sink`.
    pub locations: BTreeMap<String, Isometry3<f64>>,
}

impl Kitchen {
    /// The pose of a named location.
    ///
    /// # Errors
    /// [`AssetError::UnknownAsset`] for an unknown name.
    pub fn location(&self, name: &str) -> Result<Isometry3<f64>> {
        self.locations
            .get(name)
            .copied()
            .ok_or_else(|| AssetError::UnknownAsset { kind: "location", name: name.to_string() })
    }
}

fn boxed(size: [f64; 3], centre: [f64; 3]) -> Shape {
    Shape::new(Isometry3::translation(centre[0], centre[1], centre[2]), Geometry::cuboid(size[0], size[1], size[2]))
}

/// A table of top size `sx × sy` at `height`, legs inset 5 cm, body frame at floor centre.
fn table_shapes(sx: f64, sy: f64, height: f64) -> Vec<Shape> {
    use dims::TABLE_THICKNESS as t;
    let mut shapes = vec![boxed([sx, sy, t], [0.0, 0.0, height - t / 2.0])];
    let leg = 0.05;
    let (lx, ly) = (sx / 2.0 - 0.05 - leg / 2.0, sy / 2.0 - 0.05 - leg / 2.0);
    for (x, y) in [(lx, ly), (lx, -ly), (-lx, ly), (-lx, -ly)] {
        shapes.push(boxed([leg, leg, height - t], [x, y, (height - t) / 2.0]));
    }
    shapes
}

fn add(scene: &mut Scene, name: &str, pose: Isometry3<f64>, shapes: Vec<Shape>) -> Result<()> {
    scene.add_body(StaticBody::new(name, pose, shapes))?;
    Ok(())
}

/// The static kitchen with its objects, and the named locations.
fn kitchen_environment() -> Result<(Scene, BTreeMap<String, Isometry3<f64>>)> {
    use dims::*;
    let mut scene = Scene::new("kitchen");
    let id = Isometry3::identity();
    let (w, d, h) = (6.0, 5.0, WALL_HEIGHT);
    add(&mut scene, "floor", id, vec![boxed([w, d, 0.02], [w / 2.0, d / 2.0, -0.01])])?;
    add(&mut scene, "wall_back", id, vec![boxed([w, 0.1, h], [w / 2.0, d + 0.05, h / 2.0])])?;
    add(&mut scene, "wall_left", id, vec![boxed([0.1, d, h], [-0.05, d / 2.0, h / 2.0])])?;
    add(&mut scene, "wall_right", id, vec![boxed([0.1, d, h], [w + 0.05, d / 2.0, h / 2.0])])?;
    // Counter along the back wall, x ∈ [0.5, 3.5], with the sink basin at x ∈ [2.0, 2.6].
    let cy = d - COUNTER_DEPTH / 2.0 - 0.02;
    let top = 0.04;
    let counter_part = |x0: f64, x1: f64| {
        vec![
            boxed([x1 - x0, COUNTER_DEPTH, COUNTER_HEIGHT - top], [(x0 + x1) / 2.0, cy, (COUNTER_HEIGHT - top) / 2.0]),
            boxed([x1 - x0, COUNTER_DEPTH, top], [(x0 + x1) / 2.0, cy, COUNTER_HEIGHT - top / 2.0]),
        ]
    };
    add(&mut scene, "counter_left", id, counter_part(0.5, 2.0))?;
    add(&mut scene, "counter_right", id, counter_part(2.6, 3.5))?;
    let (sx0, sx1, basin_bottom) = (2.0, 2.6, COUNTER_HEIGHT - 0.2);
    let wall = 0.02;
    add(
        &mut scene,
        "sink",
        id,
        vec![
            boxed([sx1 - sx0, COUNTER_DEPTH, basin_bottom], [(sx0 + sx1) / 2.0, cy, basin_bottom / 2.0]),
            boxed([wall, COUNTER_DEPTH, 0.2], [sx0 + wall / 2.0, cy, basin_bottom + 0.1]),
            boxed([wall, COUNTER_DEPTH, 0.2], [sx1 - wall / 2.0, cy, basin_bottom + 0.1]),
            boxed(
                [sx1 - sx0 - 2.0 * wall, wall, 0.2],
                [(sx0 + sx1) / 2.0, cy - COUNTER_DEPTH / 2.0 + wall / 2.0, basin_bottom + 0.1],
            ),
            boxed(
                [sx1 - sx0 - 2.0 * wall, 0.1, 0.2],
                [(sx0 + sx1) / 2.0, cy + COUNTER_DEPTH / 2.0 - 0.05, basin_bottom + 0.1],
            ),
            // Tap on the back rim.
            Shape::new(
                Isometry3::translation((sx0 + sx1) / 2.0, cy + COUNTER_DEPTH / 2.0 - 0.05, COUNTER_HEIGHT + 0.15),
                Geometry::Cylinder { radius: 0.015, length: 0.3 },
            ),
            boxed([0.03, 0.2, 0.03], [(sx0 + sx1) / 2.0, cy + COUNTER_DEPTH / 2.0 - 0.15, COUNTER_HEIGHT + 0.285]),
        ],
    )?;
    add(
        &mut scene,
        "wall_cabinets",
        id,
        vec![boxed([3.0, 0.35, 0.7], [2.0, d - 0.175, 1.85]), boxed([1.0, 0.35, 0.7], [4.6, d - 0.175, 1.85])],
    )?;
    let [fx, fy, fz] = FRIDGE_SIZE;
    add(&mut scene, "fridge", id, vec![boxed(FRIDGE_SIZE, [3.55 + fx / 2.0, d - fy / 2.0 - 0.02, fz / 2.0])])?;
    add(&mut scene, "cabinet", id, vec![boxed([0.8, 0.6, 0.85], [4.7, d - 0.32, 0.425])])?;
    // Red table (Clean the Table source) in the middle of the room.
    let table_centre = [2.0, 2.2];
    add(
        &mut scene,
        "red_table",
        Isometry3::translation(table_centre[0], table_centre[1], 0.0),
        table_shapes(TABLE_SIZE[0], TABLE_SIZE[1], TABLE_HEIGHT),
    )?;
    // Green sideboard (Clean the Table target) against the right wall.
    let [bx, _, bz] = SIDEBOARD_SIZE;
    let sideboard_centre = [w - bx / 2.0 - 0.02, 2.2];
    add(
        &mut scene,
        "green_sideboard",
        Isometry3::translation(sideboard_centre[0], sideboard_centre[1], 0.0),
        vec![boxed(SIDEBOARD_SIZE, [0.0, 0.0, bz / 2.0])],
    )?;
    let mut locations = BTreeMap::new();
    let on = |x: f64, y: f64, z: f64, yaw: f64| iso(x, y, z, 0.0, 0.0, yaw);
    locations.insert("red_table_centre".to_string(), on(table_centre[0], table_centre[1], TABLE_HEIGHT, 0.0));
    locations.insert("sideboard_centre".to_string(), on(sideboard_centre[0], sideboard_centre[1], bz, 0.0));
    locations.insert("counter_left".to_string(), on(1.2, cy, COUNTER_HEIGHT, 0.0));
    locations.insert("counter_right".to_string(), on(3.1, cy, COUNTER_HEIGHT, 0.0));
    locations.insert("sink".to_string(), on((sx0 + sx1) / 2.0, cy - 0.03, basin_bottom, 0.0));
    // Objects: cups and the salt can on the red table, the rest on the counter.
    let places: [(&str, Isometry3<f64>); 9] = [
        ("white_cup", on(1.75, 2.35, TABLE_HEIGHT, -FRAC_PI_2)),
        ("green_cup", on(2.05, 2.25, TABLE_HEIGHT, -FRAC_PI_2)),
        ("salt_can", on(2.3, 1.97, TABLE_HEIGHT, 0.0)),
        ("measuring_cup", on(1.55, 2.45, TABLE_HEIGHT, 0.0)),
        ("bread_box", on(0.8, cy, COUNTER_HEIGHT, 0.0)),
        ("chocolate_box", on(1.25, cy - 0.1, COUNTER_HEIGHT, 0.0)),
        ("salt_box", on(1.6, cy, COUNTER_HEIGHT, 0.0)),
        ("detergent_bottle", on(2.85, cy + 0.1, COUNTER_HEIGHT, 0.0)),
        ("spray_bottle", on(3.2, cy, COUNTER_HEIGHT, 0.0)),
    ];
    for (name, pose) in places {
        let o = objects::by_name(name)?;
        scene.add_object(o.to_scene_object(pose))?;
        locations.insert(name.to_string(), pose);
    }
    // The humanoid in front of the red table, facing it (+y). The platform's lower body
    // (0.45 m high) fits under the table top (0.72 m), so the robot stands with its hip column
    // 0.2 m from the table edge.
    let start_base = [table_centre[0], table_centre[1] - TABLE_SIZE[1] / 2.0 - 0.2, FRAC_PI_2];
    locations.insert("robot_start".to_string(), on(start_base[0], start_base[1], 0.0, start_base[2]));
    Ok((scene, locations))
}

/// The kitchen: floor, three walls, counter with sink and wall cabinets, fridge, the red table
/// and the green sideboard of "Clean the Table", the nine stock objects and the humanoid
/// ([`robots::armar3`]) in front of the red table, facing it (location `robot_start`, reached
/// through its base joints).
///
/// # Errors
/// Only if a stock model were invalid ([`AssetError::Core`]); covered by tests.
pub fn kitchen() -> Result<Kitchen> {
    let robot = Arc::new(robots::armar3());
    let (scene, locations) = kitchen_environment()?;
    let start = locations["robot_start"];
    let mut q = robot.home_configuration();
    let yaw = start.rotation.euler_angles().2;
    for (joint, v) in ["base_x", "base_y", "base_yaw"].iter().zip([start.translation.x, start.translation.y, yaw]) {
        q[robot.dof_index(joint)?] = v;
    }
    finish(scene, locations, robot, Isometry3::identity(), q)
}

/// The kitchen with the user's robot instead of the humanoid, its root link at `base_pose`
/// (e.g. `Kitchen::location("robot_start")` for a robot without base joints) in
/// configuration `q`.
///
/// # Errors
/// [`AssetError::Core`] for a bad pose or a configuration of the wrong length, out of limits
/// or not finite.
pub fn kitchen_with_robot(robot: Arc<Robot>, base_pose: Isometry3<f64>, q: &[f64]) -> Result<Kitchen> {
    robot.validate_configuration(q)?;
    let (scene, locations) = kitchen_environment()?;
    finish(scene, locations, robot, base_pose, q.to_vec())
}

fn finish(
    mut scene: Scene,
    locations: BTreeMap<String, Isometry3<f64>>,
    robot: Arc<Robot>,
    base_pose: Isometry3<f64>,
    q: Vec<f64>,
) -> Result<Kitchen> {
    let name = robot.name().to_string();
    let rid = scene.add_robot(name, robot, base_pose)?;
    scene.set_robot_configuration(rid, &q)?;
    Ok(Kitchen { scene, robot: rid, start_configuration: q, locations })
}

/// A bare table (top 0.8 × 0.8 m at 0.75 m) with `object` standing in the middle of it, for
/// grasp benchmarks. Add a hand with `scene.add_robot`.
///
/// # Errors
/// [`AssetError::Core`] if the object is rejected by the scene (e.g. a non-positive mass).
pub fn table_top(object: &ObjectModel) -> Result<Scene> {
    let mut scene = Scene::new(format!("table_top_{}", object.name));
    scene.add_body(StaticBody::new("table", Isometry3::identity(), table_shapes(0.8, 0.8, dims::TABLE_HEIGHT)))?;
    scene.add_object(object.to_scene_object(Isometry3::translation(0.0, 0.0, dims::TABLE_HEIGHT)))?;
    Ok(scene)
}

/// The table-top surface height used by [`table_top`] and the red table (m).
pub fn table_height() -> f64 {
    dims::TABLE_HEIGHT
}
