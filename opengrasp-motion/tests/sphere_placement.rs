//! The sphere model places what a state check reads only when a test first reads it (a
//! cluster's spheres once its bounding sphere is not clear, the coarse cover's link bounding
//! spheres once a pair test needs them): its verdicts must still be those of its closed-form
//! distances, which place every sphere.

use std::path::PathBuf;

use opengrasp_motion::problem_set::{self, LoadedProblemSet};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::{MeshCover, StateValidityChecker};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn cage() -> LoadedProblemSet {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda/problems");
    let sets = problem_set::load(dir).unwrap();
    let cage = sets.iter().find(|s| s.name.contains("cage")).unwrap();
    LoadedProblemSet::new(cage).unwrap()
}

/// The Panda's greedy cover (several clusters per link) in the first cage problem: on 400
/// random states a state is valid exactly when every link distance (boxes, and half the
/// self-collision gaps) is positive, the state certificate gives the same verdict and one
/// non-negative gap per test, and the layered model (coarse cover first) never refuses a
/// state the fine cover accepts.
#[test]
fn lazily_placed_spheres_give_the_verdicts_of_the_distances() {
    let set = cage();
    let fine =
        set.sphere_world(0, &set.sphere_model(MeshCover::Greedy(GreedyCoverOptions::default())).unwrap()).unwrap();
    let layered = set.sphere_world(0, &set.layered_sphere_model(GreedyCoverOptions::default()).unwrap()).unwrap();
    let limits = fine.group().limits(fine.robot());
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let (mut valid, mut invalid) = (0, 0);
    let (mut d, mut gaps) = (Vec::new(), Vec::new());
    for _ in 0..400 {
        let q: Vec<f64> = limits.iter().map(|&(lo, hi)| rng.random_range(lo..hi)).collect();
        assert!(fine.link_distances(&q, &mut d));
        let min = d.iter().copied().fold(f64::INFINITY, f64::min);
        let ok = fine.is_valid(&q);
        // Away from contact (the rounding of the two formulas aside) the verdicts agree.
        if min.abs() > 1e-9 {
            assert_eq!(ok, min > 0.0, "q = {q:?}, least distance {min}");
        }
        assert_eq!(fine.state_certificate(&q, &mut gaps), ok);
        assert!(if ok { !gaps.is_empty() && gaps.iter().all(|&g| g >= 0.0) } else { gaps.is_empty() });
        if ok {
            assert!(layered.is_valid(&q));
        }
        if ok {
            valid += 1;
        } else {
            invalid += 1;
        }
    }
    assert!(valid >= 40 && invalid >= 40, "{valid} valid, {invalid} invalid");
}
