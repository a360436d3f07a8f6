//! `ROS_PACKAGE_PATH` / `AMENT_PREFIX_PATH` as package search roots. Alone in its own test
//! binary: it sets environment variables, which must not race with other threads.

use std::path::Path;

use opengrasp_core::urdf::{self, FileResolver, LoadOptions};
use opengrasp_core::CoreError;

#[test]
fn ros_package_path_finds_packages_by_name() {
    let ws = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ros_ws");
    let text = r#"<robot name="r"><link name="a"><collision><geometry>
        <mesh filename="package://fetch_like_description/meshes/base_link_collision.STL"/>
        </geometry></collision></link></robot>"#;
    let outside = Path::new("/");
    std::env::remove_var("ROS_PACKAGE_PATH");
    std::env::remove_var("AMENT_PREFIX_PATH");
    let r = urdf::from_str(text, &FileResolver::new(outside).with_ros_package_path());
    assert!(matches!(r, Err(CoreError::PackageNotFound { .. })), "{r:?}");
    let path = std::env::join_paths(["/nonexistent/ws", ws.join("fetch_like").to_str().unwrap()]).unwrap();
    std::env::set_var("ROS_PACKAGE_PATH", &path);
    let resolver = FileResolver::new(outside).with_ros_package_path();
    assert_eq!(resolver.search_roots(), [Path::new("/nonexistent/ws"), &ws.join("fetch_like")]);
    assert!(urdf::from_str(text, &resolver).is_ok());
    // load_file uses the variable by default.
    let file = ws.join("universal_robot/ur_description/urdf/ur5.urdf");
    let robot = urdf::load_file_with(&file, &LoadOptions::default()).unwrap().robot;
    assert_eq!(robot.dof(), 6);
    std::env::remove_var("ROS_PACKAGE_PATH");
}
