//! Pair distance tables of the sphere model (`SphereWorld::with_pair_tables`, on in the
//! layered problem-set model):
//! a link pair whose relative pose depends on at most two joints is settled from a table of
//! sound lower bounds over those joints' values. A table entry must never exceed the pair's
//! sphere distance, and the verdicts and state counts must be exactly those without tables.

use std::sync::OnceLock;

use opengrasp_motion::problem_set::{self, LoadedProblemSet};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::{SphereWorld, StateValidityChecker};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The vendored MotionBenchMaker Panda sets and their layered greedy sphere model.
fn panda() -> &'static (Vec<LoadedProblemSet>, SphereWorld) {
    static PANDA: OnceLock<(Vec<LoadedProblemSet>, SphereWorld)> = OnceLock::new();
    PANDA.get_or_init(|| {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda/problems");
        let sets: Vec<LoadedProblemSet> =
            problem_set::load(dir).unwrap().iter().map(|s| LoadedProblemSet::new(s).unwrap()).collect();
        let model = sets[0].layered_sphere_model(GreedyCoverOptions::default()).unwrap();
        (sets, model)
    })
}

fn random_q(rng: &mut ChaCha8Rng, limits: &[(f64, f64)]) -> Vec<f64> {
    limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect()
}

/// The Panda's tabled pairs: link 5 against the links on joint 7's frame (link 7, the hand,
/// the fingers), through joints 6 and 7.
#[test]
fn panda_tables_cover_the_wrist_pairs() {
    let (_, model) = panda();
    let q = vec![0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8];
    let pairs: Vec<(String, String)> = model
        .pair_table_bounds(&q)
        .iter()
        .map(|&(a, b, _, _)| (model.robot().link(a).name.clone(), model.robot().link(b).name.clone()))
        .collect();
    println!("{pairs:?}");
    assert!(pairs.iter().any(|(a, b)| a == "panda_link5" && b == "panda_link7"), "{pairs:?}");
    assert!(pairs.iter().any(|(a, b)| a == "panda_link5" && b == "panda_hand"), "{pairs:?}");
    assert_eq!(model.pair_table_count(), pairs.len());
    assert_eq!(model.clone().with_pair_tables(false).pair_table_count(), 0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]
    /// At random configurations of the Panda, with the wrist joints also drawn near where
    /// the wrist pairs come close: every table bound is at most the pair's sphere distance
    /// (computed with the robot's own kinematics), and a pair more than 6 mm apart is settled
    /// (a cell's bound loses at most twice the motion in the cell, 4 mm on the Panda).
    #[test]
    fn panda_table_bounds_are_sound_and_settle_clear_pairs(seed in 0u64..1_000_000) {
        let (_, model) = panda();
        let limits = model.group().limits(model.robot());
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (mut settled, mut clear) = (0, 0);
        for _ in 0..200 {
            let q = random_q(&mut rng, &limits);
            for (a, b, d, g) in model.pair_table_bounds(&q) {
                if let Some(g) = g {
                    prop_assert!(g > 0.0 && g <= d, "{a:?}-{b:?} at {q:?}: bound {g} > distance {d}");
                    settled += 1;
                }
                if d > 6e-3 {
                    clear += 1;
                    prop_assert!(g.is_some(), "{a:?}-{b:?} at {q:?}: not settled at distance {d}");
                }
            }
        }
        prop_assert!(settled >= clear && clear > 200, "{settled} settled, {clear} clear");
    }
}

/// In every vendored problem, states and planner-like motions (up to 0.5 rad per joint at
/// step 0.02) drawn near the wrist's self-contact (joint 6 near its lower limit, where link 7
/// folds onto link 5): the same verdicts and counts with and without tables, with states
/// the tables settle and wrist collisions among them.
#[test]
fn panda_checks_with_tables_equal_checks_without() {
    let (sets, model) = panda();
    let limits = model.group().limits(model.robot());
    let (mut settled, mut invalid, mut motions) = (0, 0, 0);
    for set in sets {
        for i in 0..set.len() {
            let world = set.sphere_world(i, model).unwrap();
            let plain = world.clone().with_pair_tables(false);
            assert!(world.pair_table_count() > 0 && plain.pair_table_count() == 0);
            let mut rng = ChaCha8Rng::seed_from_u64(i as u64);
            for _ in 0..100 {
                let mut a = random_q(&mut rng, &limits);
                // Half the draws put joint 6 within 0.6 rad of its lower limit.
                if rng.random_bool(0.5) {
                    a[5] = limits[5].0 + rng.random_range(0.0..0.6);
                }
                let b: Vec<f64> = a
                    .iter()
                    .zip(&limits)
                    .map(|(&x, &(lo, hi))| (x + rng.random_range(-0.5..=0.5)).clamp(lo, hi))
                    .collect();
                assert_eq!(world.is_valid(&a), plain.is_valid(&a), "{a:?}");
                invalid += usize::from(!world.is_valid(&a));
                settled += world.pair_table_bounds(&a).iter().filter(|p| p.3.is_some()).count();
                if world.is_valid(&a) {
                    motions += 1;
                    assert_eq!(world.check_motion(&a, &b, 0.02), plain.check_motion(&a, &b, 0.02), "{a:?} → {b:?}");
                }
            }
        }
    }
    println!("{settled} settled pairs, {invalid} invalid states, {motions} motions");
    assert!(settled > 1000 && invalid > 100 && motions > 300, "{settled} {invalid} {motions}");
}
