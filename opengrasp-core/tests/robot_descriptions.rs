//! Issue 11: public robot descriptions load as a new user would find them — upstream URDF and
//! SRDF files (MoveIt's panda and pr2 resources, a UR5, a Fetch-like mobile manipulator) with
//! `package://` URIs, `.dae` visuals and MoveIt SRDFs — and build a collision world.
//!
//! The files under `tests/data/ros_ws` are verbatim upstream copies with small stand-in meshes
//! (see the README there).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::Isometry3;
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{Geometry, Robot};
use opengrasp_core::scene::Scene;
use opengrasp_core::srdf::Srdf;
use opengrasp_core::urdf::{self, FileResolver, InMemoryResolver, LoadOptions, LoadWarning, LoadedRobot, Visuals};
use opengrasp_core::CoreError;

fn ws() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ros_ws")
}

/// Loads without the environment's package path, so the test sees only this workspace.
fn load(rel: &str) -> LoadedRobot {
    let options = LoadOptions { ros_package_path: false, ..LoadOptions::default() };
    urdf::load_file_with(ws().join(rel), &options).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

fn group_dofs(robot: &Robot, group: &str) -> usize {
    robot.group(group).unwrap_or_else(|e| panic!("{group}: {e}")).dofs().len()
}

/// Builds a collision world with the robot and checks its home configuration.
fn collision_world(robot: Robot) -> CollisionWorld {
    let mut scene = Scene::new("test");
    let id = scene.add_robot("robot", Arc::new(robot), Isometry3::identity()).unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    let q = scene.robots()[id.0].robot.home_configuration();
    world.in_collision(id, &q).unwrap();
    world
}

fn visual_triangles(robot: &Robot, link: &str) -> Vec<usize> {
    let link = &robot.links()[robot.link_id(link).unwrap().0];
    link.visuals
        .iter()
        .map(|s| match &s.geometry {
            Geometry::Mesh(m) => m.triangles().len(),
            _ => 0,
        })
        .collect()
}

#[test]
fn panda_from_moveit_resources() {
    // package://moveit_resources_panda_description lives in folder `panda_description`:
    // found by its package.xml name, with no configuration.
    let loaded = load("moveit_resources/panda_description/urdf/panda.urdf");
    assert_eq!(loaded.warnings, []);
    let mut robot = loaded.robot;
    assert_eq!(robot.dof(), 8); // 7 arm joints + finger joint 1 (finger joint 2 mimics it)
                                // Each .dae visual holds two geometries of 4 triangles, placed by two nodes.
    assert_eq!(visual_triangles(&robot, "panda_link0"), [8]);
    let srdf = Srdf::load_file(ws().join("moveit_resources/panda_moveit_config/config/panda.srdf")).unwrap();
    assert_eq!(srdf.ignored, ["<passive_joint> inside group `hand`"]);
    assert_eq!(srdf.virtual_joints[0].kind, "floating");
    assert_eq!(srdf.end_effectors[0].parent_group.as_deref(), Some("panda_arm"));
    let report = srdf.apply(&mut robot).unwrap();
    assert_eq!(report.groups, ["panda_arm", "hand", "panda_arm_hand"]);
    assert_eq!((group_dofs(&robot, "panda_arm"), group_dofs(&robot, "hand")), (7, 1));
    assert_eq!(group_dofs(&robot, "panda_arm_hand"), 8);
    assert!(report.allowed_pairs > 20, "{}", report.allowed_pairs);
    collision_world(robot);
}

#[test]
fn panda_with_mimic_on_fixed_finger_joints_loads_with_a_warning() {
    // VAMP's and MotionBenchMaker's panda.urdf: finger joints fixed, the <mimic> kept.
    let path = ws().join("moveit_resources/panda_description/urdf/panda.urdf");
    let text = std::fs::read_to_string(&path).unwrap().replace(r#"type="prismatic""#, r#"type="fixed""#);
    let resolver = urdf::file_resolver(&path, &LoadOptions { ros_package_path: false, ..LoadOptions::default() });
    let loaded = urdf::from_str_with(&text, &resolver, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.robot.dof(), 7);
    assert_eq!(
        loaded.warnings,
        [LoadWarning::MimicIgnored { joint: "panda_finger_joint2".into(), leader: "panda_finger_joint1".into() }]
    );
}

#[test]
fn pr2_from_moveit_resources() {
    let loaded = load("moveit_resources/pr2_description/urdf/robot.xml");
    assert_eq!(loaded.warnings, []);
    let mut robot = loaded.robot;
    assert_eq!(robot.links().len(), 95);
    let srdf = Srdf::load_file(ws().join("moveit_resources/pr2_description/srdf/robot.xml")).unwrap();
    let report = srdf.apply(&mut robot).unwrap();
    // `base` names only the planar virtual joint, which the model does not have.
    assert!(report.skipped_groups.contains(&"base".to_string()), "{report:?}");
    assert_eq!(
        report.ignored,
        [
            "virtual joint `world_joint` in group `base` (not modelled)",
            "virtual joint `world_joint` in group `whole_body` (not modelled)"
        ]
    );
    assert_eq!((group_dofs(&robot, "right_arm"), group_dofs(&robot, "left_arm")), (7, 7));
    assert_eq!(group_dofs(&robot, "arms_and_torso"), 15);
    assert_eq!(group_dofs(&robot, "whole_body"), 15);
    collision_world(robot);
}

#[test]
fn ur5_from_universal_robot() {
    let loaded = load("universal_robot/ur_description/urdf/ur5.urdf");
    assert_eq!(loaded.warnings, []);
    let mut robot = loaded.robot;
    assert_eq!(robot.dof(), 6);
    let srdf = Srdf::load_file(ws().join("universal_robot/ur5_moveit_config/config/ur5.srdf")).unwrap();
    let report = srdf.apply(&mut robot).unwrap();
    assert_eq!(report.groups, ["manipulator"]);
    assert_eq!(report.skipped_groups, ["endeffector"]);
    assert_eq!(group_dofs(&robot, "manipulator"), 6);
    collision_world(robot);
}

#[test]
fn fetch_like_mobile_manipulator() {
    let loaded = load("fetch_like/description/robots/fetch_like.urdf");
    assert_eq!(loaded.warnings, []);
    let mut robot = loaded.robot;
    assert_eq!(robot.dof(), 14); // wheels 2, torso, head 2, arm 7, fingers 2 (bellows mimics the torso)
    let srdf = Srdf::load_file(ws().join("fetch_like/moveit_config/config/fetch_like.srdf")).unwrap();
    assert_eq!(srdf.passive_joints, ["l_wheel_joint", "r_wheel_joint"]);
    let report = srdf.apply(&mut robot).unwrap();
    assert_eq!(report.groups, ["arm", "arm_with_torso", "gripper"]);
    assert_eq!(report.skipped_groups, ["base"]);
    assert_eq!((group_dofs(&robot, "arm"), group_dofs(&robot, "arm_with_torso")), (7, 8));
    assert_eq!(group_dofs(&robot, "gripper"), 2);
    collision_world(robot);
}

#[test]
fn visuals_can_be_skipped() {
    let options = LoadOptions { visuals: Visuals::Skip, ros_package_path: false, ..LoadOptions::default() };
    let loaded = urdf::load_file_with(ws().join("moveit_resources/pr2_description/urdf/robot.xml"), &options).unwrap();
    assert!(loaded.robot.links().iter().all(|l| l.visuals.is_empty()));
    assert!(loaded.robot.links().iter().any(|l| !l.collisions.is_empty()));
}

#[test]
fn a_visual_that_fails_never_fails_the_robot() {
    let text = r#"<robot name="r"><link name="a">
        <visual><geometry><mesh filename="meshes/missing.dae"/></geometry></visual>
        <visual><geometry><mesh filename="meshes/bad.dae"/></geometry></visual>
        <visual><geometry><mesh filename="meshes/texture.png"/></geometry></visual>
        <collision><geometry><box size="0.1 0.2 0.3"/></geometry></collision></link></robot>"#;
    let resolver = InMemoryResolver::new().with_file("meshes/bad.dae", b"<COLLADA><library_geometries>".to_vec());
    let loaded = urdf::from_str_with(text, &resolver, &LoadOptions::default()).unwrap();
    assert!(loaded.robot.links()[0].visuals.is_empty());
    assert_eq!(loaded.robot.links()[0].collisions.len(), 1);
    let indices: Vec<usize> = loaded
        .warnings
        .iter()
        .map(|w| match w {
            LoadWarning::VisualNotLoaded { link, index, .. } if link == "a" => *index,
            other => panic!("{other}"),
        })
        .collect();
    assert_eq!(indices, [0, 1, 2]);
    // A collision mesh that fails still fails the load.
    let broken = text.replace("<box size=\"0.1 0.2 0.3\"/>", "<mesh filename=\"meshes/bad.dae\"/>");
    assert!(matches!(urdf::from_str(&broken, &resolver), Err(CoreError::MeshFormat { .. })));
}

#[test]
fn packages_are_found_by_package_xml_name_under_search_roots() {
    // A file outside any package finds packages only through the search roots.
    let text = r#"<robot name="r"><link name="a"><collision><geometry>
        <mesh filename="package://moveit_resources_panda_description/meshes/collision/link0.stl"/>
        </geometry></collision></link></robot>"#;
    let outside = std::env::temp_dir();
    match urdf::from_str(text, &FileResolver::new(&outside)) {
        Err(CoreError::PackageNotFound { package, searched, .. }) => {
            assert_eq!(package, "moveit_resources_panda_description");
            assert_eq!(searched.first(), Some(&outside)); // every ancestor, in order
        }
        other => panic!("{other:?}"),
    }
    let resolver = FileResolver::new(&outside).with_search_root(ws());
    assert!(urdf::from_str(text, &resolver).is_ok());
    assert_eq!(
        resolver.package_dir("moveit_resources_pr2_description", "package://...").unwrap(),
        ws().join("moveit_resources/pr2_description")
    );
    // The error message lists the paths tried, not just the URI.
    let err = urdf::from_str(&text.replace("moveit_resources_panda", "nope"), &resolver).unwrap_err();
    let message = err.to_string();
    assert!(
        message.contains(&ws().display().to_string()) && message.contains("package `nope_description`"),
        "{message}"
    );
    // A package found but a file missing names the resolved path.
    let missing = text.replace("link0.stl", "link99.stl");
    match urdf::from_str(&missing, &resolver) {
        Err(CoreError::MeshNotFound { path }) => {
            assert_eq!(path, ws().join("moveit_resources/panda_description/meshes/collision/link99.stl"))
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn sibling_packages_of_the_urdf_package_are_found() {
    // A URDF in one package using meshes of a sibling package in the same workspace folder.
    let path = ws().join("universal_robot/ur_description/urdf/ur5.urdf");
    let text = std::fs::read_to_string(&path).unwrap().replace(
        "package://ur_description/meshes/ur5/visual/base.dae",
        "package://moveit_resources_panda_description/meshes/visual/hand.dae",
    );
    // ur_description's siblings are universal_robot/*: the panda package is not among them...
    let resolver = urdf::file_resolver(&path, &LoadOptions { ros_package_path: false, ..LoadOptions::default() });
    let loaded = urdf::from_str_with(&text, &resolver, &LoadOptions::default()).unwrap();
    assert!(matches!(&loaded.warnings[..], [LoadWarning::VisualNotLoaded { .. }]), "{:?}", loaded.warnings);
    // ... and are with the workspace as a search root.
    let options = LoadOptions { search_roots: vec![ws()], ros_package_path: false, ..LoadOptions::default() };
    let loaded = urdf::from_str_with(&text, &urdf::file_resolver(&path, &options), &options).unwrap();
    assert_eq!(loaded.warnings, []);
}
