//! PNG snapshots of a results file for reports: per motion scene, its first solved run that
//! replays (world, start and end, end-effector paths, invalid states); per grasp cell with
//! recorded candidates (`run grasp --grasps`), its best grasp (largest epsilon) with contacts
//! and friction cones.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use opengrasp_bench::results::ResultsFile;
use opengrasp_motion::problem_set::LoadedProblemSet;

use crate::drawing::Drawing;
use crate::error::{Result, ViewerError};
use crate::grasp::{best_candidate, grasp_drawing, grasp_id, replay_grasp};
use crate::motion::run_drawing;
use crate::replay::first_replayable;

/// Options of [`write_snapshots`].
#[derive(Clone, Debug, PartialEq)]
pub struct SnapshotOptions {
    /// Image width (pixels; default 800).
    pub width: u32,
    /// Image height (pixels; default 600).
    pub height: u32,
    /// Step at which paths are densified for drawing (rad; default 0.02).
    pub step: f64,
    /// Grasp cells drawn at most (default 16).
    pub max_grasps: usize,
}

impl Default for SnapshotOptions {
    fn default() -> Self {
        Self { width: 800, height: 600, step: 0.02, max_grasps: 16 }
    }
}

/// A written snapshot.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// What it shows.
    pub caption: String,
    /// The PNG file.
    pub path: PathBuf,
}

/// What [`write_snapshots`] did.
#[derive(Debug, Default)]
pub struct Snapshots {
    /// The images written.
    pub written: Vec<Snapshot>,
    /// Scenes or cells that could not be drawn, and why.
    pub skipped: Vec<(String, ViewerError)>,
}

/// A file-name-safe form of `s`.
pub fn file_token(s: &str) -> String {
    let t: String = s.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '_' }).collect();
    t.split('_').filter(|p| !p.is_empty()).collect::<Vec<_>>().join("_")
}

fn save(drawing: &Drawing, options: &SnapshotOptions, path: PathBuf, caption: String) -> Result<Snapshot> {
    drawing.render_framed(options.width, options.height)?.save_png(&path)?;
    Ok(Snapshot { caption, path })
}

/// Writes the snapshots of `results` into `dir` (`scene_<scene>.png`,
/// `grasp_<hand>_<object>_<planner>.png`). Scenes and cells that cannot be drawn (a planner
/// or scene the viewer cannot replay, a replay that differs) are listed in
/// [`Snapshots::skipped`]; `sets` are the problem sets the results were made with.
///
/// # Errors
/// [`ViewerError::Io`] if `dir` cannot be created or a file written.
pub fn write_snapshots(
    results: &ResultsFile,
    dir: &Path,
    sets: &[Arc<LoadedProblemSet>],
    options: &SnapshotOptions,
) -> Result<Snapshots> {
    std::fs::create_dir_all(dir).map_err(|source| ViewerError::Io { path: dir.to_path_buf(), source })?;
    let mut out = Snapshots::default();
    if let Some(motion) = &results.motion {
        for scene in &motion.scenes {
            let drawn =
                first_replayable(motion, scene, sets).and_then(|run| Ok((run_drawing(&run, options.step)?, run)));
            match drawn {
                Ok((d, run)) => {
                    let path = dir.join(format!("scene_{}.png", file_token(scene)));
                    let caption = format!(
                        "{scene}: {} run {} (orange: planned, green: post-processed end-effector path; \
                         red: invalid states and colliding parts)",
                        run.record.planner, run.record.run
                    );
                    out.written.push(save(&d, options, path, caption)?);
                }
                Err(e @ (ViewerError::Io { .. } | ViewerError::Png { .. })) => return Err(e),
                Err(e) => out.skipped.push((scene.clone(), e)),
            }
        }
    }
    if let Some(grasp) = &results.grasp {
        for cell in grasp.cells.iter().filter(|c| !c.cell.candidates.is_empty()).take(options.max_grasps) {
            let Some(best) = best_candidate(cell) else { continue };
            let id = grasp_id(cell, best);
            match replay_grasp(cell, best).and_then(|g| grasp_drawing(&g)) {
                Ok(d) => {
                    let c = &cell.cell;
                    let name = format!(
                        "grasp_{}_{}_{}.png",
                        file_token(&c.hand),
                        file_token(&c.object),
                        file_token(&c.planner)
                    );
                    let fc = if best.force_closure {
                        "force closure (green hand)"
                    } else {
                        "no force closure (orange hand)"
                    };
                    let caption = format!(
                        "{} with {} on {}: best grasp #{} (epsilon {:.4}, {fc}; contacts and friction cones in magenta)",
                        c.planner, c.hand, c.object, best.index, best.epsilon
                    );
                    out.written.push(save(&d, options, dir.join(name), caption)?);
                }
                Err(e @ (ViewerError::Io { .. } | ViewerError::Png { .. })) => return Err(e),
                Err(e) => out.skipped.push((id, e)),
            }
        }
    }
    Ok(out)
}
