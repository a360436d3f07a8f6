//! The kd-tree answers exactly as the linear scan (ties included), and the planners return the
//! same paths with either structure.

use std::sync::Arc;
use std::time::Duration;

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::model::{samples, JointGroup};
use opengrasp_motion::nearest::{KdTree, LinearScan, NearestNeighbors};
use opengrasp_motion::planners::{NeighborStructure, Prm, RrtConnect};
use opengrasp_motion::validity::{ObstacleBox, SphereWorld};
use opengrasp_motion::{Goal, MotionError, MotionPlanner, PlanningProblem, SetupContext};
use proptest::prelude::*;

fn both(dim: usize, points: &[Vec<f64>]) -> (KdTree, LinearScan) {
    let (mut kd, mut lin) = (KdTree::new(dim), LinearScan::new(dim));
    for p in points {
        assert_eq!(kd.add(p).unwrap(), lin.add(p).unwrap());
    }
    (kd, lin)
}

fn assert_same(kd: &KdTree, lin: &LinearScan, q: &[f64], k: usize, r: f64) {
    assert_eq!(kd.nearest(q).unwrap(), lin.nearest(q).unwrap());
    let (mut a, mut b) = (Vec::new(), Vec::new());
    kd.k_nearest(q, k, &mut a).unwrap();
    lin.k_nearest(q, k, &mut b).unwrap();
    assert_eq!(a, b, "k nearest, k = {k}");
    kd.within_radius(q, r, &mut a).unwrap();
    lin.within_radius(q, r, &mut b).unwrap();
    assert_eq!(a, b, "within radius {r}");
}

/// Coordinates on a coarse grid produce many exact ties.
fn coord(grid: bool) -> BoxedStrategy<f64> {
    if grid {
        (-3i32..=3).prop_map(|v| f64::from(v) * 0.5).boxed()
    } else {
        (-3.0f64..3.0).boxed()
    }
}

fn cloud() -> impl Strategy<Value = (usize, Vec<Vec<f64>>, Vec<Vec<f64>>, usize, f64)> {
    (1usize..8, any::<bool>()).prop_flat_map(|(dim, grid)| {
        (
            Just(dim),
            prop::collection::vec(prop::collection::vec(coord(grid), dim), 0..300),
            prop::collection::vec(prop::collection::vec(coord(grid), dim), 1..8),
            0usize..40,
            0.0f64..4.0,
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn kd_tree_equals_linear_scan((dim, points, queries, k, r) in cloud()) {
        let (kd, lin) = both(dim, &points);
        for q in &queries {
            assert_same(&kd, &lin, q, k, r);
        }
        // Stored points are their own nearest (lowest index among duplicates), at distance 0.
        for p in points.iter().take(20) {
            let i = lin.nearest(p).unwrap().unwrap();
            prop_assert_eq!(lin.get(i).unwrap(), p.as_slice());
            prop_assert_eq!(kd.nearest(p).unwrap(), Some(i));
        }
    }
}

#[test]
fn ties_go_to_the_lowest_index() {
    let points = vec![vec![1.0, 0.0], vec![-1.0, 0.0], vec![0.0, 1.0], vec![1.0, 0.0]];
    let (kd, lin) = both(2, &points);
    assert_eq!(kd.nearest(&[0.0, 0.0]).unwrap(), Some(0));
    let mut out = Vec::new();
    kd.k_nearest(&[0.0, 0.0], 3, &mut out).unwrap();
    assert_eq!(out, vec![(0, 1.0), (1, 1.0), (2, 1.0)]);
    kd.within_radius(&[1.0, 0.0], 0.0, &mut out).unwrap();
    assert_eq!(out, vec![(0, 0.0), (3, 0.0)]);
    assert_same(&kd, &lin, &[0.0, 0.0], 4, 1.0);
}

/// Points added in sorted order (the worst order for a tree grown by insertion) and many
/// duplicates: the depth stays logarithmic and the answers exact.
#[test]
fn sorted_and_duplicate_insertions_keep_the_tree_shallow() {
    let mut points: Vec<Vec<f64>> = (0..5000).map(|i| vec![f64::from(i) * 1e-3, 0.5]).collect();
    points.extend((0..500).map(|_| vec![2.0, 2.0]));
    let (kd, lin) = both(2, &points);
    assert!(kd.depth() <= 3 * 9 + 8, "depth {}", kd.depth());
    for q in [[0.0, 0.0], [2.5, 0.5], [2.0, 2.0], [4.9999, 0.5], [10.0, -3.0]] {
        assert_same(&kd, &lin, &q, 7, 0.01);
    }
    let mut out = Vec::new();
    kd.within_radius(&[2.0, 2.0], 0.0, &mut out).unwrap();
    assert_eq!(out.len(), 500);
    assert_eq!(out[0], (5000, 0.0));
}

#[test]
fn bad_input_is_a_typed_error() {
    let mut kd = KdTree::new(3);
    assert!(matches!(kd.add(&[0.0, 1.0]), Err(MotionError::DimensionMismatch { expected: 3, actual: 2 })));
    assert!(matches!(kd.add(&[0.0, f64::NAN, 1.0]), Err(MotionError::NonFinite { .. })));
    assert_eq!(kd.len(), 0);
    assert_eq!(kd.nearest(&[0.0; 3]).unwrap(), None);
    kd.add(&[0.0; 3]).unwrap();
    let mut out = vec![(9, 9.0)];
    assert!(matches!(kd.within_radius(&[0.0; 3], -1.0, &mut out), Err(MotionError::InvalidParameter { .. })));
    assert!(matches!(kd.k_nearest(&[0.0; 4], 1, &mut out), Err(MotionError::DimensionMismatch { .. })));
    let lin = LinearScan::new(3);
    assert!(matches!(lin.nearest(&[f64::INFINITY, 0.0, 0.0]), Err(MotionError::NonFinite { .. })));
    assert!(matches!(lin.within_radius(&[0.0; 3], f64::NAN, &mut out), Err(MotionError::InvalidParameter { .. })));
    kd.k_nearest(&[1.0, 0.0, 0.0], 0, &mut out).unwrap();
    assert!(out.is_empty());
    kd.clear();
    assert!(kd.is_empty() && kd.get(0).is_none());
}

/// RRT-Connect and PRM plan the same paths on the kd-tree and on the linear scan.
#[test]
fn planners_plan_the_same_paths_with_either_structure() {
    let robot = Arc::new(samples::seven_dof_arm().unwrap());
    let group: JointGroup = robot.group("arm").unwrap().clone();
    let q_full = robot.home_configuration();
    // The cupboard of the `validity` bench: table, shelf, divider, back wall.
    let cupboard = vec![
        ObstacleBox::new("table", Isometry3::translation(0.65, 0.0, 0.225), Vector3::new(0.6, 1.2, 0.05)),
        ObstacleBox::new("shelf", Isometry3::translation(0.65, 0.0, 0.85), Vector3::new(0.6, 1.2, 0.04)),
        ObstacleBox::new("divider", Isometry3::translation(0.7, 0.0, 0.54), Vector3::new(0.5, 0.04, 0.58)),
        ObstacleBox::new("back", Isometry3::translation(0.97, 0.0, 0.54), Vector3::new(0.04, 1.2, 0.58)),
    ];
    let world =
        SphereWorld::new(robot.clone(), group.clone(), q_full.clone(), Isometry3::identity(), cupboard).unwrap();
    let start = [1.4175, 1.026, -1.5041, 1.5464, -0.1228, -0.1075, 1.1446];
    let goal = Goal::Configuration(vec![-1.4175, 1.026, 1.5041, 1.5464, 0.1228, -0.1075, -1.1446]);
    let mut iterations = 0;
    for seed in 0..6 {
        let problem = PlanningProblem {
            robot: &robot,
            group: &group,
            q_full: &q_full,
            start: &start,
            goal: &goal,
            checker: &world,
            time_limit: Duration::from_secs(30),
            seed,
            step: 0.02,
        };
        let mut paths = Vec::new();
        for neighbors in [NeighborStructure::KdTree, NeighborStructure::LinearScan] {
            let rrt = RrtConnect { neighbors, ..RrtConnect::default() }.plan(&problem).unwrap();
            let mut prm = Prm::default();
            prm.neighbors = neighbors;
            prm.options.nodes = 150;
            prm.setup(&SetupContext {
                robot: &robot,
                group: &group,
                q_full: &q_full,
                checker: &world,
                seed,
                step: 0.02,
            })
            .unwrap();
            let roadmap = (prm.roadmap_nodes(), prm.roadmap_edges());
            let prm_path = prm.plan(&problem).unwrap();
            iterations += rrt.iterations;
            paths.push((rrt.path, rrt.iterations, prm_path.path, roadmap));
        }
        assert_eq!(paths[0], paths[1], "seed {seed}");
    }
    assert!(iterations > 12, "the problem needs more than a straight line");
}
