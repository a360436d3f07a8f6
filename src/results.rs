//! Results files: every benchmark run with its provenance, as JSON.
//!
//! A [`ResultsFile`] is what `opengrasp run` writes and what `opengrasp report`, `submit` and
//! the high-score board read. Its schema (version [`SCHEMA_VERSION`]):
//!
//! ```text
//! {
//!   "schema_version": 1,
//!   "provenance": {                      // Provenance: where and how the results were made
//!     "suite_version": "opengrasp-suite/1", "suite_size": "default",
//!     "opengrasp_version": "0.1.0", "crate_versions": {"opengrasp-core": "0.1.0", ...},
//!     "git_commit": "0123abcd..." | null, "cpu_model": "..." | null, "cpu_cores": 2,
//!     "os": "linux", "arch": "x86_64", "started_at": "2026-11-23T01:40:00Z",
//!     "finished_at": "2026-11-23T01:42:10Z", "wall_seconds": 130.2, "jobs": 2
//!   },
//!   "grasp": null | {                    // GraspSection
//!     "seed": 0, "hands": ["armar3", "barrett"], "objects": ["salt_can", ...],
//!     "max_candidates": 64 | null,
//!     "planners": [{"name": "medial-axis", "parameters": "MedialAxisOptions { .. }"}],
//!     "cells": [ {GraspRecord: "seed" + every field of opengrasp_grasp::benchmark::CellResult} ]
//!   },
//!   "motion": null | {                   // MotionSection
//!     "options": {opengrasp_motion::benchmark::BenchmarkOptions},
//!     "scenes": ["standard (exact)", ...],
//!     "planners": [{"name": "RrtConnect", "parameters": "..."}],
//!     "runs": [ {opengrasp_motion::benchmark::RunRecord: planner, scene, run, seed, status, ...} ],
//!     "summaries": [ {opengrasp_motion::benchmark::Summary} ]
//!   }
//! }
//! ```
//!
//! Files are written atomically ([`write_atomic`]: temporary file in the same directory,
//! fsync, rename), so an interrupted run never leaves a truncated file behind, and loading
//! ([`ResultsFile::load`]) validates the contents ([`ResultsFile::validate`]: schema version,
//! finite non-negative times, percentages in [0, 100], consistent counts, known planners).
//! [`ResultsFile::scores`] flattens a file into one [`ScoreEntry`] per planner and benchmark
//! cell, the unit the high-score board ranks.

use std::collections::BTreeMap;
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

use opengrasp_grasp::benchmark::CellResult;
use opengrasp_motion::benchmark::{BenchmarkOptions, RunRecord, RunStatus, Summary};
use serde::{Deserialize, Serialize};

/// Version of the results-file schema; [`ResultsFile::load`] rejects other versions.
pub const SCHEMA_VERSION: u32 = 1;

/// Version of the benchmark suite (scenes, objects, hands, metrics). Results of different
/// suite versions are not comparable.
pub const SUITE_VERSION: &str = "opengrasp-suite/1";

/// Errors of the `opengrasp` facade (results files, reports, plots, suites).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Reading or writing a file failed.
    #[error("i/o error on {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: io::Error,
    },
    /// A file is not valid JSON of the expected shape.
    #[error("malformed results file {path}: {source}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: serde_json::Error,
    },
    /// Serialising results failed.
    #[error("cannot serialise results: {0}")]
    Serialize(#[source] serde_json::Error),
    /// The file has a schema version this build cannot read.
    #[error("unsupported results schema version {found} (this build reads {expected})")]
    SchemaVersion {
        /// Version in the file.
        found: u32,
        /// Version this build reads.
        expected: u32,
    },
    /// A value in the results is out of range or inconsistent.
    #[error("invalid results: {field}: {reason}")]
    Invalid {
        /// Path of the offending field (e.g. `motion.runs[3].planning_time`).
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A suite or command option is invalid.
    #[error("invalid option {name}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The grasp benchmark failed.
    #[error(transparent)]
    Grasp(#[from] opengrasp_grasp::GraspError),
    /// The motion benchmark failed.
    #[error(transparent)]
    Motion(#[from] opengrasp_motion::MotionError),
    /// A high-score board operation failed.
    #[error(transparent)]
    Highscore(#[from] crate::highscore::HighscoreError),
    /// Drawing a plot failed.
    #[error("plot {path}: {reason}")]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// What failed.
        reason: String,
    },
}

/// Result type of the facade.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Where, when and with what the results were produced.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// [`SUITE_VERSION`] of the suite that ran.
    pub suite_version: String,
    /// Suite size that ran (`"default"`, `"paper"`, `"tiny"` or `"custom"`).
    pub suite_size: String,
    /// Version of the `opengrasp` facade.
    pub opengrasp_version: String,
    /// Versions of the member crates (`opengrasp-core`, `-grasp`, `-motion`, `-assets`).
    pub crate_versions: BTreeMap<String, String>,
    /// Git commit of the opengrasp checkout it was built from, else of the working
    /// directory's repository; `None` if neither is a git repository.
    pub git_commit: Option<String>,
    /// CPU model (`model name` of `/proc/cpuinfo`), if known.
    pub cpu_model: Option<String>,
    /// Logical CPU cores available.
    pub cpu_cores: usize,
    /// Operating system (`std::env::consts::OS`).
    pub os: String,
    /// CPU architecture (`std::env::consts::ARCH`).
    pub arch: String,
    /// Start of the run, UTC ISO-8601 (`2026-11-23T01:40:00Z`).
    pub started_at: String,
    /// End of the run, UTC ISO-8601.
    pub finished_at: String,
    /// Wall time of the whole run (s).
    pub wall_seconds: f64,
    /// Worker threads used.
    pub jobs: usize,
}

impl Provenance {
    /// Collects the provenance of this process and machine now (`finished_at` = `started_at`,
    /// `wall_seconds` = 0 until [`Provenance::finish`]).
    pub fn collect(suite_size: &str, jobs: usize) -> Self {
        let now = utc_now_iso8601();
        let crate_versions = [
            ("opengrasp", env!("CARGO_PKG_VERSION")),
            // The members share the workspace version (`version.workspace = true`).
            ("opengrasp-core", env!("CARGO_PKG_VERSION")),
            ("opengrasp-grasp", env!("CARGO_PKG_VERSION")),
            ("opengrasp-motion", env!("CARGO_PKG_VERSION")),
            ("opengrasp-assets", env!("CARGO_PKG_VERSION")),
        ]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
        Self {
            suite_version: SUITE_VERSION.to_string(),
            suite_size: suite_size.to_string(),
            opengrasp_version: env!("CARGO_PKG_VERSION").to_string(),
            crate_versions,
            // The checkout opengrasp was built from, else the working directory's repository.
            git_commit: git_commit(Path::new(env!("CARGO_MANIFEST_DIR")))
                .or_else(|| std::env::current_dir().ok().and_then(|d| git_commit(&d))),
            cpu_model: cpu_model(),
            cpu_cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            os: std::env::consts::OS.to_string(),
            arch: std::env::consts::ARCH.to_string(),
            started_at: now.clone(),
            finished_at: now,
            wall_seconds: 0.0,
            jobs,
        }
    }

    /// Stamps the end of the run.
    pub fn finish(&mut self, wall_seconds: f64) {
        self.finished_at = utc_now_iso8601();
        self.wall_seconds = wall_seconds;
    }
}

/// A planner that took part, with its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannerInfo {
    /// The planner's name (as in the records).
    pub name: String,
    /// Its parameters as text (the `Debug` form of the options for the reference planners,
    /// whatever the user supplied for their own).
    pub parameters: String,
}

/// One grasp benchmark cell (planner × hand × object) with the seed it ran with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraspRecord {
    /// Seed handed to the planner.
    pub seed: u64,
    /// The cell's results (flattened into this record in JSON).
    #[serde(flatten)]
    pub cell: CellResult,
}

/// Grasp benchmark results.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraspSection {
    /// Seed of the run.
    pub seed: u64,
    /// Hands (`"armar3"`, `"barrett"`).
    pub hands: Vec<String>,
    /// Object asset names.
    pub objects: Vec<String>,
    /// Candidates evaluated per cell at most (`None`: all).
    pub max_candidates: Option<usize>,
    /// Planners that ran.
    pub planners: Vec<PlannerInfo>,
    /// One record per planner × hand × object.
    pub cells: Vec<GraspRecord>,
}

/// Motion benchmark results.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotionSection {
    /// Benchmark options (runs, base seed, time limit, validator steps, ...).
    pub options: BenchmarkOptions,
    /// Scene names.
    pub scenes: Vec<String>,
    /// Planners that ran.
    pub planners: Vec<PlannerInfo>,
    /// Every run (planner, scene, run index, seed, outcome, times, graded paths).
    pub runs: Vec<RunRecord>,
    /// One summary per scene × planner (recomputable from `runs`).
    pub summaries: Vec<Summary>,
    /// Clean the Table episodes (their grasp and place queries are in `runs`, scene
    /// [`opengrasp_motion::clean_table::SCENE_NAME`]); absent from files without any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub episodes: Vec<EpisodeRecord>,
}

/// One Clean the Table episode: a planner carrying the red table's objects to the sideboard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeRecord {
    /// Planner name.
    pub planner: String,
    /// Episode index (0-based); its queries are runs `index · 2 · objects ..` of the scene.
    pub index: usize,
    /// Seed of the object placement and the queries.
    pub seed: u64,
    /// Objects to carry, in order.
    pub objects: Vec<String>,
    /// Objects placed on the sideboard.
    pub cleaned: usize,
    /// Sum of setup times (s).
    pub setup_time: f64,
    /// Sum of planning times (s).
    pub planning_time: f64,
    /// Sum of post-processing times (s).
    pub postprocessing_time: f64,
    /// Sum of post-processed C-space lengths.
    pub length: f64,
    /// Sum of post-processed end-effector lengths (m).
    pub ee_length: f64,
    /// True if every post-processed path passed every validator.
    pub all_valid: bool,
    /// Why the episode could not run, if it could not (e.g. an asset error).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// A results file (see the [module docs](self) for the JSON layout).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultsFile {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// Provenance.
    pub provenance: Provenance,
    /// Grasp benchmark results, if the grasp benchmark ran.
    pub grasp: Option<GraspSection>,
    /// Motion benchmark results, if the motion benchmark ran.
    pub motion: Option<MotionSection>,
}

/// Benchmark category of a [`ScoreEntry`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Category {
    /// Grasp planning (Tables I/II).
    Grasp,
    /// Motion planning (Table III).
    Motion,
}

impl Category {
    /// `"grasp"` or `"motion"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Grasp => "grasp",
            Self::Motion => "motion",
        }
    }
}

/// One planner's headline figures on one benchmark cell, the unit a high-score board ranks.
///
/// Grasp: `task` = `"<hand>/<object>"`, `score` = force closure % among palm-contact
/// candidates (higher is better), `secondary` = mean Ferrari-Canny epsilon of the
/// force-closure grasps, `samples` = candidates with palm contact.
/// Motion: `task` = scene name, `score` = success rate % (higher is better), `secondary` =
/// median planning time (s, lower is better; `None` if no run), `samples` = runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScoreEntry {
    /// Category.
    pub category: Category,
    /// Planner name.
    pub planner: String,
    /// Benchmark cell.
    pub task: String,
    /// Main score (percent, higher is better).
    pub score: f64,
    /// Tie-breaker (see the type docs for its meaning per category).
    pub secondary: Option<f64>,
    /// Number of samples behind the score.
    pub samples: usize,
}

impl ResultsFile {
    /// An empty results file with fresh provenance.
    pub fn new(provenance: Provenance) -> Self {
        Self { schema_version: SCHEMA_VERSION, provenance, grasp: None, motion: None }
    }

    /// Parses and validates a results file from JSON text.
    ///
    /// # Errors
    /// [`Error::Parse`] (with an empty path), [`Error::SchemaVersion`], [`Error::Invalid`].
    pub fn from_json(text: &str) -> Result<Self> {
        Self::parse(text, Path::new(""))
    }

    fn parse(text: &str, path: &Path) -> Result<Self> {
        // Check the version before the shape, so a newer file gives the clearer error.
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|source| Error::Parse { path: path.to_path_buf(), source })?;
        if let Some(found) = value.get("schema_version").and_then(serde_json::Value::as_u64) {
            if found != u64::from(SCHEMA_VERSION) {
                return Err(Error::SchemaVersion {
                    found: u32::try_from(found).unwrap_or(u32::MAX),
                    expected: SCHEMA_VERSION,
                });
            }
        }
        let file: Self =
            serde_json::from_value(value).map_err(|source| Error::Parse { path: path.to_path_buf(), source })?;
        file.validate()?;
        Ok(file)
    }

    /// Pretty JSON of the file (validated first, so no NaN is silently written as `null`).
    ///
    /// # Errors
    /// [`Error::Invalid`] from [`ResultsFile::validate`], [`Error::Serialize`].
    pub fn to_json(&self) -> Result<String> {
        self.validate()?;
        serde_json::to_string_pretty(self).map_err(Error::Serialize)
    }

    /// Reads and validates a results file.
    ///
    /// # Errors
    /// [`Error::Io`], [`Error::Parse`], [`Error::SchemaVersion`], [`Error::Invalid`].
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let text = fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
        Self::parse(&text, path)
    }

    /// Validates and writes the file atomically (see [`write_atomic`]).
    ///
    /// # Errors
    /// [`Error::Invalid`] (nothing is written), [`Error::Io`], [`Error::Serialize`].
    pub fn save(&self, path: impl AsRef<Path>) -> Result<()> {
        self.validate()?;
        write_atomic(path.as_ref(), |w| {
            serde_json::to_writer_pretty(&mut *w, self).map_err(io::Error::other)?;
            w.write_all(b"\n")
        })
    }

    /// Checks the contents: schema version, finite non-negative times and counts consistent
    /// with each other, percentages in [0, 100], every record's planner listed, summaries'
    /// scenes and planners known.
    ///
    /// # Errors
    /// [`Error::SchemaVersion`] or [`Error::Invalid`] naming the first offending field.
    pub fn validate(&self) -> Result<()> {
        if self.schema_version != SCHEMA_VERSION {
            return Err(Error::SchemaVersion { found: self.schema_version, expected: SCHEMA_VERSION });
        }
        let p = &self.provenance;
        non_negative("provenance.wall_seconds", p.wall_seconds)?;
        if p.suite_version.is_empty() {
            return Err(invalid("provenance.suite_version", "empty"));
        }
        if let Some(g) = &self.grasp {
            validate_grasp(g)?;
        }
        if let Some(m) = &self.motion {
            validate_motion(m)?;
        }
        Ok(())
    }

    /// One [`ScoreEntry`] per grasp cell and per motion scene × planner (see its docs).
    pub fn scores(&self) -> Vec<ScoreEntry> {
        let mut out = Vec::new();
        if let Some(g) = &self.grasp {
            for r in &g.cells {
                let c = &r.cell;
                out.push(ScoreEntry {
                    category: Category::Grasp,
                    planner: c.planner.clone(),
                    task: format!("{}/{}", c.hand, c.object),
                    score: c.fc_percent_palm,
                    secondary: Some(c.mean_epsilon),
                    samples: c.palm_contact,
                });
            }
        }
        if let Some(m) = &self.motion {
            for s in motion_summaries(m) {
                out.push(ScoreEntry {
                    category: Category::Motion,
                    planner: s.planner.clone(),
                    task: s.scene.clone(),
                    score: s.success_rate,
                    secondary: s.planning_time.p50,
                    samples: s.runs,
                });
            }
        }
        out
    }
}

/// The summaries of a motion section recomputed from its runs, per scene (in `scenes` order,
/// then first appearance) and planner (first appearance).
pub fn motion_summaries(m: &MotionSection) -> Vec<Summary> {
    let mut scenes: Vec<&str> = m.scenes.iter().map(String::as_str).collect();
    let mut planners: Vec<&str> = Vec::new();
    for r in &m.runs {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
        if !planners.contains(&r.planner.as_str()) {
            planners.push(&r.planner);
        }
    }
    let mut out = Vec::new();
    for scene in &scenes {
        for planner in &planners {
            let records: Vec<&RunRecord> =
                m.runs.iter().filter(|r| r.scene == *scene && r.planner == *planner).collect();
            if !records.is_empty() {
                out.push(Summary::from_records(planner, scene, &records));
            }
        }
    }
    out
}

fn invalid(field: impl Into<String>, reason: impl Into<String>) -> Error {
    Error::Invalid { field: field.into(), reason: reason.into() }
}

fn finite(field: &str, v: f64) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(invalid(field, format!("{v} is not finite")))
    }
}

fn non_negative(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(field, format!("{v} is not a finite non-negative number")))
    }
}

fn percent(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && (0.0..=100.0).contains(&v) {
        Ok(())
    } else {
        Err(invalid(field, format!("{v} is not a percentage in [0, 100]")))
    }
}

fn at_most(field: &str, a: usize, what_b: &str, b: usize) -> Result<()> {
    if a <= b {
        Ok(())
    } else {
        Err(invalid(field, format!("{a} exceeds {what_b} ({b})")))
    }
}

fn validate_grasp(g: &GraspSection) -> Result<()> {
    for (i, r) in g.cells.iter().enumerate() {
        let c = &r.cell;
        let f = |name: &str| format!("grasp.cells[{i}].{name}");
        if !g.planners.iter().any(|p| p.name == c.planner) {
            return Err(invalid(f("planner"), format!("planner {:?} is not listed in grasp.planners", c.planner)));
        }
        at_most(&f("evaluated"), c.evaluated, "generated", c.generated)?;
        at_most(&f("closed"), c.closed, "evaluated", c.evaluated)?;
        at_most(&f("palm_contact"), c.palm_contact, "evaluated", c.evaluated)?;
        at_most(&f("force_closure"), c.force_closure, "evaluated", c.evaluated)?;
        at_most(&f("force_closure_palm"), c.force_closure_palm, "palm_contact", c.palm_contact)?;
        at_most(&f("force_closure_palm"), c.force_closure_palm, "force_closure", c.force_closure)?;
        at_most(&f("physics_held"), c.physics_held, "physics_tested", c.physics_tested)?;
        percent(&f("fc_percent_palm"), c.fc_percent_palm)?;
        percent(&f("fc_percent_all"), c.fc_percent_all)?;
        non_negative(&f("mean_epsilon"), c.mean_epsilon)?;
        non_negative(&f("median_epsilon"), c.median_epsilon)?;
        at_most(&f("candidates"), c.candidates.len(), "evaluated", c.evaluated)?;
        for (k, r) in c.candidates.iter().enumerate() {
            non_negative(&f(&format!("candidates[{k}].epsilon")), r.epsilon)?;
            non_negative(&f(&format!("candidates[{k}].volume")), r.volume)?;
            at_most(&f(&format!("candidates[{k}].index")), r.index, "generated", c.generated.saturating_sub(1))?;
        }
        non_negative(&f("planning_seconds"), c.planning_seconds)?;
        non_negative(&f("evaluation_seconds"), c.evaluation_seconds)?;
        non_negative(&f("evaluations_per_second"), c.evaluations_per_second)?;
    }
    Ok(())
}

fn validate_motion(m: &MotionSection) -> Result<()> {
    for (i, r) in m.runs.iter().enumerate() {
        let f = |name: &str| format!("motion.runs[{i}].{name}");
        if !m.planners.iter().any(|p| p.name == r.planner) {
            return Err(invalid(f("planner"), format!("planner {:?} is not listed in motion.planners", r.planner)));
        }
        non_negative(&f("setup_time"), r.setup_time)?;
        non_negative(&f("planning_time"), r.planning_time)?;
        if let Some(t) = r.postprocessing_time {
            non_negative(&f("postprocessing_time"), t)?;
        }
        for (name, v) in [("ik_position_error", r.ik_position_error), ("ik_orientation_error", r.ik_orientation_error)]
        {
            if let Some(v) = v {
                non_negative(&f(name), v)?;
            }
        }
        if r.status == RunStatus::Solved && r.planned.is_none() {
            return Err(invalid(f("planned"), "a solved run must carry its planned path's report"));
        }
        for (name, report) in [("planned", &r.planned), ("processed", &r.processed)] {
            if let Some(p) = report {
                let g = |x: &str| f(&format!("{name}.metrics.{x}"));
                non_negative(&g("length"), p.metrics.length)?;
                finite(&g("smoothness"), p.metrics.smoothness)?;
                if let Some(v) = p.metrics.ee_length {
                    non_negative(&g("ee_length"), v)?;
                }
                for (x, v) in [("clearance_mean", p.metrics.clearance_mean), ("clearance_min", p.metrics.clearance_min)]
                {
                    if let Some(v) = v {
                        finite(&g(x), v)?;
                    }
                }
            }
        }
        if let Some(q) = &r.final_state {
            if q.iter().any(|v| !v.is_finite()) {
                return Err(invalid(f("final_state"), "non-finite joint value"));
            }
        }
    }
    for (i, s) in m.summaries.iter().enumerate() {
        let f = |name: &str| format!("motion.summaries[{i}].{name}");
        percent(&f("success_rate"), s.success_rate)?;
        at_most(&f("solved"), s.solved, "runs", s.runs)?;
        if !m.planners.iter().any(|p| p.name == s.planner) {
            return Err(invalid(f("planner"), format!("planner {:?} is not listed in motion.planners", s.planner)));
        }
    }
    for (i, e) in m.episodes.iter().enumerate() {
        let f = |name: &str| format!("motion.episodes[{i}].{name}");
        at_most(&f("cleaned"), e.cleaned, "objects", e.objects.len())?;
        for (name, v) in [
            ("setup_time", e.setup_time),
            ("planning_time", e.planning_time),
            ("postprocessing_time", e.postprocessing_time),
            ("length", e.length),
            ("ee_length", e.ee_length),
        ] {
            non_negative(&f(name), v)?;
        }
        if !m.planners.iter().any(|p| p.name == e.planner) {
            return Err(invalid(f("planner"), format!("planner {:?} is not listed in motion.planners", e.planner)));
        }
    }
    Ok(())
}

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes a file atomically: `write` fills a temporary file in the same directory, which is
/// flushed, fsynced and renamed over `path` (then the directory is fsynced, best effort).
/// If anything fails, the temporary file is removed and the old file at `path` (if any) is
/// left untouched.
///
/// # Errors
/// [`Error::Io`] for the first failing step (including an error returned by `write`).
pub fn write_atomic(path: &Path, write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>) -> Result<()> {
    let io_err = |source| Error::Io { path: path.to_path_buf(), source };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| io_err(io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name")))?;
    let tmp = dir.join(format!(
        ".{}.tmp.{}.{}",
        name.to_string_lossy(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let result = (|| {
        let file = File::create(&tmp)?;
        let mut w = BufWriter::new(file);
        write(&mut w)?;
        let file = w.into_inner().map_err(io::IntoInnerError::into_error)?;
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = fs::remove_file(&tmp);
        return Err(io_err(e));
    }
    // Persist the rename itself; not possible on every platform, hence best effort.
    if let Ok(d) = File::open(&dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// The git commit of the repository containing `dir` (searching upwards): `.git/HEAD` and
/// the ref it names (loose or in `packed-refs`), else `git rev-parse HEAD`; `None` if neither
/// works.
pub fn git_commit(dir: &Path) -> Option<String> {
    let is_hash = |s: &str| s.len() >= 40 && s.chars().all(|c| c.is_ascii_hexdigit());
    for d in dir.ancestors() {
        let git = d.join(".git");
        if !git.exists() {
            continue;
        }
        if !git.is_dir() {
            // A worktree or submodule (`.git` file): ask git itself.
            break;
        }
        if let Ok(head) = fs::read_to_string(git.join("HEAD")) {
            let head = head.trim();
            if let Some(reference) = head.strip_prefix("ref:") {
                let reference = reference.trim();
                if let Ok(h) = fs::read_to_string(git.join(reference)) {
                    if is_hash(h.trim()) {
                        return Some(h.trim().to_string());
                    }
                }
                if let Ok(packed) = fs::read_to_string(git.join("packed-refs")) {
                    for line in packed.lines() {
                        if let Some((h, r)) = line.split_once(' ') {
                            if r.trim() == reference && is_hash(h) {
                                return Some(h.to_string());
                            }
                        }
                    }
                }
            } else if is_hash(head) {
                return Some(head.to_string());
            }
        }
        break;
    }
    let out = std::process::Command::new("git").arg("-C").arg(dir).args(["rev-parse", "HEAD"]).output().ok()?;
    let h = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (out.status.success() && is_hash(&h)).then_some(h)
}

/// The CPU model (`model name` in `/proc/cpuinfo`), if available.
pub fn cpu_model() -> Option<String> {
    let text = fs::read_to_string("/proc/cpuinfo").ok()?;
    text.lines()
        .filter_map(|l| l.split_once(':'))
        .find(|(k, _)| k.trim() == "model name")
        .map(|(_, v)| v.trim().to_string())
        .filter(|v| !v.is_empty())
}

/// The current UTC time as ISO-8601 with second resolution (`2026-11-23T01:40:00Z`).
pub fn utc_now_iso8601() -> String {
    let secs = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    iso8601_from_unix(secs as i64)
}

/// Formats seconds since the Unix epoch as UTC ISO-8601 (`1970-01-01T00:00:00Z`).
pub fn iso8601_from_unix(secs: i64) -> String {
    let days = secs.div_euclid(86_400);
    let rem = secs.rem_euclid(86_400);
    let (y, m, d) = civil_from_days(days);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", rem / 3600, rem % 3600 / 60, rem % 60)
}

/// Proleptic Gregorian date `(year, month, day)` of a day count since 1970-01-01
/// (H. Hinnant's `civil_from_days`).
pub fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097); // [0, 146096]
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // [0, 399]
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // [0, 365]
    let mp = (5 * doy + 2) / 153; // [0, 11]
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32; // [1, 31]
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32; // [1, 12]
    (if m <= 2 { y + 1 } else { y }, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_dates_match_known_days() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
        assert_eq!(civil_from_days(59), (1970, 3, 1));
        // 2000-02-29 is day 11016; 2024-02-29 is day 19782.
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(19_782), (2024, 2, 29));
        assert_eq!(iso8601_from_unix(1_700_000_000), "2023-11-14T22:13:20Z");
    }
}
