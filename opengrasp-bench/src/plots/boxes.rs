//! Tukey box plots, one box per label.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::backend::{category_label, plot_err, render, titled, Axis, DrawResult, Figure, FONT, NO_DATA, PALETTE};
use super::tukey::BoxStats;
use crate::results::Result;

/// The convention, printed under every box plot's title.
pub const BOX_PLOT_SUBTITLE: &str =
    "box: quartiles and median; whiskers: farthest point within 1.5 IQR (Tukey); dots: outliers";

/// Draws a Tukey box plot (one box per label, x axis "planner") to `path`: PNG if its extension
/// is `png`, SVG otherwise.
///
/// Each box spans the quartiles with a line at the median; the whiskers end at the most extreme
/// values within 1.5 IQR of the box ([`BoxStats`](super::BoxStats)) and every value beyond is
/// drawn as a dot. Labels read `name (n=count)`; a label without values gets a "no data" mark.
///
/// # Errors
/// [`Error::Plot`](crate::results::Error::Plot) if drawing or writing fails or no label has
/// values.
pub fn box_plot(path: &Path, title: &str, y_label: &str, series: &[(String, Vec<f64>)]) -> Result<()> {
    box_plot_with_x(path, title, "planner", y_label, series)
}

/// [`box_plot`] with an x-axis description of your own.
///
/// # Errors
/// As [`box_plot`].
pub fn box_plot_with_x(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(String, Vec<f64>)],
) -> Result<()> {
    let boxes: Vec<(String, Option<BoxStats>)> = series
        .iter()
        .map(|(name, v)| {
            let stats = BoxStats::new(v);
            (format!("{name} (n={})", stats.as_ref().map_or(0, |s| s.n)), stats)
        })
        .collect();
    let (lo, hi) = boxes
        .iter()
        .filter_map(|(_, s)| s.as_ref().map(BoxStats::extent))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (l, h)| (a.min(l), b.max(h)));
    if !lo.is_finite() {
        return Err(plot_err(path, "no values to plot"));
    }
    let pad = if hi > lo { 0.08 * (hi - lo) } else { 0.1 * hi.abs().max(1e-3) };
    let y0 = if lo >= 0.0 { (lo - pad).max(0.0) } else { lo - pad };
    let figure = BoxFigure { title, x_label, y_label, boxes, y_range: (y0, hi + pad) };
    render(path, &figure)
}

struct BoxFigure<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    /// Label (with n) and statistics (`None`: no data) per box.
    boxes: Vec<(String, Option<BoxStats>)>,
    y_range: (f64, f64),
}

impl Figure for BoxFigure<'_> {
    fn size(&self) -> (u32, u32) {
        ((170 * self.boxes.len() as u32 + 200).max(720), 540)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let area = titled(root, self.title, BOX_PLOT_SUBTITLE)?;
        let n = self.boxes.len();
        let names: Vec<String> = self.boxes.iter().map(|(l, _)| l.clone()).collect();
        let formatter = move |x: &f64| category_label(&names, *x);
        let mut chart = ChartBuilder::on(&area)
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(Axis::categories(n), self.y_range.0..self.y_range.1)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_label_formatter(&formatter)
            .x_label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .x_desc(self.x_label)
            .y_desc(self.y_label)
            .draw()?;
        let (half, cap) = (0.22, 0.1);
        for (i, (_, stats)) in self.boxes.iter().enumerate() {
            let x = i as f64;
            let color = PALETTE[i % PALETTE.len()];
            let Some(s) = stats else {
                let mid = 0.5 * (self.y_range.0 + self.y_range.1);
                let style =
                    TextStyle::from((FONT, 16).into_font()).color(&NO_DATA).pos(Pos::new(HPos::Center, VPos::Center));
                chart.draw_series(std::iter::once(Text::new("no data", (x, mid), style)))?;
                continue;
            };
            let line =
                |a: (f64, f64), b: (f64, f64), width: u32| PathElement::new(vec![a, b], color.stroke_width(width));
            chart.draw_series([
                Rectangle::new([(x - half, s.q1), (x + half, s.q3)], color.mix(0.2).filled()),
                Rectangle::new([(x - half, s.q1), (x + half, s.q3)], color.stroke_width(2)),
            ])?;
            chart.draw_series([
                line((x - half, s.median), (x + half, s.median), 3),
                line((x, s.q3), (x, s.whisker_high), 1),
                line((x, s.q1), (x, s.whisker_low), 1),
                line((x - cap, s.whisker_high), (x + cap, s.whisker_high), 2),
                line((x - cap, s.whisker_low), (x + cap, s.whisker_low), 2),
            ])?;
            chart.draw_series(s.outliers.iter().map(|&o| Circle::new((x, o), 4, color.stroke_width(2))))?;
        }
        Ok(())
    }
}
