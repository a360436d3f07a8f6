//! Certified motion checks of the sphere model (`SphereWorld::with_certified_motions`, the
//! default): a test that passes at a state with some sphere distance is skipped at the states
//! of the motion its links cannot reach. The verdicts and state counts must be exactly those
//! of checking every state one by one, in particular for motions whose end states are valid
//! but which pass through an obstacle or through the robot itself (where an unsound
//! certificate would wrongly accept). The same holds for motions checked with their end
//! states' certificates (`is_motion_valid_between`).

use std::sync::{Arc, OnceLock};

mod arm_world;

use opengrasp_core::model::{JointGroup, Robot};
use opengrasp_motion::problem_set::{self, LoadedProblemSet};
use opengrasp_motion::validate::distance;
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::{OneByOne, SphereWorld, StateValidityChecker};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The sample arm among every closed-form shape, plain and layered.
fn arm_worlds() -> &'static (Arc<Robot>, JointGroup, [SphereWorld; 2]) {
    static WORLDS: OnceLock<(Arc<Robot>, JointGroup, [SphereWorld; 2])> = OnceLock::new();
    WORLDS.get_or_init(|| {
        let (robot, group, world, layered) = arm_world::arm_among_shapes();
        (robot, group, [world, layered])
    })
}

fn random_q(rng: &mut ChaCha8Rng, limits: &[(f64, f64)]) -> Vec<f64> {
    limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect()
}

/// Tallies of a comparison: valid motions, motions rejected at an end state, and motions with
/// both end states valid rejected in between (the cases certificates could get wrong).
#[derive(Debug, Default)]
struct Tally {
    valid: usize,
    end_invalid: usize,
    passes_through: usize,
}

/// `check_motion` certified (default) against uncertified and one by one, on `n` random
/// motions from valid states of `world` (lengths up to `reach` per joint, steps `steps`; with
/// `most`, motions are shortened to at most that many steps, e.g. 62: one word of certificate
/// bits).
fn compare(world: &SphereWorld, seed: u64, n: usize, reach: f64, steps: (f64, f64), most: Option<f64>) -> Tally {
    let limits = world.group().limits(world.robot());
    let plain = world.clone().with_certified_motions(false);
    let one_by_one = OneByOne(world);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut tally = Tally::default();
    let mut tries = 0;
    while tally.valid + tally.end_invalid + tally.passes_through < n && tries < 100 * n {
        tries += 1;
        let a = random_q(&mut rng, &limits);
        if !world.is_valid(&a) {
            continue;
        }
        let mut b: Vec<f64> =
            a.iter().zip(&limits).map(|(&x, &(lo, hi))| (x + rng.random_range(-reach..=reach)).clamp(lo, hi)).collect();
        let step = rng.random_range(steps.0..steps.1);
        let length = distance(&a, &b);
        if let Some(most) = most.filter(|&m| length > m * step) {
            let t = most * step / length;
            b = a.iter().zip(&b).map(|(x, y)| x + t * (y - x)).collect();
        }
        let certified = world.check_motion(&a, &b, step);
        assert_eq!(certified, plain.check_motion(&a, &b, step), "{a:?} → {b:?} at {step}");
        assert_eq!(certified, one_by_one.check_motion(&a, &b, step), "{a:?} → {b:?} at {step}");
        assert_eq!(certified.0, world.is_motion_valid(&a, &b, step));
        // With the ends' certificates (as PRM's setup checks its edges): the same verdict.
        let (mut a_cert, mut b_cert) = (Vec::new(), Vec::new());
        assert!(world.state_certificate(&a, &mut a_cert));
        if world.state_certificate(&b, &mut b_cert) {
            assert_eq!(certified.0, world.is_motion_valid_between(&a, &a_cert, &b, &b_cert, step), "{a:?} → {b:?}");
        }
        match (certified.0, world.is_valid(&b)) {
            (true, _) => tally.valid += 1,
            (false, false) => tally.end_invalid += 1,
            (false, true) => tally.passes_through += 1,
        }
    }
    tally
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    /// Random motions on the sample arm, plain and layered, at steps that give 1 to several
    /// hundred states (certificate bits over several 64-state words): same verdicts and
    /// counts.
    #[test]
    fn certified_motion_checks_equal_one_by_one_checks(seed in 0u64..1_000_000, reach in 0.01f64..1.5) {
        let (_, _, worlds) = arm_worlds();
        for world in worlds {
            compare(world, seed, 10, reach, (0.005, 0.1), None);
        }
    }
}

/// The comparison sees many motions between valid states that pass through a collision, so
/// an unsound certificate would be caught.
#[test]
fn certified_motion_checks_reject_motions_through_collisions() {
    let (_, _, worlds) = arm_worlds();
    for world in worlds {
        let tally = compare(world, 3, 600, 1.5, (0.03, 0.06), Some(62.0));
        println!("{tally:?}");
        assert!(tally.valid > 50 && tally.passes_through > 50 && tally.end_invalid > 50, "{tally:?}");
    }
}

/// Motions of 60 to 68 steps, on both sides of the one-word bit sets (motions of fewer than
/// 64 states) and the multi-word ones: same verdicts and counts, valid motions and motions
/// through collisions among them.
#[test]
fn certified_motion_checks_across_the_word_boundary() {
    let (_, _, worlds) = arm_worlds();
    let mut total = Tally::default();
    for most in 60..=68 {
        for world in worlds {
            let tally = compare(world, most, 30, 1.5, (0.01, 0.02), Some(most as f64));
            assert_eq!(tally.valid + tally.end_invalid + tally.passes_through, 30, "{tally:?}");
            total.valid += tally.valid;
            total.passes_through += tally.passes_through;
        }
    }
    println!("{total:?}");
    assert!(total.valid > 100 && total.passes_through >= 10, "{total:?}");
}

/// The MotionBenchMaker Panda on its layered greedy sphere model (SRDF pairs), in every
/// vendored problem, with the planner's extensions (up to 0.5 rad at step 0.02): certified
/// checks equal one-by-one checks, with motions through collisions among them.
#[test]
fn panda_certified_motion_checks_equal_one_by_one_checks() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda/problems");
    let sets: Vec<LoadedProblemSet> =
        problem_set::load(dir).unwrap().iter().map(|s| LoadedProblemSet::new(s).unwrap()).collect();
    let model = sets[0].layered_sphere_model(GreedyCoverOptions::default()).unwrap();
    let mut total = Tally::default();
    for set in &sets {
        for i in 0..set.len() {
            let world = set.sphere_world(i, &model).unwrap();
            let tally = compare(&world, i as u64, 200, 1.0, (0.02, 0.0201), Some(62.0));
            total.valid += tally.valid;
            total.end_invalid += tally.end_invalid;
            total.passes_through += tally.passes_through;
        }
    }
    println!("{total:?}");
    assert!(total.valid > 100 && total.passes_through > 20 && total.end_invalid > 20, "{total:?}");
}
