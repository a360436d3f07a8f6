//! Validation of results files: ranges, finiteness and consistency.

use opengrasp_motion::benchmark::RunStatus;

use super::{GraspSection, MotionSection};
use crate::error::{Error, Result};

pub(super) fn invalid(field: impl Into<String>, reason: impl Into<String>) -> Error {
    Error::Invalid { field: field.into(), reason: reason.into() }
}

fn finite(field: &str, v: f64) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(invalid(field, format!("{v} is not finite")))
    }
}

pub(super) fn non_negative(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(field, format!("{v} is not a finite non-negative number")))
    }
}

fn percent(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && (0.0..=100.0).contains(&v) {
        Ok(())
    } else {
        Err(invalid(field, format!("{v} is not a percentage in [0, 100]")))
    }
}

fn at_most(field: &str, a: usize, what_b: &str, b: usize) -> Result<()> {
    if a <= b {
        Ok(())
    } else {
        Err(invalid(field, format!("{a} exceeds {what_b} ({b})")))
    }
}

pub(super) fn validate_grasp(g: &GraspSection) -> Result<()> {
    for (i, r) in g.cells.iter().enumerate() {
        let c = &r.cell;
        let f = |name: &str| format!("grasp.cells[{i}].{name}");
        if !g.planners.iter().any(|p| p.name == c.planner) {
            return Err(invalid(f("planner"), format!("planner {:?} is not listed in grasp.planners", c.planner)));
        }
        at_most(&f("evaluated"), c.evaluated, "generated", c.generated)?;
        at_most(&f("closed"), c.closed, "evaluated", c.evaluated)?;
        at_most(&f("palm_contact"), c.palm_contact, "evaluated", c.evaluated)?;
        at_most(&f("force_closure"), c.force_closure, "evaluated", c.evaluated)?;
        at_most(&f("force_closure_palm"), c.force_closure_palm, "palm_contact", c.palm_contact)?;
        at_most(&f("force_closure_palm"), c.force_closure_palm, "force_closure", c.force_closure)?;
        at_most(&f("physics_held"), c.physics_held, "physics_tested", c.physics_tested)?;
        at_most(&f("static_holdable"), c.static_holdable, "physics_tested", c.physics_tested)?;
        at_most(&f("static_agree"), c.static_agree, "physics_tested", c.physics_tested)?;
        at_most(&f("physics_diverged"), c.physics_diverged, "physics_tested", c.physics_tested)?;
        at_most(&f("physics_held"), c.physics_held + c.physics_diverged, "physics_tested", c.physics_tested)?;
        let finished_failures = c.physics_tested.saturating_sub(c.physics_held + c.physics_diverged);
        at_most(&f("physics_grip_escaped"), c.physics_grip_escaped, "failed checks", finished_failures)?;
        percent(&f("fc_percent_palm"), c.fc_percent_palm)?;
        percent(&f("fc_percent_all"), c.fc_percent_all)?;
        non_negative(&f("mean_epsilon"), c.mean_epsilon)?;
        non_negative(&f("median_epsilon"), c.median_epsilon)?;
        at_most(&f("candidates"), c.candidates.len(), "evaluated", c.evaluated)?;
        for (k, r) in c.candidates.iter().enumerate() {
            non_negative(&f(&format!("candidates[{k}].epsilon")), r.epsilon)?;
            if let Some(volume) = r.volume {
                non_negative(&f(&format!("candidates[{k}].volume")), volume)?;
            }
            at_most(&f(&format!("candidates[{k}].index")), r.index, "generated", c.generated.saturating_sub(1))?;
        }
        non_negative(&f("planning_seconds"), c.planning_seconds)?;
        non_negative(&f("evaluation_seconds"), c.evaluation_seconds)?;
        non_negative(&f("evaluations_per_second"), c.evaluations_per_second)?;
    }
    Ok(())
}

pub(super) fn validate_motion(m: &MotionSection) -> Result<()> {
    for (i, r) in m.runs.iter().enumerate() {
        let f = |name: &str| format!("motion.runs[{i}].{name}");
        if !m.planners.iter().any(|p| p.name == r.planner) {
            return Err(invalid(f("planner"), format!("planner {:?} is not listed in motion.planners", r.planner)));
        }
        non_negative(&f("setup_time"), r.setup_time)?;
        non_negative(&f("planning_time"), r.planning_time)?;
        if let Some(t) = r.postprocessing_time {
            non_negative(&f("postprocessing_time"), t)?;
        }
        for (name, v) in [("ik_position_error", r.ik_position_error), ("ik_orientation_error", r.ik_orientation_error)]
        {
            if let Some(v) = v {
                non_negative(&f(name), v)?;
            }
        }
        if r.status == RunStatus::Solved && r.planned.is_none() {
            return Err(invalid(f("planned"), "a solved run must carry its planned path's report"));
        }
        for (name, report) in [("planned", &r.planned), ("processed", &r.processed)] {
            if let Some(p) = report {
                let g = |x: &str| f(&format!("{name}.metrics.{x}"));
                non_negative(&g("length"), p.metrics.length)?;
                finite(&g("smoothness"), p.metrics.smoothness)?;
                if let Some(v) = p.metrics.ee_length {
                    non_negative(&g("ee_length"), v)?;
                }
                for (x, v) in [("clearance_mean", p.metrics.clearance_mean), ("clearance_min", p.metrics.clearance_min)]
                {
                    if let Some(v) = v {
                        finite(&g(x), v)?;
                    }
                }
            }
        }
        if let Some(q) = &r.final_state {
            if q.iter().any(|v| !v.is_finite()) {
                return Err(invalid(f("final_state"), "non-finite joint value"));
            }
        }
    }
    for (i, s) in m.summaries.iter().enumerate() {
        let f = |name: &str| format!("motion.summaries[{i}].{name}");
        percent(&f("success_rate"), s.success_rate)?;
        at_most(&f("solved"), s.solved, "runs", s.runs)?;
        if !m.planners.iter().any(|p| p.name == s.planner) {
            return Err(invalid(f("planner"), format!("planner {:?} is not listed in motion.planners", s.planner)));
        }
    }
    for (i, e) in m.episodes.iter().enumerate() {
        let f = |name: &str| format!("motion.episodes[{i}].{name}");
        let t = &e.totals;
        at_most(&f("cleaned"), t.cleaned, "objects", e.objects.len())?;
        for (name, v) in [
            ("setup_time", t.setup_time),
            ("planning_time", t.planning_time),
            ("postprocessing_time", t.postprocessing_time),
            ("length", t.length),
            ("ee_length", t.ee_length),
        ] {
            non_negative(&f(name), v)?;
        }
        if !m.planners.iter().any(|p| p.name == e.planner) {
            return Err(invalid(f("planner"), format!("planner {:?} is not listed in motion.planners", e.planner)));
        }
    }
    Ok(())
}
