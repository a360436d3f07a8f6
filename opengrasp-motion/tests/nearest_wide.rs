//! The kd-tree's nearest-neighbour query keeps its per-axis offsets on the stack up to 32
//! axes and on the heap beyond: both paths answer exactly as the linear scan (ties included).

use opengrasp_motion::nearest::{KdTree, LinearScan, NearestNeighbors};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn kd_nearest_equals_linear_scan_below_and_above_32_axes() {
    for dim in [1, 7, 32, 33, 40] {
        let mut rng = ChaCha8Rng::seed_from_u64(dim as u64);
        let (mut kd, mut lin) = (KdTree::new(dim), LinearScan::new(dim));
        // Coordinates on a coarse grid: many exact ties, which go to the lowest index.
        let mut point = || (0..dim).map(|_| f64::from(rng.random_range(-2i32..=2)) * 0.5).collect::<Vec<f64>>();
        for _ in 0..400 {
            let p = point();
            assert_eq!(kd.add(&p).unwrap(), lin.add(&p).unwrap());
        }
        let mut differ = 0;
        for _ in 0..200 {
            let q = point();
            let (a, b) = (kd.nearest(&q).unwrap(), lin.nearest(&q).unwrap());
            assert_eq!(a, b, "dim {dim}");
            differ += usize::from(a != Some(0));
        }
        assert!(differ > 0, "dim {dim}: every query answered by node 0");
    }
    assert_eq!(KdTree::new(40).nearest(&[0.0; 40]).unwrap(), None);
}
