//! The coordinate-axis shortcut against the general composition and core's forward
//! kinematics, on the Panda (every joint about z) and an arm with skewed and mimic joints.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use opengrasp_core::kinematics::forward_kinematics_into;
use opengrasp_core::model::{samples, JointGroup, JointKind, JointSpec, Link, LinkId, Robot, RobotBuilder};
use opengrasp_core::urdf::{self, LoadOptions, Visuals};
use proptest::prelude::*;

use super::{compose, mat34, Chain, Lanes, Mat34, Place, LANES};

/// The MotionBenchMaker Panda (fingers fixed: seven joints, all about z).
fn panda() -> Robot {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda");
    let options = LoadOptions {
        visuals: Visuals::Skip,
        packages: vec![("meshes".into(), dir.join("meshes"))],
        ..LoadOptions::default()
    };
    urdf::load_file_with(dir.join("panda.urdf"), &options).expect("panda urdf").robot
}

/// Joints about x, −y, z, a skewed axis, a prismatic skewed axis and a −x joint mimicking the
/// first (multiplier −1.3, offset 0.2), each at a rotated origin.
fn skew_arm() -> Robot {
    let skew = Vector3::new(0.48, -0.6, 0.64);
    let joints: [(JointKind, Vector3<f64>); 5] = [
        (JointKind::Revolute, Vector3::x()),
        (JointKind::Revolute, -Vector3::y()),
        (JointKind::Revolute, Vector3::z()),
        (JointKind::Revolute, skew),
        (JointKind::Prismatic, Vector3::new(0.6, 0.0, 0.8)),
    ];
    let mut b = RobotBuilder::new("skew").link(Link::new("l0"));
    for (i, (kind, axis)) in joints.into_iter().enumerate() {
        let turn = UnitQuaternion::from_euler_angles(0.3 * i as f64, -0.7, 1.1 - 0.4 * i as f64);
        let origin = Isometry3::from_parts(Translation3::new(0.1, -0.05 * i as f64, 0.3), turn);
        b = b.link(Link::new(format!("l{}", i + 1))).joint(
            JointSpec::new(format!("j{i}"), kind, format!("l{i}"), format!("l{}", i + 1))
                .origin(origin)
                .axis(axis)
                .limits(-3.0, 3.0, 1.0, 1.0),
        );
    }
    b.link(Link::new("follower"))
        .joint(
            JointSpec::new("mimic", JointKind::Revolute, "l2", "follower")
                .origin(Isometry3::translation(0.0, 0.2, 0.0))
                .axis(-Vector3::x())
                .limits(-5.0, 5.0, 1.0, 1.0)
                .mimic("j0", -1.3, 0.2),
        )
        .build()
        .expect("skew arm")
}

fn base() -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::new(0.4, -0.2, 0.1), UnitQuaternion::from_euler_angles(0.2, 0.1, -0.9))
}

/// The chain of every moving joint of `robot` at [`base`], and the group.
fn chain(robot: &Robot) -> (Chain, JointGroup) {
    let group = JointGroup::all(robot, "all").expect("group");
    (Chain::new(robot, &group, &robot.home_configuration(), &base()), group)
}

/// [`Chain::frames`] without the shortcut: every joint composed with its Rodrigues matrix.
fn general_frames(chain: &Chain, q: &[f64]) -> Vec<Mat34> {
    let mut out = vec![super::IDENTITY];
    for f in &chain.frames {
        let m = compose(&out[f.parent], &f.fixed);
        out.push(compose(&m, &f.motion(q[f.dof])));
    }
    out
}

/// Checks `chain`'s frames at `q` against the general path (bit for bit) and every link's
/// pose against core's forward kinematics (within 1e-12).
fn check(robot: &Robot, chain: &Chain, group: &JointGroup, q: &[f64]) {
    let mut frames = Vec::new();
    chain.frames(q, &mut frames);
    assert_eq!(frames, general_frames(chain, q));
    let mut q_full = robot.home_configuration();
    group.insert(&mut q_full, q).expect("insert");
    let mut poses = Vec::new();
    forward_kinematics_into(robot, &q_full, &mut poses);
    for (l, pose) in poses.iter().enumerate() {
        let (f, local) = chain.link(LinkId(l));
        let ours = compose(&frames[f], &local);
        let theirs = mat34(&(base() * pose));
        for (a, b) in ours.iter().zip(theirs) {
            assert!((a - b).abs() < 1e-12, "link {l}: {ours:?} vs {theirs:?}");
        }
    }
}

#[test]
fn the_panda_turns_about_z_and_the_skew_arm_mixes_axes() {
    let (p, _) = chain(&panda());
    assert_eq!(p.frames.iter().map(|f| f.aligned).collect::<Vec<_>>(), vec![Some((2, 1.0)); 7]);
    let (s, _) = chain(&skew_arm());
    let aligned: Vec<_> = s.frames.iter().map(|f| f.aligned).collect();
    assert_eq!(aligned, [Some((0, 1.0)), Some((1, -1.0)), Some((2, 1.0)), Some((0, -1.0)), None, None]);
}

#[test]
fn the_panda_origins_turn_about_x_and_the_skew_arm_origins_are_general() {
    let (p, _) = chain(&panda());
    let place: Vec<_> = p.frames.iter().skip(1).map(|f| f.place).collect();
    assert_eq!(place, vec![Place::Block(0); 6]);
    assert!(matches!(p.frames[0].place, Place::World(_)));
    // Turned origins, but the follower's (on l2, after j2's frame) is a plain translation.
    let (s, _) = chain(&skew_arm());
    let place: Vec<_> = s.frames.iter().skip(1).map(|f| f.place).collect();
    assert_eq!(place, [Place::General, Place::General, Place::Block(0), Place::General, Place::General]);
}

#[test]
fn a_planar_arm_reaches_its_closed_form_tip() {
    let robot = samples::planar_arm(&[0.5, 0.4]).expect("arm");
    let group = JointGroup::all(&robot, "all").expect("group");
    let chain = Chain::new(&robot, &group, &robot.home_configuration(), &Isometry3::identity());
    let (t0, t1) = (0.7, -1.9);
    let mut frames = Vec::new();
    chain.frames(&[t0, t1], &mut frames);
    let (f, local) = chain.link(robot.link_id("tool").expect("tool"));
    let tip = compose(&frames[f], &local);
    let (x, y) = (0.5 * t0.cos() + 0.4 * (t0 + t1).cos(), 0.5 * t0.sin() + 0.4 * (t0 + t1).sin());
    assert!((tip[3] - x).abs() < 1e-12 && (tip[7] - y).abs() < 1e-12 && tip[11].abs() < 1e-12, "{tip:?}");
    // The tool's x axis points along θ₀ + θ₁.
    assert!((tip[0] - (t0 + t1).cos()).abs() < 1e-12 && (tip[4] - (t0 + t1).sin()).abs() < 1e-12);
}

fn lanes_match(chain: &Chain, qs: &[Vec<f64>]) {
    let dim = qs[0].len();
    let lanes: Vec<Lanes> = (0..dim).map(|d| std::array::from_fn(|l| qs[l][d])).collect();
    let mut out = Vec::new();
    chain.frames_lanes(&lanes, &mut out);
    for (l, q) in qs.iter().enumerate().take(LANES) {
        let mut one = Vec::new();
        chain.frames(q, &mut one);
        for (f, frame) in one.iter().enumerate() {
            assert_eq!(*frame, out[f].map(|v| v[l]), "lane {l} frame {f}");
        }
    }
}

proptest! {
    #[test]
    fn panda_frames_equal_the_general_path(q in prop::collection::vec(-2.8..2.8f64, 7)) {
        let robot = panda();
        let (chain, group) = chain(&robot);
        check(&robot, &chain, &group, &q);
    }

    #[test]
    fn skew_arm_frames_equal_the_general_path(q in prop::collection::vec(-3.0..3.0f64, 5)) {
        let robot = skew_arm();
        let (chain, group) = chain(&robot);
        check(&robot, &chain, &group, &q);
    }

    #[test]
    fn lanes_equal_the_scalar_frames(qs in prop::collection::vec(prop::collection::vec(-3.0..3.0f64, 7), LANES)) {
        lanes_match(&chain(&panda()).0, &qs);
        let skew: Vec<Vec<f64>> = qs.iter().map(|q| q[..5].to_vec()).collect();
        lanes_match(&chain(&skew_arm()).0, &skew);
    }
}
