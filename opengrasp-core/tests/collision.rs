//! Integration tests of `opengrasp_core::collision` against analytic cases and a brute-force
//! reference.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use opengrasp_core::collision::{
    geometry_to_parry, shapes_to_parry, Collider, CollisionOptions, CollisionWorld, MeshRepresentation,
};
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::model::{
    samples, Geometry, JointKind, JointSpec, Link, LinkId, Robot, RobotBuilder, Shape, TriangleMesh,
};
use opengrasp_core::scene::{BodyId, ObjectId, RobotId, Scene, SceneObject, StaticBody};
use opengrasp_core::CoreError;
use parry3d_f64::query;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const TOL: f64 = 1e-6;

/// A robot made of one link (no joints) carrying `geometry` at its origin.
fn probe(geometry: Geometry) -> Arc<Robot> {
    Arc::new(RobotBuilder::new("probe").link(Link::new("body").with_shape(Shape::at_origin(geometry))).build().unwrap())
}

fn body(name: &str, pose: Isometry3<f64>, geometry: Geometry) -> StaticBody {
    StaticBody::new(name, pose, vec![Shape::at_origin(geometry)])
}

fn sphere(radius: f64) -> Geometry {
    Geometry::Sphere { radius }
}

fn t(x: f64, y: f64, z: f64) -> Isometry3<f64> {
    Isometry3::translation(x, y, z)
}

/// A scene with a probe at `pose` and static bodies.
fn probe_scene(geometry: Geometry, pose: Isometry3<f64>, bodies: Vec<StaticBody>) -> (Scene, RobotId) {
    let mut scene = Scene::new("probe");
    let r = scene.add_robot("probe", probe(geometry), pose).unwrap();
    for b in bodies {
        scene.add_body(b).unwrap();
    }
    (scene, r)
}

#[test]
fn box_sphere_distance_is_analytic() {
    let (scene, r) = probe_scene(
        sphere(0.1),
        t(0.8, 0.9, 0.2),
        vec![body("box", Isometry3::identity(), Geometry::cuboid(1.0, 1.0, 1.0))],
    );
    let world = CollisionWorld::new(&scene).unwrap();
    let rep = world.distance(r, &[]).unwrap();
    // Nearest box point (0.5, 0.5, 0.2); centre offset (0.3, 0.4, 0) of length 0.5.
    assert!((rep.distance - 0.4).abs() < TOL, "{rep:?}");
    assert_eq!(rep.other, Collider::Body(BodyId(0)));
    assert_eq!(rep.link, LinkId(0));
    assert_eq!(rep.attached, None);
    assert!((rep.point_on_other - Point3::new(0.5, 0.5, 0.2)).norm() < TOL);
    assert!((rep.point_on_robot - Point3::new(0.74, 0.82, 0.2)).norm() < TOL);
    assert!(!world.in_collision(r, &[]).unwrap());
    assert!((world.link_distances(r, &[]).unwrap()[0] - 0.4).abs() < TOL);
    assert_eq!(world.min_distance(r, &[]).unwrap(), rep.distance);
}

#[test]
fn sphere_sphere_distance_and_penetration() {
    let (scene, r) = probe_scene(sphere(0.2), t(1.0, 0.0, 0.0), vec![body("ball", Isometry3::identity(), sphere(0.3))]);
    let mut world = CollisionWorld::new(&scene).unwrap();
    assert!((world.distance(r, &[]).unwrap().distance - 0.5).abs() < TOL);
    // The separation alone is the same number, bit for bit.
    assert_eq!(world.min_distance(r, &[]).unwrap(), world.distance(r, &[]).unwrap().distance);
    assert!(!world.in_collision(r, &[]).unwrap());
    world.set_robot_base_pose(r, t(0.4, 0.0, 0.0)).unwrap();
    let rep = world.distance(r, &[]).unwrap();
    // Overlap of 0.1: the distance is minus the penetration depth.
    assert!((rep.distance + 0.1).abs() < TOL, "{rep:?}");
    assert!((rep.point_on_robot - Point3::new(0.2, 0.0, 0.0)).norm() < TOL);
    assert!((rep.point_on_other - Point3::new(0.3, 0.0, 0.0)).norm() < TOL);
    assert!(world.in_collision(r, &[]).unwrap());
    // Exact distance (not depth) per link, and for the robot as a whole.
    assert_eq!(world.link_distances(r, &[]).unwrap(), vec![0.0]);
    assert_eq!(world.min_distance(r, &[]).unwrap(), 0.0);
}

#[test]
fn capsule_box_distance_depends_on_axis() {
    let floor = body("floor", t(0.0, 0.0, -0.1), Geometry::cuboid(2.0, 2.0, 0.2));
    let capsule = Geometry::Capsule { radius: 0.05, length: 0.4 };
    // Upright (along z): lowest point at 0.3 - 0.2 - 0.05.
    let (scene, r) = probe_scene(capsule.clone(), t(0.0, 0.0, 0.3), vec![floor.clone()]);
    let world = CollisionWorld::new(&scene).unwrap();
    let rep = world.distance(r, &[]).unwrap();
    assert!((rep.distance - 0.05).abs() < TOL, "{rep:?}");
    assert!((rep.point_on_robot.z - 0.05).abs() < TOL && rep.point_on_other.z.abs() < TOL);
    // Lying along x: lowest point at 0.3 - 0.05.
    let lying = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, 0.3),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
    );
    let (scene, r) = probe_scene(capsule, lying, vec![floor]);
    let world = CollisionWorld::new(&scene).unwrap();
    assert!((world.distance(r, &[]).unwrap().distance - 0.25).abs() < TOL);
    // Against box edges: a unit cube turned 45° about z has a vertical edge at x = √2/2; turned
    // 45° about x, a top edge along x at z = √2/2.
    let edge = std::f64::consts::FRAC_1_SQRT_2;
    let cube = |axis: nalgebra::Unit<Vector3<f64>>| {
        let pose = Isometry3::from_parts(
            Translation3::identity(),
            UnitQuaternion::from_axis_angle(&axis, std::f64::consts::FRAC_PI_4),
        );
        body("cube", pose, Geometry::cuboid(1.0, 1.0, 1.0))
    };
    let capsule = Geometry::Capsule { radius: 0.05, length: 0.4 };
    let (scene, r) = probe_scene(capsule.clone(), t(1.0, 0.0, 0.1), vec![cube(Vector3::z_axis())]);
    let d = CollisionWorld::new(&scene).unwrap().distance(r, &[]).unwrap().distance;
    assert!((d - (1.0 - edge - 0.05)).abs() < 1e-9, "{d}");
    let above = t(0.0, 0.0, 0.7) * lying; // lying along x at z = 1.0
    let (scene, r) = probe_scene(capsule, above, vec![cube(Vector3::x_axis())]);
    let rep = CollisionWorld::new(&scene).unwrap().distance(r, &[]).unwrap();
    assert!((rep.distance - (1.0 - edge - 0.05)).abs() < 1e-9, "{rep:?}");
    assert!((rep.point_on_other.z - edge).abs() < 1e-6 && (rep.point_on_robot.z - 0.95).abs() < 1e-6);
}

#[test]
fn z_cylinder_of_length_one_reaches_half_a_metre() {
    let cyl = Geometry::Cylinder { radius: 0.1, length: 1.0 };
    let cases = [
        // (sphere centre, radius, expected distance)
        (Point3::new(0.0, 0.0, 0.7), 0.1, 0.1),    // above the top face at z = 0.5
        (Point3::new(0.0, 0.0, -0.65), 0.1, 0.05), // below the bottom face at z = -0.5
        (Point3::new(0.0, 0.7, 0.0), 0.1, 0.5),    // beside: radius 0.1
        (Point3::new(0.4, 0.0, 0.3), 0.1, 0.2),    // beside, within the height
    ];
    for (c, rad, expected) in cases {
        let (scene, r) =
            probe_scene(cyl.clone(), Isometry3::identity(), vec![body("s", t(c.x, c.y, c.z), sphere(rad))]);
        let world = CollisionWorld::new(&scene).unwrap();
        let d = world.distance(r, &[]).unwrap().distance;
        assert!((d - expected).abs() < 1e-5, "sphere at {c:?}: {d} vs {expected}");
    }
    // A sphere dipping 5 cm below the top face collides; one 5 cm beside the mantle does not.
    let (scene, r) = probe_scene(cyl.clone(), Isometry3::identity(), vec![body("s", t(0.0, 0.0, 0.55), sphere(0.1))]);
    assert!(CollisionWorld::new(&scene).unwrap().in_collision(r, &[]).unwrap());
    let (scene, r) = probe_scene(cyl.clone(), Isometry3::identity(), vec![body("s", t(0.0, 0.25, 0.0), sphere(0.1))]);
    assert!(!CollisionWorld::new(&scene).unwrap().in_collision(r, &[]).unwrap());
    // The conversion itself: parry's y-cylinder rotated onto z.
    let (correction, shape) = geometry_to_parry(&cyl, MeshRepresentation::Auto).unwrap();
    let aabb = shape.compute_aabb(&correction);
    assert!((aabb.maxs - Point3::new(0.1, 0.1, 0.5)).norm() < 1e-9, "{aabb:?}");
}

fn cube_mesh(half: f64) -> TriangleMesh {
    let v: Vec<Point3<f64>> = (0..8)
        .map(|i| {
            let s = |b: usize| if i & b != 0 { half } else { -half };
            Point3::new(s(1), s(2), s(4))
        })
        .collect();
    // Faces outward (counter-clockwise seen from outside).
    let tris = vec![
        [0, 2, 3],
        [0, 3, 1], // z-
        [4, 5, 7],
        [4, 7, 6], // z+
        [0, 1, 5],
        [0, 5, 4], // y-
        [2, 6, 7],
        [2, 7, 3], // y+
        [0, 4, 6],
        [0, 6, 2], // x-
        [1, 3, 7],
        [1, 7, 5], // x+
    ];
    TriangleMesh::new(v, tris).unwrap()
}

#[test]
fn meshes_as_hull_or_trimesh_give_the_box_distance() {
    let mesh = cube_mesh(0.5);
    assert!(mesh.is_watertight() && (mesh.signed_volume() - 1.0).abs() < 1e-12);
    for meshes in [MeshRepresentation::Auto, MeshRepresentation::ConvexHull, MeshRepresentation::TriMesh] {
        let (scene, r) = probe_scene(
            sphere(0.1),
            t(0.0, 0.0, 1.0),
            vec![body("mesh", Isometry3::identity(), Geometry::Mesh(Arc::new(mesh.clone())))],
        );
        let world = CollisionWorld::with_options(&scene, CollisionOptions { meshes }).unwrap();
        let d = world.distance(r, &[]).unwrap().distance;
        assert!((d - 0.4).abs() < 1e-6, "{meshes:?}: {d}");
    }
    let (_, hull) = geometry_to_parry(&Geometry::Mesh(Arc::new(mesh.clone())), MeshRepresentation::Auto).unwrap();
    assert!(hull.as_convex_polyhedron().is_some(), "a closed convex mesh becomes its hull");
    let (_, tri) = geometry_to_parry(&Geometry::Mesh(Arc::new(mesh)), MeshRepresentation::TriMesh).unwrap();
    assert!(tri.as_trimesh().is_some());
}

/// The 7-DoF arm alone in a scene.
fn arm_scene() -> (Scene, RobotId, Arc<Robot>) {
    let robot = Arc::new(samples::seven_dof_arm().unwrap());
    let mut scene = Scene::new("arm");
    let r = scene.add_robot("arm", robot.clone(), Isometry3::identity()).unwrap();
    (scene, r, robot)
}

#[test]
fn folded_arm_self_collision_is_detected() {
    let (scene, arm, robot) = arm_scene();
    let world = CollisionWorld::new(&scene).unwrap();
    assert!(!world.in_collision(arm, &[0.0; 7]).unwrap());
    // Shoulder, elbow and wrist all bent by 2.09 rad about y: the forearm comes back under the
    // base and the wrist points up into the base cylinder.
    let q = [0.0, 2.09, 0.0, 2.09, 0.0, 2.09, 0.0];
    let poses = forward_kinematics(&robot, &q).unwrap();
    let tool = poses[robot.link_id("tool").unwrap()];
    // By hand: every corner of the 8 x 12 x 6 cm hand box lies inside the base cylinder
    // (radius 0.08, z in [0, 0.2]).
    for i in 0..8 {
        let s = |b: usize, h: f64| if i & b != 0 { h } else { -h };
        let corner = tool * Point3::new(s(1, 0.04), s(2, 0.06), 0.05 + s(4, 0.03));
        assert!(corner.coords.xy().norm() < 0.08 && corner.z > 0.0 && corner.z < 0.2, "corner {corner:?}");
    }
    assert!(world.in_collision(arm, &q).unwrap());
    let contacts = world.contacts(arm, &q, 0.0).unwrap();
    let base = robot.link_id("base").unwrap();
    let tool_id = robot.link_id("tool").unwrap();
    assert!(
        contacts.iter().any(|c| (c.link, c.other) == (base, Collider::Link(arm, tool_id)) && c.depth > 0.0),
        "{contacts:?}"
    );
    // Every reported self-contact is between non-allowed links.
    for c in &contacts {
        let Collider::Link(_, other) = c.other else { panic!("only self-contacts expected: {c:?}") };
        assert!(!robot.is_collision_allowed(c.link, other));
    }
}

#[test]
fn allowed_pairs_are_ignored() {
    let (scene, arm, robot) = arm_scene();
    let mut world = CollisionWorld::new(&scene).unwrap();
    // Shoulder at its limit: link2's capsule grazes the rim of the base cylinder.
    let q = [0.0, 2.09, 0.0, 0.0, 0.0, 0.0, 0.0];
    let (base, link2) = (robot.link_id("base").unwrap(), robot.link_id("link2").unwrap());
    // By hand: distance from the rim point (0.08, 0, 0.2) to link2's axis through (0, 0, 0.31)
    // with direction (sin q2, 0, cos q2), minus the capsule radius 0.06.
    let (s, c) = 2.09_f64.sin_cos();
    let axis_distance = (0.08 * c + 0.11 * s).abs();
    let depth = 0.06 - axis_distance;
    assert!(depth > 0.003);
    let contacts = world.contacts(arm, &q, 0.0).unwrap();
    assert_eq!(contacts.len(), 1, "{contacts:?}");
    assert_eq!((contacts[0].link, contacts[0].other), (base, Collider::Link(arm, link2)));
    assert!((contacts[0].depth - depth).abs() < 5e-4, "{} vs {depth}", contacts[0].depth);
    assert!(world.in_collision(arm, &q).unwrap());
    // Allowed in the world...
    let pairs = world.self_collision_pair_count(arm).unwrap();
    world.allow_collision(arm, link2, base).unwrap();
    assert!(world.is_collision_allowed(arm, base, link2).unwrap());
    assert_eq!(world.self_collision_pair_count(arm).unwrap(), pairs - 1);
    assert!(!world.in_collision(arm, &q).unwrap());
    assert!(world.contacts(arm, &q, 0.0).unwrap().is_empty());
    // ...or in the robot model before building the world.
    let mut model = samples::seven_dof_arm().unwrap();
    model.allow_collision("base", "link2").unwrap();
    let mut scene = Scene::new("allowed");
    let arm = scene.add_robot("arm", Arc::new(model), Isometry3::identity()).unwrap();
    assert!(!CollisionWorld::new(&scene).unwrap().in_collision(arm, &q).unwrap());
}

#[test]
fn attached_object_is_carried_into_the_wall() {
    let (mut scene, arm, robot) = arm_scene();
    // A wall whose face is at x = 1.07, beyond the reach of the horizontal arm's hand
    // (joint2 at z = 0.31, hand tip 0.97 + 0.08 = 1.05 m away).
    scene.add_body(body("wall", t(1.27, 0.0, 0.5), Geometry::cuboid(0.4, 2.0, 2.0))).unwrap();
    // A 5 cm cube 9 cm above the tool frame: it overlaps the hand box (top at 8 cm) and reaches
    // 1.085 m from joint2.
    let tool = robot.link_id("tool").unwrap();
    let tool_pose = scene.link_world_pose(arm, "tool").unwrap();
    let cube = Shape::at_origin(Geometry::cuboid(0.05, 0.05, 0.05));
    let obj = scene.add_object(SceneObject::new("cube", tool_pose * t(0.0, 0.0, 0.09), vec![cube], 0.1)).unwrap();
    let mut world = CollisionWorld::new(&scene).unwrap();
    let home = [0.0; 7];
    let reach = [0.0, std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0, 0.0];
    // Free object overlapping the hand: collision; the arm alone reaching out: none.
    assert!(world.in_collision(arm, &home).unwrap());
    assert!(!world.in_collision(arm, &reach).unwrap());
    world.attach(obj, arm, tool).unwrap();
    // Carried: no collision with its own link, but it hits the wall when carried there.
    assert!(!world.in_collision(arm, &home).unwrap());
    assert!(world.in_collision(arm, &reach).unwrap());
    let rep = world.distance(arm, &reach).unwrap();
    assert_eq!(rep.attached, Some(obj));
    assert_eq!(rep.link, tool);
    assert_eq!(rep.other, Collider::Body(BodyId(0)));
    assert!((rep.distance + 0.015).abs() < 1e-5, "{rep:?}");
    let per_link = world.link_distances(arm, &reach).unwrap();
    assert_eq!(per_link[tool.0], 0.0);
    // At home the hand box (half width 4 cm) is nearer the wall than the cube (2.5 cm).
    let d = world.link_distances(arm, &home).unwrap();
    assert!((d[tool.0] - (1.07 - 0.04)).abs() < 1e-5, "{d:?}");
    // Same through the scene and `sync`.
    scene.attach(obj, arm, "tool").unwrap();
    let mut synced = CollisionWorld::new(&Scene::new("empty")).unwrap();
    synced.sync(&scene).unwrap();
    assert!(!synced.in_collision(arm, &home).unwrap() && synced.in_collision(arm, &reach).unwrap());
    // Detached, the object stays where the hand left it (at home) and collides with it again.
    world.detach(obj).unwrap();
    assert!(world.in_collision(arm, &home).unwrap());
    assert!(matches!(world.detach(obj), Err(CoreError::InvalidHandle { kind: "attachment", .. })));
}

#[test]
fn attached_object_against_other_links_unless_touch_allowed() {
    let (mut scene, arm, robot) = arm_scene();
    let link4 = robot.link_id("link4").unwrap();
    // A bar held by link4 that overlaps link5's capsule.
    let link4_pose = scene.link_world_pose(arm, "link4").unwrap();
    let bar = Shape::at_origin(Geometry::cuboid(0.05, 0.05, 0.1));
    let obj = scene.add_object(SceneObject::new("bar", link4_pose * t(0.0, 0.05, 0.27), vec![bar], 0.1)).unwrap();
    let mut world = CollisionWorld::new(&scene).unwrap();
    world.attach(obj, arm, link4).unwrap();
    assert!(world.in_collision(arm, &[0.0; 7]).unwrap());
    world.allow_touch(obj, robot.link_id("link5").unwrap()).unwrap();
    assert!(!world.in_collision(arm, &[0.0; 7]).unwrap());
}

/// A robot whose link `finger` (a 10 cm sphere) slides along world z: `q` is its height.
fn slider() -> Arc<Robot> {
    Arc::new(
        RobotBuilder::new("slider")
            .link(Link::new("base"))
            .link(Link::new("finger").with_shape(Shape::at_origin(sphere(0.1))))
            .joint(JointSpec::new("lift", JointKind::Prismatic, "base", "finger").limits(-1.0, 2.0, 1.0, 10.0))
            .build()
            .unwrap(),
    )
}

#[test]
fn sphere_tipped_link_contacts_are_analytic() {
    let mut scene = Scene::new("contacts");
    let r = scene.add_robot("slider", slider(), t(0.1, -0.2, 0.0)).unwrap();
    scene.add_body(body("table", t(0.0, 0.0, -0.1), Geometry::cuboid(1.0, 1.0, 0.2))).unwrap();
    let cube = Shape::at_origin(Geometry::cuboid(0.1, 0.1, 0.1));
    let obj = scene.add_object(SceneObject::new("cube", t(0.24, -0.2, 0.5), vec![cube], 0.1)).unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    let finger = LinkId(1);
    // Sphere centre 8 cm above the table top: 2 cm deep.
    let cs = world.contacts(r, &[0.08], 0.0).unwrap();
    assert_eq!(cs.len(), 1, "{cs:?}");
    let c = cs[0];
    assert_eq!((c.link, c.other), (finger, Collider::Body(BodyId(0))));
    assert!((c.depth - 0.02).abs() < TOL);
    assert!((c.normal.into_inner() - Vector3::z()).norm() < TOL, "normal points from the table to the finger");
    assert!((c.point_on_robot - Point3::new(0.1, -0.2, -0.02)).norm() < TOL);
    assert!((c.point_on_other - Point3::new(0.1, -0.2, 0.0)).norm() < TOL);
    // 3 cm above: reported with a 5 cm margin (negative depth), not with 1 cm.
    let cs = world.contacts(r, &[0.13], 0.05).unwrap();
    assert_eq!(cs.len(), 1);
    assert!((cs[0].depth + 0.03).abs() < TOL);
    assert!(world.contacts(r, &[0.13], 0.01).unwrap().is_empty());
    // Beside the cube (face at x = 0.19): 1 cm deep, normal -x.
    let cs = world.contacts_with_object(r, &[0.5], obj, 0.0).unwrap();
    assert_eq!(cs.len(), 1, "{cs:?}");
    assert_eq!(cs[0].other, Collider::Object(ObjectId(0)));
    assert!((cs[0].depth - 0.01).abs() < TOL);
    assert!((cs[0].normal.into_inner() + Vector3::x()).norm() < TOL);
    assert!((cs[0].point_on_other - Point3::new(0.19, -0.2, 0.5)).norm() < TOL);
    // The general query sees the cube too, and nothing else at that height.
    let all = world.contacts(r, &[0.5], 0.0).unwrap();
    assert_eq!(all.len(), 1);
    assert_eq!(all[0].other, Collider::Object(obj));
    assert!(matches!(world.contacts(r, &[0.5], -0.1), Err(CoreError::InvalidParameter { .. })));
    assert!(matches!(world.contacts(r, &[0.5], f64::NAN), Err(CoreError::InvalidParameter { .. })));
    assert!(matches!(
        world.contacts_with_object(r, &[0.5], ObjectId(7), 0.0),
        Err(CoreError::InvalidHandle { kind: "object", index: 7 })
    ));
}

#[test]
fn bad_configurations_and_handles_are_typed_errors() {
    let (mut scene, arm, _) = arm_scene();
    scene.add_body(body("b", t(1.0, 0.0, 0.0), sphere(0.1))).unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    assert!(matches!(world.in_collision(arm, &[0.0; 6]), Err(CoreError::DimensionMismatch { expected: 7, actual: 6 })));
    assert!(matches!(
        world.distance(arm, &[0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0]),
        Err(CoreError::NonFiniteJointValue { .. })
    ));
    assert!(matches!(
        world.link_distances(arm, &[0.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        Err(CoreError::JointOutOfLimits { .. })
    ));
    assert!(matches!(world.contacts(arm, &[0.0; 8], 0.0), Err(CoreError::DimensionMismatch { .. })));
    assert!(matches!(world.in_collision(RobotId(3), &[0.0; 7]), Err(CoreError::InvalidHandle { kind: "robot", .. })));
    let mut world = world;
    assert!(matches!(
        world.set_object_pose(ObjectId(0), Isometry3::identity()),
        Err(CoreError::InvalidHandle { kind: "object", .. })
    ));
    assert!(matches!(
        world.allow_collision(arm, LinkId(0), LinkId(99)),
        Err(CoreError::InvalidHandle { kind: "link", .. })
    ));
    let bad = Isometry3::translation(f64::NAN, 0.0, 0.0);
    assert!(matches!(world.set_robot_base_pose(arm, bad), Err(CoreError::NonFinite { .. })));
}

#[test]
fn empty_scene_distance_is_an_error_and_link_distances_infinite() {
    let (scene, arm, robot) = arm_scene();
    let world = CollisionWorld::new(&scene).unwrap();
    assert!(matches!(world.distance(arm, &[0.0; 7]), Err(CoreError::EmptyScene { .. })));
    assert!(matches!(world.min_distance(arm, &[0.0; 7]), Err(CoreError::EmptyScene { .. })));
    let d = world.link_distances(arm, &[0.0; 7]).unwrap();
    assert_eq!(d.len(), robot.links().len());
    assert!(d.iter().all(|v| *v == f64::INFINITY));
    assert!(!world.in_collision(arm, &[0.0; 7]).unwrap());
    assert!(world.contacts(arm, &[0.0; 7], 0.0).unwrap().is_empty());
    // With a margin, only near self pairs (e.g. link6 and the hand, 4 cm apart) show up.
    let near = world.contacts(arm, &[0.0; 7], 0.1).unwrap();
    assert!(!near.is_empty() && near.iter().all(|c| matches!(c.other, Collider::Link(r, _) if r == arm)));
}

#[test]
fn other_robots_are_obstacles_at_their_configuration() {
    let robot = Arc::new(samples::seven_dof_arm().unwrap());
    let mut scene = Scene::new("two arms");
    let a = scene.add_robot("a", robot.clone(), Isometry3::identity()).unwrap();
    let b = scene.add_robot("b", robot.clone(), t(1.0, 0.0, 0.0)).unwrap();
    let mut world = CollisionWorld::new(&scene).unwrap();
    // Both upright: 1 m apart, capsule radius 0.06 and base radius 0.08.
    let rep = world.distance(a, &[0.0; 7]).unwrap();
    assert!((rep.distance - (1.0 - 0.16)).abs() < 1e-6, "{rep:?}");
    assert!(matches!(rep.other, Collider::Link(r, _) if r == b));
    // Arm b leans towards arm a (joint2 = -pi/2 rotates +z onto -x): its hand reaches a's column.
    world.set_robot_configuration(b, &[0.0, -std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    assert!(world.in_collision(a, &[0.0; 7]).unwrap());
    assert!(world.in_collision(b, &[0.0, -std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap());
}

/// 50 seeded boxes around the arm's workspace.
fn boxes_scene(seed: u64) -> (Scene, RobotId, Arc<Robot>) {
    let (mut scene, arm, robot) = arm_scene();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for i in 0..50 {
        let r = rng.random_range(0.35..1.2);
        let a = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        let pose = Isometry3::from_parts(
            Translation3::new(r * a.cos(), r * a.sin(), rng.random_range(0.0..1.4)),
            UnitQuaternion::from_euler_angles(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), a),
        );
        let g =
            Geometry::cuboid(rng.random_range(0.03..0.15), rng.random_range(0.03..0.15), rng.random_range(0.03..0.15));
        scene.add_body(body(&format!("box{i}"), pose, g)).unwrap();
    }
    (scene, arm, robot)
}

/// Every collision part of the arm at `q` and every box, as parry shapes in the world frame.
type Placed = Vec<(LinkId, Isometry3<f64>, parry3d_f64::shape::SharedShape)>;

fn placed(robot: &Robot, q: &[f64]) -> Placed {
    let poses = forward_kinematics(robot, q).unwrap();
    let mut out = Vec::new();
    for (l, link) in robot.links().iter().enumerate() {
        for s in &link.collisions {
            let (corr, shape) = geometry_to_parry(&s.geometry, MeshRepresentation::Auto).unwrap();
            out.push((LinkId(l), poses[LinkId(l)] * s.origin * corr, shape));
        }
    }
    out
}

/// Distance from parry's closest points (independent of the distance routines the world uses).
fn reference_distance(
    p1: &Isometry3<f64>,
    s1: &dyn parry3d_f64::shape::Shape,
    p2: &Isometry3<f64>,
    s2: &dyn parry3d_f64::shape::Shape,
) -> f64 {
    match query::closest_points(p1, s1, p2, s2, f64::MAX).unwrap() {
        query::ClosestPoints::WithinMargin(a, b) => (a - b).norm(),
        query::ClosestPoints::Intersecting => 0.0,
        query::ClosestPoints::Disjoint => f64::INFINITY,
    }
}

/// Regression test: parry3d 0.25.3's cuboid–cuboid `query::distance` over-estimates
/// separations (1.40 m instead of 1.03 m here); the world must not inherit it.
#[test]
fn parry_cuboid_cuboid_distance_bug_is_worked_around() {
    let hand = Geometry::cuboid(0.08, 0.12, 0.06);
    let (scene, r) =
        probe_scene(hand, t(0.0, 0.0, 1.33), vec![body("wall", t(1.27, 0.0, 0.5), Geometry::cuboid(0.4, 2.0, 2.0))]);
    let world = CollisionWorld::new(&scene).unwrap();
    let rep = world.distance(r, &[]).unwrap();
    assert!((rep.distance - 1.03).abs() < 1e-6, "{rep:?}");
    assert!((rep.point_on_robot.x - 0.04).abs() < 1e-6 && (rep.point_on_other.x - 1.07).abs() < 1e-6, "{rep:?}");
    assert!((world.link_distances(r, &[]).unwrap()[0] - 1.03).abs() < 1e-6);
}

/// Compared with parry's GJK (whose distances can be ~1.5e-5 m too large on capsule–box pairs,
/// while the world's closed form is exact; see `capsule_box_distance_is_exact`), hence the 5e-5
/// tolerance on distances.
#[test]
fn bvh_queries_match_brute_force() {
    let (scene, arm, robot) = boxes_scene(7);
    let world = CollisionWorld::new(&scene).unwrap();
    assert_eq!(world.static_part_count(), 50);
    let boxes: Vec<(Isometry3<f64>, parry3d_f64::shape::SharedShape)> = scene
        .bodies()
        .iter()
        .map(|b| {
            let (c, s) = geometry_to_parry(&b.shapes[0].geometry, MeshRepresentation::Auto).unwrap();
            (b.pose * c, s)
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut colliding, mut free) = (0, 0);
    for _ in 0..150 {
        let q: Vec<f64> = (0..7)
            .map(|i| {
                let (lo, hi) = robot.dof_limits(i);
                rng.random_range(lo..hi)
            })
            .collect();
        let parts = placed(&robot, &q);
        let env_hit = parts
            .iter()
            .any(|(_, p, s)| boxes.iter().any(|(bp, bs)| query::intersection_test(p, &**s, bp, &**bs).unwrap()));
        let self_hit = parts.iter().enumerate().any(|(i, (la, pa, sa))| {
            parts[i + 1..].iter().any(|(lb, pb, sb)| {
                !robot.is_collision_allowed(*la, *lb) && query::intersection_test(pa, &**sa, pb, &**sb).unwrap()
            })
        });
        let expected = env_hit || self_hit;
        assert_eq!(world.in_collision(arm, &q).unwrap(), expected, "q = {q:?}");
        assert_eq!(world.in_collision_unchecked(arm, &q), expected);
        if expected {
            colliding += 1;
        } else {
            free += 1;
        }
        let mut per_link = vec![f64::INFINITY; robot.links().len()];
        for (l, p, s) in &parts {
            for (bp, bs) in &boxes {
                let d = reference_distance(p, &**s, bp, &**bs);
                per_link[l.0] = per_link[l.0].min(d);
            }
        }
        let got = world.link_distances(arm, &q).unwrap();
        let mut buf = vec![-1.0; 3];
        world.link_distances_into(arm, &q, &mut buf).unwrap();
        assert_eq!(buf, got);
        for (g, e) in got.iter().zip(&per_link) {
            assert!((g - e).abs() < 5e-5 || (g.is_infinite() && e.is_infinite()), "{got:?} vs {per_link:?}");
        }
        let min = per_link.iter().copied().fold(f64::INFINITY, f64::min);
        let rep = world.distance(arm, &q).unwrap();
        if min > 0.0 {
            assert!((rep.distance - min).abs() < 5e-5, "{} vs {min}", rep.distance);
            assert!(((rep.point_on_robot - rep.point_on_other).norm() - min).abs() < 5e-5);
        } else {
            assert!(rep.distance <= 0.0);
        }
    }
    assert!(colliding > 10 && free > 10, "{colliding} colliding, {free} free");
}

#[test]
fn world_is_shared_between_threads() {
    let (scene, arm, robot) = boxes_scene(3);
    let world = CollisionWorld::new(&scene).unwrap();
    let qs: Vec<Vec<f64>> = {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        (0..40)
            .map(|_| (0..7).map(|i| rng.random_range(robot.dof_limits(i).0..robot.dof_limits(i).1)).collect())
            .collect()
    };
    let serial: Vec<bool> = qs.iter().map(|q| world.in_collision(arm, q).unwrap()).collect();
    let parallel: Vec<Vec<bool>> = std::thread::scope(|s| {
        let handles: Vec<_> =
            (0..2).map(|_| s.spawn(|| qs.iter().map(|q| world.in_collision(arm, q).unwrap()).collect())).collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert!(parallel.iter().all(|p| *p == serial));
}

#[test]
fn set_object_pose_moves_and_detaches() {
    let mut scene = Scene::new("objects");
    let r = scene.add_robot("probe", probe(sphere(0.1)), Isometry3::identity()).unwrap();
    let obj =
        scene.add_object(SceneObject::new("ball", t(2.0, 0.0, 0.0), vec![Shape::at_origin(sphere(0.1))], 0.1)).unwrap();
    let mut world = CollisionWorld::new(&scene).unwrap();
    assert!((world.distance(r, &[]).unwrap().distance - 1.8).abs() < TOL);
    world.set_object_pose(obj, t(0.0, 0.5, 0.0)).unwrap();
    let rep = world.distance(r, &[]).unwrap();
    assert!((rep.distance - 0.3).abs() < TOL);
    assert_eq!(rep.other, Collider::Object(obj));
    // A carried object is no longer an obstacle of its carrier; moving it detaches it.
    world.attach(obj, r, LinkId(0)).unwrap();
    assert!(matches!(world.distance(r, &[]), Err(CoreError::EmptyScene { .. })));
    assert!(matches!(world.attach(obj, r, LinkId(0)), Err(CoreError::InvalidParameter { .. })));
    world.set_object_pose(obj, t(0.0, 0.0, 0.15)).unwrap();
    assert!(world.in_collision(r, &[]).unwrap());
}

#[test]
fn sync_matches_a_fresh_world() {
    let (mut scene, arm, robot) = boxes_scene(9);
    let cube = Shape::at_origin(Geometry::cuboid(0.06, 0.06, 0.06));
    let obj = scene.add_object(SceneObject::new("cube", t(0.0, 0.0, 2.0), vec![cube], 0.1)).unwrap();
    let mut world = CollisionWorld::new(&scene).unwrap();
    // Edit the scene: move the arm, grab the cube at the hand, move the arm again.
    let q1 = [0.3, 0.8, 0.0, 0.9, 0.0, 0.5, 0.0];
    scene.set_robot_configuration(arm, &q1).unwrap();
    let hand = scene.link_world_pose(arm, "tool").unwrap();
    scene.set_object_pose(obj, hand * t(0.0, 0.0, 0.12)).unwrap();
    scene.attach(obj, arm, "tool").unwrap();
    scene.set_robot_configuration(arm, &[-0.5, 0.4, 0.2, 1.2, 0.1, -0.3, 0.0]).unwrap();
    world.sync(&scene).unwrap();
    let fresh = CollisionWorld::new(&scene).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for _ in 0..40 {
        let q: Vec<f64> = (0..7).map(|i| rng.random_range(robot.dof_limits(i).0..robot.dof_limits(i).1)).collect();
        assert_eq!(world.in_collision(arm, &q).unwrap(), fresh.in_collision(arm, &q).unwrap());
        assert_eq!(world.link_distances(arm, &q).unwrap(), fresh.link_distances(arm, &q).unwrap());
        let (a, b) = (world.distance(arm, &q).unwrap(), fresh.distance(arm, &q).unwrap());
        assert_eq!((a.distance, a.attached, a.other), (b.distance, b.attached, b.other));
    }
}

#[test]
fn multi_shape_links_and_compounds() {
    // A dumbbell: two 10 cm spheres 1 m apart along x, on one link.
    let shapes = vec![Shape::new(t(-0.5, 0.0, 0.0), sphere(0.1)), Shape::new(t(0.5, 0.0, 0.0), sphere(0.1))];
    let mut link = Link::new("dumbbell");
    link.collisions = shapes.clone();
    let robot = Arc::new(RobotBuilder::new("dumbbell").link(link).build().unwrap());
    let mut scene = Scene::new("compound");
    let r = scene.add_robot("dumbbell", robot, Isometry3::identity()).unwrap();
    scene.add_body(body("ball", t(1.0, 0.3, 0.0), sphere(0.2))).unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    // Nearest part: the +x sphere, centre distance sqrt(0.25 + 0.09).
    let expected = (0.25_f64 + 0.09).sqrt() - 0.3;
    let rep = world.distance(r, &[]).unwrap();
    assert!((rep.distance - expected).abs() < TOL, "{rep:?}");
    assert!(rep.point_on_robot.x > 0.5);
    // The same shapes as one parry compound.
    let compound = shapes_to_parry(&shapes, MeshRepresentation::Auto).unwrap();
    assert!(compound.as_compound().is_some());
    let d = query::distance(&Isometry3::identity(), &*compound, &t(1.0, 0.3, 0.0), &parry3d_f64::shape::Ball::new(0.2))
        .unwrap();
    assert!((d - expected).abs() < TOL);
    // A single posed mesh has its pose baked in (no compound around a triangle mesh).
    let mesh = Shape::new(t(0.0, 0.0, 2.0), Geometry::Mesh(Arc::new(cube_mesh(0.5))));
    let baked = shapes_to_parry(&[mesh], MeshRepresentation::TriMesh).unwrap();
    let aabb = baked.compute_local_aabb();
    assert!((aabb.mins.z - 1.5).abs() < 1e-12 && (aabb.maxs.z - 2.5).abs() < 1e-12);
    assert!(matches!(shapes_to_parry(&[], MeshRepresentation::Auto), Err(CoreError::InvalidGeometry { .. })));
}

/// Distance from a capsule (axis `a`–`b`, radius `r`) to a box (half extents `h`), both in the
/// box frame, by dense sampling of the axis refined with a ternary search (the distance is
/// convex along the axis).
fn sampled_capsule_box_distance(a: Point3<f64>, b: Point3<f64>, r: f64, h: Vector3<f64>) -> f64 {
    let f = |t: f64| {
        let x = a + (b - a) * t;
        Vector3::new((x.x.abs() - h.x).max(0.0), (x.y.abs() - h.y).max(0.0), (x.z.abs() - h.z).max(0.0)).norm()
    };
    let n = 1000;
    let k = (0..=n).min_by(|&i, &j| f(i as f64 / n as f64).total_cmp(&f(j as f64 / n as f64))).unwrap();
    let (mut lo, mut hi) = (((k as f64 - 1.0) / n as f64).max(0.0), ((k as f64 + 1.0) / n as f64).min(1.0));
    for _ in 0..200 {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if f(m1) <= f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    (f(0.5 * (lo + hi)) - r).max(0.0)
}

#[test]
fn capsule_box_distance_is_exact() {
    let (scene, arm, robot) = boxes_scene(7);
    let world = CollisionWorld::new(&scene).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut checked = 0;
    for _ in 0..12 {
        let q: Vec<f64> = (0..7).map(|i| rng.random_range(robot.dof_limits(i).0..robot.dof_limits(i).1)).collect();
        let got = world.link_distances(arm, &q).unwrap();
        for (l, p, shape) in placed(&robot, &q) {
            let Some(cap) = shape.as_capsule() else { continue };
            let expected = scene
                .bodies()
                .iter()
                .map(|b| {
                    let Geometry::Box { half_extents } = b.shapes[0].geometry else { unreachable!() };
                    let to_box = b.pose.inverse() * p;
                    sampled_capsule_box_distance(
                        to_box * cap.segment.a,
                        to_box * cap.segment.b,
                        cap.radius,
                        half_extents,
                    )
                })
                .fold(f64::INFINITY, f64::min);
            assert!((got[l.0] - expected).abs() < 1e-9, "link {l:?}: {} vs {expected}", got[l.0]);
            checked += 1;
        }
    }
    assert_eq!(checked, 12 * 7);
}
