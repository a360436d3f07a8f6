//! The benchmark is open: a hand from a URDF + spec file, an object from an STL + metadata
//! file and a user's planner run through the grasp benchmark next to the reference planners,
//! and the tables show that planner.

use std::path::{Path, PathBuf};

use opengrasp_bench::report::{self, Format};
use opengrasp_bench::stock::{resolve_hand, resolve_object};
use opengrasp_bench::suite::{Suite, SuiteSize};
use opengrasp_core::hand::Hand;
use opengrasp_core::nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use opengrasp_core::object::ObjectModel;
use opengrasp_core::CoreError;
use opengrasp_grasp::planners::{GraspCandidate, GraspPlanner, GraspRequest, Preshape};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/user_models").join(name)
}

fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("opengrasp-user-models-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A user's planner: top-down grasps over the object's bounding-box centre at `rolls` angles
/// about the vertical, the palm's closing axis turned by each.
struct TopDown {
    rolls: usize,
}

impl GraspPlanner for TopDown {
    fn name(&self) -> &str {
        "top-down"
    }

    fn plan(&self, request: &GraspRequest<'_>) -> opengrasp_grasp::Result<Vec<GraspCandidate>> {
        let (lo, hi) = request.object.aabb();
        let top = Point3::new(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), hi.z);
        let down = Unit::new_normalize(-Vector3::z());
        Ok((0..self.rolls)
            .map(|k| {
                let roll = std::f64::consts::PI * k as f64 / self.rolls as f64;
                let closing = Vector3::new(roll.cos(), roll.sin(), 0.0);
                let hand_pose = opengrasp_grasp::planners::palm_pose(request.hand, &top, &down, &closing);
                GraspCandidate { hand_pose, preshape: Preshape::Default, approach: down, standoff: 0.0 }
            })
            .collect())
    }
}

#[test]
fn a_hand_loads_from_a_urdf_and_a_spec_file() {
    let hand = Hand::load(data("gripper.hand.json")).unwrap();
    assert_eq!(hand.name(), "lab_gripper");
    assert_eq!(hand.robot().dof(), 1);
    assert_eq!(hand.fingers().len(), 2);
    assert_eq!(hand.tactile_links().len(), 2);
    assert_eq!(hand.closing_velocity(), &[-0.05]);
    // The "open" preshape puts each jaw 5 cm from the centre plane.
    assert_eq!(hand.open_configuration(), vec![0.05]);
    assert_eq!(hand.approach().into_inner(), Vector3::z());
    // The stock-or-path resolver takes the same file.
    assert_eq!(resolve_hand(data("gripper.hand.json").to_str().unwrap()).unwrap().name(), "lab_gripper");
}

#[test]
fn an_object_loads_from_a_mesh_and_a_metadata_file() {
    let from_mesh = ObjectModel::load(data("tea_box.stl")).unwrap();
    assert_eq!(from_mesh.name, "tea_box");
    assert!((from_mesh.size() - Vector3::new(0.05, 0.05, 0.08)).norm() < 1e-12, "{:?}", from_mesh.size());
    assert_eq!(from_mesh.mass(), 0.12);
    assert_eq!(from_mesh.friction, 0.5);
    // A uniform box: centre of mass in the middle, I_xx = m (b² + c²) / 12.
    assert!((from_mesh.center_of_mass() - Point3::new(0.0, 0.0, 0.04)).norm() < 1e-12);
    let ixx = 0.12 * (0.05f64.powi(2) + 0.08f64.powi(2)) / 12.0;
    assert!((from_mesh.inertial.inertia[(0, 0)] - ixx).abs() < 1e-12);
    // The same object through a metadata file that names the mesh.
    let dir = scratch("meta");
    let meta = dir.join("box.json");
    let mesh = data("tea_box.stl");
    std::fs::write(
        &meta,
        format!(r#"{{"name": "tea_box", "mesh": {:?}, "mass": 0.12, "friction": 0.5, "scale": 0.001}}"#, mesh),
    )
    .unwrap();
    assert_eq!(ObjectModel::load(&meta).unwrap(), from_mesh);
    assert_eq!(resolve_object(mesh.to_str().unwrap()).unwrap(), from_mesh);
}

#[test]
fn bad_hand_and_object_files_are_typed_errors() {
    let dir = scratch("bad");
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let urdf = data("gripper.urdf");
    let spec = |extra: &str| {
        format!(
            r#"{{"urdf": {urdf:?}, "palm_link": "palm", "approach": [0, 0, 1],
                "fingers": [{{"name": "l", "links": ["left_finger"]}}], "closing": {{"left_joint": -0.05}}{extra}}}"#
        )
    };
    assert!(Hand::load(write("ok.json", &spec(""))).is_ok());
    // The actuation: position servos unless the spec says otherwise; a compliance must be
    // finite and positive, and an unknown model is an error.
    use opengrasp_core::hand::Actuation;
    assert_eq!(Hand::load(write("ok.json", &spec(""))).unwrap().actuation(), Actuation::Position);
    let compliant = Hand::load(write("soft.json", &spec(r#", "actuation": {"compliant": {"compliance": 0.1}}"#)));
    assert_eq!(compliant.unwrap().actuation(), Actuation::Compliant { compliance: 0.1 });
    let position = Hand::load(write("servo.json", &spec(r#", "actuation": "position""#)));
    assert_eq!(position.unwrap().actuation(), Actuation::Position);
    for bad in ["0", "-0.1", "1e999"] {
        let text = spec(&format!(r#", "actuation": {{"compliant": {{"compliance": {bad}}}}}"#));
        let loaded = Hand::load(write("stiff.json", &text));
        assert!(
            matches!(loaded, Err(CoreError::InvalidParameter { .. } | CoreError::MalformedSpec { .. })),
            "{bad}: {loaded:?}"
        );
    }
    for bad in [r#""pneumatic""#, r#"{"compliant": {}}"#, r#"{"compliant": {"compliance": 0.1, "gain": 2}}"#] {
        let loaded = Hand::load(write("model.json", &spec(&format!(r#", "actuation": {bad}"#))));
        assert!(matches!(loaded, Err(CoreError::MalformedSpec { .. })), "{bad}: {loaded:?}");
    }
    // A typo is an error, not a silently ignored key.
    let typo = Hand::load(write("typo.json", &spec(r#", "tactile_link": []"#)));
    assert!(matches!(typo, Err(CoreError::MalformedSpec { .. })), "{typo:?}");
    assert!(matches!(
        Hand::load(write("nourdf.json", r#"{"palm_link": "palm"}"#)),
        Err(CoreError::MalformedSpec { .. })
    ));
    assert!(matches!(Hand::load(write("notjson.json", "palm = 1")), Err(CoreError::MalformedSpec { .. })));
    let bad_link = spec("").replace(r#""palm_link": "palm""#, r#""palm_link": "wrist""#);
    assert!(matches!(Hand::load(write("link.json", &bad_link)), Err(CoreError::UnknownLink { .. })));
    let zero = spec("").replace("[0, 0, 1]", "[0, 0, 0]");
    assert!(matches!(Hand::load(write("zero.json", &zero)), Err(CoreError::InvalidParameter { .. })));
    let twice = spec("").replace(r#"{"left_joint": -0.05}"#, r#"{"left_joint": -0.05, "left_joint": 1}"#);
    assert!(matches!(Hand::load(write("twice.json", &twice)), Err(CoreError::MalformedSpec { .. })));
    assert!(matches!(Hand::load(dir.join("missing.json")), Err(CoreError::Io { .. })));
    // Huge files are refused after reading at most the limit.
    let huge = write("huge.json", &" ".repeat(2 << 20));
    assert!(matches!(Hand::load(&huge), Err(CoreError::FileTooLarge { .. })));
    // Objects: bad mass, no mesh named, a mesh that is not closed.
    let mesh = data("tea_box.stl");
    let object = |body: &str| write("object.json", &format!(r#"{{"mesh": {mesh:?}, {body}}}"#));
    assert!(matches!(
        ObjectModel::load(object(r#""mass": -1, "friction": 0.5"#)),
        Err(CoreError::InvalidParameter { .. })
    ));
    assert!(matches!(
        ObjectModel::load(object(r#""mass": 1, "friction": 0.5, "scale": 0"#)),
        Err(CoreError::InvalidParameter { .. })
    ));
    assert!(matches!(
        ObjectModel::load(write("nomesh.json", r#"{"mass": 1, "friction": 0.5}"#)),
        Err(CoreError::MalformedSpec { .. })
    ));
    let open = write("open.stl", "solid o\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n vertex 0 1 0\n endloop\n endfacet\nendsolid o\n");
    write("open.json", r#"{"mass": 1, "friction": 0.5}"#);
    assert!(matches!(ObjectModel::load(open), Err(CoreError::InvalidParameter { .. })));
}

#[test]
fn user_hand_object_and_planner_run_through_the_grasp_benchmark() {
    let hand = Hand::load(data("gripper.hand.json")).unwrap();
    let object = ObjectModel::load(data("tea_box.stl")).unwrap();
    let suite = Suite::new()
        .with_reference_grasp(SuiteSize::Tiny)
        .grasp_planner("rolls = 4", TopDown { rolls: 4 })
        .hands(vec![hand])
        .objects(vec![object])
        .max_candidates(Some(8))
        .seed(3);
    let results = suite.run().unwrap();
    let grasp = results.grasp.as_ref().unwrap();
    assert_eq!(grasp.hands, ["lab_gripper"]);
    assert_eq!(grasp.objects, ["tea_box"]);
    let planners: Vec<&str> = grasp.cells.iter().map(|r| r.cell.planner.as_str()).collect();
    assert_eq!(planners, ["medial-axis", "surface-normals", "top-down"]);
    let top_down = &grasp.cells[2].cell;
    assert_eq!((top_down.generated, top_down.evaluated), (4, 4));
    // Closing the jaws across the box from above: the fingers meet the 5 cm faces, and a
    // two-sided squeeze with μ = 0.5 on flat faces is force closure.
    assert!(top_down.closed >= 1 && top_down.force_closure >= 1, "{top_down:?}");
    // The report's grasp table has a column group for the user's planner.
    let text = report::render(&results, Format::Markdown);
    assert!(text.contains("top-down"), "{text}");
    assert!(text.contains("lab_gripper") && text.contains("tea_box"), "{text}");
    // And the results file validates and ranks the user's planner like any other.
    let back = opengrasp_bench::ResultsFile::from_json(&results.to_json().unwrap()).unwrap();
    assert!(back.scores().iter().any(|s| s.planner == "top-down" && s.task == "lab_gripper/tea_box"));
}

#[test]
fn palm_pose_helper_is_what_the_user_planner_uses() {
    // Guard the test planner itself: the candidate's approach axis points down.
    let hand = Hand::load(data("gripper.hand.json")).unwrap();
    let info = opengrasp_grasp::evaluator::hand_info(&hand).unwrap();
    let object = ObjectModel::load(data("tea_box.stl")).unwrap();
    let request = GraspRequest { hand: &info, object: &object.mesh, seed: 0 };
    let candidates = TopDown { rolls: 2 }.plan(&request).unwrap();
    let expected = Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.08), UnitQuaternion::identity());
    for c in &candidates {
        assert!((c.hand_pose.translation.vector - expected.translation.vector).norm() < 1e-12);
        let approach_world = c.hand_pose.rotation * info.approach.into_inner();
        assert!((approach_world + Vector3::z()).norm() < 1e-12, "{approach_world:?}");
    }
}
