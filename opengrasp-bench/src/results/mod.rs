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

mod atomic;
mod merge;
mod provenance;
mod validate;

use std::fs;
use std::io::{self, Write};
use std::path::Path;

use opengrasp_grasp::benchmark::CellResult;
use opengrasp_motion::benchmark::{BenchmarkOptions, RunRecord, Summary};
use serde::{Deserialize, Serialize};

pub use crate::error::{Error, Result};
pub use atomic::{check_writable, write_atomic};
pub use merge::merge;
pub use provenance::{
    civil_from_days, cpu_model, git_commit, iso8601_from_unix, utc_now_iso8601, Provenance, Shard, BUILD_GIT_COMMIT,
};
use validate::{invalid, non_negative, validate_grasp, validate_motion};

/// Version of the results-file schema; [`ResultsFile::load`] rejects other versions.
pub const SCHEMA_VERSION: u32 = 1;

/// Version of the benchmark suite (scenes, objects, hands, metrics). Results of different
/// suite versions are not comparable.
pub const SUITE_VERSION: &str = "opengrasp-suite/1";

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
    /// [`crate::clean_table::SCENE_NAME`]); absent from files without any.
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
    /// Sums over its queries (flattened into the record in JSON).
    #[serde(flatten)]
    pub totals: crate::clean_table::EpisodeTotals,
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
