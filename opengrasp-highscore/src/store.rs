//! The SQLite results database: schema, submissions and rankings.
//!
//! # Schema (version [`SCHEMA_VERSION`], kept in `PRAGMA user_version`)
//!
//! - `benchmarks(id TEXT PRIMARY KEY, kind TEXT, target TEXT, description TEXT)`: the
//!   benchmarks the board administers (`grasp/<hand>`, `motion/<scene slug>`).
//! - `submissions(id INTEGER PRIMARY KEY AUTOINCREMENT, submitted_at TEXT, submitter TEXT,
//!   team TEXT, suite_version TEXT, suite_size TEXT, opengrasp_version TEXT, git_commit TEXT,
//!   started_at TEXT, grasp_seed TEXT, motion_seed TEXT, provenance TEXT /*json*/,
//!   results TEXT /*the uploaded file, verbatim*/)`: one row per upload (seeds as decimal
//!   text, since SQLite integers are signed 64-bit).
//! - `submission_planners(submission_id, kind, name, parameters)`: the planners of an upload.
//! - `grasp_cells(submission_id, benchmark_id, planner, hand, object, seed, generated,
//!   evaluated, closed, palm_contact, force_closure_palm, force_closure, mean_epsilon,
//!   median_epsilon, physics_tested, physics_held, planning_seconds, evaluation_seconds)`:
//!   every grasp cell.
//! - `motion_runs(submission_id, benchmark_id, planner, scene, run, seed, status, setup_time,
//!   planning_time, postprocessing_time, processed_discrete, processed_strict,
//!   processed_continuous, processed_length, planned_strict)`: every motion run.
//!
//! - (v2) `submissions.content_hash`: SHA-256 of the canonical results (unique), so a retried
//!   or repeated upload is one entry.
//! - (v2) `entries(submission_id, benchmark_id, planner, metrics /*json EntryMetrics*/)`: the
//!   ranked entries, computed from the cell and run rows when a submission is stored (and for
//!   every stored submission when a v1 database is migrated), so a ranking is one query.
//! - (v2) `tokens(id, team, hash, created_at, revoked)`: API tokens, SHA-256 hashed.
//!
//! Each submission is written in one transaction ([`Store::insert_submission`]), or several
//! in one transaction under a savepoint each ([`Store::insert_batch`], the web service's group
//! commit). The database runs in WAL mode with
//! `synchronous = FULL`: readers never wait for the writer and an acknowledged submission
//! survives a crash of the process or the machine.

use std::path::Path;

use rusqlite::{params, Connection, OpenFlags, OptionalExtension};

use super::error::{HighscoreError, Result};
use super::{
    builtin_benchmarks, rank, slug, BenchmarkInfo, BenchmarkKind, Ranking, Submission, SubmissionId, GRASP_RULES,
    MOTION_RULES,
};

/// Version of the schema this build reads and writes.
pub const SCHEMA_VERSION: i64 = 2;

const SCHEMA_V1: &str = "
CREATE TABLE benchmarks (
    id TEXT PRIMARY KEY NOT NULL,
    kind TEXT NOT NULL CHECK (kind IN ('grasp', 'motion')),
    target TEXT NOT NULL,
    description TEXT NOT NULL
);
CREATE TABLE submissions (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    submitted_at TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
    submitter TEXT NOT NULL,
    team TEXT,
    suite_version TEXT NOT NULL,
    suite_size TEXT NOT NULL,
    opengrasp_version TEXT NOT NULL,
    git_commit TEXT,
    started_at TEXT NOT NULL,
    grasp_seed TEXT,
    motion_seed TEXT,
    provenance TEXT NOT NULL,
    results TEXT NOT NULL
);
CREATE TABLE submission_planners (
    submission_id INTEGER NOT NULL REFERENCES submissions(id),
    kind TEXT NOT NULL CHECK (kind IN ('grasp', 'motion')),
    name TEXT NOT NULL,
    parameters TEXT NOT NULL
);
CREATE TABLE grasp_cells (
    submission_id INTEGER NOT NULL REFERENCES submissions(id),
    benchmark_id TEXT NOT NULL REFERENCES benchmarks(id),
    planner TEXT NOT NULL,
    hand TEXT NOT NULL,
    object TEXT NOT NULL,
    seed TEXT NOT NULL,
    generated INTEGER NOT NULL,
    evaluated INTEGER NOT NULL,
    closed INTEGER NOT NULL,
    palm_contact INTEGER NOT NULL,
    force_closure_palm INTEGER NOT NULL,
    force_closure INTEGER NOT NULL,
    mean_epsilon REAL NOT NULL,
    median_epsilon REAL NOT NULL,
    physics_tested INTEGER NOT NULL,
    physics_held INTEGER NOT NULL,
    planning_seconds REAL NOT NULL,
    evaluation_seconds REAL NOT NULL
);
CREATE INDEX grasp_cells_benchmark ON grasp_cells(benchmark_id);
CREATE TABLE motion_runs (
    submission_id INTEGER NOT NULL REFERENCES submissions(id),
    benchmark_id TEXT NOT NULL REFERENCES benchmarks(id),
    planner TEXT NOT NULL,
    scene TEXT NOT NULL,
    run INTEGER NOT NULL,
    seed TEXT NOT NULL,
    status TEXT NOT NULL,
    setup_time REAL NOT NULL,
    planning_time REAL NOT NULL,
    postprocessing_time REAL,
    processed_discrete INTEGER,
    processed_strict INTEGER,
    processed_continuous INTEGER,
    processed_length REAL,
    planned_strict INTEGER
);
CREATE INDEX motion_runs_benchmark ON motion_runs(benchmark_id);
";

const SCHEMA_V2: &str = "
ALTER TABLE submissions ADD COLUMN content_hash TEXT;
CREATE UNIQUE INDEX submissions_content_hash ON submissions(content_hash);
CREATE INDEX submission_planners_submission ON submission_planners(submission_id);
CREATE INDEX grasp_cells_submission ON grasp_cells(submission_id);
CREATE INDEX motion_runs_submission ON motion_runs(submission_id);
CREATE TABLE entries (
    submission_id INTEGER NOT NULL REFERENCES submissions(id),
    benchmark_id TEXT NOT NULL REFERENCES benchmarks(id),
    planner TEXT NOT NULL,
    metrics TEXT NOT NULL,
    PRIMARY KEY (benchmark_id, submission_id, planner)
);
CREATE TABLE tokens (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    team TEXT NOT NULL,
    hash TEXT NOT NULL UNIQUE,
    created_at TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
    revoked INTEGER NOT NULL DEFAULT 0
);
";

/// Row counts of the stored data (to check that a rejected upload left no trace).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Counts {
    /// Submissions.
    pub submissions: u64,
    /// Grasp cells.
    pub grasp_cells: u64,
    /// Motion runs.
    pub motion_runs: u64,
}

/// An open results database.
#[derive(Debug)]
pub struct Store {
    conn: Connection,
}

/// Outcome of [`Store::insert_submission`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Inserted {
    /// The stored submission (the earlier one for a retried upload).
    pub id: SubmissionId,
    /// True if these results were already stored by the same submitter (nothing written).
    pub duplicate: bool,
}

impl Store {
    /// Opens (creating if needed) the database at `path`, creates, migrates or checks the
    /// schema, registers the built-in benchmarks and switches to WAL mode.
    ///
    /// # Errors
    /// [`HighscoreError::Database`] if SQLite fails, [`HighscoreError::Busy`] if another
    /// process holds the write lock too long, [`HighscoreError::SchemaVersion`] if the file
    /// was written by a newer schema version.
    pub fn open(path: &Path) -> Result<Self> {
        let conn = Connection::open(path)?;
        conn.busy_timeout(std::time::Duration::from_secs(2))?;
        // WAL: readers do not wait for the writer; FULL: a commit is on disk when acknowledged.
        let _: String = conn.pragma_update_and_check(None, "journal_mode", "WAL", |r| r.get(0))?;
        conn.pragma_update(None, "synchronous", "FULL")?;
        Self::init(conn)
    }

    /// Opens an existing database for reading only (never creates or migrates it).
    ///
    /// # Errors
    /// [`HighscoreError::NoDatabase`] if the file does not exist,
    /// [`HighscoreError::SchemaVersion`] unless it has this build's schema, database errors.
    pub fn open_read_only(path: &Path) -> Result<Self> {
        if !path.exists() {
            return Err(HighscoreError::NoDatabase { path: path.to_path_buf() });
        }
        let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX | OpenFlags::SQLITE_OPEN_URI;
        let conn = Connection::open_with_flags(path, flags)?;
        conn.busy_timeout(std::time::Duration::from_secs(1))?;
        let version: i64 = conn.pragma_query_value(None, "user_version", |r| r.get(0))?;
        if version != SCHEMA_VERSION {
            return Err(HighscoreError::SchemaVersion { found: version, supported: SCHEMA_VERSION });
        }
        Ok(Self { conn })
    }

    /// An in-memory database (for tests and dry runs).
    ///
    /// # Errors
    /// As [`Store::open`].
    pub fn open_in_memory() -> Result<Self> {
        Self::init(Connection::open_in_memory()?)
    }

    fn init(mut conn: Connection) -> Result<Self> {
        conn.pragma_update(None, "foreign_keys", true)?;
        let tx = conn.transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)?;
        let version: i64 = tx.pragma_query_value(None, "user_version", |r| r.get(0))?;
        match version {
            0 => {
                tx.execute_batch(SCHEMA_V1)?;
                tx.execute_batch(SCHEMA_V2)?;
            }
            1 => tx.execute_batch(SCHEMA_V2)?,
            SCHEMA_VERSION => {}
            found => return Err(HighscoreError::SchemaVersion { found, supported: SCHEMA_VERSION }),
        }
        for b in builtin_benchmarks() {
            tx.execute(
                "INSERT OR IGNORE INTO benchmarks (id, kind, target, description) VALUES (?1, ?2, ?3, ?4)",
                params![b.id, b.kind.as_str(), b.target, b.description],
            )?;
        }
        if version == 1 {
            // v1 stored no entries: compute them for every stored submission.
            let ids: Vec<i64> = tx
                .prepare("SELECT id FROM submissions")?
                .query_map([], |r| r.get(0))?
                .collect::<rusqlite::Result<_>>()?;
            for id in ids {
                rank::store_entries(&tx, id)?;
            }
        }
        if version != SCHEMA_VERSION {
            tx.pragma_update(None, "user_version", SCHEMA_VERSION)?;
        }
        tx.commit()?;
        Ok(Self { conn })
    }

    pub(crate) fn conn(&self) -> &Connection {
        &self.conn
    }

    /// Adds a benchmark (`<kind>/<slug of target>`) to the board; returns its id. Registering
    /// an existing id keeps the stored description.
    ///
    /// # Errors
    /// [`HighscoreError::InvalidField`] for an empty or overlong target or description,
    /// [`HighscoreError::Database`] if SQLite fails.
    pub fn register_benchmark(&self, kind: BenchmarkKind, target: &str, description: &str) -> Result<String> {
        super::check_name("target", target)?;
        super::check_text("description", description, super::MAX_TEXT)?;
        let s = slug(target);
        if s.is_empty() {
            return Err(HighscoreError::field("target", "has no letters or digits"));
        }
        let id = format!("{}/{s}", kind.as_str());
        self.conn.execute(
            "INSERT OR IGNORE INTO benchmarks (id, kind, target, description) VALUES (?1, ?2, ?3, ?4)",
            params![id, kind.as_str(), target, description],
        )?;
        Ok(id)
    }

    /// Every benchmark with its number of submissions, ordered by id.
    ///
    /// # Errors
    /// [`HighscoreError::Database`] if SQLite fails.
    pub fn benchmarks(&self) -> Result<Vec<BenchmarkInfo>> {
        let mut stmt = self.conn.prepare_cached(
            "SELECT b.id, b.kind, b.target, b.description,
                (SELECT COUNT(DISTINCT submission_id) FROM entries e WHERE e.benchmark_id = b.id)
             FROM benchmarks b ORDER BY b.id",
        )?;
        let rows = stmt.query_map([], |r| {
            Ok(BenchmarkInfo {
                id: r.get(0)?,
                kind: BenchmarkKind::parse(&r.get::<_, String>(1)?).unwrap_or(BenchmarkKind::Grasp),
                target: r.get(2)?,
                description: r.get(3)?,
                submissions: r.get::<_, i64>(4)?.max(0) as u64,
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// The benchmark `id` (exact id, or `<kind>/<target>` whose target slugifies to a known id).
    ///
    /// # Errors
    /// [`HighscoreError::UnknownBenchmark`] if no benchmark matches.
    pub fn benchmark(&self, id: &str) -> Result<BenchmarkInfo> {
        let unknown = || HighscoreError::UnknownBenchmark { id: id.to_string() };
        let canonical = canonical_id(id).ok_or_else(unknown)?;
        self.benchmarks()?.into_iter().find(|b| b.id == id || b.id == canonical).ok_or_else(unknown)
    }

    /// Row counts of the stored data.
    ///
    /// # Errors
    /// [`HighscoreError::Database`] if SQLite fails.
    pub fn counts(&self) -> Result<Counts> {
        let n = |table: &str| -> Result<u64> {
            let v: i64 = self.conn.query_row(&format!("SELECT COUNT(*) FROM {table}"), [], |r| r.get(0))?;
            Ok(v.max(0) as u64)
        };
        Ok(Counts { submissions: n("submissions")?, grasp_cells: n("grasp_cells")?, motion_runs: n("motion_runs")? })
    }

    /// The newest submission id (0 if none): changes whenever a submission is stored, by this
    /// or any other process, so it versions cached rankings.
    ///
    /// # Errors
    /// [`HighscoreError::Database`] if SQLite fails.
    pub fn generation(&self) -> Result<i64> {
        Ok(self.conn.prepare_cached("SELECT COALESCE(MAX(id), 0) FROM submissions")?.query_row([], |r| r.get(0))?)
    }

    /// Stores a validated submission in one transaction (all of it or nothing); a submission
    /// whose results were already stored by the same submitter returns the earlier id.
    ///
    /// # Errors
    /// As [`Store::insert_submission`].
    pub fn insert(&mut self, submission: &Submission) -> Result<SubmissionId> {
        Ok(self.insert_submission(submission)?.id)
    }

    /// Stores a validated submission in one transaction (all of it or nothing).
    ///
    /// # Errors
    /// [`HighscoreError::Duplicate`] if the same results were stored by another submitter,
    /// [`HighscoreError::UnknownBenchmark`] if a cell's hand or a run's scene is not a
    /// benchmark of the board, [`HighscoreError::Busy`] if another process holds the write
    /// lock, [`HighscoreError::Database`] if SQLite fails.
    pub fn insert_submission(&mut self, submission: &Submission) -> Result<Inserted> {
        let tx = self.conn.transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)?;
        let inserted = super::insert::insert_in(&tx, submission)?;
        tx.commit()?;
        Ok(inserted)
    }

    /// Stores several validated submissions in ONE transaction (group commit: one fsync for
    /// all of them). Each submission is written under its own savepoint, so a rejected one
    /// (duplicate, unknown benchmark) leaves no trace and does not affect the others; the
    /// outcomes are in the order of `submissions`. Nothing is durable (and no outcome may be
    /// acknowledged to a client) unless this returns `Ok`.
    ///
    /// # Errors
    /// [`HighscoreError::Busy`] if another process holds the write lock,
    /// [`HighscoreError::Database`] if the transaction cannot begin or commit (then none of
    /// the submissions is stored).
    pub fn insert_batch(&mut self, submissions: &[&Submission]) -> Result<Vec<Result<Inserted>>> {
        let mut tx = self.conn.transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)?;
        let mut outcomes = Vec::with_capacity(submissions.len());
        for s in submissions {
            let sp = tx.savepoint()?;
            let outcome = super::insert::insert_in(&sp, s);
            if outcome.is_ok() {
                sp.commit()?;
            } // else: dropped, rolled back to the savepoint
            outcomes.push(outcome);
        }
        tx.commit()?;
        Ok(outcomes)
    }

    /// The uploaded results of a submission, verbatim.
    ///
    /// # Errors
    /// [`HighscoreError::UnknownSubmission`] if there is no such submission.
    pub fn submission_json(&self, id: SubmissionId) -> Result<String> {
        self.conn
            .query_row("SELECT results FROM submissions WHERE id = ?1", [id.0], |r| r.get(0))
            .optional()?
            .ok_or(HighscoreError::UnknownSubmission { id: id.0 })
    }

    /// The benchmarks a submission has results on, ordered by id.
    ///
    /// # Errors
    /// [`HighscoreError::Database`] if SQLite fails.
    pub fn submission_benchmarks(&self, id: SubmissionId) -> Result<Vec<String>> {
        let mut stmt = self
            .conn
            .prepare_cached("SELECT DISTINCT benchmark_id FROM entries WHERE submission_id = ?1 ORDER BY 1")?;
        let rows = stmt.query_map([id.0], |r| r.get(0))?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// The full ranking of one benchmark (see [`GRASP_RULES`] and [`MOTION_RULES`]).
    ///
    /// # Errors
    /// [`HighscoreError::UnknownBenchmark`] if `benchmark` is not on the board,
    /// [`HighscoreError::Database`] if SQLite fails.
    pub fn ranking(&self, benchmark: &str) -> Result<Ranking> {
        let info = self.benchmark(benchmark)?;
        let entries = rank::ranked_entries(&self.conn, &info)?;
        let rules = match info.kind {
            BenchmarkKind::Grasp => GRASP_RULES,
            BenchmarkKind::Motion => MOTION_RULES,
        };
        Ok(Ranking { benchmark: info, rules: rules.to_string(), total: entries.len(), offset: 0, entries })
    }

    /// The per-object cells (grasp) or solved planning times (motion) behind the charts of a
    /// ranking page, for its first [`MAX_CHARTED`](crate::charts::MAX_CHARTED) entries.
    ///
    /// # Errors
    /// [`HighscoreError::Database`] if SQLite fails.
    pub fn chart_data(&self, ranking: &Ranking) -> Result<crate::charts::ChartData> {
        crate::charts::chart_data(&self.conn, &ranking.benchmark, &ranking.entries)
    }

    /// Rankings of every benchmark, ordered by id.
    ///
    /// # Errors
    /// As [`Store::ranking`].
    pub fn rankings(&self) -> Result<Vec<Ranking>> {
        self.benchmarks()?.iter().map(|b| self.ranking(&b.id)).collect()
    }
}

/// `<kind>/<slug(target)>` of a user-given benchmark id, if it has a known kind.
fn canonical_id(id: &str) -> Option<String> {
    let (kind, target) = id.split_once('/')?;
    let kind = BenchmarkKind::parse(kind.trim())?;
    Some(format!("{}/{}", kind.as_str(), slug(target)))
}
