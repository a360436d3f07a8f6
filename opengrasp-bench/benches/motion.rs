//! Planning time on the standard motion-planning scene (scene 1): RRT-Connect on the
//! ARMAR-III-like humanoid in the kitchen (hip yaw + right arm; exact checker, and
//! `armar_kitchen/rrt_connect_spheres` / `state_check_spheres` on the conservative sphere model
//! the harness plans on) and on the 7-DoF stand-in, the
//! post-processing of planned paths (repair + shortcut, as the harness runs it), plus the cost
//! of one validity check; and RRT-Connect on the MotionBenchMaker Panda problems vendored in
//! `opengrasp-motion/tests/data/mbm` (`mbm/<set>/...`: on the Panda's meshes with the exact
//! checker, and on its guaranteed greedy sphere cover: `rrt_connect_spheres`,
//! `state_check_spheres`, `state_check_spheres_batch64`, `motion_check_spheres`, each also
//! `_lanes` with `SphereWorld::with_batched_checks`, `_uncertified` with
//! `SphereWorld::with_certified_motions(false)` and `_one_by_one` through the trait's
//! one-state defaults); and certified post-processing (`postprocess/scene1`,
//! `postprocess/scene1_exact`, `postprocess/clean_table_episode`).
//!
//! ```sh
//! cargo bench -p opengrasp-bench --bench motion -- --warm-up-time 1 --measurement-time 3
//! ```

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use std::sync::Arc;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use opengrasp_bench::clean_table::{clean_the_table, CleanTheTableOptions};
use opengrasp_bench::problem_sets::load_problem_sets;
use opengrasp_bench::scenes::{armar_standard_scene, standard_scene, CheckerKind};
use opengrasp_motion::benchmark::{postprocessing_options, BenchmarkOptions, BenchmarkScene, SceneInstance};
use opengrasp_motion::planners::{NeighborStructure, RrtConnect, RrtConnectOptions};
use opengrasp_motion::problem_set::PlanningModel;
use opengrasp_motion::smoothing::{repair, repair_with, shortcut, shortcut_with, ShortcutOptions};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::{OneByOne, StateValidityChecker};
use opengrasp_motion::MotionPlanner;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// RRT-Connect paths of seeds `0..n` on `instance`.
fn rrt_connect_paths(instance: &SceneInstance, n: u64) -> Vec<Vec<Vec<f64>>> {
    let mut planner = RrtConnect::default();
    (0..n)
        .map(|seed| {
            let problem = instance.problem(&*instance.checker, Duration::from_secs(10), seed, 0.02);
            planner.plan(&problem).expect("solved").path
        })
        .collect()
}

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
    // Post-processing as the harness runs it (repair, then shortcut with every validator's
    // check), on the paths of 10 seeds, cycling.
    let paths = rrt_connect_paths(&instance, 10);
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
    // The planning model the harness plans on (kitchen scenes: the conservative sphere model).
    if let Some(model) = instance.planning_checker.as_deref() {
        let mut planner = RrtConnect::default();
        let mut seed = 0u64;
        c.bench_function(&format!("{id}/rrt_connect_spheres"), |b| {
            b.iter(|| {
                seed = (seed + 1) % 100;
                planner.plan(&instance.problem(model, Duration::from_secs(10), seed, 0.02)).expect("solved")
            })
        });
        c.bench_function(&format!("{id}/state_check_spheres"), |b| b.iter(|| model.is_valid(std::hint::black_box(&q))));
        // 64 uniform random states within the limits (what a roadmap samples): exact and model.
        let limits = instance.group.limits(&instance.robot);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let states: Vec<Vec<f64>> =
            (0..64).map(|_| limits.iter().map(|(lo, hi)| rng.random_range(*lo..=*hi)).collect()).collect();
        for (row, checker) in [("random64_exact", &*instance.checker), ("random64_spheres", model)] {
            c.bench_function(&format!("{id}/state_check_{row}"), |b| {
                b.iter(|| states.iter().filter(|q| checker.is_valid(q)).count())
            });
        }
    }
}

/// RRT-Connect planning time per MBM set, cycling over the set's problems (failures within
/// the time limit are timed too), and one state check at the first problem's start: on the
/// meshes (exact checker), and on the Panda's layered greedy sphere cover
/// (`LoadedProblemSet::layered_sphere_model`, default options; graded by the meshes in the
/// runner), one state at a time and in batches of 64 random states.
fn mbm_panda(c: &mut Criterion) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../opengrasp-motion/tests/data/mbm/panda/problems");
    let sets = load_problem_sets(dir).expect("vendored MBM sets");
    let spheres_model = Arc::new(sets[0].layered_sphere_model(GreedyCoverOptions::default()).expect("cover"));
    let model = PlanningModel::Spheres(spheres_model.clone());
    // The same model checking every state of a motion (no certificates): the reference.
    let uncertified = PlanningModel::Spheres(Arc::new(spheres_model.as_ref().clone().with_certified_motions(false)));
    for set in &sets {
        let instances: Vec<_> =
            (0..set.len()).map(|i| set.instance_with(i, &model).expect("problem instance")).collect();
        let uncertified: Vec<_> =
            (0..set.len()).map(|i| set.instance_with(i, &uncertified).expect("problem instance")).collect();
        // `rrt_connect_spheres_vamp_like`: the problem-set settings (tree balancing, range 1.0).
        for (row, on_spheres, instances, options) in [
            ("rrt_connect_plan", false, &instances, RrtConnectOptions::default()),
            ("rrt_connect_spheres", true, &instances, RrtConnectOptions::default()),
            ("rrt_connect_spheres_uncertified", true, &uncertified, RrtConnectOptions::default()),
            ("rrt_connect_spheres_vamp_like", true, &instances, RrtConnectOptions::vamp_like()),
        ] {
            let mut planner = RrtConnect::new(options);
            let mut k = 0usize;
            c.bench_function(&format!("mbm/{}/{row}", set.name()), |b| {
                b.iter(|| {
                    k += 1;
                    let instance = &instances[k % instances.len()];
                    let checker = if on_spheres { instance.planner_checker() } else { &*instance.checker };
                    let problem = instance.problem(checker, Duration::from_secs(10), k as u64, 0.02);
                    planner.plan(&problem).is_ok()
                })
            });
        }
        let first = &instances[0];
        c.bench_function(&format!("mbm/{}/validity_check", set.name()), |b| {
            b.iter(|| first.checker.is_valid(std::hint::black_box(&first.start)))
        });
        let spheres = first.planner_checker();
        c.bench_function(&format!("mbm/{}/state_check_spheres", set.name()), |b| {
            b.iter(|| spheres.is_valid(std::hint::black_box(&first.start)))
        });
        // 64 random states (seeded) within the joint limits, checked in one call.
        let limits = first.group.limits(&first.robot);
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let states: Vec<f64> =
            (0..64).flat_map(|_| limits.iter().map(|l| rng.random_range(l.0..=l.1)).collect::<Vec<_>>()).collect();
        let mut out = vec![false; 64];
        let lanes = set.sphere_world(0, &spheres_model).expect("sphere world").with_batched_checks(true);
        for (row, checker) in [("state_check_spheres_batch64", spheres), ("state_check_spheres_batch64_lanes", &lanes)]
        {
            c.bench_function(&format!("mbm/{}/{row}", set.name()), |b| {
                b.iter(|| {
                    checker.are_valid(std::hint::black_box(&states), &mut out);
                    out.iter().filter(|&&v| v).count()
                })
            });
        }
        // The same 64 states one `is_valid` call at a time: the reference of the batch row.
        c.bench_function(&format!("mbm/{}/state_check_spheres_one_by_one64", set.name()), |b| {
            b.iter(|| states.chunks(limits.len()).filter(|q| spheres.is_valid(std::hint::black_box(q))).count())
        });
        // 32 motions of length 0.5 (the planner's range) from random states, at step 0.02:
        // certified (default), every state, batched coarse to fine, and one state at a time in
        // the same order.
        let motions: Vec<(Vec<f64>, Vec<f64>)> = states
            .chunks(limits.len())
            .zip(states.chunks(limits.len()).skip(32))
            .map(|(a, b)| {
                let d = opengrasp_motion::validate::distance(a, b);
                (a.to_vec(), a.iter().zip(b).map(|(x, y)| x + 0.5 / d * (y - x)).collect())
            })
            .collect();
        let one_by_one = OneByOne(spheres);
        let every_state = set.sphere_world(0, &spheres_model).expect("sphere world").with_certified_motions(false);
        for (row, checker) in [
            ("motion_check_spheres", spheres),
            ("motion_check_spheres_uncertified", &every_state),
            ("motion_check_spheres_lanes", &lanes),
            ("motion_check_spheres_one_by_one", &one_by_one),
        ] {
            c.bench_function(&format!("mbm/{}/{row}", set.name()), |b| {
                b.iter(|| motions.iter().filter(|(a, b)| checker.is_motion_valid(a, b, 0.02)).count())
            });
        }
    }
}

/// Post-processing (repair + shortcut as `run_once` runs it, with the benchmark's options) of
/// the RRT-Connect paths of 10 seeds on kitchen scene 1, cycling: `postprocess/scene1` with
/// the scene's certifier (the harness's way), `postprocess/scene1_exact` without (the same
/// paths, exact checks only); and one whole Clean the Table episode (RRT-Connect, seed 0:
/// planning, post-processing and grading of its 8 queries), `postprocess/clean_table_episode`.
fn postprocess_rows(c: &mut Criterion) {
    let instance = (armar_standard_scene().generate)(0).expect("scene instance");
    let options = BenchmarkOptions::default();
    let paths = rrt_connect_paths(&instance, 10);
    let limits = instance.group.limits(&instance.robot);
    for (row, certifier) in [("scene1", instance.certifier.as_deref()), ("scene1_exact", None)] {
        let mut k = 0usize;
        c.bench_function(&format!("postprocess/{row}"), |b| {
            b.iter(|| {
                k = (k + 1) % paths.len();
                let so = postprocessing_options(&options, k as u64);
                let (repaired, _) = repair_with(&*instance.checker, certifier, &paths[k], &limits, &so);
                shortcut_with(&*instance.checker, certifier, &repaired, &so)
            })
        });
    }
    let mut group = c.benchmark_group("postprocess");
    group.sample_size(10);
    group.bench_function("clean_table_episode", |b| {
        b.iter(|| {
            let mut planner = RrtConnect::default();
            clean_the_table(&mut planner, &CleanTheTableOptions::default()).expect("episode").totals.cleaned
        })
    });
    group.finish();
}

fn motion(c: &mut Criterion) {
    postprocess_rows(c);
    bench_scene(c, "armar_kitchen", armar_standard_scene());
    bench_scene(c, "seven_dof_cupboard", standard_scene(CheckerKind::Exact));
    mbm_panda(c);
}

criterion_group!(benches, motion);
criterion_main!(benches);
