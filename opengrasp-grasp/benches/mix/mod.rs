//! The default suite's mix of candidates, shared by the `grasp` bench (`throughput/…`) and the
//! `eval_profile` example (the same workload for instruction counts).

use opengrasp_assets::{hands, objects};
use opengrasp_core::hand::Hand;
use opengrasp_core::object::ObjectModel;
use opengrasp_grasp::evaluator::{EvaluatorOptions, GraspEvaluator};
use opengrasp_grasp::planners::{GraspCandidate, GraspPlanner, GraspRequest, MedialAxisPlanner, SurfaceNormalPlanner};

/// The default suite's objects: the stock objects without the measuring cup (the last one).
fn suite_objects() -> &'static [&'static str] {
    &objects::NAMES[..objects::NAMES.len() - 1]
}

/// Candidates per hand × object × planner in the throughput mix (evenly spaced through the
/// planner's list, as the suite picks its capped candidates).
const PER_CELL: usize = 4;

/// One evaluator per hand × object of the suite with its share of the mix of candidates.
pub fn suite_mix() -> Vec<(GraspEvaluator, ObjectModel, Vec<GraspCandidate>)> {
    let hands: [Hand; 2] = [hands::armar3_hand(), hands::barrett()];
    let mut mix = Vec::new();
    for hand in &hands {
        for &name in suite_objects() {
            let object = objects::by_name(name).expect("stock object");
            let ev = GraspEvaluator::new(hand, &object, EvaluatorOptions::default()).expect("evaluator");
            let info = ev.hand_info().clone();
            let request = GraspRequest { hand: &info, object: &object.mesh, seed: 0 };
            let mut chosen = Vec::new();
            let planners: [&dyn GraspPlanner; 2] = [&MedialAxisPlanner::default(), &SurfaceNormalPlanner::default()];
            for planner in planners {
                let all = planner.plan(&request).expect("candidates");
                let m = PER_CELL.min(all.len());
                chosen.extend((0..m).map(|i| all[i * all.len() / m].clone()));
            }
            mix.push((ev, object, chosen));
        }
    }
    mix
}
