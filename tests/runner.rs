//! The runner: results files (round trip, atomic writes, validation, provenance), reports,
//! parallel == serial and sharded == unsharded runs' building blocks.

mod common;

use std::path::Path;

use opengrasp::bench::stock::{resolve_object, stock_hand, stock_object};
use opengrasp::motion::benchmark::RunStatus;
use opengrasp::motion::planners::{Prm, PrmOptions, RrtConnect};
use opengrasp::report::{self, Format};
use opengrasp::results::{self, write_atomic, Error, Provenance, ResultsFile, SCHEMA_VERSION};
use opengrasp::suite::{planar_scene, Suite, SuiteSize};

use common::*;

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

    // Diverged physics checks are among the tested ones and never held.
    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["grasp"]["cells"][0]["physics_diverged"] = serde_json::json!(1);
    match ResultsFile::from_json(&v.to_string()) {
        Err(Error::Invalid { field, .. }) => assert_eq!(field, "grasp.cells[0].physics_diverged"),
        other => panic!("expected an invalid field, got {other:?}"),
    }
    let cell = &mut v["grasp"]["cells"][0];
    (cell["physics_tested"], cell["physics_held"]) = (serde_json::json!(2), serde_json::json!(2));
    match ResultsFile::from_json(&v.to_string()) {
        Err(Error::Invalid { field, reason }) => {
            assert_eq!(
                (field.as_str(), reason.as_str()),
                ("grasp.cells[0].physics_held", "3 exceeds physics_tested (2)")
            )
        }
        other => panic!("expected an invalid field, got {other:?}"),
    }
    v["grasp"]["cells"][0]["physics_held"] = serde_json::json!(1);
    assert!(ResultsFile::from_json(&v.to_string()).is_ok());

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
fn grasp_legend_splits_physics_failures_into_explained_and_not() {
    let mut file = hand_made();
    let g = file.grasp.as_mut().unwrap();
    // 4 + 3 simulated: 1 + 1 held, 1 diverged, 3 of the other 4 failures escaped without gravity.
    for (r, (tested, held, diverged, escaped)) in
        g.cells.iter_mut().zip([(4, 1, 1, 1), (3, 1, 0, 2), (0, 0, 0, 0), (0, 0, 0, 0)])
    {
        (r.cell.physics_tested, r.cell.physics_held) = (tested, held);
        (r.cell.physics_diverged, r.cell.physics_grip_escaped) = (diverged, escaped);
    }
    let legend = report::grasp_tables(g)[0].legend.join(" ");
    assert!(legend.contains("Of the 4 simulated grasps not held, 3 are explained by the hand's actuation"), "{legend}");
    assert!(legend.contains("; 1 kept the grasp without gravity"), "{legend}");
    // A record claiming more escapes than failures is rejected.
    g.cells[1].cell.physics_grip_escaped = 3;
    let json = serde_json::to_string(&file).unwrap();
    match ResultsFile::from_json(&json) {
        Err(Error::Invalid { field, .. }) => assert_eq!(field, "grasp.cells[1].physics_grip_escaped"),
        other => panic!("{other:?}"),
    }
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
