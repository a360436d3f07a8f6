//! Inline SVG charts of a ranking page (no scripts: the CSP forbids them) and the paper's
//! reference figures for the same benchmark.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use rusqlite::Connection;

use super::error::Result;
use super::html::escape;
use super::{BenchmarkInfo, BenchmarkKind, RankedEntry};

/// Most entries drawn in a page's charts (the first ones of the page).
pub const MAX_CHARTED: usize = 12;

/// Per-entry detail behind a ranking page's charts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChartData {
    /// Grasp benchmarks: `(entry index, object, FC % of palm-contact candidates, mean ε)`.
    pub objects: Vec<(usize, String, f64, f64)>,
    /// Motion benchmarks: planning times (s) of each charted entry's solved runs, ascending.
    pub times: Vec<Vec<f64>>,
}

/// Reads the per-object cells (grasp) or solved planning times (motion) of `entries`.
pub(crate) fn chart_data(conn: &Connection, info: &BenchmarkInfo, entries: &[RankedEntry]) -> Result<ChartData> {
    let mut data = ChartData::default();
    for (i, e) in entries.iter().take(MAX_CHARTED).enumerate() {
        match info.kind {
            BenchmarkKind::Grasp => {
                let mut stmt = conn.prepare_cached(
                    "SELECT object, SUM(palm_contact), SUM(force_closure_palm), SUM(mean_epsilon * force_closure_palm)
                     FROM grasp_cells WHERE submission_id = ?1 AND benchmark_id = ?2 AND planner = ?3
                     GROUP BY object ORDER BY object",
                )?;
                let rows = stmt.query_map(rusqlite::params![e.submission.0, info.id, e.planner], |r| {
                    Ok((r.get::<_, String>(0)?, r.get::<_, i64>(1)?, r.get::<_, i64>(2)?, r.get::<_, f64>(3)?))
                })?;
                for row in rows {
                    let (object, palm, fc, eps_sum) = row?;
                    let pct = if palm > 0 { 100.0 * fc as f64 / palm as f64 } else { 0.0 };
                    let eps = if fc > 0 { eps_sum / fc as f64 } else { 0.0 };
                    data.objects.push((i, object, pct, eps));
                }
            }
            BenchmarkKind::Motion => {
                let mut stmt = conn.prepare_cached(
                    "SELECT planning_time FROM motion_runs
                     WHERE submission_id = ?1 AND benchmark_id = ?2 AND planner = ?3 AND status = 'solved'
                     ORDER BY planning_time",
                )?;
                let rows = stmt.query_map(rusqlite::params![e.submission.0, info.id, e.planner], |r| r.get(0))?;
                data.times.push(rows.collect::<rusqlite::Result<_>>()?);
            }
        }
    }
    Ok(data)
}

/// A reference figure of the paper (Ulbrich et al. 2011) for a benchmark.
#[derive(Clone, Debug, PartialEq)]
pub struct PaperRow {
    /// What the row is (planner and table).
    pub label: String,
    /// Grasp: pooled FC % over the paper's objects; motion: average planning time (s).
    pub figure: f64,
    /// Grasp: per-object FC %, keyed by our asset name; motion: empty.
    pub per_object: BTreeMap<String, f64>,
    /// Motion: post-processed paths valid (%); grasp: `None`.
    pub valid_processed: Option<f64>,
}

/// The paper's rows for `info` (Tables I and II for the ARMAR-III and Barrett hands, Table
/// III for the scene standing in for its first motion scene); empty for other benchmarks.
pub fn paper_rows(info: &BenchmarkInfo) -> Vec<PaperRow> {
    use opengrasp_bench::paper::{PAPER_RESULTS, PAPER_SCENE_1, PAPER_TABLE_III};
    match info.kind {
        BenchmarkKind::Grasp => {
            let table = if info.target == "barrett" { "II" } else { "I" };
            ["medial-axis", "surface-normals"]
                .iter()
                .filter_map(|planner| {
                    let rows: Vec<_> = PAPER_RESULTS.iter().filter(|r| r.1 == info.target && r.2 == *planner).collect();
                    let candidates: usize = rows.iter().map(|r| r.3).sum();
                    (candidates > 0).then(|| PaperRow {
                        label: format!("paper, Table {table}: {planner}"),
                        figure: rows.iter().map(|r| r.3 as f64 * r.4).sum::<f64>() / candidates as f64,
                        per_object: rows.iter().map(|r| (r.0.to_string(), r.4)).collect(),
                        valid_processed: None,
                    })
                })
                .collect()
        }
        BenchmarkKind::Motion if info.target == PAPER_SCENE_1 => vec![PaperRow {
            label: "paper, Table III: reference planner".into(),
            figure: PAPER_TABLE_III.planning,
            per_object: BTreeMap::new(),
            valid_processed: Some(PAPER_TABLE_III.valid_processed),
        }],
        BenchmarkKind::Motion => Vec::new(),
    }
}

/// Colour of the `i`-th charted entry (a qualitative palette).
fn colour(i: usize) -> &'static str {
    const PALETTE: [&str; 8] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"];
    PALETTE[i % PALETTE.len()]
}

const WIDTH: f64 = 900.0;
const LEFT: f64 = 230.0;
const RIGHT: f64 = 30.0;
const ROW: f64 = 22.0;

fn svg_open(out: &mut String, height: f64, title: &str) {
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {WIDTH} {height}\" width=\"100%\" \
         role=\"img\" aria-label=\"{t}\" font-family=\"sans-serif\" font-size=\"14\"><title>{t}</title>",
        t = escape(title)
    );
}

/// x axis from 0 to `max` with five ticks at `y`; returns the x of a value.
fn axis(out: &mut String, y: f64, max: f64, unit: &str) -> impl Fn(f64) -> f64 {
    let scale = move |v: f64| LEFT + (WIDTH - LEFT - RIGHT) * (v / max).clamp(0.0, 1.0);
    let _ = write!(out, "<line x1=\"{LEFT}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"#444\"/>", WIDTH - RIGHT);
    for k in 0..=4 {
        let v = max * k as f64 / 4.0;
        let x = scale(v);
        let _ = write!(
            out,
            "<line x1=\"{x:.1}\" y1=\"{y}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"#444\"/>\
             <text x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}{}</text>",
            y + 4.0,
            y + 16.0,
            tick(v),
            if k == 4 { unit } else { "" }
        );
    }
    scale
}

fn tick(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v >= 10.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.3}").trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

fn label(e: &RankedEntry) -> String {
    let mut name = format!("#{} {} (submission {})", e.rank, e.planner, e.submission.0);
    if name.chars().count() > 30 {
        name = name.chars().take(29).collect::<String>() + "…";
    }
    escape(&name)
}

/// Planning-time distributions, one row per entry: every solved run a dot, the median a bar.
pub fn planning_times_svg(entries: &[RankedEntry], data: &ChartData) -> String {
    let rows = data.times.len();
    let max = data.times.iter().flat_map(|t| t.last()).copied().fold(0.0_f64, f64::max);
    let max = if max > 0.0 { nice(max) } else { 1.0 };
    let height = 30.0 + ROW * rows as f64 + 30.0;
    let mut out = String::new();
    svg_open(&mut out, height, "planning time of each solved run per entry (s)");
    let scale = axis(&mut out, height - 26.0, max, " s");
    for (i, (times, e)) in data.times.iter().zip(entries).enumerate() {
        let y = 30.0 + ROW * i as f64;
        let _ =
            write!(out, "<text x=\"{:.0}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>", LEFT - 8.0, y + 4.0, label(e));
        for t in times {
            let _ = write!(
                out,
                "<circle cx=\"{:.1}\" cy=\"{y:.1}\" r=\"3\" fill=\"{}\" fill-opacity=\"0.5\"/>",
                scale(*t),
                colour(i)
            );
        }
        if let Some(m) = median(times) {
            let x = scale(m);
            let _ = write!(
                out,
                "<line x1=\"{x:.1}\" y1=\"{:.1}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"#000\" stroke-width=\"2\"/>",
                y - 8.0,
                y + 8.0
            );
        } else {
            let _ = write!(out, "<text x=\"{LEFT}\" y=\"{:.1}\" fill=\"#777\">no solved run</text>", y + 4.0);
        }
    }
    out.push_str("</svg>");
    out
}

/// Per object: FC % (or mean ε) of every entry as a coloured dot, the paper's FC % as
/// hollow black diamonds.
pub fn per_object_svg(entries: &[RankedEntry], data: &ChartData, paper: &[PaperRow], epsilon: bool) -> String {
    let objects: Vec<&str> = {
        let mut o: Vec<&str> = data.objects.iter().map(|r| r.1.as_str()).collect();
        o.sort_unstable();
        o.dedup();
        o
    };
    let value = |r: &(usize, String, f64, f64)| if epsilon { r.3 } else { r.2 };
    let max = if epsilon { nice(data.objects.iter().map(value).fold(0.0, f64::max).max(1e-3)) } else { 100.0 };
    let charted = entries.len().min(MAX_CHARTED);
    let legend_rows = charted + if epsilon { 0 } else { paper.len() };
    let top = 20.0 + 16.0 * legend_rows as f64;
    let height = top + ROW * objects.len() as f64 + 34.0;
    let mut out = String::new();
    let title = if epsilon { "mean epsilon of force-closure grasps per object" } else { "FC % per object" };
    svg_open(&mut out, height, title);
    for (i, e) in entries.iter().take(charted).enumerate() {
        let y = 14.0 + 16.0 * i as f64;
        let _ = write!(
            out,
            "<circle cx=\"{LEFT}\" cy=\"{:.1}\" r=\"4\" fill=\"{}\"/><text x=\"{:.0}\" y=\"{:.1}\">{}</text>",
            y,
            colour(i),
            LEFT + 10.0,
            y + 4.0,
            label(e)
        );
    }
    if !epsilon {
        for (k, p) in paper.iter().enumerate() {
            let y = 14.0 + 16.0 * (charted + k) as f64;
            let _ = write!(
                out,
                "{}<text x=\"{:.0}\" y=\"{:.1}\">{}</text>",
                diamond(LEFT, y, k),
                LEFT + 10.0,
                y + 4.0,
                escape(&p.label)
            );
        }
    }
    let scale = axis(&mut out, height - 28.0, max, if epsilon { "" } else { " %" });
    for (j, object) in objects.iter().enumerate() {
        let y = top + ROW * j as f64 + 8.0;
        let _ = write!(
            out,
            "<text x=\"{:.0}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
            LEFT - 8.0,
            y + 4.0,
            escape(object)
        );
        let _ =
            write!(out, "<line x1=\"{LEFT}\" y1=\"{y:.1}\" x2=\"{}\" y2=\"{y:.1}\" stroke=\"#eee\"/>", WIDTH - RIGHT);
        for r in data.objects.iter().filter(|r| r.1 == *object) {
            let _ = write!(
                out,
                "<circle cx=\"{:.1}\" cy=\"{y:.1}\" r=\"4\" fill=\"{}\" fill-opacity=\"0.8\"/>",
                scale(value(r)),
                colour(r.0)
            );
        }
        if !epsilon {
            for (k, p) in paper.iter().enumerate() {
                if let Some(v) = p.per_object.get(*object) {
                    out.push_str(&diamond(scale(*v), y, k));
                }
            }
        }
    }
    out.push_str("</svg>");
    out
}

/// A hollow diamond (paper reference mark); `k` picks a dashed outline for the second row.
fn diamond(x: f64, y: f64, k: usize) -> String {
    let dash = if k % 2 == 1 { " stroke-dasharray=\"2 1\"" } else { "" };
    format!(
        "<path d=\"M{x:.1} {:.1}L{:.1} {y:.1}L{x:.1} {:.1}L{:.1} {y:.1}Z\" fill=\"none\" stroke=\"#000\"{dash}/>",
        y - 5.0,
        x + 5.0,
        y + 5.0,
        x - 5.0
    )
}

/// Median of ascending values.
fn median(sorted: &[f64]) -> Option<f64> {
    let n = sorted.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(sorted[n / 2]),
        _ => Some(0.5 * (sorted[n / 2 - 1] + sorted[n / 2])),
    }
}

/// The smallest of 1, 2, 2.5, 5 × 10^k at or above `v` (> 0): a round axis end.
pub fn nice(v: f64) -> f64 {
    let p = 10f64.powf(v.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0].iter().map(|m| m * p).find(|&c| c >= v * (1.0 - 1e-12)).unwrap_or(10.0 * p)
}
