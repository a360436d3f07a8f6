//! Shared by the `physics_*` examples: the force-closure palm grasps they check.

// Each example compiles its own copy of this module and reads only some of it.
#![allow(dead_code)]

use opengrasp_assets::objects;
use opengrasp_core::hand::Hand;
use opengrasp_core::object::ObjectModel;
use opengrasp_grasp::evaluator::{EvaluatorOptions, GraspEvaluation, GraspEvaluator};
use opengrasp_grasp::planners::{GraspPlanner, GraspRequest, MedialAxisPlanner, SurfaceNormalPlanner};

/// Evaluates the first 128 of `planner`'s candidates for the evaluator's hand on `object`
/// (spread evenly) and returns those with the palm touching in force closure.
pub fn fc_palm_grasps(
    evaluator: &mut GraspEvaluator,
    object: &ObjectModel,
    planner: &dyn GraspPlanner,
) -> Result<Vec<GraspEvaluation>, Box<dyn std::error::Error>> {
    let info = evaluator.hand_info().clone();
    let candidates = planner.plan(&GraspRequest { hand: &info, object: &object.mesh, seed: 0 })?;
    let m = candidates.len().min(128);
    let mut grasps = Vec::new();
    for i in 0..m {
        let e = evaluator.evaluate(&candidates[i * candidates.len() / m])?;
        if e.palm_contact && e.force_closure() {
            grasps.push(e);
        }
    }
    Ok(grasps)
}

/// The grasps one planner contributes to a sample ([`paper_sample`]).
pub struct PlannerSample {
    /// The planner's name.
    pub planner: String,
    /// How many force-closure palm grasps it found ([`fc_palm_grasps`]).
    pub found: usize,
    /// `per_cell` of them (all if fewer), spread evenly.
    pub grasps: Vec<GraspEvaluation>,
}

/// One object of a sample, with the grasps of both reference planners (medial axis first).
pub struct ObjectSample {
    /// The object.
    pub object: ObjectModel,
    /// Per planner.
    pub planners: Vec<PlannerSample>,
}

/// The grasps the physics examples check for `hand`: on each of the paper's eight objects and
/// for each reference planner, `per_cell` of its force-closure palm grasps, spread evenly.
pub fn paper_sample(hand: &Hand, per_cell: usize) -> Result<Vec<ObjectSample>, Box<dyn std::error::Error>> {
    let planners: [&dyn GraspPlanner; 2] = [&MedialAxisPlanner::default(), &SurfaceNormalPlanner::default()];
    let mut sample = Vec::new();
    for name in objects::NAMES.split_at(8).0 {
        let object = objects::by_name(name)?;
        let mut evaluator = GraspEvaluator::new(hand, &object, EvaluatorOptions::default())?;
        let mut per_planner = Vec::new();
        for planner in planners {
            let found = fc_palm_grasps(&mut evaluator, &object, planner)?;
            let k = per_cell.min(found.len());
            let grasps = (0..k).map(|j| found[j * found.len() / k].clone()).collect();
            per_planner.push(PlannerSample { planner: planner.name().to_string(), found: found.len(), grasps });
        }
        sample.push(ObjectSample { object, planners: per_planner });
    }
    Ok(sample)
}
