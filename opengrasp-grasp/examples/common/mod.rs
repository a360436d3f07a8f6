//! Shared by the `physics_*` examples: the force-closure palm grasps of one planner.

use opengrasp_core::object::ObjectModel;
use opengrasp_grasp::evaluator::{GraspEvaluation, GraspEvaluator};
use opengrasp_grasp::planners::{GraspPlanner, GraspRequest};

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
