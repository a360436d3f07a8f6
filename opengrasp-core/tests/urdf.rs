//! URDF loading/writing and mesh file I/O, checked against hand-computed numbers.

use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::mesh_io::{self, MeshFormat};
use opengrasp_core::model::{samples, Geometry, JointKind, Link, Robot, RobotBuilder, Shape, TriangleMesh};
use opengrasp_core::nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use opengrasp_core::urdf::{self, ExportOptions, FileResolver, InMemoryResolver, MeshResolver};
use opengrasp_core::CoreError;

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/test_arm")
}

fn arm_urdf_path() -> PathBuf {
    data_dir().join("urdf/arm.urdf")
}

fn load_arm() -> Robot {
    urdf::load_file(arm_urdf_path()).expect("test arm loads")
}

/// A fresh directory under cargo's per-target temp dir.
fn temp_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("urdf-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
/// Axis-aligned cube of side `s` centred at the origin, outward-facing (12 triangles).
fn cube(s: f64) -> TriangleMesh {
    TriangleMesh::cuboid(nalgebra::Vector3::repeat(s)).unwrap()
}

/// Same triangles in the same order with bit-identical corner coordinates.
fn assert_same_triangles(m: &TriangleMesh, n: &TriangleMesh) {
    assert_eq!(m.triangles().len(), n.triangles().len());
    for (t0, t1) in m.triangles().iter().zip(n.triangles()) {
        for k in 0..3 {
            assert_eq!(m.vertices()[t0[k] as usize], n.vertices()[t1[k] as usize]);
        }
    }
}

fn rot_z(a: f64) -> Rotation3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), a)
}

fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b} (tol {tol})");
}

#[test]
fn test_arm_structure_limits_and_inertials() {
    let robot = load_arm();
    assert_eq!(robot.name(), "test_arm");
    assert_eq!(robot.links().len(), 8);
    assert_eq!(robot.joints().len(), 7);
    // Actuated joints in declaration order; the mimic and fixed joints are not DoFs.
    let dof_names: Vec<&str> = robot.dof_joints().iter().map(|&j| robot.joint(j).name.as_str()).collect();
    assert_eq!(dof_names, ["shoulder", "elbow", "slide", "grip", "beacon_spin"]);
    assert_eq!(robot.dof(), 5);

    let elbow = robot.joint(robot.joint_id("elbow").unwrap());
    assert_eq!(elbow.kind, JointKind::Revolute);
    let l = elbow.limits.unwrap();
    assert_eq!((l.lower, l.upper, l.effort, l.velocity), (-2.5, 2.5, 30.0, 2.0));
    let slide = robot.joint(robot.joint_id("slide").unwrap());
    assert_eq!(slide.kind, JointKind::Prismatic);
    assert_eq!(robot.dof_limits(2), (0.0, 0.2));
    assert_eq!(slide.limits.unwrap().velocity, 0.25);
    let beacon = robot.joint(robot.joint_id("beacon_spin").unwrap());
    assert_eq!(beacon.kind, JointKind::Continuous);
    assert_eq!(robot.dof_limits(4), (f64::NEG_INFINITY, f64::INFINITY));
    let tool = robot.joint(robot.joint_id("tool_joint").unwrap());
    assert_eq!(tool.kind, JointKind::Fixed);
    assert!(tool.dof.is_none());

    let base = robot.link(robot.link_id("base").unwrap());
    let inertial = base.inertial.as_ref().unwrap();
    assert_eq!(inertial.mass, 2.0);
    assert_eq!(inertial.inertia, Matrix3::new(0.01, 0.001, 0.0, 0.001, 0.02, 0.0, 0.0, 0.0, 0.03));
    assert_eq!(inertial.origin, Isometry3::translation(0.0, 0.0, 0.05));
    assert!(inertial.is_physical());
    // No <inertial> element: no mass data.
    assert!(robot.link(robot.link_id("finger_a").unwrap()).inertial.is_none());

    // Primitive geometry: cylinder visual, capsule rotated onto x, box by half extents, sphere.
    assert_eq!(base.visuals[0].geometry, Geometry::Cylinder { radius: 0.1, length: 0.1 });
    let link1 = robot.link(robot.link_id("link1").unwrap());
    assert_eq!(link1.collisions[0].geometry, Geometry::Capsule { radius: 0.03, length: 0.4 });
    // Ry(pi/2) maps the capsule's z axis onto +x.
    let capsule_axis = link1.collisions[0].origin.rotation * Vector3::z();
    assert!((capsule_axis - Vector3::x()).norm() < 1e-15);
    let link2 = robot.link(robot.link_id("link2").unwrap());
    assert_eq!(link2.collisions[0].geometry, Geometry::Box { half_extents: Vector3::new(0.15, 0.025, 0.025) });
    let carriage = robot.link(robot.link_id("carriage").unwrap());
    assert_eq!(carriage.collisions[0].geometry, Geometry::Sphere { radius: 0.02 });
}

#[test]
fn meshes_resolve_by_package_uri_and_relative_path_with_scale() {
    let robot = load_arm();
    // package://test_arm/meshes/cube.stl, a unit cube in ASCII STL scaled by 0.1.
    let base = robot.link(robot.link_id("base").unwrap());
    let Geometry::Mesh(cube) = &base.collisions[0].geometry else { panic!("base collision is not a mesh") };
    assert_eq!(cube.vertices().len(), 8, "36 STL corners weld to 8 vertices");
    assert_eq!(cube.triangles().len(), 12);
    assert!(cube.is_watertight());
    assert_close(cube.signed_volume(), 1e-3, 1e-15, "cube volume 0.1^3");
    let (lo, hi) = cube.aabb();
    assert_close(lo.x, -0.05, 1e-15, "cube min x");
    assert_close(hi.z, 0.05, 1e-15, "cube max z");

    // ../meshes/tool.obj: 0.02 x 0.02 x 0.06 box of quads with per-face normals.
    let tool = robot.link(robot.link_id("tool").unwrap());
    let Geometry::Mesh(visual) = &tool.visuals[0].geometry else { panic!("tool visual is not a mesh") };
    let Geometry::Mesh(collision) = &tool.collisions[0].geometry else { panic!("tool collision is not a mesh") };
    assert!(Arc::ptr_eq(visual, collision), "one file is decoded once and shared");
    assert_eq!(visual.vertices().len(), 8, "24 normal-split OBJ vertices weld to 8");
    assert_eq!(visual.triangles().len(), 12, "6 quads triangulate to 12 triangles");
    assert!(visual.is_watertight());
    assert_close(visual.signed_volume(), 0.02 * 0.02 * 0.06, 1e-18, "tool volume");
}

#[test]
fn forward_kinematics_of_loaded_arm_matches_hand_computation() {
    let robot = load_arm();
    let (t1, t2, d, g, b) = (0.3, -0.5, 0.12, 0.2, 1.0);
    let q = [t1, t2, d, g, b];
    let poses = forward_kinematics(&robot, &q).unwrap();

    // Tool: base -> T(0,0,0.1) Rz(t1) -> T(0.5,0.05,0) Rz(t2) -> T(0.3,0,0) T(d,0,0)
    //       -> T(0.1,0,0) Rz(pi/2).
    // Position = (0,0,0.1) + Rz(t1) [ (0.5, 0.05, 0) + Rz(t2) (0.3 + d + 0.1, 0, 0) ]
    let a = 0.3 + d + 0.1;
    let x = 0.5 * t1.cos() - 0.05 * t1.sin() + a * (t1 + t2).cos();
    let y = 0.5 * t1.sin() + 0.05 * t1.cos() + a * (t1 + t2).sin();
    let z = 0.1;
    let yaw = t1 + t2 + FRAC_PI_2;
    let tool = poses[robot.link_id("tool").unwrap()];
    assert_close(tool.translation.x, x, 1e-12, "tool x");
    assert_close(tool.translation.y, y, 1e-12, "tool y");
    assert_close(tool.translation.z, z, 1e-12, "tool z");
    // Planar chain: orientation is a pure rotation about z by the summed angles.
    assert!(tool.rotation.angle_to(&UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw)) < 1e-12);
    // Numerically: t1 + t2 = -0.2, a = 0.52.
    assert_close(x, 0.5 * 0.3f64.cos() - 0.05 * 0.3f64.sin() + 0.52 * 0.2f64.cos(), 1e-15, "x literal");

    // Beacon on a continuous joint: T(0,0,0.2) Rz(b), independent of the arm.
    let beacon = poses[robot.link_id("beacon").unwrap()];
    assert!((beacon.translation.vector - Vector3::new(0.0, 0.0, 0.2)).norm() < 1e-15);
    assert!((beacon.rotation.to_rotation_matrix().into_inner() - rot_z(b).into_inner()).norm() < 1e-12);
}

#[test]
fn mimic_joint_follows_its_leader() {
    let robot = load_arm();
    let mimic_id = robot.joint_id("grip_mimic").unwrap();
    let mimic = robot.joint(mimic_id);
    let m = mimic.mimic.unwrap();
    assert_eq!(robot.joint(m.leader).name, "grip");
    assert_eq!((m.multiplier, m.offset), (-2.0, 0.1));
    assert!(mimic.dof.is_none());
    assert_eq!(robot.driving_dof(mimic_id), Some((3, -2.0)));

    let (t1, t2, d) = (0.3, -0.5, 0.12);
    for g in [0.0, 0.2, 0.45, 0.8] {
        let q = [t1, t2, d, g, 0.0];
        assert_close(robot.joint_position(&q, mimic_id), -2.0 * g + 0.1, 1e-15, "mimic position");
        let poses = forward_kinematics(&robot, &q).unwrap();
        // finger_b: carriage frame (at (0.3 + d, 0) in link2, yaw t1 + t2) -> T(0.05,-0.02,0)
        //           Rz(-2 g + 0.1).
        let local = Vector3::new(0.3 + d + 0.05, -0.02, 0.0);
        let expected_pos = Vector3::new(0.0, 0.0, 0.1) + rot_z(t1) * (Vector3::new(0.5, 0.05, 0.0) + rot_z(t2) * local);
        let finger_b = poses[robot.link_id("finger_b").unwrap()];
        assert!((finger_b.translation.vector - expected_pos).norm() < 1e-12);
        let expected_yaw = t1 + t2 - 2.0 * g + 0.1;
        let expected = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), expected_yaw);
        assert!(finger_b.rotation.angle_to(&expected) < 1e-12, "g = {g}");
        // The leader finger turns the other way: yaw t1 + t2 + g.
        let finger_a = poses[robot.link_id("finger_a").unwrap()];
        let expected_a = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), t1 + t2 + g);
        assert!(finger_a.rotation.angle_to(&expected_a) < 1e-12);
    }
}

#[test]
fn origin_rpy_is_fixed_axis_roll_pitch_yaw() {
    let text = r#"<robot name="r">
      <link name="a"/><link name="b"/>
      <joint name="j" type="fixed">
        <parent link="a"/><child link="b"/>
        <origin xyz="1 -2 3.5" rpy="0.3 -0.7 1.1"/>
      </joint>
    </robot>"#;
    let robot = urdf::from_str(text, &InMemoryResolver::new()).unwrap();
    let pose = robot.joint(robot.joint_id("j").unwrap()).origin;
    // URDF: R = Rz(yaw) * Ry(pitch) * Rx(roll).
    let expected = Rotation3::from_axis_angle(&Vector3::z_axis(), 1.1)
        * Rotation3::from_axis_angle(&Vector3::y_axis(), -0.7)
        * Rotation3::from_axis_angle(&Vector3::x_axis(), 0.3);
    assert!((pose.rotation.to_rotation_matrix().into_inner() - expected.into_inner()).norm() < 1e-15);
    assert_eq!(pose.translation.vector, Vector3::new(1.0, -2.0, 3.5));
    // The default axis of a joint without <axis> is x, as in URDF.
    assert_eq!(robot.joint(robot.joint_id("j").unwrap()).axis.into_inner(), Vector3::x());
}

#[test]
fn stl_binary_round_trip_keeps_volume_and_welds() {
    let mesh = cube(0.25); // f32-exact coordinates
    let bytes = mesh_io::write_stl_binary(&mesh);
    assert_eq!(bytes.len(), 84 + 50 * 12);
    let back = mesh_io::read_stl(&bytes).unwrap();
    assert_eq!(back.vertices().len(), 8);
    assert_eq!(back.triangles().len(), 12);
    assert!(back.is_watertight());
    assert_close(back.signed_volume(), 0.25f64.powi(3), 1e-15, "cube volume");
    // Triangles come back in order with the same corner coordinates.
    assert_same_triangles(&mesh, &back);
    // Coordinates that are not f32-representable come back rounded to f32.
    let fine = cube(0.1);
    let back = mesh_io::read_stl(&mesh_io::write_stl_binary(&fine)).unwrap();
    assert_eq!(back.vertices().len(), 8);
    assert_close(back.signed_volume(), 1e-3, 1e-9, "f32-rounded cube volume");
    assert_eq!(back.vertices()[0].x, f64::from(-0.05f32));
}

#[test]
fn stl_ascii_and_binary_agree() {
    let ascii = std::fs::read(data_dir().join("meshes/cube.stl")).unwrap();
    let a = mesh_io::read_stl(&ascii).unwrap();
    let b = mesh_io::read_stl(&mesh_io::write_stl_binary(&a)).unwrap();
    assert_eq!(a, b);
    assert_close(a.signed_volume(), 1.0, 1e-15, "unit cube volume");
}

#[test]
fn obj_round_trip_with_several_objects_is_exact() {
    let small = cube(0.1).transformed(&Isometry3::translation(1.0, 0.0, 0.0));
    let big = cube(0.3);
    let text = mesh_io::write_obj(&[("small box", &small), ("big", &big)]);
    assert!(text.contains("o small_box\n"));
    // Second object's faces are offset past the first object's 8 vertices.
    assert!(text.contains("f 9 11 12\n"), "indices offset:\n{text}");

    let objects = mesh_io::read_obj_objects(text.as_bytes()).unwrap();
    assert_eq!(objects.len(), 2);
    assert_eq!(objects[0].0, "small_box");
    // f64 coordinates survive exactly (vertices are renumbered in order of first use).
    assert_same_triangles(&objects[0].1, &small);
    assert_eq!(objects[0].1.vertices().len(), 8);
    assert_eq!(objects[1].0, "big");
    assert_same_triangles(&objects[1].1, &big);
    // Written again, the renumbered mesh reads back identically.
    let again = mesh_io::read_obj(mesh_io::write_obj(&[("b", &objects[1].1)]).as_bytes()).unwrap();
    assert_eq!(again, objects[1].1);

    let merged = mesh_io::read_obj(text.as_bytes()).unwrap();
    assert_eq!(merged.vertices().len(), 16);
    assert_eq!(merged.triangles().len(), 24);
    assert_close(merged.signed_volume(), 0.1f64.powi(3) + 0.3f64.powi(3), 1e-15, "merged volume");
    assert!(merged.is_watertight());
}

#[test]
fn read_mesh_dispatches_on_extension() {
    let stl = mesh_io::write_stl_binary(&cube(0.5));
    assert_eq!(mesh_io::read_mesh(&stl, "a/b/C.STL").unwrap().vertices().len(), 8);
    let obj = mesh_io::write_obj(&[("c", &cube(0.5))]);
    assert_eq!(mesh_io::read_mesh(obj.as_bytes(), "c.obj").unwrap().triangles().len(), 12);
    match mesh_io::read_mesh(&stl, "robot/visual.dae") {
        Err(CoreError::MeshFormat { path, .. }) => assert_eq!(path, Path::new("robot/visual.dae")),
        other => panic!("expected MeshFormat, got {other:?}"),
    }
    assert_eq!(MeshFormat::from_path("x.Obj"), Some(MeshFormat::Obj));
}

/// Compares two robots field by field: names, structure, kinds, limits and mimic exactly;
/// poses within `tol`; mesh triangles corner by corner.
fn assert_same_robot(a: &Robot, b: &Robot, tol: f64) {
    assert_eq!(a.name(), b.name());
    assert_eq!(a.links().len(), b.links().len());
    assert_eq!(a.joints().len(), b.joints().len());
    assert_eq!(a.dof(), b.dof());
    let pose_close = |x: &Isometry3<f64>, y: &Isometry3<f64>| {
        (x.translation.vector - y.translation.vector).norm() <= tol && x.rotation.angle_to(&y.rotation) <= tol
    };
    let shapes_same = |x: &[Shape], y: &[Shape]| {
        assert_eq!(x.len(), y.len());
        for (s, t) in x.iter().zip(y) {
            assert!(pose_close(&s.origin, &t.origin), "{:?} vs {:?}", s.origin, t.origin);
            match (&s.geometry, &t.geometry) {
                (Geometry::Mesh(m), Geometry::Mesh(n)) => assert_same_triangles(m, n),
                (g, h) => assert_eq!(g, h),
            }
        }
    };
    for (la, lb) in a.links().iter().zip(b.links()) {
        assert_eq!(la.name, lb.name);
        match (&la.inertial, &lb.inertial) {
            (Some(i), Some(j)) => {
                assert_eq!(i.mass, j.mass);
                assert_eq!(i.inertia, j.inertia);
                assert!(pose_close(&i.origin, &j.origin));
            }
            (None, None) => {}
            other => panic!("inertial mismatch on {}: {other:?}", la.name),
        }
        shapes_same(&la.visuals, &lb.visuals);
        shapes_same(&la.collisions, &lb.collisions);
    }
    for (ja, jb) in a.joints().iter().zip(b.joints()) {
        assert_eq!(ja.name, jb.name);
        assert_eq!(ja.kind, jb.kind);
        assert_eq!((ja.parent, ja.child), (jb.parent, jb.child));
        assert_eq!(ja.limits, jb.limits);
        assert_eq!(ja.mimic, jb.mimic);
        assert_eq!(ja.dof, jb.dof);
        assert!(pose_close(&ja.origin, &jb.origin), "joint {} origin", ja.name);
        assert!((ja.axis.into_inner() - jb.axis.into_inner()).norm() <= tol);
    }
}

#[test]
fn export_then_load_gives_the_same_model() {
    let robot = load_arm();
    let dir = temp_dir("export");
    let path = urdf::export(&robot, &dir).unwrap();
    assert_eq!(path, dir.join("test_arm.urdf"));
    // Two distinct meshes (cube, shared tool mesh) -> two STL files.
    let meshes: Vec<_> = std::fs::read_dir(dir.join("meshes")).unwrap().collect();
    assert_eq!(meshes.len(), 2);
    let again = urdf::load_file(&path).unwrap();
    // The test arm's mesh coordinates (0.05, 0.01, 0.03, ...) are not f32-exact, so STL
    // rounds them; everything else round-trips to 1e-12.
    let doc = urdf::to_urdf_string(&robot, &ExportOptions { mesh_format: MeshFormat::Obj, ..Default::default() });
    let exact = urdf::from_str(&doc.urdf, &doc.resolver()).unwrap();
    assert_same_robot(&robot, &exact, 1e-12);
    // Through STL: identical apart from f32 rounding of mesh vertices.
    let base = again.link(again.link_id("base").unwrap());
    let Geometry::Mesh(cube) = &base.collisions[0].geometry else { panic!("mesh expected") };
    assert_eq!(cube.vertices()[0].x, f64::from(-0.05f32));
    let mut robot_f32 = robot.clone();
    for l in 0..robot_f32.links().len() {
        let link = robot_f32.link_mut(opengrasp_core::model::LinkId(l));
        for s in link.visuals.iter_mut().chain(link.collisions.iter_mut()) {
            if let Geometry::Mesh(m) = &s.geometry {
                let v = m.vertices().iter().map(|p| p.map(|c| f64::from(c as f32))).collect();
                s.geometry = Geometry::Mesh(Arc::new(TriangleMesh::new(v, m.triangles().to_vec()).unwrap()));
            }
        }
    }
    assert_same_robot(&robot_f32, &again, 1e-12);
    // Same configuration, same poses.
    let q = [0.4, 1.1, 0.05, 0.3, -2.0];
    let (p0, p1) = (forward_kinematics(&robot, &q).unwrap(), forward_kinematics(&again, &q).unwrap());
    for (x, y) in p0.as_slice().iter().zip(p1.as_slice()) {
        assert!((x.translation.vector - y.translation.vector).norm() < 1e-12);
        assert!(x.rotation.angle_to(&y.rotation) < 1e-12);
    }
    // Exporting the reloaded robot reproduces the same text.
    let doc2 = urdf::to_urdf_string(&exact, &ExportOptions { mesh_format: MeshFormat::Obj, ..Default::default() });
    assert_eq!(doc2, doc);
    assert!(!doc.urdf.contains("-0.0 "), "negative zeros are written as 0.0");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn export_round_trips_awkward_numbers_capsules_and_names() {
    // Floats that need all 17 digits, rotations off the axes, a capsule, a name needing escapes.
    let third = 1.0 / 3.0;
    let origin = Isometry3::from_parts(
        Translation3::new(third, -1e-7, 12345.678901234567),
        UnitQuaternion::from_euler_angles(0.1, -1.2, 2.9),
    );
    let robot = RobotBuilder::new("odd <robot> & \"co\"")
        .link(Link::new("base").with_shape(Shape::new(origin, Geometry::Capsule { radius: third, length: 0.0 })))
        .link(Link::new("tip").with_shape(Shape::at_origin(Geometry::Mesh(Arc::new(cube(0.5))))))
        .joint(
            opengrasp_core::model::JointSpec::new("j1", JointKind::Prismatic, "base", "tip")
                .origin(origin)
                .axis(Vector3::new(0.0, 0.6, 0.8))
                .limits(-third, 2.0 * third, f64::INFINITY, 1e300),
        )
        .build()
        .unwrap();
    let doc = urdf::to_urdf_string(&robot, &ExportOptions::default());
    let again = urdf::from_str(&doc.urdf, &doc.resolver()).unwrap();
    assert_same_robot(&robot, &again, 1e-12);
    assert_eq!(again.name(), "odd <robot> & \"co\"");
    assert_eq!(again.joint(opengrasp_core::model::JointId(0)).limits.unwrap().velocity, f64::INFINITY);

    // The 7-DoF sample arm (capsule links) round-trips too.
    let arm = samples::seven_dof_arm().unwrap();
    let doc = urdf::to_urdf_string(&arm, &ExportOptions::default());
    assert!(doc.mesh_files.is_empty());
    assert_same_robot(&arm, &urdf::from_str(&doc.urdf, &InMemoryResolver::new()).unwrap(), 1e-12);
}

#[test]
fn in_memory_resolver_needs_no_files() {
    let stl = mesh_io::write_stl_binary(&cube(1.0));
    let obj = mesh_io::write_obj(&[("finger", &cube(0.5))]);
    let resolver = InMemoryResolver::new()
        .with_file("package://virtual_pkg/meshes/palm.stl", stl)
        .with_file("meshes/finger.obj", obj.into_bytes());
    let text = r#"<robot name="virtual">
      <link name="palm"><collision><geometry>
        <mesh filename="package://virtual_pkg/meshes/palm.stl" scale="0.1 0.2 0.3"/>
      </geometry></collision></link>
      <link name="finger"><collision><geometry><mesh filename="./meshes/finger.obj"/></geometry></collision></link>
      <joint name="j" type="prismatic"><parent link="palm"/><child link="finger"/>
        <axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="20" velocity="0.1"/></joint>
    </robot>"#;
    let robot = urdf::from_str(text, &resolver).unwrap();
    let Geometry::Mesh(palm) = &robot.link(robot.root()).collisions[0].geometry else { panic!("mesh expected") };
    // Unit cube scaled by (0.1, 0.2, 0.3).
    assert_close(palm.signed_volume(), 0.1 * 0.2 * 0.3, 1e-15, "scaled volume");
    let (lo, hi) = palm.aabb();
    assert_eq!((lo.y, hi.z), (-0.1, 0.15));
    let finger = robot.link(robot.link_id("finger").unwrap());
    assert_close(finger.collisions[0].geometry.volume(), 0.125, 1e-15, "finger volume");
    // Trait objects work (Send + Sync, boxed).
    let boxed: Box<dyn MeshResolver> = Box::new(resolver);
    assert!(urdf::from_str(text, &boxed).is_ok());
}

#[test]
fn file_resolver_with_registered_package() {
    let text = r#"<robot name="r"><link name="a"><collision><geometry>
        <mesh filename="package://assets/meshes/cube.stl"/></geometry></collision></link></robot>"#;
    let resolver = FileResolver::new("/nonexistent").with_package("assets", data_dir());
    let robot = urdf::from_str(text, &resolver).unwrap();
    assert_close(robot.links()[0].collisions[0].geometry.volume(), 1.0, 1e-15, "unit cube");
    // file:// URI with an absolute path.
    let abs = format!("file://{}", data_dir().join("meshes/cube.stl").display());
    let text = text.replace("package://assets/meshes/cube.stl", &abs);
    assert!(urdf::from_str(&text, &FileResolver::new("/nonexistent")).is_ok());
}

// ---- errors -------------------------------------------------------------------------------

const ONE_MESH: &str = r#"<robot name="r"><link name="a"><collision><geometry>
    <mesh filename="FILE"/></geometry></collision></link></robot>"#;

#[test]
fn malformed_xml_is_a_typed_error() {
    for text in ["<robot name=\"r\"><link name=\"a\">", "not xml at all", "<robot name=\"r\"></robot>", ""] {
        let r = urdf::from_str(text, &InMemoryResolver::new());
        assert!(matches!(r, Err(CoreError::MalformedUrdf { .. })), "{text:?} gave {r:?}");
    }
    // Structural problems found by the builder are reported as malformed URDF too.
    let two_roots = r#"<robot name="r"><link name="a"/><link name="b"/></robot>"#;
    assert!(matches!(urdf::from_str(two_roots, &InMemoryResolver::new()), Err(CoreError::MalformedUrdf { .. })));
    let bad_radius = r#"<robot name="r"><link name="a"><collision><geometry><sphere radius="-1"/></geometry></collision></link></robot>"#;
    assert!(matches!(urdf::from_str(bad_radius, &InMemoryResolver::new()), Err(CoreError::MalformedUrdf { .. })));
    // The same in a visual leaves the visual out, with a warning.
    let visual = bad_radius.replace("collision>", "visual>");
    let loaded = urdf::from_str_with(&visual, &InMemoryResolver::new(), &urdf::LoadOptions::default()).unwrap();
    assert!(loaded.robot.links()[0].visuals.is_empty());
    assert!(matches!(&loaded.warnings[..], [urdf::LoadWarning::VisualNotLoaded { index: 0, .. }]));
}

#[test]
fn missing_mesh_is_mesh_not_found() {
    let text = ONE_MESH.replace("FILE", "meshes/nope.stl");
    match urdf::from_str(&text, &InMemoryResolver::new()) {
        Err(CoreError::MeshNotFound { path }) => assert_eq!(path, Path::new("meshes/nope.stl")),
        other => panic!("expected MeshNotFound, got {other:?}"),
    }
    match urdf::from_str(&text, &FileResolver::new(data_dir())) {
        Err(CoreError::MeshNotFound { path }) => assert_eq!(path, data_dir().join("meshes/nope.stl")),
        other => panic!("expected MeshNotFound, got {other:?}"),
    }
    assert!(matches!(urdf::load_file(data_dir().join("urdf/missing.urdf")), Err(CoreError::Io { .. })));
}

/// A binary STL whose header promises 5 triangles but holds 1.
fn truncated_binary_stl() -> Vec<u8> {
    let mut bytes = mesh_io::write_stl_binary(&cube(1.0));
    bytes[80..84].copy_from_slice(&5u32.to_le_bytes());
    bytes.truncate(84 + 50);
    bytes
}

#[test]
fn undecodable_mesh_is_mesh_format() {
    let text = ONE_MESH.replace("FILE", "bad.stl");
    let cases: [(&str, Vec<u8>); 4] = [
        ("bad.stl", b"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0\n".to_vec()),
        ("bad.stl", truncated_binary_stl()),
        ("bad.obj", b"v 0 0 0\nf 1 2 3\n".to_vec()),
        ("bad.dae", b"<COLLADA/>".to_vec()),
    ];
    for (name, bytes) in cases {
        let resolver = InMemoryResolver::new().with_file(name, bytes);
        let r = urdf::from_str(&text.replace("bad.stl", name), &resolver);
        assert!(matches!(r, Err(CoreError::MeshFormat { .. })), "{name} gave {r:?}");
    }
}

#[test]
fn degenerate_mesh_is_degenerate_mesh() {
    // Every triangle has zero area (collinear corners).
    let flat = "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
    let resolver = InMemoryResolver::new().with_file("flat.obj", flat.as_bytes().to_vec());
    let r = urdf::from_str(&ONE_MESH.replace("FILE", "flat.obj"), &resolver);
    assert!(matches!(r, Err(CoreError::DegenerateMesh { .. })), "{r:?}");
    // A zero scale collapses a good mesh.
    let resolver = InMemoryResolver::new().with_file("c.stl", mesh_io::write_stl_binary(&cube(1.0)));
    let text = ONE_MESH.replace("\"FILE\"", "\"c.stl\" scale=\"1 0 1\"");
    assert!(matches!(urdf::from_str(&text, &resolver), Err(CoreError::DegenerateMesh { .. })));
    // An empty binary STL decodes but has no triangles.
    let mut empty = vec![0u8; 80];
    empty.extend_from_slice(&0u32.to_le_bytes());
    assert!(matches!(mesh_io::read_stl(&empty), Err(CoreError::DegenerateMesh { .. })));
    // Zero-area faces mixed into a good mesh are dropped, not fatal.
    let mut with_sliver = mesh_io::write_obj(&[("c", &cube(1.0))]);
    with_sliver.push_str("v 0 0 0\nv 0.1 0 0\nv 0.2 0 0\nf 9 10 11\n");
    let mesh = mesh_io::read_obj(with_sliver.as_bytes()).unwrap();
    assert_eq!(mesh.triangles().len(), 12);
}

#[test]
fn mimic_of_unknown_joint_is_unknown_joint() {
    let text = r#"<robot name="r"><link name="a"/><link name="b"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/>
        <mimic joint="ghost" multiplier="2"/></joint></robot>"#;
    match urdf::from_str(text, &InMemoryResolver::new()) {
        Err(CoreError::UnknownJoint { name }) => assert_eq!(name, "ghost"),
        other => panic!("expected UnknownJoint, got {other:?}"),
    }
}

#[test]
fn joint_limit_edge_cases() {
    // URDF 1.0: a revolute or prismatic joint needs <limit>.
    for kind in ["revolute", "prismatic"] {
        let text = format!(
            r#"<robot name="r"><link name="a"/><link name="b"/>
            <joint name="j" type="{kind}"><parent link="a"/><child link="b"/></joint></robot>"#
        );
        let r = urdf::from_str(&text, &InMemoryResolver::new());
        assert!(matches!(r, Err(CoreError::MalformedUrdf { .. })), "{kind}: {r:?}");
    }
    // URDF 1.2: omitted revolute limits mean unlimited, i.e. a continuous joint.
    let text = r#"<robot name="r" version="1.2"><link name="a"/><link name="b"/>
        <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
        <limit effort="3" velocity="4"/></joint></robot>"#;
    let robot = urdf::from_str(text, &InMemoryResolver::new()).unwrap();
    assert_eq!(robot.joints()[0].kind, JointKind::Continuous);
    assert_eq!(robot.dof_limits(0), (f64::NEG_INFINITY, f64::INFINITY));
    // ... but an unbounded prismatic joint cannot be modelled.
    let text = text.replace("revolute", "prismatic");
    assert!(matches!(urdf::from_str(&text, &InMemoryResolver::new()), Err(CoreError::MalformedUrdf { .. })));
}

#[test]
fn try_from_parsed_urdf_rs_robot() {
    let text = std::fs::read_to_string(arm_urdf_path()).unwrap();
    let parsed = urdf::urdf_rs::read_from_string(&text).unwrap();
    // Mesh paths resolve against the working directory (the package root under cargo test),
    // where package `test_arm` is not found.
    assert!(matches!(Robot::try_from(&parsed), Err(CoreError::PackageNotFound { .. })));
    let resolver = FileResolver::new(data_dir().join("urdf"));
    let robot = urdf::from_urdf_rs(&parsed, &resolver).unwrap();
    assert_same_robot(&robot, &load_arm(), 0.0);
    let simple = urdf::urdf_rs::read_from_string(r#"<robot name="s"><link name="a"/></robot>"#).unwrap();
    assert_eq!(Robot::try_from(&simple).unwrap().links().len(), 1);
}

#[test]
fn floating_and_planar_joints_are_rejected() {
    for kind in ["floating", "planar"] {
        let text = format!(
            r#"<robot name="r"><link name="a"/><link name="b"/>
            <joint name="j" type="{kind}"><parent link="a"/><child link="b"/></joint></robot>"#
        );
        match urdf::from_str(&text, &InMemoryResolver::new()) {
            Err(CoreError::MalformedUrdf { reason }) => assert!(reason.contains("unsupported type"), "{reason}"),
            other => panic!("expected MalformedUrdf for {kind}, got {other:?}"),
        }
    }
}

#[test]
fn export_rejects_escaping_mesh_dir() {
    let robot = samples::planar_arm(&[0.5, 0.4]).unwrap();
    let dir = temp_dir("escape");
    for bad in ["../out", "/abs/meshes"] {
        let r = urdf::export_with(&robot, &dir, &ExportOptions { mesh_dir: bad.to_string(), ..Default::default() });
        assert!(matches!(r, Err(CoreError::InvalidParameter { .. })), "{bad}");
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "nothing written");
    let _ = std::fs::remove_dir_all(&dir);
}

mod never_panics {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        /// Truncated or corrupted URDF text gives a result, never a panic.
        #[test]
        fn truncated_or_corrupted_urdf(cut in 0usize..4000, pos in 0usize..4000, byte in b' '..b'~') {
            let text = std::fs::read_to_string(arm_urdf_path()).unwrap();
            let resolver = FileResolver::new(data_dir().join("urdf"));
            let cut = cut.min(text.len());
            let _ = urdf::from_str(&text[..cut], &resolver);
            let mut bytes = text.into_bytes();
            let pos = pos.min(bytes.len() - 1);
            bytes[pos] = byte;
            if let Ok(corrupted) = String::from_utf8(bytes) {
                let _ = urdf::from_str(&corrupted, &resolver);
            }
        }

        /// Arbitrary bytes and OBJ-like text decode to a mesh or a typed error.
        #[test]
        fn arbitrary_mesh_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400), obj in "[vf0-9 ./\\-\n]{0,200}") {
            for r in [mesh_io::read_stl(&bytes), mesh_io::read_obj(&bytes), mesh_io::read_obj(obj.as_bytes())] {
                if let Err(e) = r {
                    prop_assert!(matches!(e, CoreError::MeshFormat { .. } | CoreError::DegenerateMesh { .. }), "{e:?}");
                }
            }
        }
    }
}
