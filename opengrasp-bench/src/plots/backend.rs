//! Output backends (SVG, PNG), the bundled font and the pieces every figure shares.

use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::results::{Error, Result};

/// DejaVu Sans (Bitstream Vera licence, `assets/fonts/LICENSE-DejaVu`), embedded so that PNG
/// text renders without any system font.
static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The font family every figure uses; the bundled font is registered under this name.
pub(super) const FONT: &str = "sans-serif";

/// Colours of the series (matplotlib's "tab10").
pub(super) const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// Colour of "no data" markers.
pub(super) const NO_DATA: RGBColor = RGBColor(120, 120, 120);

/// Colour of subtitles.
const SUBTITLE: RGBColor = RGBColor(90, 90, 90);

/// Height of the title strip (title and subtitle) above the chart, in pixels.
pub(super) const TITLE_HEIGHT: u32 = 58;

/// The image formats plots are written in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum PlotFormat {
    /// SVG only (text as `<text>` elements, rendered by the viewer).
    Svg,
    /// PNG only (text rasterised with the bundled DejaVu Sans).
    Png,
    /// Both, side by side with the same file stem.
    #[default]
    Both,
}

impl PlotFormat {
    /// The file extensions written, in order.
    #[must_use]
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            PlotFormat::Svg => &["svg"],
            PlotFormat::Png => &["png"],
            PlotFormat::Both => &["svg", "png"],
        }
    }
}

pub(super) fn plot_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Plot { path: path.to_path_buf(), reason: e.to_string() }
}

/// Registers the bundled font with plotters once; every text layout (SVG too) needs it.
fn register_font(path: &Path) -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, DEJAVU_SANS).is_ok());
    if ok {
        Ok(())
    } else {
        Err(plot_err(path, "the bundled font could not be loaded"))
    }
}

/// Result of drawing on a backend `DB`.
pub(super) type DrawResult<DB> = std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// A figure that draws itself on any plotters backend.
pub(super) trait Figure {
    /// Image size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the figure on `root` (already filled white).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB>;
}

/// Writes `figure` to `path`: PNG if the extension is `png` (any case), SVG otherwise.
pub(super) fn render(path: &Path, figure: &impl Figure) -> Result<()> {
    register_font(path)?;
    let size = figure.size();
    let png = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if png {
        let root = BitMapBackend::new(path, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
        figure.draw(&root).map_err(|e| plot_err(path, e))?;
        root.present().map_err(|e| plot_err(path, e))
    } else {
        let root = SVGBackend::new(path, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
        figure.draw(&root).map_err(|e| plot_err(path, e))?;
        root.present().map_err(|e| plot_err(path, e))
    }
}

/// Draws the title and a smaller grey subtitle, centred, and returns the area below them.
pub(super) fn titled<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    subtitle: &str,
) -> std::result::Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (top, rest) = root.split_vertically(TITLE_HEIGHT);
    let centre = i32::try_from(top.dim_in_pixel().0 / 2).unwrap_or(0);
    let style = |size: f64, color: &'static RGBColor| {
        TextStyle::from((FONT, size).into_font()).color(color).pos(Pos::new(HPos::Center, VPos::Top))
    };
    top.draw(&Text::new(title.to_string(), (centre, 8), style(20.0, &BLACK)))?;
    top.draw(&Text::new(subtitle.to_string(), (centre, 36), style(13.0, &SUBTITLE)))?;
    Ok(rest)
}

/// The label of category `x` (an integer position) among `names`, empty between categories.
pub(super) fn category_label(names: &[String], x: f64) -> String {
    let r = x.round();
    if (x - r).abs() < 1e-6 && r >= 0.0 && (r as usize) < names.len() {
        names[r as usize].clone()
    } else {
        String::new()
    }
}

/// A linear axis with ticks exactly at the given values (categories at 0, 1, ...; or
/// percentages up to 100 on a taller axis).
#[derive(Clone, Debug)]
pub(super) struct Axis {
    range: Range<f64>,
    ticks: Vec<f64>,
}

impl Axis {
    /// `n` categories at 0..n, half a slot of room on either side.
    pub(super) fn categories(n: usize) -> Self {
        Self { range: -0.5..n as f64 - 0.5, ticks: (0..n).map(|i| i as f64).collect() }
    }

    /// `range` with ticks at `ticks`.
    pub(super) fn with_ticks(range: Range<f64>, ticks: Vec<f64>) -> Self {
        Self { range, ticks }
    }
}

impl Ranged for Axis {
    type ValueType = f64;
    type FormatOption = NoDefaultFormatting;

    fn range(&self) -> Range<f64> {
        self.range.clone()
    }

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        RangedCoordf64::from(self.range.clone()).map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, _hint: Hint) -> Vec<f64> {
        self.ticks.clone()
    }
}

impl ValueFormatter<f64> for Axis {
    fn format(value: &f64) -> String {
        format!("{value}")
    }
}
