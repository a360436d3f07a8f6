//! Sphere covers with a guaranteed bound: every sampled surface point is covered; the voxel
//! cover's overhang shrinks with its cell, against the bounding-box grid cover; spherized URDFs
//! become the sphere model directly.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{Geometry, JointGroup, JointKind, JointSpec, Link, RobotBuilder, Shape, TriangleMesh};
use opengrasp_core::scene::{Scene, StaticBody};
use opengrasp_core::urdf::{self, InMemoryResolver};
use opengrasp_motion::validity::cover::{
    adaptive_cover, bounding_box_cover, surface_distance, voxel_cover, SphereCover,
};
use opengrasp_motion::validity::{CollisionChecker, MeshCover, ObstacleBox, SphereWorld, StateValidityChecker};
use opengrasp_motion::MotionError;
use proptest::prelude::*;

mod common;
use common::{cylinder, soup};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `n` uniform points on the surface (area-weighted triangle, uniform barycentric).
fn surface_samples(mesh: &TriangleMesh, n: usize, seed: u64) -> Vec<Point3<f64>> {
    let v = mesh.vertices();
    let tri = |t: &[u32; 3]| (v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(n + 3 * mesh.triangles().len());
    for t in mesh.triangles() {
        let (a, b, c) = tri(t);
        out.extend([a, b, c]); // corners and edges are the hardest points to cover
    }
    for _ in 0..n {
        let (a, b, c) = tri(&mesh.triangles()[rng.random_range(0..mesh.triangles().len())]);
        let (mut s, mut u) = (rng.random::<f64>(), rng.random::<f64>());
        if s + u > 1.0 {
            (s, u) = (1.0 - s, 1.0 - u);
        }
        out.push(a + (b - a) * s + (c - a) * u);
    }
    out
}

fn uncovered(cover: &SphereCover, mesh: &TriangleMesh, seed: u64) -> Vec<Point3<f64>> {
    surface_samples(mesh, 2000, seed).into_iter().filter(|p| !cover.contains(p)).collect()
}

fn point() -> impl Strategy<Value = Point3<f64>> {
    (-0.3f64..0.3, -0.3f64..0.3, -0.3f64..0.3).prop_map(|(x, y, z)| Point3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Random triangle soups at random offsets, any cell size: nothing left uncovered.
    #[test]
    fn voxel_cover_covers_every_surface_point(
        tris in prop::collection::vec((point(), point(), point()), 1..6),
        offset in (-5.0f64..5.0, -5.0f64..5.0, -5.0f64..5.0),
        cell in 0.01f64..0.4,
        seed in 0u64..1000,
    ) {
        let mesh = soup(&tris, Vector3::new(offset.0, offset.1, offset.2));
        prop_assume!(mesh.is_some());
        let mesh = mesh.unwrap();
        let cover = voxel_cover(&mesh, cell).unwrap();
        prop_assert!(uncovered(&cover, &mesh, seed).is_empty());
        // Every kept cell meets the bounding box of a surface piece no wider than the cell:
        // no sphere reaches more than 2√3 cells past the surface.
        prop_assert!(cover.overhang(&mesh) <= 2.0 * 3f64.sqrt() * cell * (1.0 + 1e-6) + 1e-6);
        // Merged octree-wise within a budget: still everything covered, fewer spheres.
        let budget = 3.0 * cell;
        let merged = adaptive_cover(&mesh, cell, budget).unwrap();
        prop_assert!(uncovered(&merged, &mesh, seed + 1).is_empty());
        prop_assert!(merged.spheres.len() <= cover.spheres.len());
        prop_assert!(merged.overhang(&mesh) <= budget.max(2.0 * 3f64.sqrt() * cell) * (1.0 + 1e-6) + 1e-6);
    }
}

/// Sphere count against overhang for a 12-facet cylinder link (r 5 cm, 30 cm long, tilted),
/// voxel covers of several cells against the bounding-box grid (printed as the report).
#[test]
fn voxel_cover_trades_spheres_for_overhang() {
    let pose =
        Isometry3::from_parts(Vector3::new(0.1, -0.2, 0.3).into(), UnitQuaternion::from_euler_angles(0.4, 0.7, 0.1));
    let mesh = cylinder(0.05, 0.3, 12).transformed(&pose);
    // Checks the cover, prints its row and returns its overhang.
    let row = |label: String, cover: &SphereCover| {
        assert!(uncovered(cover, &mesh, 2).is_empty(), "{label}");
        let radii = cover.spheres.iter().map(|s| s.1);
        let (lo, hi) = (radii.clone().fold(f64::INFINITY, f64::min), radii.fold(0.0, f64::max));
        let overhang = cover.overhang(&mesh);
        println!("{label:17} {:7}  {:5.1}–{:5.1}  {:17.1}", cover.spheres.len(), lo * 1e3, hi * 1e3, overhang * 1e3);
        overhang
    };
    println!("cover             spheres  radius [mm]  max overhang [mm]");
    let boxed = bounding_box_cover(&mesh);
    let boxed_overhang = row("bounding box".into(), &boxed);
    let mut last = f64::INFINITY;
    for cell in [0.08, 0.04, 0.02, 0.01] {
        let overhang = row(format!("voxel {:.0} mm", cell * 1e3), &voxel_cover(&mesh, cell).unwrap());
        assert!(overhang <= 2.0 * 3f64.sqrt() * cell + 1e-6 && overhang < last, "cell {cell}: {overhang}");
        last = overhang;
    }
    for budget in [0.08, 0.04, 0.02] {
        let overhang = row(format!("adaptive ≤{:.0} mm", budget * 1e3), &adaptive_cover(&mesh, 0.005, budget).unwrap());
        assert!(overhang <= budget + 1e-9, "budget {budget}: {overhang}");
    }
    // At 1 cm cells the voxel cover reaches at most 2√3 cm past the surface; the box grid
    // reaches past the tilted cylinder's bounding box.
    assert!(last < 0.035 && boxed_overhang > 0.1, "{last} vs {boxed_overhang}");
}

#[test]
fn surface_distance_is_exact_for_a_cube() {
    let cube = TriangleMesh::cuboid(Vector3::new(0.2, 0.2, 0.2)).unwrap();
    assert!((surface_distance(&cube, &Point3::new(0.3, 0.0, 0.0)) - 0.2).abs() < 1e-12);
    assert!((surface_distance(&cube, &Point3::new(0.2, 0.2, 0.0)) - 0.1 * 2f64.sqrt()).abs() < 1e-12);
    assert!(
        (surface_distance(&cube, &Point3::new(0.0, 0.0, 0.05)) - 0.05).abs() < 1e-12,
        "inside: to the nearest face"
    );
}

#[test]
fn bad_cell_sizes_are_typed_errors() {
    let cube = TriangleMesh::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap();
    for cell in [0.0, -0.1, f64::NAN, f64::INFINITY, 1e-5] {
        assert!(matches!(voxel_cover(&cube, cell), Err(MotionError::InvalidParameter { name: "cell", .. })), "{cell}");
        assert!(matches!(adaptive_cover(&cube, cell, 0.1), Err(MotionError::InvalidParameter { name: "cell", .. })));
    }
    for budget in [-0.1, f64::NAN] {
        assert!(matches!(
            adaptive_cover(&cube, 0.1, budget),
            Err(MotionError::InvalidParameter { name: "max_overhang", .. })
        ));
    }
}

/// A spherized URDF (collision geometry made of spheres) is its own sphere model: one sphere
/// per collision sphere, and the verdicts match the closed form.
#[test]
fn spherized_urdf_is_used_directly() {
    let text = r#"<robot name="spherized">
      <link name="base"><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
      <link name="arm">
        <collision><origin xyz="0 0 0.2"/><geometry><sphere radius="0.05"/></geometry></collision>
        <collision><origin xyz="0 0 0.3"/><geometry><sphere radius="0.05"/></geometry></collision>
        <collision><origin xyz="0 0 0.4"/><geometry><sphere radius="0.04"/></geometry></collision>
      </link>
      <joint name="j" type="revolute">
        <parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
        <limit lower="-3" upper="3" effort="1" velocity="1"/>
      </joint>
    </robot>"#;
    let robot = Arc::new(urdf::from_str(text, &InMemoryResolver::new()).unwrap());
    let group = JointGroup::all(&robot, "arm").unwrap();
    // A wall whose face is at x = 0.37: the tip sphere (centre 0.4 m from the joint, r 0.04)
    // touches it at the angle where 0.4 sin θ + 0.04 = 0.37.
    let wall = ObstacleBox::new("wall", Isometry3::translation(0.47, 0.0, 0.0), Vector3::new(0.2, 1.0, 2.0));
    let world = SphereWorld::new(robot.clone(), group, vec![0.0], Isometry3::identity(), vec![wall]).unwrap();
    assert_eq!(world.sphere_count(), 4);
    let touch = (0.33f64 / 0.4).asin();
    assert!(world.is_valid(&[touch - 1e-6]));
    assert!(!world.is_valid(&[touch + 1e-6]));
    let d = world.clearance(&[0.0]).unwrap();
    assert!((d - 0.32).abs() < 1e-9, "clearance {d}: the 0.05 spheres at x 0 are 0.32 m from the wall");
}

/// A one-joint arm whose link is a cylinder mesh swinging towards a wall: both mesh covers
/// accept only states the exact checker accepts; the voxel cover rejects only states within
/// its overhang bound of contact, and accepts more than the bounding-box grid.
#[test]
fn voxel_mesh_cover_is_sound_and_tighter_in_a_sphere_world() {
    let mesh = Arc::new(cylinder(0.05, 0.4, 16));
    // Tilted in the link, so its bounding box is loose.
    let origin =
        Isometry3::from_parts(Vector3::new(0.0, 0.0, 0.25).into(), UnitQuaternion::from_euler_angles(0.0, 0.5, 0.0));
    let link = Link::new("arm").with_shape(Shape::new(origin, Geometry::Mesh(mesh)));
    let mut robot = RobotBuilder::new("swing")
        .link(Link::new("base"))
        .link(link)
        .joint(JointSpec::new("j", JointKind::Revolute, "base", "arm").axis(Vector3::y()).limits(-1.5, 1.5, 1.0, 1.0))
        .build()
        .unwrap();
    robot.add_group("arm", &["j"]).unwrap();
    let robot = Arc::new(robot);
    let group = JointGroup::all(&robot, "arm").unwrap();
    let wall_pose = Isometry3::translation(0.5, 0.0, 0.0);
    let wall = ObstacleBox::new("wall", wall_pose, Vector3::new(0.2, 1.0, 2.0));
    let sphere_world = |meshes| {
        SphereWorld::with_mesh_cover(
            robot.clone(),
            group.clone(),
            vec![0.0],
            Isometry3::identity(),
            vec![wall.clone()],
            meshes,
        )
        .unwrap()
    };
    let (boxed, cell) = (sphere_world(MeshCover::BoundingBox), 0.01);
    let voxels = sphere_world(MeshCover::Voxels { cell });
    let adaptive = sphere_world(MeshCover::Adaptive { cell: 0.005, max_overhang: 0.02 });
    let mut by_adaptive = 0;
    assert!(voxels.sphere_count() > boxed.sphere_count());
    let mut scene = Scene::new("wall");
    let id = scene.add_robot("swing", robot.clone(), Isometry3::identity()).unwrap();
    scene
        .add_body(StaticBody::new("wall", wall_pose, vec![Shape::at_origin(Geometry::cuboid(0.2, 1.0, 2.0))]))
        .unwrap();
    let world = Arc::new(CollisionWorld::new(&scene).unwrap());
    let exact = CollisionChecker::new(world, id, robot.clone(), group, vec![0.0]).unwrap();
    let (mut by_voxels, mut by_box) = (0, 0);
    for i in 0..=3000 {
        let q = [-1.5 + 0.001 * f64::from(i)];
        let clearance = exact.clearance(&q).unwrap();
        if voxels.is_valid(&q) {
            by_voxels += 1;
            assert!(exact.is_valid(&q), "{q:?}");
        } else {
            assert!(clearance <= 2.0 * 3f64.sqrt() * cell + 1e-6, "{q:?}: rejected {clearance} m from the wall");
        }
        if adaptive.is_valid(&q) {
            by_adaptive += 1;
            assert!(exact.is_valid(&q), "{q:?}");
        } else {
            assert!(clearance <= 0.02 + 1e-6, "{q:?}: adaptive cover rejected {clearance} m from the wall");
        }
        if boxed.is_valid(&q) {
            by_box += 1;
            assert!(exact.is_valid(&q), "{q:?}");
        }
    }
    println!(
        "of 3001 swing angles: voxel cover ({} spheres) accepts {by_voxels}, adaptive ({} spheres) {by_adaptive}, box \
         grid ({} spheres) {by_box}",
        voxels.sphere_count(),
        adaptive.sphere_count(),
        boxed.sphere_count()
    );
    assert!(
        by_voxels > by_box && by_adaptive > by_box && by_box > 1000,
        "voxels accept {by_voxels}, adaptive {by_adaptive}, box grid {by_box}"
    );
    assert!(matches!(
        SphereWorld::with_mesh_cover(
            robot.clone(),
            JointGroup::all(&robot, "arm").unwrap(),
            vec![0.0],
            Isometry3::identity(),
            Vec::new(),
            MeshCover::Voxels { cell: -1.0 }
        ),
        Err(MotionError::InvalidParameter { name: "cell", .. })
    ));
}
