//! The runner: results files (round trip, atomic writes, validation, provenance), reports,
//! parallel == serial, and the command line end to end (tiny suites).

use std::path::{Path, PathBuf};

use clap::Parser;
use opengrasp::bench::stock::{resolve_object, stock_hand, stock_object};
use opengrasp::cli::{self, CheckerArg, Cli, Command, FormatArg, ListWhat, PlotFormatArg, RunArgs, SizeArg, Which};
use opengrasp::grasp::benchmark::CellResult;
use opengrasp::motion::benchmark::{BenchmarkOptions, PathReport, RunRecord, RunStatus};
use opengrasp::motion::metrics::PathMetrics;
use opengrasp::motion::planners::{Prm, PrmOptions, RrtConnect};
use opengrasp::motion::validate::PathValidity;
use opengrasp::report::{self, Format};
use opengrasp::results::{
    self, write_atomic, Error, GraspRecord, GraspSection, MotionSection, PlannerInfo, Provenance, ResultsFile,
    SCHEMA_VERSION,
};
use opengrasp::suite::{planar_scene, Suite, SuiteSize};

/// A fresh empty directory under the system temp dir.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("opengrasp-runner-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn cell(
    planner: &str,
    hand: &str,
    object: &str,
    evaluated: usize,
    palm: usize,
    fc_palm: usize,
    fc: usize,
) -> CellResult {
    let pct = |a: usize, b: usize| if b == 0 { 0.0 } else { 100.0 * a as f64 / b as f64 };
    CellResult {
        planner: planner.into(),
        hand: hand.into(),
        object: object.into(),
        generated: evaluated * 2,
        evaluated,
        closed: evaluated,
        palm_contact: palm,
        force_closure_palm: fc_palm,
        force_closure: fc,
        fc_percent_palm: pct(fc_palm, palm),
        fc_percent_all: pct(fc, evaluated),
        mean_epsilon: 0.05,
        median_epsilon: 0.04,
        physics_tested: 0,
        physics_held: 0,
        physics_slipped: 0,
        physics_dropped: 0,
        physics_grip_moved: 0,
        planning_seconds: 0.01,
        evaluation_seconds: 0.2,
        evaluations_per_second: evaluated as f64 / 0.2,
        candidates: Vec::new(),
    }
}

fn path_report(length: f64, clearance: f64, valid: bool) -> PathReport {
    PathReport {
        validity: PathValidity { discrete: valid, strict: valid, continuous: None },
        metrics: PathMetrics {
            waypoints: 5,
            length,
            ee_length: None,
            clearance_mean: Some(clearance),
            clearance_min: Some(clearance / 2.0),
            smoothness: 0.5,
        },
    }
}

fn run(planner: &str, run: usize, status: RunStatus, planning_time: f64, length: f64) -> RunRecord {
    let solved = status == RunStatus::Solved;
    RunRecord {
        planner: planner.into(),
        scene: "scene A".into(),
        run,
        seed: run as u64,
        status,
        message: (!solved).then(|| "planning timed out".to_string()),
        setup_time: 0.5,
        planning_time,
        postprocessing_time: solved.then_some(0.1),
        planning_checks: 100,
        postprocessing_checks: 50,
        iterations: solved.then_some(10),
        shortcuts: solved.then_some(2),
        repaired_segments: solved.then_some(0),
        unrepaired_segments: solved.then_some(0),
        planned: solved.then(|| path_report(length * 2.0, 0.2, run != 1)),
        processed: solved.then(|| path_report(length, 0.1, true)),
        final_state: solved.then(|| vec![0.1, 0.2]),
        ik_position_error: None,
        ik_orientation_error: None,
    }
}

/// A hand-made results file with known numbers.
fn hand_made() -> ResultsFile {
    let mut file = ResultsFile::new(Provenance::collect("custom", 1));
    let planners = vec![
        PlannerInfo { name: "medial-axis".into(), parameters: "defaults".into() },
        PlannerInfo { name: "surface-normals".into(), parameters: "defaults".into() },
    ];
    file.grasp = Some(GraspSection {
        seed: 3,
        hands: vec!["barrett".into()],
        objects: vec!["salt_can".into(), "white_cup".into()],
        max_candidates: Some(20),
        planners,
        cells: vec![
            GraspRecord { seed: 3, cell: cell("medial-axis", "barrett", "salt_can", 20, 10, 7, 9) },
            GraspRecord { seed: 3, cell: cell("surface-normals", "barrett", "salt_can", 20, 4, 1, 2) },
            GraspRecord { seed: 3, cell: cell("medial-axis", "barrett", "white_cup", 20, 10, 3, 3) },
            GraspRecord { seed: 3, cell: cell("surface-normals", "barrett", "white_cup", 20, 0, 0, 1) },
        ],
    });
    file.motion = Some(MotionSection {
        options: BenchmarkOptions { runs: 3, ..BenchmarkOptions::default() },
        scenes: vec!["scene A".into()],
        planners: vec![PlannerInfo { name: "P1".into(), parameters: "x = 1".into() }],
        runs: vec![
            run("P1", 0, RunStatus::Solved, 0.001, 1.0),
            run("P1", 1, RunStatus::Solved, 0.003, 2.0),
            run("P1", 2, RunStatus::Timeout, 0.008, 0.0),
        ],
        summaries: Vec::new(),
        episodes: Vec::new(),
    });
    file
}

#[test]
fn results_round_trip_through_a_file() {
    let dir = temp_dir("roundtrip");
    let path = dir.join("results.json");
    let mut file = hand_made();
    let tiny = Suite::new()
        .motion_planner("defaults", || Box::new(RrtConnect::default()))
        .motion_scene(planar_scene())
        .runs(2)
        .seed(5)
        .run()
        .unwrap();
    file.motion = tiny.motion;
    file.save(&path).unwrap();
    let loaded = ResultsFile::load(&path).unwrap();
    assert_eq!(loaded, file);
    let m = loaded.motion.as_ref().unwrap();
    assert_eq!(m.runs.len(), 2);
    assert_eq!(m.runs.iter().map(|r| r.seed).collect::<Vec<_>>(), vec![5, 6]);
    assert_eq!(loaded.grasp.as_ref().unwrap().cells[0].cell.force_closure_palm, 7);
    // The grasp record is flat in JSON: its seed next to the cell's fields.
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(json["schema_version"], SCHEMA_VERSION);
    assert_eq!(json["grasp"]["cells"][0]["seed"], 3);
    assert_eq!(json["grasp"]["cells"][0]["palm_contact"], 10);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn failed_write_leaves_the_old_file_intact() {
    let dir = temp_dir("atomic");
    let path = dir.join("results.json");
    let file = hand_made();
    file.save(&path).unwrap();
    let before = std::fs::read(&path).unwrap();

    // A writer that fails half-way (as a crash or a full disk would).
    let err = write_atomic(&path, |w| {
        std::io::Write::write_all(w, b"{\"schema_version\": 1, \"provenance\": ")?;
        Err(std::io::Error::other("disk full"))
    })
    .unwrap_err();
    assert!(matches!(err, Error::Io { .. }), "{err}");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    // No temporary file is left behind.
    let names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(names, vec!["results.json".to_string()]);

    // Invalid results (NaN time) are rejected before anything is written.
    let mut bad = hand_made();
    bad.motion.as_mut().unwrap().runs[0].planning_time = f64::NAN;
    assert!(matches!(bad.save(&path), Err(Error::Invalid { .. })));
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(ResultsFile::load(&path).unwrap(), file);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn loading_validates_the_contents() {
    let good = hand_made().to_json().unwrap();
    assert!(ResultsFile::from_json(&good).is_ok());

    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["grasp"]["cells"][1]["fc_percent_palm"] = serde_json::json!(150.0);
    match ResultsFile::from_json(&v.to_string()) {
        Err(Error::Invalid { field, .. }) => assert_eq!(field, "grasp.cells[1].fc_percent_palm"),
        other => panic!("expected an invalid field, got {other:?}"),
    }

    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["motion"]["runs"][2]["planning_time"] = serde_json::json!(-1.0);
    match ResultsFile::from_json(&v.to_string()) {
        Err(Error::Invalid { field, .. }) => assert_eq!(field, "motion.runs[2].planning_time"),
        other => panic!("expected an invalid field, got {other:?}"),
    }

    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["grasp"]["cells"][0]["force_closure_palm"] = serde_json::json!(11);
    assert!(matches!(ResultsFile::from_json(&v.to_string()), Err(Error::Invalid { .. })));

    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["motion"]["runs"][0]["planner"] = serde_json::json!("unlisted");
    assert!(matches!(ResultsFile::from_json(&v.to_string()), Err(Error::Invalid { .. })));

    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["schema_version"] = serde_json::json!(2);
    assert!(matches!(
        ResultsFile::from_json(&v.to_string()),
        Err(Error::SchemaVersion { found: 2, expected: SCHEMA_VERSION })
    ));

    assert!(matches!(ResultsFile::from_json(&good[..good.len() / 2]), Err(Error::Parse { .. })));
    assert!(matches!(ResultsFile::load(Path::new("/nonexistent/results.json")), Err(Error::Io { .. })));
}

#[test]
fn provenance_fields_are_filled() {
    let p = Provenance::collect("default", 2);
    assert_eq!(p.suite_version, results::SUITE_VERSION);
    assert_eq!(p.suite_size, "default");
    assert_eq!(p.opengrasp_version, env!("CARGO_PKG_VERSION"));
    assert_eq!(p.crate_versions.len(), 5);
    assert_eq!(p.crate_versions["opengrasp-motion"], env!("CARGO_PKG_VERSION"));
    assert!(p.cpu_cores >= 1);
    assert_eq!(p.jobs, 2);
    assert_eq!(p.os, std::env::consts::OS);
    // UTC ISO-8601: 2026-11-23T01:40:00Z
    let d = p.started_at.as_bytes();
    assert_eq!(d.len(), 20, "{}", p.started_at);
    assert!(p.started_at.ends_with('Z') && d[4] == b'-' && d[7] == b'-' && d[10] == b'T' && d[13] == b':');
    let year: i32 = p.started_at[..4].parse().unwrap();
    assert!((2024..2200).contains(&year));
    if Path::new("/proc/cpuinfo").exists() {
        assert!(p.cpu_model.as_deref().is_some_and(|m| !m.is_empty()));
    }
    // The tests run in the package root: inside the repository if it is a git checkout.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if root.join(".git").exists() {
        let commit = results::git_commit(root).expect("commit of the checkout");
        assert_eq!(commit.len(), 40);
        assert!(commit.chars().all(|c| c.is_ascii_hexdigit()));
        if let Ok(out) = std::process::Command::new("git").arg("-C").arg(root).args(["rev-parse", "HEAD"]).output() {
            if out.status.success() {
                assert_eq!(commit, String::from_utf8(out.stdout).unwrap().trim());
            }
        }
    }
    assert_eq!(results::git_commit(&std::env::temp_dir().join("no-such-dir-opengrasp")), None);
}

#[test]
fn grasp_tables_have_the_right_numbers() {
    let file = hand_made();
    let tables = report::grasp_tables(file.grasp.as_ref().unwrap());
    assert_eq!(tables.len(), 1);
    let t = &tables[0];
    assert!(t.title.starts_with("Table II"));
    assert_eq!(t.cell("Salt can", "MA n"), Some("10"));
    assert_eq!(t.cell("Salt can", "MA FC%"), Some("70.0"));
    assert_eq!(t.cell("Salt can", "SN n"), Some("4"));
    assert_eq!(t.cell("Salt can", "SN FC%"), Some("25.0"));
    assert_eq!(t.cell("White cup", "SN FC%"), Some("-"));
    // The paper's Table II numbers beside ours.
    assert_eq!(t.cell("Salt can", "MA p.n"), Some("1072"));
    assert_eq!(t.cell("Salt can", "MA p.FC%"), Some("91.4"));
    assert_eq!(t.cell("White cup", "SN p.FC%"), Some("37.5"));
    // Totals: (7 + 3) / (10 + 10) and (1 + 0) / (4 + 0).
    assert_eq!(t.cell("total", "MA n"), Some("20"));
    assert_eq!(t.cell("total", "MA FC%"), Some("50.0"));
    assert_eq!(t.cell("total", "SN FC%"), Some("25.0"));
    // Paper totals: 1072·0.914 + 732·0.638 over 1804 = 80.2 %.
    assert_eq!(t.cell("total", "MA p.FC%"), Some("80.2"));

    let md = t.render(Format::Markdown);
    assert!(md.contains("| Salt can | 10 | 70.0 | 0.0500 | 1072 | 91.4 | 4 | 25.0 |"), "{md}");
    // A hand table with paper columns and its legend fit 120 columns.
    let text = t.render(Format::Table);
    assert!(text.lines().all(|l| l.chars().count() <= 120), "{text}");
    // Every column explained under the table; "-" is "no data", not 0 %.
    assert!(md.contains("*n: candidates tested") && md.contains("MA = medial-axis"), "{md}");
    // Tidy CSV: one header, one line per cell, numbers only in the value column.
    let csv = opengrasp::report::render_all(std::slice::from_ref(t), Format::Csv);
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("table,row,column,value,text"));
    let title = format!("\"{}\"", t.title);
    assert!(csv.lines().any(|l| l == format!("{title},Salt can,MA FC%,70,")), "{csv}");
    assert!(csv.lines().any(|l| l == format!("{title},White cup,SN FC%,,")), "{csv}");
    for l in lines {
        let fields: Vec<&str> = l.rsplitn(3, ',').collect();
        assert!(fields[1].is_empty() || fields[1].parse::<f64>().is_ok(), "non-numeric value in {l}");
    }
    assert!(csv.lines().count() > t.rows.len() * 4);
}

#[test]
fn grasp_differences_explain_each_cell_from_the_records() {
    let file = hand_made();
    let g = file.grasp.as_ref().unwrap();
    let tables = report::grasp_differences(g);
    assert_eq!(tables.len(), 1);
    let t = &tables[0];
    assert_eq!(t.rows.len(), 4);
    let ma = "barrett / Salt can / MA";
    assert_eq!(t.cell(ma, "n"), Some("10"));
    assert_eq!(t.cell(ma, "p.n"), Some("1072"));
    assert_eq!(t.cell(ma, "FC%"), Some("70.0"));
    // 70.0 - 91.4 percentage points.
    assert_eq!(t.cell(ma, "diff"), Some("-21.4"));
    // Without the palm-contact rule: 9 of 20 closed grasps; the rule keeps 10 of 20.
    assert_eq!(t.cell(ma, "FC% all"), Some("45.0"));
    assert_eq!(t.cell(ma, "kept %"), Some("50.0"));
    let why = t.cell(ma, "reason").unwrap();
    assert!(why.contains("cap 20/40") && why.contains("n 0.01x"), "{why}");
    assert!(why.contains("model: less FC"), "{why}");
    // No palm-contact grasp is "no data", not 0 %, and says why.
    let sn_cup = "barrett / White cup / SN";
    assert_eq!(t.cell(sn_cup, "FC%"), Some("-"));
    assert_eq!(t.cell(sn_cup, "diff"), Some("-"));
    assert!(t.cell(sn_cup, "reason").unwrap().contains("no palm grasp of 20 closed"));
    // Ranking: ours MA 10/20 = 50 % > SN 1/4 = 25 %; paper MA 80.2 % > SN 41.3 %.
    let legend = t.legend.join(" ");
    assert!(legend.contains("ours MA 50.0 % > SN 25.0 %, paper MA 80.2 % > SN 41.3 %: the ranking agrees"), "{legend}");
    assert!(legend.contains("capped at 20 candidates"), "{legend}");
    // A cell whose palm rule explains the gap: 4 of 10 palm grasps in FC, 18 of 20 closed.
    let mut g2 = g.clone();
    let c = &mut g2.cells[0].cell;
    (c.palm_contact, c.force_closure_palm, c.force_closure, c.closed) = (10, 4, 18, 20);
    let t2 = &report::grasp_differences(&g2)[0];
    let why = t2.cell(ma, "reason").unwrap();
    assert!(why.contains("palm rule (90.0 % without)"), "{why}");
    // Grasp tables print "-" for the epsilon of a cell without force-closure grasps.
    let tables = report::grasp_tables(&g2);
    assert_eq!(tables[0].cell("White cup", "SN eps"), Some("-"));
    // Cells without a paper figure give no differences table.
    let mut g3 = g.clone();
    g3.cells.iter_mut().for_each(|r| r.cell.hand = "sdh".into());
    assert!(report::grasp_differences(&g3).is_empty());
    // The text rendering fits 120 columns.
    let text = t.render(Format::Table);
    assert!(text.lines().all(|l| l.chars().count() <= 120), "{text}");
}

#[test]
fn motion_tables_have_the_right_numbers() {
    let file = hand_made();
    let tables = report::motion_tables(file.motion.as_ref().unwrap());
    assert_eq!(tables.len(), 4);
    let (times, quality, paths, pct) = (&tables[0], &tables[1], &tables[2], &tables[3]);
    let row = "scene A / P1";
    assert_eq!(times.cell(row, "runs"), Some("3"));
    assert_eq!(times.cell(row, "success %"), Some("66.7"));
    assert_eq!(times.cell(row, "setup [ms]"), Some("500.00"));
    // Planning times 1, 3, 8 ms: mean 4, median 3.
    assert_eq!(times.cell(row, "plan [ms]"), Some("4.00"));
    assert_eq!(times.cell(row, "plan p50 [ms]"), Some("3.00"));
    assert_eq!(times.cell(row, "post [ms]"), Some("100.00"));
    // Run 1's planned path is invalid: 50 % valid planned, 100 % post-processed.
    assert_eq!(quality.cell(row, "valid P %"), Some("50.0"));
    assert_eq!(quality.cell(row, "valid PP %"), Some("100.0"));
    // Lengths: planned 2 and 4 (mean 3), processed 1 and 2 (mean 1.5).
    assert_eq!(paths.cell(row, "length P"), Some("3.000"));
    assert_eq!(paths.cell(row, "length PP"), Some("1.500"));
    assert_eq!(paths.cell(row, "clear. P [mm]"), Some("200.0"));
    assert_eq!(paths.cell(row, "clear. PP [mm]"), Some("100.0"));
    assert_eq!(paths.cell(row, "EE P [m]"), Some("-"));
    // Percentiles of the planning time (linear interpolation): p25 of [1, 3, 8] = 2.
    let r = pct.rows.iter().find(|r| r[1] == "plan [ms]").unwrap();
    assert_eq!(r[2..], ["3", "1.00", "2.00", "3.00", "5.50", "7.50", "8.00"].map(String::from));

    // The high-score units: one per grasp cell, one per motion scene × planner.
    let scores = file.scores();
    assert_eq!(scores.len(), 5);
    assert_eq!(scores[0].task, "barrett/salt_can");
    assert_eq!((scores[0].score, scores[0].samples), (70.0, 10));
    let motion = scores.last().unwrap();
    assert_eq!((motion.planner.as_str(), motion.task.as_str(), motion.samples), ("P1", "scene A", 3));
    assert!((motion.score - 200.0 / 3.0).abs() < 1e-9);
    assert_eq!(motion.secondary, Some(0.003));

    let text = report::render(&file, Format::Table);
    assert!(text.contains("Table III") && text.contains("Table II") && text.contains("Provenance"));
}

/// The planar scene without a shared environment (setup per run, one job per run).
fn per_run_scene() -> opengrasp::motion::benchmark::BenchmarkScene {
    let mut scene = planar_scene();
    scene.name = "planar post (per run)".into();
    scene.shared_environment = false;
    scene
}

fn without_timing(mut file: ResultsFile) -> (Option<GraspSection>, Option<MotionSection>) {
    if let Some(g) = &mut file.grasp {
        for r in &mut g.cells {
            r.cell.planning_seconds = 0.0;
            r.cell.evaluation_seconds = 0.0;
            r.cell.evaluations_per_second = 0.0;
        }
    }
    if let Some(m) = &mut file.motion {
        for r in &mut m.runs {
            r.setup_time = 0.0;
            r.planning_time = 0.0;
            r.postprocessing_time = r.postprocessing_time.map(|_| 0.0);
        }
        // Summaries aggregate the timing fields; recompute them without.
        m.summaries = results::motion_summaries(m);
    }
    (file.grasp, file.motion)
}

#[test]
fn parallel_sweep_equals_serial_sweep() {
    let suite = |jobs: usize| {
        Suite::new()
            .with_reference_grasp(SuiteSize::Tiny)
            .objects(vec![stock_object("salt_can").unwrap(), stock_object("white_cup").unwrap()])
            .motion_planner("defaults", || Box::new(RrtConnect::default()))
            .motion_planner("nodes = 150", || Box::new(Prm::new(PrmOptions { nodes: 150, ..PrmOptions::default() })))
            .motion_scene(planar_scene())
            .motion_scene(per_run_scene())
            .runs(3)
            .seed(11)
            .jobs(jobs)
    };
    let serial = suite(1).run().unwrap();
    let parallel = suite(2).run().unwrap();
    assert_eq!(serial.provenance.jobs, 1);
    assert_eq!(parallel.provenance.jobs, 2);
    let g = serial.grasp.as_ref().unwrap();
    assert_eq!(g.cells.len(), 4); // 2 objects × 2 planners × 1 hand
    let m = serial.motion.as_ref().unwrap();
    assert_eq!(m.runs.len(), 12);
    assert_eq!(m.runs.iter().map(|r| r.seed).collect::<Vec<_>>(), [11, 12, 13].repeat(4));
    assert_eq!(m.runs.iter().map(|r| r.run).collect::<Vec<_>>(), [0, 1, 2].repeat(4));
    assert_eq!(m.summaries.len(), 4);
    assert!(m.summaries.iter().all(|s| s.runs == 3));
    // The per-run scene runs setup (PRM's roadmap) for every run, the shared one once.
    let prm_setups = |scene: &str| {
        let mut t: Vec<f64> =
            m.runs.iter().filter(|r| r.scene == scene && r.planner == "PRM").map(|r| r.setup_time).collect();
        t.dedup();
        t.len()
    };
    assert_eq!(prm_setups("planar post"), 1);
    assert_eq!(prm_setups("planar post (per run)"), 3);
    assert!(m.runs.iter().all(|r| r.status == RunStatus::Solved));
    assert_eq!(without_timing(serial), without_timing(parallel));
}

#[test]
fn suite_rejects_bad_options() {
    assert!(matches!(
        Suite::standard(SuiteSize::Tiny).retain_planners(&["nope".into()]),
        Err(Error::InvalidOption { name: "planner", .. })
    ));
    assert!(matches!(Suite::new().run(), Err(Error::InvalidOption { name: "suite", .. })));
    let zero = Suite::new().motion_planner("", || Box::new(RrtConnect::default())).motion_scene(planar_scene()).jobs(0);
    assert!(matches!(zero.run(), Err(Error::InvalidOption { name: "jobs", .. })));
    assert!(matches!(stock_object("anvil"), Err(Error::InvalidOption { name: "object", .. })));
    assert!(matches!(resolve_object("no/such/anvil.stl"), Err(Error::InvalidOption { name: "object", .. })));
    let kept = Suite::standard(SuiteSize::Tiny).retain_planners(&["prm".into(), "MEDIAL-AXIS".into()]).unwrap();
    assert_eq!(kept.planner_names(), vec!["medial-axis".to_string(), "PRM".to_string()]);
    let hands = Suite::new().with_reference_grasp(SuiteSize::Tiny).hands(vec![stock_hand("armar3").unwrap()]);
    assert_eq!(hands.planner_names().len(), 2);
    // Scene filters: exact names (any case), Clean the Table included or not, unknown rejected.
    let standard = || Suite::standard(SuiteSize::Default);
    assert_eq!(standard().scene_names().len(), 5);
    let one = standard().retain_scenes(&["STANDARD (ARMAR-III kitchen)".into()]).unwrap();
    assert_eq!(one.scene_names(), ["standard (ARMAR-III kitchen)"]);
    let table = standard().retain_scenes(&["clean the table".into()]).unwrap();
    assert_eq!(table.scene_names(), ["clean the table"]);
    assert!(matches!(standard().retain_scenes(&["attic".into()]), Err(Error::InvalidOption { name: "scene", .. })));
}

#[test]
fn command_line_parses() {
    let cli = Cli::try_parse_from([
        "opengrasp",
        "run",
        "motion",
        "--runs",
        "2",
        "--seed",
        "3",
        "--out",
        "x.json",
        "--jobs",
        "2",
        "--planner",
        "PRM",
        "--planner",
        "RRT-Connect",
        "--size",
        "tiny",
    ])
    .unwrap();
    match cli.command {
        Command::Run(a) => {
            assert_eq!(a.which, Which::Motion);
            assert_eq!(a.runs, Some(2));
            assert_eq!(a.seed, 3);
            assert_eq!(a.out, PathBuf::from("x.json"));
            assert_eq!(a.jobs, Some(2));
            assert_eq!(a.planners, vec!["PRM".to_string(), "RRT-Connect".to_string()]);
            assert_eq!(a.size, SizeArg::Tiny);
            assert_eq!((a.physics, a.episodes), (None, None));
        }
        other => panic!("parsed {other:?}"),
    }
    let cli = Cli::try_parse_from(["opengrasp", "run", "grasp", "--physics", "3", "--episodes", "0"]).unwrap();
    match cli.command {
        Command::Run(a) => {
            assert_eq!((a.physics, a.episodes), (Some(3), Some(0)));
            assert!(a.scenes.is_empty());
        }
        other => panic!("parsed {other:?}"),
    }
    let cli =
        Cli::try_parse_from(["opengrasp", "run", "motion", "--scene", "clean the table", "--scene", "x"]).unwrap();
    match cli.command {
        Command::Run(a) => assert_eq!(a.scenes, ["clean the table", "x"]),
        other => panic!("parsed {other:?}"),
    }
    let cli = Cli::try_parse_from(["opengrasp", "run", "all"]).unwrap();
    match cli.command {
        Command::Run(a) => {
            assert_eq!((a.which, a.size, a.runs, a.seed), (Which::All, SizeArg::Default, None, 0));
            assert_eq!(a.out, PathBuf::from("results.json"));
        }
        other => panic!("parsed {other:?}"),
    }
    match Cli::try_parse_from(["opengrasp", "report", "r.json", "--format", "csv", "--plots", "p", "--ompl", "o"])
        .unwrap()
        .command
    {
        Command::Report { file, format, plots, plot_format, ompl, .. } => {
            assert_eq!(file, PathBuf::from("r.json"));
            assert_eq!(format, FormatArg::Csv);
            assert_eq!(plots, Some(PathBuf::from("p")));
            assert_eq!(plot_format, PlotFormatArg::Both);
            assert_eq!(ompl, Some(PathBuf::from("o")));
        }
        other => panic!("parsed {other:?}"),
    }
    assert!(matches!(
        Cli::try_parse_from(["opengrasp", "report", "r.json", "--plots", "p", "--plot-format", "png"]).unwrap().command,
        Command::Report { plot_format: PlotFormatArg::Png, .. }
    ));
    assert!(Cli::try_parse_from(["opengrasp", "report", "r.json", "--plot-format", "gif"]).is_err());
    assert!(matches!(
        Cli::try_parse_from(["opengrasp", "list", "objects"]).unwrap().command,
        Command::List { what: ListWhat::Objects }
    ));
    assert!(matches!(
        Cli::try_parse_from(["opengrasp", "submit", "r.json", "--name", "ann", "--team", "lab"]).unwrap().command,
        Command::Submit { .. }
    ));
    assert!(Cli::try_parse_from(["opengrasp", "highscore", "grasp/barrett"]).is_ok());
    assert!(Cli::try_parse_from(["opengrasp", "serve", "--addr", "127.0.0.1:0"]).is_ok());
    match Cli::try_parse_from(["opengrasp", "run", "motion", "--problems", "d", "--checker", "spheres"])
        .unwrap()
        .command
    {
        Command::Run(a) => assert_eq!((a.problems, a.checker), (vec![PathBuf::from("d")], CheckerArg::Spheres)),
        other => panic!("parsed {other:?}"),
    }
    assert!(matches!(
        Cli::try_parse_from(["opengrasp", "run", "motion"]).unwrap().command,
        Command::Run(a) if a.checker == CheckerArg::Exact
    ));
    assert!(Cli::try_parse_from(["opengrasp", "run", "motion", "--checker", "boxes"]).is_err());
    assert!(Cli::try_parse_from(["opengrasp", "run", "everything"]).is_err());
    assert!(Cli::try_parse_from(["opengrasp", "run", "grasp", "--runs", "many"]).is_err());
    assert!(Cli::try_parse_from(["opengrasp", "report", "r.json", "--format", "xml"]).is_err());
    assert!(Cli::try_parse_from(["opengrasp", "submit", "r.json"]).is_err()); // --name missing
}

#[test]
fn run_motion_end_to_end() {
    let dir = temp_dir("cli");
    let out = dir.join("results.json");
    let cli = Cli::try_parse_from([
        "opengrasp",
        "run",
        "motion",
        "--size",
        "tiny",
        "--runs",
        "2",
        "--seed",
        "4",
        "--out",
        out.to_str().unwrap(),
    ])
    .unwrap();
    let Command::Run(args) = cli.command else { panic!("not a run") };
    let (results, text) = cli::run(&args, false).unwrap();
    let loaded = ResultsFile::load(&out).unwrap();
    assert_eq!(loaded, results);
    assert!(loaded.grasp.is_none());
    let m = loaded.motion.as_ref().unwrap();
    assert_eq!(m.planners.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(), vec!["RRT-Connect", "PRM"]);
    assert_eq!(m.runs.len(), 4);
    assert_eq!(m.summaries.len(), 2);
    assert!(m.summaries.iter().all(|s| s.runs == 2 && s.solved == 2));
    assert_eq!(loaded.provenance.suite_size, "tiny");
    assert!(text.contains("planar post / PRM"), "{text}");

    // `report --plots --ompl` on the file.
    let plots = dir.join("plots");
    let ompl = dir.join("ompl");
    let cli = Cli::try_parse_from([
        "opengrasp",
        "report",
        out.to_str().unwrap(),
        "--format",
        "markdown",
        "--plots",
        plots.to_str().unwrap(),
        "--ompl",
        ompl.to_str().unwrap(),
    ])
    .unwrap();
    cli::execute(cli).unwrap();
    for f in ["motion_planar_post_planning_time", "motion_planar_post_length"] {
        let svg = std::fs::read_to_string(plots.join(format!("{f}.svg"))).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("RRT-Connect (n=2)") && svg.contains("PRM (n=2)"), "{f}");
        // The default --plot-format is both.
        let png = std::fs::read(plots.join(format!("{f}.png"))).unwrap();
        assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "{f}");
    }
    let log = std::fs::read_to_string(ompl.join("ompl_planar_post.log")).unwrap();
    assert!(log.starts_with("OpenGRASP-rs version"));

    // Unknown planners are an error, not an empty run.
    let bad = RunArgs { planners: vec!["nope".into()], ..args };
    assert!(matches!(cli::run(&bad, false), Err(Error::InvalidOption { name: "planner", .. })));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn list_names_everything() {
    let text = cli::list(ListWhat::All);
    for item in [
        "grasp",
        "motion",
        "medial-axis",
        "surface-normals",
        "RRT-Connect",
        "PRM",
        "IK-RRT",
        "barrett",
        "armar3",
        "sdh",
        "salt_can",
        "standard (7-DoF stand-in)",
        "clean the table",
    ] {
        assert!(text.contains(item), "{item} missing in\n{text}");
    }
    // The stock objects, then how to bring your own.
    let objects = cli::list(ListWhat::Objects);
    assert_eq!(objects.lines().count(), 2 + opengrasp::assets::objects::NAMES.len());
    assert!(objects.contains("--object PATH"), "{objects}");
    assert!(cli::list(ListWhat::Hands).contains("--hand PATH"));
}

/// `--hand PATH` and `--object PATH` bring a lab's own hand (URDF + spec file) and object
/// (STL + metadata file) into `opengrasp run grasp`; unknown names are errors.
#[test]
fn run_grasp_takes_hands_and_objects_from_files() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("opengrasp-bench/tests/data/user_models");
    let out = std::env::temp_dir().join(format!("opengrasp-cli-user-models-{}.json", std::process::id()));
    let hand = data.join("gripper.hand.json");
    let object = data.join("tea_box.stl");
    let args = |hand: &str, object: &str| {
        let cli = Cli::try_parse_from([
            "opengrasp",
            "run",
            "grasp",
            "--size",
            "tiny",
            "--hand",
            hand,
            "--hand",
            "sdh",
            "--object",
            object,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .unwrap();
        match cli.command {
            Command::Run(a) => a,
            other => panic!("parsed {other:?}"),
        }
    };
    let a = args(hand.to_str().unwrap(), object.to_str().unwrap());
    assert_eq!(a.hands.len(), 2);
    let (results, _) = cli::run(&a, false).unwrap();
    let grasp = results.grasp.as_ref().unwrap();
    assert_eq!(grasp.hands, ["lab_gripper", "sdh"]);
    assert_eq!(grasp.objects, ["tea_box"]);
    assert_eq!(grasp.cells.len(), 2 * 2);
    assert_eq!(ResultsFile::load(&out).unwrap().grasp.unwrap().hands, grasp.hands);
    std::fs::remove_file(&out).ok();
    assert!(matches!(
        cli::run(&args("hand-of-god", "salt_can"), false),
        Err(Error::InvalidOption { name: "hand", .. })
    ));
    assert!(matches!(cli::run(&args("barrett", "anvil"), false), Err(Error::InvalidOption { name: "object", .. })));
}

/// The contents of every `<text>` element of an SVG document, trimmed.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = &t[t.find('>')? + 1..];
            Some(body[..body.find("</text>")?].trim().to_string())
        })
        .collect()
}

#[test]
fn grasp_plots_are_svg_and_png() {
    use opengrasp::plots::PlotFormat;
    let dir = temp_dir("plots");
    let written = opengrasp::plots::plot_all(&hand_made(), &dir).unwrap();
    let names: Vec<String> = written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(names, vec!["grasp_barrett_fc.svg", "motion_scene_a_planning_time.svg", "motion_scene_a_length.svg"]);
    let svg = std::fs::read_to_string(dir.join("grasp_barrett_fc.svg")).unwrap();
    assert!(svg.contains("<rect"));
    let texts = svg_texts(&svg);
    // Palm-contact counts per bar; surface-normals on white_cup had no palm contact: no data.
    for label in ["salt_can", "white_cup", "medial-axis", "surface-normals", "n=10", "n=4", "object"] {
        assert!(texts.iter().any(|t| t == label), "{label} missing in {texts:?}");
    }
    assert_eq!(texts.iter().filter(|t| *t == "no data").count(), 1, "{texts:?}");
    assert!(texts.iter().any(|t| t.starts_with("force closure [%")), "{texts:?}");
    // Issue 16: no Debug quotes in labels; n per box; units on the axes.
    let times = svg_texts(&std::fs::read_to_string(dir.join("motion_scene_a_planning_time.svg")).unwrap());
    assert!(times.iter().any(|t| t == "P1 (n=3)") && times.iter().any(|t| t == "planning time [ms]"), "{times:?}");
    let lengths = svg_texts(&std::fs::read_to_string(dir.join("motion_scene_a_length.svg")).unwrap());
    assert!(lengths.iter().any(|t| t == "P1 (n=2)") && lengths.iter().any(|t| t.contains("[rad, m]")), "{lengths:?}");
    assert!(texts.iter().chain(&times).chain(&lengths).all(|t| !t.contains('"') && !t.contains("&quot;")));

    // Both formats: each figure as SVG, then PNG.
    let both = opengrasp::plots::plot_all_as(&hand_made(), &dir.join("both"), PlotFormat::Both).unwrap();
    assert_eq!(both.len(), 6);
    for pair in both.chunks(2) {
        assert_eq!(pair[0].with_extension("png"), pair[1]);
        let png = std::fs::read(&pair[1]).unwrap();
        assert!(png.starts_with(b"\x89PNG\r\n\x1a\n") && &png[12..16] == b"IHDR", "{}", pair[1].display());
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn clean_the_table_episodes_in_the_suite() {
    use opengrasp::suite::CLEAN_THE_TABLE_SCENE;
    // A small shortcut budget keeps the test quick; the episode is otherwise the standard one.
    let mut options = BenchmarkOptions::default();
    options.shortcut.iterations = 5;
    let suite = Suite::new()
        .motion_planner("defaults", || Box::new(RrtConnect::default()))
        .motion_options(options)
        .clean_the_table(1)
        .seed(3);
    assert_eq!(suite.scene_names(), vec![CLEAN_THE_TABLE_SCENE.to_string()]);
    let file = suite.run().unwrap();
    let m = file.motion.as_ref().unwrap();
    assert_eq!(m.episodes.len(), 1);
    let e = &m.episodes[0];
    assert_eq!((e.planner.as_str(), e.index, e.seed, e.error.as_deref()), ("RRT-Connect", 0, 3, None));
    assert_eq!(e.objects, ["white_cup", "green_cup", "salt_can", "measuring_cup"]);
    // Grasp and place query per cleaned object, numbered in order, all under one scene.
    assert_eq!(e.totals.cleaned, 4, "{e:?}");
    assert_eq!(m.runs.len(), 8);
    assert!(m.runs.iter().all(|r| r.scene == CLEAN_THE_TABLE_SCENE && r.planner == "RRT-Connect"));
    assert_eq!(m.runs.iter().map(|r| r.run).collect::<Vec<_>>(), (0..8).collect::<Vec<_>>());
    assert!(m.runs.iter().all(|r| r.status == RunStatus::Solved));
    // The episode's sums are the sums of its queries.
    let planning: f64 = m.runs.iter().map(|r| r.planning_time).sum();
    assert!((e.totals.planning_time - planning).abs() < 1e-9, "{} vs {planning}", e.totals.planning_time);
    let length: f64 = m.runs.iter().filter_map(|r| r.processed.as_ref()).map(|p| p.metrics.length).sum();
    assert!((e.totals.length - length).abs() < 1e-9);
    assert_eq!(e.totals.all_valid, m.runs.iter().all(|r| r.processed.as_ref().is_some_and(|p| p.validity.strict)));
    assert_eq!(m.summaries.len(), 1);
    assert_eq!((m.summaries[0].runs, m.summaries[0].solved), (8, 8));
    // The file validates, round-trips and reports the episode.
    let back = ResultsFile::from_json(&file.to_json().unwrap()).unwrap();
    assert_eq!(back, file);
    let text = report::render(&file, Format::Table);
    assert!(text.contains("Clean the Table") && text.contains("4/4"), "{text}");
}

#[test]
fn run_grasp_with_physics_checks_end_to_end() {
    let dir = temp_dir("cli-physics");
    let out = dir.join("results.json");
    let run = |physics: &str| {
        let mut argv = vec!["opengrasp", "run", "grasp", "--size", "tiny", "--physics", physics, "--quiet"];
        if physics != "0" {
            argv.push("--grasps");
        }
        argv.extend(["--out", out.to_str().unwrap()]);
        let cli = Cli::try_parse_from(argv).unwrap();
        let Command::Run(args) = cli.command else { panic!("not a run") };
        cli::run(&args, false).unwrap().0
    };
    let checked = run("2");
    let cells = &checked.grasp.as_ref().unwrap().cells;
    // The tiny suite's medial-axis cell has four force-closure palm grasps: two are simulated.
    let ma = cells.iter().find(|c| c.cell.planner == "medial-axis").unwrap();
    assert_eq!((ma.cell.force_closure_palm, ma.cell.physics_tested), (4, 2), "{:?}", ma.cell);
    assert!(cells
        .iter()
        .all(|c| c.cell.physics_held <= c.cell.physics_tested
            && c.cell.physics_tested <= c.cell.force_closure_palm.min(2)));
    let text = report::render(&checked, Format::Table);
    assert!(text.contains("MA held"), "{text}");
    // --grasps: one record per evaluated candidate, adding up to the cell's figures.
    for c in cells.iter().map(|r| &r.cell) {
        let k = &c.candidates;
        assert_eq!(k.len(), c.evaluated);
        assert_eq!(k.iter().filter(|r| r.palm_contact).count(), c.palm_contact);
        assert_eq!(k.iter().filter(|r| r.force_closure).count(), c.force_closure);
        let fc_palm: Vec<f64> = k.iter().filter(|r| r.palm_contact && r.force_closure).map(|r| r.epsilon).collect();
        assert_eq!(fc_palm.len(), c.force_closure_palm);
        if !fc_palm.is_empty() {
            let mean = fc_palm.iter().sum::<f64>() / fc_palm.len() as f64;
            assert!((mean - c.mean_epsilon).abs() < 1e-12);
        }
        assert_eq!(k.iter().filter(|r| r.physics_held.is_some()).count(), c.physics_tested);
        assert_eq!(k.iter().filter(|r| r.physics_held == Some(true)).count(), c.physics_held);
        assert!(k.iter().all(|r| r.index < c.generated && r.epsilon >= 0.0 && r.volume >= 0.0));
    }
    assert_eq!(ResultsFile::load(&out).unwrap(), checked);
    // --grasps also stores the static tactile frames (the Barrett hand's optional pads), and
    // the report draws a heat map of each cell's best one.
    let records: Vec<_> = cells.iter().flat_map(|r| &r.cell.candidates).collect();
    assert!(records
        .iter()
        .any(|r| r.tactile.as_ref().is_some_and(|t| t.pads.len() == 4 && t.pads.iter().any(|p| !p.cells.is_empty()))));
    // Physics-checked grasps carry a tactile time series (0.3 s, a frame every 25 ms).
    for r in &records {
        assert_eq!(r.tactile_series.len(), if r.physics_held.is_some() { 12 } else { 0 });
    }
    let written = opengrasp::plots::plot_all(&checked, &dir.join("plots")).unwrap();
    let heat: Vec<_> = written.iter().filter(|p| p.to_string_lossy().contains("tactile_")).collect();
    assert!(!heat.is_empty(), "{written:?}");
    let svg = std::fs::read_to_string(heat[0]).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("f1_distal") && svg.contains("palm"));
    let unchecked = run("0");
    assert!(unchecked.grasp.as_ref().unwrap().cells.iter().all(|c| c.cell.physics_tested == 0));
    assert!(unchecked.grasp.as_ref().unwrap().cells.iter().all(|c| c.cell.candidates.is_empty()));
    assert!(!std::fs::read_to_string(&out).unwrap().contains("\"candidates\""));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `run --shard K/N` as N separate processes, merged with `opengrasp merge`, gives exactly the
/// records of the unsharded run (timing aside) in the same order, the same tables, and a
/// provenance that lists the shards; incomplete or mixed shard sets are refused.
#[test]
fn sharded_runs_merge_into_the_unsharded_run() {
    let dir = std::env::temp_dir().join(format!("opengrasp-shards-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let opengrasp = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_opengrasp")).args(args).output().unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    };
    let run = |out: &Path, shard: Option<&str>| {
        let mut args = vec![
            "run",
            "all",
            "--size",
            "tiny",
            "--hand",
            "barrett",
            "--hand",
            "sdh",
            "--object",
            "salt_can",
            "--object",
            "white_cup",
            "--seed",
            "5",
            "--jobs",
            "1",
            "--quiet",
            "--out",
        ];
        args.push(out.to_str().unwrap());
        if let Some(s) = shard {
            args.extend(["--shard", s]);
        }
        opengrasp(&args);
    };
    let whole = dir.join("whole.json");
    run(&whole, None);
    let shards: Vec<PathBuf> = (0..3).map(|k| dir.join(format!("shard{k}.json"))).collect();
    for (k, path) in shards.iter().enumerate() {
        run(path, Some(&format!("{k}/3")));
    }
    // Each shard holds only its slice: 4 grasp cells + 2 motion pairs = 6 jobs, 2 per shard.
    let first = ResultsFile::load(&shards[0]).unwrap();
    assert_eq!(first.provenance.shard, Some(opengrasp::results::Shard { index: 0, count: 3 }));
    assert_eq!(first.grasp.as_ref().unwrap().cells.len(), 2 * 2); // 2 cells × 2 planners
    let merged_path = dir.join("merged.json");
    let mut args = vec!["merge"];
    let names: Vec<String> = shards.iter().rev().map(|p| p.to_str().unwrap().to_string()).collect();
    args.extend(names.iter().map(String::as_str));
    args.extend(["--out", merged_path.to_str().unwrap()]);
    opengrasp(&args);
    let unsharded = ResultsFile::load(&whole).unwrap();
    let merged = ResultsFile::load(&merged_path).unwrap();
    assert_eq!(merged.provenance.merged_from.len(), 3);
    assert!(merged.provenance.merged_from.iter().enumerate().all(|(k, p)| p.shard.unwrap().index == k));
    let order = |f: &ResultsFile| -> Vec<(String, String)> {
        f.motion.as_ref().unwrap().summaries.iter().map(|s| (s.scene.clone(), s.planner.clone())).collect()
    };
    assert_eq!(order(&merged), order(&unsharded));
    assert_eq!(
        report::render(&ResultsFile { provenance: unsharded.provenance.clone(), ..merged.clone() }, Format::Csv)
            .lines()
            .count(),
        report::render(&unsharded, Format::Csv).lines().count()
    );
    assert_eq!(without_timing(merged), without_timing(unsharded.clone()));
    // Incomplete, repeated and unsharded inputs are errors.
    let load = |p: &PathBuf| ResultsFile::load(p).unwrap();
    assert!(opengrasp::results::merge(vec![load(&shards[0]), load(&shards[1])]).is_err());
    assert!(opengrasp::results::merge(vec![load(&shards[0]), load(&shards[0]), load(&shards[2])]).is_err());
    assert!(opengrasp::results::merge(vec![unsharded]).is_err());
    assert!(opengrasp::results::merge(Vec::new()).is_err());
    assert!(opengrasp::results::Shard::parse("3/3").is_err() && opengrasp::results::Shard::parse("a/2").is_err());
    std::fs::remove_dir_all(&dir).ok();
}

/// A run's `--out` is checked before the run: a bad path fails at once, with nothing run.
#[test]
fn run_checks_its_output_path_first() {
    let cli =
        Cli::try_parse_from(["opengrasp", "run", "motion", "--size", "tiny", "--out", "/no/such/dir/r.json"]).unwrap();
    let Command::Run(args) = cli.command else { panic!("a run") };
    match cli::run(&args, false) {
        Err(Error::Io { path, .. }) => assert_eq!(path, PathBuf::from("/no/such/dir/r.json")),
        other => panic!("expected an i/o error on the output path, got {other:?}"),
    }
    // A directory is not a results file either.
    assert!(matches!(opengrasp::results::check_writable(&std::env::temp_dir()), Err(Error::Io { .. })));
    assert!(opengrasp::results::check_writable(&std::env::temp_dir().join("fresh-results.json")).is_ok());
}
