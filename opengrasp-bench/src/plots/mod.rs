//! Plots of a [`ResultsFile`] as SVG and PNG (plotters; text uses DejaVu Sans, bundled in the
//! crate, so no system font or font library is needed).
//!
//! - per scene, Tukey box plots per planner of the planning time and of the post-processed path
//!   length (`motion_<scene>_planning_time.svg`, `motion_<scene>_length.svg`);
//! - per hand, bars of the force-closure percentage per object and planner
//!   (`grasp_<hand>_fc.svg`);
//! - per grasp cell with recorded tactile frames (`run --grasps`), a heat map of its best
//!   grasp's frame, one panel per pad (`tactile_<hand>_<object>_<planner>.svg`, [`tactile`]).
//!
//! Box plots follow Tukey: the box spans the quartiles (linear interpolation, type 7) with a
//! line at the median, the whiskers end at the most extreme data points within 1.5 IQR of the
//! box (never beyond the sample's minimum or maximum), and every point beyond is drawn as an
//! outlier dot ([`BoxStats`]); the convention is printed under each title. Labels carry the
//! sample size (`RRT-Connect (n=20)`, `n=…` above each bar), axes their units, and an empty cell
//! is marked "no data" instead of being drawn as 0.
//!
//! [`PlotFormat`] picks SVG, PNG or both; [`box_plot`] and [`grouped_bars`] choose by the
//! file's extension.

use std::path::{Path, PathBuf};

use opengrasp_motion::benchmark::RunRecord;

use crate::results::{Error, GraspSection, MotionSection, Result, ResultsFile};

mod backend;
mod bars;
mod boxes;
pub mod tactile;
#[cfg(test)]
mod tests;
mod tukey;

pub use backend::PlotFormat;
pub use bars::{grouped_bars, grouped_bars_counted, Bar, BAR_CHART_SUBTITLE};
pub use boxes::{box_plot, box_plot_with_x, BOX_PLOT_SUBTITLE};
pub use tactile::{tactile_frame_svg, tactile_plots};
pub use tukey::{BoxStats, WHISKER_IQR};

fn file_token(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '_' }).collect()
}

/// Writes one figure in every extension of `format` (`stem` + `.svg` / `.png`) and records the
/// files.
fn write_each(
    dir: &Path,
    stem: &str,
    format: PlotFormat,
    written: &mut Vec<PathBuf>,
    draw: impl Fn(&Path) -> Result<()>,
) -> Result<()> {
    for ext in format.extensions() {
        let path = dir.join(format!("{stem}.{ext}"));
        draw(&path)?;
        written.push(path);
    }
    Ok(())
}

/// Motion plots of a section into `dir` as SVG; returns the files written.
///
/// # Errors
/// [`Error::Plot`].
pub fn motion_plots(m: &MotionSection, dir: &Path) -> Result<Vec<PathBuf>> {
    motion_plots_as(m, dir, PlotFormat::Svg)
}

/// Motion plots of a section into `dir` in `format`; returns the files written. Per scene:
/// planning time \[ms\] of every run, and C-space path length after post-processing of the
/// runs that have a processed path, one Tukey box per planner.
///
/// # Errors
/// [`Error::Plot`].
pub fn motion_plots_as(m: &MotionSection, dir: &Path, format: PlotFormat) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let mut scenes: Vec<&str> = m.scenes.iter().map(String::as_str).collect();
    for r in &m.runs {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    for scene in scenes {
        let planners: Vec<&str> = m
            .planners
            .iter()
            .map(|p| p.name.as_str())
            .filter(|p| m.runs.iter().any(|r| r.scene == scene && r.planner == *p))
            .collect();
        if planners.is_empty() {
            continue;
        }
        let runs =
            |p: &str| -> Vec<&RunRecord> { m.runs.iter().filter(|r| r.scene == scene && r.planner == p).collect() };
        let times: Vec<(String, Vec<f64>)> =
            planners.iter().map(|p| (p.to_string(), runs(p).iter().map(|r| r.planning_time * 1e3).collect())).collect();
        let lengths: Vec<(String, Vec<f64>)> = planners
            .iter()
            .map(|p| {
                (p.to_string(), runs(p).iter().filter_map(|r| r.processed.as_ref().map(|x| x.metrics.length)).collect())
            })
            .collect();
        let token = file_token(scene);
        write_each(dir, &format!("motion_{token}_planning_time"), format, &mut written, |path| {
            box_plot(path, &format!("planning time: {scene}"), "planning time [ms]", &times)
        })?;
        if lengths.iter().any(|(_, v)| !v.is_empty()) {
            write_each(dir, &format!("motion_{token}_length"), format, &mut written, |path| {
                box_plot(
                    path,
                    &format!("path length after post-processing: {scene}"),
                    "path length in C-space [rad, m]",
                    &lengths,
                )
            })?;
        }
    }
    Ok(written)
}

/// Grasp plots of a section into `dir` as SVG; returns the files written.
///
/// # Errors
/// [`Error::Plot`].
pub fn grasp_plots(g: &GraspSection, dir: &Path) -> Result<Vec<PathBuf>> {
    grasp_plots_as(g, dir, PlotFormat::Svg)
}

/// Grasp plots of a section into `dir` in `format`; returns the files written. Per hand: the
/// force-closure percentage among palm-contact grasps (the paper's FC) per object and planner,
/// with the number of palm-contact grasps as n; a cell without palm contact is "no data".
///
/// # Errors
/// [`Error::Plot`].
pub fn grasp_plots_as(g: &GraspSection, dir: &Path, format: PlotFormat) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for hand in &g.hands {
        let cells: Vec<_> = g.cells.iter().map(|r| &r.cell).filter(|c| &c.hand == hand).collect();
        if cells.is_empty() {
            continue;
        }
        let objects: Vec<String> =
            g.objects.iter().filter(|o| cells.iter().any(|c| &c.object == *o)).cloned().collect();
        let series: Vec<(String, Vec<Option<Bar>>)> = g
            .planners
            .iter()
            .map(|p| {
                let v = objects
                    .iter()
                    .map(|o| {
                        cells
                            .iter()
                            .find(|c| c.planner == p.name && &c.object == o)
                            .filter(|c| c.palm_contact > 0)
                            .map(|c| Bar { value: c.fc_percent_palm, n: Some(c.palm_contact) })
                    })
                    .collect();
                (p.name.clone(), v)
            })
            .collect();
        write_each(dir, &format!("grasp_{}_fc", file_token(hand)), format, &mut written, |path| {
            grouped_bars_counted(
                path,
                &format!("force closure per object: {hand} hand"),
                "object",
                "force closure [% of palm-contact grasps]",
                &objects,
                &series,
            )
        })?;
    }
    Ok(written)
}

/// All plots of a results file into `dir` (created if missing) as SVG; returns the files
/// written.
///
/// # Errors
/// [`Error::Io`] if the directory cannot be created, [`Error::Plot`].
pub fn plot_all(results: &ResultsFile, dir: &Path) -> Result<Vec<PathBuf>> {
    plot_all_as(results, dir, PlotFormat::Svg)
}

/// All plots of a results file into `dir` (created if missing) in `format`; returns the files
/// written (grasp plots first, each figure's SVG before its PNG).
///
/// # Errors
/// [`Error::Io`] if the directory cannot be created, [`Error::Plot`].
pub fn plot_all_as(results: &ResultsFile, dir: &Path, format: PlotFormat) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_path_buf(), source })?;
    let mut written = Vec::new();
    if let Some(g) = &results.grasp {
        written.extend(grasp_plots_as(g, dir, format)?);
        // Tactile heat maps are SVG (one panel per pad).
        written.extend(tactile_plots(g, dir)?);
    }
    if let Some(m) = &results.motion {
        written.extend(motion_plots_as(m, dir, format)?);
    }
    Ok(written)
}
