//! Benchmarks of opengrasp-core: forward and inverse kinematics, collision checking and
//! distance queries. Every input is seeded.
//!
//! Run briefly with `cargo bench -p opengrasp-core --bench core -- --warm-up-time 1 --measurement-time 3`.

use std::f64::consts::PI;
use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_main, Criterion};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use opengrasp_core::collision::{CollisionWorld, NearestTriangles};
use opengrasp_core::kinematics::{forward_kinematics, forward_kinematics_into, solve_ik, IkOptions};
use opengrasp_core::model::{samples, Geometry, Robot, Shape};
use opengrasp_core::scene::{RobotId, Scene, StaticBody};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `n` configurations drawn uniformly within the joint limits.
fn random_configurations(robot: &Robot, n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            (0..robot.dof())
                .map(|i| {
                    let (lo, hi) = robot.dof_limits(i);
                    rng.random_range(lo.max(-PI)..hi.min(PI))
                })
                .collect()
        })
        .collect()
}

/// The 7-DoF arm among 50 seeded boxes (3-15 cm) placed 0.35-1.2 m from its axis, 0-1.4 m
/// high: a mix of colliding and free configurations.
fn arm_among_boxes(seed: u64) -> (Scene, RobotId, Arc<Robot>) {
    let robot = Arc::new(samples::seven_dof_arm().expect("sample arm"));
    let mut scene = Scene::new("arm among boxes");
    let arm = scene.add_robot("arm", robot.clone(), Isometry3::identity()).expect("robot");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for i in 0..50 {
        let r = rng.random_range(0.35..1.2);
        let a = rng.random_range(-PI..PI);
        let pose = Isometry3::from_parts(
            Translation3::new(r * a.cos(), r * a.sin(), rng.random_range(0.0..1.4)),
            UnitQuaternion::from_euler_angles(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), a),
        );
        let size = [(); 3].map(|_| rng.random_range(0.03..0.15));
        let shape = Shape::at_origin(Geometry::cuboid(size[0], size[1], size[2]));
        scene.add_body(StaticBody::new(format!("box{i}"), pose, vec![shape])).expect("body");
    }
    (scene, arm, robot)
}

fn bench_kinematics(c: &mut Criterion) {
    let chain = samples::serial_chain(10).expect("chain");
    let qs = random_configurations(&chain, 256, 1);
    let mut poses = Vec::new();
    let mut k = 0;
    c.bench_function("fk_10_joint_chain", |b| {
        b.iter(|| {
            k = (k + 1) % qs.len();
            forward_kinematics_into(&chain, black_box(&qs[k]), &mut poses);
            black_box(&poses);
        })
    });

    let arm = samples::seven_dof_arm().expect("arm");
    let group = arm.group("arm").expect("group").clone();
    let tip = arm.link_id("tool").expect("tool");
    let targets: Vec<Isometry3<f64>> =
        random_configurations(&arm, 64, 2).iter().map(|q| forward_kinematics(&arm, q).expect("fk")[tip]).collect();
    let start = arm.home_configuration();
    let options = IkOptions::default();
    let mut k = 0;
    c.bench_function("ik_7dof", |b| {
        b.iter(|| {
            k = (k + 1) % targets.len();
            black_box(solve_ik(&arm, &group, tip, black_box(&targets[k]), &start, &options).expect("ik"))
        })
    });
}

fn bench_collision(c: &mut Criterion) {
    let (scene, arm, robot) = arm_among_boxes(7);
    let world = CollisionWorld::new(&scene).expect("world");
    let qs = random_configurations(&robot, 256, 3);
    let colliding = qs.iter().filter(|q| world.in_collision_unchecked(arm, q)).count();
    eprintln!("collision_check_7dof_50_boxes: {colliding} of {} configurations collide", qs.len());
    let mut k = 0;
    c.bench_function("collision_check_7dof_50_boxes", |b| {
        b.iter(|| {
            k = (k + 1) % qs.len();
            black_box(world.in_collision_unchecked(arm, black_box(&qs[k])))
        })
    });
    let mut k = 0;
    c.bench_function("min_distance_7dof_50_boxes", |b| {
        b.iter(|| {
            k = (k + 1) % qs.len();
            black_box(world.distance(arm, black_box(&qs[k])).expect("distance"))
        })
    });
    // A non-convex triangle mesh (the exact link-to-mesh distance walks the mesh's BVH).
    let (scene, arm) = arm_beside_torus();
    let world = CollisionWorld::new(&scene).expect("world");
    let mut k = 0;
    c.bench_function("min_distance_7dof_torus_mesh", |b| {
        b.iter(|| {
            k = (k + 1) % qs.len();
            black_box(world.distance(arm, black_box(&qs[k])).expect("distance"))
        })
    });
    // Every link's distance to the torus along a path of small steps (as a grasp's closing
    // queries them), plain and warm-started from each link's nearest triangle of the step
    // before (the same distances).
    let path: Vec<Vec<f64>> =
        (0..256).map(|k| qs[0].iter().zip(&qs[1]).map(|(a, b)| a + (b - a) * f64::from(k) / 255.0).collect()).collect();
    let selected = vec![true; 16];
    for (row, hinted) in [("link_distances_7dof_torus_path", false), ("link_distances_hinted_7dof_torus_path", true)] {
        let (mut hints, mut out, mut k) = (NearestTriangles::new(), Vec::new(), 0);
        c.bench_function(row, |b| {
            b.iter(|| {
                k = (k + 1) % path.len();
                if k == 0 {
                    hints.clear();
                }
                let q = black_box(&path[k]);
                if hinted {
                    world.selected_link_distances_hinted_into(arm, q, &selected, &mut out, &mut hints)
                } else {
                    world.selected_link_distances_into(arm, q, &selected, &mut out)
                }
                .expect("distances");
                black_box(&out);
            })
        });
    }
}

/// The sample arm beside a torus mesh (radii 0.3 and 0.08, 1,024 triangles) at 0.5 m.
fn arm_beside_torus() -> (Scene, RobotId) {
    let robot = Arc::new(samples::seven_dof_arm().expect("sample arm"));
    let mut scene = Scene::new("arm beside a torus");
    let arm = scene.add_robot("arm", robot, Isometry3::identity()).expect("robot");
    let (n, m) = (32u32, 16u32);
    let mut vertices = Vec::new();
    for i in 0..n {
        let phi = 2.0 * PI * f64::from(i) / f64::from(n);
        for j in 0..m {
            let theta = 2.0 * PI * f64::from(j) / f64::from(m);
            let rho = 0.3 + 0.08 * theta.cos();
            vertices.push(nalgebra::Point3::new(rho * phi.cos(), rho * phi.sin(), 0.08 * theta.sin()));
        }
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let v = |a: u32, b: u32| (a % n) * m + b % m;
            triangles.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            triangles.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    let mesh = opengrasp_core::model::TriangleMesh::new(vertices, triangles).expect("torus mesh");
    let shape = Shape::at_origin(Geometry::Mesh(Arc::new(mesh)));
    let pose = Isometry3::translation(0.5, 0.0, 0.6);
    scene.add_body(StaticBody::new("torus", pose, vec![shape])).expect("body");
    (scene, arm)
}

mod group {
    // `criterion_group!` generates an undocumented public function.
    #![allow(missing_docs)]
    criterion::criterion_group!(benches, super::bench_kinematics, super::bench_collision);
}
criterion_main!(group::benches);
