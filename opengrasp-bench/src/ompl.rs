//! Motion results in OMPL's benchmark log format, for `ompl_benchmark_statistics.py` and
//! Planner Arena.
//!
//! The tests load the logs with OMPL's own reader (`ompl_benchmark_statistics.py` of the `ompl`
//! 2.0.1 wheel, vendored in `tests/data/ompl`) and compare the database it builds with the
//! recorded runs.
//!
//! OMPL logs one experiment (one planning problem) per file, so [`write_log`] writes one scene
//! of a [`MotionSection`]; [`logs`] gives one log per scene. The grammar follows OMPL's
//! `Benchmark::saveResultsToStream` (OMPL 1.x):
//!
//! ```text
//! OpenGRASP-rs version 0.1.0            <- "<library> version <v>" (the script reads both)
//! Experiment <scene name, spaces as _>
//! Running on <host>
//! Starting at <UTC ISO-8601 date>
//! <<<|
//! <setup: suite version, scene, benchmark options>
//! |>>>
//! <<<|
//! <cpu info: model, cores, os>
//! |>>>
//! <seed> is the random seed
//! <time limit> seconds per run
//! -1 MB per run                         <- no memory limit
//! <runs> runs per planner
//! <wall time> seconds spent to collect the data
//! 1 enum type
//! status|Unknown status|Invalid start|...|Infeasible
//! <P> planners
//! <planner name>
//! 1 common properties
//! parameters = <the planner's parameters>
//! <m> properties for each run
//! <name> <BOOLEAN|INTEGER|REAL|ENUM>    <- sorted by name, see RUN_PROPERTIES
//! <n> runs
//! v1; v2; ...; vm;                      <- one line per run, "" for missing values
//! .
//! ```
//!
//! Run properties use OMPL's names where the meaning is the same (`time` = planning time,
//! `solved`, `status`, `solution length`, `simplified solution length`, `simplification time`,
//! `correct solution`, ...); the `status` enum is OMPL's `PlannerStatus` (solved runs are
//! "Exact solution", timeouts "Timeout", invalid queries "Invalid start"/"Invalid goal",
//! other failures "Unknown status").

use std::fmt::Write as _;

use opengrasp_motion::benchmark::{PathReport, RunRecord, RunStatus};

use crate::results::{MotionSection, Provenance, SUITE_VERSION};

/// OMPL's `PlannerStatus` strings, in enum order (the `status` enum of the log).
pub const STATUS_VALUES: [&str; 10] = [
    "Unknown status",
    "Invalid start",
    "Invalid goal",
    "Unrecognized goal type",
    "Timeout",
    "Approximate solution",
    "Exact solution",
    "Crash",
    "Abort",
    "Infeasible",
];

/// The per-run properties written for every planner: `(name, OMPL type)`, sorted by name as
/// OMPL sorts them.
pub const RUN_PROPERTIES: [(&str, &str); 26] = [
    ("approximate solution", "BOOLEAN"),
    ("collision checks", "INTEGER"),
    ("correct solution", "BOOLEAN"),
    ("correct solution continuous", "BOOLEAN"),
    ("correct solution strict", "BOOLEAN"),
    ("ik position error", "REAL"),
    ("iterations", "INTEGER"),
    ("run", "INTEGER"),
    ("seed", "INTEGER"),
    ("setup time", "REAL"),
    ("simplification time", "REAL"),
    ("simplified correct solution", "BOOLEAN"),
    ("simplified correct solution continuous", "BOOLEAN"),
    ("simplified correct solution strict", "BOOLEAN"),
    ("simplified solution clearance", "REAL"),
    ("simplified solution ee length", "REAL"),
    ("simplified solution length", "REAL"),
    ("simplified solution segments", "INTEGER"),
    ("simplified solution smoothness", "REAL"),
    ("solution clearance", "REAL"),
    ("solution ee length", "REAL"),
    ("solution length", "REAL"),
    ("solution segments", "INTEGER"),
    ("solution smoothness", "REAL"),
    ("solved", "BOOLEAN"),
    ("status", "ENUM"),
];

/// The `time REAL` property (planning time) is written too; it sorts last.
const TIME_PROPERTY: (&str, &str) = ("time", "REAL");

/// The OMPL `status` enum value of a run.
pub fn status_value(record: &RunRecord) -> usize {
    match record.status {
        RunStatus::Solved => 6,
        RunStatus::Timeout => 4,
        RunStatus::InvalidInput => {
            if record.message.as_deref().is_some_and(|m| m.contains("goal")) {
                2
            } else {
                1
            }
        }
        RunStatus::Error => 0,
    }
}

fn real(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x}"),
        Some(x) if x.is_nan() => "nan".into(),
        Some(_) => "inf".into(),
        None => String::new(),
    }
}

fn boolean(v: Option<bool>) -> String {
    v.map_or_else(String::new, |b| if b { "1".into() } else { "0".into() })
}

fn int(v: Option<u64>) -> String {
    v.map_or_else(String::new, |x| x.to_string())
}

fn path_values(p: Option<&PathReport>) -> [String; 8] {
    [
        boolean(p.map(|p| p.validity.discrete)),
        boolean(p.and_then(|p| p.validity.continuous)),
        boolean(p.map(|p| p.validity.strict)),
        real(p.and_then(|p| p.metrics.clearance_mean)),
        real(p.and_then(|p| p.metrics.ee_length)),
        real(p.map(|p| p.metrics.length)),
        int(p.map(|p| p.metrics.waypoints.saturating_sub(1) as u64)),
        real(p.map(|p| p.metrics.smoothness)),
    ]
}

/// The values of one run in the order of [`RUN_PROPERTIES`] followed by `time`.
pub fn run_values(r: &RunRecord) -> Vec<String> {
    let solved = r.status == RunStatus::Solved;
    let planned = path_values(r.planned.as_ref());
    let processed = path_values(r.processed.as_ref());
    let mut v = vec![
        boolean(Some(false)),
        int(Some(r.planning_checks)),
        planned[0].clone(),
        planned[1].clone(),
        planned[2].clone(),
        real(r.ik_position_error),
        int(r.iterations),
        int(Some(r.run as u64)),
        int(Some(r.seed)),
        real(Some(r.setup_time)),
        real(r.postprocessing_time),
        processed[0].clone(),
        processed[1].clone(),
        processed[2].clone(),
    ];
    // simplified solution clearance, ee length, length, segments, smoothness
    v.extend(processed[3..].iter().cloned());
    // solution clearance, ee length, length, segments, smoothness
    v.extend(planned[3..].iter().cloned());
    v.push(boolean(Some(solved)));
    v.push(status_value(r).to_string());
    v.push(real(Some(r.planning_time)));
    v
}

/// Host name (`/etc/hostname`, then `$HOSTNAME`), whitespace-free; `UNKNOWN` if unavailable.
pub fn hostname() -> String {
    std::fs::read_to_string("/etc/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|h| h.split_whitespace().collect::<Vec<_>>().join("_"))
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "UNKNOWN".into())
}

/// Replaces whitespace and `;` (OMPL's field separator) so a value fits one log token.
fn token(s: &str) -> String {
    let t: String = s.chars().map(|c| if c.is_whitespace() || c == ';' { '_' } else { c }).collect();
    if t.is_empty() {
        "NO_NAME".into()
    } else {
        t
    }
}

/// One line of text: newlines become spaces, `; ` becomes `, `.
fn line(s: &str) -> String {
    s.replace(['\n', '\r'], " ").replace("; ", ", ")
}

/// Writes the OMPL benchmark log of one scene of `motion` (see the [module docs](self)).
/// Planners appear in the order of `motion.planners` if they have runs on the scene.
pub fn write_log(motion: &MotionSection, scene: &str, provenance: &Provenance) -> String {
    let mut out = String::new();
    let o = &motion.options;
    let _ = writeln!(out, "OpenGRASP-rs version {}", token(&provenance.opengrasp_version));
    let _ = writeln!(out, "Experiment {}", token(scene));
    let _ = writeln!(out, "Running on {}", hostname());
    let _ = writeln!(out, "Starting at {}", provenance.started_at);
    let _ = writeln!(out, "<<<|");
    let _ = writeln!(out, "suite {SUITE_VERSION} ({})", provenance.suite_size);
    let _ = writeln!(out, "scene {scene}");
    let _ = writeln!(out, "git commit {}", provenance.git_commit.as_deref().unwrap_or("unknown"));
    let _ = writeln!(out, "options {}", line(&format!("{o:?}")));
    let _ = writeln!(out, "|>>>");
    let _ = writeln!(out, "<<<|");
    let _ = writeln!(out, "model name: {}", provenance.cpu_model.as_deref().unwrap_or("unknown"));
    let _ = writeln!(out, "cores: {}", provenance.cpu_cores);
    let _ = writeln!(out, "os: {} {}", provenance.os, provenance.arch);
    let _ = writeln!(out, "|>>>");
    let _ = writeln!(out, "{} is the random seed", o.seed);
    let _ = writeln!(out, "{} seconds per run", o.time_limit.as_secs_f64());
    let _ = writeln!(out, "-1 MB per run");
    let _ = writeln!(out, "{} runs per planner", o.runs);
    let _ = writeln!(out, "{} seconds spent to collect the data", provenance.wall_seconds);
    let _ = writeln!(out, "1 enum type");
    let _ = writeln!(out, "status|{}", STATUS_VALUES.join("|"));
    let planners: Vec<_> = motion
        .planners
        .iter()
        .filter(|p| motion.runs.iter().any(|r| r.scene == scene && r.planner == p.name))
        .collect();
    let _ = writeln!(out, "{} planners", planners.len());
    for p in planners {
        let runs: Vec<&RunRecord> = motion.runs.iter().filter(|r| r.scene == scene && r.planner == p.name).collect();
        let _ = writeln!(out, "{}", line(&p.name));
        let _ = writeln!(out, "1 common properties");
        let _ = writeln!(out, "parameters = {}", line(&p.parameters));
        let _ = writeln!(out, "{} properties for each run", RUN_PROPERTIES.len() + 1);
        for (name, ty) in RUN_PROPERTIES.iter().chain(std::iter::once(&TIME_PROPERTY)) {
            let _ = writeln!(out, "{name} {ty}");
        }
        let _ = writeln!(out, "{} runs", runs.len());
        for r in runs {
            for v in run_values(r) {
                let _ = write!(out, "{v}; ");
            }
            out.push('\n');
        }
        out.push_str(".\n");
    }
    out
}

/// One OMPL log per scene of `motion`: `(file name, log text)` with file names
/// `ompl_<scene>.log` (scene name with non-alphanumeric characters as `_`).
pub fn logs(motion: &MotionSection, provenance: &Provenance) -> Vec<(String, String)> {
    let mut scenes: Vec<&str> = motion.scenes.iter().map(String::as_str).collect();
    for r in &motion.runs {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    scenes
        .into_iter()
        .filter(|s| motion.runs.iter().any(|r| r.scene == *s))
        .map(|s| {
            let file: String = s.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
            (format!("ompl_{file}.log"), write_log(motion, s, provenance))
        })
        .collect()
}
