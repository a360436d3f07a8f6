//! Integration tests of opengrasp-motion on analytic worlds.

use std::f64::consts::PI;
use std::sync::Arc;
use std::time::Duration;

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::kinematics::{forward_kinematics, link_pose_unchecked};
use opengrasp_core::model::{samples, Geometry, JointGroup, JointKind, JointSpec, Link, Robot, RobotBuilder, Shape};
use opengrasp_motion::benchmark::{
    run_benchmark, run_once, BenchmarkOptions, BenchmarkScene, RunRecord, RunStatus, SceneInstance,
};
use opengrasp_motion::metrics::{densify, path_metrics, percentile, smoothness, Stats};
use opengrasp_motion::planners::{IkRrt, Prm, PrmOptions, RrtConnect};
use opengrasp_motion::smoothing::{shortcut, ShortcutOptions};
use opengrasp_motion::validate::{
    path_length, path_valid_discrete, segment_valid_continuous, segment_valid_discrete, validate_path, CcdOptions,
    ValidationOptions,
};
use opengrasp_motion::validity::{AlwaysValid, MotionBound, ObstacleBox, SphereWorld, StateValidityChecker};
use opengrasp_motion::{Goal, MotionError, MotionPlanner, PlanningProblem, PoseGoal, Solution};
use proptest::prelude::*;

/// A two-link planar arm (0.5 m + 0.4 m) with a post in its way between the start and goal.
fn planar_world() -> (Arc<Robot>, JointGroup, SphereWorld) {
    let robot = Arc::new(samples::planar_arm(&[0.5, 0.4]).unwrap());
    let group = JointGroup::all(&robot, "arm").unwrap();
    let boxes = vec![
        ObstacleBox::new("post", Isometry3::translation(0.6, 0.0, 0.0), Vector3::new(0.1, 0.1, 0.5)),
        ObstacleBox::new("wall", Isometry3::translation(-0.7, 0.0, 0.0), Vector3::new(0.1, 0.6, 0.5)),
    ];
    let world = SphereWorld::new(robot.clone(), group.clone(), vec![0.0, 0.0], Isometry3::identity(), boxes).unwrap();
    (robot, group, world)
}

const START: [f64; 2] = [1.2, 0.3];
const GOAL: [f64; 2] = [-1.2, 0.3];

fn problem<'a>(
    robot: &'a Robot,
    group: &'a JointGroup,
    checker: &'a dyn StateValidityChecker,
    start: &'a [f64],
    goal: &'a Goal,
    seed: u64,
) -> PlanningProblem<'a> {
    PlanningProblem {
        robot,
        group,
        q_full: &[0.0, 0.0],
        start,
        goal,
        checker,
        time_limit: Duration::from_secs(10),
        seed,
        step: 0.02,
    }
}

fn planners() -> Vec<Box<dyn MotionPlanner>> {
    vec![
        Box::new(RrtConnect::default()),
        Box::new(Prm::new(PrmOptions { nodes: 150, ..PrmOptions::default() })),
        Box::new(IkRrt::default()),
    ]
}

#[test]
fn straight_line_is_blocked_in_the_planar_world() {
    let (_, _, world) = planar_world();
    assert!(world.is_valid(&START) && world.is_valid(&GOAL));
    assert!(!segment_valid_discrete(&world, &START, &GOAL, 0.02));
}

#[test]
fn planners_solve_the_planar_world_deterministically_with_valid_paths() {
    let (robot, group, world) = planar_world();
    let goal = Goal::Configuration(GOAL.to_vec());
    for mut planner in planners() {
        let ctx = opengrasp_motion::SetupContext {
            robot: &robot,
            group: &group,
            q_full: &[0.0, 0.0],
            checker: &world,
            seed: 1,
            step: 0.02,
        };
        planner.setup(&ctx).unwrap();
        let a = planner.plan(&problem(&robot, &group, &world, &START, &goal, 3)).unwrap();
        planner.setup(&ctx).unwrap();
        let b = planner.plan(&problem(&robot, &group, &world, &START, &goal, 3)).unwrap();
        assert_eq!(a, b, "{}: same seed must give the same path", planner.name());
        assert_eq!(a.path.first().unwrap().as_slice(), &START);
        assert_eq!(a.path.last().unwrap().as_slice(), &GOAL);
        assert!(a.path.len() >= 3, "{}: the direct segment is blocked", planner.name());
        assert!(path_valid_discrete(&world, &a.path, 0.02), "{}", planner.name());
        // Any path from START to GOAL is at least as long as the straight line.
        assert!(path_length(&a.path) >= 2.4 - 1e-12);
    }
}

#[test]
fn different_seeds_give_different_rrt_paths() {
    let (robot, group, world) = planar_world();
    let goal = Goal::Configuration(GOAL.to_vec());
    let mut rrt = RrtConnect::default();
    let a = rrt.plan(&problem(&robot, &group, &world, &START, &goal, 1)).unwrap();
    let b = rrt.plan(&problem(&robot, &group, &world, &START, &goal, 2)).unwrap();
    assert_ne!(a.path, b.path);
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let (robot, group, world) = planar_world();
    let goal = Goal::Configuration(GOAL.to_vec());
    let mut rrt = RrtConnect::default();
    // Start inside the post: link 2 crosses it.
    let bad_start = [0.0, 0.0];
    let e = rrt.plan(&problem(&robot, &group, &world, &bad_start, &goal, 0)).unwrap_err();
    assert!(matches!(e, MotionError::InvalidState { what: "start" }), "{e}");
    let short = [0.1];
    let e = rrt.plan(&problem(&robot, &group, &world, &short, &goal, 0)).unwrap_err();
    assert!(matches!(e, MotionError::DimensionMismatch { expected: 2, actual: 1 }), "{e}");
    let out = [4.0, 0.0];
    let e = rrt.plan(&problem(&robot, &group, &world, &out, &goal, 0)).unwrap_err();
    assert!(matches!(e, MotionError::OutOfLimits { index: 0, .. }), "{e}");
    let nan = [f64::NAN, 0.0];
    let e = rrt.plan(&problem(&robot, &group, &world, &nan, &goal, 0)).unwrap_err();
    assert!(e.is_invalid_input());
}

#[test]
fn prm_reuses_its_roadmap_across_queries() {
    let (robot, group, world) = planar_world();
    let mut prm = Prm::new(PrmOptions { nodes: 120, ..PrmOptions::default() });
    let ctx = opengrasp_motion::SetupContext {
        robot: &robot,
        group: &group,
        q_full: &[0.0, 0.0],
        checker: &world,
        seed: 5,
        step: 0.02,
    };
    prm.setup(&ctx).unwrap();
    let nodes = prm.roadmap_nodes();
    assert_eq!(nodes, 120);
    assert!(prm.roadmap_edges() > 0);
    let g1 = Goal::Configuration(GOAL.to_vec());
    let g2 = Goal::Configuration(vec![-1.5, -0.8]);
    let p1 = prm.plan(&problem(&robot, &group, &world, &START, &g1, 0)).unwrap();
    let after_first = prm.roadmap_nodes();
    let p2 = prm.plan(&problem(&robot, &group, &world, &START, &g2, 0)).unwrap();
    // Query configurations are not added to the roadmap; it only ever grows by samples.
    assert!(after_first >= nodes && prm.roadmap_nodes() >= after_first);
    assert!(path_valid_discrete(&world, &p1.path, 0.02) && path_valid_discrete(&world, &p2.path, 0.02));
    assert_eq!(p2.path.last().unwrap(), &vec![-1.5, -0.8]);
}

/// A three-link planar arm reaching a pose taken from forward kinematics of a known
/// configuration (so it is reachable), with the post in the way.
#[test]
fn ik_rrt_and_rrt_connect_reach_pose_goals() {
    let robot = Arc::new(samples::planar_arm(&[0.4, 0.3, 0.2]).unwrap());
    let group = JointGroup::all(&robot, "arm").unwrap();
    let boxes = vec![ObstacleBox::new("post", Isometry3::translation(0.55, 0.0, 0.0), Vector3::new(0.1, 0.1, 0.5))];
    let world = SphereWorld::new(robot.clone(), group.clone(), vec![0.0; 3], Isometry3::identity(), boxes).unwrap();
    let tip = robot.link_id("tool").unwrap();
    let q_goal = [-1.0, 0.4, 0.3];
    assert!(world.is_valid(&q_goal));
    let target = link_pose_unchecked(&robot, &q_goal, tip);
    let goal = Goal::Pose(PoseGoal { tip, target, position_tolerance: 1e-3, orientation_tolerance: 1e-2 });
    let start = [1.0, 0.3, 0.2];
    let q_full = [0.0; 3];
    for mut planner in [Box::new(IkRrt::default()) as Box<dyn MotionPlanner>, Box::new(RrtConnect::default())] {
        let p = PlanningProblem {
            robot: &robot,
            group: &group,
            q_full: &q_full,
            start: &start,
            goal: &goal,
            checker: &world,
            time_limit: Duration::from_secs(10),
            seed: 11,
            step: 0.02,
        };
        let sol = planner.plan(&p).unwrap();
        let last = sol.path.last().unwrap();
        assert!(p.satisfies_goal(last), "{}", planner.name());
        let Goal::Pose(pg) = &goal else { unreachable!() };
        let (dp, dr) = pg.error(&robot, last);
        assert!(dp <= 1e-3 && dr <= 1e-2, "{}: {dp} {dr}", planner.name());
        assert!(path_valid_discrete(&world, &sol.path, 0.02));
    }
}

#[test]
fn shortcut_straightens_a_zigzag_in_free_space() {
    let path: Vec<Vec<f64>> = (0..=10).map(|i| vec![i as f64 * 0.1, if i % 2 == 0 { 0.0 } else { 0.2 }]).collect();
    let (smoothed, stats) =
        shortcut(&AlwaysValid(2), &path, &ShortcutOptions { iterations: 200, ..Default::default() });
    assert!(stats.accepted > 0);
    assert_eq!(smoothed.first(), path.first());
    assert_eq!(smoothed.last(), path.last());
    let before = path_length(&path);
    let after = path_length(&smoothed);
    assert!(after < before);
    // The straight line is 1.0 long; 200 shortcuts get close to it.
    assert!(after < 1.05, "{after}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]

    /// Shortcutting never lengthens a planned path and keeps it valid under every validator.
    #[test]
    fn shortcut_never_lengthens_and_keeps_validity(seed in 0u64..1000) {
        let (robot, group, world) = planar_world();
        let goal = Goal::Configuration(GOAL.to_vec());
        let sol = RrtConnect::default().plan(&problem(&robot, &group, &world, &START, &goal, seed)).unwrap();
        let options = ShortcutOptions { iterations: 50, seed, ..Default::default() };
        let (smoothed, _) = shortcut(&world, &sol.path, &options);
        prop_assert!(path_length(&smoothed) <= path_length(&sol.path) + 1e-12);
        prop_assert_eq!(smoothed.first(), sol.path.first());
        prop_assert_eq!(smoothed.last(), sol.path.last());
        let before = validate_path(&world, &sol.path, &ValidationOptions::default());
        let after = validate_path(&world, &smoothed, &ValidationOptions::default());
        prop_assert!(after.strict || !before.strict);
        prop_assert!(after.continuous == Some(true) || before.continuous != Some(true));
    }
}

/// One link of length 1 swinging about z past a 2 mm pole: a discrete check at a 0.2 rad step
/// misses the pole, a fine one and the continuous check catch it.
#[test]
fn ccd_catches_a_thin_obstacle_that_coarse_discrete_checking_misses() {
    let robot = Arc::new(samples::planar_arm(&[1.0]).unwrap());
    let group = JointGroup::all(&robot, "arm").unwrap();
    let pole = ObstacleBox::new("pole", Isometry3::translation(0.8, 0.0, 0.0), Vector3::new(0.002, 0.002, 1.0));
    let world = SphereWorld::new(robot, group, vec![0.0], Isometry3::identity(), vec![pole]).unwrap();
    let (a, b) = ([-0.5], [0.5]);
    assert!(world.is_valid(&a) && world.is_valid(&b));
    assert!(segment_valid_discrete(&world, &a, &b, 0.2), "coarse check should miss the pole");
    assert!(!segment_valid_discrete(&world, &a, &b, 0.01));
    assert_eq!(segment_valid_continuous(&world, &a, &b, &CcdOptions::default()), Some(false));
    // A swing that stays clear is certified.
    assert_eq!(segment_valid_continuous(&world, &[0.3], &[1.5], &CcdOptions::default()), Some(true));
    let v = validate_path(
        &world,
        &[a.to_vec(), b.to_vec()],
        &ValidationOptions { step: 0.2, strict_step: 0.02, ..Default::default() },
    );
    assert!(v.discrete && !v.strict && v.continuous == Some(false));
}

/// A robot with a prismatic joint, for the motion-bound property.
fn slider_arm() -> Robot {
    RobotBuilder::new("slider")
        .link(Link::new("base"))
        .link(Link::new("carriage").with_shape(Shape::at_origin(Geometry::cuboid(0.1, 0.1, 0.05))))
        .link(
            Link::new("arm")
                .with_shape(Shape::new(Isometry3::translation(0.3, 0.0, 0.0), Geometry::cuboid(0.6, 0.05, 0.05))),
        )
        .joint(
            JointSpec::new("slide", JointKind::Prismatic, "base", "carriage")
                .axis(Vector3::x())
                .limits(-0.5, 0.5, 1.0, 10.0),
        )
        .joint(
            JointSpec::new("turn", JointKind::Revolute, "carriage", "arm")
                .origin(Isometry3::translation(0.0, 0.1, 0.05))
                .axis(Vector3::z())
                .limits(-2.0, 2.0, 1.0, 10.0),
        )
        .build()
        .unwrap()
}

fn check_bound(robot: &Robot, q: &[f64], dq: &[f64], fractions: &[[f64; 3]]) -> Result<(), TestCaseError> {
    let group = JointGroup::all(robot, "all").unwrap();
    let bound = MotionBound::from_robot(robot, &group).unwrap();
    let mut q1: Vec<f64> = q.iter().zip(dq).map(|(a, d)| a + d).collect();
    robot.clamp_configuration(&mut q1);
    let dq: Vec<f64> = q1.iter().zip(q).map(|(b, a)| b - a).collect();
    let p0 = forward_kinematics(robot, q).unwrap();
    let p1 = forward_kinematics(robot, &q1).unwrap();
    for (i, &link) in bound.links().iter().enumerate() {
        let b = bound.bound(i, &dq);
        for shape in &robot.link(link).collisions {
            let (lo, hi) = shape.geometry.local_aabb();
            for f in fractions {
                let local = shape.origin
                    * Point3::new(
                        lo.x + f[0] * (hi.x - lo.x),
                        lo.y + f[1] * (hi.y - lo.y),
                        lo.z + f[2] * (hi.z - lo.z),
                    );
                let moved = (p1[link] * local - p0[link] * local).norm();
                prop_assert!(moved <= b + 1e-9, "link {}: moved {} > bound {}", link.0, moved, b);
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, .. ProptestConfig::default() })]

    /// B_i(Δq) bounds the displacement of every sampled point of link i (7-DoF arm).
    #[test]
    fn motion_bound_covers_point_displacement_seven_dof(
        q in prop::collection::vec(-2.0f64..2.0, 7),
        dq in prop::collection::vec(-0.5f64..0.5, 7),
        fractions in prop::collection::vec(prop::array::uniform3(0.0f64..=1.0), 4),
    ) {
        let robot = samples::seven_dof_arm().unwrap();
        check_bound(&robot, &q, &dq, &fractions)?;
    }

    /// Same property with a prismatic joint in the chain.
    #[test]
    fn motion_bound_covers_point_displacement_prismatic(
        q in prop::collection::vec(-0.5f64..0.5, 2),
        dq in prop::collection::vec(-1.0f64..1.0, 2),
        fractions in prop::collection::vec(prop::array::uniform3(0.0f64..=1.0), 4),
    ) {
        check_bound(&slider_arm(), &q, &dq, &fractions)?;
    }
}

#[test]
fn motion_bound_of_a_planar_arm_matches_hand_computation() {
    // Link 0 spans x in [0, 0.5] (box 0.5 x 0.04 x 0.04): farthest corner from joint 0 at
    // sqrt(0.5² + 0.02² + 0.02²). Link 1 is 0.5 further along the chain.
    let robot = samples::planar_arm(&[0.5, 0.4]).unwrap();
    let group = JointGroup::all(&robot, "arm").unwrap();
    let bound = MotionBound::from_robot(&robot, &group).unwrap();
    let l0 = (0.5f64.powi(2) + 2.0 * 0.02f64.powi(2)).sqrt();
    let l1 = (0.4f64.powi(2) + 2.0 * 0.02f64.powi(2)).sqrt();
    assert!((bound.radius(0, 0) - l0).abs() < 1e-12);
    assert_eq!(bound.radius(0, 1), 0.0);
    assert!((bound.radius(1, 0) - (0.5 + l1)).abs() < 1e-12);
    assert!((bound.radius(1, 1) - l1).abs() < 1e-12);
    assert!((bound.bound(1, &[0.1, -0.2]) - (0.1 * (0.5 + l1) + 0.2 * l1)).abs() < 1e-12);
}

/// `MotionBound::with_extents` from each link's largest corner norm gives the radii of
/// `MotionBound::from_robot`; a larger extent grows every nonzero radius of its link (revolute
/// joints) by the difference, and a length mismatch is a typed error.
#[test]
fn motion_bound_from_extents_matches_the_bound_from_points() {
    let robot = samples::seven_dof_arm().unwrap();
    let group = robot.group("arm").unwrap().clone();
    let bound = MotionBound::from_robot(&robot, &group).unwrap();
    let extents: Vec<f64> = bound
        .links()
        .iter()
        .map(|&l| {
            let corners = robot.link(l).collisions.iter().flat_map(|s| s.aabb_corners());
            corners.map(|p| p.coords.norm()).fold(0.0, f64::max)
        })
        .collect();
    let same = MotionBound::with_extents(&robot, &group, bound.links(), &extents).unwrap();
    assert_eq!(same, bound);
    let grown: Vec<f64> = extents.iter().map(|e| e + 0.25).collect();
    let grown = MotionBound::with_extents(&robot, &group, bound.links(), &grown).unwrap();
    for k in 0..bound.links().len() {
        for j in 0..group.len() {
            // The sample arm's joints are revolute: each radius moving the link grows.
            let r = bound.radius(k, j);
            let expected = if r > 0.0 { r + 0.25 } else { r };
            assert!((grown.radius(k, j) - expected).abs() < 1e-12, "link {k}, joint {j}");
        }
    }
    assert!(matches!(
        MotionBound::with_extents(&robot, &group, bound.links(), &extents[1..]),
        Err(MotionError::DimensionMismatch { .. })
    ));
}

#[test]
fn metrics_of_an_l_shaped_path() {
    let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
    assert!((path_length(&path) - 2.0).abs() < 1e-12);
    // OMPL smoothness: a right angle between unit segments gives k = 2 (π/2) / 2 = π/2.
    assert!((smoothness(&path) - PI * PI / 4.0).abs() < 1e-12);
    assert_eq!(smoothness(&[vec![0.0, 0.0], vec![1.0, 0.0], vec![2.0, 0.0]]), 0.0);
    let dense = densify(&path, 0.1);
    assert_eq!(dense.len(), 21);
    assert!((path_length(&dense) - 2.0).abs() < 1e-12);
}

#[test]
fn end_effector_length_and_clearance_of_a_swing() {
    // Straight two-link arm (total 2 m) swinging joint 0 by π/2: the tool travels an arc of
    // length 2 · π/2 = π (chords at a 0.01 rad step underestimate it by < 1e-5 relative).
    let robot = samples::planar_arm(&[1.0, 1.0]).unwrap();
    let group = JointGroup::all(&robot, "arm").unwrap();
    let tip = robot.link_id("tool").unwrap();
    let path = vec![vec![0.0, 0.0], vec![PI / 2.0, 0.0]];
    // The wall's near face lies 3 m from the base; links are covered by spheres of radius
    // sqrt(3) · 0.02 centred up to 1.98 m out, so the clearance is 3 - 1.98 - 0.02 sqrt(3) when
    // the arm points at the wall and grows as it turns away.
    let wall = ObstacleBox::new("wall", Isometry3::translation(3.5, 0.0, 0.0), Vector3::new(1.0, 10.0, 1.0));
    let world =
        SphereWorld::new(Arc::new(robot.clone()), group.clone(), vec![0.0, 0.0], Isometry3::identity(), vec![wall])
            .unwrap();
    let m = path_metrics(&robot, &group, &[0.0, 0.0], Some(tip), &world, &path, 0.01);
    assert!((m.ee_length.unwrap() - PI).abs() < 1e-4, "{:?}", m.ee_length);
    assert!((m.length - PI / 2.0).abs() < 1e-12);
    assert_eq!(m.waypoints, 2);
    let expected_min = 3.0 - 1.98 - 0.02 * 3f64.sqrt();
    assert!((m.clearance_min.unwrap() - expected_min).abs() < 1e-9, "{:?}", m.clearance_min);
    assert!(m.clearance_mean.unwrap() > expected_min);
}

#[test]
fn percentiles_interpolate_linearly() {
    let v = [4.0, 1.0, 3.0, 2.0];
    assert_eq!(percentile(&v, 50.0), Some(2.5));
    assert_eq!(percentile(&v, 25.0), Some(1.75));
    assert!((percentile(&v, 95.0).unwrap() - 3.85).abs() < 1e-12);
    assert_eq!(percentile(&v, 0.0), Some(1.0));
    assert_eq!(percentile(&v, 100.0), Some(4.0));
    assert_eq!(percentile(&[], 50.0), None);
    assert_eq!(percentile(&v, 101.0), None);
    let s = Stats::from_options([Some(1.0), None, Some(3.0), Some(f64::NAN)]);
    assert_eq!((s.count, s.missing), (2, 2));
    assert_eq!(s.mean, Some(2.0));
    assert_eq!(s.p50, Some(2.0));
}

/// A user planner that only implements `plan`: the straight line, valid or not.
struct StraightLine;

impl MotionPlanner for StraightLine {
    fn plan(&mut self, problem: &PlanningProblem<'_>) -> opengrasp_motion::Result<Solution> {
        let Goal::Configuration(g) = problem.goal else {
            return Err(MotionError::UnsupportedGoal { planner: "StraightLine".into(), goal: problem.goal.kind() });
        };
        Ok(Solution { path: vec![problem.start.to_vec(), g.clone()], iterations: 1 })
    }
}

fn planar_scene() -> BenchmarkScene {
    BenchmarkScene {
        name: "planar".into(),
        shared_environment: true,
        generate: Box::new(|_| {
            let (robot, group, world) = planar_world();
            let tip = robot.link_id("tool")?;
            Ok(SceneInstance {
                robot,
                group,
                q_full: vec![0.0, 0.0],
                tip: Some(tip),
                start: START.to_vec(),
                goal: Goal::Configuration(GOAL.to_vec()),
                checker: Box::new(world),
                planning_checker: None,
                certifier: None,
            })
        }),
    }
}

#[test]
fn benchmark_grades_every_planner_the_same_way() {
    let mut planners = planners();
    planners.push(Box::new(StraightLine));
    let options = BenchmarkOptions { runs: 3, ..Default::default() };
    let report = run_benchmark(&mut planners, &[planar_scene()], &options);
    assert_eq!(report.runs.len(), 12);
    assert_eq!(report.summaries.len(), 4);
    assert_eq!(report.summaries[3].planner, "StraightLine");
    for s in &report.summaries[..3] {
        assert_eq!(s.solved, 3, "{}", s.planner);
        assert_eq!(s.valid_processed.strict, 100.0, "{}", s.planner);
        assert_eq!(s.valid_processed.continuous, Some(100.0), "{}", s.planner);
        assert!(s.length_processed.p50.unwrap() <= s.length_planned.p50.unwrap() + 1e-9);
        assert!(s.planning_checks.p50.unwrap() > 0.0);
    }
    // The straight line "solves" the query but every validator rejects it.
    let straight = &report.summaries[3];
    assert_eq!(straight.solved, 3);
    assert_eq!(straight.valid_planned.discrete, 0.0);
    assert_eq!(straight.valid_planned.continuous, Some(0.0));
    for r in &report.runs {
        if let (Some(p), Some(q)) = (&r.planned, &r.processed) {
            assert!(q.metrics.length <= p.metrics.length + 1e-9);
            assert!(p.metrics.clearance_mean.is_some() && p.metrics.ee_length.is_some());
        }
    }
    let table = report.table();
    assert!(table.contains("RRT-Connect") && table.contains("valid (continuous)"));
    // Every run round-trips through JSON.
    let json = serde_json::to_string(&report.runs).unwrap();
    let back: Vec<RunRecord> = serde_json::from_str(&json).unwrap();
    assert_eq!(back.len(), report.runs.len());
    assert_eq!(back[0].status, report.runs[0].status);
}

#[test]
fn benchmark_records_invalid_input_and_timeouts() {
    let (robot, group, world) = planar_world();
    let tip = robot.link_id("tool").unwrap();
    let instance = SceneInstance {
        robot,
        group,
        q_full: vec![0.0, 0.0],
        tip: Some(tip),
        start: vec![0.0, 0.0], // in collision with the post
        goal: Goal::Configuration(GOAL.to_vec()),
        checker: Box::new(world),
        planning_checker: None,
        certifier: None,
    };
    let options = BenchmarkOptions::default();
    let r = run_once(&mut RrtConnect::default(), &instance, "bad", 0, 0, 0.0, &options);
    assert_eq!(r.status, RunStatus::InvalidInput);
    assert!(r.planned.is_none() && r.message.is_some());
    // An unreachable goal (the arm folded through the wall side, disconnected by the post and
    // wall) is a timeout, not a panic: here a zero time limit.
    let instance = SceneInstance { start: START.to_vec(), ..instance };
    let options = BenchmarkOptions { time_limit: Duration::ZERO, ..Default::default() };
    let r = run_once(&mut RrtConnect::default(), &instance, "zero", 0, 0, 0.0, &options);
    assert_eq!(r.status, RunStatus::Timeout);
}

/// A planned segment grazing a thin pole just inside the arm's reach (accepted at a coarse
/// step, rejected by the strict and continuous validators) is replaced by a valid detour (the
/// elbow bent so the tip passes short of the pole) by `repair`.
#[test]
fn repair_replaces_a_segment_the_validators_reject() {
    use opengrasp_motion::smoothing::repair;
    let robot = Arc::new(samples::planar_arm(&[0.5, 0.4]).unwrap());
    let group = JointGroup::all(&robot, "arm").unwrap();
    let pole = ObstacleBox::new("pole", Isometry3::translation(0.91, 0.0, 0.0), Vector3::new(0.002, 0.002, 1.0));
    let world =
        SphereWorld::new(robot.clone(), group.clone(), vec![0.0, 0.0], Isometry3::identity(), vec![pole]).unwrap();
    let path = vec![vec![-0.5, 0.0], vec![0.5, 0.0]];
    let validation = ValidationOptions { step: 0.2, strict_step: 0.002, ..Default::default() };
    let before = validate_path(&world, &path, &validation);
    assert!(
        before.discrete && !before.strict && before.continuous == Some(false),
        "{before:?} {:?}",
        world.clearance(&[0.0, 0.0])
    );
    let options = ShortcutOptions { step: 0.002, planning_step: 0.2, ..Default::default() };
    let (fixed, stats) = repair(&world, &path, &group.limits(&robot), &options);
    assert_eq!((stats.repaired, stats.unrepaired), (1, 0));
    assert_eq!(fixed.len(), 3);
    assert_eq!((fixed.first(), fixed.last()), (path.first(), path.last()));
    let after = validate_path(&world, &fixed, &validation);
    assert!(after.discrete && after.strict && after.continuous == Some(true), "{after:?}");
    // A valid path is returned unchanged.
    let (same, stats) = repair(&world, &fixed, &group.limits(&robot), &options);
    assert_eq!(same, fixed);
    assert_eq!((stats.repaired, stats.unrepaired), (0, 0));
}

/// Default planner names: the type's last path segment, and the whole type for a generic
/// wrapper (not a truncated `RrtConnect>`); a planner holding non-`Sync` state is a planner.
#[test]
fn default_planner_names_and_non_sync_planners() {
    use std::cell::Cell;
    struct Straight {
        calls: Cell<usize>,
    }
    impl MotionPlanner for Straight {
        fn plan(&mut self, problem: &PlanningProblem<'_>) -> opengrasp_motion::Result<Solution> {
            self.calls.set(self.calls.get() + 1);
            let Goal::Configuration(goal) = problem.goal else { unreachable!("configuration goals only") };
            Ok(Solution { path: vec![problem.start.to_vec(), goal.clone()], iterations: 1 })
        }
    }
    struct Timed<P>(P);
    impl<P: MotionPlanner> MotionPlanner for Timed<P> {
        fn plan(&mut self, problem: &PlanningProblem<'_>) -> opengrasp_motion::Result<Solution> {
            self.0.plan(problem)
        }
    }
    let straight = Straight { calls: Cell::new(0) };
    assert_eq!(straight.name(), "Straight");
    let timed = Timed(Straight { calls: Cell::new(0) });
    assert!(
        timed.name().ends_with("Timed<motion::default_planner_names_and_non_sync_planners::Straight>"),
        "{}",
        timed.name()
    );
    let mut boxed: Box<dyn MotionPlanner> = Box::new(timed);
    let robot = Arc::new(samples::planar_arm(&[0.5, 0.4]).unwrap());
    let group = JointGroup::all(&robot, "arm").unwrap();
    let checker = opengrasp_motion::validity::AlwaysValid(2);
    let goal = Goal::Configuration(vec![0.5, 0.5]);
    let problem = PlanningProblem {
        robot: &robot,
        group: &group,
        q_full: &[0.0, 0.0],
        start: &[0.0, 0.0],
        goal: &goal,
        checker: &checker,
        time_limit: Duration::from_secs(1),
        seed: 0,
        step: 0.02,
    };
    assert_eq!(boxed.plan(&problem).unwrap().path.len(), 2);
}
