//! Replaying a motion run from its record: results files keep a run's figures, not its path,
//! so the viewer plans the run again — same scene instance, planner, seed and
//! post-processing as [`opengrasp_motion::benchmark::run_once`] — and checks that the replay
//! gives the recorded iterations, validity and path lengths before drawing it.
//!
//! Only the reference planners (RRT-Connect, PRM, IK-RRT, with the parameters recorded in
//! the results) can be replayed.

use std::sync::Arc;

use opengrasp_bench::results::MotionSection;
use opengrasp_motion::benchmark::{postprocessing_options, timed_setup, RunRecord, RunStatus};
use opengrasp_motion::metrics::path_metrics;
use opengrasp_motion::planners::{IkRrt, Prm, PrmOptions, RrtConnect};
use opengrasp_motion::problem::MotionPlanner;
use opengrasp_motion::problem_set::LoadedProblemSet;
use opengrasp_motion::smoothing::{repair, shortcut};
use opengrasp_motion::validate::validate_path;

use crate::error::{Result, ViewerError};
use crate::world::MotionWorld;

/// The id of a run: `planner/scene/run`.
pub fn run_id(r: &RunRecord) -> String {
    format!("{}/{}/{}", r.planner, r.scene, r.run)
}

/// Finds a run by id: `planner/scene/run` or its position in the file (`0`, `1`, ...).
///
/// # Errors
/// [`ViewerError::UnknownRun`] if there is no such run.
pub fn find_run<'a>(motion: &'a MotionSection, id: &str) -> Result<&'a RunRecord> {
    let by_index = id.parse::<usize>().ok().and_then(|i| motion.runs.get(i));
    by_index.or_else(|| motion.runs.iter().find(|r| run_id(r) == id)).ok_or_else(|| ViewerError::UnknownRun {
        id: id.to_string(),
        available: motion.runs.len(),
        example: motion.runs.first().map_or_else(|| "(the file has no runs)".into(), run_id),
    })
}

/// A replayed run.
pub struct ReplayedRun {
    /// The record replayed.
    pub record: RunRecord,
    /// Its scene, world and instance.
    pub world: MotionWorld,
    /// The planner's path (group configurations; empty if the run was not solved).
    pub planned: Vec<Vec<f64>>,
    /// The post-processed path (empty if the run was not solved).
    pub processed: Vec<Vec<f64>>,
}

/// The reference planner `name` with the parameters recorded for it (`parameters`) on
/// `scene`.
fn reference_planner(name: &str, parameters: &str, scene: &str) -> Result<Box<dyn MotionPlanner>> {
    let unknown = |reason: String| ViewerError::UnknownPlanner { planner: name.to_string(), reason };
    let head = parameters.split(';').next().unwrap_or_default().trim();
    let planner: Box<dyn MotionPlanner> = match name {
        "RRT-Connect" if head == format!("{:?}", RrtConnect::default().options) => Box::new(RrtConnect::default()),
        "IK-RRT" if head == format!("{:?}", IkRrt::default().options) => Box::new(IkRrt::default()),
        "PRM" => {
            let base = PrmOptions::default();
            // The suites' PRM variants: default nodes, 150 (IK scenes, problem sets), 200 (tiny).
            let options = [base.nodes, 150, 200]
                .into_iter()
                .map(|nodes| PrmOptions { nodes, ..base })
                .find(|o| head == format!("{o:?}"))
                .ok_or_else(|| unknown(format!("parameters `{head}` are not a reference PRM's")))?;
            let per_scene = parameters.contains("nodes = 150 on the IK-based scenes") && scene.starts_with("IK-based");
            Box::new(Prm::new(if per_scene { PrmOptions { nodes: 150, ..options } } else { options }))
        }
        _ => return Err(unknown(format!("not a reference planner with its reference parameters (`{head}`)"))),
    };
    Ok(planner)
}

/// Replays run `id` of a motion section (`sets`: the problem sets the results were made
/// with, if any).
///
/// # Errors
/// [`ViewerError::UnknownRun`], [`ViewerError::UnknownScene`], [`ViewerError::UnknownPlanner`];
/// [`ViewerError::ReplayDiffers`] if the replay does not reproduce the record.
pub fn replay(motion: &MotionSection, id: &str, sets: &[Arc<LoadedProblemSet>]) -> Result<ReplayedRun> {
    let record = find_run(motion, id)?.clone();
    let options = &motion.options;
    let parameters = motion.planners.iter().find(|p| p.name == record.planner).map_or("", |p| p.parameters.as_str());
    let mut planner = reference_planner(&record.planner, parameters, &record.scene)?;
    let world = MotionWorld::rebuild(&record.scene, record.seed, options.seed, sets)?;
    let mut out = ReplayedRun { record, world, planned: Vec::new(), processed: Vec::new() };
    if out.record.status != RunStatus::Solved {
        return Ok(out);
    }
    // As the benchmark does: a shared environment is set up once on the base seed's instance
    // and every run before this one has been planned with the same planner.
    let run = run_id(&out.record);
    let differs = |what: String| ViewerError::ReplayDiffers { run: run.clone(), what };
    let earlier: Vec<u64> = if out.world.scene.shared_environment {
        let base = (out.world.scene.generate)(options.seed)?;
        timed_setup(planner.as_mut(), &base, options.seed, options).map_err(|e| differs(format!("setup: {e}")))?;
        (0..out.record.run as u64).map(|r| options.seed.wrapping_add(r)).collect()
    } else {
        timed_setup(planner.as_mut(), &out.world.instance, out.record.seed, options)
            .map_err(|e| differs(format!("setup: {e}")))?;
        Vec::new()
    };
    for seed in earlier {
        let instance = (out.world.scene.generate)(seed)?;
        let problem = instance.problem(instance.planner_checker(), options.time_limit, seed, options.validation.step);
        let _ = planner.plan(&problem);
    }
    let instance = &out.world.instance;
    let seed = out.record.seed;
    let problem = instance.problem(instance.planner_checker(), options.time_limit, seed, options.validation.step);
    let solution = planner.plan(&problem)?;
    // Post-processing exactly as `run_once` does it (its options, repair then shortcut).
    let shortcut_options = postprocessing_options(options, seed);
    let limits = instance.group.limits(&instance.robot);
    let (repaired, _) = repair(&*instance.checker, &solution.path, &limits, &shortcut_options);
    let (smoothed, _) = shortcut(&*instance.checker, &repaired, &shortcut_options);
    if Some(solution.iterations) != out.record.iterations {
        return Err(differs(format!("{} iterations, recorded {:?}", solution.iterations, out.record.iterations)));
    }
    for (what, path, report) in
        [("planned", &solution.path, &out.record.planned), ("post-processed", &smoothed, &out.record.processed)]
    {
        let Some(report) = report else { return Err(differs(format!("no {what} path recorded"))) };
        let m = path_metrics(
            &instance.robot,
            &instance.group,
            &instance.q_full,
            instance.tip,
            &*instance.checker,
            path,
            options.metrics_step,
        );
        let validity = validate_path(&*instance.checker, path, &options.validation);
        let close = (m.length - report.metrics.length).abs() <= 1e-9 * m.length.abs().max(1.0);
        if !close || validity != report.validity {
            return Err(differs(format!(
                "{what} path length {} and validity {validity:?}, recorded {} and {:?}",
                m.length, report.metrics.length, report.validity
            )));
        }
    }
    out.planned = solution.path;
    out.processed = smoothed;
    Ok(out)
}

/// The first solved run of `scene` (in file order) that replays; the last replay error if
/// none does ([`ViewerError::UnknownRun`] if the scene has no solved run).
///
/// # Errors
/// As [`replay`].
pub fn first_replayable(motion: &MotionSection, scene: &str, sets: &[Arc<LoadedProblemSet>]) -> Result<ReplayedRun> {
    let mut last = ViewerError::UnknownRun {
        id: format!("a solved run of {scene}"),
        available: motion.runs.len(),
        example: "none solved".into(),
    };
    for r in motion.runs.iter().filter(|r| r.scene == scene && r.status == RunStatus::Solved) {
        match replay(motion, &run_id(r), sets) {
            Ok(run) => return Ok(run),
            Err(e) => last = e,
        }
    }
    Err(last)
}
