//! The motion-planning benchmark: N seeded runs per planner per scene, graded identically.
//!
//! For every run the harness generates the scene instance from the run's seed, calls the
//! planner's [`MotionPlanner::plan`] (timed as planning; `setup` is timed separately, once per
//! scene when the environment is shared across runs, otherwise once per run), checks that the
//! path starts at the start and ends at a goal, post-processes it (timed): segments rejected by
//! a validator are repaired ([`crate::smoothing::repair`]) and the path is shortcut
//! ([`crate::smoothing::shortcut`]), and grades both paths with the same validators
//! ([`crate::validate::validate_path`]) and metrics ([`crate::metrics::path_metrics`]).
//! Collision checks are counted by wrapping the scene's checker in a
//! [`CountingChecker`].

use std::fmt::Write as _;
use std::sync::Arc;
use std::time::{Duration, Instant};

use opengrasp_core::model::{JointGroup, LinkId, Robot};
use serde::{Deserialize, Serialize};

use crate::certify::SegmentCertifier;
use crate::error::{MotionError, Result};
use crate::metrics::{path_metrics, PathMetrics, Stats};
use crate::problem::{Goal, MotionPlanner, PlanningProblem, SetupContext};
use crate::protocol::Protocol;
use crate::smoothing::{repair_with, shortcut_with, ShortcutOptions};
use crate::validate::{distance, validate_path, PathValidity, ValidationOptions};
use crate::validity::{CountingChecker, StateValidityChecker};

/// One concrete planning query of a scene.
pub struct SceneInstance {
    /// The robot.
    pub robot: Arc<Robot>,
    /// The planning group.
    pub group: JointGroup,
    /// Full configuration holding the joints outside the group.
    pub q_full: Vec<f64>,
    /// End-effector link for the workspace path length (`None`: not measured).
    pub tip: Option<LinkId>,
    /// Start configuration (group values).
    pub start: Vec<f64>,
    /// The goal.
    pub goal: Goal,
    /// The validity checker: the judge of every path (validators, metrics, post-processing)
    /// and, unless `planning_checker` is set, the planner's checker too.
    pub checker: Box<dyn StateValidityChecker>,
    /// A different checker for the planner (setup and planning), e.g. a conservative sphere
    /// model of the robot; `None` (the usual case): the planner uses `checker`. Planned paths
    /// are still graded by `checker`.
    pub planning_checker: Option<Box<dyn StateValidityChecker>>,
    /// Proves post-processing's shortcuts free on a conservative model so that the exact
    /// checks run only where it cannot ([`crate::smoothing::shortcut_with`]); the
    /// post-processed paths are the same with or without it. `None`: exact checks only.
    pub certifier: Option<Box<dyn SegmentCertifier>>,
}

impl SceneInstance {
    /// The checker the planner uses: `planning_checker` if set, else `checker`.
    pub fn planner_checker(&self) -> &dyn StateValidityChecker {
        self.planning_checker.as_deref().unwrap_or(&*self.checker)
    }

    /// The planning query of this instance, validated by `checker` (the instance's own
    /// `&*self.checker`, or a wrapper around it such as a counting checker).
    pub fn problem<'a>(
        &'a self,
        checker: &'a dyn StateValidityChecker,
        time_limit: Duration,
        seed: u64,
        step: f64,
    ) -> PlanningProblem<'a> {
        PlanningProblem {
            robot: &self.robot,
            group: &self.group,
            q_full: &self.q_full,
            start: &self.start,
            goal: &self.goal,
            checker,
            time_limit,
            seed,
            step,
        }
    }
}

/// A benchmark scene: a generator of instances from a run seed.
pub struct BenchmarkScene {
    /// Name in reports.
    pub name: String,
    /// True if every instance has the same environment (then `setup` runs once per planner on
    /// the instance of the benchmark's base seed and its roadmaps are reused by all runs).
    pub shared_environment: bool,
    /// Builds the instance of a run from its seed.
    #[allow(clippy::type_complexity)]
    pub generate: Box<dyn Fn(u64) -> Result<SceneInstance> + Send + Sync>,
}

/// Options of [`run_benchmark`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchmarkOptions {
    /// Runs per planner per scene (default 20).
    pub runs: usize,
    /// Seed of run 0; run `r` uses `seed + r` for the scene and the planner (default 0).
    pub seed: u64,
    /// Planning time limit per run (default 10 s).
    pub time_limit: Duration,
    /// Validator steps (defaults of [`ValidationOptions`]: 0.02 planning step, 0.002 strict);
    /// `validation.step` is also the planners' discrete step.
    pub validation: ValidationOptions,
    /// Shortcut options (defaults of [`ShortcutOptions`]; the seed is replaced by the run's).
    pub shortcut: ShortcutOptions,
    /// Step at which paths are densified for clearance and end-effector length (default 0.02).
    pub metrics_step: f64,
    /// The protocol these options follow ([`Protocol::apply`] sets the steps and checks); with
    /// [`Protocol::Paper`] setup time also counts generating the scene instance (default
    /// [`Protocol::Certified`]).
    #[serde(default)]
    pub protocol: Protocol,
}

impl Default for BenchmarkOptions {
    fn default() -> Self {
        Self {
            runs: 20,
            seed: 0,
            time_limit: Duration::from_secs(10),
            validation: ValidationOptions::default(),
            shortcut: ShortcutOptions::default(),
            metrics_step: crate::validate::DEFAULT_STEP,
            protocol: Protocol::Certified,
        }
    }
}

/// Outcome of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// A path was found (and starts at the start and ends at a goal).
    Solved,
    /// The planner hit its time limit.
    Timeout,
    /// The query was rejected as invalid (bad dimensions, start or goal in collision, ...).
    InvalidInput,
    /// The planner failed otherwise, or returned a path with wrong end points.
    Error,
}

/// A graded path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathReport {
    /// Validator verdicts.
    pub validity: PathValidity,
    /// Metrics.
    pub metrics: PathMetrics,
}

/// Everything recorded about one run (like a row of OMPL's benchmark database).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Planner name.
    pub planner: String,
    /// Scene name.
    pub scene: String,
    /// Run index.
    pub run: usize,
    /// Seed of the run.
    pub seed: u64,
    /// Outcome.
    pub status: RunStatus,
    /// Error message for failed runs.
    pub message: Option<String>,
    /// Setup time of the planner for this run's scene (s; shared across runs when the
    /// environment is shared).
    pub setup_time: f64,
    /// Planning time (s).
    pub planning_time: f64,
    /// Post-processing (shortcut) time (s), for solved runs.
    pub postprocessing_time: Option<f64>,
    /// Validity checks during planning.
    pub planning_checks: u64,
    /// Validity checks during post-processing.
    pub postprocessing_checks: u64,
    /// Planner iterations.
    pub iterations: Option<u64>,
    /// Shortcuts accepted.
    pub shortcuts: Option<usize>,
    /// Planned segments rejected by a validator and replaced by a valid detour.
    pub repaired_segments: Option<usize>,
    /// Planned segments rejected by a validator that could not be repaired.
    pub unrepaired_segments: Option<usize>,
    /// The planned path, graded.
    pub planned: Option<PathReport>,
    /// The post-processed path, graded.
    pub processed: Option<PathReport>,
    /// Final configuration of the post-processed path (group values).
    pub final_state: Option<Vec<f64>>,
    /// For pose goals: position error of the final state's tip (m).
    pub ik_position_error: Option<f64>,
    /// For pose goals: orientation error of the final state's tip (rad).
    pub ik_orientation_error: Option<f64>,
}

impl RunRecord {
    /// A run that ended with `status` before producing a path: every figure after setup empty.
    pub fn unfinished(planner: &str, scene: &str, run: usize, seed: u64, status: RunStatus, setup_time: f64) -> Self {
        Self {
            planner: planner.to_string(),
            scene: scene.to_string(),
            run,
            seed,
            status,
            message: None,
            setup_time,
            planning_time: 0.0,
            postprocessing_time: None,
            planning_checks: 0,
            postprocessing_checks: 0,
            iterations: None,
            shortcuts: None,
            repaired_segments: None,
            unrepaired_segments: None,
            planned: None,
            processed: None,
            final_state: None,
            ik_position_error: None,
            ik_orientation_error: None,
        }
    }

    /// Validity checks per second of planning.
    pub fn checks_per_second(&self) -> Option<f64> {
        (self.planning_time > 0.0).then(|| self.planning_checks as f64 / self.planning_time)
    }
}

/// Percentages of solved runs whose paths pass each validator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ValidityRates {
    /// Discrete check at the planning step (%).
    pub discrete: f64,
    /// Strict discrete check (%).
    pub strict: f64,
    /// Continuous check (% of runs where it was available; `None` if never available).
    pub continuous: Option<f64>,
}

fn rates<'a>(reports: impl Iterator<Item = &'a PathReport>) -> ValidityRates {
    let v: Vec<&PathValidity> = reports.map(|r| &r.validity).collect();
    let pct = |n: usize, d: usize| if d == 0 { 0.0 } else { 100.0 * n as f64 / d as f64 };
    let cont: Vec<bool> = v.iter().filter_map(|x| x.continuous).collect();
    ValidityRates {
        discrete: pct(v.iter().filter(|x| x.discrete).count(), v.len()),
        strict: pct(v.iter().filter(|x| x.strict).count(), v.len()),
        continuous: (!cont.is_empty()).then(|| pct(cont.iter().filter(|&&c| c).count(), cont.len())),
    }
}

/// Aggregates of one planner on one scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Planner name.
    pub planner: String,
    /// Scene name.
    pub scene: String,
    /// Runs.
    pub runs: usize,
    /// Solved runs.
    pub solved: usize,
    /// Timeouts.
    pub timeouts: usize,
    /// Invalid-input runs.
    pub invalid_input: usize,
    /// Other errors.
    pub errors: usize,
    /// Solved / runs (%).
    pub success_rate: f64,
    /// Setup time (s).
    pub setup_time: Stats,
    /// Planning time of all runs (s).
    pub planning_time: Stats,
    /// Post-processing time (s).
    pub postprocessing_time: Stats,
    /// Validity of planned paths.
    pub valid_planned: ValidityRates,
    /// Validity of post-processed paths.
    pub valid_processed: ValidityRates,
    /// C-space length of planned paths.
    pub length_planned: Stats,
    /// C-space length of post-processed paths.
    pub length_processed: Stats,
    /// End-effector length of planned paths (m).
    pub ee_length_planned: Stats,
    /// End-effector length of post-processed paths (m).
    pub ee_length_processed: Stats,
    /// Mean clearance of planned paths (m).
    pub clearance_planned: Stats,
    /// Mean clearance of post-processed paths (m).
    pub clearance_processed: Stats,
    /// Minimum clearance of post-processed paths (m).
    pub min_clearance_processed: Stats,
    /// Smoothness of planned paths.
    pub smoothness_planned: Stats,
    /// Smoothness of post-processed paths.
    pub smoothness_processed: Stats,
    /// Validity checks during planning.
    pub planning_checks: Stats,
    /// Validity checks per second of planning.
    pub checks_per_second: Stats,
    /// IK position error of the final state (m), pose goals only.
    pub ik_position_error: Stats,
    /// Runs whose post-processing repaired at least one planned segment.
    pub repaired_runs: usize,
    /// Runs with a planned segment post-processing could not repair.
    pub unrepaired_runs: usize,
}

impl Summary {
    /// Aggregates the records of one planner on one scene.
    pub fn from_records(planner: &str, scene: &str, records: &[&RunRecord]) -> Self {
        let n = records.len();
        let count = |s: RunStatus| records.iter().filter(|r| r.status == s).count();
        let solved = count(RunStatus::Solved);
        let planned = || records.iter().filter_map(|r| r.planned.as_ref());
        let processed = || records.iter().filter_map(|r| r.processed.as_ref());
        let m = |f: &dyn Fn(&RunRecord) -> Option<f64>| Stats::from_options(records.iter().map(|r| f(r)));
        Self {
            planner: planner.to_string(),
            scene: scene.to_string(),
            runs: n,
            solved,
            timeouts: count(RunStatus::Timeout),
            invalid_input: count(RunStatus::InvalidInput),
            errors: count(RunStatus::Error),
            success_rate: if n == 0 { 0.0 } else { 100.0 * solved as f64 / n as f64 },
            setup_time: m(&|r| Some(r.setup_time)),
            planning_time: m(&|r| Some(r.planning_time)),
            postprocessing_time: m(&|r| r.postprocessing_time),
            valid_planned: rates(planned()),
            valid_processed: rates(processed()),
            length_planned: m(&|r| r.planned.as_ref().map(|p| p.metrics.length)),
            length_processed: m(&|r| r.processed.as_ref().map(|p| p.metrics.length)),
            ee_length_planned: m(&|r| r.planned.as_ref().and_then(|p| p.metrics.ee_length)),
            ee_length_processed: m(&|r| r.processed.as_ref().and_then(|p| p.metrics.ee_length)),
            clearance_planned: m(&|r| r.planned.as_ref().and_then(|p| p.metrics.clearance_mean)),
            clearance_processed: m(&|r| r.processed.as_ref().and_then(|p| p.metrics.clearance_mean)),
            min_clearance_processed: m(&|r| r.processed.as_ref().and_then(|p| p.metrics.clearance_min)),
            smoothness_planned: m(&|r| r.planned.as_ref().map(|p| p.metrics.smoothness)),
            smoothness_processed: m(&|r| r.processed.as_ref().map(|p| p.metrics.smoothness)),
            planning_checks: m(&|r| Some(r.planning_checks as f64)),
            checks_per_second: m(&|r| r.checks_per_second()),
            ik_position_error: m(&|r| r.ik_position_error),
            repaired_runs: records.iter().filter(|r| r.repaired_segments.is_some_and(|n| n > 0)).count(),
            unrepaired_runs: records.iter().filter(|r| r.unrepaired_segments.is_some_and(|n| n > 0)).count(),
        }
    }
}

/// All runs and their aggregates.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BenchmarkReport {
    /// Options used.
    pub options: Option<BenchmarkOptions>,
    /// Every run.
    pub runs: Vec<RunRecord>,
    /// One summary per (scene, planner).
    pub summaries: Vec<Summary>,
}

fn fmt_opt(v: Option<f64>, scale: f64, prec: usize) -> String {
    v.map_or_else(|| "-".to_string(), |x| format!("{:.*}", prec, x * scale))
}

impl BenchmarkReport {
    /// The report (options, every run, summaries) as pretty-printed JSON.
    ///
    /// # Errors
    /// [`MotionError::Other`] wrapping a serialisation error (not expected for these types).
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string_pretty(self).map_err(|e| MotionError::Other(Box::new(e)))
    }

    /// A text table in the shape of the seed paper's Table III (average setup, planning and
    /// post-processing time; valid % planned / post-processed; length; clearance), with
    /// success rate, medians and collision checks per second added.
    pub fn table(&self) -> String {
        let mut out = String::new();
        for s in &self.summaries {
            let _ = writeln!(
                out,
                "== {} / {} ({} runs, success {:.1} %, {} timeouts, {} invalid input, {} errors)",
                s.scene, s.planner, s.runs, s.success_rate, s.timeouts, s.invalid_input, s.errors
            );
            let _ = writeln!(out, "  {:<16}{:>12}{:>12}{:>12}", "time [ms]", "mean", "median", "p95");
            for (name, st) in
                [("setup", &s.setup_time), ("planning", &s.planning_time), ("postprocessing", &s.postprocessing_time)]
            {
                let _ = writeln!(
                    out,
                    "  {:<16}{:>12}{:>12}{:>12}",
                    name,
                    fmt_opt(st.mean, 1e3, 2),
                    fmt_opt(st.p50, 1e3, 2),
                    fmt_opt(st.p95, 1e3, 2)
                );
            }
            let _ = writeln!(out, "  {:<26}{:>16}{:>16}", "solution", "planned", "postprocessed");
            let pct = |r: &ValidityRates| {
                (
                    format!("{:.1} %", r.discrete),
                    format!("{:.1} %", r.strict),
                    r.continuous.map_or("-".into(), |c| format!("{c:.1} %")),
                )
            };
            let (pd, ps, pc) = pct(&s.valid_planned);
            let (qd, qs, qc) = pct(&s.valid_processed);
            let _ = writeln!(out, "  {:<26}{:>16}{:>16}", "valid (discrete step)", pd, qd);
            let _ = writeln!(out, "  {:<26}{:>16}{:>16}", "valid (strict step)", ps, qs);
            let _ = writeln!(out, "  {:<26}{:>16}{:>16}", "valid (continuous)", pc, qc);
            let row = |name: &str, a: &Stats, b: &Stats, scale: f64, prec: usize| {
                format!(
                    "  {:<26}{:>16}{:>16}\n",
                    name,
                    format!("{} ({})", fmt_opt(a.mean, scale, prec), fmt_opt(a.p50, scale, prec)),
                    format!("{} ({})", fmt_opt(b.mean, scale, prec), fmt_opt(b.p50, scale, prec))
                )
            };
            out.push_str(&row("length C-space mean (med)", &s.length_planned, &s.length_processed, 1.0, 2));
            out.push_str(&row("length EE [m]", &s.ee_length_planned, &s.ee_length_processed, 1.0, 2));
            out.push_str(&row("clearance [mm]", &s.clearance_planned, &s.clearance_processed, 1e3, 1));
            out.push_str(&row("smoothness", &s.smoothness_planned, &s.smoothness_processed, 1.0, 2));
            let _ = writeln!(
                out,
                "  collision checks/run (median) {}, checks/s (median) {}, \
                 min clearance after post-processing (median) {} mm",
                fmt_opt(s.planning_checks.p50, 1.0, 0),
                fmt_opt(s.checks_per_second.p50, 1.0, 0),
                fmt_opt(s.min_clearance_processed.p50, 1e3, 1)
            );
            let _ = writeln!(
                out,
                "  post-processing repaired planned segments in {} runs ({} runs with unrepairable segments)",
                s.repaired_runs, s.unrepaired_runs
            );
            if s.ik_position_error.count > 0 {
                let _ = writeln!(out, "  IK position error (median) {} mm", fmt_opt(s.ik_position_error.p50, 1e3, 3));
            }
        }
        out
    }
}

fn grade(instance: &SceneInstance, path: &[Vec<f64>], options: &BenchmarkOptions) -> PathReport {
    let checker: &dyn StateValidityChecker = &*instance.checker;
    PathReport {
        validity: validate_path(checker, path, &options.validation),
        metrics: path_metrics(
            &instance.robot,
            &instance.group,
            &instance.q_full,
            instance.tip,
            checker,
            path,
            options.metrics_step,
        ),
    }
}

/// The options `run_once` repairs and shortcuts a run's path with: the benchmark's shortcut
/// options at the validators' steps and continuous check, seeded by the run's seed.
pub fn postprocessing_options(options: &BenchmarkOptions, seed: u64) -> ShortcutOptions {
    ShortcutOptions {
        seed,
        step: options.validation.strict_step,
        planning_step: options.validation.step,
        ccd: options.validation.ccd,
        ..options.shortcut
    }
}

/// Runs one planner on one scene instance and grades it.
pub fn run_once(
    planner: &mut dyn MotionPlanner,
    instance: &SceneInstance,
    scene: &str,
    run: usize,
    seed: u64,
    setup_time: f64,
    options: &BenchmarkOptions,
) -> RunRecord {
    let counter = CountingChecker::new(instance.planner_checker());
    let problem = instance.problem(&counter, options.time_limit, seed, options.validation.step);
    let mut record = RunRecord::unfinished(planner.name(), scene, run, seed, RunStatus::Error, setup_time);
    let t0 = Instant::now();
    let result = planner.plan(&problem);
    record.planning_time = t0.elapsed().as_secs_f64();
    record.planning_checks = counter.checks();
    let solution = match result {
        Ok(s) => s,
        Err(e) => {
            record.status = match &e {
                MotionError::Timeout { .. } => RunStatus::Timeout,
                e if e.is_invalid_input() => RunStatus::InvalidInput,
                _ => RunStatus::Error,
            };
            record.message = Some(e.to_string());
            return record;
        }
    };
    record.iterations = Some(solution.iterations);
    let path = solution.path;
    let ends_ok = path.first().is_some_and(|f| f.len() == instance.group.len() && distance(f, &instance.start) <= 1e-6)
        && path.iter().all(|q| q.len() == instance.group.len() && q.iter().all(|v| v.is_finite()))
        && path.last().is_some_and(|l| problem.satisfies_goal(l));
    if !ends_ok {
        record.message = Some("path does not lead from the start to a goal".into());
        return record;
    }
    record.status = RunStatus::Solved;
    record.planned = Some(grade(instance, &path, options));
    // Post-processing certifies its shortcuts with the judge's checker.
    let counter = CountingChecker::new(&*instance.checker);
    let shortcut_options = postprocessing_options(options, seed);
    let limits = instance.group.limits(&instance.robot);
    let t1 = Instant::now();
    let certifier = instance.certifier.as_deref();
    let (repaired, repair_stats) = repair_with(&counter, certifier, &path, &limits, &shortcut_options);
    let (smoothed, stats) = shortcut_with(&counter, certifier, &repaired, &shortcut_options);
    record.postprocessing_time = Some(t1.elapsed().as_secs_f64());
    record.postprocessing_checks = counter.checks();
    record.shortcuts = Some(stats.accepted);
    record.repaired_segments = Some(repair_stats.repaired);
    record.unrepaired_segments = Some(repair_stats.unrepaired);
    record.processed = Some(grade(instance, &smoothed, options));
    record.final_state = smoothed.last().cloned();
    if let (Goal::Pose(p), Some(last)) = (&instance.goal, smoothed.last()) {
        let (dp, dr) = p.error(&instance.robot, &problem.full_configuration(last));
        record.ik_position_error = Some(dp);
        record.ik_orientation_error = Some(dr);
    }
    record
}

/// Runs every planner `options.runs` times on every scene and aggregates the results.
///
/// Scene generation errors are recorded as [`RunStatus::InvalidInput`] runs; a failing
/// `setup` as [`RunStatus::Error`] runs. Nothing panics on bad input.
pub fn run_benchmark(
    planners: &mut [Box<dyn MotionPlanner>],
    scenes: &[BenchmarkScene],
    options: &BenchmarkOptions,
) -> BenchmarkReport {
    let mut report = BenchmarkReport { options: Some(options.clone()), ..BenchmarkReport::default() };
    for scene in scenes {
        for planner in planners.iter_mut() {
            let first = report.runs.len();
            let planner_name = planner.name().to_string();
            let mut shared_setup: Option<std::result::Result<f64, String>> = None;
            // Under the paper protocol, setup time includes loading and preparing the scene.
            let loading =
                |t0: Instant| if options.protocol == Protocol::Paper { t0.elapsed().as_secs_f64() } else { 0.0 };
            if scene.shared_environment {
                let t0 = Instant::now();
                shared_setup = Some(match (scene.generate)(options.seed) {
                    Ok(inst) => timed_setup(planner.as_mut(), &inst, options.seed, options).map(|t| t + loading(t0)),
                    Err(e) => Err(e.to_string()),
                });
            }
            for run in 0..options.runs {
                let seed = options.seed.wrapping_add(run as u64);
                let failed = |status, message: String, setup_time| RunRecord {
                    message: Some(message),
                    ..RunRecord::unfinished(&planner_name, &scene.name, run, seed, status, setup_time)
                };
                let t0 = Instant::now();
                let instance = match (scene.generate)(seed) {
                    Ok(i) => i,
                    Err(e) => {
                        report.runs.push(failed(RunStatus::InvalidInput, e.to_string(), 0.0));
                        continue;
                    }
                };
                let setup = match &shared_setup {
                    Some(s) => s.clone(),
                    None => timed_setup(planner.as_mut(), &instance, seed, options).map(|t| t + loading(t0)),
                };
                match setup {
                    Ok(t) => {
                        let record = run_once(planner.as_mut(), &instance, &scene.name, run, seed, t, options);
                        report.runs.push(record);
                    }
                    Err(msg) => report.runs.push(failed(RunStatus::Error, format!("setup failed: {msg}"), 0.0)),
                }
            }
            let records: Vec<&RunRecord> = report.runs[first..].iter().collect();
            report.summaries.push(Summary::from_records(planner.name(), &scene.name, &records));
        }
    }
    report
}

/// Runs `planner.setup` on `instance` (seeded) and returns its wall time (s), or the error's
/// message: how the benchmark times setup, for harnesses that drive their own query sequences.
///
/// # Errors
/// The planner's setup error, as text.
pub fn timed_setup(
    planner: &mut dyn MotionPlanner,
    instance: &SceneInstance,
    seed: u64,
    options: &BenchmarkOptions,
) -> std::result::Result<f64, String> {
    let context = SetupContext {
        robot: &instance.robot,
        group: &instance.group,
        q_full: &instance.q_full,
        checker: instance.planner_checker(),
        seed,
        step: options.validation.step,
    };
    let t = Instant::now();
    planner.setup(&context).map_err(|e| e.to_string())?;
    Ok(t.elapsed().as_secs_f64())
}
