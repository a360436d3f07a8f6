//! Text tables of rankings for the terminal.

use std::fmt::Write as _;

use super::{BenchmarkKind, EntryMetrics, RankedEntry, Ranking};

fn fmt_f(v: f64, prec: usize) -> String {
    format!("{v:.prec$}")
}

/// Text tables of rankings (one per benchmark, empty benchmarks say so), for the terminal.
pub fn render_rankings(rankings: &[Ranking]) -> String {
    let mut out = String::new();
    for (i, r) in rankings.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        let _ = writeln!(out, "== {} ({})", r.benchmark.id, r.benchmark.target);
        if r.entries.is_empty() {
            let _ = writeln!(out, "   no submissions yet");
            continue;
        }
        let metric_heads: [&str; 4] = match r.benchmark.kind {
            BenchmarkKind::Grasp => ["FC %", "mean eps", "palm", "objects"],
            BenchmarkKind::Motion => ["success %", "median t (s)", "valid pp %", "runs"],
        };
        let mut head = vec!["suite", "#", "planner", "submitter", "sub"];
        head.extend(metric_heads);
        head.push("date");
        let rows: Vec<Vec<String>> = r
            .entries
            .iter()
            .map(|e| {
                let mut row = vec![
                    e.suite_size.clone(),
                    e.rank.to_string(),
                    e.planner.clone(),
                    who(e),
                    e.submission.0.to_string(),
                ];
                row.extend(match &e.metrics {
                    EntryMetrics::Grasp { fc_percent, mean_epsilon, palm_contact, objects, .. } => {
                        [fmt_f(*fc_percent, 1), fmt_f(*mean_epsilon, 4), palm_contact.to_string(), objects.to_string()]
                    }
                    EntryMetrics::Motion { success_rate, median_planning_time, valid_processed, runs, .. } => [
                        fmt_f(*success_rate, 1),
                        median_planning_time.map_or_else(|| "-".to_string(), |t| fmt_f(t, 4)),
                        fmt_f(*valid_processed, 1),
                        runs.to_string(),
                    ],
                });
                row.push(e.submitted_at.chars().take(10).collect());
                row
            })
            .collect();
        let mut widths: Vec<usize> = head.iter().map(|h| h.chars().count()).collect();
        for row in &rows {
            for (w, cell) in widths.iter_mut().zip(row) {
                *w = (*w).max(cell.chars().count());
            }
        }
        let line = |cells: &[String]| {
            let parts: Vec<String> = cells.iter().zip(&widths).map(|(c, w)| format!("{c:<w$}")).collect();
            parts.join("  ").trim_end().to_string()
        };
        let head: Vec<String> = head.iter().map(|h| h.to_string()).collect();
        let _ = writeln!(out, "{}", line(&head));
        let _ = writeln!(out, "{}", widths.iter().map(|w| "-".repeat(*w)).collect::<Vec<_>>().join("  "));
        for row in &rows {
            let _ = writeln!(out, "{}", line(row));
        }
    }
    out
}

fn who(e: &RankedEntry) -> String {
    match &e.team {
        Some(t) => format!("{} ({t})", e.submitter),
        None => e.submitter.clone(),
    }
}
