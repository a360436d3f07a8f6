//! The paper protocol: its steps and checks, setup timing, and the report that says which
//! protocol ran and prints the paper's Table III row beside scene 1.

use opengrasp_bench::report::{self, Format};
use opengrasp_bench::suite::{planar_scene, Suite};
use opengrasp_motion::benchmark::BenchmarkOptions;
use opengrasp_motion::planners::RrtConnect;
use opengrasp_motion::protocol::{Protocol, PAPER_STEP, PAPER_STRICT_STEP};

#[test]
fn protocols_set_steps_and_checks() {
    let base = BenchmarkOptions { runs: 7, seed: 3, ..Default::default() };
    let paper = Protocol::Paper.apply(base.clone());
    assert_eq!((paper.runs, paper.seed, paper.protocol), (7, 3, Protocol::Paper));
    assert_eq!((paper.validation.step, paper.validation.strict_step), (PAPER_STEP, PAPER_STRICT_STEP));
    assert_eq!((paper.shortcut.step, paper.shortcut.planning_step, paper.shortcut.certify), (0.05, 0.05, false));
    // Back to the certified protocol: the defaults again, runs and seed kept.
    let certified = Protocol::Certified.apply(paper);
    assert_eq!(certified, base);
}

#[test]
fn a_paper_protocol_run_is_labelled_and_times_scene_loading() {
    let run = |protocol| {
        Suite::new()
            .motion_planner("defaults", || Box::new(RrtConnect::default()))
            .motion_scene(planar_scene())
            .runs(3)
            .seed(2)
            .protocol(protocol)
            .run()
            .unwrap()
    };
    let paper = run(Protocol::Paper);
    let m = paper.motion.as_ref().unwrap();
    assert_eq!(m.options.protocol, Protocol::Paper);
    assert_eq!(m.options.validation.step, PAPER_STEP);
    // Setup now counts building the scene (robot, checker): never zero, unlike RRT-Connect's
    // empty setup under the certified protocol.
    assert!(m.runs.iter().all(|r| r.setup_time > 0.0), "{:?}", m.runs.iter().map(|r| r.setup_time).collect::<Vec<_>>());
    let certified = run(Protocol::Certified);
    assert!(certified.motion.as_ref().unwrap().runs.iter().all(|r| r.setup_time < 1e-3));
    let text = report::render(&paper, Format::Table);
    assert!(text.contains("Protocol: paper: planning step 0.05"), "{text}");
    assert!(report::render(&certified, Format::Table).contains("Protocol: certified"));
    // No scene 1 in this run: no paper row.
    assert!(!text.contains("/ paper"), "{text}");
}

#[test]
fn table_iii_prints_the_paper_row_beside_scene_1() {
    let mut scene = planar_scene();
    scene.name = opengrasp_bench::paper::PAPER_SCENE_1.to_string();
    let results = Suite::new()
        .motion_planner("defaults", || Box::new(RrtConnect::default()))
        .motion_scene(scene)
        .runs(1)
        .run()
        .unwrap();
    let tables = report::motion_tables(results.motion.as_ref().unwrap());
    let row = format!("{} / paper", opengrasp_bench::paper::PAPER_SCENE_1);
    assert_eq!(tables[0].cell(&row, "setup [ms]"), Some("1440.00"));
    assert_eq!(tables[1].cell(&row, "strict P %"), Some("98.1"));
    assert_eq!(tables[1].cell(&row, "strict PP %"), Some("76.9"));
    assert_eq!(tables[2].cell(&row, "length PP"), Some("2.850"));
    assert_eq!(tables[2].cell(&row, "clear. PP [mm]"), Some("44.3"));
    // The certified checker's continuous column for our row.
    let ours = format!("{} / RRT-Connect", opengrasp_bench::paper::PAPER_SCENE_1);
    assert_eq!(tables[1].cell(&ours, "cont. PP %"), Some("100.0"));
    // With the suite's longest scene label the whole report, legends included, fits 120 columns.
    let text = report::render(&results, Format::Table);
    let widest = text.lines().map(|l| l.chars().count()).max().unwrap();
    assert!(widest <= 120, "{widest} columns:\n{text}");
}
