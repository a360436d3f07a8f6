//! Tactile heat maps: for every grasp cell with recorded tactile frames, the frame of its best
//! grasp (largest epsilon among the candidates with a lit pad, then the most raw signal) drawn
//! as one panel per pad (`tactile_<hand>_<object>_<planner>.svg`).

use std::path::{Path, PathBuf};

use opengrasp_grasp::benchmark::{CandidateRecord, CellResult};
use opengrasp_grasp::tactile::{CompactFrame, CompactPad};
use plotters::prelude::*;

use super::backend::plot_err;
use super::file_token;
use crate::results::{GraspSection, Result};

/// Largest raw value of the DSA modules (12 bit): the top of the colour scale.
const RAW_MAX: f64 = 4095.0;

/// White → yellow → red → dark red for `x` in `[0, 1]`.
fn heat(x: f64) -> RGBColor {
    let x = x.clamp(0.0, 1.0);
    let stops = [(255.0, 255.0, 255.0), (255.0, 220.0, 60.0), (220.0, 40.0, 30.0), (90.0, 0.0, 20.0)];
    let t = x * (stops.len() - 1) as f64;
    let i = (t.floor() as usize).min(stops.len() - 2);
    let f = t - i as f64;
    let (a, b) = (stops[i], stops[i + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn signal(f: &CompactFrame) -> u64 {
    f.pads.iter().flat_map(|p| &p.cells).map(|c| u64::from(c[1])).sum()
}

/// The candidate whose frame is drawn: lit pads first, then largest epsilon, then most signal.
fn best(cell: &CellResult) -> Option<(&CandidateRecord, &CompactFrame)> {
    cell.candidates
        .iter()
        .filter_map(|r| r.tactile.as_ref().map(|t| (r, t)))
        .filter(|(_, t)| signal(t) > 0)
        .max_by(|a, b| a.0.epsilon.total_cmp(&b.0.epsilon).then(signal(a.1).cmp(&signal(b.1))))
}

/// Draws one frame, a panel per pad (rows upwards from the proximal end), to an SVG file.
///
/// # Errors
/// [`crate::results::Error::Plot`] if drawing or writing fails or the frame has no pads.
pub fn tactile_frame_svg(path: &Path, title: &str, frame: &CompactFrame) -> Result<()> {
    let n = frame.pads.len();
    if n == 0 {
        return Err(plot_err(path, "frame has no pads"));
    }
    let per_row = n.min(6);
    let grid_rows = n.div_ceil(per_row);
    let (pw, ph) = (150u32, 330u32);
    let root = SVGBackend::new(path, (pw * per_row as u32, ph * grid_rows as u32 + 40)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let root = root.titled(title, ("sans-serif", 18)).map_err(|e| plot_err(path, e))?;
    let panels = root.split_evenly((grid_rows, per_row));
    for (pad, area) in frame.pads.iter().zip(&panels) {
        draw_pad(area, pad).map_err(|e| plot_err(path, e))?;
    }
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

fn draw_pad<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    pad: &CompactPad,
) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (rows, cols) = (pad.rows.max(1) as i32, pad.columns.max(1) as i32);
    let peak = pad.cells.iter().map(|c| c[1]).max().unwrap_or(0);
    let mut chart = ChartBuilder::on(area)
        .caption(format!("{} (max {peak})", pad.name), ("sans-serif", 13))
        .margin(8)
        .build_cartesian_2d(0..cols, 0..rows)?;
    let dense = pad.dense();
    chart.draw_series((0..rows).flat_map(|r| (0..cols).map(move |c| (r, c))).map(|(r, c)| {
        let v = dense.get((r * cols + c) as usize).copied().unwrap_or(0);
        Rectangle::new([(c, r), (c + 1, r + 1)], heat(f64::from(v) / RAW_MAX).filled())
    }))?;
    chart.draw_series(
        (0..rows)
            .flat_map(|r| (0..cols).map(move |c| (r, c)))
            .map(|(r, c)| Rectangle::new([(c, r), (c + 1, r + 1)], RGBColor(200, 200, 200).stroke_width(1))),
    )?;
    Ok(())
}

/// Heat maps of the best recorded tactile frame of every grasp cell into `dir`; returns the
/// files written (none if no candidate records carry tactile frames).
///
/// # Errors
/// [`crate::results::Error::Plot`].
pub fn tactile_plots(g: &GraspSection, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for record in &g.cells {
        let c = &record.cell;
        let Some((candidate, frame)) = best(c) else { continue };
        let path = dir.join(format!(
            "tactile_{}_{}_{}.svg",
            file_token(&c.hand),
            file_token(&c.object),
            file_token(&c.planner)
        ));
        let title = format!(
            "{} hand, {}, {}: candidate {} (epsilon {:.3}), raw 0..4095",
            c.hand, c.object, c.planner, candidate.index, candidate.epsilon
        );
        tactile_frame_svg(&path, &title, frame)?;
        written.push(path);
    }
    Ok(written)
}
