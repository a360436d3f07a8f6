//! Sphere counts and overhangs of greedy covers of the vendored MotionBenchMaker Panda, and
//! which problem states each cover rejects (start, goal), per overhang budget.
//!
//! ```sh
//! cargo run --release -p opengrasp-motion --example panda_cover -- 0.02 0.01 0.005
//! ```

use std::time::Instant;

use opengrasp_motion::problem_set::{self, LoadedProblemSet};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::{MeshCover, StateValidityChecker};
use opengrasp_motion::Goal;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mbm/panda/problems");
    let sets: Vec<LoadedProblemSet> =
        problem_set::load(dir)?.iter().map(LoadedProblemSet::new).collect::<Result<_, _>>()?;
    let budgets: Vec<f64> = std::env::args().skip(1).map(|a| a.parse()).collect::<Result<_, _>>()?;
    for budget in if budgets.is_empty() { vec![0.02, 0.01, 0.005] } else { budgets } {
        let options = GreedyCoverOptions { max_overhang: budget, ..GreedyCoverOptions::default() };
        let t = Instant::now();
        let model = sets[0].sphere_model(MeshCover::Greedy(options))?;
        println!(
            "budget {:.1} mm: {} spheres, built in {:.2} s",
            budget * 1e3,
            model.sphere_count(),
            t.elapsed().as_secs_f64()
        );
        for set in &sets {
            for i in 0..set.len() {
                let world = set.sphere_world(i, &model)?;
                let exact = set.instance(i)?;
                let goals: Vec<Vec<f64>> = match set.goal(i) {
                    Some(Goal::Configuration(q)) => vec![q.clone()],
                    Some(Goal::ConfigurationSet(qs)) => qs.clone(),
                    _ => Vec::new(),
                };
                let start_ok = world.is_valid(&exact.start);
                let goals_ok = goals.iter().filter(|g| world.is_valid(g)).count();
                if !start_ok || goals_ok < goals.len() {
                    println!(
                        "  {} {i}: start {} goals {goals_ok}/{} (clearance start {:.1} mm)",
                        set.name(),
                        start_ok,
                        goals.len(),
                        exact.checker.clearance(&exact.start).unwrap_or(f64::NAN) * 1e3
                    );
                    for g in &goals {
                        println!("    goal clearance {:.1} mm", exact.checker.clearance(g).unwrap_or(f64::NAN) * 1e3);
                    }
                }
            }
        }
    }
    Ok(())
}
