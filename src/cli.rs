//! The `opengrasp` command line (clap derive), as a library module so it can be tested and
//! embedded: [`Cli`] parses, [`execute`] runs.
//!
//! ```text
//! opengrasp list [categories|scenes|planners|hands|objects]
//! opengrasp run grasp|motion|all [--size tiny|default|paper] [--planner NAME]... [--runs N]
//!                                [--hand NAME|PATH]... [--object NAME|PATH]...
//!                                [--seed S] [--max-candidates N|all] [--out results.json] [--jobs J]
//!                                [--quiet] [--record out.rrd]
//! opengrasp report results.json [--format table|markdown|csv] [--plots DIR]
//!                                [--plot-format svg|png|both] [--ompl DIR] [--problems PATH]...
//! opengrasp view results.json [--run ID | --grasp ID] [--out file.rrd] [--no-spawn]
//!                                [--problems PATH]...   (feature `rerun`)
//! opengrasp submit results.json --name NAME [--team TEAM] [--db highscore.sqlite]
//! opengrasp submit results.json --name NAME --server http://HOST:PORT [--token TOKEN]
//! opengrasp highscore [BENCHMARK] [--db highscore.sqlite]
//! opengrasp serve [--db highscore.sqlite] [--addr 127.0.0.1:8080] [--max-connections N] [--verify-sample K]
//! opengrasp token issue --team TEAM | list | revoke ID [--db highscore.sqlite]
//! ```

use std::collections::HashMap;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;

use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::bench::problem_sets::{load_problem_sets, ProblemSetChecker};
use crate::bench::stock;
use crate::motion::validity::cover::GreedyCoverOptions;
use crate::report::{self, Format};
use crate::results::{Category, Error, Result, ResultsFile};
use crate::suite::{Progress, Suite, SuiteSize};

/// Errors of the `opengrasp` command: the harness's and the high-score board's.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// Running, loading, reporting or writing results failed.
    #[error(transparent)]
    Bench(#[from] Error),
    /// A high-score board operation failed.
    #[error(transparent)]
    Highscore(#[from] crate::highscore::HighscoreError),
    /// Drawing, replaying or recording for the viewer failed.
    #[error(transparent)]
    Viewer(#[from] crate::viewer::ViewerError),
    /// A rerun recording was asked of a build without the `rerun` feature.
    #[error(
        "`{command}` writes rerun recordings, but this opengrasp was built without the `rerun` feature: \
         install it with `cargo install --path . --features rerun` (needs Rust 1.95), or draw PNG \
         snapshots with `opengrasp report FILE --format markdown --plots DIR`"
    )]
    RerunDisabled {
        /// The command.
        command: &'static str,
    },
}

/// `opengrasp`: run the OpenGRASP grasp and motion planning benchmarks, report and rank results.
#[derive(Debug, Parser)]
#[command(name = "opengrasp", version, about, long_about = None)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// What to list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ListWhat {
    /// Everything below.
    All,
    /// Benchmark categories.
    Categories,
    /// Motion benchmark scenes.
    Scenes,
    /// Reference planners.
    Planners,
    /// Grasp benchmark hands.
    Hands,
    /// Grasp benchmark objects.
    Objects,
}

/// Which benchmark to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Which {
    /// The grasp benchmark (Tables I and II).
    Grasp,
    /// The motion benchmark (Table III).
    Motion,
    /// Both.
    All,
}

/// Suite size on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SizeArg {
    /// Seconds: one object and hand, a planar arm.
    Tiny,
    /// A few minutes on two cores (release build).
    Default,
    /// The paper's sizes (every grasp candidate, 100 motion runs).
    Paper,
}

impl From<SizeArg> for SuiteSize {
    fn from(s: SizeArg) -> Self {
        match s {
            SizeArg::Tiny => SuiteSize::Tiny,
            SizeArg::Default => SuiteSize::Default,
            SizeArg::Paper => SuiteSize::Paper,
        }
    }
}

/// Motion protocol on the command line (see `opengrasp::motion::protocol`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProtocolArg {
    /// Certified shortcutting (default).
    Certified,
    /// The paper's reference evaluation.
    Paper,
}

impl From<ProtocolArg> for crate::motion::protocol::Protocol {
    fn from(p: ProtocolArg) -> Self {
        match p {
            ProtocolArg::Certified => Self::Certified,
            ProtocolArg::Paper => Self::Paper,
        }
    }
}

/// Planning checker of problem sets on the command line (`run --checker`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum CheckerArg {
    /// Exact meshes and primitives (default).
    #[default]
    Exact,
    /// The robot's guaranteed sphere cover.
    Spheres,
}

/// Image format of `report --plots` on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum PlotFormatArg {
    /// SVG only.
    Svg,
    /// PNG only.
    Png,
    /// SVG and PNG of every plot.
    #[default]
    Both,
}

impl From<PlotFormatArg> for crate::plots::PlotFormat {
    fn from(f: PlotFormatArg) -> Self {
        match f {
            PlotFormatArg::Svg => Self::Svg,
            PlotFormatArg::Png => Self::Png,
            PlotFormatArg::Both => Self::Both,
        }
    }
}

/// Report format on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    /// Aligned text.
    Table,
    /// Markdown tables.
    Markdown,
    /// CSV.
    Csv,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Table => Format::Table,
            FormatArg::Markdown => Format::Markdown,
            FormatArg::Csv => Format::Csv,
        }
    }
}

/// Options of `opengrasp run`.
#[derive(Clone, Debug, PartialEq, clap::Args)]
pub struct RunArgs {
    /// Benchmark to run.
    pub which: Which,
    /// Suite size: `default` (grasp: 8 objects × 2 hands, ≤128 candidates per cell; motion:
    /// 4 scenes, 20 runs, 1 Clean the Table episode) finishes in a few minutes on two cores.
    #[arg(long, value_enum, default_value = "default")]
    pub size: SizeArg,
    /// Run only these planners (repeatable; names as in `opengrasp list planners`).
    #[arg(long = "planner")]
    pub planners: Vec<String>,
    /// Run only these motion scenes (repeatable; names as in `opengrasp list scenes`, e.g.
    /// `"standard (ARMAR-III kitchen)"` or `"clean the table"`).
    #[arg(long = "scene")]
    pub scenes: Vec<String>,
    /// Grasp hands (repeatable): a stock hand (`opengrasp list hands`) or a hand spec file
    /// naming its URDF (see `opengrasp::core::hand`). Default: the size's hands.
    #[arg(long = "hand", value_name = "NAME|PATH")]
    pub hands: Vec<String>,
    /// Grasp objects (repeatable): a stock object (`opengrasp list objects`), or an object's
    /// mesh (`.stl`/`.obj` with a `.json` metadata file beside it) or metadata file (see
    /// `opengrasp::core::object`). Default: the size's objects.
    #[arg(long = "object", value_name = "NAME|PATH")]
    pub objects: Vec<String>,
    /// Motion problem sets to benchmark instead of the kitchen scenes (repeatable): a JSON
    /// problem-set file, a MotionBenchMaker set directory (`sceneNNNN.yaml` +
    /// `requestNNNN.yaml`, robot found by name up the tree) or a directory of such sets. Run
    /// `r` plans problem `r`; `--runs` defaults to the largest set's size.
    #[arg(long = "problems", value_name = "PATH")]
    pub problems: Vec<PathBuf>,
    /// With `--problems`: what the planners check states with. `exact` (default): the robot's
    /// meshes and the obstacles' shapes; `spheres`: the robot's guaranteed greedy sphere cover
    /// (every mesh point inside a sphere) and the SRDF's self-collision pairs, scenes named
    /// `"<set> (spheres)"`. Paths are graded by the exact validators either way.
    #[arg(long, value_enum, default_value = "exact")]
    pub checker: CheckerArg,
    /// Motion runs per planner per scene (default: the size's).
    #[arg(long)]
    pub runs: Option<usize>,
    /// Base seed of both benchmarks.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Grasp candidates evaluated per cell at most, or `all` (default: the size's).
    #[arg(long)]
    pub max_candidates: Option<String>,
    /// Force-closure palm-contact grasps per grasp cell sent to the physics hold check
    /// (rapier; default: the size's, 0 for `tiny`, 2 for `default`, 5 for `paper`).
    #[arg(long)]
    pub physics: Option<usize>,
    /// Keep every evaluated grasp candidate (pose, preshape, approach, closed configuration,
    /// contacts, force closure, epsilon, volume, physics outcome, tactile frame) in the results
    /// file.
    #[arg(long)]
    pub grasps: bool,
    /// With `--grasps`: do not store the grasps' static tactile frames (stored by default for
    /// hands with tactile pads).
    #[arg(long)]
    pub no_tactile: bool,
    /// Total finger normal force (N) of the static tactile frames (default 10).
    #[arg(long)]
    pub grip_force: Option<f64>,
    /// Clean the Table episodes per motion planner (default: the size's, 0 for `tiny`, 1 for
    /// `default`, 5 for `paper`).
    #[arg(long)]
    pub episodes: Option<usize>,
    /// Results file to write (atomically; checked for writability before the run starts).
    #[arg(long, default_value = "results.json")]
    pub out: PathBuf,
    /// Motion protocol: `certified` (default; shortcuts certified, post-processed paths valid
    /// by construction) or `paper` (the OpenGRASP paper's reference evaluation: step 0.05, plain
    /// shortcutting, fine re-check; setup time includes loading the scene).
    #[arg(long, value_enum, default_value = "certified")]
    pub protocol: ProtocolArg,
    /// Run only shard K of N (0-based, `K/N`): every N-th job of the suite from job K, with
    /// the seeds an unsharded run gives them; `opengrasp merge` combines the shards' files.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Do not print the report after the run.
    #[arg(long)]
    pub quiet: bool,
    /// Also write a rerun recording of the results (`.rrd`: scenes, each scene's first solved
    /// run replayed, each grasp cell's best recorded grasp). Needs the `rerun` feature.
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List categories, scenes, planners, hands and objects.
    List {
        /// What to list.
        #[arg(value_enum, default_value = "all")]
        what: ListWhat,
    },
    /// Run a benchmark suite and write a results file.
    Run(RunArgs),
    /// Print the tables of a results file; optionally write plots and OMPL logs.
    Report {
        /// The results file.
        file: PathBuf,
        /// Output format.
        #[arg(long, value_enum, default_value = "table")]
        format: FormatArg,
        /// Write plots (Tukey box plots of planning time and path length, force-closure bars)
        /// into this directory.
        #[arg(long)]
        plots: Option<PathBuf>,
        /// Image format of the plots.
        #[arg(long, value_enum, default_value = "both")]
        plot_format: PlotFormatArg,
        /// Write the motion results as OMPL benchmark logs (one per scene) into this directory.
        #[arg(long)]
        ompl: Option<PathBuf>,
        /// The motion problem sets the results were made with, for the scene snapshots of
        /// `--plots`.
        #[arg(long = "problems", value_name = "PATH")]
        problems: Vec<PathBuf>,
    },
    /// Write a rerun recording (`.rrd`) of a results file and open it in the rerun viewer
    /// when installed (`pip install rerun-sdk` or `cargo install rerun-cli`). Needs the
    /// `rerun` feature.
    View(crate::view::ViewArgs),
    /// Merge the results files of a sharded run (`run --shard K/N`, all N shards) into the
    /// results of the unsharded run.
    Merge {
        /// The shards' results files, in any order.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// The merged results file.
        #[arg(long, default_value = "results.json")]
        out: PathBuf,
    },
    /// Submit a results file to a high-score server (`--server`) or a local database.
    Submit {
        /// The results file (`-` for standard input; at most 8 MiB).
        file: PathBuf,
        /// Participant name.
        #[arg(long)]
        name: String,
        /// Group or lab (with `--server`: the token's team).
        #[arg(long)]
        team: Option<String>,
        /// The local high-score database (without `--server`).
        #[arg(long, default_value = "highscore.sqlite")]
        db: PathBuf,
        /// Upload to this high-score server (`http://host:port`).
        #[arg(long)]
        server: Option<String>,
        /// The team's API token (default: `$OPENGRASP_TOKEN`).
        #[arg(long, env = "OPENGRASP_TOKEN", hide_env_values = true)]
        token: Option<String>,
    },
    /// Print the high-score rankings.
    Highscore {
        /// One benchmark (e.g. `grasp/barrett`); all if omitted.
        benchmark: Option<String>,
        /// The high-score database.
        #[arg(long, default_value = "highscore.sqlite")]
        db: PathBuf,
    },
    /// Serve the high-score board over HTTP.
    Serve {
        /// The high-score database.
        #[arg(long, default_value = "highscore.sqlite")]
        db: PathBuf,
        /// Address to listen on.
        #[arg(long, default_value = "127.0.0.1:8080")]
        addr: String,
        /// Most connections served at once.
        #[arg(long, default_value_t = 256)]
        max_connections: usize,
        /// Replay this many motion runs of reference planners per upload from their seeds and
        /// refuse (422) an upload whose replays differ; 0: off.
        #[arg(long, default_value_t = 0)]
        verify_sample: usize,
    },
    /// Manage the API tokens of networked submission (administrator).
    Token {
        /// What to do.
        #[command(subcommand)]
        action: TokenAction,
        /// The high-score database.
        #[arg(long, default_value = "highscore.sqlite", global = true)]
        db: PathBuf,
    },
}

/// `opengrasp token` actions.
#[derive(Debug, Subcommand)]
pub enum TokenAction {
    /// Issue a token for a team (printed once; only its hash is stored).
    Issue {
        /// The team.
        #[arg(long)]
        team: String,
    },
    /// List the issued tokens (without secrets).
    List,
    /// Revoke a token by id.
    Revoke {
        /// The token id (see `list`).
        id: i64,
    },
}

/// Largest results file `opengrasp report` reads (files with every grasp candidate are big).
pub const MAX_REPORT_BYTES: usize = 512 * 1024 * 1024;

/// Loads a results file for `report` and `view` (at most [`MAX_REPORT_BYTES`]).
///
/// # Errors
/// [`Error::Io`] / [`Error::Parse`] (naming the file) / validation errors.
pub fn load_results(file: &std::path::Path) -> std::result::Result<ResultsFile, CliError> {
    let text = crate::highscore::read::read_file_bounded(file, MAX_REPORT_BYTES)?;
    Ok(ResultsFile::from_json(&text).map_err(|e| match e {
        Error::Parse { source, .. } => Error::Parse { path: file.to_path_buf(), source },
        other => other,
    })?)
}

/// Builds the suite `opengrasp run` would run.
///
/// # Errors
/// [`Error::InvalidOption`] for an unknown planner, hand or object, a bad `--max-candidates`
/// or zero jobs; [`Error::Core`] for a hand or object file that does not load.
pub fn build_suite(args: &RunArgs) -> Result<Suite> {
    let size = SuiteSize::from(args.size);
    let mut suite = if args.problems.is_empty() {
        match args.which {
            Which::Grasp => Suite::new().with_reference_grasp(size),
            Which::Motion => Suite::new().with_reference_motion(size),
            Which::All => Suite::standard(size),
        }
    } else {
        let checker = match args.checker {
            CheckerArg::Exact => ProblemSetChecker::Exact,
            CheckerArg::Spheres => ProblemSetChecker::Spheres(GreedyCoverOptions::default()),
        };
        let mut sets = Vec::new();
        for path in &args.problems {
            sets.extend(load_problem_sets(path)?);
        }
        match args.which {
            Which::Grasp => {
                return Err(Error::InvalidOption {
                    name: "problems",
                    reason: "motion problem sets need `run motion` or `run all`".into(),
                })
            }
            Which::Motion => {
                Suite::new().labelled(size.name()).with_problem_sets_checked_by(sets, args.seed, checker)?
            }
            Which::All => {
                Suite::new().with_reference_grasp(size).with_problem_sets_checked_by(sets, args.seed, checker)?
            }
        }
    };
    suite = suite.seed(args.seed);
    if !args.hands.is_empty() {
        suite = suite.hands(args.hands.iter().map(|h| stock::resolve_hand(h)).collect::<Result<_>>()?);
    }
    if !args.objects.is_empty() {
        suite = suite.objects(args.objects.iter().map(|o| stock::resolve_object(o)).collect::<Result<_>>()?);
    }
    if let Some(r) = args.runs {
        suite = suite.runs(r);
    }
    if let Some(m) = &args.max_candidates {
        let max = if m.eq_ignore_ascii_case("all") {
            None
        } else {
            Some(m.parse::<usize>().map_err(|e| Error::InvalidOption {
                name: "max-candidates",
                reason: format!("{m:?}: {e} (expected a number or `all`)"),
            })?)
        };
        suite = suite.max_candidates(max);
    }
    if let Some(n) = args.physics {
        suite = suite.physics_per_cell(n);
    }
    if args.grasps {
        suite = suite.record_grasps(true);
        if !args.no_tactile {
            let mut tactile = opengrasp_grasp::benchmark::TactileRecording::default();
            if let Some(g) = args.grip_force {
                tactile.grip_force = g;
            }
            suite = suite.record_tactile(Some(tactile));
        }
    }
    if let Some(e) = args.episodes {
        suite = suite.clean_the_table(e);
    }
    if let Some(j) = args.jobs {
        if j == 0 {
            return Err(Error::InvalidOption { name: "jobs", reason: "must be at least 1".into() });
        }
        suite = suite.jobs(j);
    }
    if !args.planners.is_empty() {
        suite = suite.retain_planners(&args.planners)?;
    }
    if !args.scenes.is_empty() {
        suite = suite.retain_scenes(&args.scenes)?;
    }
    if args.protocol != ProtocolArg::Certified {
        suite = suite.protocol(args.protocol.into());
    }
    if let Some(shard) = &args.shard {
        suite = suite.shard(crate::results::Shard::parse(shard)?);
    }
    Ok(suite)
}

/// Progress bars on stderr (one per category), hidden when stderr is not a terminal.
fn progress_bars() -> impl Fn(&Progress) + Send + Sync + 'static {
    let multi = MultiProgress::with_draw_target(if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let bars: Mutex<HashMap<Category, ProgressBar>> = Mutex::new(HashMap::new());
    move |p: &Progress| {
        let Ok(mut bars) = bars.lock() else { return };
        let bar = bars.entry(p.category).or_insert_with(|| {
            let bar = multi.add(ProgressBar::new(p.total as u64));
            let unit = if p.category == Category::Grasp { "cells" } else { "runs" };
            if let Ok(style) = ProgressStyle::with_template(&format!(
                "{{prefix:>6}} [{{elapsed_precise}}] {{bar:30}} {{pos}}/{{len}} {unit} (eta {{eta}}) {{msg}}"
            )) {
                bar.set_style(style);
            }
            bar.set_prefix(p.category.name());
            bar
        });
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
        bar.set_message(p.label.clone());
        if p.done >= p.total {
            bar.finish();
        }
    }
}

/// Runs `opengrasp run`: the suite, the results file and (unless `quiet`) the report, which
/// is returned.
///
/// # Errors
/// As [`build_suite`], [`Suite::run`] and [`ResultsFile::save`].
pub fn run(args: &RunArgs, show_progress: bool) -> Result<(ResultsFile, String)> {
    let mut suite = build_suite(args)?;
    crate::results::check_writable(&args.out)?;
    if show_progress {
        suite = suite.on_progress(progress_bars());
    }
    let results = suite.run()?;
    results.save(&args.out)?;
    let text = if args.quiet { String::new() } else { report::render(&results, Format::Table) };
    Ok((results, text))
}

/// The text of `opengrasp list`.
pub fn list(what: ListWhat) -> String {
    let suite = Suite::standard(SuiteSize::Default);
    let tiny = Suite::standard(SuiteSize::Tiny);
    let mut out = String::new();
    let section = |out: &mut String, title: &str, items: Vec<String>| {
        out.push_str(title);
        out.push_str(":\n");
        for i in items {
            out.push_str("  ");
            out.push_str(&i);
            out.push('\n');
        }
    };
    let all = what == ListWhat::All;
    if all || what == ListWhat::Categories {
        section(&mut out, "categories", vec!["grasp (Tables I, II)".into(), "motion (Table III)".into()]);
    }
    if all || what == ListWhat::Scenes {
        let mut scenes = suite.scene_names();
        scenes.extend(tiny.scene_names().into_iter().map(|s| format!("{s} (tiny suite)")));
        section(&mut out, "motion scenes", scenes);
    }
    if all || what == ListWhat::Planners {
        section(&mut out, "planners", suite.planner_names());
    }
    if all || what == ListWhat::Hands {
        let mut hands: Vec<String> = stock::HAND_NAMES.iter().map(|s| s.to_string()).collect();
        hands.push("or PATH: a hand spec file naming its URDF (--hand PATH)".into());
        section(&mut out, "hands", hands);
    }
    if all || what == ListWhat::Objects {
        let mut objects: Vec<String> = stock::OBJECT_NAMES.iter().map(|s| s.to_string()).collect();
        objects
            .push("or PATH: a mesh with a .json metadata file beside it, or the metadata file (--object PATH)".into());
        section(&mut out, "objects", objects);
    }
    out
}

/// Executes a parsed command line, printing to stdout.
///
/// # Errors
/// The command's errors.
pub fn execute(cli: Cli) -> std::result::Result<(), CliError> {
    match cli.command {
        Command::List { what } => print!("{}", list(what)),
        Command::Run(args) => {
            if let Some(path) = &args.record {
                if !cfg!(feature = "rerun") {
                    return Err(CliError::RerunDisabled { command: "run --record" });
                }
                crate::results::check_writable(path)?;
            }
            let (results, text) = run(&args, true)?;
            print!("{text}");
            eprintln!(
                "wrote {} ({:.1} s on {} jobs)",
                args.out.display(),
                results.provenance.wall_seconds,
                results.provenance.jobs
            );
            if let Some(path) = &args.record {
                let sets = crate::view::load_sets(&args.problems)?;
                crate::view::record(&results, path, &crate::view::Selection::Overview, &sets)?;
            }
        }
        Command::View(args) => {
            crate::view::view(&args)?;
        }
        Command::Merge { files, out } => {
            crate::results::check_writable(&out)?;
            let shards = files.iter().map(ResultsFile::load).collect::<Result<Vec<_>>>()?;
            let merged = crate::results::merge(shards)?;
            merged.save(&out)?;
            eprintln!("merged {} shards into {}", files.len(), out.display());
        }
        Command::Report { file, format, plots, plot_format, ompl, problems } => {
            let results = load_results(&file)?;
            let sets = crate::view::load_sets(&problems)?;
            // Output directories first, so a bad path fails before anything is printed.
            for dir in plots.iter().chain(&ompl) {
                std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.clone(), source })?;
            }
            print!("{}", report::render(&results, format.into()));
            if let Some(dir) = plots {
                for p in crate::plots::plot_all_as(&results, &dir, plot_format.into())? {
                    eprintln!("wrote {}", p.display());
                }
                let section = crate::view::snapshots(&results, &dir, &sets)?;
                if matches!(format, FormatArg::Markdown) && !section.is_empty() {
                    print!("\n{section}");
                }
            }
            if let Some(dir) = ompl {
                let motion = results.motion.as_ref().ok_or_else(|| Error::InvalidOption {
                    name: "ompl",
                    reason: "the results file has no motion results".into(),
                })?;
                for (name, text) in crate::ompl::logs(motion, &results.provenance) {
                    let path = dir.join(name);
                    crate::results::write_atomic(&path, |w| std::io::Write::write_all(w, text.as_bytes()))?;
                    eprintln!("wrote {}", path.display());
                }
            }
        }
        Command::Submit { file, name, team, db, server, token } => {
            let mut who = crate::highscore::Submitter::new(name);
            if let Some(t) = team {
                who = who.with_team(t);
            }
            if let Some(url) = server {
                let token = token.ok_or_else(|| crate::highscore::HighscoreError::Unauthorized {
                    reason: "--server needs --token or $OPENGRASP_TOKEN".into(),
                })?;
                let text = crate::highscore::read::read_file_bounded(&file, crate::highscore::MAX_UPLOAD_BYTES)?;
                let answer = crate::highscore::client::upload(&url, &token, &who, &text)?;
                let verb = if answer.duplicate { "already stored" } else { "uploaded" };
                println!(
                    "{verb} {} as submission {} on {url} ({})",
                    file.display(),
                    answer.id,
                    answer.benchmarks.join(", ")
                );
            } else {
                let id = crate::highscore::submit(&db, &file, who)?;
                println!("stored {} as submission {} in {}", file.display(), id.0, db.display());
            }
        }
        Command::Highscore { benchmark, db } => {
            let rankings = crate::highscore::ranking(&db, benchmark.as_deref())?;
            print!("{}", crate::highscore::render_rankings(&rankings));
        }
        Command::Serve { db, addr, max_connections, verify_sample } => {
            let options = crate::highscore::ServerOptions { max_connections, verify_sample, ..Default::default() };
            let server = crate::highscore::spawn(&db, &addr, options)?;
            eprintln!("serving {} on http://{}/", db.display(), server.addr());
            server.wait()?;
        }
        Command::Token { action, db } => {
            let store = crate::highscore::Store::open(&db)?;
            match action {
                TokenAction::Issue { team } => {
                    let (id, token) = store.issue_token(&team)?;
                    eprintln!("token {id} for team {team} (shown once; only its hash is stored):");
                    println!("{token}");
                }
                TokenAction::List => {
                    for t in store.tokens()? {
                        let state = if t.revoked { "revoked" } else { "active" };
                        println!("{}\t{}\t{}\t{state}", t.id, t.team, t.created_at);
                    }
                }
                TokenAction::Revoke { id } => {
                    if store.revoke_token(id)? {
                        println!("revoked token {id}");
                    } else {
                        println!("no token {id}");
                    }
                }
            }
        }
    }
    Ok(())
}
