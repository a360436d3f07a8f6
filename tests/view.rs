//! `opengrasp view`, `run --record` and the report's snapshots through the command line:
//! typed errors for bad input, and the feature switch.

use clap::Parser;
use opengrasp::cli::{self, Cli, CliError};
use opengrasp::results::Error;

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("opengrasp-view-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn execute(args: &[&str]) -> Result<(), CliError> {
    cli::execute(Cli::try_parse_from(args).unwrap())
}

#[test]
fn malformed_results_files_are_parse_errors_naming_the_file() {
    let bad = tmp("malformed.json");
    std::fs::write(&bad, "{ \"schema_version\": 1, ").unwrap();
    match cli::load_results(&bad) {
        Err(CliError::Bench(Error::Parse { path, .. })) => assert_eq!(path, bad),
        other => panic!("{other:?}"),
    }
    let missing = tmp("missing.json");
    let e = cli::load_results(&missing).unwrap_err();
    assert!(e.to_string().contains("missing.json"), "{e}");
}

#[test]
fn run_and_view_parse_their_options() {
    let cli = Cli::try_parse_from(["opengrasp", "view", "r.json", "--run", "RRT-Connect/planar post/0", "--no-spawn"])
        .unwrap();
    match cli.command {
        cli::Command::View(v) => {
            assert_eq!(v.run.as_deref(), Some("RRT-Connect/planar post/0"));
            assert!(v.no_spawn && v.grasp.is_none() && v.out.is_none());
        }
        other => panic!("{other:?}"),
    }
    // --run and --grasp exclude each other.
    assert!(Cli::try_parse_from(["opengrasp", "view", "r.json", "--run", "0", "--grasp", "0"]).is_err());
    let cli = Cli::try_parse_from(["opengrasp", "run", "motion", "--record", "x.rrd"]).unwrap();
    assert!(matches!(cli.command, cli::Command::Run(a) if a.record == Some("x.rrd".into())));
}

#[cfg(not(feature = "rerun"))]
#[test]
fn without_the_rerun_feature_recording_commands_say_how_to_enable_it() {
    let out = tmp("never.json");
    let out_s = out.to_string_lossy().into_owned();
    let e = execute(&["opengrasp", "run", "motion", "--size", "tiny", "--record", "x.rrd", "--out", &out_s, "--quiet"])
        .unwrap_err();
    assert!(matches!(e, CliError::RerunDisabled { command: "run --record" }), "{e:?}");
    assert!(!out.exists(), "nothing ran");
    let e = execute(&["opengrasp", "view", "whatever.json"]).unwrap_err();
    assert!(matches!(e, CliError::RerunDisabled { command: "view" }), "{e:?}");
    let text = e.to_string();
    assert!(text.contains("--features rerun") && text.contains("--plots"), "{text}");
}

#[test]
fn the_markdown_report_embeds_the_snapshots_it_writes() {
    let results = opengrasp::suite::Suite::standard(opengrasp::suite::SuiteSize::Tiny)
        .record_grasps(true)
        .max_candidates(Some(16))
        .runs(1)
        .jobs(1)
        .run()
        .unwrap();
    let dir = tmp("plots");
    let section = opengrasp::view::snapshots(&results, &dir, &[]).unwrap();
    assert!(section.starts_with("## Snapshots\n"));
    let links: Vec<&str> =
        section.lines().filter_map(|l| l.strip_prefix("![")).filter_map(|l| l.split("](").nth(1)).collect();
    // One scene (planar post) and one cell per grasp planner (Barrett on the salt can).
    assert_eq!(links.len(), 1 + results.grasp.as_ref().unwrap().cells.len(), "{section}");
    for l in links {
        let path = l.trim_end_matches(')').replace("%20", " ");
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{path}");
    }
}

#[cfg(feature = "rerun")]
#[test]
fn view_writes_a_recording_and_rejects_unknown_runs() {
    let results = opengrasp::suite::Suite::standard(opengrasp::suite::SuiteSize::Tiny).runs(1).jobs(1).run().unwrap();
    let file = tmp("tiny.json");
    results.save(&file).unwrap();
    let f = file.to_string_lossy().into_owned();
    let out = tmp("tiny.rrd");
    let o = out.to_string_lossy().into_owned();
    let e = execute(&["opengrasp", "view", &f, "--run", "nope/0", "--out", &o, "--no-spawn"]).unwrap_err();
    assert!(matches!(e, CliError::Viewer(opengrasp::viewer::ViewerError::UnknownRun { .. })), "{e:?}");
    execute(&["opengrasp", "view", &f, "--run", "0", "--out", &o, "--no-spawn"]).unwrap();
    assert!(std::fs::metadata(&out).unwrap().len() > 1000);
    let bad = tmp("bad.json");
    std::fs::write(&bad, "not json").unwrap();
    let b = bad.to_string_lossy().into_owned();
    let e = execute(&["opengrasp", "view", &b, "--no-spawn"]).unwrap_err();
    assert!(matches!(e, CliError::Bench(Error::Parse { .. })), "{e:?}");
}
