//! Table III and the motion percentiles and episodes.

use opengrasp_motion::metrics::Stats;

use super::{opt, Table};
use crate::paper::{PAPER_SCENE_1, PAPER_TABLE_III};
use crate::results::{motion_summaries, MotionSection};

/// Table III and the percentile table (see the [module docs](super)).
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
            s.valid_processed.continuous.filter(|_| s.solved > 0).map_or("-".into(), |v| format!("{v:.1}")),
            opt(s.length_planned.mean, 1.0, 3),
            opt(s.length_processed.mean, 1.0, 3),
            opt(s.ee_length_planned.mean, 1.0, 3),
            opt(s.ee_length_processed.mean, 1.0, 3),
            opt(s.clearance_planned.mean, 1e3, 1),
            opt(s.clearance_processed.mean, 1e3, 1),
        ]);
    }
    // The paper's Table III beside its scene (scene 1), when that scene ran.
    let with_paper = summaries.iter().any(|s| s.scene == PAPER_SCENE_1);
    if with_paper {
        let t = &PAPER_TABLE_III;
        let label = format!("{PAPER_SCENE_1} / paper");
        time_rows.push(vec![
            label.clone(),
            "-".into(),
            "-".into(),
            format!("{:.2}", t.setup * 1e3),
            format!("{:.2}", t.planning * 1e3),
            "-".into(),
            format!("{:.2}", t.postprocessing * 1e3),
        ]);
        quality_rows.push(vec![
            label,
            "-".into(),
            "-".into(),
            format!("{:.1}", t.valid_planned),
            format!("{:.1}", t.valid_processed),
            "-".into(),
            format!("{:.3}", t.length_planned),
            format!("{:.3}", t.length_processed),
            "-".into(),
            "-".into(),
            format!("{:.1}", t.clearance_planned),
            format!("{:.1}", t.clearance_processed),
        ]);
    }
    let protocol = format!("Protocol: {}.", m.options.protocol.description());
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
        legend: vec![
            "success %: runs that found a path; times are means over runs (p50: median planning time).".into(),
            "setup: the planner's setup (e.g. a PRM roadmap; under the paper protocol also loading the scene); \
             post-proc.: repair, shortcutting and certification of the path."
                .into(),
            protocol.clone(),
        ]
        .into_iter()
        .chain(with_paper.then(|| {
            format!("The row '{PAPER_SCENE_1} / paper' is the OpenGRASP paper's Table III (its reference planner).")
        }))
        .collect(),
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
            "cont. PP %",
            "length P",
            "length PP",
            "EE length P [m]",
            "EE length PP [m]",
            "clearance P [mm]",
            "clearance PP [mm]",
        ]),
        rows: quality_rows,
        legend: vec![
            "P: planned path, PP: post-processed path; % of solved runs.".into(),
            format!(
                "valid: discrete check at the planning step ({}); strict: at the fine step ({}); cont.: certified \
                 continuous check (conservative advancement), where the checker supports it.",
                m.options.validation.step, m.options.validation.strict_step
            ),
            "length: C-space path length (rad for revolute joints); EE length: end-effector path (m); clearance: \
             mean distance to obstacles along the path (mm). The paper's 'Valid' is its fine re-check (strict column)."
                .into(),
            protocol,
        ],
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
    let percentiles = Table {
        title: "Motion planners: percentiles".into(),
        headers,
        rows,
        legend: vec!["n: runs with a value (solved runs for path metrics); p25, p75, p95: percentiles.".into()],
    };
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
    Table {
        title: "Scene 3, Clean the Table: episodes (sums over the grasp and place queries)".into(),
        headers,
        rows,
        legend: vec![
            "cleaned: objects placed on the sideboard of those on the table; PP: post-processed; all valid: every \
             post-processed path passed every validator."
                .into(),
        ],
    }
}
