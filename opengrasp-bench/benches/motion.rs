//! Planning time on the standard motion-planning scene (scene 1): RRT-Connect on the
//! ARMAR-III-like humanoid in the kitchen (hip yaw + right arm) and on the 7-DoF stand-in, the
//! post-processing of planned paths (repair + shortcut, as the harness runs it), plus the cost
//! of one validity check; and RRT-Connect on the MotionBenchMaker Panda problems vendored in
//! `opengrasp-motion/tests/data/mbm` (`mbm/<set>/...`, the Panda's meshes, exact checker).
//!
//! ```sh
//! cargo bench -p opengrasp-bench --bench motion -- --warm-up-time 1 --measurement-time 3
//! ```

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use opengrasp_bench::problem_sets::load_problem_sets;
use opengrasp_bench::scenes::{armar_standard_scene, standard_scene, CheckerKind};
use opengrasp_motion::benchmark::BenchmarkScene;
use opengrasp_motion::planners::{NeighborStructure, RrtConnect};
use opengrasp_motion::smoothing::{repair, shortcut, ShortcutOptions};
use opengrasp_motion::MotionPlanner;

fn bench_scene(c: &mut Criterion, id: &str, scene: BenchmarkScene) {
    let instance = (scene.generate)(0).expect("scene instance");
    // Cycle through 100 seeds so the measurement averages over the planner's randomness; the
    // kd-tree (default) and the linear scan give the same paths, only the time differs.
    for (name, neighbors) in
        [("rrt_connect_plan", NeighborStructure::KdTree), ("rrt_connect_plan_linear_nn", NeighborStructure::LinearScan)]
    {
        let mut planner = RrtConnect { neighbors, ..RrtConnect::default() };
        let mut seed = 0u64;
        c.bench_function(&format!("{id}/{name}"), |b| {
            b.iter(|| {
                seed = (seed + 1) % 100;
                let problem = instance.problem(&*instance.checker, Duration::from_secs(10), seed, 0.02);
                planner.plan(&problem).expect("solved")
            })
        });
    }
    let mut planner = RrtConnect::default();
    // Post-processing as the harness runs it (repair, then shortcut with every validator's
    // check), on the paths of 10 seeds, cycling.
    let paths: Vec<Vec<Vec<f64>>> = (0..10)
        .map(|seed| {
            let problem = instance.problem(&*instance.checker, Duration::from_secs(10), seed, 0.02);
            planner.plan(&problem).expect("solved").path
        })
        .collect();
    let limits = instance.group.limits(&instance.robot);
    let mut k = 0usize;
    c.bench_function(&format!("{id}/postprocess"), |b| {
        b.iter(|| {
            k = (k + 1) % paths.len();
            let options = ShortcutOptions { seed: k as u64, ..ShortcutOptions::default() };
            let (repaired, _) = repair(&*instance.checker, &paths[k], &limits, &options);
            shortcut(&*instance.checker, &repaired, &options)
        })
    });
    let q = instance.start.clone();
    c.bench_function(&format!("{id}/validity_check"), |b| {
        b.iter(|| instance.checker.is_valid(std::hint::black_box(&q)))
    });
}

/// RRT-Connect planning time per MBM set, cycling over the set's problems (failures within
/// the time limit are timed too), and one state check at the first problem's start.
fn mbm_panda(c: &mut Criterion) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../opengrasp-motion/tests/data/mbm/panda/problems");
    for set in load_problem_sets(dir).expect("vendored MBM sets") {
        let instances: Vec<_> = (0..set.len()).map(|i| set.instance(i).expect("problem instance")).collect();
        let mut planner = RrtConnect::default();
        let mut k = 0usize;
        c.bench_function(&format!("mbm/{}/rrt_connect_plan", set.name()), |b| {
            b.iter(|| {
                k += 1;
                let instance = &instances[k % instances.len()];
                let problem = instance.problem(&*instance.checker, Duration::from_secs(10), k as u64, 0.02);
                planner.plan(&problem).is_ok()
            })
        });
        let first = &instances[0];
        c.bench_function(&format!("mbm/{}/validity_check", set.name()), |b| {
            b.iter(|| first.checker.is_valid(std::hint::black_box(&first.start)))
        });
    }
}

fn motion(c: &mut Criterion) {
    bench_scene(c, "armar_kitchen", armar_standard_scene());
    bench_scene(c, "seven_dof_cupboard", standard_scene(CheckerKind::Exact));
    mbm_panda(c);
}

criterion_group!(benches, motion);
criterion_main!(benches);
