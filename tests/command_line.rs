//! The command line end to end (tiny suites): parsing, `run`, `list`, `report`, plots, sharding.

mod common;

use std::path::{Path, PathBuf};

use clap::Parser;
use opengrasp::cli::{self, CheckerArg, Cli, Command, FormatArg, ListWhat, PlotFormatArg, RunArgs, SizeArg, Which};
use opengrasp::motion::benchmark::{BenchmarkOptions, RunStatus};
use opengrasp::motion::planners::RrtConnect;
use opengrasp::report::{self, Format};
use opengrasp::results::{Error, ResultsFile};
use opengrasp::suite::Suite;

use common::*;

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
            argv.extend(["--grasps", "--hull-stats"]);
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
    assert!(cells.iter().all(|c| c.cell.physics_held <= c.cell.physics_tested
        && c.cell.static_holdable <= c.cell.physics_tested
        && c.cell.static_agree <= c.cell.physics_tested
        && c.cell.physics_tested <= c.cell.force_closure_palm.min(2)));
    let text = report::render(&checked, Format::Table);
    assert!(text.contains("MA held") && text.contains("MA stat"), "{text}");
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
        assert!(k.iter().all(|r| r.index < c.generated && r.epsilon >= 0.0));
        // --hull-stats: every record carries the hull's volume and facet count, nonzero
        // exactly for the force-closure grasps.
        for r in k {
            let (volume, facets) = (r.volume.unwrap(), r.hull_facets.unwrap());
            assert_eq!((volume > 0.0, facets > 0), (r.force_closure, r.force_closure), "{r:?}");
        }
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
