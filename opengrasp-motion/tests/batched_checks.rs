//! The batched checks of the sphere model (`SphereWorld::are_valid` and
//! `SphereWorld::check_motion`, one state at a time on the compiled kernels or, with
//! `with_batched_checks`, several states per kernel call) give exactly the verdicts — and for
//! motions the state counts — of checking the same states one by one through `is_valid`.

use std::sync::{Arc, OnceLock};

mod arm_world;

use opengrasp_core::model::{JointGroup, Robot};
use opengrasp_motion::problem_set::{self, LoadedProblemSet};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::{CountingChecker, OneByOne, SphereWorld, StateValidityChecker};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The sample arm among every closed-form shape, plain and layered.
fn arm_worlds() -> &'static (Arc<Robot>, JointGroup, SphereWorld, SphereWorld) {
    static WORLDS: OnceLock<(Arc<Robot>, JointGroup, SphereWorld, SphereWorld)> = OnceLock::new();
    WORLDS.get_or_init(arm_world::arm_among_shapes)
}

fn random_q(rng: &mut ChaCha8Rng, limits: &[(f64, f64)]) -> Vec<f64> {
    limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect()
}

/// `are_valid` and `check_motion` of `world`, plain and batched, against the one-by-one
/// defaults, on `n` random
/// states and motions from `seed` (motion lengths up to `reach` per joint, steps from 0.005 to
/// 0.1). Returns how many motions were valid and invalid, so a caller can see both occur.
fn compare(world: &SphereWorld, limits: &[(f64, f64)], seed: u64, n: usize, reach: f64) -> (usize, usize) {
    let plain = OneByOne(world);
    let lanes = world.clone().with_batched_checks(true);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let dim = world.dim();
    // Batches of every length from 0 to 2 full batches and more.
    let count = rng.random_range(0..20);
    let states: Vec<f64> = (0..count).flat_map(|_| random_q(&mut rng, limits)).collect();
    for w in [world, &lanes] {
        let mut out = vec![false; count];
        w.are_valid(&states, &mut out);
        for (q, &v) in states.chunks(dim).zip(&out) {
            assert_eq!(v, world.is_valid(q), "{q:?}");
        }
    }
    let (mut valid, mut invalid) = (0, 0);
    for _ in 0..n {
        let a = random_q(&mut rng, limits);
        let b: Vec<f64> =
            a.iter().zip(limits).map(|(&x, &(lo, hi))| (x + rng.random_range(-reach..=reach)).clamp(lo, hi)).collect();
        let step = rng.random_range(0.005..0.1);
        let batched = lanes.check_motion(&a, &b, step);
        assert_eq!(batched, plain.check_motion(&a, &b, step), "{a:?} → {b:?} at {step}");
        assert_eq!(batched, world.check_motion(&a, &b, step));
        assert_eq!(batched.0, lanes.is_motion_valid(&a, &b, step));
        if batched.0 {
            valid += 1;
        } else {
            invalid += 1;
        }
    }
    (valid, invalid)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Random motions and batches on the sample arm, plain and layered: same verdicts, same
    /// counts as one by one.
    #[test]
    fn batched_checks_equal_one_by_one_checks(seed in 0u64..1_000_000, reach in 0.01f64..2.0) {
        let (robot, group, world, layered) = arm_worlds();
        let limits = group.limits(robot);
        compare(world, &limits, seed, 8, reach);
        compare(layered, &limits, seed, 8, reach);
    }
}

/// Both verdicts occur in the comparison on the sample arm (so it can fail), and a counting
/// wrapper counts what the one-by-one check would.
#[test]
fn batched_motion_checks_see_valid_and_invalid_motions_and_count_like_one_by_one() {
    let (robot, group, world, layered) = arm_worlds();
    let limits = group.limits(robot);
    for w in [world, layered] {
        let (valid, invalid) = compare(w, &limits, 11, 400, 0.6);
        println!("{valid} valid, {invalid} invalid motions");
        assert!(valid > 20 && invalid > 20, "{valid} valid, {invalid} invalid");
    }
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let counter = CountingChecker::new(world);
    let mut expected = 0;
    for _ in 0..50 {
        let (a, b) = (random_q(&mut rng, &limits), random_q(&mut rng, &limits));
        let (verdict, states) = OneByOne(world).check_motion(&a, &b, 0.02);
        assert_eq!(counter.is_motion_valid(&a, &b, 0.02), verdict);
        expected += states;
    }
    assert_eq!(counter.checks(), expected);
    assert!(expected > 50);
}

/// The MotionBenchMaker Panda on its layered greedy sphere model (coarse cover first, SRDF
/// pairs), in every vendored problem: batched motion checks equal one-by-one checks.
#[test]
fn panda_batched_motion_checks_equal_one_by_one_checks() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda/problems");
    let sets: Vec<LoadedProblemSet> =
        problem_set::load(dir).unwrap().iter().map(|s| LoadedProblemSet::new(s).unwrap()).collect();
    let model = sets[0].layered_sphere_model(GreedyCoverOptions::default()).unwrap();
    let (mut valid, mut invalid) = (0, 0);
    for set in &sets {
        for i in 0..set.len() {
            let world = set.sphere_world(i, &model).unwrap();
            let limits = world.group().limits(world.robot());
            let (v, n) = compare(&world, &limits, i as u64, 40, 0.5);
            valid += v;
            invalid += n;
        }
    }
    println!("{valid} valid, {invalid} invalid motions");
    assert!(valid > 20 && invalid > 20, "{valid} valid, {invalid} invalid");
}
