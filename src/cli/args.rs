//! The command line's arguments and errors (clap derive): [`Cli`] and what it parses into.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};

use crate::report::Format;
use crate::results::Error;
use crate::suite::SuiteSize;

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
    /// contacts, force closure, epsilon, physics outcome, tactile frame; hull volume and facet
    /// count with `--hull-stats`) in the results file.
    #[arg(long)]
    pub grasps: bool,
    /// Also compute each force-closure grasp's wrench-space hull volume and facet count (the
    /// full 6-D hull; epsilon does not need it), stored with `--grasps`. Off by default: it
    /// costs several times the rest of a grasp evaluation.
    #[arg(long)]
    pub hull_stats: bool,
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
