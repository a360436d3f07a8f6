//! Logging to rerun (feature `rerun`): scenes, robots at their link poses, motion runs as
//! time-scrubbable trajectories, grasps with contacts, friction cones and tactile frames.
//!
//! Entities (parts are [`file_token`]s of the names):
//!
//! - `scenes/<scene>/world/<mesh>`: the scene's static bodies and objects (static);
//! - `scenes/<scene>/<run>/planned/robot/<link>/<shape>`: the robot's link meshes in link
//!   frames (static), posed by a `Transform3D` on `.../robot/<link>` at every state of the
//!   planned path on timeline `planned` (sequence 0, 1, …); the same under `processed/` on
//!   timeline `processed`; link meshes in collision turn red at invalid states, and
//!   `.../planned/status` holds a text of the colliding pair;
//! - `.../planned/tip_path`, `.../processed/tip_path`: the end effector's path (static),
//!   `.../planned/invalid_states`: tips of the invalid states (static, red);
//! - `grasps/<planner>/<hand>/<object>/<index>/`: `object`, `hand/<link>` (coloured by force
//!   closure), `contacts`, `friction_cones` (static), `tactile/<pad>` images (the static
//!   frame) and, when recorded, the squeeze series on timeline `tactile_time` (seconds).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3};
use opengrasp_bench::results::ResultsFile;
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::scene::Scene;
use opengrasp_grasp::tactile::CompactFrame;
use opengrasp_motion::problem_set::LoadedProblemSet;
use rerun::{Color, LineStrips3D, Mesh3D, Points3D, RecordingStream, TextDocument, Transform3D};

use crate::drawing::{Drawing, Kind, MeshItem};
use crate::error::{Result, ViewerError};
use crate::grasp::{best_candidate, find_grasp, grasp_drawing, grasp_id, replay_grasp, ReplayedGrasp};
use crate::motion::{colliding_pairs, path_states, PathState, INVALID, PLANNED, PROCESSED};
use crate::replay::{first_replayable, replay, run_id, ReplayedRun};
use crate::snapshot::file_token;
use crate::world::MotionWorld;

/// Application id of the recordings.
pub const APPLICATION_ID: &str = "opengrasp";

/// Largest raw tactile value (12 bit): white in the tactile images.
const TACTILE_MAX: f64 = 4095.0;

fn rerun_err(e: impl std::fmt::Display) -> ViewerError {
    ViewerError::Rerun { reason: e.to_string() }
}

fn rgba(c: [u8; 3]) -> Color {
    Color::from_rgb(c[0], c[1], c[2])
}

fn albedo(c: [u8; 3]) -> [u8; 4] {
    [c[0], c[1], c[2], 255]
}

fn p32(p: &Point3<f64>) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
}

fn transform(pose: &Isometry3<f64>) -> Transform3D {
    let q = pose.rotation.coords;
    Transform3D::from_translation_rotation(
        p32(&Point3::from(pose.translation.vector)),
        rerun::Quaternion::from_xyzw([q.x as f32, q.y as f32, q.z as f32, q.w as f32]),
    )
}

fn mesh(item: &MeshItem) -> Mesh3D {
    Mesh3D::new(item.mesh.vertices().iter().map(p32))
        .with_triangle_indices(item.mesh.triangles().iter().copied())
        .with_albedo_factor(albedo(item.colour))
}

/// What `opengrasp view` records.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Selection {
    /// Per motion scene its first solved run that replays; per grasp cell its best grasp.
    #[default]
    Overview,
    /// One motion run (`planner/scene/run` or its position).
    Run(String),
    /// One grasp candidate (`planner/hand/object/index` or its position).
    Grasp(String),
}

/// A rerun recording being written.
pub struct Recorder {
    rec: RecordingStream,
}

impl Recorder {
    /// A recording written to the `.rrd` file `path`.
    ///
    /// # Errors
    /// [`ViewerError::Rerun`] if the file cannot be created.
    pub fn to_file(path: &Path) -> Result<Self> {
        let rec = rerun::RecordingStreamBuilder::new(APPLICATION_ID).save(path).map_err(rerun_err)?;
        Ok(Self { rec })
    }

    /// The underlying stream.
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// Flushes everything to the sink.
    ///
    /// # Errors
    /// [`ViewerError::Rerun`] if writing fails.
    pub fn finish(self) -> Result<()> {
        self.rec.flush_blocking().map_err(rerun_err)
    }

    fn log_static(&self, path: &str, what: &impl rerun::AsComponents) -> Result<()> {
        self.rec.log_static(path, what).map_err(rerun_err)
    }

    fn log(&self, path: &str, what: &impl rerun::AsComponents) -> Result<()> {
        self.rec.log(path, what).map_err(rerun_err)
    }

    /// Logs a drawing statically under `prefix`: meshes at `prefix/<mesh>`, lines as one
    /// `LineStrips3D` per name group, dots as `Points3D`.
    ///
    /// # Errors
    /// [`ViewerError::Rerun`].
    pub fn log_drawing(&self, prefix: &str, drawing: &Drawing) -> Result<()> {
        for m in &drawing.meshes {
            self.log_static(&format!("{prefix}/{}", entity(&m.name)), &mesh(m))?;
        }
        let mut lines: BTreeMap<String, Vec<&crate::drawing::Polyline>> = BTreeMap::new();
        for l in &drawing.lines {
            lines.entry(group_of(&l.name)).or_default().push(l);
        }
        for (group, ls) in lines {
            let strips = LineStrips3D::new(ls.iter().map(|l| l.points.iter().map(p32).collect::<Vec<_>>()))
                .with_colors(ls.iter().map(|l| rgba(l.colour)));
            self.log_static(&format!("{prefix}/{group}"), &strips)?;
        }
        let mut dots: BTreeMap<String, Vec<&crate::drawing::Dot>> = BTreeMap::new();
        for d in &drawing.dots {
            dots.entry(group_of(&d.name)).or_default().push(d);
        }
        for (group, ds) in dots {
            let points = Points3D::new(ds.iter().map(|d| p32(&d.position)))
                .with_colors(ds.iter().map(|d| rgba(d.colour)))
                .with_radii([0.008f32]);
            self.log_static(&format!("{prefix}/{group}"), &points)?;
        }
        Ok(())
    }

    /// Logs a replayed motion run under `prefix`: the world (static), then the planned and
    /// post-processed paths as animated robots on timelines `planned` and `processed`.
    ///
    /// # Errors
    /// [`ViewerError::Rerun`]; core errors computing the states.
    pub fn log_run(&self, prefix: &str, run: &ReplayedRun, step: f64) -> Result<()> {
        let world = &run.world;
        let mut env = Drawing::new();
        env.add_scene(&world.world, Kind::Robot)?;
        env.meshes.retain(|m| m.kind != Kind::Robot);
        self.log_drawing(&format!("{prefix}/world"), &env)?;
        let summary = format!(
            "{}\n\nstatus {:?}, seed {}, planning {:.3} s",
            run_id(&run.record),
            run.record.status,
            run.record.seed,
            run.record.planning_time
        );
        self.log_static(&format!("{prefix}/summary"), &TextDocument::new(summary))?;
        for (name, colour, path) in [("planned", PLANNED, &run.planned), ("processed", PROCESSED, &run.processed)] {
            let states = path_states(world, path, step)?;
            self.log_trajectory(&format!("{prefix}/{name}"), name, colour, world, &states)?;
        }
        Ok(())
    }

    /// Logs one animated trajectory on `timeline`.
    fn log_trajectory(
        &self,
        prefix: &str,
        timeline: &'static str,
        colour: [u8; 3],
        world: &MotionWorld,
        states: &[PathState],
    ) -> Result<()> {
        if states.is_empty() {
            return Ok(());
        }
        let robot = world.world.robot(world.robot)?;
        let links = robot.robot.links();
        // Link meshes in link frames, from the world-frame meshes of the first state.
        let first = world.at(&states[0].q)?;
        let poses = link_poses(&first, world)?;
        let mut robot_only = Drawing::new();
        robot_only.add_robots(&first, Kind::Robot, "r")?;
        let own = format!("r/{}/", robot.name);
        let mut shapes_of: Vec<Vec<String>> = vec![Vec::new(); links.len()];
        for m in &robot_only.meshes {
            let Some(name) = m.name.strip_prefix(&own) else { continue };
            let Some(l) = link_of(name, links) else { continue };
            let local = m.mesh.transformed(&poses[l].inverse());
            let item = MeshItem { name: m.name.clone(), kind: Kind::Robot, colour: Kind::Robot.colour(), mesh: local };
            let path = format!("{prefix}/robot/{}/{}", entity(&links[l].name), entity(name));
            self.log_static(&path, &mesh(&item))?;
            shapes_of[l].push(path);
        }
        let tips: Vec<[f32; 3]> = states.iter().map(|s| p32(&s.tip)).collect();
        self.log_static(&format!("{prefix}/tip_path"), &LineStrips3D::new([tips]).with_colors([rgba(colour)]))?;
        let invalid: Vec<[f32; 3]> = states.iter().filter(|s| !s.valid).map(|s| p32(&s.tip)).collect();
        if !invalid.is_empty() {
            let points = Points3D::new(invalid).with_colors([rgba(INVALID)]).with_radii([0.01f32]);
            self.log_static(&format!("{prefix}/invalid_states"), &points)?;
        }
        let mut red: Vec<usize> = Vec::new();
        for (i, s) in states.iter().enumerate() {
            self.rec.set_time_sequence(timeline, i as i64);
            let poses = link_poses(&world.at(&s.q)?, world)?;
            for (l, pose) in poses.iter().enumerate() {
                self.log(&format!("{prefix}/robot/{}", entity(&links[l].name)), &transform(pose))?;
            }
            // Colliding links red while the state is invalid, back to normal after.
            let now: Vec<usize> = if s.valid {
                Vec::new()
            } else {
                let pairs = colliding_pairs(world, &s.q)?;
                let text = if pairs.is_empty() {
                    "invalid (rejected by the run's checker; no exact contact)".to_string()
                } else {
                    pairs.iter().map(|(a, b)| format!("{a} ↔ {b}")).collect::<Vec<_>>().join("\n")
                };
                self.log(&format!("{prefix}/status"), &TextDocument::new(text))?;
                let prefix_robot = format!("{}/", robot.name);
                pairs
                    .iter()
                    .flat_map(|(a, b)| [a, b])
                    .filter_map(|n| n.strip_prefix(&prefix_robot).and_then(|n| link_of(n, links)))
                    .collect()
            };
            if s.valid && !red.is_empty() {
                self.log(&format!("{prefix}/status"), &TextDocument::new("valid"))?;
            }
            for &l in red.iter().filter(|l| !now.contains(l)) {
                for p in &shapes_of[l] {
                    self.log(p, &Mesh3D::update_fields().with_albedo_factor(albedo(Kind::Robot.colour())))?;
                }
            }
            for &l in now.iter().filter(|l| !red.contains(l)) {
                for p in &shapes_of[l] {
                    self.log(p, &Mesh3D::update_fields().with_albedo_factor(albedo(Kind::Colliding.colour())))?;
                }
            }
            red = now;
        }
        self.rec.reset_time();
        Ok(())
    }

    /// Logs a replayed grasp under `prefix`: object, hand, contacts, friction cones (static)
    /// and its tactile frames.
    ///
    /// # Errors
    /// [`ViewerError::Rerun`]; core errors building the grasp scene.
    pub fn log_grasp(&self, prefix: &str, g: &ReplayedGrasp) -> Result<()> {
        self.log_drawing(prefix, &grasp_drawing(g)?)?;
        let r = &g.record;
        let hull = match (r.volume, r.hull_facets) {
            (Some(v), Some(f)) => format!(", volume {v:.3e} ({f} facets)"),
            (Some(v), None) => format!(", volume {v:.3e}"),
            _ => String::new(),
        };
        let text = format!(
            "status {:?}\nforce closure: {}\nepsilon {:.5}{hull}\ncontacts {}, palm contact {}\nphysics held: {:?}",
            r.status, r.force_closure, r.epsilon, r.contacts, r.palm_contact, r.physics_held
        );
        self.log_static(&format!("{prefix}/summary"), &TextDocument::new(text))?;
        if let Some(frame) = &r.tactile {
            self.log_tactile(&format!("{prefix}/tactile"), frame, true)?;
        }
        for frame in &r.tactile_series {
            self.rec.set_duration_secs("tactile_time", frame.time);
            self.log_tactile(&format!("{prefix}/tactile_series"), frame, false)?;
        }
        self.rec.reset_time();
        Ok(())
    }

    /// Logs a tactile frame: one 8-bit grey image per pad (raw 0..4095 → 0..255).
    fn log_tactile(&self, prefix: &str, frame: &CompactFrame, stat: bool) -> Result<()> {
        for pad in &frame.pads {
            let pixels: Vec<u8> =
                pad.dense().iter().map(|&v| ((f64::from(v) / TACTILE_MAX).min(1.0) * 255.0).round() as u8).collect();
            let image = rerun::Image::from_l8(pixels, [pad.columns, pad.rows]);
            let path = format!("{prefix}/{}", entity(&pad.name));
            if stat {
                self.log_static(&path, &image)?;
            } else {
                self.log(&path, &image)?;
            }
        }
        Ok(())
    }

    /// Logs what `selection` asks for from a results file (`sets`: its problem sets). Runs or
    /// grasps that cannot be replayed in the overview are skipped and returned with the
    /// reason; a selected one that cannot is an error.
    ///
    /// # Errors
    /// [`ViewerError::UnknownRun`] / [`ViewerError::UnknownGrasp`] for an id not in the file,
    /// the replay's errors for a selected run or grasp, [`ViewerError::Rerun`].
    pub fn log_results(
        &self,
        results: &ResultsFile,
        selection: &Selection,
        sets: &[Arc<LoadedProblemSet>],
        step: f64,
    ) -> Result<Vec<(String, ViewerError)>> {
        let mut skipped = Vec::new();
        match selection {
            Selection::Run(id) => {
                let motion = results.motion.as_ref().ok_or_else(|| ViewerError::UnknownRun {
                    id: id.clone(),
                    available: 0,
                    example: "(the file has no motion results)".into(),
                })?;
                let run = replay(motion, id, sets)?;
                self.log_run(&run_prefix(&run), &run, step)?;
            }
            Selection::Grasp(id) => {
                let grasp = results.grasp.as_ref().ok_or_else(|| ViewerError::UnknownGrasp {
                    id: id.clone(),
                    available: 0,
                    example: "(the file has no grasp results)".into(),
                })?;
                let (cell, c) = find_grasp(grasp, id)?;
                self.log_grasp(&grasp_prefix(&grasp_id(cell, c)), &replay_grasp(cell, c)?)?;
            }
            Selection::Overview => {
                if let Some(motion) = &results.motion {
                    for scene in &motion.scenes {
                        match first_replayable(motion, scene, sets) {
                            Ok(run) => self.log_run(&run_prefix(&run), &run, step)?,
                            Err(e) => skipped.push((scene.clone(), e)),
                        }
                    }
                }
                if let Some(grasp) = &results.grasp {
                    for cell in grasp.cells.iter() {
                        let Some(best) = best_candidate(cell) else { continue };
                        let id = grasp_id(cell, best);
                        match replay_grasp(cell, best) {
                            Ok(g) => self.log_grasp(&grasp_prefix(&id), &g)?,
                            Err(e) => skipped.push((id, e)),
                        }
                    }
                }
            }
        }
        Ok(skipped)
    }
}

/// Entity path of a run: `scenes/<scene>/<planner>_run_<n>`.
pub fn run_prefix(run: &ReplayedRun) -> String {
    format!("scenes/{}/{}_run_{}", file_token(&run.record.scene), file_token(&run.record.planner), run.record.run)
}

/// Entity path of a grasp: `grasps/<planner>/<hand>/<object>/<index>`.
pub fn grasp_prefix(id: &str) -> String {
    format!("grasps/{}", id.split('/').map(file_token).collect::<Vec<_>>().join("/"))
}

/// An entity path of a `/`-separated name (each part a [`file_token`]).
fn entity(name: &str) -> String {
    name.split('/').map(file_token).collect::<Vec<_>>().join("/")
}

/// The group of a drawing item's name (`cone/3/edge_1` → `cone`, `invalid/4` → `invalid`).
fn group_of(name: &str) -> String {
    let g = name.split('/').next().unwrap_or(name);
    match g {
        "cone" => "friction_cones".into(),
        "contact" => "contacts".into(),
        other => file_token(other),
    }
}

/// The index of the link a `scene_meshes` robot mesh name (`link` or `link_<k>`) belongs to.
fn link_of(name: &str, links: &[opengrasp_core::model::Link]) -> Option<usize> {
    links.iter().position(|l| l.name == name).or_else(|| {
        let (base, k) = name.rsplit_once('_')?;
        k.parse::<usize>().ok()?;
        links.iter().position(|l| l.name == base)
    })
}

/// World poses of the planning robot's links in `scene`.
fn link_poses(scene: &Scene, world: &MotionWorld) -> Result<Vec<Isometry3<f64>>> {
    let r = scene.robot(world.robot)?;
    let fk = forward_kinematics(&r.robot, &r.q)?;
    Ok(fk.as_slice().iter().map(|p| r.base_pose * p).collect())
}
