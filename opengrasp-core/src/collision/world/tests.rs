//! Tests of the world's placement and distance queries.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::model::{samples, Geometry, JointKind, JointSpec, Link, RobotBuilder, Shape};
use crate::scene::{SceneObject, StaticBody};

/// The sample seven-joint arm beside a wall, and a configuration near it.
fn arm_beside_a_wall() -> (CollisionWorld, RobotId, [f64; 7]) {
    let mut scene = Scene::new("arm and wall");
    let arm = scene.add_robot("arm", Arc::new(samples::seven_dof_arm().unwrap()), Isometry3::identity()).unwrap();
    let wall = Shape::at_origin(Geometry::cuboid(0.05, 1.0, 1.0));
    scene.add_body(StaticBody::new("wall", Isometry3::translation(0.6, 0.0, 0.5), vec![wall])).unwrap();
    (CollisionWorld::new(&scene).unwrap(), arm, [0.3, 0.8, -0.2, 0.5, 0.1, 0.4, 0.0])
}

#[test]
fn selected_link_distances_match_the_full_query() {
    let (world, arm, q) = arm_beside_a_wall();
    let full = world.link_distances(arm, &q).unwrap();
    let selected: Vec<bool> = (0..full.len()).map(|l| l % 2 == 1).collect();
    let mut out = Vec::new();
    world.selected_link_distances_into(arm, &q, &selected, &mut out).unwrap();
    assert_eq!(out.len(), full.len());
    for (l, (&a, &b)) in full.iter().zip(&out).enumerate() {
        if selected[l] {
            assert_eq!(a, b, "link {l}");
        } else {
            assert_eq!(b, f64::INFINITY, "link {l}");
        }
    }
    assert!(full.iter().any(|d| d.is_finite()));
    // A short mask leaves the remaining links unqueried; bad configurations are errors.
    world.selected_link_distances_into(arm, &q, &[true], &mut out).unwrap();
    assert_eq!(out[0], full[0]);
    assert!(out[1..].iter().all(|d| *d == f64::INFINITY));
    assert!(world.selected_link_distances_into(arm, &q[..3], &selected, &mut out).is_err());
}

/// A branching robot: a torso turning about z, a frame link without geometry, two arms (the
/// second's elbow mimics the first's), a fixed tool and an empty fingertip link.
fn two_arm_robot() -> Robot {
    let capsule =
        |name: &str| Link::new(name).with_shape(Shape::at_origin(Geometry::Capsule { radius: 0.04, length: 0.2 }));
    let revolute = |name: &str, parent: &str, child: &str, origin: Isometry3<f64>, axis: Vector3<f64>| {
        JointSpec::new(name, JointKind::Revolute, parent, child).origin(origin).axis(axis).limits(-2.5, 2.5, 1.0, 10.0)
    };
    let up = |z: f64| Isometry3::translation(0.0, 0.0, z);
    let side = |y: f64| {
        Isometry3::from_parts(Translation3::new(0.0, y, 0.3), UnitQuaternion::from_euler_angles(0.3 * y, 0.2, -0.1))
    };
    RobotBuilder::new("two_arms")
        .link(Link::new("torso").with_shape(Shape::at_origin(Geometry::cuboid(0.3, 0.4, 0.5))))
        .link(Link::new("chest"))
        .link(capsule("l1"))
        .link(capsule("l2"))
        .link(capsule("r1"))
        .link(Link::new("r2").with_shape(Shape::new(up(0.1), Geometry::Cylinder { radius: 0.05, length: 0.2 })))
        .link(Link::new("tool").with_shape(Shape::new(up(0.05), Geometry::cuboid(0.06, 0.1, 0.04))))
        .link(Link::new("tip"))
        .joint(revolute("waist", "torso", "chest", up(0.3), Vector3::z()))
        .joint(revolute("l_shoulder", "chest", "l1", side(0.25), Vector3::y()))
        .joint(revolute("l_elbow", "l1", "l2", up(0.2), Vector3::x()))
        .joint(revolute("r_shoulder", "chest", "r1", side(-0.25), Vector3::y()))
        .joint(revolute("r_elbow", "r1", "r2", up(0.2), Vector3::x()).mimic("l_elbow", -0.5, 0.1))
        .joint(JointSpec::new("tool_joint", JointKind::Fixed, "l2", "tool").origin(up(0.2)))
        .joint(revolute("tip_joint", "tool", "tip", up(0.1), Vector3::z()))
        .build()
        .unwrap()
}

/// The two-arm robot on a rotated base near a wall, holding a box in its right hand.
fn two_arm_world() -> (CollisionWorld, RobotId) {
    let (scene, robot) = two_arm_scene();
    (CollisionWorld::new(&scene).unwrap(), robot)
}

/// The scene of [`two_arm_world`].
fn two_arm_scene() -> (Scene, RobotId) {
    let mut scene = Scene::new("two arms");
    let base =
        Isometry3::from_parts(Translation3::new(0.2, -0.1, 0.05), UnitQuaternion::from_euler_angles(0.0, 0.0, 0.7));
    let robot = scene.add_robot("robot", Arc::new(two_arm_robot()), base).unwrap();
    let wall = Shape::at_origin(Geometry::cuboid(0.05, 2.0, 2.0));
    scene.add_body(StaticBody::new("wall", Isometry3::translation(0.9, 0.0, 0.5), vec![wall])).unwrap();
    let held = SceneObject::new(
        "held",
        Isometry3::translation(0.3, -0.3, 0.9),
        vec![Shape::at_origin(Geometry::cuboid(0.05, 0.05, 0.1))],
        0.1,
    );
    let held = scene.add_object(held).unwrap();
    scene.attach(held, robot, "r2").unwrap();
    (scene, robot)
}

fn random_q(robot: &Robot, rng: &mut ChaCha8Rng) -> Vec<f64> {
    (0..robot.dof())
        .map(|d| {
            let (lo, hi) = robot.dof_limits(d);
            rng.random_range(lo..=hi)
        })
        .collect()
}

fn same_bits(a: &Isometry3<f64>, b: &Isometry3<f64>) -> bool {
    let bits = |p: &Isometry3<f64>| {
        let (t, r) = (p.translation.vector, p.rotation.coords);
        [t.x, t.y, t.z, r.x, r.y, r.z, r.w].map(f64::to_bits)
    };
    bits(a) == bits(b)
}

/// Asserts that placing the links of `mask` at `q` gives each placed part (and part of the
/// carried object) the very pose and bounding box of full forward kinematics (the placement
/// every query used before `place_links`), in the same order, and places nothing else; with
/// the scratch `s` (and whatever poses it remembers).
fn assert_placement_matches_full_fk(world: &CollisionWorld, robot: RobotId, q: &[f64], mask: &[bool], s: &mut Scratch) {
    let r = &world.robots[robot.0];
    let mut full_poses = Vec::new();
    crate::kinematics::forward_kinematics_into(&r.robot, q, &mut full_poses);
    let mut reference: Vec<(LinkId, Isometry3<f64>)> =
        r.parts.iter().zip(&r.part_link).map(|(p, l)| (*l, r.base_pose * full_poses[l.0] * p.local)).collect();
    let (object, att) = world.objects.iter().find_map(|o| o.attached.as_ref().map(|a| (o, a))).unwrap();
    let carried = r.base_pose * full_poses[att.link.0] * att.offset;
    reference.extend(object.parts.iter().map(|p| (att.link, carried * p.local)));
    world.place_links(robot.0, q, |l| mask[l], s);
    let expected: Vec<&(LinkId, Isometry3<f64>)> = reference.iter().filter(|(l, _)| mask[l.0]).collect();
    assert_eq!(s.items.len(), expected.len(), "{mask:?}");
    for (item, (link, pose)) in s.items.iter().zip(expected) {
        assert_eq!(item.link, *link);
        assert!(same_bits(&item.pose, pose), "{mask:?}: {:?} vs {pose:?}", item.pose);
        let aabb = world.item_shape(robot.0, item).compute_aabb(pose);
        assert_eq!((item.aabb.mins, item.aabb.maxs), (aabb.mins, aabb.maxs));
    }
}

/// Placing a subset of the links matches full forward kinematics bit for bit (see
/// [`assert_placement_matches_full_fk`]).
#[test]
fn placed_links_match_full_forward_kinematics() {
    let (world, robot) = two_arm_world();
    let r = &world.robots[robot.0];
    let n = r.n_links();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..20 {
        let q = random_q(&r.robot, &mut rng);
        let masks = (0..n)
            .map(|l| (0..n).map(|k| k == l).collect::<Vec<bool>>())
            .chain(std::iter::once((0..n).map(|_| rng.random_bool(0.5)).collect()))
            .chain(std::iter::once(vec![true; n]));
        for mask in masks {
            assert_placement_matches_full_fk(&world, robot, &q, &mask, &mut Scratch::default());
        }
    }
}

/// Only the root (the torso) is behind fixed joints alone: the tool hangs on a fixed joint
/// but behind revolute ones. Its copied pose and box follow base moves, configuration changes
/// and scene syncs bit for bit.
/// One scratch shared by placements that alternate configurations (repeated and fresh),
/// link masks and two worlds of the same robot moved to different bases, with a world of a
/// new robot built in between (possibly at a freed address): every placement is full
/// forward kinematics bit for bit, the poses the scratch remembers included.
#[test]
fn remembered_link_poses_match_full_forward_kinematics() {
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    let mut s = Scratch::default();
    // Two worlds of one scene hold the same robot.
    let (scene, robot) = two_arm_scene();
    let mut a = CollisionWorld::new(&scene).unwrap();
    let mut b = CollisionWorld::new(&scene).unwrap();
    let n = a.robots[robot.0].n_links();
    let qs: Vec<Vec<f64>> = (0..4).map(|_| random_q(&a.robots[robot.0].robot, &mut rng)).collect();
    let (mut placed, mut reused) = (0, 0);
    for round in 0..60 {
        // Each configuration for three placements in a row, then another (or a random one).
        let q = if round % 7 == 6 { &qs[rng.random_range(0..qs.len())] } else { &qs[(round / 3) % qs.len()] };
        let mask: Vec<bool> = (0..n).map(|_| rng.random_bool(0.4)).collect();
        let base = Isometry3::translation(rng.random_range(-1.0..1.0), 0.2, 0.0);
        let world = if round % 2 == 0 { &mut a } else { &mut b };
        world.set_robot_base_pose(robot, base).unwrap();
        // Links whose pose the scratch holds for this configuration already.
        if s.fk_q == *q {
            reused += (0..n).filter(|&l| mask[l] && s.fk_posed.get(l).copied().unwrap_or(false)).count();
        }
        assert_placement_matches_full_fk(world, robot, q, &mask, &mut s);
        placed += mask.iter().filter(|&&m| m).count();
        if round % 20 == 19 {
            // A new robot of the same shape (the old one dropped): nothing remembered applies.
            b = two_arm_world().0;
        }
    }
    assert!(placed >= 150 && reused >= 40, "only {placed} links placed, {reused} remembered");
}

#[test]
fn links_behind_fixed_joints_follow_the_base() {
    let (mut scene, robot) = two_arm_scene();
    let mut world = CollisionWorld::new(&scene).unwrap();
    let r = &world.robots[robot.0];
    let torso = r.robot.link_id("torso").unwrap();
    let fixed: Vec<usize> = (0..r.n_links()).filter(|&l| r.fixed_link[l]).collect();
    assert_eq!(fixed, vec![torso.0]);
    let model = r.robot.clone();
    let all = vec![true; model.links().len()];
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for step in 0..6 {
        let base = Isometry3::new(
            Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), 0.1 * step as f64),
            Vector3::new(0.2, rng.random_range(-3.0..3.0), 0.5),
        );
        if step % 2 == 0 {
            world.set_robot_base_pose(robot, base).unwrap();
        } else {
            scene.set_robot_base_pose(robot, base).unwrap();
            scene.set_robot_configuration(robot, &random_q(&model, &mut rng)).unwrap();
            world.sync(&scene).unwrap();
        }
        let q = random_q(&model, &mut rng);
        assert_placement_matches_full_fk(&world, robot, &q, &all, &mut Scratch::default());
        // The torso's box is where the moved base puts it (a 0.3 × 0.4 × 0.5 m box).
        let mut s = Scratch::default();
        world.place(robot.0, &q, &mut s);
        let torso_item = s.items.iter().find(|i| i.link == torso).unwrap();
        let centre = world.robots[robot.0].base_pose.translation.vector;
        assert!((torso_item.pose.translation.vector - centre).norm() < 1e-12);
        assert!((torso_item.aabb.center().coords - centre).norm() < 1e-12);
    }
}

/// Moving only the base (which reuses the link poses of the stored configuration) leaves the
/// robot's parts, and the object it carries, exactly where a world built from scratch at that
/// base and configuration puts them; a later configuration change still takes effect.
#[test]
fn base_moves_reuse_the_kinematics_bit_for_bit() {
    let (mut scene, robot) = two_arm_scene();
    let mut world = CollisionWorld::new(&scene).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let model = world.robots[robot.0].robot.clone();
    for step in 0..12 {
        if step % 4 == 0 {
            let q = random_q(&model, &mut rng);
            world.set_robot_configuration(robot, &q).unwrap();
            scene.set_robot_configuration(robot, &q).unwrap();
        }
        let t = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(0.0..1.0));
        let base = Isometry3::new(t, Vector3::new(rng.random_range(-3.0..3.0), 0.4, rng.random_range(-3.0..3.0)));
        world.set_robot_base_pose(robot, base).unwrap();
        scene.set_robot_base_pose(robot, base).unwrap();
        let fresh = CollisionWorld::new(&scene).unwrap();
        let parts = |w: &CollisionWorld| {
            let mut out: Vec<(Isometry3<f64>, Aabb)> = w.robots[robot.0].world.clone();
            out.extend(w.objects.iter().flat_map(|o| o.world.iter().copied()));
            out
        };
        let (moved, built) = (parts(&world), parts(&fresh));
        assert_eq!(moved.len(), built.len());
        for ((p, a), (q, b)) in moved.iter().zip(&built) {
            assert!(same_bits(p, q), "step {step}: {p:?} vs {q:?}");
            assert_eq!((a.mins, a.maxs), (b.mins, b.maxs));
        }
    }
    // A bad pose is an error and moves nothing.
    let before = world.robots[robot.0].world.clone();
    let nan = Isometry3::translation(f64::NAN, 0.0, 0.0);
    assert!(world.set_robot_base_pose(robot, nan).is_err());
    assert!(world.robots[robot.0].world.iter().zip(&before).all(|(a, b)| same_bits(&a.0, &b.0)));
}

/// Each link's selected distance is bit-identical to its entry of the full query, on a
/// branching robot carrying an object, one link at a time and all together.
#[test]
fn single_link_distances_equal_the_full_query_bit_for_bit() {
    let (world, robot) = two_arm_world();
    let n = world.robots[robot.0].n_links();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut out = Vec::new();
    let mut finite = 0;
    for _ in 0..20 {
        let q = random_q(&world.robots[robot.0].robot, &mut rng);
        let full = world.link_distances(robot, &q).unwrap();
        for l in 0..n {
            let mask: Vec<bool> = (0..n).map(|k| k == l).collect();
            world.selected_link_distances_into(robot, &q, &mask, &mut out).unwrap();
            assert_eq!(out[l].to_bits(), full[l].to_bits(), "link {l} at {q:?}");
            assert!(out.iter().enumerate().all(|(k, d)| k == l || *d == f64::INFINITY));
            finite += usize::from(full[l].is_finite());
        }
    }
    // The six links with geometry (the right forearm with its box) are all measured.
    assert_eq!(finite, 20 * 6);
}

/// [`two_arm_world`] with a tetrahedral mesh (queried through its convex hull) and a free
/// cylinder beside the wall.
fn two_arm_world_with_mesh() -> (CollisionWorld, RobotId) {
    let (mut scene, robot) = two_arm_scene();
    let v = vec![
        nalgebra::Point3::new(0.0, 0.0, 0.0),
        nalgebra::Point3::new(0.4, 0.0, 0.0),
        nalgebra::Point3::new(0.0, 0.4, 0.0),
        nalgebra::Point3::new(0.0, 0.0, 0.4),
    ];
    let mesh = crate::model::TriangleMesh::new(v, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]).unwrap();
    let mesh = Shape::at_origin(Geometry::Mesh(Arc::new(mesh)));
    scene.add_body(StaticBody::new("mesh", Isometry3::translation(-0.5, 0.3, 0.4), vec![mesh])).unwrap();
    let can = Shape::at_origin(Geometry::Cylinder { radius: 0.05, length: 0.3 });
    scene.add_object(SceneObject::new("can", Isometry3::translation(0.2, 0.6, 0.6), vec![can], 0.2)).unwrap();
    (CollisionWorld::new(&scene).unwrap(), robot)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// The bounded query is bit for bit `min(distance, bound)` of the plain query, for bounds
    /// below, around and above each link's distance, zero, negative and infinite.
    #[test]
    fn bounded_link_distances_are_the_minimum_of_the_plain_query_and_the_bound(
        seed in 0u64..1_000_000,
        kinds in proptest::collection::vec(0u8..6, 8),
        scale in 0.0f64..2.0,
    ) {
        let (world, robot) = two_arm_world_with_mesh();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let q = random_q(&world.robots[robot.0].robot, &mut rng);
        let full = world.link_distances(robot, &q).unwrap();
        proptest::prop_assert_eq!(full.len(), kinds.len());
        let bounds: Vec<f64> = full
            .iter()
            .zip(&kinds)
            .map(|(&d, k)| match k {
                0 => 0.0,
                1 => -scale,
                2 => f64::INFINITY,
                3 => if d.is_finite() { d * scale } else { scale },
                4 => if d.is_finite() { d } else { 1.0 },
                _ => scale,
            })
            .collect();
        let mut out = vec![7.0; 3];
        world.link_distances_below_into(robot, &q, &bounds, &mut out).unwrap();
        proptest::prop_assert_eq!(out.len(), full.len());
        for l in 0..full.len() {
            proptest::prop_assert_eq!(out[l].to_bits(), full[l].min(bounds[l]).to_bits(), "link {} bound {}", l, bounds[l]);
        }
    }
}

/// The bounded query on hand-checked cases: a link far from everything keeps its bound, a
/// near one gets its exact distance; bad bounds are typed errors.
#[test]
fn bounded_link_distances_on_known_cases_and_bad_input() {
    let (world, arm, q) = arm_beside_a_wall();
    let full = world.link_distances(arm, &q).unwrap();
    let n = full.len();
    let (near, &d) =
        full.iter().enumerate().filter(|(_, d)| d.is_finite() && **d > 0.0).min_by(|a, b| a.1.total_cmp(b.1)).unwrap();
    assert!(d > 0.0 && d < 1.0, "{d}");
    let mut out = Vec::new();
    // Just above the distance: exact; just below: the bound; all others unqueried (bound 0).
    let mut bounds = vec![0.0; n];
    bounds[near] = d + 1e-9;
    world.link_distances_below_into(arm, &q, &bounds, &mut out).unwrap();
    assert_eq!(out[near], d);
    assert!(out.iter().enumerate().all(|(l, &x)| l == near || x == 0.0));
    bounds[near] = 0.5 * d;
    world.link_distances_below_into(arm, &q, &bounds, &mut out).unwrap();
    assert_eq!(out[near], 0.5 * d);
    assert!(matches!(
        world.link_distances_below_into(arm, &q, &bounds[1..], &mut out),
        Err(CoreError::DimensionMismatch { expected, actual }) if expected == n && actual == n - 1
    ));
    bounds[0] = f64::NAN;
    assert!(matches!(world.link_distances_below_into(arm, &q, &bounds, &mut out), Err(CoreError::NonFinite { .. })));
    assert!(world.link_distances_below_into(arm, &q[..3], &vec![1.0; n], &mut out).is_err());
}

/// A non-convex triangle mesh (an open box: a floor and four walls, no lid) as parry's
/// `TriMesh`.
fn open_box_trimesh() -> parry3d_f64::shape::SharedShape {
    let (v, t) = open_box();
    parry3d_f64::shape::SharedShape::trimesh(v, t).unwrap()
}

/// Hinted link distances ([`NearestTriangles`]) along a motion of the arm in and around two
/// open boxes (a static body and a movable object, so both searches take hints) are the
/// plain query's bit for bit, and leave each measured link's nearest triangle as its hint;
/// so are the hinted nearest distance ([`CollisionWorld::min_distance_hinted`]) and the
/// hinted bounded distances ([`CollisionWorld::link_distances_below_hinted_into`]).
#[test]
fn hinted_link_distances_are_the_plain_ones_bit_for_bit() {
    let mut scene = Scene::new("arm and open boxes");
    let arm = scene.add_robot("arm", Arc::new(samples::seven_dof_arm().unwrap()), Isometry3::identity()).unwrap();
    let (v, t) = open_box();
    let mesh = Arc::new(crate::model::TriangleMesh::new(v, t).unwrap());
    let shape = || vec![Shape::at_origin(Geometry::Mesh(mesh.clone()))];
    scene.add_body(StaticBody::new("box", Isometry3::translation(0.5, 0.0, 0.3), shape())).unwrap();
    scene.add_object(SceneObject::new("box", Isometry3::translation(-0.4, 0.3, 0.5), shape(), 1.0)).unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    let n = world.robots[arm.0].n_links();
    let selected = vec![true; n];
    let (mut plain, mut hinted, mut hints) = (Vec::new(), Vec::new(), NearestTriangles::new());
    let mut nearest_hints = NearestTriangles::new();
    let (mut below, mut below_hints) = (Vec::new(), NearestTriangles::new());
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut compared = 0;
    for _ in 0..4 {
        let (a, b) = (random_q(&world.robots[arm.0].robot, &mut rng), random_q(&world.robots[arm.0].robot, &mut rng));
        for step in 0..=40 {
            let q: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x + (y - x) * f64::from(step) / 40.0).collect();
            world.selected_link_distances_into(arm, &q, &selected, &mut plain).unwrap();
            world.selected_link_distances_hinted_into(arm, &q, &selected, &mut hinted, &mut hints).unwrap();
            assert_eq!(
                plain.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
                hinted.iter().map(|d| d.to_bits()).collect::<Vec<_>>()
            );
            compared += plain.iter().filter(|d| d.is_finite()).count();
            // Bounded with hints: min(distance, bound) bit for bit, the bounds by link cycling
            // through unqueried, below, just above and beyond the distance, and unbounded.
            // (Just above: 1 nm, inside GJK's tolerance of ~5e-8 of the distance, by which the
            // hull pre-check's estimate can exceed the mesh's own where they share the
            // nearest feature: the pre-check leaves that much slack.)
            let bounds: Vec<f64> = plain
                .iter()
                .enumerate()
                .map(|(l, &d)| match (l + step as usize) % 5 {
                    0 => 0.0,
                    1 if d.is_finite() => 0.5 * d,
                    2 if d.is_finite() => d + 1e-9,
                    3 => 2.0,
                    _ => f64::INFINITY,
                })
                .collect();
            world.link_distances_below_hinted_into(arm, &q, &bounds, &mut below, &mut below_hints).unwrap();
            for ((&x, &d), &bound) in below.iter().zip(&plain).zip(&bounds) {
                assert_eq!(x.to_bits(), d.min(bound).to_bits(), "distance {d}, bound {bound}, got {x}");
            }
            // The nearest distance with hints: the plain one bit for bit.
            let d = world.min_distance(arm, &q).unwrap();
            assert_eq!(d.to_bits(), world.min_distance_hinted(arm, &q, &mut nearest_hints).unwrap().to_bits());
        }
    }
    assert!((0..n).any(|l| nearest_hints.triangle(crate::model::LinkId(l)).is_some()));
    // Every link with geometry was measured against the meshes and holds a hint.
    let with_hint = (0..n).filter(|&l| hints.triangle(crate::model::LinkId(l)).is_some()).count();
    assert_eq!(with_hint, plain.iter().filter(|d| d.is_finite()).count());
    assert!(with_hint >= 4 && compared >= 4 * 41 * 4, "{with_hint} links, {compared} distances");
    hints.clear();
    assert_eq!(hints.triangle(crate::model::LinkId(0)), None);
    // A bad configuration is a typed error.
    assert!(world.selected_link_distances_hinted_into(arm, &[0.0; 3], &selected, &mut hinted, &mut hints).is_err());
    assert!(world.min_distance_hinted(arm, &[0.0; 3], &mut hints).is_err());
    let q = vec![0.0; world.robots[arm.0].robot.dof()];
    assert!(matches!(
        world.link_distances_below_hinted_into(arm, &q, &vec![1.0; n - 1], &mut below, &mut hints),
        Err(CoreError::DimensionMismatch { expected, actual }) if expected == n && actual == n - 1
    ));
    let mut nan = vec![1.0; n];
    nan[1] = f64::NAN;
    assert!(matches!(
        world.link_distances_below_hinted_into(arm, &q, &nan, &mut below, &mut hints),
        Err(CoreError::NonFinite { .. })
    ));
}

/// The open box's corners and triangles (see [`open_box_trimesh`]).
fn open_box() -> (Vec<nalgebra::Point3<f64>>, Vec<[u32; 3]>) {
    // Corners 0-3 on the floor (z = 0), 4-7 above them (z = 0.2), counter-clockwise.
    let v = (0..8)
        .map(|k: usize| {
            let (x, y) = [(-0.3, -0.3), (0.3, -0.3), (0.3, 0.3), (-0.3, 0.3)][k % 4];
            nalgebra::Point3::new(x, y, if k < 4 { 0.0 } else { 0.2 })
        })
        .collect();
    // The floor, then two triangles per wall.
    let mut t = vec![[0, 2, 1], [0, 3, 2]];
    for a in 0..4u32 {
        let b = (a + 1) % 4;
        t.extend([[a, b, b + 4], [a, b + 4, a + 4]]);
    }
    (v, t)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]

    /// The bounded mesh walk gives parry's mesh distance bit for bit when it is below the
    /// bound and "not below" otherwise, with the mesh first or second, against a ball, a box,
    /// a capsule, a cylinder and a convex hull, in and around the open box.
    #[test]
    fn bounded_mesh_distance_is_parrys_below_the_bound(
        x in -0.6f64..0.6, y in -0.6f64..0.6, z in -0.3f64..0.6,
        roll in -3.2f64..3.2, pitch in -3.2f64..3.2, yaw in -3.2f64..3.2,
        kind in 0usize..5,
        fraction in 0.0f64..2.0,
        mesh_first in proptest::bool::ANY,
    ) {
        use parry3d_f64::shape::SharedShape;
        let mesh = open_box_trimesh();
        let other = match kind {
            0 => SharedShape::ball(0.05),
            1 => SharedShape::cuboid(0.04, 0.1, 0.02),
            2 => SharedShape::capsule_z(0.1, 0.03),
            3 => SharedShape::cylinder(0.08, 0.04),
            _ => SharedShape::convex_hull(&[
                nalgebra::Point3::new(0.0, 0.0, 0.0),
                nalgebra::Point3::new(0.1, 0.0, 0.0),
                nalgebra::Point3::new(0.0, 0.12, 0.0),
                nalgebra::Point3::new(0.0, 0.0, 0.09),
            ]).unwrap(),
        };
        let mesh_pose = Isometry3::from_parts(Translation3::new(0.1, -0.2, 0.3), UnitQuaternion::from_euler_angles(0.2, -0.1, 0.5));
        let pose = mesh_pose * Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(roll, pitch, yaw));
        let (p1, s1, p2, s2) = if mesh_first {
            (&mesh_pose, &*mesh.0, &pose, &*other.0)
        } else {
            (&pose, &*other.0, &mesh_pose, &*mesh.0)
        };
        let plain = parry3d_f64::query::distance(p1, s1, p2, s2).unwrap();
        let bound = plain * fraction + if fraction > 1.0 { 1e-3 } else { 0.0 };
        let bounded = super::mesh_distance::mesh_distance_hinted(p1, s1, p2, s2, bound, None);
        let expected = (plain < bound).then_some(plain);
        proptest::prop_assert_eq!(bounded.map(|d| d.map(f64::to_bits)), Some(expected.map(f64::to_bits)), "plain {} bound {}", plain, bound);
        // An infinite bound gives parry's distance; pairs without a mesh are left to the plain query.
        let unbounded = super::mesh_distance::mesh_distance_hinted(p1, s1, p2, s2, f64::INFINITY, None);
        proptest::prop_assert_eq!(unbounded.map(|d| d.map(f64::to_bits)), Some(Some(plain.to_bits())));
        proptest::prop_assert_eq!(super::mesh_distance::mesh_distance_hinted(p1, &*other.0, p2, &*other.0, bound, None), None);
    }
}
