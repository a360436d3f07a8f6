//! Grouped bar charts of percentages, one bar per series in each group.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::backend::{category_label, plot_err, render, titled, Axis, DrawResult, Figure, FONT, NO_DATA, PALETTE};
use crate::results::Result;

/// One bar of [`grouped_bars_counted`]: a percentage and the number of samples behind it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bar {
    /// Height in percent.
    pub value: f64,
    /// Number of samples the percentage is of (shown as `n=…` above the bar), if known.
    pub n: Option<usize>,
}

/// Subtitle of the bar charts: how to read bars, counts and empty cells.
pub const BAR_CHART_SUBTITLE: &str = "n above a bar: samples the percentage is of; no data: empty cell (not 0 %)";

/// Draws grouped bars (`groups` on the x axis, one bar per series in each group; values in
/// percent) to `path`: PNG if its extension is `png`, SVG otherwise. A `None` value is an empty
/// cell, marked "no data" rather than drawn as a 0 % bar.
///
/// # Errors
/// [`Error::Plot`](crate::results::Error::Plot) if drawing or writing fails or there is nothing
/// to draw.
pub fn grouped_bars(
    path: &Path,
    title: &str,
    y_label: &str,
    groups: &[String],
    series: &[(String, Vec<Option<f64>>)],
) -> Result<()> {
    let series: Vec<(String, Vec<Option<Bar>>)> = series
        .iter()
        .map(|(name, v)| (name.clone(), v.iter().map(|v| v.map(|value| Bar { value, n: None })).collect()))
        .collect();
    grouped_bars_counted(path, title, "", y_label, groups, &series)
}

/// [`grouped_bars`] with sample counts per bar (`n=…` above it) and an x-axis description
/// (`x_label`, may be empty).
///
/// # Errors
/// As [`grouped_bars`].
pub fn grouped_bars_counted(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    groups: &[String],
    series: &[(String, Vec<Option<Bar>>)],
) -> Result<()> {
    if groups.is_empty() || series.is_empty() {
        return Err(plot_err(path, "no values to plot"));
    }
    render(path, &BarFigure { title, x_label, y_label, groups, series })
}

struct BarFigure<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    groups: &'a [String],
    series: &'a [(String, Vec<Option<Bar>>)],
}

/// Top of the y axis: room above 100 % for the counts and the legend.
const Y_MAX: f64 = 132.0;

impl Figure for BarFigure<'_> {
    fn size(&self) -> (u32, u32) {
        let group = (48 * self.series.len() as u32 + 30).max(110);
        ((group * self.groups.len() as u32 + 220).max(720), 540)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let area = titled(root, self.title, BAR_CHART_SUBTITLE)?;
        let n = self.groups.len();
        let names = self.groups.to_vec();
        let formatter = move |x: &f64| category_label(&names, *x);
        let mut chart =
            ChartBuilder::on(&area).margin(15).x_label_area_size(45).y_label_area_size(70).build_cartesian_2d(
                Axis::categories(n),
                Axis::with_ticks(0.0..Y_MAX, vec![0.0, 20.0, 40.0, 60.0, 80.0, 100.0]),
            )?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_label_formatter(&formatter)
            .x_label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .x_desc(self.x_label)
            .y_desc(self.y_label)
            .draw()?;
        let width = 0.8 / self.series.len() as f64;
        let small = TextStyle::from((FONT, 11).into_font()).color(&BLACK);
        for (k, (name, values)) in self.series.iter().enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            let x0 = |i: usize| i as f64 - 0.4 + k as f64 * width;
            let centre = |i: usize| x0(i) + 0.45 * width;
            let bars = values.iter().enumerate().filter_map(|(i, b)| b.map(|b| (i, b)));
            chart
                .draw_series(bars.clone().map(|(i, b)| {
                    Rectangle::new([(x0(i), 0.0), (x0(i) + width * 0.9, b.value.clamp(0.0, 100.0))], color.filled())
                }))?
                .label(name.clone())
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], color.filled()));
            let above = Pos::new(HPos::Center, VPos::Bottom);
            chart.draw_series(bars.filter_map(|(i, b)| {
                b.n.map(|n| Text::new(format!("n={n}"), (centre(i), b.value.clamp(0.0, 100.0) + 1.5), small.pos(above)))
            }))?;
            // Empty cells: a cross on the axis and "no data" upwards, never a 0 % bar.
            let empty: Vec<usize> = values.iter().enumerate().filter(|(_, b)| b.is_none()).map(|(i, _)| i).collect();
            let vertical = TextStyle::from((FONT, 12).into_font())
                .color(&NO_DATA)
                .transform(FontTransform::Rotate270)
                .pos(Pos::new(HPos::Left, VPos::Center));
            chart.draw_series(empty.iter().map(|&i| Cross::new((centre(i), 0.0), 5, NO_DATA.stroke_width(2))))?;
            chart.draw_series(empty.iter().map(|&i| Text::new("no data", (centre(i), 4.0), vertical.clone())))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, 13))
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    }
}
