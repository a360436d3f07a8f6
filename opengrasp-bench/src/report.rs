//! Reports: the OpenGRASP paper's tables from a [`ResultsFile`], as aligned text, Markdown
//! or CSV.
//!
//! - [`grasp_tables`]: Tables I and II, one table per hand: per object, the candidates tested
//!   (grasps with palm contact) and the percentage of force-closure grasps among them for
//!   every planner (medial axis and surface normals for the reference suite), the mean
//!   epsilon of those force-closure grasps, the physics hold check (held / tested) when it
//!   ran, the paper's numbers beside them when known, and a total row.
//! - [`motion_tables`]: Table III, one row per planner per scene: runs, success, average
//!   setup / planning / post-processing time, valid % of planned and post-processed paths,
//!   C-space and end-effector lengths, clearance; plus a table of planning-time and
//!   path-length percentiles (min, p25, median, p75, p95, max); and one row per Clean the
//!   Table episode when they ran.
//!
//! All numbers come from the records (motion summaries are recomputed from the runs).

use std::fmt::Write as _;

use crate::paper::{PAPER_OBJECTS, PAPER_RESULTS};
use opengrasp_motion::metrics::Stats;

use crate::results::{motion_summaries, GraspSection, MotionSection, ResultsFile};

/// Output format of a report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Format {
    /// Aligned plain-text columns (terminal).
    #[default]
    Table,
    /// GitHub-flavoured Markdown tables.
    Markdown,
    /// Comma-separated values (each table preceded by its title as a one-cell row).
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
            }
            Format::Csv => {
                let _ = writeln!(out, "{}", csv_field(&self.title));
                let _ = writeln!(out, "{}", self.headers.iter().map(|s| csv_field(s)).collect::<Vec<_>>().join(","));
                for r in &self.rows {
                    let _ = writeln!(out, "{}", r.iter().map(|s| csv_field(s)).collect::<Vec<_>>().join(","));
                }
            }
        }
        out
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

/// Tables I/II: one table per hand (see the [module docs](self)).
pub fn grasp_tables(g: &GraspSection) -> Vec<Table> {
    let mut hands: Vec<&str> = g.hands.iter().map(String::as_str).collect();
    let mut objects: Vec<&str> = g.objects.iter().map(String::as_str).collect();
    let mut planners: Vec<&str> = g.planners.iter().map(|p| p.name.as_str()).collect();
    for r in &g.cells {
        for (list, v) in [(&mut hands, &r.cell.hand), (&mut objects, &r.cell.object), (&mut planners, &r.cell.planner)]
        {
            if !list.contains(&v.as_str()) {
                list.push(v);
            }
        }
    }
    let mut tables = Vec::new();
    for hand in hands {
        let cells: Vec<_> = g.cells.iter().filter(|r| r.cell.hand == hand).map(|r| &r.cell).collect();
        if cells.is_empty() {
            continue;
        }
        let hand_planners: Vec<&str> =
            planners.iter().copied().filter(|p| cells.iter().any(|c| c.planner == *p)).collect();
        let with_paper = |p: &str| PAPER_RESULTS.iter().any(|r| r.1 == hand && r.2 == p);
        // A physics column (held / tested in the rapier hold check) when the check ran.
        let with_physics = cells.iter().any(|c| c.physics_tested > 0);
        let mut headers = vec!["object".to_string()];
        for p in &hand_planners {
            let a = abbreviation(p);
            headers.push(format!("{a} tested"));
            headers.push(format!("{a} FC %"));
            headers.push(format!("{a} eps"));
            if with_physics {
                headers.push(format!("{a} held"));
            }
            if with_paper(p) {
                headers.push(format!("{a} paper tested"));
                headers.push(format!("{a} paper FC %"));
            }
        }
        let mut rows = Vec::new();
        for object in objects.iter().copied().filter(|o| cells.iter().any(|c| c.object == *o)) {
            let label = PAPER_OBJECTS.iter().find(|(_, n)| *n == object).map_or(object, |(l, _)| l);
            let mut row = vec![label.to_string()];
            for p in &hand_planners {
                match cells.iter().find(|c| c.object == object && c.planner == *p) {
                    Some(c) => {
                        row.push(c.palm_contact.to_string());
                        row.push(pct(c.force_closure_palm, c.palm_contact));
                        row.push(format!("{:.4}", c.mean_epsilon));
                        if with_physics {
                            row.push(format!("{}/{}", c.physics_held, c.physics_tested));
                        }
                    }
                    None => row.extend(std::iter::repeat_n("-".to_string(), 3 + usize::from(with_physics))),
                }
                if with_paper(p) {
                    match PAPER_RESULTS.iter().find(|r| r.0 == object && r.1 == hand && r.2 == *p) {
                        Some(r) => {
                            row.push(r.3.to_string());
                            row.push(format!("{:.1}", r.4));
                        }
                        None => row.extend(std::iter::repeat_n("-".to_string(), 2)),
                    }
                }
            }
            rows.push(row);
        }
        let mut total = vec!["total".to_string()];
        for p in &hand_planners {
            let pc: Vec<_> = cells.iter().filter(|c| c.planner == *p).collect();
            let palm: usize = pc.iter().map(|c| c.palm_contact).sum();
            let fc: usize = pc.iter().map(|c| c.force_closure_palm).sum();
            // Cell epsilons are means over their force-closure palm-contact grasps.
            let eps = if fc == 0 {
                0.0
            } else {
                pc.iter().map(|c| c.mean_epsilon * c.force_closure_palm as f64).sum::<f64>() / fc as f64
            };
            total.extend([palm.to_string(), pct(fc, palm), format!("{eps:.4}")]);
            if with_physics {
                let tested: usize = pc.iter().map(|c| c.physics_tested).sum();
                let held: usize = pc.iter().map(|c| c.physics_held).sum();
                total.push(format!("{held}/{tested}"));
            }
            if with_paper(p) {
                let pr: Vec<_> = PAPER_RESULTS
                    .iter()
                    .filter(|r| r.1 == hand && r.2 == *p && pc.iter().any(|c| c.object == r.0))
                    .collect();
                let n: usize = pr.iter().map(|r| r.3).sum();
                let f: f64 = pr.iter().map(|r| r.3 as f64 * r.4 / 100.0).sum();
                total.push(n.to_string());
                total.push(if n == 0 { "-".into() } else { format!("{:.1}", 100.0 * f / n as f64) });
            }
        }
        rows.push(total);
        let which = match hand {
            "armar3" => "Table I",
            "barrett" => "Table II",
            _ => "grasp table",
        };
        tables.push(Table { title: format!("{which}: grasp planners, hand {hand}"), headers, rows });
    }
    tables
}

/// Table III and the percentile table (see the [module docs](self)).
pub fn motion_tables(m: &MotionSection) -> Vec<Table> {
    let summaries = motion_summaries(m);
    let strings = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<String>>();
    let pct_or_dash = |solved: usize, v: f64| if solved == 0 { "-".to_string() } else { format!("{v:.1}") };
    let mut time_rows = Vec::new();
    let mut quality_rows = Vec::new();
    for s in &summaries {
        let label = format!("{} / {}", s.scene, s.planner);
        time_rows.push(vec![
            label.clone(),
            s.runs.to_string(),
            format!("{:.1}", s.success_rate),
            opt(s.setup_time.mean, 1e3, 2),
            opt(s.planning_time.mean, 1e3, 2),
            opt(s.planning_time.p50, 1e3, 2),
            opt(s.postprocessing_time.mean, 1e3, 2),
        ]);
        quality_rows.push(vec![
            label,
            pct_or_dash(s.solved, s.valid_planned.discrete),
            pct_or_dash(s.solved, s.valid_processed.discrete),
            pct_or_dash(s.solved, s.valid_planned.strict),
            pct_or_dash(s.solved, s.valid_processed.strict),
            opt(s.length_planned.mean, 1.0, 3),
            opt(s.length_processed.mean, 1.0, 3),
            opt(s.ee_length_planned.mean, 1.0, 3),
            opt(s.ee_length_processed.mean, 1.0, 3),
            opt(s.clearance_planned.mean, 1e3, 1),
            opt(s.clearance_processed.mean, 1e3, 1),
        ]);
    }
    let table3_time = Table {
        title: "Table III: motion planners, times (means over runs; post-proc. = post-processing)".into(),
        headers: strings(&[
            "scene / planner",
            "runs",
            "success %",
            "setup [ms]",
            "planning [ms]",
            "planning p50 [ms]",
            "post-proc. [ms]",
        ]),
        rows: time_rows,
    };
    let table3_quality = Table {
        title: "Table III: motion planners, solutions (P = planned, PP = post-processed; means over solved runs)"
            .into(),
        headers: strings(&[
            "scene / planner",
            "valid P %",
            "valid PP %",
            "strict P %",
            "strict PP %",
            "length P",
            "length PP",
            "EE length P [m]",
            "EE length PP [m]",
            "clearance P [mm]",
            "clearance PP [mm]",
        ]),
        rows: quality_rows,
    };
    let mut headers = vec!["scene / planner".to_string(), "metric".to_string()];
    headers.extend(["n", "min", "p25", "median", "p75", "p95", "max"].iter().map(|s| s.to_string()));
    let mut rows = Vec::new();
    for s in &summaries {
        let stat_row = |metric: &str, st: &Stats, scale: f64, prec: usize| {
            vec![
                format!("{} / {}", s.scene, s.planner),
                metric.to_string(),
                st.count.to_string(),
                opt(st.min, scale, prec),
                opt(st.p25, scale, prec),
                opt(st.p50, scale, prec),
                opt(st.p75, scale, prec),
                opt(st.p95, scale, prec),
                opt(st.max, scale, prec),
            ]
        };
        rows.push(stat_row("planning time [ms]", &s.planning_time, 1e3, 2));
        rows.push(stat_row("post-proc. time [ms]", &s.postprocessing_time, 1e3, 2));
        rows.push(stat_row("length post-proc.", &s.length_processed, 1.0, 3));
    }
    let percentiles = Table { title: "Motion planners: percentiles".into(), headers, rows };
    let mut tables = vec![table3_time, table3_quality, percentiles];
    if !m.episodes.is_empty() {
        tables.push(episode_table(m));
    }
    tables
}

/// One row per Clean the Table episode: objects cleaned, summed times and lengths, validity.
fn episode_table(m: &MotionSection) -> Table {
    let headers = [
        "planner",
        "episode",
        "seed",
        "cleaned",
        "setup [ms]",
        "planning [ms]",
        "post-proc. [s]",
        "length PP",
        "EE length PP [m]",
        "all valid",
    ]
    .iter()
    .map(|h| h.to_string())
    .collect();
    let rows = m
        .episodes
        .iter()
        .map(|e| {
            let t = &e.totals;
            vec![
                e.planner.clone(),
                e.index.to_string(),
                e.seed.to_string(),
                match &e.error {
                    Some(err) => format!("error: {err}"),
                    None => format!("{}/{}", t.cleaned, e.objects.len()),
                },
                format!("{:.2}", t.setup_time * 1e3),
                format!("{:.2}", t.planning_time * 1e3),
                format!("{:.2}", t.postprocessing_time),
                format!("{:.3}", t.length),
                format!("{:.3}", t.ee_length),
                if t.all_valid { "yes" } else { "no" }.to_string(),
            ]
        })
        .collect();
    Table { title: "Scene 3, Clean the Table: episodes (sums over the grasp and place queries)".into(), headers, rows }
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
    .map(|(k, v)| vec![k.to_string(), v])
    .collect();
    Table { title: "Provenance".into(), headers: vec!["field".into(), "value".into()], rows }
}

/// All tables of a results file: provenance, grasp tables, motion tables.
pub fn tables(results: &ResultsFile) -> Vec<Table> {
    let mut t = vec![provenance_table(results)];
    if let Some(g) = &results.grasp {
        t.extend(grasp_tables(g));
    }
    if let Some(m) = &results.motion {
        t.extend(motion_tables(m));
    }
    t
}

/// Renders all tables of a results file, separated by blank lines.
pub fn render(results: &ResultsFile, format: Format) -> String {
    tables(results).iter().map(|t| t.render(format)).collect::<Vec<_>>().join("\n")
}

/// Renders the grasp tables of a section.
pub fn grasp_table(g: &GraspSection, format: Format) -> String {
    grasp_tables(g).iter().map(|t| t.render(format)).collect::<Vec<_>>().join("\n")
}

/// Renders the motion tables of a section.
pub fn motion_table(m: &MotionSection, format: Format) -> String {
    motion_tables(m).iter().map(|t| t.render(format)).collect::<Vec<_>>().join("\n")
}
