//! Benchmarks of opengrasp-grasp: one candidate through the shared grasp evaluator (place,
//! retract, close, contacts, quality) on the salt can with and without the 6-D hull and on the
//! non-convex detergent bottle, and candidate generation
//! of the two reference planners. Inputs are deterministic (fixed candidates, seed 0).
//!
//! Run briefly with `cargo bench -p opengrasp-grasp --bench grasp -- --warm-up-time 1 --measurement-time 3`.

use std::hint::black_box;

use criterion::{criterion_main, Criterion};
use opengrasp_assets::{hands, objects};
use opengrasp_grasp::evaluator::{EvaluatorOptions, GraspEvaluator};
use opengrasp_grasp::planners::{GraspPlanner, GraspRequest, MedialAxisPlanner, SurfaceNormalPlanner};

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
            let label = format!("evaluate/{name}/salt_can/{}", if hull { "all metrics" } else { "no hull" });
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
    criterion::criterion_group!(benches, super::evaluation, super::planning);
}
criterion_main!(group::benches);
