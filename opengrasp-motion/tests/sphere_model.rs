//! The sphere model for planning: greedy guaranteed covers (every surface point inside a
//! sphere), closed-form primitive obstacles, and the MotionBenchMaker Panda planned on spheres
//! with paths that pass the exact validators.

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use opengrasp_core::model::{Geometry, TriangleMesh};
use opengrasp_motion::planners::RrtConnect;
use opengrasp_motion::problem_set::{self, LoadedProblemSet, PlanningModel};
use opengrasp_motion::validate::{path_valid_discrete, validate_path, ValidationOptions, DEFAULT_STEP};
use opengrasp_motion::validity::cover::{greedy_cover, signed_depth, GreedyCoverOptions, SphereCover};
use opengrasp_motion::validity::{
    MeshCover, ObstacleBox, ObstaclePrimitive, ObstacleShape, SphereWorld, StateValidityChecker,
};
use opengrasp_motion::{MotionError, MotionPlanner};
use proptest::prelude::*;

mod common;
use common::{cylinder, soup};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda/problems")
}

/// Every corner plus `n` area-uniform points of the surface that no sphere contains.
fn uncovered(cover: &SphereCover, mesh: &TriangleMesh, n: usize, seed: u64) -> Vec<Point3<f64>> {
    let v = mesh.vertices();
    let tri = |t: &[u32; 3]| (v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
    let areas: Vec<f64> = mesh
        .triangles()
        .iter()
        .map(|t| {
            let (a, b, c) = tri(t);
            (b - a).cross(&(c - a)).norm()
        })
        .collect();
    let total: f64 = areas.iter().sum();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut points: Vec<Point3<f64>> = v.to_vec();
    for _ in 0..n {
        let mut pick = rng.random::<f64>() * total;
        let k = areas.iter().position(|a| {
            pick -= a;
            pick <= 0.0
        });
        let (a, b, c) = tri(&mesh.triangles()[k.unwrap_or(areas.len() - 1)]);
        let (mut s, mut u) = (rng.random::<f64>(), rng.random::<f64>());
        if s + u > 1.0 {
            (s, u) = (1.0 - s, 1.0 - u);
        }
        points.push(a + (b - a) * s + (c - a) * u);
    }
    points.into_iter().filter(|p| !cover.contains(p)).collect()
}

fn point() -> impl Strategy<Value = Point3<f64>> {
    (-0.2f64..0.2, -0.2f64..0.2, -0.2f64..0.2).prop_map(|(x, y, z)| Point3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    /// Random triangle soups at random offsets, any piece, grid and budget: nothing left
    /// uncovered, and no sphere is larger than its candidate allowed.
    #[test]
    fn greedy_cover_covers_every_surface_point(
        tris in prop::collection::vec((point(), point(), point()), 1..5),
        offset in (-5.0f64..5.0, -5.0f64..5.0, -5.0f64..5.0),
        piece in 0.02f64..0.1,
        grid in 0.04f64..0.1,
        budget in 0.0f64..0.1,
        seed in 0u64..1000,
    ) {
        let mesh = soup(&tris, Vector3::new(offset.0, offset.1, offset.2));
        prop_assume!(mesh.is_some());
        let mesh = mesh.unwrap();
        let options = GreedyCoverOptions { piece, grid, max_overhang: budget };
        let cover = greedy_cover(&mesh, &options).unwrap();
        prop_assert!(uncovered(&cover, &mesh, 2000, seed).is_empty());
        for (c, r) in &cover.spheres {
            // A grid candidate may grow to depth + budget, a piece's centroid also to its piece.
            let allowed = (signed_depth(&mesh, c) + budget).max(piece);
            prop_assert!(*r <= allowed * (1.0 + 1e-6) + 1e-6, "radius {r} > {allowed}");
        }
    }
}

#[test]
fn signed_depth_is_exact_for_a_cube() {
    let cube = TriangleMesh::cuboid(Vector3::new(0.2, 0.2, 0.2)).unwrap();
    assert!((signed_depth(&cube, &Point3::new(0.0, 0.0, 0.05)) - 0.05).abs() < 1e-12);
    assert!((signed_depth(&cube, &Point3::new(0.02, -0.03, 0.0)) - 0.07).abs() < 1e-12);
    assert!((signed_depth(&cube, &Point3::new(0.3, 0.0, 0.0)) + 0.2).abs() < 1e-12);
    assert!((signed_depth(&cube, &Point3::new(0.2, 0.2, 0.0)) + 0.1 * 2f64.sqrt()).abs() < 1e-12);
}

/// A tilted closed cylinder link: the greedy cover keeps every surface point, stays within
/// its budget beyond the solid, and needs far fewer spheres than the budget's voxels would.
#[test]
fn greedy_cover_of_a_closed_link_stays_within_its_budget() {
    let pose =
        Isometry3::from_parts(Vector3::new(0.1, -0.2, 0.3).into(), UnitQuaternion::from_euler_angles(0.4, 0.7, 0.1));
    let mesh = cylinder(0.05, 0.3, 12).transformed(&pose);
    println!("budget [mm]  spheres  max overhang beyond the solid [mm]");
    let mut last = 0;
    for budget in [0.04, 0.02, 0.01] {
        let cover = greedy_cover(&mesh, &GreedyCoverOptions { max_overhang: budget, ..Default::default() }).unwrap();
        assert!(uncovered(&cover, &mesh, 5000, 3).is_empty(), "budget {budget}");
        let overhang = cover.solid_overhang(&mesh);
        println!("{:11.0}  {:7}  {:.1}", budget * 1e3, cover.spheres.len(), overhang * 1e3);
        assert!(overhang <= budget + 1e-6, "budget {budget}: {overhang}");
        // Smaller budgets need more spheres.
        assert!(cover.spheres.len() > last, "budget {budget}: {} spheres", cover.spheres.len());
        last = cover.spheres.len();
    }
    // The previous session's adaptive octree cover needed 312 spheres at ≤ 40 mm for this
    // link; 2 cm of budget on a 5 cm cylinder takes a few dozen.
    assert!(last < 200, "{last} spheres at 10 mm");
}

#[test]
fn bad_greedy_options_are_typed_errors() {
    let cube = TriangleMesh::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap();
    let bad = |o: GreedyCoverOptions| match greedy_cover(&cube, &o) {
        Err(MotionError::InvalidParameter { name, .. }) => name,
        other => panic!("{o:?}: {other:?}"),
    };
    let d = GreedyCoverOptions::default();
    assert_eq!(bad(GreedyCoverOptions { piece: 0.0, ..d }), "piece");
    assert_eq!(bad(GreedyCoverOptions { piece: 1e-5, ..d }), "piece");
    assert_eq!(bad(GreedyCoverOptions { grid: f64::NAN, ..d }), "grid");
    assert_eq!(bad(GreedyCoverOptions { grid: 1e-3, ..d }), "grid");
    assert_eq!(bad(GreedyCoverOptions { max_overhang: -0.1, ..d }), "max_overhang");
}

/// Closed-form signed distances of the primitive obstacles at analytic points.
#[test]
fn primitive_obstacle_distances_are_exact() {
    let pose =
        Isometry3::from_parts(Vector3::new(1.0, 2.0, 3.0).into(), UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1));
    let at = |x: f64, y: f64, z: f64| pose * Point3::new(x, y, z);
    let cyl = ObstaclePrimitive::new("c", pose, ObstacleShape::Cylinder { radius: 0.1, half_length: 0.2 });
    let cap = ObstaclePrimitive::new("k", pose, ObstacleShape::Capsule { radius: 0.1, half_length: 0.2 });
    let ball = ObstaclePrimitive::new("s", pose, ObstacleShape::Sphere { radius: 0.1 });
    let cases = [
        (&cyl, at(0.3, 0.0, 0.0), 0.2),    // radially out
        (&cyl, at(0.0, 0.0, 0.5), 0.3),    // beyond the cap
        (&cyl, at(0.0, 0.4, 0.6), 0.5),    // off the rim: (0.3, 0.4) → 0.5
        (&cyl, at(0.05, 0.0, 0.1), -0.05), // inside, nearest the side
        (&cyl, at(0.0, 0.0, 0.19), -0.01), // inside, nearest the cap
        (&cap, at(0.0, 0.0, 0.5), 0.2),    // beyond the hemisphere
        (&cap, at(0.3, 0.4, 0.2), 0.4),    // off the end centre: 0.5 − 0.1
        (&cap, at(0.0, 0.04, 0.0), -0.06), // inside
        (&ball, at(0.0, 0.6, 0.8), 0.9),   // 1.0 − 0.1
    ];
    for (o, p, d) in cases {
        assert!((o.signed_distance(&p) - d).abs() < 1e-12, "{} at {p}: {} vs {d}", o.name, o.signed_distance(&p));
    }
    let b = ObstacleBox::new("b", pose, Vector3::new(0.2, 0.4, 0.6));
    assert!((b.signed_distance(&at(0.3, 0.0, 0.0)) - 0.2).abs() < 1e-12);
    assert!((ObstaclePrimitive::from(b).signed_distance(&at(0.0, 0.0, 0.25)) + 0.05).abs() < 1e-12);
    let bad = ObstaclePrimitive::new("neg", pose, ObstacleShape::Cylinder { radius: -0.1, half_length: 0.2 });
    assert!(matches!(bad.validate(), Err(MotionError::InvalidParameter { name: "obstacle", .. })));
}

fn panda_sets() -> Vec<LoadedProblemSet> {
    problem_set::load(data()).unwrap().iter().map(|s| LoadedProblemSet::new(s).unwrap()).collect()
}

/// The Panda's layered sphere model (default greedy cover, coarse cover tried first), built
/// once for the tests.
fn panda_model() -> Arc<SphereWorld> {
    static MODEL: OnceLock<Arc<SphereWorld>> = OnceLock::new();
    MODEL.get_or_init(|| Arc::new(panda_sets()[0].layered_sphere_model(GreedyCoverOptions::default()).unwrap())).clone()
}

/// The Panda's collision meshes under the default greedy cover: every surface point of every
/// link covered; the sphere count and the largest overhang beyond the solid are the report.
#[test]
fn panda_greedy_cover_covers_every_link_surface() {
    let world = panda_model();
    let robot = world.robot();
    let mut worst: f64 = 0.0;
    println!("link            spheres  max overhang beyond the mesh solid [mm]");
    for (i, link) in robot.links().iter().enumerate() {
        let spheres: Vec<(Point3<f64>, f64)> =
            world.spheres().filter(|(l, _, _)| l.0 == i).map(|(_, c, r)| (c, r)).collect();
        for shape in &link.collisions {
            let Geometry::Mesh(mesh) = &shape.geometry else { panic!("the Panda's links are meshes") };
            let mesh = mesh.transformed(&shape.origin);
            let cover = SphereCover { spheres: spheres.clone() };
            assert!(uncovered(&cover, &mesh, 3000, i as u64).is_empty(), "{}", link.name);
            let overhang = cover.solid_overhang(&mesh);
            worst = worst.max(overhang);
            println!("{:15} {:7}  {:.1}", link.name, spheres.len(), overhang * 1e3);
        }
    }
    println!(
        "total {} spheres, max overhang {:.1} mm; coarse layer {} spheres",
        world.sphere_count(),
        worst * 1e3,
        world.coarse_sphere_count().unwrap()
    );
    assert!(worst <= GreedyCoverOptions::default().max_overhang + 1e-6, "{worst}");
    // A regression bound (the greedy cover gives about 700 at the default 10 mm budget).
    assert!(world.sphere_count() < 1000, "{} spheres", world.sphere_count());
}

/// RRT-Connect plans every vendored MBM problem on the layered sphere model, and every path
/// passes the exact (mesh) validator at the planning step; the sphere model accepts no state
/// the exact checker rejects, and every state the fine cover alone accepts (2,000 random
/// states per problem).
#[test]
fn panda_paths_planned_on_spheres_pass_the_exact_validators() {
    let mut solved = 0;
    let mut strict = 0;
    let fine_model = panda_sets()[0].sphere_model(MeshCover::Greedy(GreedyCoverOptions::default())).unwrap();
    for set in panda_sets() {
        let model = PlanningModel::Spheres(panda_model());
        for i in 0..set.len() {
            let inst = set.instance_with(i, &model).unwrap();
            let spheres = inst.planning_checker.as_deref().unwrap();
            let problem = inst.problem(spheres, Duration::from_secs(60), i as u64, DEFAULT_STEP);
            let path = RrtConnect::default().plan(&problem).unwrap().path;
            assert!(path_valid_discrete(spheres, &path, DEFAULT_STEP));
            let v = validate_path(&*inst.checker, &path, &ValidationOptions::default());
            assert!(v.discrete, "{} problem {i}: planned on spheres, invalid under the meshes", set.name());
            strict += usize::from(v.strict);
            solved += 1;
            let limits = inst.group.limits(&inst.robot);
            let mut rng = ChaCha8Rng::seed_from_u64(i as u64);
            let fine = set.sphere_world(i, &fine_model).unwrap();
            let (mut accepted, mut by_fine) = (0, 0);
            for _ in 0..2000 {
                let q: Vec<f64> = limits.iter().map(|l| rng.random_range(l.0..=l.1)).collect();
                if spheres.is_valid(&q) {
                    accepted += 1;
                    assert!(inst.checker.is_valid(&q), "{} problem {i}: {q:?}", set.name());
                }
                // The coarse layer only ever adds acceptances.
                if fine.is_valid(&q) {
                    by_fine += 1;
                    assert!(spheres.is_valid(&q), "{} problem {i}: {q:?}", set.name());
                }
            }
            assert!(accepted >= by_fine);
            assert!(accepted > 100, "{} problem {i}: the sphere model accepts only {accepted}", set.name());
        }
    }
    println!("{solved} solved, {strict} also valid at the strict step");
    assert_eq!(solved, 10);
}

#[test]
fn mesh_obstacles_are_refused_by_the_sphere_model() {
    let text = r#"{"name": "mesh", "robot": {"stock": "seven_dof_arm", "group": "arm"},
      "problems": [{"obstacles": [{"name": "wedge", "type": "mesh",
         "vertices": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "triangles": [[0,2,1],[0,1,3],[0,3,2],[1,2,3]]}],
        "start": [0,0,0,0,0,0,0], "goal": {"configuration": [0.1,0,0,0,0,0,0]}}]}"#;
    let set = problem_set::ProblemSet::from_json_str(text, "mesh.json").unwrap();
    let loaded = LoadedProblemSet::new(&set).unwrap();
    let model = loaded.sphere_model(MeshCover::default()).unwrap();
    assert!(matches!(loaded.sphere_world(0, &model), Err(MotionError::InvalidParameter { name: "obstacle", .. })));
    assert!(matches!(
        loaded.instance_with(0, &PlanningModel::Spheres(Arc::new(model))),
        Err(MotionError::InvalidParameter { name: "obstacle", .. })
    ));
}
