//! Re-verification of a sample of motion runs: where a submission's planner is a reference
//! planner of the suite it claims (same name and parameters), runs picked by a seeded draw
//! are replayed from their seeds and compared with what was submitted (status, iterations,
//! validity and lengths of the planned and post-processed paths; times are not compared,
//! they depend on the machine).

use opengrasp_bench::results::ResultsFile;
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

/// Replays up to `sample` runs of reference planners (drawn with `seed`) and compares them.
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
    let Some(motion) = &results.motion else { return Ok(Verification::default()) };
    let reference = Suite::new().with_reference_motion(size);
    let (names, scenes) = (reference.planner_names(), reference.scene_names());
    let mut candidates: Vec<&RunRecord> =
        motion.runs.iter().filter(|r| names.contains(&r.planner) && scenes.contains(&r.scene)).collect();
    // Partial Fisher-Yates: the first `sample` of a seeded shuffle.
    let mut state = seed;
    let k = sample.min(candidates.len());
    for i in 0..k {
        let j = i + (splitmix(&mut state) % (candidates.len() - i) as u64) as usize;
        candidates.swap(i, j);
    }
    candidates.truncate(k);
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
    let bad = |e: opengrasp_bench::Error| HighscoreError::field("results", format!("cannot replay the suite: {e}"));
    let mut options = motion.options.clone();
    options.runs = runs;
    let replay = reference
        .motion_options(options)
        .jobs(1)
        .retain_planners(&planners)
        .and_then(|s| s.retain_scenes(&used_scenes))
        .and_then(|s| s.run())
        .map_err(bad)?;
    let Some(replayed) = replay.motion else { return Ok(Verification::default()) };
    let mut out = Verification::default();
    for r in candidates {
        let same_parameters = |m: &opengrasp_bench::results::MotionSection| {
            m.planners.iter().find(|p| p.name == r.planner).map(|p| p.parameters.clone())
        };
        if same_parameters(motion) != same_parameters(&replayed) {
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
