//! Plausibility rules: values that pass the results-file schema but cannot come from the
//! suite (so cannot be ranked).
//!
//! - the suite size is one the board knows ([`KNOWN_SUITE_SIZES`]): no private leagues;
//! - Ferrari-Canny epsilons are within their analytic bound ([`epsilon_bound`]) and zero
//!   without force closure; percentages equal what the counts give;
//! - solved motion runs took at least [`MIN_PLANNING_SECONDS`], no run took longer than
//!   twice the time limit plus a second; grasp evaluation took at least
//!   [`MIN_EVALUATION_SECONDS`] per evaluated candidate;
//! - grasp cells are unique per planner × hand × object, at most `max_candidates` evaluated;
//! - motion runs are unique per planner × scene × run index, complete (indices `0..runs`
//!   for the suite's run count; Clean the Table: `0..n` without gaps) and seeded as the
//!   suite seeds them (`seed + run`);
//! - the reference sizes (`tiny`, `default`, `paper`) ran their own run count and
//!   candidate limit;
//! - stored summaries equal the summaries recomputed from the runs.

use std::collections::{BTreeMap, BTreeSet};

use opengrasp_bench::results::ResultsFile;
use opengrasp_bench::suite::{SuiteSize, CLEAN_THE_TABLE_SCENE};
use opengrasp_motion::benchmark::{RunRecord, RunStatus, Summary};
use serde_json::Value;

use super::error::{HighscoreError, Result};

/// Suite sizes the board ranks, each its own league.
pub const KNOWN_SUITE_SIZES: [&str; 4] = ["paper", "default", "custom", "tiny"];

/// Coulomb friction coefficient of the suite's contact model (the default of
/// `opengrasp_grasp::contact::ContactModel`).
pub const REFERENCE_FRICTION: f64 = 0.5;

/// Shortest planning time (s) of a solved motion run: below any real planner's first
/// collision check.
pub const MIN_PLANNING_SECONDS: f64 = 1e-6;

/// Shortest evaluation time (s) per evaluated grasp candidate (closing the hand, contacts,
/// force-closure QP and hull take tens of microseconds at least).
pub const MIN_EVALUATION_SECONDS: f64 = 1e-6;

/// Tolerance of recomputed percentages and summaries (absolute, or relative for large values).
const TOL: f64 = 1e-6;

/// Analytic upper bound of the Ferrari-Canny (L1) epsilon: the largest origin-centred ball
/// in the wrench hull fits in the hull's projection on force space, whose points are convex
/// combinations of friction-cone edges of length `√(1 + μ²)`, so `ε ≤ √(1 + μ²)`.
pub fn epsilon_bound() -> f64 {
    (1.0 + REFERENCE_FRICTION * REFERENCE_FRICTION).sqrt()
}

fn bad(field: impl Into<String>, reason: impl Into<String>) -> HighscoreError {
    HighscoreError::field(field, reason)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOL * a.abs().max(b.abs()).max(1.0)
}

fn pct(a: usize, b: usize) -> f64 {
    if b == 0 {
        0.0
    } else {
        100.0 * a as f64 / b as f64
    }
}

fn reference_size(name: &str) -> Option<SuiteSize> {
    match name {
        "tiny" => Some(SuiteSize::Tiny),
        "default" => Some(SuiteSize::Default),
        "paper" => Some(SuiteSize::Paper),
        _ => None,
    }
}

/// Checks the plausibility rules of the [module docs](self).
///
/// # Errors
/// [`HighscoreError::InvalidField`] naming the first implausible field.
pub fn check_plausible(r: &ResultsFile) -> Result<()> {
    let size = r.provenance.suite_size.as_str();
    if !KNOWN_SUITE_SIZES.contains(&size) {
        return Err(bad("provenance.suite_size", format!("{size:?} is not one of {KNOWN_SUITE_SIZES:?}")));
    }
    let reference = reference_size(size);
    if let Some(g) = &r.grasp {
        if let Some(s) = reference {
            if g.max_candidates != s.max_candidates() {
                return Err(bad(
                    "grasp.max_candidates",
                    format!(
                        "the {size} suite evaluates {:?} candidates per cell, not {:?}",
                        s.max_candidates(),
                        g.max_candidates
                    ),
                ));
            }
        }
        let bound = epsilon_bound();
        let mut seen = BTreeSet::new();
        for (i, rec) in g.cells.iter().enumerate() {
            let c = &rec.cell;
            let f = |name: &str| format!("grasp.cells[{i}].{name}");
            if !seen.insert((&c.planner, &c.hand, &c.object)) {
                return Err(bad(f("object"), "a second cell for the same planner, hand and object"));
            }
            for (name, v) in [("mean_epsilon", c.mean_epsilon), ("median_epsilon", c.median_epsilon)] {
                if v > bound {
                    return Err(bad(f(name), format!("{v} exceeds the analytic bound √(1 + μ²) = {bound:.4}")));
                }
                if c.force_closure == 0 && v != 0.0 {
                    return Err(bad(f(name), "is not 0 although no grasp is in force closure"));
                }
            }
            if !close(c.fc_percent_palm, pct(c.force_closure_palm, c.palm_contact)) {
                return Err(bad(f("fc_percent_palm"), "differs from 100 · force_closure_palm / palm_contact"));
            }
            if !close(c.fc_percent_all, pct(c.force_closure, c.evaluated)) {
                return Err(bad(f("fc_percent_all"), "differs from 100 · force_closure / evaluated"));
            }
            if let Some(max) = g.max_candidates {
                if c.evaluated > max {
                    return Err(bad(f("evaluated"), format!("{} exceeds max_candidates ({max})", c.evaluated)));
                }
            }
            if c.evaluation_seconds < c.evaluated as f64 * MIN_EVALUATION_SECONDS {
                return Err(bad(f("evaluation_seconds"), "below the time floor of the evaluated candidates"));
            }
        }
    }
    if let Some(m) = &r.motion {
        if let Some(s) = reference {
            if m.options.runs != s.runs() {
                return Err(bad(
                    "motion.options.runs",
                    format!("the {size} suite runs {} runs, not {}", s.runs(), m.options.runs),
                ));
            }
        }
        let limit = m.options.time_limit.as_secs_f64();
        let mut groups: BTreeMap<(&str, &str), BTreeSet<usize>> = BTreeMap::new();
        for (i, run) in m.runs.iter().enumerate() {
            let f = |name: &str| format!("motion.runs[{i}].{name}");
            if !groups.entry((&run.planner, &run.scene)).or_default().insert(run.run) {
                return Err(bad(f("run"), format!("run index {} appears twice for this planner and scene", run.run)));
            }
            if run.status == RunStatus::Solved && run.planning_time < MIN_PLANNING_SECONDS {
                return Err(bad(f("planning_time"), format!("a solved run takes at least {MIN_PLANNING_SECONDS} s")));
            }
            if run.planning_time > 2.0 * limit + 1.0 {
                return Err(bad(f("planning_time"), format!("exceeds the time limit of {limit} s")));
            }
            if run.scene != CLEAN_THE_TABLE_SCENE && run.seed != m.options.seed.wrapping_add(run.run as u64) {
                return Err(bad(f("seed"), "run r is seeded with options.seed + r"));
            }
        }
        for ((planner, scene), indices) in &groups {
            let expected = if *scene == CLEAN_THE_TABLE_SCENE { indices.len() } else { m.options.runs };
            if indices.len() != expected || indices.iter().next_back().is_some_and(|&last| last + 1 != expected) {
                return Err(bad(
                    "motion.runs",
                    format!("{planner} on {scene}: run indices must be 0..{expected}, found {} runs", indices.len()),
                ));
            }
        }
        let mut episodes = BTreeSet::new();
        for (i, e) in m.episodes.iter().enumerate() {
            if !episodes.insert((&e.planner, e.index)) {
                return Err(bad(format!("motion.episodes[{i}].index"), "episode index appears twice"));
            }
        }
        let mut pairs = BTreeSet::new();
        for (i, s) in m.summaries.iter().enumerate() {
            let f = format!("motion.summaries[{i}]");
            if !pairs.insert((&s.planner, &s.scene)) {
                return Err(bad(f, "a second summary for the same planner and scene"));
            }
            let records: Vec<&RunRecord> =
                m.runs.iter().filter(|r| r.planner == s.planner && r.scene == s.scene).collect();
            let given = serde_json::to_value(s).unwrap_or(Value::Null);
            let recomputed =
                serde_json::to_value(Summary::from_records(&s.planner, &s.scene, &records)).unwrap_or(Value::Null);
            if !same(&given, &recomputed) {
                return Err(bad(f, "differs from the summary of its runs"));
            }
        }
    }
    Ok(())
}

/// JSON equality with numbers compared within the tolerance.
fn same(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => close(x, y),
            _ => x == y,
        },
        (Value::Array(x), Value::Array(y)) => x.len() == y.len() && x.iter().zip(y).all(|(a, b)| same(a, b)),
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| same(v, w)))
        }
        _ => a == b,
    }
}
