//! The worlds of the motion benchmark's scenes, rebuilt by name for drawing: the benchmark
//! scene (which generates a run's planning instance from its seed) plus the geometry its
//! checker was built from, as an [`opengrasp_core::scene::Scene`].
//!
//! Known scenes: the ARMAR-III kitchen scenes (`standard (ARMAR-III kitchen)`,
//! `IK-based (ARMAR-III kitchen)`: the stock kitchen with the humanoid at
//! [`opengrasp_bench::scenes::ARMAR_BASE`]), the 7-DoF stand-ins in the cupboard
//! ([`opengrasp_bench::scenes::cupboard`]), the tiny suite's `planar post`, and problem sets
//! ([`LoadedProblemSet::scene`]) given by the caller. The IK scenes' seeded target box is not
//! part of the rebuilt world; their goal pose is drawn instead (see [`crate::motion`]).

use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};
use opengrasp_bench::problem_sets::problem_set_scene;
use opengrasp_bench::scenes::{self, CheckerKind};
use opengrasp_bench::suite::planar_scene;
use opengrasp_core::model::{Geometry, Robot, Shape};
use opengrasp_core::scene::{RobotId, Scene, StaticBody};
use opengrasp_motion::benchmark::{BenchmarkScene, SceneInstance};
use opengrasp_motion::problem_set::LoadedProblemSet;
use opengrasp_motion::validity::ObstacleBox;

use crate::error::{Result, ViewerError};

/// A rebuilt motion scene: how to generate instances, and the world to draw them in.
pub struct MotionWorld {
    /// The benchmark scene (its `generate` gives a run's instance from the run's seed).
    pub scene: BenchmarkScene,
    /// Geometry of the world of `seed` with the planning robot at its full configuration.
    pub world: Scene,
    /// The planning robot in `world`.
    pub robot: RobotId,
    /// The planning instance of `seed`.
    pub instance: SceneInstance,
}

impl MotionWorld {
    /// Rebuilds scene `name` and its instance for `seed`. `base_seed` is the benchmark's
    /// seed (problem sets map run `seed − base_seed` to a problem); `sets` are the problem
    /// sets the results were produced with (empty when none).
    ///
    /// # Errors
    /// [`ViewerError::UnknownScene`] for a scene the viewer cannot rebuild; the scene's own
    /// errors generating the instance.
    pub fn rebuild(name: &str, seed: u64, base_seed: u64, sets: &[Arc<LoadedProblemSet>]) -> Result<Self> {
        let set = sets.iter().find(|s| s.name() == name);
        let scene = match set {
            Some(set) => problem_set_scene(set.clone(), base_seed),
            None => known_scene(name)?,
        };
        let instance = (scene.generate)(seed)?;
        let (mut world, robot) = match set {
            Some(set) => {
                let index = (seed.wrapping_sub(base_seed) % set.len().max(1) as u64) as usize;
                let world = set.scene(index)?;
                (world, RobotId(0))
            }
            None => geometry_of(name, &instance.robot)?,
        };
        world.set_robot_configuration(robot, &instance.q_full)?;
        Ok(Self { scene, world, robot, instance })
    }

    /// The world with the planning robot at group configuration `q`.
    ///
    /// # Errors
    /// [`ViewerError::Core`] if `q` has the wrong size or is outside the limits.
    pub fn at(&self, q: &[f64]) -> Result<Scene> {
        let mut world = self.world.clone();
        world.set_robot_configuration(self.robot, &self.full(q)?)?;
        Ok(world)
    }

    /// The full configuration of group configuration `q`.
    ///
    /// # Errors
    /// [`ViewerError::Core`] if `q` has the wrong size.
    pub fn full(&self, q: &[f64]) -> Result<Vec<f64>> {
        let mut full = self.instance.q_full.clone();
        self.instance.group.insert(&mut full, q)?;
        Ok(full)
    }
}

/// The reference scenes by name.
fn known_scene(name: &str) -> Result<BenchmarkScene> {
    let all = [
        scenes::armar_standard_scene(),
        scenes::armar_ik_scene(),
        scenes::standard_scene(CheckerKind::Exact),
        scenes::standard_scene(CheckerKind::Spheres),
        scenes::ik_scene(CheckerKind::Exact),
        planar_scene(),
    ];
    let known: Vec<String> = all.iter().map(|s| s.name.clone()).collect();
    all.into_iter().find(|s| s.name == name).ok_or_else(|| ViewerError::UnknownScene {
        scene: name.to_string(),
        reason: format!("known scenes: {}; problem sets need their files", known.join(", ")),
    })
}

/// The static geometry of a reference scene, with its robot.
fn geometry_of(name: &str, robot: &Arc<Robot>) -> Result<(Scene, RobotId)> {
    if name.contains("ARMAR-III kitchen") {
        let kitchen = opengrasp_assets::scenes::kitchen()?;
        return Ok((kitchen.scene, kitchen.robot));
    }
    let boxes = if name.contains("7-DoF stand-in") {
        scenes::cupboard()
    } else if name == planar_scene().name {
        vec![ObstacleBox::new("post", Isometry3::translation(0.6, 0.0, 0.0), Vector3::new(0.1, 0.1, 0.5))]
    } else {
        return Err(ViewerError::UnknownScene { scene: name.into(), reason: "no geometry known".into() });
    };
    let mut scene = Scene::new(name);
    let id = scene.add_robot("arm", robot.clone(), Isometry3::identity())?;
    for b in boxes {
        let shape = Shape::at_origin(Geometry::Box { half_extents: b.half_extents });
        scene.add_body(StaticBody::new(b.name.clone(), b.pose, vec![shape]))?;
    }
    Ok((scene, id))
}
