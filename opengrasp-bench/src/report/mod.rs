//! Reports: the OpenGRASP paper's tables from a [`ResultsFile`], as aligned text, Markdown
//! or CSV.
//!
//! - [`grasp_tables`]: Tables I and II, one table per hand: per object, the candidates tested
//!   (grasps with palm contact) and the percentage of force-closure grasps among them for
//!   every planner (medial axis and surface normals for the reference suite), the mean
//!   epsilon of those force-closure grasps, the physics hold check (held / tested) when it
//!   ran, the paper's numbers beside them when known, and a total row.
//! - [`grasp_differences`]: every cell with a paper figure beside it, and the reason measured
//!   in the records where they differ (evaluation cap, candidate count, palm-contact rule,
//!   contact model), plus whether the planner ranking agrees with the paper's.
//! - [`motion_tables`]: Table III, one row per planner per scene: runs, success, average
//!   setup / planning / post-processing time, valid % of planned and post-processed paths,
//!   C-space and end-effector lengths, clearance; plus a table of planning-time and
//!   path-length percentiles (min, p25, median, p75, p95, max); and one row per Clean the
//!   Table episode when they ran.
//!
//! All numbers come from the records (motion summaries are recomputed from the runs).

use std::fmt::Write as _;

mod grasp;
mod grasp_diff;
mod motion;

pub use grasp::grasp_tables;
pub use grasp_diff::{grasp_differences, AGREEMENT_PP};
pub use motion::motion_tables;

use crate::results::{GraspSection, MotionSection, ResultsFile};

/// Output format of a report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Format {
    /// Aligned plain-text columns (terminal).
    #[default]
    Table,
    /// GitHub-flavoured Markdown tables.
    Markdown,
    /// Tidy comma-separated values: one long-format file with the header
    /// `table,row,column,value,text`, one line per cell; `value` holds only numbers (empty for
    /// "no data"), `text` the cell's text when it is not a plain number (a `held/simulated`
    /// cell gives two lines, `… held` and `… simulated`; `yes`/`no` give 1/0).
    Csv,
}

/// A titled table of strings.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Title (e.g. `"Table II: grasp planners, hand barrett"`).
    pub title: String,
    /// Column headers.
    pub headers: Vec<String>,
    /// Rows (each as long as `headers`).
    pub rows: Vec<Vec<String>>,
    /// What the columns and abbreviations mean, printed under the table (not in CSV data).
    pub legend: Vec<String>,
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

impl Table {
    /// The cell in the row whose first cell is `row` and the column headed `column`.
    pub fn cell(&self, row: &str, column: &str) -> Option<&str> {
        let c = self.headers.iter().position(|h| h == column)?;
        self.rows.iter().find(|r| r.first().is_some_and(|f| f == row)).and_then(|r| r.get(c)).map(String::as_str)
    }

    /// Renders the table.
    pub fn render(&self, format: Format) -> String {
        let mut out = String::new();
        match format {
            Format::Table => {
                let widths: Vec<usize> = (0..self.headers.len())
                    .map(|c| {
                        self.rows
                            .iter()
                            .filter_map(|r| r.get(c))
                            .chain(std::iter::once(&self.headers[c]))
                            .map(|s| s.chars().count())
                            .max()
                            .unwrap_or(0)
                    })
                    .collect();
                let _ = writeln!(out, "{}", self.title);
                let fmt_row =
                    |r: &[String]| {
                        r.iter()
                            .enumerate()
                            .map(|(c, s)| {
                                if c == 0 {
                                    format!("{s:<w$}", w = widths[c])
                                } else {
                                    format!("{s:>w$}", w = widths[c])
                                }
                            })
                            .collect::<Vec<_>>()
                            .join("  ")
                    };
                let _ = writeln!(out, "{}", fmt_row(&self.headers));
                let _ = writeln!(out, "{}", widths.iter().map(|w| "-".repeat(*w)).collect::<Vec<_>>().join("  "));
                for r in &self.rows {
                    let _ = writeln!(out, "{}", fmt_row(r));
                }
                for l in &self.legend {
                    for line in wrap(l, LEGEND_WIDTH) {
                        let _ = writeln!(out, "  {line}");
                    }
                }
            }
            Format::Markdown => {
                let _ = writeln!(out, "### {}\n", self.title);
                let esc = |s: &String| s.replace('|', "\\|");
                let _ = writeln!(out, "| {} |", self.headers.iter().map(esc).collect::<Vec<_>>().join(" | "));
                let sep: Vec<&str> = (0..self.headers.len()).map(|c| if c == 0 { "---" } else { "---:" }).collect();
                let _ = writeln!(out, "| {} |", sep.join(" | "));
                for r in &self.rows {
                    let _ = writeln!(out, "| {} |", r.iter().map(esc).collect::<Vec<_>>().join(" | "));
                }
                if !self.legend.is_empty() {
                    let _ = writeln!(out, "\n*{}*", self.legend.join(" "));
                }
            }
            Format::Csv => {
                for r in &self.rows {
                    let Some(label) = r.first() else { continue };
                    for (column, cell) in self.headers.iter().zip(r).skip(1) {
                        for (column, value, text) in tidy_cells(column, cell) {
                            let _ = writeln!(
                                out,
                                "{},{},{},{},{}",
                                csv_field(&self.title),
                                csv_field(label),
                                csv_field(&column),
                                value.map_or(String::new(), |v| v.to_string()),
                                csv_field(&text)
                            );
                        }
                    }
                }
            }
        }
        out
    }
}

/// Width (characters) legends are wrapped to in [`Format::Table`], so a report fits 120 columns.
const LEGEND_WIDTH: usize = 116;

/// `text` wrapped at spaces into lines of at most `width` characters (longer words stay whole).
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split_whitespace() {
        let line = lines.last_mut().expect("never empty");
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            lines.push(word.to_string());
        } else {
            if !line.is_empty() {
                line.push(' ');
            }
            line.push_str(word);
        }
    }
    lines
}

/// The CSV header of [`Format::Csv`].
pub const CSV_HEADER: &str = "table,row,column,value,text";

/// One display cell as tidy `(column, number, text)` entries (see [`Format::Csv`]).
fn tidy_cells(column: &str, cell: &str) -> Vec<(String, Option<f64>, String)> {
    let number = |t: &str| t.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    match cell {
        "-" | "" => vec![(column.to_string(), None, String::new())],
        "yes" => vec![(column.to_string(), Some(1.0), cell.to_string())],
        "no" => vec![(column.to_string(), Some(0.0), cell.to_string())],
        _ => {
            if let Some(v) = number(cell) {
                return vec![(column.to_string(), Some(v), String::new())];
            }
            if let Some((a, b)) = cell.split_once('/') {
                if let (Some(a), Some(b)) = (number(a), number(b)) {
                    let (first, second) = if column.ends_with("held") {
                        (column.to_string(), format!("{} simulated", column.trim_end_matches(" held")))
                    } else {
                        (column.to_string(), format!("{column} of"))
                    };
                    return vec![(first, Some(a), String::new()), (second, Some(b), String::new())];
                }
            }
            vec![(column.to_string(), None, cell.to_string())]
        }
    }
}

fn pct(a: usize, b: usize) -> String {
    if b == 0 {
        "-".into()
    } else {
        format!("{:.1}", 100.0 * a as f64 / b as f64)
    }
}

fn opt(v: Option<f64>, scale: f64, prec: usize) -> String {
    v.map_or_else(|| "-".into(), |x| format!("{:.*}", prec, x * scale))
}

/// Short column name of a planner: `MA` (medial axis), `SN` (surface normals), else the name.
pub fn abbreviation(planner: &str) -> &str {
    match planner {
        "medial-axis" => "MA",
        "surface-normals" => "SN",
        p => p,
    }
}

/// The provenance as a two-column table.
pub fn provenance_table(results: &ResultsFile) -> Table {
    let p = &results.provenance;
    let rows = [
        ("suite", format!("{} ({})", p.suite_version, p.suite_size)),
        ("opengrasp", p.opengrasp_version.clone()),
        ("git commit", p.git_commit.clone().unwrap_or_else(|| "-".into())),
        ("cpu", format!("{} ({} cores, {} jobs)", p.cpu_model.as_deref().unwrap_or("-"), p.cpu_cores, p.jobs)),
        ("os", format!("{} {}", p.os, p.arch)),
        ("started", p.started_at.clone()),
        ("wall time [s]", format!("{:.1}", p.wall_seconds)),
    ]
    .into_iter()
    .chain(results.motion.as_ref().map(|m| ("motion protocol", m.options.protocol.name().to_string())))
    .chain(p.shard.map(|s| ("shard", format!("{}/{} (of a sharded run)", s.index, s.count))))
    .chain((!p.merged_from.is_empty()).then(|| ("merged from", format!("{} shards", p.merged_from.len()))))
    .map(|(k, v)| vec![k.to_string(), v])
    .collect();
    Table { title: "Provenance".into(), headers: vec!["field".into(), "value".into()], rows, legend: Vec::new() }
}

/// All tables of a results file: provenance, grasp tables, motion tables.
pub fn tables(results: &ResultsFile) -> Vec<Table> {
    let mut t = vec![provenance_table(results)];
    if let Some(g) = &results.grasp {
        t.extend(grasp_tables(g));
        t.extend(grasp_differences(g));
    }
    if let Some(m) = &results.motion {
        t.extend(motion_tables(m));
    }
    t
}

/// Renders all tables of a results file, separated by blank lines.
pub fn render(results: &ResultsFile, format: Format) -> String {
    render_all(&tables(results), format)
}

/// Renders the grasp tables of a section.
pub fn grasp_table(g: &GraspSection, format: Format) -> String {
    let mut t = grasp_tables(g);
    t.extend(grasp_differences(g));
    render_all(&t, format)
}

/// Renders the motion tables of a section.
pub fn motion_table(m: &MotionSection, format: Format) -> String {
    render_all(&motion_tables(m), format)
}

/// A Markdown section of images (the viewer's scene snapshots): a `## title` heading, then
/// each image as `![caption](link)` with its caption in italics under it. Brackets in
/// captions are escaped.
pub fn images_markdown(title: &str, images: &[(String, String)]) -> String {
    let mut out = format!("## {title}\n\n");
    for (caption, link) in images {
        let caption = caption.replace('[', "\\[").replace(']', "\\]");
        let _ = writeln!(out, "![{caption}]({})\n*{caption}*\n", link.replace(' ', "%20"));
    }
    out
}

/// Renders tables one after the other: separated by blank lines, or as one tidy CSV.
pub fn render_all(tables: &[Table], format: Format) -> String {
    match format {
        Format::Csv => {
            std::iter::once(format!("{CSV_HEADER}\n")).chain(tables.iter().map(|t| t.render(format))).collect()
        }
        _ => tables.iter().map(|t| t.render(format)).collect::<Vec<_>>().join("\n"),
    }
}
