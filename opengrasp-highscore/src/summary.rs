//! One submission at a glance, for its HTML page.

use rusqlite::OptionalExtension;
use serde::{Deserialize, Serialize};

use super::error::{HighscoreError, Result};
use super::{EntryMetrics, Store, SubmissionId};

/// A stored submission: who, what ran, and its entries on each benchmark.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubmissionSummary {
    /// The submission.
    pub id: SubmissionId,
    /// When it was stored (UTC, ISO-8601).
    pub submitted_at: String,
    /// Who submitted.
    pub submitter: String,
    /// Their group, if given.
    pub team: Option<String>,
    /// Suite size that ran.
    pub suite_size: String,
    /// `opengrasp` version that produced the results.
    pub version: String,
    /// Git commit of the harness, if known.
    pub git_commit: Option<String>,
    /// Planners: kind (`grasp`/`motion`), name and parameters.
    pub planners: Vec<(String, String, String)>,
    /// Entries: benchmark id, planner and figures.
    pub entries: Vec<(String, String, EntryMetrics)>,
}

impl Store {
    /// The summary of one submission.
    ///
    /// # Errors
    /// [`HighscoreError::UnknownSubmission`], database errors.
    pub fn submission_summary(&self, id: SubmissionId) -> Result<SubmissionSummary> {
        type Head = (String, String, Option<String>, String, String, Option<String>);
        let head: Option<Head> = self
            .conn()
            .query_row(
                "SELECT submitted_at, submitter, team, suite_size, opengrasp_version, git_commit
                 FROM submissions WHERE id = ?1",
                [id.0],
                |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?, r.get(5)?)),
            )
            .optional()?;
        let (submitted_at, submitter, team, suite_size, version, git_commit) =
            head.ok_or(HighscoreError::UnknownSubmission { id: id.0 })?;
        let mut stmt = self
            .conn()
            .prepare_cached("SELECT kind, name, parameters FROM submission_planners WHERE submission_id = ?1")?;
        let planners =
            stmt.query_map([id.0], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?.collect::<rusqlite::Result<_>>()?;
        let mut stmt = self.conn().prepare_cached(
            "SELECT benchmark_id, planner, metrics FROM entries WHERE submission_id = ?1 ORDER BY benchmark_id, planner",
        )?;
        let rows = stmt
            .query_map([id.0], |r| Ok((r.get::<_, String>(0)?, r.get::<_, String>(1)?, r.get::<_, String>(2)?)))?
            .collect::<rusqlite::Result<Vec<_>>>()?;
        let entries =
            rows.into_iter().filter_map(|(b, p, m)| serde_json::from_str(&m).ok().map(|m| (b, p, m))).collect();
        Ok(SubmissionSummary { id, submitted_at, submitter, team, suite_size, version, git_commit, planners, entries })
    }
}
