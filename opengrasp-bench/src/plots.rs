//! Plots of a [`ResultsFile`] as SVG (plotters' SVG backend: no system font libraries needed;
//! text is emitted as SVG `<text>` and rendered by the viewer).
//!
//! - per scene, box plots per planner of the planning time and of the post-processed path
//!   length (`motion_<scene>_planning_time.svg`, `motion_<scene>_length.svg`);
//! - per hand, bars of the force-closure percentage per object and planner
//!   (`grasp_<hand>_fc.svg`);
//! - per grasp cell with recorded tactile frames (`run --grasps`), a heat map of its best
//!   grasp's frame, one panel per pad (`tactile_<hand>_<object>_<planner>.svg`, [`tactile`]).
//!
//! PNG output is not offered: plotters' bitmap text needs a font rasteriser and font files,
//! which a CI machine with only the Rust toolchain lacks.

use std::path::{Path, PathBuf};

use opengrasp_motion::benchmark::RunRecord;
use plotters::prelude::*;

use crate::results::{Error, GraspSection, MotionSection, Result, ResultsFile};

pub mod tactile;
pub use tactile::{tactile_frame_svg, tactile_plots};

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn file_token(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '_' }).collect()
}

fn plot_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Plot { path: path.to_path_buf(), reason: e.to_string() }
}

/// Draws a box plot (one box per label) to an SVG file.
///
/// # Errors
/// [`Error::Plot`] if drawing or writing fails or no label has values.
pub fn box_plot(path: &Path, title: &str, y_label: &str, series: &[(String, Vec<f64>)]) -> Result<()> {
    let series: Vec<&(String, Vec<f64>)> = series.iter().filter(|(_, v)| !v.is_empty()).collect();
    if series.is_empty() {
        return Err(plot_err(path, "no values to plot"));
    }
    let labels: Vec<String> = series.iter().map(|(l, _)| l.clone()).collect();
    let (lo, hi) = series
        .iter()
        .flat_map(|(_, v)| v.iter().copied())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    let pad = if hi > lo { 0.08 * (hi - lo) } else { 0.1 * hi.abs().max(1e-3) };
    let (y0, y1) = ((lo - pad).max(if lo >= 0.0 { 0.0 } else { f64::NEG_INFINITY }) as f32, (hi + pad) as f32);
    let root = SVGBackend::new(path, (160 * labels.len() as u32 + 200, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(labels[..].into_segmented(), y0..y1)
        .map_err(|e| plot_err(path, e))?;
    chart.configure_mesh().disable_x_mesh().y_desc(y_label).x_desc("planner").draw().map_err(|e| plot_err(path, e))?;
    chart
        .draw_series(series.iter().enumerate().map(|(i, (l, v))| {
            Boxplot::new_vertical(SegmentValue::CenterOf(l), &Quartiles::new(v))
                .width(30)
                .style(PALETTE[i % PALETTE.len()])
        }))
        .map_err(|e| plot_err(path, e))?;
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// Draws grouped bars (`groups` on the x axis, one bar per series in each group; values in
/// percent) to an SVG file.
///
/// # Errors
/// [`Error::Plot`] if drawing or writing fails or there is nothing to draw.
pub fn grouped_bars(
    path: &Path,
    title: &str,
    y_label: &str,
    groups: &[String],
    series: &[(String, Vec<Option<f64>>)],
) -> Result<()> {
    if groups.is_empty() || series.is_empty() {
        return Err(plot_err(path, "no values to plot"));
    }
    let n = groups.len();
    let root = SVGBackend::new(path, (110 * n as u32 + 200, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let names = groups.to_vec();
    let formatter = move |x: &f64| {
        let r = x.round();
        if (x - r).abs() < 1e-6 && r >= 0.0 && (r as usize) < names.len() {
            names[r as usize].clone()
        } else {
            String::new()
        }
    };
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(-0.5f64..(n as f64 - 0.5), 0f64..105.0)
        .map_err(|e| plot_err(path, e))?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(n)
        .x_label_formatter(&formatter)
        .y_desc(y_label)
        .draw()
        .map_err(|e| plot_err(path, e))?;
    let width = 0.8 / series.len() as f64;
    for (k, (name, values)) in series.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        chart
            .draw_series(values.iter().enumerate().filter_map(|(i, v)| {
                v.map(|v| {
                    let x0 = i as f64 - 0.4 + k as f64 * width;
                    Rectangle::new([(x0, 0.0), (x0 + width * 0.9, v)], color.filled())
                })
            }))
            .map_err(|e| plot_err(path, e))?
            .label(name.clone())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], color.filled()));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| plot_err(path, e))?;
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// Motion plots of a section into `dir`; returns the files written.
///
/// # Errors
/// [`Error::Plot`].
pub fn motion_plots(m: &MotionSection, dir: &Path) -> Result<Vec<PathBuf>> {
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
        let path = dir.join(format!("motion_{token}_planning_time.svg"));
        box_plot(&path, &format!("planning time: {scene}"), "planning time [ms]", &times)?;
        written.push(path);
        if lengths.iter().any(|(_, v)| !v.is_empty()) {
            let path = dir.join(format!("motion_{token}_length.svg"));
            box_plot(&path, &format!("path length after post-processing: {scene}"), "C-space length", &lengths)?;
            written.push(path);
        }
    }
    Ok(written)
}

/// Grasp plots of a section into `dir`; returns the files written.
///
/// # Errors
/// [`Error::Plot`].
pub fn grasp_plots(g: &GraspSection, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for hand in &g.hands {
        let cells: Vec<_> = g.cells.iter().map(|r| &r.cell).filter(|c| &c.hand == hand).collect();
        if cells.is_empty() {
            continue;
        }
        let objects: Vec<String> =
            g.objects.iter().filter(|o| cells.iter().any(|c| &c.object == *o)).cloned().collect();
        let series: Vec<(String, Vec<Option<f64>>)> = g
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
                            .map(|c| c.fc_percent_palm)
                    })
                    .collect();
                (p.name.clone(), v)
            })
            .collect();
        let path = dir.join(format!("grasp_{}_fc.svg", file_token(hand)));
        grouped_bars(&path, &format!("force closure per object: {hand} hand"), "force closure [%]", &objects, &series)?;
        written.push(path);
    }
    Ok(written)
}

/// All plots of a results file into `dir` (created if missing); returns the files written.
///
/// # Errors
/// [`Error::Io`] if the directory cannot be created, [`Error::Plot`].
pub fn plot_all(results: &ResultsFile, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_path_buf(), source })?;
    let mut written = Vec::new();
    if let Some(g) = &results.grasp {
        written.extend(grasp_plots(g, dir)?);
        written.extend(tactile_plots(g, dir)?);
    }
    if let Some(m) = &results.motion {
        written.extend(motion_plots(m, dir)?);
    }
    Ok(written)
}
