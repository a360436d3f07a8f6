//! The OMPL benchmark log writer against the grammar of OMPL's `saveResultsToStream` as read
//! by `ompl_benchmark_statistics.py` (`readBenchmarkLog`): the parser below mirrors the
//! script's reading logic line by line.

use std::collections::BTreeMap;

use opengrasp_bench::ompl::{self, RUN_PROPERTIES, STATUS_VALUES};
use opengrasp_bench::results::ResultsFile;
use opengrasp_bench::suite::{planar_scene, Suite};
use opengrasp_motion::benchmark::RunStatus;
use opengrasp_motion::planners::{Prm, PrmOptions, RrtConnect};

/// What `readBenchmarkLog` extracts from one log.
#[derive(Debug)]
struct Experiment {
    library: String,
    version: String,
    name: String,
    hostname: String,
    date: String,
    setup: String,
    cpuinfo: Option<String>,
    seed: String,
    time_limit: f64,
    memory_limit: f64,
    runs_per_planner: i64,
    total_time: f64,
    enums: BTreeMap<String, Vec<String>>,
    planners: Vec<Planner>,
}

#[derive(Debug)]
struct Planner {
    name: String,
    settings: String,
    properties: Vec<(String, String)>,
    runs: Vec<Vec<Option<f64>>>,
}

struct Lines<'a> {
    lines: Vec<&'a str>,
    pos: usize,
}

impl<'a> Lines<'a> {
    fn readline(&mut self) -> &'a str {
        let l = self.lines.get(self.pos).copied().unwrap_or("");
        self.pos += 1;
        l
    }
    /// `readLogValue`: token `index` of the next line if the expected tokens match, else
    /// the read is undone.
    fn read_value(&mut self, index: isize, expected: &[(isize, &str)]) -> Option<String> {
        let start = self.pos;
        let tokens: Vec<&str> = self.readline().split_whitespace().collect();
        let at =
            |i: isize| if i < 0 { tokens.get((tokens.len() as isize + i) as usize) } else { tokens.get(i as usize) };
        for (i, t) in expected {
            if at(*i) != Some(t) {
                self.pos = start;
                return None;
            }
        }
        at(index).map(|s| s.to_string())
    }
    fn required(&mut self, what: &str, index: isize, expected: &[(isize, &str)]) -> String {
        self.read_value(index, expected).unwrap_or_else(|| panic!("unable to read {what} at line {}", self.pos + 1))
    }
    fn multiline(&mut self, required: bool) -> Option<String> {
        let start = self.pos;
        if !self.readline().starts_with("<<<|") {
            assert!(!required, "expected <<<| at line {}", start + 1);
            self.pos = start;
            return None;
        }
        let mut value = String::new();
        loop {
            assert!(self.pos < self.lines.len(), "expected token |>>> missing");
            let l = self.readline();
            if l.starts_with("|>>>") {
                return Some(value);
            }
            value.push_str(l);
            value.push('\n');
        }
    }
}

/// Mirrors `readBenchmarkLog` (non-MoveIt format) and additionally asserts the grammar's
/// constraints the script relies on.
fn parse(text: &str) -> Experiment {
    assert!(text.ends_with('\n'));
    let mut f = Lines { lines: text.lines().collect(), pos: 0 };
    let library = f.read_value(0, &[(1, "version")]).unwrap_or_else(|| "OMPL".into());
    f.pos = 0;
    let version = f.read_value(-1, &[(1, "version")]).unwrap_or_else(|| "0.0.0".into());
    let name = f.required("experiment name", -1, &[(0, "Experiment")]);
    // optional experiment properties
    let n_props: usize = f.read_value(0, &[(-2, "experiment"), (-1, "properties")]).map_or(0, |s| s.parse().unwrap());
    for _ in 0..n_props {
        f.readline();
    }
    let hostname = f.required("hostname", -1, &[(0, "Running")]);
    let date_line = f.readline();
    assert!(date_line.starts_with("Starting"));
    let date = date_line.split_whitespace().skip(2).collect::<Vec<_>>().join(" ");
    let setup = f.multiline(true).unwrap();
    let cpuinfo = f.multiline(false);
    let seed = f.required("random seed", 0, &[(-2, "random"), (-1, "seed")]);
    let time_limit: f64 = f.required("time limit", 0, &[(-3, "seconds"), (-2, "per"), (-1, "run")]).parse().unwrap();
    let memory_limit: f64 = f.required("memory limit", 0, &[(-3, "MB"), (-2, "per"), (-1, "run")]).parse().unwrap();
    let runs_per_planner: i64 =
        f.read_value(0, &[(-3, "runs"), (-2, "per"), (-1, "planner")]).map_or(-1, |s| s.parse().unwrap());
    let total_time: f64 = f.required("total time", 0, &[(-3, "collect"), (-2, "the"), (-1, "data")]).parse().unwrap();
    let n_enums: usize = f.read_value(0, &[(-2, "enum")]).map_or(0, |s| s.parse().unwrap());
    let mut enums = BTreeMap::new();
    for _ in 0..n_enums {
        let e: Vec<&str> = f.readline().split('|').collect();
        enums.insert(e[0].to_string(), e[1..].iter().map(|s| s.to_string()).collect());
    }
    let n_planners: usize = f.required("planner count", 0, &[(-1, "planners")]).parse().unwrap();
    let mut planners = Vec::new();
    for _ in 0..n_planners {
        let name = f.readline().to_string();
        let n_common: usize = f.readline().split_whitespace().next().unwrap().parse().unwrap();
        let mut settings = String::new();
        for _ in 0..n_common {
            let l = f.readline();
            assert!(l.contains(" = "), "planner property {l:?} is not `name = value`");
            settings.push_str(l);
            settings.push(';');
        }
        let header = f.readline();
        assert!(header.ends_with(" properties for each run"), "{header}");
        let n_properties: usize = header.split_whitespace().next().unwrap().parse().unwrap();
        let mut properties = Vec::new();
        for _ in 0..n_properties {
            let field: Vec<&str> = f.readline().split_whitespace().collect();
            let ty = field.last().unwrap().to_string();
            assert!(["BOOLEAN", "INTEGER", "REAL", "ENUM"].contains(&ty.as_str()), "type {ty}");
            properties.push((field[..field.len() - 1].join("_"), ty));
        }
        let runs_line = f.readline();
        assert!(runs_line.ends_with(" runs"), "{runs_line}");
        let n_runs: usize = runs_line.split_whitespace().next().unwrap().parse().unwrap();
        let mut runs = Vec::new();
        for _ in 0..n_runs {
            // The script: `line.split('; ')[:-1]` (the newline is the last element).
            let line = format!("{}\n", f.readline());
            let parts: Vec<&str> = line.split("; ").collect();
            let values: Vec<Option<f64>> = parts[..parts.len() - 1]
                .iter()
                .map(|x| if x.is_empty() || *x == "nan" || *x == "inf" { None } else { Some(x.parse().unwrap()) })
                .collect();
            assert_eq!(values.len(), n_properties, "run row {line:?}");
            runs.push(values);
        }
        let next = f.readline().trim();
        assert_eq!(next, ".", "no progress properties are written, so the planner ends with `.`");
        planners.push(Planner { name, settings, properties, runs });
    }
    assert_eq!(f.pos, f.lines.len(), "trailing lines after the last planner");
    Experiment {
        library,
        version,
        name,
        hostname,
        date,
        setup,
        cpuinfo,
        seed,
        time_limit,
        memory_limit,
        runs_per_planner,
        total_time,
        enums,
        planners,
    }
}

fn tiny_results() -> ResultsFile {
    Suite::new()
        .motion_planner("default options", || Box::new(RrtConnect::default()))
        .motion_planner("nodes = 150", || Box::new(Prm::new(PrmOptions { nodes: 150, ..PrmOptions::default() })))
        .motion_scene(planar_scene())
        .runs(3)
        .seed(9)
        .run()
        .unwrap()
}

#[test]
fn log_follows_the_ompl_grammar() {
    let mut results = tiny_results();
    let motion = results.motion.as_mut().unwrap();
    // A timed-out run: missing values must be empty fields.
    let mut timeout = motion.runs[0].clone();
    timeout.run = 3;
    timeout.status = RunStatus::Timeout;
    timeout.message = Some("planning timed out".into());
    timeout.postprocessing_time = None;
    timeout.planned = None;
    timeout.processed = None;
    timeout.iterations = None;
    timeout.final_state = None;
    motion.runs.insert(3, timeout);
    let motion = results.motion.as_ref().unwrap();

    let logs = ompl::logs(motion, &results.provenance);
    assert_eq!(logs.len(), 1);
    assert_eq!(logs[0].0, "ompl_planar_post.log");
    let e = parse(&logs[0].1);

    assert_eq!(e.library, "OpenGRASP-rs");
    assert_eq!(e.version, env!("CARGO_PKG_VERSION"));
    assert_eq!(e.name, "planar_post");
    assert!(!e.hostname.is_empty());
    assert_eq!(e.date, results.provenance.started_at);
    assert!(e.setup.contains("scene planar post"));
    assert!(e.cpuinfo.as_deref().is_some_and(|c| c.contains("cores: ")));
    assert_eq!(e.seed, "9");
    assert_eq!(e.time_limit, 10.0);
    assert_eq!(e.memory_limit, -1.0);
    assert_eq!(e.runs_per_planner, 3);
    assert!((e.total_time - results.provenance.wall_seconds).abs() < 1e-9);
    assert_eq!(e.enums.len(), 1);
    assert_eq!(e.enums["status"], STATUS_VALUES.map(String::from).to_vec());

    assert_eq!(e.planners.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(), vec!["RRT-Connect", "PRM"]);
    let expected: Vec<(String, String)> = RUN_PROPERTIES
        .iter()
        .chain(std::iter::once(&("time", "REAL")))
        .map(|(n, t)| (n.replace(' ', "_"), t.to_string()))
        .collect();
    for p in &e.planners {
        assert_eq!(p.properties, expected);
        // Property names are sorted, as OMPL sorts them.
        let names: Vec<&String> = p.properties.iter().map(|(n, _)| n).collect();
        assert!(names.windows(2).all(|w| w[0] < w[1]), "{names:?}");
    }
    let rrt = &e.planners[0];
    assert_eq!(rrt.settings, "parameters = default options;");
    assert_eq!(rrt.runs.len(), 4);
    assert_eq!(e.planners[1].runs.len(), 3);

    let col = |name: &str| expected.iter().position(|(n, _)| n == name).unwrap();
    let records: Vec<_> = motion.runs.iter().filter(|r| r.planner == "RRT-Connect").collect();
    for (row, r) in rrt.runs.iter().zip(&records) {
        assert_eq!(row[col("time")], Some(r.planning_time));
        assert_eq!(row[col("setup_time")], Some(r.setup_time));
        assert_eq!(row[col("run")], Some(r.run as f64));
        assert_eq!(row[col("seed")], Some(r.seed as f64));
        assert_eq!(row[col("collision_checks")], Some(r.planning_checks as f64));
        assert_eq!(row[col("approximate_solution")], Some(0.0));
        let solved = r.status == RunStatus::Solved;
        assert_eq!(row[col("solved")], Some(if solved { 1.0 } else { 0.0 }));
        assert_eq!(row[col("status")], Some(if solved { 6.0 } else { 4.0 }));
        assert_eq!(
            STATUS_VALUES[row[col("status")].unwrap() as usize],
            if solved { "Exact solution" } else { "Timeout" }
        );
        match (&r.planned, &r.processed) {
            (Some(p), Some(q)) => {
                assert_eq!(row[col("solution_length")], Some(p.metrics.length));
                assert_eq!(row[col("simplified_solution_length")], Some(q.metrics.length));
                assert_eq!(row[col("solution_clearance")], p.metrics.clearance_mean);
                assert_eq!(row[col("simplified_solution_smoothness")], Some(q.metrics.smoothness));
                assert_eq!(row[col("solution_segments")], Some((p.metrics.waypoints - 1) as f64));
                assert_eq!(row[col("correct_solution")], Some(f64::from(u8::from(p.validity.discrete))));
                assert_eq!(
                    row[col("simplified_correct_solution_strict")],
                    Some(f64::from(u8::from(q.validity.strict)))
                );
                assert_eq!(row[col("simplification_time")], r.postprocessing_time);
                assert_eq!(row[col("iterations")], r.iterations.map(|i| i as f64));
            }
            _ => {
                for c in [
                    "solution_length",
                    "simplified_solution_length",
                    "simplification_time",
                    "iterations",
                    "correct_solution",
                ] {
                    assert_eq!(row[col(c)], None, "{c} of a failed run");
                }
            }
        }
        // Not measured on this scene (no tip link, no pose goal).
        assert_eq!(row[col("solution_ee_length")], None);
        assert_eq!(row[col("ik_position_error")], None);
    }
}

#[test]
fn log_values_never_break_the_line_format() {
    let mut results = tiny_results();
    let motion = results.motion.as_mut().unwrap();
    // Planner parameters with the run separator and newlines stay on one line.
    motion.planners[0].parameters = "a; b\nc".into();
    let log = ompl::write_log(motion, "planar post", &results.provenance);
    let e = parse(&log);
    assert_eq!(e.planners[0].settings, "parameters = a, b c;");
    // A scene without runs gives no log; an unknown scene an experiment without planners.
    let empty = ompl::write_log(motion, "elsewhere", &results.provenance);
    assert_eq!(parse(&empty).planners.len(), 0);
}

/// OMPL's own reader (`ompl_benchmark_statistics.py` from the `ompl` wheel, vendored under
/// `tests/data/ompl`) loads the logs into its SQLite database with the values we recorded.
#[test]
fn ompl_benchmark_statistics_loads_the_logs() {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    if std::process::Command::new(&python).arg("--version").output().is_err() {
        eprintln!("skipped: {python} not found (set PYTHON to a Python 3 interpreter)");
        return;
    }
    let results = tiny_results();
    let motion = results.motion.as_ref().unwrap();
    let dir = std::env::temp_dir().join(format!("opengrasp-ompl-stats-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut logs = Vec::new();
    for (name, text) in ompl::logs(motion, &results.provenance) {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        logs.push(path);
    }
    let db = dir.join("benchmark.db");
    let scripts = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ompl");
    let out = std::process::Command::new(&python)
        .arg(scripts.join("ompl_benchmark_statistics.py"))
        .args(&logs)
        .arg("-d")
        .arg(&db)
        .env("PYTHONPATH", &scripts)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));

    let conn = rusqlite::Connection::open(&db).unwrap();
    let experiment: (String, f64, i64) = conn
        .query_row("SELECT name, timelimit, runcount FROM experiments", [], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
        .unwrap();
    assert_eq!(experiment, ("planar_post".to_string(), 10.0, 3));
    let planners: Vec<String> = conn
        .prepare("SELECT name FROM plannerConfigs ORDER BY id")
        .unwrap()
        .query_map([], |r| r.get(0))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(planners, ["RRT-Connect", "PRM"]);
    // Every run, with its planning time, seed and post-processed length as recorded.
    let mut stmt = conn
        .prepare(
            "SELECT p.name, r.run, r.seed, r.time, r.solved, r.simplified_solution_length, r.collision_checks
             FROM runs r JOIN plannerConfigs p ON r.plannerid = p.id ORDER BY r.id",
        )
        .unwrap();
    type Row = (String, i64, i64, f64, i64, Option<f64>, Option<i64>);
    let rows: Vec<Row> = stmt
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?, r.get(5)?, r.get(6)?)))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(rows.len(), motion.runs.len());
    for (row, run) in rows.iter().zip(&motion.runs) {
        assert_eq!((row.0.as_str(), row.1, row.2), (run.planner.as_str(), run.run as i64, run.seed as i64));
        assert!((row.3 - run.planning_time).abs() <= 1e-9 * run.planning_time.max(1.0), "{row:?}");
        assert_eq!(row.4, i64::from(run.status == RunStatus::Solved));
        let length = run.processed.as_ref().map(|p| p.metrics.length);
        assert!(row.5.zip(length).is_some_and(|(a, b)| (a - b).abs() < 1e-9), "{row:?} vs {length:?}");
        assert_eq!(row.6, Some(run.planning_checks as i64));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
