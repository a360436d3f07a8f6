//! Server-rendered HTML pages of the high-score board (every interpolated text is escaped).

use std::fmt::Write as _;

use super::charts::{self, ChartData};
use super::{BenchmarkInfo, EntryMetrics, Ranking};

/// Escapes `&`, `<`, `>`, `"` and `'` for HTML text and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "body{font-family:sans-serif;margin:1.5em;max-width:80em}\
table{border-collapse:collapse;width:100%;font-size:.9em}\
th,td{padding:.3em .5em;border-bottom:1px solid #ccc;text-align:left;vertical-align:top;overflow-wrap:anywhere}\
td.n{text-align:right}tr.paper{background:#f3f3e6;font-style:italic}p.rules{color:#444;font-size:.9em}\
dl.kv{margin:0;display:grid;grid-template-columns:auto 1fr;gap:0 .6em;font-size:.9em}\
dl.kv dt{color:#555}dl.kv dd{margin:0;font-family:monospace;overflow-wrap:anywhere}\
svg{max-width:60em;display:block;margin:.5em 0}code{overflow-wrap:anywhere}";

fn page(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n\
         <style>{STYLE}</style>\n</head>\n<body>\n{body}</body>\n</html>\n",
        escape(title)
    )
}

/// The index page: every benchmark with a link to its high-score page.
pub fn index_page(benchmarks: &[BenchmarkInfo]) -> String {
    let mut body = String::from(
        "<h1>OpenGRASP high-score</h1>\n<table>\n<tr><th>benchmark</th><th>kind</th>\
<th>description</th><th>submissions</th></tr>\n",
    );
    for b in benchmarks {
        let _ = writeln!(
            body,
            "<tr><td><a href=\"/highscore/{id}\">{id}</a></td><td>{kind}</td><td>{desc}</td><td class=\"n\">{n}</td></tr>",
            id = escape(&b.id),
            kind = b.kind.as_str(),
            desc = escape(&b.description),
            n = b.submissions
        );
    }
    body.push_str(
        "</table>\n<p>JSON API: <code>GET /api/benchmarks</code>, \
<code>GET /api/benchmarks/&lt;kind&gt;/&lt;name&gt;/ranking</code>, <code>POST /api/submissions</code>.</p>\n",
    );
    page("OpenGRASP high-score", &body)
}

/// The high-score page of one benchmark: the paper's reference rows, the ranked entries
/// (links to their submissions and uploaded files, parameters as key/value lists) and inline
/// SVG charts of the first [`MAX_CHARTED`](crate::charts::MAX_CHARTED) entries.
pub fn ranking_page(ranking: &Ranking, data: &ChartData) -> String {
    let b = &ranking.benchmark;
    let mut body = format!(
        "<p><a href=\"/\">all benchmarks</a></p>\n<h1>{}</h1>\n<p>{} (name in results files: <code>{}</code>)</p>\n\
         <p class=\"rules\">Ranking: {}</p>\n",
        escape(&b.id),
        escape(&b.description),
        escape(&b.target),
        escape(&ranking.rules)
    );
    let paper = charts::paper_rows(b);
    let grasp = b.kind == crate::BenchmarkKind::Grasp;
    let _ = write!(
        body,
        "<p>{} entries in all; this page shows {} to {}.</p>\n<table>\n<tr><th>#</th><th>planner</th><th>submitter</th>\
         <th>submission</th>{}<th>suite</th><th>seed</th><th>submitted</th><th>parameters</th></tr>\n",
        ranking.total,
        (ranking.offset + 1).min(ranking.total),
        ranking.offset + ranking.entries.len(),
        if grasp {
            "<th>FC %</th><th>mean ε</th><th>palm-contact candidates</th><th>objects</th>"
        } else {
            "<th>success %</th><th>median planning time (s)</th><th>valid post-processed %</th><th>runs</th>"
        }
    );
    for p in &paper {
        let figures = if grasp {
            format!(
                "<td class=\"n\">{:.1}</td><td class=\"n\">-</td><td class=\"n\">-</td><td class=\"n\">{}</td>",
                p.figure,
                p.per_object.len()
            )
        } else {
            format!(
                "<td class=\"n\">-</td><td class=\"n\">{:.2} (mean)</td><td class=\"n\">{:.1}</td><td class=\"n\">-</td>",
                p.figure,
                p.valid_processed.unwrap_or(f64::NAN)
            )
        };
        let _ = writeln!(
            body,
            "<tr class=\"paper\"><td>ref</td><td colspan=\"3\">{}</td>{figures}<td colspan=\"4\">Ulbrich et al. 2011 (published figures)</td></tr>",
            escape(&p.label)
        );
    }
    for e in &ranking.entries {
        let who = match &e.team {
            Some(t) => format!("{} ({})", escape(&e.submitter), escape(t)),
            None => escape(&e.submitter),
        };
        let _ = write!(
            body,
            "<tr><td class=\"n\">{}</td><td>{}</td><td>{who}</td><td class=\"n\"><a href=\"/submission/{id}\">{id}</a> \
             (<a href=\"/api/submissions/{id}\">file</a>)</td>",
            e.rank,
            escape(&e.planner),
            id = e.submission.0
        );
        let figures = match &e.metrics {
            EntryMetrics::Grasp { fc_percent, mean_epsilon, palm_contact, objects, .. } => [
                format!("{fc_percent:.1}"),
                format!("{mean_epsilon:.4}"),
                palm_contact.to_string(),
                objects.to_string(),
            ],
            EntryMetrics::Motion { success_rate, median_planning_time, valid_processed, runs, .. } => [
                format!("{success_rate:.1}"),
                median_planning_time.map_or_else(|| "-".to_string(), |t| format!("{t:.4}")),
                format!("{valid_processed:.1}"),
                runs.to_string(),
            ],
        };
        for f in figures {
            let _ = write!(body, "<td class=\"n\">{f}</td>");
        }
        let _ = writeln!(
            body,
            "<td>{}</td><td class=\"n\">{}</td><td>{}</td><td>{}</td></tr>",
            escape(&e.suite_size),
            e.seed.map_or_else(|| "-".to_string(), |s| s.to_string()),
            escape(e.submitted_at.get(..16).unwrap_or(&e.submitted_at)).replace('T', " "),
            e.parameters.as_deref().map_or_else(|| "-".to_string(), parameters_list)
        );
    }
    body.push_str("</table>\n");
    if ranking.entries.is_empty() {
        body.push_str("<p>No submissions on this page.</p>\n");
    } else if grasp {
        body.push_str("<h2>FC % per object</h2>\n");
        body.push_str(&charts::per_object_svg(&ranking.entries, data, &paper, false));
        body.push_str("\n<h2>Mean ε per object</h2>\n");
        body.push_str(&charts::per_object_svg(&ranking.entries, data, &paper, true));
        body.push('\n');
    } else {
        body.push_str("<h2>Planning times</h2>\n<p>Each dot is a solved run, the bar its entry's median.</p>\n");
        body.push_str(&charts::planning_times_svg(&ranking.entries, data));
        body.push('\n');
    }
    page(&format!("{} high-score", b.id), &body)
}

/// A small error page (status and message, escaped).
pub fn error_page(status: u16, message: &str) -> String {
    page(
        &format!("{status}"),
        &format!("<p><a href=\"/\">all benchmarks</a></p>\n<h1>{status}</h1>\n<p>{}</p>\n", escape(message)),
    )
}

/// The page of one submission: provenance, planners with their parameters, its entries with
/// links to the benchmarks, and a link to the uploaded file.
pub fn submission_page(s: &crate::SubmissionSummary) -> String {
    let who = match &s.team {
        Some(t) => format!("{} ({})", escape(&s.submitter), escape(t)),
        None => escape(&s.submitter),
    };
    let mut body = format!(
        "<p><a href=\"/\">all benchmarks</a></p>\n<h1>Submission {id}</h1>\n<dl class=\"kv\">\
<dt>submitter</dt><dd>{who}</dd><dt>submitted</dt><dd>{at}</dd><dt>suite</dt><dd>{size}</dd>\
<dt>version</dt><dd>{ver}</dd><dt>commit</dt><dd>{commit}</dd>\
<dt>results file</dt><dd><a href=\"/api/submissions/{id}\">as uploaded (JSON)</a></dd></dl>\n",
        id = s.id.0,
        at = escape(&s.submitted_at),
        size = escape(&s.suite_size),
        ver = escape(&s.version),
        commit = escape(s.git_commit.as_deref().unwrap_or("-")),
    );
    body.push_str("<h2>Entries</h2>\n<ul>\n");
    for (bench, planner, m) in &s.entries {
        let figures = match m {
            EntryMetrics::Grasp { fc_percent, mean_epsilon, .. } => {
                format!("FC {fc_percent:.1} %, mean ε {mean_epsilon:.4}")
            }
            EntryMetrics::Motion { success_rate, median_planning_time, .. } => format!(
                "success {success_rate:.1} %, median {}",
                median_planning_time.map_or_else(|| "-".to_string(), |t| format!("{t:.4} s"))
            ),
        };
        let _ = writeln!(
            body,
            "<li><a href=\"/highscore/{b}\">{b}</a>: {p} — {figures}</li>",
            b = escape(bench),
            p = escape(planner)
        );
    }
    body.push_str("</ul>\n<h2>Planners</h2>\n");
    for (kind, name, params) in &s.planners {
        let _ = writeln!(body, "<h3>{} ({})</h3>\n{}", escape(name), escape(kind), parameters_list(params));
    }
    page(&format!("submission {}", s.id.0), &body)
}

/// Planner parameters as a key/value list: Rust `Debug` text such as
/// `RrtConnect { range: 0.1, goal_bias: 0.05 }` becomes `range = 0.1`, `goal_bias = 0.05`;
/// anything else is shown as text.
pub fn parameters_list(text: &str) -> String {
    let pairs = parameter_pairs(text);
    if pairs.is_empty() {
        return format!("<p class=\"params\"><code>{}</code></p>", escape(text));
    }
    let mut out = String::from("<dl class=\"kv\">");
    for (k, v) in pairs {
        let _ = write!(out, "<dt>{}</dt><dd>{}</dd>", escape(&k), escape(&v));
    }
    out.push_str("</dl>");
    out
}

/// `key: value` pairs at any depth of `Debug`-like text (`Name { a: 1, b: Inner { c: 2 } }`
/// gives `a = 1`, `b.c = 2`); empty when the text has none.
pub fn parameter_pairs(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut path: Vec<String> = Vec::new();
    let mut key = String::new();
    let mut value = String::new();
    let mut in_value = false;
    let mut depth_in_value = 0usize;
    let mut pending_key: Option<String> = None;
    for c in text.chars() {
        if in_value {
            match c {
                '(' | '[' => {
                    depth_in_value += 1;
                    value.push(c);
                }
                ')' | ']' if depth_in_value > 0 => {
                    depth_in_value -= 1;
                    value.push(c);
                }
                '{' if depth_in_value == 0 => {
                    // A nested struct: the key becomes a path prefix.
                    path.push(pending_key.take().unwrap_or_default());
                    in_value = false;
                    value.clear();
                }
                ',' | '}' if depth_in_value == 0 => {
                    if let Some(k) = pending_key.take() {
                        out.push((join(&path, &k), value.trim().to_string()));
                    }
                    value.clear();
                    in_value = false;
                    if c == '}' {
                        path.pop();
                    }
                }
                _ => value.push(c),
            }
            continue;
        }
        match c {
            ':' => {
                pending_key = Some(key.trim().to_string());
                key.clear();
                in_value = true;
            }
            '{' => key.clear(),
            '}' => {
                path.pop();
                key.clear();
            }
            ',' => key.clear(),
            _ => key.push(c),
        }
    }
    if let Some(k) = pending_key {
        if !value.trim().is_empty() {
            out.push((join(&path, &k), value.trim().to_string()));
        }
    }
    out
}

fn join(path: &[String], key: &str) -> String {
    let mut parts: Vec<&str> = path.iter().map(String::as_str).filter(|s| !s.is_empty()).collect();
    parts.push(key);
    parts.join(".")
}
