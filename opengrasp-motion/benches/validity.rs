//! State and motion checks of the sphere model ([`SphereWorld`]): one state, a batch of
//! states (per state), a motion (coarse to fine), and RRT-Connect on it (kd-tree and linear-scan nearest neighbours), for core's 7-DoF sample
//! arm in a small cupboard (table, shelf, divider, back wall: the stand-in scene of the
//! standard suite, rebuilt here so the bench needs no other crate), and one nearest-neighbour
//! query among 10,000 configurations, and a state check with a mesh forearm under each mesh
//! cover (bounding-box grid, voxels, adaptive).
//!
//! ```sh
//! cargo bench -p opengrasp-motion --bench validity -- --warm-up-time 1 --measurement-time 3
//! ```

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use opengrasp_core::model::{samples, Geometry, JointGroup, Shape, TriangleMesh};
use opengrasp_motion::nearest::{KdTree, LinearScan, NearestNeighbors};
use opengrasp_motion::planners::{NeighborStructure, RrtConnect};
use opengrasp_motion::validity::{MeshCover, ObstacleBox, SphereWorld, StateValidityChecker};
use opengrasp_motion::{Goal, MotionPlanner, PlanningProblem};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const START: [f64; 7] = [1.4175, 1.026, -1.5041, 1.5464, -0.1228, -0.1075, 1.1446];
const GOAL: [f64; 7] = [-1.4175, 1.026, 1.5041, 1.5464, 0.1228, -0.1075, -1.1446];

fn cupboard() -> Vec<ObstacleBox> {
    vec![
        ObstacleBox::new("table", Isometry3::translation(0.65, 0.0, 0.225), Vector3::new(0.6, 1.2, 0.05)),
        ObstacleBox::new("shelf", Isometry3::translation(0.65, 0.0, 0.85), Vector3::new(0.6, 1.2, 0.04)),
        ObstacleBox::new("divider", Isometry3::translation(0.7, 0.0, 0.54), Vector3::new(0.5, 0.04, 0.58)),
        ObstacleBox::new("back", Isometry3::translation(0.97, 0.0, 0.54), Vector3::new(0.04, 1.2, 0.58)),
    ]
}

fn validity(c: &mut Criterion) {
    let robot = Arc::new(samples::seven_dof_arm().expect("sample arm"));
    let group = robot.group("arm").expect("arm group").clone();
    let q_full = robot.home_configuration();
    let world = SphereWorld::new(robot.clone(), group.clone(), q_full.clone(), Isometry3::identity(), cupboard())
        .expect("sphere world");
    let limits = JointGroup::limits(&group, &robot);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let states: Vec<Vec<f64>> =
        (0..64).map(|_| limits.iter().map(|&(lo, hi)| lo + (hi - lo) * rng.random::<f64>()).collect()).collect();
    let mut k = 0;
    c.bench_function("spheres_7dof/state_check", |b| {
        b.iter(|| {
            k = (k + 1) % states.len();
            world.is_valid(black_box(&states[k]))
        })
    });
    let flat: Vec<f64> = states.iter().flatten().copied().collect();
    let mut out = vec![false; states.len()];
    // One iteration checks 64 states: divide the time by 64 for the per-state figure.
    c.bench_function("spheres_7dof/are_valid_64", |b| b.iter(|| world.are_valid(black_box(&flat), &mut out)));
    c.bench_function("spheres_7dof/motion_start_goal", |b| {
        b.iter(|| world.is_motion_valid(black_box(&START), black_box(&GOAL), 0.02))
    });
    let goal = Goal::Configuration(GOAL.to_vec());
    // Same paths with either nearest-neighbour structure; only the time differs.
    for (name, neighbors) in
        [("rrt_connect_plan", NeighborStructure::KdTree), ("rrt_connect_plan_linear_nn", NeighborStructure::LinearScan)]
    {
        let mut planner = RrtConnect { neighbors, ..RrtConnect::default() };
        let mut seed = 0u64;
        c.bench_function(&format!("spheres_7dof/{name}"), |b| {
            b.iter(|| {
                seed = (seed + 1) % 100;
                let problem = PlanningProblem {
                    robot: &robot,
                    group: &group,
                    q_full: &q_full,
                    start: &START,
                    goal: &goal,
                    checker: &world,
                    time_limit: Duration::from_secs(10),
                    seed,
                    step: 0.02,
                };
                planner.plan(&problem).expect("solved")
            })
        });
    }
}

/// One nearest-neighbour query among 10,000 uniform 7-DoF configurations (RRT-sized trees
/// hold a few hundred; PRM roadmaps and hard problems reach this size).
fn nearest(c: &mut Criterion) {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut uniform =
        |n: usize| -> Vec<Vec<f64>> { (0..n).map(|_| (0..7).map(|_| rng.random_range(-3.0..3.0)).collect()).collect() };
    let (points, queries) = (uniform(10_000), uniform(256));
    let structures: [(&str, Box<dyn NearestNeighbors>); 2] =
        [("kd_tree", Box::new(KdTree::new(7))), ("linear_scan", Box::new(LinearScan::new(7)))];
    for (name, mut nn) in structures {
        for p in &points {
            nn.add(p).expect("finite 7-DoF point");
        }
        let mut k = 0;
        c.bench_function(&format!("nearest_7dof_10000/{name}"), |b| {
            b.iter(|| {
                k = (k + 1) % queries.len();
                nn.nearest(black_box(&queries[k]))
            })
        });
    }
}

/// One state check of a 7-DoF arm whose forearm (`link4`) is a tilted cylinder mesh, with
/// the mesh covered by the bounding-box grid, 10 mm voxels or adaptive spheres (≤ 40 mm).
fn mesh_covers(c: &mut Criterion) {
    let mut robot = samples::seven_dof_arm().expect("sample arm");
    let n = 16;
    let mut vertices = vec![Point3::new(0.0, 0.0, -0.1), Point3::new(0.0, 0.0, 0.1)];
    for i in 0..n {
        let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
        vertices.extend([
            Point3::new(0.06 * a.cos(), 0.06 * a.sin(), -0.1),
            Point3::new(0.06 * a.cos(), 0.06 * a.sin(), 0.1),
        ]);
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        let (b0, t0, b1, t1) = (2 + 2 * i, 3 + 2 * i, 2 + 2 * ((i + 1) % n), 3 + 2 * ((i + 1) % n));
        triangles.extend([[0, b1, b0], [1, t0, t1], [b0, b1, t1], [b0, t1, t0]]);
    }
    let mesh = Arc::new(TriangleMesh::new(vertices, triangles).expect("cylinder mesh"));
    let origin =
        Isometry3::from_parts(Vector3::new(0.0, 0.0, 0.1).into(), UnitQuaternion::from_euler_angles(0.3, 0.0, 0.0));
    let link4 = robot.link_id("link4").expect("link4");
    robot.link_mut(link4).collisions = vec![Shape::new(origin, Geometry::Mesh(mesh))];
    let robot = Arc::new(robot);
    let group = robot.group("arm").expect("arm group").clone();
    let q_full = robot.home_configuration();
    let limits = JointGroup::limits(&group, &robot);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let states: Vec<Vec<f64>> =
        (0..64).map(|_| limits.iter().map(|&(lo, hi)| lo + (hi - lo) * rng.random::<f64>()).collect()).collect();
    let covers = [
        ("bounding_box", MeshCover::BoundingBox),
        ("voxels_10mm", MeshCover::Voxels { cell: 0.01 }),
        ("adaptive_40mm", MeshCover::Adaptive { cell: 0.005, max_overhang: 0.04 }),
    ];
    for (name, cover) in covers {
        let world = SphereWorld::with_mesh_cover(
            robot.clone(),
            group.clone(),
            q_full.clone(),
            Isometry3::identity(),
            cupboard(),
            cover,
        )
        .expect("sphere world");
        let mut k = 0;
        c.bench_function(&format!("mesh_link_7dof/state_check_{name}_{}_spheres", world.sphere_count()), |b| {
            b.iter(|| {
                k = (k + 1) % states.len();
                world.is_valid(black_box(&states[k]))
            })
        });
    }
}

criterion_group!(benches, validity, nearest, mesh_covers);
criterion_main!(benches);
