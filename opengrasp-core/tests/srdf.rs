//! SRDF: groups and allowed collisions written, read back and resolved as MoveIt does; bad
//! documents are typed errors and leave the robot untouched.

use opengrasp_core::model::{samples, Robot};
use opengrasp_core::srdf::{self, DisabledCollision, Srdf};
use opengrasp_core::urdf::{self, ExportOptions};
use opengrasp_core::CoreError;

fn pairs(robot: &Robot) -> Vec<(String, String)> {
    let mut p: Vec<(String, String)> = robot
        .allowed_collision_pairs()
        .map(|(a, b)| (robot.links()[a.0].name.clone(), robot.links()[b.0].name.clone()))
        .collect();
    p.sort();
    p
}

/// The seven-DoF sample arm through URDF alone: its group and explicit pair are lost.
fn urdf_only(robot: &Robot) -> Robot {
    let doc = urdf::to_urdf_string(robot, &ExportOptions::default());
    urdf::from_str(&doc.urdf, &doc.resolver()).unwrap()
}

#[test]
fn urdf_plus_srdf_reload_to_the_same_groups_and_collision_matrix() {
    let arm = samples::seven_dof_arm().unwrap();
    let mut reloaded = urdf_only(&arm);
    assert!(reloaded.groups().is_empty());
    assert_ne!(pairs(&reloaded), pairs(&arm), "link5/link7 is allowed only by the sample's ACM");
    let text = Srdf::from_robot(&arm).to_xml();
    assert!(text.contains(r#"<disable_collisions link1="link5" link2="link7" reason="User"/>"#), "{text}");
    assert!(text.contains(r#"<disable_collisions link1="base" link2="link1" reason="Adjacent"/>"#), "{text}");
    let parsed = Srdf::parse(&text).unwrap();
    assert_eq!(parsed, Srdf::from_robot(&arm));
    let report = parsed.apply(&mut reloaded).unwrap();
    assert_eq!(report.groups, ["arm"]);
    assert!(report.skipped_groups.is_empty());
    assert_eq!(report.allowed_pairs, pairs(&arm).len());
    assert_eq!(reloaded.groups(), arm.groups());
    assert_eq!(pairs(&reloaded), pairs(&arm));
    // And through files.
    let dir = std::env::temp_dir().join(format!("opengrasp-srdf-{}", std::process::id()));
    let path = srdf::export(&arm, &dir).unwrap();
    assert_eq!(path.file_name().unwrap(), "seven_dof_arm.srdf");
    assert_eq!(Srdf::load_file(&path).unwrap(), parsed);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn members_resolve_like_moveit() {
    let mut arm = urdf_only(&samples::seven_dof_arm().unwrap());
    let text = r#"<?xml version="1.0"?>
<robot name="seven_dof_arm">
  <virtual_joint name="world" type="fixed" parent_frame="world" child_link="base"/>
  <group name="whole"><chain base_link="base" tip_link="tool"/></group>
  <group name="wrist"><link name="link5"/><link name="link6"/><joint name="joint7"/><joint name="tool_joint"/></group>
  <group name="upper"><joint name="joint2"/><joint name="joint1"/><group name="wrist"/><joint name="joint1"/></group>
  <group name="tool_only"><link name="tool"/></group>
  <group_state name="home" group="whole"><joint name="joint1" value="0.5"/><joint name="joint4" value="-1"/></group_state>
  <end_effector name="ee" parent_link="tool" group="tool_only"/>
  <disable_collisions link1="link1" link2="link3" reason="Never"/>
</robot>"#;
    let srdf = Srdf::parse(text).unwrap();
    assert_eq!(srdf.robot, "seven_dof_arm");
    assert_eq!(srdf.group_states[0].joints, [("joint1".to_string(), 0.5), ("joint4".to_string(), -1.0)]);
    assert_eq!(
        srdf.disabled_collisions,
        [DisabledCollision { link1: "link1".into(), link2: "link3".into(), reason: "Never".into() }]
    );
    let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    // A chain from base to tip, fixed tool joint dropped.
    let whole = ["joint1", "joint2", "joint3", "joint4", "joint5", "joint6", "joint7"];
    assert_eq!(srdf.group_joints(&arm, "whole").unwrap(), names(&whole));
    // Links by their parent joints; the fixed joint is not a degree of freedom.
    assert_eq!(srdf.group_joints(&arm, "wrist").unwrap(), names(&["joint7", "joint5", "joint6"]));
    // Member order, subgroups expanded, duplicates once.
    assert_eq!(srdf.group_joints(&arm, "upper").unwrap(), names(&["joint2", "joint1", "joint7", "joint5", "joint6"]));
    let report = srdf.apply(&mut arm).unwrap();
    assert_eq!(report.groups, ["whole", "wrist", "upper"]);
    assert_eq!(report.skipped_groups, ["tool_only"]);
    assert_eq!(arm.group("upper").unwrap().dofs(), &[1, 0, 6, 4, 5]);
    let (a, b) = (arm.link_id("link1").unwrap(), arm.link_id("link3").unwrap());
    assert!(arm.is_collision_allowed(a, b));
}

#[test]
fn bad_documents_are_typed_errors_and_change_nothing() {
    let arm = urdf_only(&samples::seven_dof_arm().unwrap());
    let malformed = |text: &str| matches!(Srdf::parse(text), Err(CoreError::MalformedSrdf { .. }));
    assert!(malformed("<robot name=\"x\"><group name=\"g\"><joint name=\"j\"></group></robot>"));
    assert!(malformed("<model name=\"x\"/>"));
    assert!(malformed(""));
    assert!(malformed("<robot><group><joint name=\"joint1\"/></group></robot>"));
    assert!(malformed("<robot><disable_collisions link1=\"a\"/></robot>"));
    assert!(malformed("<robot><group name=\"g\"><chain base_link=\"base\"/></group></robot>"));
    assert!(
        Srdf::parse("<robot><group name=\"g\"><box/></group></robot>").unwrap().ignored == ["<box> inside group `g`"]
    );
    assert!(malformed(
        "<robot><group_state name=\"s\" group=\"g\"><joint name=\"joint1\" value=\"NaN\"/></group_state></robot>"
    ));
    assert!(malformed(
        "<robot><group_state name=\"s\" group=\"g\"><joint name=\"joint1\" value=\"up\"/></group_state></robot>"
    ));

    // Well-formed documents naming what the robot does not have.
    let apply = |text: &str| {
        let mut robot = arm.clone();
        let err = Srdf::parse(text).unwrap().apply(&mut robot).unwrap_err();
        assert!(robot.groups().is_empty() && pairs(&robot) == pairs(&arm), "robot changed by {text}");
        err
    };
    let ok_group = r#"<group name="ok"><joint name="joint1"/></group>"#;
    let err = apply(&format!(r#"<robot>{ok_group}<group name="g"><joint name="elbow"/></group></robot>"#));
    assert!(matches!(err, CoreError::UnknownJoint { ref name } if name == "elbow"), "{err}");
    let err = apply(&format!(r#"<robot>{ok_group}<disable_collisions link1="link1" link2="gripper"/></robot>"#));
    assert!(matches!(err, CoreError::UnknownLink { ref name } if name == "gripper"), "{err}");
    let err =
        apply(r#"<robot><group name="a"><group name="b"/></group><group name="b"><group name="a"/></group></robot>"#);
    assert!(matches!(err, CoreError::MalformedSrdf { ref reason } if reason.contains("contains itself")), "{err}");
    let err = apply(r#"<robot><group name="a"><group name="missing"/></group></robot>"#);
    assert!(matches!(err, CoreError::MalformedSrdf { ref reason } if reason.contains("unknown group")), "{err}");
    let err = apply(r#"<robot><group name="a"><chain base_link="link5" tip_link="link2"/></group></robot>"#);
    assert!(matches!(err, CoreError::MalformedSrdf { ref reason } if reason.contains("does not descend")), "{err}");
    assert!(matches!(Srdf::load_file("/nonexistent/robot.srdf"), Err(CoreError::Io { .. })));
}

mod properties {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

        /// Truncated or corrupted SRDF text parses and applies to a result, never a panic;
        /// a failed apply leaves the robot as it was.
        #[test]
        fn truncated_or_corrupted_srdf(cut in 0usize..2000, pos in 0usize..2000, byte in b' '..b'~') {
            let arm = samples::seven_dof_arm().unwrap();
            let text = Srdf::from_robot(&arm).to_xml();
            let mut bytes = text.clone().into_bytes();
            let pos = pos.min(bytes.len() - 1);
            bytes[pos] = byte;
            let corrupted = String::from_utf8(bytes).unwrap();
            for doc in [&text[..cut.min(text.len())], corrupted.as_str()] {
                if let Ok(srdf) = Srdf::parse(doc) {
                    let mut robot = urdf_only(&arm);
                    let before = pairs(&robot);
                    if srdf.apply(&mut robot).is_err() {
                        prop_assert!(robot.groups().is_empty() && pairs(&robot) == before);
                    }
                }
            }
        }
    }
}
