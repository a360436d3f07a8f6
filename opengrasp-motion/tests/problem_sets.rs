//! Problem sets from files: the JSON format, MotionBenchMaker's YAML problems (a vendored
//! subset: 5 problems each of `table_pick` and `cage` with the Panda, see
//! `tools/vendor_mbm_subset.py`) and hostile input.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use opengrasp_motion::planners::RrtConnect;
use opengrasp_motion::problem_set::{self, Configuration, GoalSpec, LoadedProblemSet, ShapeSpec};
use opengrasp_motion::validate::{distance, path_valid_discrete, DEFAULT_STEP};
use opengrasp_motion::{Goal, MotionPlanner};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mbm/panda")
}

#[test]
fn mbm_set_directory_loads_scenes_and_requests() {
    let sets = problem_set::load(data().join("problems/table_pick_panda")).unwrap();
    assert_eq!(sets.len(), 1);
    let set = &sets[0];
    assert_eq!(set.name, "table_pick_panda");
    assert_eq!(set.problems.len(), 5);
    assert_eq!(set.robot.group.as_deref(), Some("panda_arm"));
    assert!(set.robot.urdf.as_ref().unwrap().ends_with("panda/panda.urdf"));
    let p = &set.problems[0];
    assert_eq!(p.name.as_deref(), Some("0001"));
    // Can1, Cube, Object1..5, four table legs, the table top.
    assert_eq!(p.obstacles.len(), 12);
    let top = p.obstacles.iter().find(|o| o.name == "table_top").unwrap();
    assert_eq!(top.shape, ShapeSpec::Box { size: [1.2, 2.0, 0.04] });
    assert!((top.pose.position[2] - 0.1984669621486253).abs() < 1e-12);
    let can = p.obstacles.iter().find(|o| o.name == "Can1").unwrap();
    assert_eq!(can.shape, ShapeSpec::Cylinder { radius: 0.03, length: 0.12 });
    let Configuration::Named(start) = &p.start else { panic!("named start") };
    assert_eq!(start["panda_joint4"], -2.356);
    assert_eq!(start["panda_finger_joint1"], 0.065);
    let GoalSpec::Configuration(Configuration::Named(goal)) = &p.goal else { panic!("joint goal") };
    assert!((goal["panda_joint1"] + 1.451140183264752).abs() < 1e-15);
    // The scene's allowed-collision matrix: 11 links, the pairs it allows.
    assert!(p.allowed_collisions.contains(&["panda_hand".to_string(), "panda_leftfinger".to_string()]));
}

#[test]
fn a_directory_of_sets_gives_one_set_each_sorted() {
    let sets = problem_set::load(data().join("problems")).unwrap();
    let names: Vec<&str> = sets.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["cage_panda", "table_pick_panda"]);
    assert!(sets.iter().all(|s| s.problems.len() == 5));
}

#[test]
fn loaded_panda_problems_have_valid_starts_and_goals() {
    for set in problem_set::load(data().join("problems")).unwrap() {
        let t = Instant::now();
        let loaded = LoadedProblemSet::new(&set).unwrap();
        eprintln!("{}: loaded in {:?}", set.name, t.elapsed());
        assert_eq!(loaded.len(), 5);
        assert_eq!(loaded.group().len(), 7);
        assert_eq!(loaded.robot().dof(), 7, "the Panda's fingers are fixed joints");
        assert_eq!(loaded.tip(), Some(loaded.robot().link_id("panda_link8").unwrap()));
        for i in 0..loaded.len() {
            let t = Instant::now();
            let inst = loaded.instance(i).unwrap();
            eprintln!("  instance {i}: {:?}", t.elapsed());
            assert_eq!(inst.start, [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785]);
            assert!(inst.checker.is_valid(&inst.start), "{} problem {i}: start in collision", set.name);
            let Goal::Configuration(g) = &inst.goal else { panic!("configuration goal") };
            assert!(inst.checker.is_valid(g), "{} problem {i}: goal in collision", set.name);
        }
    }
}

#[test]
fn rrt_connect_solves_the_vendored_mbm_problems() {
    // Planning only, checked at the planning step (the benchmark's full grading, with strict
    // and continuous validators and clearance, runs in `opengrasp-bench`'s tests and the
    // `opengrasp run motion --problems` figures).
    let mut solved = 0;
    for set in problem_set::load(data().join("problems")).unwrap() {
        let loaded = LoadedProblemSet::new(&set).unwrap();
        for i in 0..loaded.len() {
            let inst = loaded.instance(i).unwrap();
            let problem = inst.problem(&*inst.checker, Duration::from_secs(20), i as u64, DEFAULT_STEP);
            let t = Instant::now();
            let solution = RrtConnect::default().plan(&problem).unwrap();
            eprintln!("{} {i}: {:.1} ms", set.name, t.elapsed().as_secs_f64() * 1e3);
            assert!(distance(&solution.path[0], &inst.start) < 1e-9);
            assert!(problem.satisfies_goal(solution.path.last().unwrap()));
            assert!(path_valid_discrete(&*inst.checker, &solution.path, DEFAULT_STEP));
            solved += 1;
        }
    }
    assert_eq!(solved, 10);
}
