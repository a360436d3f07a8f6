//! Benchmarks of the tactile model: one contact mapped onto a DSA 9335 (6 × 14 cells), and a
//! full Schunk SDH tactile frame (6 pads) from the contacts of one rapier step of the SDH
//! squeezing a 6 cm cylinder. Inputs are deterministic.
//!
//! Run with `cargo bench -p opengrasp-grasp --bench tactile -- --warm-up-time 1 --measurement-time 3`.

use std::hint::black_box;

use criterion::{criterion_main, Criterion};
use nalgebra::{Isometry3, Point3, Unit, Vector3};
use opengrasp_assets::hands;
use opengrasp_core::model::LinkId;
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::{PhysicsEngine, RapierBackend};
use opengrasp_grasp::evaluator::{hand_info, EvaluatorOptions, GraspEvaluator};
use opengrasp_grasp::planners::{palm_pose, GraspCandidate, Preshape};
use opengrasp_grasp::tactile::sources::{squeeze_engine, PhysicsTactile, TactileSeriesOptions};
use opengrasp_grasp::tactile::{
    LinkContact, MatrixPad, PadReading, TactileArray, TactileFrame, TactileSensor, DSA_9335,
};

#[path = "../tests/common/mod.rs"]
mod common;

fn one_contact(c: &mut Criterion) {
    let pad = MatrixPad::new("proximal", LinkId(0), Isometry3::identity(), DSA_9335).expect("pad");
    // 2 N between cells (the patch covers 2 × 2 cells).
    let contact = [LinkContact::point(LinkId(0), Point3::new(0.0, 0.0034, 0.0238), 2.0)];
    let mut reading = PadReading::default();
    c.bench_function("tactile/one contact on a DSA 9335 (6x14)", |b| {
        b.iter(|| {
            pad.read(black_box(&contact), &mut reading);
            black_box(reading.raw[0])
        })
    });
}

fn sdh_frame(c: &mut Criterion) {
    let hand = hands::sdh();
    let info = hand_info(&hand).expect("hand info");
    let object = ObjectModel::from_mesh("can", common::cylinder_mesh(0.03, 0.2, 48), 0.1, 0.8).expect("object");
    let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).expect("evaluator");
    let approach = Unit::new_normalize(-Vector3::x());
    let candidate = GraspCandidate {
        hand_pose: palm_pose(&info, &Point3::origin(), &approach, &Vector3::y()),
        preshape: Preshape::Default,
        approach,
        standoff: 0.02,
    };
    let evaluation = ev.evaluate(&candidate).expect("evaluation");
    let array = TactileArray::stock(&hand).expect("stock SDH pads");
    let options = TactileSeriesOptions::default();
    let (mut engine, rid) = squeeze_engine::<RapierBackend>(&hand, &object, &evaluation, &options).expect("simulation");
    engine.step_n(48, options.physics.timestep).expect("steps");
    let contacts = engine.contacts();
    let mut reader = PhysicsTactile::new();
    let mut frame = TactileFrame::default();
    reader.read(&array, &engine, rid, &contacts, &mut frame).expect("frame");
    let lit = frame.pads.iter().filter(|p| p.active_cells() > 0).count();
    eprintln!("SDH frame: {} physics contacts, {lit} of 6 pads lit", contacts.len());
    c.bench_function("tactile/SDH frame from one physics step (given contacts)", |b| {
        b.iter(|| {
            reader.read(&array, &engine, rid, black_box(&contacts), &mut frame).expect("frame");
            black_box(frame.pads[0].raw[0])
        })
    });
    c.bench_function("tactile/SDH frame from one physics step (with engine.contacts())", |b| {
        b.iter(|| {
            let contacts = engine.contacts();
            reader.read(&array, &engine, rid, &contacts, &mut frame).expect("frame");
            black_box(frame.pads[0].raw[0])
        })
    });
}

mod group {
    // `criterion_group!` generates an undocumented public function.
    #![allow(missing_docs)]
    criterion::criterion_group!(benches, super::one_contact, super::sdh_frame);
}
criterion_main!(group::benches);
