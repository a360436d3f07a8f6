//! Quickstart: load a robot from URDF, run forward and inverse kinematics, query collisions
//! and clearance, and simulate a box falling onto a table with both physics backends.
//!
//! ```sh
//! cargo run --release --example quickstart
//! ```

use std::sync::Arc;
use std::time::Instant;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp::core::collision::CollisionWorld;
use opengrasp::core::kinematics::{forward_kinematics, jacobian, solve_ik, IkOptions};
use opengrasp::core::model::{samples, Geometry, Shape};
use opengrasp::core::physics::{MockBackend, PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp::core::scene::{Scene, SceneObject, StaticBody};
use opengrasp::core::{urdf, Result};

fn main() -> Result<()> {
    // 1. A robot written to URDF (+ meshes) and loaded back, as a user's own robot would be.
    let dir = std::env::temp_dir().join(format!("opengrasp-quickstart-{}", std::process::id()));
    let urdf_path = urdf::export(&samples::seven_dof_arm()?, &dir)?;
    let mut robot = urdf::load_file(&urdf_path)?;
    // URDF carries no semantic data: joint groups and disabled collision pairs (an SRDF's job)
    // are added in code.
    robot.add_group("arm", &["joint1", "joint2", "joint3", "joint4", "joint5", "joint6", "joint7"])?;
    robot.allow_collision("link5", "link7")?;
    println!(
        "robot `{}` from {}: {} links, {} dof",
        robot.name(),
        urdf_path.display(),
        robot.links().len(),
        robot.dof()
    );

    // 2. Forward kinematics and the Jacobian.
    let tool = robot.link_id("tool")?;
    let q = [0.3, 0.6, -0.2, -1.2, 0.1, 0.8, 0.0];
    let pose = forward_kinematics(&robot, &q)?[tool];
    let t = pose.translation.vector;
    println!("FK: tool at ({:.4}, {:.4}, {:.4}) m", t.x, t.y, t.z);
    let j = jacobian(&robot, &q, tool, &Point3::origin(), robot.group("arm")?.dofs())?;
    println!(
        "Jacobian 6x{}: manipulability sqrt(det(J J^T)) = {:.4}",
        j.ncols(),
        (&j * j.transpose()).determinant().sqrt()
    );

    // 3. Inverse kinematics back to that pose from the home configuration.
    let started = Instant::now();
    let ik = solve_ik(&robot, robot.group("arm")?, tool, &pose, &robot.home_configuration(), &IkOptions::default())?;
    println!(
        "IK: {:?} in {:.1} µs, {} iterations, {} restarts, error {:.2e} m / {:.2e} rad",
        ik.status,
        started.elapsed().as_secs_f64() * 1e6,
        ik.iterations,
        ik.restarts,
        ik.position_error,
        ik.orientation_error
    );

    // 4. Collision and clearance against a table and a shelf.
    let mut scene = Scene::new("quickstart");
    let robot = Arc::new(robot);
    let arm = scene.add_robot("arm", robot.clone(), Isometry3::identity())?;
    let table_top = Shape::at_origin(Geometry::cuboid(0.8, 1.2, 0.04));
    scene.add_body(StaticBody::new("table", Isometry3::translation(0.75, 0.0, 0.70), vec![table_top]))?;
    let shelf = Shape::at_origin(Geometry::cuboid(0.3, 0.3, 0.02));
    scene.add_body(StaticBody::new("shelf", Isometry3::translation(0.0, 0.6, 1.2), vec![shelf]))?;
    let world = CollisionWorld::new(&scene)?;
    for (name, q) in
        [("home", vec![0.0; 7]), ("reaching", q.to_vec()), ("into table", vec![0.0, 0.9, 0.0, 0.0, 0.0, 0.0, 0.0])]
    {
        let report = world.distance(arm, &q)?;
        println!(
            "collision `{name}`: in collision = {}, min distance {:.4} m ({} <-> {:?})",
            world.in_collision(arm, &q)?,
            report.distance,
            robot.link(report.link).name,
            report.other
        );
    }
    let checks = 20_000;
    let started = Instant::now();
    let mut hits = 0;
    for i in 0..checks {
        let s = i as f64 / checks as f64;
        let qi = [s - 0.5, 1.6 * s, 0.0, 0.4, 0.0, 0.0, 0.0];
        hits += usize::from(world.in_collision_unchecked(arm, &qi));
    }
    println!(
        "{checks} collision checks: {:.2} µs each ({hits} in collision)",
        started.elapsed().as_secs_f64() * 1e6 / checks as f64
    );

    // 5. Physics: a 10 cm box dropped onto the table, on both backends (same program).
    let mut drop_scene = Scene::new("drop");
    drop_scene.add_body(StaticBody::new(
        "table",
        Isometry3::translation(0.75, 0.0, 0.70),
        vec![Shape::at_origin(Geometry::cuboid(0.8, 1.2, 0.04))],
    ))?;
    let cube = drop_scene.add_object(SceneObject::new(
        "cube",
        Isometry3::translation(0.75, 0.0, 1.0),
        vec![Shape::at_origin(Geometry::cuboid(0.1, 0.1, 0.1))],
        0.5,
    ))?;
    let expected = 0.70 + 0.02 + 0.05;
    simulate::<RapierBackend>(&drop_scene, cube, expected)?;
    // The mock integrates joints exactly but has no contact dynamics: objects stay where they are.
    simulate::<MockBackend>(&drop_scene, cube, expected)?;
    std::fs::remove_dir_all(&dir).ok();
    Ok(())
}

fn simulate<E: PhysicsEngine>(scene: &Scene, cube: opengrasp::core::scene::ObjectId, expected_rest: f64) -> Result<()> {
    let mut engine = E::from_scene(scene, &PhysicsOptions::default())?;
    let started = Instant::now();
    let steps = 480;
    engine.step_n(steps, 1.0 / 240.0)?;
    let z = engine.object_pose(cube)?.translation.z;
    let v: Vector3<f64> = engine.object_velocity(cube)?.linear;
    println!(
        "physics [{}]: after {:.1} s the cube is at z = {:.4} m (table rest height {:.4} m), |v| = {:.4} m/s; {:.1} µs/step",
        engine.name(),
        engine.time(),
        z,
        expected_rest,
        v.norm(),
        started.elapsed().as_secs_f64() * 1e6 / steps as f64
    );
    Ok(())
}
