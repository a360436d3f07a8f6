//! The benchmarking high-score board: a local results database and its web service.
//!
//! Like the OpenGRASP web service that "administers the available benchmarks ... and a
//! benchmarking high-score that records the participants' results", this module keeps every
//! submitted [`ResultsFile`](opengrasp_bench::results::ResultsFile) in a SQLite database ([`store`]) with its provenance and ranks
//! the planners per benchmark; [`server`] serves a JSON API and HTML high-score pages.
//!
//! # Benchmarks
//!
//! A benchmark id is `<kind>/<slug>`: `grasp/<hand>` (e.g. `grasp/barrett`) ranks grasp
//! planners on one hand over the objects they were run on; `motion/<scene>` ranks motion
//! planners on one scene, the scene name slugified ([`slug`]: lowercase ASCII letters and
//! digits, every other run of characters one `-`; `"standard (7-DoF stand-in)"` →
//! `motion/standard-7-dof-stand-in`). Lookups accept the id or `<kind>/<target name>`.
//! The board knows the built-in hands and scenes ([`builtin_benchmarks`]); more are added
//! with [`register_benchmark`]. An upload with a cell or run of an unknown benchmark is
//! rejected whole.
//!
//! # Ranking rules
//!
//! One entry per submission × planner × benchmark, computed from the stored cells and runs
//! (so every ranking can be recomputed from the database). See [`GRASP_RULES`] and
//! [`MOTION_RULES`]. Runs of different suite sizes (`paper`, `default`, `custom`, `tiny`) are
//! not comparable, so each size is ranked as its own league, listed in that order. Entries
//! equal on every key share a rank (1, 1, 3, ...) and are listed by submission order.
//!
//! # Service
//!
//! [`serve`] (blocking, for `opengrasp serve`) and [`spawn`] (background thread, ephemeral
//! port, [`ServerHandle`] to stop it) run the HTTP service described in [`server`]: JSON API
//! (`GET /api/benchmarks`, `GET /api/benchmarks/<kind>/<name>/ranking`,
//! `POST /api/submissions`, `GET /api/submissions/<id>`) and HTML pages (`/`,
//! `/highscore/<kind>/<name>`). Uploads are limited to [`MAX_UPLOAD_BYTES`] and validated
//! like files ([`Submission::from_json`]); rejections are 4xx JSON errors and write nothing.
//!
//! # Example
//!
//! ```no_run
//! # fn main() -> opengrasp_highscore::Result<()> {
//! use std::path::Path;
//! use opengrasp_highscore as highscore;
//! let db = Path::new("results.sqlite");
//! let id = highscore::submit(db, Path::new("results.json"), "alice")?;
//! println!("stored as submission {}", id.0);
//! println!("{}", highscore::render_rankings(&highscore::ranking(db, Some("grasp/barrett"))?));
//! # Ok(())
//! # }
//! ```

pub mod charts;
pub mod client;
mod db;
mod error;
pub mod html;
mod insert;
pub mod plausible;
mod rank;
pub mod read;
pub mod server;
pub mod store;
mod submission;
mod summary;
mod text;
mod tokens;
pub mod verify;

use std::cmp::Ordering;
use std::path::Path;

use serde::{Deserialize, Serialize};

pub use db::{Db, Stored};
pub use error::{HighscoreError, Result};
pub use server::{serve, spawn, ServerHandle, ServerOptions};
pub use store::{Counts, Inserted, Store, SCHEMA_VERSION};
pub use submission::Submission;
pub(crate) use submission::{check_name, check_text};
pub use summary::SubmissionSummary;
pub use text::render_rankings;
pub use tokens::{sha256_hex, TokenInfo};

/// Largest accepted upload or results file (8 MiB).
pub const MAX_UPLOAD_BYTES: usize = 8 * 1024 * 1024;
/// Longest accepted name (submitter, team, planner, hand, object, scene), in characters.
pub const MAX_NAME: usize = 200;
/// Longest accepted free text (planner parameters, run messages, descriptions), in characters.
pub const MAX_TEXT: usize = 10_000;
/// Most grasp cells plus motion runs accepted in one submission.
pub const MAX_RECORDS: usize = 100_000;

/// Ranking rules of `grasp/<hand>` benchmarks.
pub const GRASP_RULES: &str = "per submission and planner, pooled over the objects it ran: \
1. force closure % among palm-contact candidates (sum of force-closure palm grasps / sum of palm-contact candidates), higher first; \
2. mean Ferrari-Canny epsilon over those force-closure palm-contact grasps (cell means weighted by their counts), higher first; \
3. earlier submission first; \
entries are ranked within the suite size they ran (paper, default, custom, tiny): different sizes are not comparable";

/// Ranking rules of `motion/<scene>` benchmarks.
pub const MOTION_RULES: &str = "per submission and planner: \
1. success rate % (solved runs / runs), higher first; \
2. median planning time of the solved runs, lower first (no solved run: last); \
3. post-processed validity % (solved runs whose post-processed path passes the strict discrete check and, where available, the continuous check), higher first; \
4. earlier submission first; \
entries are ranked within the suite size they ran (paper, default, custom, tiny): different sizes are not comparable";

/// Id of a stored submission.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct SubmissionId(pub i64);

/// Who submitted: a participant and optionally their group.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Submitter {
    /// Participant name (1 to [`MAX_NAME`] characters, no control characters).
    pub name: String,
    /// Group or lab, if given.
    pub team: Option<String>,
}

impl Submitter {
    /// A participant without a group.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), team: None }
    }

    /// Sets the group.
    pub fn with_team(mut self, team: impl Into<String>) -> Self {
        self.team = Some(team.into());
        self
    }

    fn validate(&self) -> Result<()> {
        check_name("submitter", &self.name)?;
        if let Some(t) = &self.team {
            check_name("team", t)?;
        }
        Ok(())
    }
}

impl From<&str> for Submitter {
    fn from(name: &str) -> Self {
        Self::new(name)
    }
}

impl From<String> for Submitter {
    fn from(name: String) -> Self {
        Self::new(name)
    }
}

/// Kind of a benchmark.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BenchmarkKind {
    /// Grasp planning on one hand.
    Grasp,
    /// Motion planning on one scene.
    Motion,
}

impl BenchmarkKind {
    /// `"grasp"` or `"motion"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Grasp => "grasp",
            Self::Motion => "motion",
        }
    }

    /// The kind named `s` (`"grasp"` or `"motion"`).
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "grasp" => Some(Self::Grasp),
            "motion" => Some(Self::Motion),
            _ => None,
        }
    }
}

/// A benchmark of the board.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct BenchmarkInfo {
    /// Id, `<kind>/<slug of target>`.
    pub id: String,
    /// Kind.
    pub kind: BenchmarkKind,
    /// The hand (grasp) or scene (motion) name as in results files.
    pub target: String,
    /// One-line description.
    pub description: String,
    /// Submissions with results on this benchmark.
    pub submissions: u64,
}

/// Headline figures of one ranked entry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum EntryMetrics {
    /// A grasp planner on one hand, pooled over objects.
    Grasp {
        /// Distinct objects.
        objects: u64,
        /// Candidates evaluated.
        evaluated: u64,
        /// Candidates with palm contact.
        palm_contact: u64,
        /// Force-closure grasps among them.
        force_closure_palm: u64,
        /// `100 · force_closure_palm / palm_contact` (0 without palm contact).
        fc_percent: f64,
        /// Mean Ferrari-Canny epsilon over the force-closure palm-contact grasps (0 if none).
        mean_epsilon: f64,
    },
    /// A motion planner on one scene.
    Motion {
        /// Runs.
        runs: u64,
        /// Solved runs.
        solved: u64,
        /// `100 · solved / runs`.
        success_rate: f64,
        /// Median planning time of the solved runs (s); `None` if none solved.
        median_planning_time: Option<f64>,
        /// Solved runs whose post-processed path is valid (%, see [`MOTION_RULES`]).
        valid_processed: f64,
    },
}

impl EntryMetrics {
    /// Order of the ranking rules: `Less` means `self` ranks better than `other`.
    pub fn compare(&self, other: &Self) -> Ordering {
        match (self, other) {
            (
                Self::Grasp { fc_percent: a, mean_epsilon: ea, .. },
                Self::Grasp { fc_percent: b, mean_epsilon: eb, .. },
            ) => b.total_cmp(a).then(eb.total_cmp(ea)),
            (
                Self::Motion { success_rate: a, median_planning_time: ta, valid_processed: va, .. },
                Self::Motion { success_rate: b, median_planning_time: tb, valid_processed: vb, .. },
            ) => b
                .total_cmp(a)
                .then(match (ta, tb) {
                    (Some(x), Some(y)) => x.total_cmp(y),
                    (Some(_), None) => Ordering::Less,
                    (None, Some(_)) => Ordering::Greater,
                    (None, None) => Ordering::Equal,
                })
                .then(vb.total_cmp(va)),
            (Self::Grasp { .. }, Self::Motion { .. }) => Ordering::Less,
            (Self::Motion { .. }, Self::Grasp { .. }) => Ordering::Greater,
        }
    }
}

/// One row of a ranking.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RankedEntry {
    /// Rank (1 = best; equal entries share a rank).
    pub rank: usize,
    /// The submission.
    pub submission: SubmissionId,
    /// When it was stored (UTC, ISO-8601).
    pub submitted_at: String,
    /// Who submitted.
    pub submitter: String,
    /// Their group, if given.
    pub team: Option<String>,
    /// Planner name.
    pub planner: String,
    /// The planner's parameters as listed in the results file.
    pub parameters: Option<String>,
    /// Seed of the benchmark run (grasp section seed or motion options seed).
    pub seed: Option<u64>,
    /// `opengrasp` version that produced the results.
    pub version: String,
    /// Suite size that ran (`default`, `paper`, `tiny`, `custom`).
    pub suite_size: String,
    /// Figures the entry is ranked by.
    pub metrics: EntryMetrics,
}

/// The ranking of one benchmark.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ranking {
    /// The benchmark.
    pub benchmark: BenchmarkInfo,
    /// The rules applied ([`GRASP_RULES`] or [`MOTION_RULES`]).
    pub rules: String,
    /// Entries of the whole ranking (`entries` may be one page of them).
    #[serde(default)]
    pub total: usize,
    /// Position of `entries[0]` in the whole ranking.
    #[serde(default)]
    pub offset: usize,
    /// Entries, best first.
    pub entries: Vec<RankedEntry>,
}

/// Slug of a hand or scene name: lowercase ASCII letters and digits, every other run of
/// characters replaced by one `-`, no leading or trailing `-`.
pub fn slug(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.is_empty() && !out.ends_with('-') {
            out.push('-');
        }
    }
    while out.ends_with('-') {
        out.pop();
    }
    out
}

/// The benchmarks every database starts with: one per stock hand
/// ([`opengrasp_bench::stock::HAND_NAMES`]), one per scene of [`opengrasp_bench::scenes`],
/// Clean the Table ([`CLEAN_THE_TABLE_SCENE`](opengrasp_bench::suite::CLEAN_THE_TABLE_SCENE), ranked per
/// grasp/place query) and the tiny suite's [`planar_scene`](opengrasp_bench::suite::planar_scene).
pub fn builtin_benchmarks() -> Vec<BenchmarkInfo> {
    use opengrasp_bench::scenes::{self, CheckerKind};
    let mut out = Vec::new();
    for hand in opengrasp_bench::stock::HAND_NAMES {
        out.push(BenchmarkInfo {
            id: format!("grasp/{}", slug(hand)),
            kind: BenchmarkKind::Grasp,
            target: hand.to_string(),
            description: format!("grasp planning with the {hand} hand on the KIT kitchen objects"),
            submissions: 0,
        });
    }
    let scenes = [
        scenes::armar_standard_scene(),
        scenes::armar_ik_scene(),
        scenes::standard_scene(CheckerKind::Exact),
        scenes::standard_scene(CheckerKind::Spheres),
        scenes::ik_scene(CheckerKind::Exact),
        opengrasp_bench::suite::planar_scene(),
    ];
    let names =
        scenes.into_iter().map(|s| s.name).chain(std::iter::once(opengrasp_bench::suite::CLEAN_THE_TABLE_SCENE.into()));
    for name in names {
        out.push(BenchmarkInfo {
            id: format!("motion/{}", slug(&name)),
            kind: BenchmarkKind::Motion,
            description: format!("motion planning in the scene {name}"),
            target: name,
            submissions: 0,
        });
    }
    out
}

/// Reads, validates and stores a results file; returns the new submission's id.
///
/// # Errors
/// [`HighscoreError::Io`] if the file cannot be read, [`HighscoreError::TooLarge`] above
/// [`MAX_UPLOAD_BYTES`], the validation errors of [`Submission::from_json`],
/// [`HighscoreError::UnknownBenchmark`] for a hand or scene the board does not rank, and
/// database errors. Nothing is stored unless everything succeeds.
pub fn submit(db_path: &Path, results_file_path: &Path, submitter: impl Into<Submitter>) -> Result<SubmissionId> {
    let text = read::read_file_bounded(results_file_path, MAX_UPLOAD_BYTES)?;
    submit_json(db_path, &text, submitter)
}

/// As [`submit`], from the results file's JSON text.
///
/// # Errors
/// As [`submit`].
pub fn submit_json(db_path: &Path, text: &str, submitter: impl Into<Submitter>) -> Result<SubmissionId> {
    let submission = Submission::from_json(text, submitter.into())?;
    Store::open(db_path)?.insert(&submission)
}

/// Rankings of one benchmark (`Some(id)`, one element) or of every benchmark (`None`). Reads
/// never create or change the database.
///
/// # Errors
/// [`HighscoreError::NoDatabase`] if there is no database at `db_path`,
/// [`HighscoreError::UnknownBenchmark`], database errors.
pub fn ranking(db_path: &Path, benchmark: Option<&str>) -> Result<Vec<Ranking>> {
    let store = Store::open_read_only(db_path)?;
    match benchmark {
        Some(b) => Ok(vec![store.ranking(b)?]),
        None => store.rankings(),
    }
}

/// The benchmarks of the board (never creates the database).
///
/// # Errors
/// [`HighscoreError::NoDatabase`], database errors.
pub fn benchmarks(db_path: &Path) -> Result<Vec<BenchmarkInfo>> {
    Store::open_read_only(db_path)?.benchmarks()
}

/// Adds a benchmark to the board (see [`Store::register_benchmark`]); returns its id.
///
/// # Errors
/// As [`Store::register_benchmark`].
pub fn register_benchmark(db_path: &Path, kind: BenchmarkKind, target: &str, description: &str) -> Result<String> {
    Store::open(db_path)?.register_benchmark(kind, target, description)
}
