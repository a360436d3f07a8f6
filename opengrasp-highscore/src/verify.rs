//! Re-verification by replay: where a submission's planner is a reference planner of the
//! suite it claims (same name and parameters), a seeded draw picks motion runs and grasp cells
//! that are replayed from their seeds and compared with what was submitted.
//!
//! - Motion runs: status, iterations, validity and lengths of the planned and post-processed
//!   paths (times are not compared, they depend on the machine).
//! - Grasp cells (the stock hands and objects): the shared evaluator's counts — candidates
//!   generated and evaluated, closed, palm-contact, force-closure — and the mean and median ε.
//!   The physics hold check is not replayed (it is the slow part; its counts are checked for
//!   plausibility only).

use opengrasp_bench::results::{GraspRecord, PlannerInfo, ResultsFile};
use opengrasp_bench::stock::{resolve_hand, resolve_object, HAND_NAMES, OBJECT_NAMES};
use opengrasp_bench::suite::{Suite, SuiteSize};
use opengrasp_motion::benchmark::RunRecord;

use super::error::{HighscoreError, Result};

/// Outcome of [`verify_sample`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Verification {
    /// Runs replayed and compared.
    pub checked: usize,
    /// One line per replayed run that differs from the submitted one.
    pub mismatches: Vec<String>,
}

/// SplitMix64: the seeded draw of the sample.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Replays up to `sample` motion runs and up to `sample` grasp cells of reference planners
/// (drawn with `seed`) and compares them with the submitted ones.
/// A file of another suite size than `tiny`, `default` or `paper`, or without reference
/// planners, has nothing to check (`checked == 0`).
///
/// # Errors
/// [`HighscoreError::InvalidField`] if the suite cannot be rebuilt or run.
pub fn verify_sample(results: &ResultsFile, sample: usize, seed: u64) -> Result<Verification> {
    let size = match results.provenance.suite_size.as_str() {
        "tiny" => SuiteSize::Tiny,
        "default" => SuiteSize::Default,
        "paper" => SuiteSize::Paper,
        _ => return Ok(Verification::default()),
    };
    let mut out = verify_motion(results, size, sample, seed)?;
    let grasp = verify_grasp(results, size, sample, seed)?;
    out.checked += grasp.checked;
    out.mismatches.extend(grasp.mismatches);
    Ok(out)
}

/// Keeps the first `k` items of a shuffle seeded with `seed` (partial Fisher-Yates).
fn seeded_sample<T>(items: &mut Vec<T>, k: usize, seed: u64) {
    let mut state = seed;
    let k = k.min(items.len());
    for i in 0..k {
        let j = i + (splitmix(&mut state) % (items.len() - i) as u64) as usize;
        items.swap(i, j);
    }
    items.truncate(k);
}

fn replay_error(e: opengrasp_bench::Error) -> HighscoreError {
    HighscoreError::field("results", format!("cannot replay the suite: {e}"))
}

/// The parameters of planner `name` in a section's planner list.
fn parameters_of<'a>(planners: &'a [PlannerInfo], name: &str) -> Option<&'a str> {
    planners.iter().find(|p| p.name == name).map(|p| p.parameters.as_str())
}

/// Replays up to `sample` grasp cells of the reference planners on stock hands and objects.
fn verify_grasp(results: &ResultsFile, size: SuiteSize, sample: usize, seed: u64) -> Result<Verification> {
    let Some(grasp) = &results.grasp else { return Ok(Verification::default()) };
    let names = Suite::new().with_reference_grasp(size).planner_names();
    let stock =
        |c: &GraspRecord| HAND_NAMES.contains(&c.cell.hand.as_str()) && OBJECT_NAMES.contains(&c.cell.object.as_str());
    let mut cells: Vec<&GraspRecord> =
        grasp.cells.iter().filter(|c| names.contains(&c.cell.planner) && stock(c)).collect();
    seeded_sample(&mut cells, sample, seed);
    let mut out = Verification::default();
    for sent in cells {
        let c = &sent.cell;
        let hand = resolve_hand(&c.hand).map_err(replay_error)?;
        let object = resolve_object(&c.object).map_err(replay_error)?;
        let replay = Suite::new()
            .with_reference_grasp(size)
            .seed(grasp.seed)
            .max_candidates(grasp.max_candidates)
            .physics_per_cell(0)
            .hands(vec![hand])
            .objects(vec![object])
            .jobs(1)
            .retain_planners(std::slice::from_ref(&c.planner))
            .and_then(|s| s.run())
            .map_err(replay_error)?;
        let Some(replayed) = replay.grasp else { continue };
        if parameters_of(&grasp.planners, &c.planner) != parameters_of(&replayed.planners, &c.planner) {
            continue; // a planner of the same name with other parameters: not a reference one
        }
        out.checked += 1;
        let again = replayed.cells.iter().find(|x| x.cell.planner == c.planner);
        if let Some(d) = again.map_or_else(|| Some("not replayed".to_string()), |a| grasp_difference(sent, a)) {
            out.mismatches.push(format!("{} with {} on {}: {d}", c.planner, c.hand, c.object));
        }
    }
    Ok(out)
}

/// The first difference between a submitted grasp cell and its replay, if any.
fn grasp_difference(sent: &GraspRecord, replay: &GraspRecord) -> Option<String> {
    let (a, b) = (&sent.cell, &replay.cell);
    if sent.seed != replay.seed {
        return Some(format!("seed {} but the suite's is {}", sent.seed, replay.seed));
    }
    let counts = [
        ("generated", a.generated, b.generated),
        ("evaluated", a.evaluated, b.evaluated),
        ("closed", a.closed, b.closed),
        ("palm-contact", a.palm_contact, b.palm_contact),
        ("force-closure palm", a.force_closure_palm, b.force_closure_palm),
        ("force-closure", a.force_closure, b.force_closure),
    ];
    if let Some((what, x, y)) = counts.into_iter().find(|(_, x, y)| x != y) {
        return Some(format!("{x} {what} grasps but the replay gives {y}"));
    }
    // NaN (no grasp in force closure) equals NaN here.
    let close = |x: f64, y: f64| (x.is_nan() && y.is_nan()) || (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1e-12);
    for (what, x, y) in [("mean", a.mean_epsilon, b.mean_epsilon), ("median", a.median_epsilon, b.median_epsilon)] {
        if !close(x, y) {
            return Some(format!("{what} epsilon {x} but the replay gives {y}"));
        }
    }
    None
}

/// Replays up to `sample` motion runs of the reference planners.
fn verify_motion(results: &ResultsFile, size: SuiteSize, sample: usize, seed: u64) -> Result<Verification> {
    let Some(motion) = &results.motion else { return Ok(Verification::default()) };
    let reference = Suite::new().with_reference_motion(size);
    let (names, scenes) = (reference.planner_names(), reference.scene_names());
    let mut candidates: Vec<&RunRecord> =
        motion.runs.iter().filter(|r| names.contains(&r.planner) && scenes.contains(&r.scene)).collect();
    seeded_sample(&mut candidates, sample, seed);
    if candidates.is_empty() {
        return Ok(Verification::default());
    }
    let mut planners: Vec<String> = candidates.iter().map(|r| r.planner.clone()).collect();
    let mut used_scenes: Vec<String> = candidates.iter().map(|r| r.scene.clone()).collect();
    planners.sort();
    planners.dedup();
    used_scenes.sort();
    used_scenes.dedup();
    let runs = candidates.iter().map(|r| r.run).max().unwrap_or(0) + 1;
    let mut options = motion.options.clone();
    options.runs = runs;
    let replay = reference
        .motion_options(options)
        .jobs(1)
        .retain_planners(&planners)
        .and_then(|s| s.retain_scenes(&used_scenes))
        .and_then(|s| s.run())
        .map_err(replay_error)?;
    let Some(replayed) = replay.motion else { return Ok(Verification::default()) };
    let mut out = Verification::default();
    for r in candidates {
        if parameters_of(&motion.planners, &r.planner) != parameters_of(&replayed.planners, &r.planner) {
            continue; // a planner of the same name with other parameters: not a reference one
        }
        out.checked += 1;
        let again = replayed.runs.iter().find(|x| x.planner == r.planner && x.scene == r.scene && x.run == r.run);
        if let Some(d) = again.map_or_else(|| Some("not replayed".to_string()), |a| difference(r, a)) {
            out.mismatches.push(format!("{} on {} run {}: {d}", r.planner, r.scene, r.run));
        }
    }
    Ok(out)
}

/// The first difference between a submitted run and its replay, if any.
fn difference(sent: &RunRecord, replay: &RunRecord) -> Option<String> {
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
    if sent.seed != replay.seed || sent.status != replay.status {
        return Some(format!("status {:?} (seed {}) but the replay gives {:?}", sent.status, sent.seed, replay.status));
    }
    if sent.iterations != replay.iterations {
        return Some(format!("{:?} iterations but the replay needs {:?}", sent.iterations, replay.iterations));
    }
    for (what, a, b) in
        [("planned", &sent.planned, &replay.planned), ("post-processed", &sent.processed, &replay.processed)]
    {
        match (a, b) {
            (None, None) => {}
            (Some(a), Some(b)) if a.validity == b.validity && close(a.metrics.length, b.metrics.length) => {}
            (a, b) => {
                let len = |p: &Option<opengrasp_motion::benchmark::PathReport>| p.as_ref().map(|p| p.metrics.length);
                return Some(format!("{what} path length {:?} but the replay gives {:?}", len(a), len(b)));
            }
        }
    }
    None
}
