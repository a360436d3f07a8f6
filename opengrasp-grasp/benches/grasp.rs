//! Benchmarks of opengrasp-grasp: one candidate through the shared grasp evaluator (place,
//! retract, close, contacts, quality) on the salt can with and without the 6-D hull and on the
//! non-convex detergent bottle; the evaluation throughput on a mix of candidates like the
//! default suite's (`throughput/…`, reported in candidates per second on one core); the 6-D
//! hull of the force-closure grasps of that mix, optimised builder against the previous one
//! (`hull6d/…`); the force-closure LP and min-norm programs of that mix, dense solvers against
//! clarabel (`fc_solvers/…`); and candidate generation of the two reference planners. Inputs are
//! deterministic (fixed candidates, seed 0).
//!
//! Run briefly with `cargo bench -p opengrasp-grasp --bench grasp -- --warm-up-time 1 --measurement-time 3`.

mod mix;

use std::hint::black_box;

use criterion::{criterion_main, Criterion, Throughput};
use mix::suite_mix;
use opengrasp_assets::{hands, objects};
use opengrasp_grasp::evaluator::{EvaluatorOptions, GraspEvaluator};
use opengrasp_grasp::planners::{GraspPlanner, GraspRequest, MedialAxisPlanner, SurfaceNormalPlanner};
use opengrasp_grasp::quality::solver;
use opengrasp_grasp::{ContactModel, ConvexHull, GraspWrenchSpace, HullOptions, ObjectFrame, Wrench};

/// Evaluation throughput on the suite mix: one iteration evaluates every candidate once.
fn throughput(c: &mut Criterion) {
    let mut mix = suite_mix();
    let n: usize = mix.iter().map(|m| m.2.len()).sum();
    let mut group = c.benchmark_group("throughput");
    group.throughput(Throughput::Elements(n as u64));
    group.sample_size(10);
    group.bench_function(format!("suite_mix_{n}"), |b| {
        b.iter(|| {
            for (ev, _, candidates) in &mut mix {
                for candidate in candidates.iter() {
                    black_box(ev.evaluate(candidate).expect("evaluation"));
                }
            }
        })
    });
    group.finish();
}

/// The primitive wrenches of every grasp of the mix, with the grasp's force-closure verdict.
fn mix_wrench_sets() -> Vec<(bool, Vec<Wrench>)> {
    let mut sets = Vec::new();
    for (ev, object, candidates) in &mut suite_mix() {
        let frame = ObjectFrame::from_points(object.center_of_mass(), object.mesh.vertices()).expect("frame");
        let model = ContactModel { friction: object.friction, ..ContactModel::default() };
        for candidate in candidates.iter() {
            let e = ev.evaluate(candidate).expect("evaluation");
            let contacts: Vec<_> = e.contacts.iter().map(|c| c.contact).collect();
            let ws = GraspWrenchSpace::new(&contacts, &frame, &model).expect("wrench space");
            sets.push((e.force_closure(), ws.wrenches().to_vec()));
        }
    }
    sets
}

/// The 6-D hulls of the mix's force-closure grasps (the optimised builder and the previous
/// one), and their Ferrari-Canny epsilon by the depth search without the hull.
fn hull6d(c: &mut Criterion) {
    let sets: Vec<Vec<f64>> = mix_wrench_sets()
        .into_iter()
        .filter(|(fc, _)| *fc)
        .map(|(_, w)| w.iter().flat_map(|w| w.iter().copied()).collect())
        .collect();
    let mut group = c.benchmark_group("hull6d");
    group.throughput(Throughput::Elements(sets.len() as u64));
    group.sample_size(10);
    let options = HullOptions::default();
    group.bench_function(format!("suite_fc_{}/optimised", sets.len()), |b| {
        b.iter(|| {
            for s in &sets {
                black_box(ConvexHull::from_flat(6, s, &options).expect("hull"));
            }
        })
    });
    group.bench_function(format!("suite_fc_{}/epsilon_search", sets.len()), |b| {
        b.iter(|| {
            for s in &sets {
                black_box(ConvexHull::depth_flat(6, s, &options, &[0.0; 6]).expect("depth"));
            }
        })
    });
    group.bench_function(format!("suite_fc_{}/reference", sets.len()), |b| {
        b.iter(|| {
            for s in &sets {
                black_box(ConvexHull::from_flat_reference(6, s, &options).expect("hull"));
            }
        })
    });
    group.finish();
}

/// The force-closure programs of every closed grasp of the mix: the strict LP, and the
/// min-norm distance where the LP finds no strict margin (as the evaluator runs them), solved
/// by the dense solvers and by clarabel in the same process.
fn fc_solvers(c: &mut Criterion) {
    let sets: Vec<Vec<Wrench>> = mix_wrench_sets()
        .into_iter()
        .filter(|(_, w)| GraspWrenchSpace::from_wrenches(w.clone()).expect("wrenches").affine_rank(1e-9) == 6)
        .map(|(_, w)| w)
        .collect();
    let mut group = c.benchmark_group("fc_solvers");
    group.throughput(Throughput::Elements(sets.len() as u64));
    group.sample_size(10);
    group.bench_function(format!("suite_{}/dense", sets.len()), |b| {
        b.iter(|| {
            for w in &sets {
                if solver::strict_combination_vertex(w).expect("lp").margin <= 1e-6 {
                    black_box(solver::min_norm_distance(w).expect("qp"));
                }
            }
        })
    });
    group.bench_function(format!("suite_{}/clarabel", sets.len()), |b| {
        b.iter(|| {
            for w in &sets {
                if solver::strict_combination(w).expect("lp").margin <= 1e-6 {
                    black_box(solver::min_norm_point(w).expect("qp").distance);
                }
            }
        })
    });
    group.finish();
}

fn evaluation(c: &mut Criterion) {
    let object = objects::by_name("salt_can").expect("stock object");
    for (name, hand) in [("barrett", hands::barrett()), ("armar3", hands::armar3_hand())] {
        for hull in [true, false] {
            let mut options = EvaluatorOptions::default();
            options.quality.compute_hull = hull;
            let mut ev = GraspEvaluator::new(&hand, &object, options).expect("evaluator");
            let info = ev.hand_info().clone();
            let candidates = MedialAxisPlanner::default()
                .plan(&GraspRequest { hand: &info, object: &object.mesh, seed: 0 })
                .expect("candidates");
            let mut k = 0;
            let label = format!("evaluate/{name}/salt_can/{}", if hull { "epsilon" } else { "no epsilon" });
            c.bench_function(&label, |b| {
                b.iter(|| {
                    k = (k + 1) % candidates.len();
                    black_box(ev.evaluate(&candidates[k]).expect("evaluation"))
                })
            });
        }
    }
    // A non-convex object (exact triangle-mesh distances near the surface while closing).
    let object = objects::by_name("detergent_bottle").expect("stock object");
    for (name, hand) in [("barrett", hands::barrett()), ("armar3", hands::armar3_hand())] {
        let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).expect("evaluator");
        let info = ev.hand_info().clone();
        let candidates = SurfaceNormalPlanner::default()
            .plan(&GraspRequest { hand: &info, object: &object.mesh, seed: 0 })
            .expect("candidates");
        let mut k = 0;
        c.bench_function(&format!("evaluate/{name}/detergent_bottle/all metrics"), |b| {
            b.iter(|| {
                k = (k + 7) % candidates.len();
                black_box(ev.evaluate(&candidates[k]).expect("evaluation"))
            })
        });
    }
}

fn planning(c: &mut Criterion) {
    let object = objects::by_name("salt_can").expect("stock object");
    let hand = hands::barrett();
    let info = opengrasp_grasp::evaluator::hand_info(&hand).expect("hand info");
    let request = GraspRequest { hand: &info, object: &object.mesh, seed: 0 };
    c.bench_function("plan/surface-normals/salt_can", |b| {
        b.iter(|| black_box(SurfaceNormalPlanner::default().plan(&request).expect("plan")))
    });
    c.bench_function("plan/medial-axis/salt_can", |b| {
        b.iter(|| black_box(MedialAxisPlanner::default().plan(&request).expect("plan")))
    });
}

mod group {
    // `criterion_group!` generates an undocumented public function.
    #![allow(missing_docs)]
    criterion::criterion_group!(
        benches,
        super::evaluation,
        super::throughput,
        super::hull6d,
        super::fc_solvers,
        super::planning
    );
}
criterion_main!(group::benches);
