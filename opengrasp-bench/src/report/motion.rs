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
    let cont = |solved: usize, v: Option<f64>| v.filter(|_| solved > 0).map_or("-".into(), |v| format!("{v:.1}"));
    let (mut time_rows, mut validity_rows, mut path_rows) = (Vec::new(), Vec::new(), Vec::new());
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
        validity_rows.push(vec![
            label.clone(),
            pct_or_dash(s.solved, s.valid_planned.discrete),
            pct_or_dash(s.solved, s.valid_processed.discrete),
            pct_or_dash(s.solved, s.valid_planned.strict),
            pct_or_dash(s.solved, s.valid_processed.strict),
            cont(s.solved, s.valid_planned.continuous),
            cont(s.solved, s.valid_processed.continuous),
        ]);
        path_rows.push(vec![
            label,
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
        let dash = || "-".to_string();
        let ms = |v: f64| format!("{:.2}", v * 1e3);
        time_rows.push(vec![label.clone(), dash(), dash(), ms(t.setup), ms(t.planning), dash(), ms(t.postprocessing)]);
        let pct = |v: f64| format!("{v:.1}");
        validity_rows.push(vec![
            label.clone(),
            dash(),
            dash(),
            pct(t.valid_planned),
            pct(t.valid_processed),
            dash(),
            dash(),
        ]);
        path_rows.push(vec![
            label,
            format!("{:.3}", t.length_planned),
            format!("{:.3}", t.length_processed),
            dash(),
            dash(),
            format!("{:.1}", t.clearance_planned),
            format!("{:.1}", t.clearance_processed),
        ]);
    }
    let protocol = format!("Protocol: {}.", m.options.protocol.description());
    let paper_row = with_paper.then(|| {
        format!("The row '{PAPER_SCENE_1} / paper' is the OpenGRASP paper's Table III (its reference planner).")
    });
    let with_notes = |mut legend: Vec<String>| {
        legend.push(protocol.clone());
        legend.extend(paper_row.clone());
        legend
    };
    let table3_time = Table {
        title: "Table III: motion planners, times (means over runs)".into(),
        headers: strings(&[
            "scene / planner",
            "runs",
            "success %",
            "setup [ms]",
            "plan [ms]",
            "plan p50 [ms]",
            "post [ms]",
        ]),
        rows: time_rows,
        legend: with_notes(vec![
            "success %: runs that found a path; plan: planning time (p50: median); setup: the planner's setup (e.g. a \
             PRM roadmap; under the paper protocol also loading the scene); post: post-processing (repair, \
             shortcutting, certification)."
                .into(),
        ]),
    };
    let table3_validity = Table {
        title: "Table III: motion planners, valid paths (% of solved runs)".into(),
        headers: strings(&[
            "scene / planner",
            "valid P %",
            "valid PP %",
            "strict P %",
            "strict PP %",
            "cont. P %",
            "cont. PP %",
        ]),
        rows: validity_rows,
        legend: with_notes(vec![format!(
            "P: planned path, PP: post-processed path. valid: discrete check at the planning step ({}); strict: at the \
             fine step ({}); cont.: certified continuous check (conservative advancement), where the checker \
             supports it; -: no data. The paper's 'Valid' is its fine re-check (the strict columns).",
            m.options.validation.step, m.options.validation.strict_step
        )]),
    };
    let table3_paths = Table {
        title: "Table III: motion planners, paths (means over solved runs)".into(),
        headers: strings(&[
            "scene / planner",
            "length P",
            "length PP",
            "EE P [m]",
            "EE PP [m]",
            "clear. P [mm]",
            "clear. PP [mm]",
        ]),
        rows: path_rows,
        legend: with_notes(vec![
            "length: C-space path length (rad for revolute joints); EE: end-effector path length; clear.: mean \
             distance to obstacles along the path."
                .into(),
        ]),
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
        rows.push(stat_row("plan [ms]", &s.planning_time, 1e3, 2));
        rows.push(stat_row("post [ms]", &s.postprocessing_time, 1e3, 2));
        rows.push(stat_row("length PP", &s.length_processed, 1.0, 3));
    }
    let percentiles = Table {
        title: "Motion planners: percentiles".into(),
        headers,
        rows,
        legend: vec!["n: runs with a value (solved runs for path metrics); p25, p75, p95: percentiles.".into()],
    };
    let mut tables = vec![table3_time, table3_validity, table3_paths, percentiles];
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
