//! One PRM roadmap setup on kitchen scene 1 on its planning checker (the sphere model), as
//! the harness runs it: prints the roadmap's size, the edge checks' verdicts and their
//! discrete states (`⌈|b − a| / step⌉` each). For callgrind:
//!
//! ```sh
//! cargo build --release -p opengrasp-bench --example prm_setup
//! valgrind --tool=callgrind --toggle-collect='*Prm*setup*' target/release/examples/prm_setup 0
//! ```
//!
//! Seed 0 on the kitchen: 600 nodes, 5765 edges, 5945 edge checks (180 invalid), 463,692
//! states.

use std::cell::Cell;

use opengrasp_bench::scenes::armar_standard_scene;
use opengrasp_motion::planners::Prm;
use opengrasp_motion::validity::StateValidityChecker;
use opengrasp_motion::{MotionPlanner, SetupContext};

/// Forwards to a checker, counting the verdicts (valid, invalid) of the edge checks and their
/// discrete states.
struct Verdicts<'a>(&'a dyn StateValidityChecker, Cell<(u64, u64)>, Cell<u64>);

impl StateValidityChecker for Verdicts<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        self.0.is_valid(q)
    }
    fn state_certificate(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        self.0.state_certificate(q, out)
    }
    fn is_motion_valid_between(&self, a: &[f64], ac: &[f64], b: &[f64], bc: &[f64], step: f64) -> bool {
        let v = self.0.is_motion_valid_between(a, ac, b, bc, step);
        let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt();
        self.2.set(self.2.get() + (d / step).ceil() as u64);
        let (t, f) = self.1.get();
        self.1.set(if v { (t + 1, f) } else { (t, f + 1) });
        v
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seed = std::env::args().nth(1).map_or(Ok(0), |s| s.parse())?;
    let scene = armar_standard_scene();
    let instance = (scene.generate)(seed)?;
    let checker = Verdicts(instance.planner_checker(), Cell::new((0, 0)), Cell::new(0));
    let mut prm = Prm::default();
    let context = SetupContext {
        robot: &instance.robot,
        group: &instance.group,
        q_full: &instance.q_full,
        checker: &checker,
        seed,
        step: opengrasp_motion::validate::DEFAULT_STEP,
    };
    prm.setup(&context)?;
    let (valid, invalid) = checker.1.get();
    println!(
        "nodes {} edges {} checks valid {valid} invalid {invalid} states {}",
        prm.roadmap_nodes(),
        prm.roadmap_edges(),
        checker.2.get()
    );
    Ok(())
}
