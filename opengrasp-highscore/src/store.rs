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
//! Rankings are computed from the cell and run rows on each query, so changing the rules
//! re-ranks every stored submission. Each submission is written in one transaction.

use std::collections::BTreeMap;
use std::path::Path;

use rusqlite::{params, Connection, OptionalExtension, Transaction};

use super::error::{HighscoreError, Result};
use super::{
    builtin_benchmarks, slug, BenchmarkInfo, BenchmarkKind, EntryMetrics, RankedEntry, Ranking, Submission,
    SubmissionId, GRASP_RULES, MOTION_RULES,
};

/// Version of the schema this build reads and writes.
pub const SCHEMA_VERSION: i64 = 1;

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

impl Store {
    /// Opens (creating if needed) the database at `path`, creates or checks the schema and
    /// registers the built-in benchmarks.
    ///
    /// # Errors
    /// [`HighscoreError::Database`] if SQLite fails, [`HighscoreError::SchemaVersion`] if the
    /// file was written by another schema version.
    pub fn open(path: &Path) -> Result<Self> {
        Self::init(Connection::open(path)?)
    }

    /// An in-memory database (for tests and dry runs).
    ///
    /// # Errors
    /// As [`Store::open`].
    pub fn open_in_memory() -> Result<Self> {
        Self::init(Connection::open_in_memory()?)
    }

    fn init(mut conn: Connection) -> Result<Self> {
        conn.busy_timeout(std::time::Duration::from_secs(5))?;
        conn.pragma_update(None, "foreign_keys", true)?;
        let tx = conn.transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)?;
        let version: i64 = tx.pragma_query_value(None, "user_version", |r| r.get(0))?;
        match version {
            0 => {
                tx.execute_batch(SCHEMA_V1)?;
                tx.pragma_update(None, "user_version", SCHEMA_VERSION)?;
            }
            SCHEMA_VERSION => {}
            found => return Err(HighscoreError::SchemaVersion { found, supported: SCHEMA_VERSION }),
        }
        for b in builtin_benchmarks() {
            tx.execute(
                "INSERT OR IGNORE INTO benchmarks (id, kind, target, description) VALUES (?1, ?2, ?3, ?4)",
                params![b.id, b.kind.as_str(), b.target, b.description],
            )?;
        }
        tx.commit()?;
        Ok(Self { conn })
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
        let mut stmt = self.conn.prepare(
            "SELECT b.id, b.kind, b.target, b.description,
                (SELECT COUNT(DISTINCT submission_id) FROM grasp_cells g WHERE g.benchmark_id = b.id)
              + (SELECT COUNT(DISTINCT submission_id) FROM motion_runs m WHERE m.benchmark_id = b.id)
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

    /// Stores a validated submission in one transaction (all of it or nothing).
    ///
    /// # Errors
    /// [`HighscoreError::UnknownBenchmark`] if a cell's hand or a run's scene is not a
    /// benchmark of the board, [`HighscoreError::Database`] if SQLite fails.
    pub fn insert(&mut self, submission: &Submission) -> Result<SubmissionId> {
        let known: BTreeMap<String, BenchmarkKind> = self.benchmarks()?.into_iter().map(|b| (b.id, b.kind)).collect();
        let tx = self.conn.transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)?;
        let r = &submission.results;
        let p = &r.provenance;
        let provenance = serde_json::to_string(p).unwrap_or_else(|_| "null".into());
        tx.execute(
            "INSERT INTO submissions (submitter, team, suite_version, suite_size, opengrasp_version, git_commit,
                started_at, grasp_seed, motion_seed, provenance, results)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)",
            params![
                submission.submitter.name,
                submission.submitter.team,
                p.suite_version,
                p.suite_size,
                p.opengrasp_version,
                p.git_commit,
                p.started_at,
                r.grasp.as_ref().map(|g| g.seed.to_string()),
                r.motion.as_ref().map(|m| m.options.seed.to_string()),
                provenance,
                submission.raw,
            ],
        )?;
        let id = tx.last_insert_rowid();
        let planners = r
            .grasp
            .iter()
            .flat_map(|g| g.planners.iter().map(|p| (BenchmarkKind::Grasp, p)))
            .chain(r.motion.iter().flat_map(|m| m.planners.iter().map(|p| (BenchmarkKind::Motion, p))));
        for (kind, pl) in planners {
            tx.execute(
                "INSERT INTO submission_planners (submission_id, kind, name, parameters) VALUES (?1, ?2, ?3, ?4)",
                params![id, kind.as_str(), pl.name, pl.parameters],
            )?;
        }
        if let Some(g) = &r.grasp {
            insert_cells(&tx, id, &g.cells, &known)?;
        }
        if let Some(m) = &r.motion {
            insert_runs(&tx, id, &m.runs, &known)?;
        }
        tx.commit()?;
        Ok(SubmissionId(id))
    }

    /// The uploaded file of a submission, verbatim.
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
        let mut stmt = self.conn.prepare(
            "SELECT benchmark_id FROM grasp_cells WHERE submission_id = ?1
             UNION SELECT benchmark_id FROM motion_runs WHERE submission_id = ?1 ORDER BY 1",
        )?;
        let rows = stmt.query_map([id.0], |r| r.get(0))?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// The ranking of one benchmark (see [`GRASP_RULES`] and [`MOTION_RULES`]).
    ///
    /// # Errors
    /// [`HighscoreError::UnknownBenchmark`] if `benchmark` is not on the board,
    /// [`HighscoreError::Database`] if SQLite fails.
    pub fn ranking(&self, benchmark: &str) -> Result<Ranking> {
        let info = self.benchmark(benchmark)?;
        let mut entries = match info.kind {
            BenchmarkKind::Grasp => self.grasp_entries(&info.id)?,
            BenchmarkKind::Motion => self.motion_entries(&info.id)?,
        };
        // Runs of different suite sizes are not comparable: each size is its own league.
        entries.sort_by(|a, b| {
            suite_size_order(&a.suite_size)
                .cmp(&suite_size_order(&b.suite_size))
                .then_with(|| a.suite_size.cmp(&b.suite_size))
                .then(a.metrics.compare(&b.metrics))
                .then(a.submission.cmp(&b.submission))
        });
        let mut league_start = 0;
        for i in 0..entries.len() {
            if i > 0 && entries[i].suite_size != entries[i - 1].suite_size {
                league_start = i;
            }
            entries[i].rank = if i > league_start && entries[i].metrics.compare(&entries[i - 1].metrics).is_eq() {
                entries[i - 1].rank
            } else {
                i - league_start + 1
            };
        }
        let rules = match info.kind {
            BenchmarkKind::Grasp => GRASP_RULES,
            BenchmarkKind::Motion => MOTION_RULES,
        };
        Ok(Ranking { benchmark: info, rules: rules.to_string(), entries })
    }

    /// Rankings of every benchmark, ordered by id.
    ///
    /// # Errors
    /// As [`Store::ranking`].
    pub fn rankings(&self) -> Result<Vec<Ranking>> {
        self.benchmarks()?.iter().map(|b| self.ranking(&b.id)).collect()
    }

    fn entry_head(
        &self,
        submission: i64,
        kind: BenchmarkKind,
        planner: String,
        metrics: EntryMetrics,
    ) -> Result<RankedEntry> {
        type Head = (String, String, Option<String>, Option<String>, String, String);
        let (submitted_at, submitter, team, seed, version, suite_size): Head = self.conn.query_row(
            &format!(
                "SELECT submitted_at, submitter, team, {}_seed, opengrasp_version, suite_size FROM submissions WHERE id = ?1",
                kind.as_str()
            ),
            [submission],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?, r.get(5)?)),
        )?;
        let parameters: Option<String> = self
            .conn
            .query_row(
                "SELECT parameters FROM submission_planners WHERE submission_id = ?1 AND kind = ?2 AND name = ?3",
                params![submission, kind.as_str(), planner],
                |r| r.get(0),
            )
            .optional()?;
        Ok(RankedEntry {
            rank: 0,
            submission: SubmissionId(submission),
            submitted_at,
            submitter,
            team,
            planner,
            parameters,
            seed: seed.and_then(|s| s.parse().ok()),
            version,
            suite_size,
            metrics,
        })
    }

    fn grasp_entries(&self, benchmark: &str) -> Result<Vec<RankedEntry>> {
        let mut stmt = self.conn.prepare(
            "SELECT submission_id, planner, COUNT(DISTINCT object), SUM(evaluated), SUM(palm_contact),
                    SUM(force_closure_palm), SUM(mean_epsilon * force_closure_palm)
             FROM grasp_cells WHERE benchmark_id = ?1 GROUP BY submission_id, planner",
        )?;
        let rows = stmt
            .query_map([benchmark], |r| {
                Ok((
                    r.get::<_, i64>(0)?,
                    r.get::<_, String>(1)?,
                    r.get::<_, i64>(2)?,
                    r.get::<_, i64>(3)?,
                    r.get::<_, i64>(4)?,
                    r.get::<_, i64>(5)?,
                    r.get::<_, f64>(6)?,
                ))
            })?
            .collect::<rusqlite::Result<Vec<_>>>()?;
        let mut out = Vec::with_capacity(rows.len());
        for (sub, planner, objects, evaluated, palm, fc_palm, eps_sum) in rows {
            let metrics = EntryMetrics::Grasp {
                objects: objects.max(0) as u64,
                evaluated: evaluated.max(0) as u64,
                palm_contact: palm.max(0) as u64,
                force_closure_palm: fc_palm.max(0) as u64,
                fc_percent: if palm > 0 { 100.0 * fc_palm as f64 / palm as f64 } else { 0.0 },
                mean_epsilon: if fc_palm > 0 { eps_sum / fc_palm as f64 } else { 0.0 },
            };
            out.push(self.entry_head(sub, BenchmarkKind::Grasp, planner, metrics)?);
        }
        Ok(out)
    }

    fn motion_entries(&self, benchmark: &str) -> Result<Vec<RankedEntry>> {
        let mut stmt = self.conn.prepare(
            "SELECT submission_id, planner, status, planning_time, processed_strict, processed_continuous
             FROM motion_runs WHERE benchmark_id = ?1 ORDER BY submission_id, planner",
        )?;
        type Row = (i64, String, String, f64, Option<bool>, Option<bool>);
        let rows = stmt
            .query_map([benchmark], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?, r.get(5)?)))?
            .collect::<rusqlite::Result<Vec<Row>>>()?;
        let mut groups: BTreeMap<(i64, String), Vec<Row>> = BTreeMap::new();
        for row in rows {
            groups.entry((row.0, row.1.clone())).or_default().push(row);
        }
        let mut out = Vec::with_capacity(groups.len());
        for ((sub, planner), runs) in groups {
            let solved: Vec<&Row> = runs.iter().filter(|r| r.2 == "solved").collect();
            let mut times: Vec<f64> = solved.iter().map(|r| r.3).collect();
            times.sort_by(f64::total_cmp);
            let median = match times.len() {
                0 => None,
                n if n % 2 == 1 => Some(times[n / 2]),
                n => Some(0.5 * (times[n / 2 - 1] + times[n / 2])),
            };
            let valid = solved.iter().filter(|r| r.4 == Some(true) && r.5 != Some(false)).count();
            let pct = |a: usize, b: usize| if b == 0 { 0.0 } else { 100.0 * a as f64 / b as f64 };
            let metrics = EntryMetrics::Motion {
                runs: runs.len() as u64,
                solved: solved.len() as u64,
                success_rate: pct(solved.len(), runs.len()),
                median_planning_time: median,
                valid_processed: pct(valid, solved.len()),
            };
            out.push(self.entry_head(sub, BenchmarkKind::Motion, planner, metrics)?);
        }
        Ok(out)
    }
}

/// `<kind>/<slug(target)>` of a user-given benchmark id, if it has a known kind.
fn canonical_id(id: &str) -> Option<String> {
    let (kind, target) = id.split_once('/')?;
    let kind = BenchmarkKind::parse(kind.trim())?;
    Some(format!("{}/{}", kind.as_str(), slug(target)))
}

fn benchmark_of(kind: BenchmarkKind, target: &str, known: &BTreeMap<String, BenchmarkKind>) -> Result<String> {
    let id = format!("{}/{}", kind.as_str(), slug(target));
    match known.get(&id) {
        Some(k) if *k == kind => Ok(id),
        _ => Err(HighscoreError::UnknownBenchmark { id }),
    }
}

fn int(v: usize) -> i64 {
    i64::try_from(v).unwrap_or(i64::MAX)
}

fn insert_cells(
    tx: &Transaction<'_>,
    id: i64,
    cells: &[opengrasp_bench::results::GraspRecord],
    known: &BTreeMap<String, BenchmarkKind>,
) -> Result<()> {
    let mut stmt = tx.prepare(
        "INSERT INTO grasp_cells (submission_id, benchmark_id, planner, hand, object, seed, generated,
            evaluated, closed, palm_contact, force_closure_palm, force_closure, mean_epsilon, median_epsilon,
            physics_tested, physics_held, planning_seconds, evaluation_seconds)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18)",
    )?;
    for rec in cells {
        let c = &rec.cell;
        let bench = benchmark_of(BenchmarkKind::Grasp, &c.hand, known)?;
        stmt.execute(params![
            id,
            bench,
            c.planner,
            c.hand,
            c.object,
            rec.seed.to_string(),
            int(c.generated),
            int(c.evaluated),
            int(c.closed),
            int(c.palm_contact),
            int(c.force_closure_palm),
            int(c.force_closure),
            c.mean_epsilon,
            c.median_epsilon,
            int(c.physics_tested),
            int(c.physics_held),
            c.planning_seconds,
            c.evaluation_seconds,
        ])?;
    }
    Ok(())
}

fn insert_runs(
    tx: &Transaction<'_>,
    id: i64,
    runs: &[opengrasp_motion::benchmark::RunRecord],
    known: &BTreeMap<String, BenchmarkKind>,
) -> Result<()> {
    use opengrasp_motion::benchmark::RunStatus;
    let mut stmt = tx.prepare(
        "INSERT INTO motion_runs (submission_id, benchmark_id, planner, scene, run, seed, status, setup_time,
            planning_time, postprocessing_time, processed_discrete, processed_strict, processed_continuous,
            processed_length, planned_strict)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15)",
    )?;
    for r in runs {
        let bench = benchmark_of(BenchmarkKind::Motion, &r.scene, known)?;
        let status = match r.status {
            RunStatus::Solved => "solved",
            RunStatus::Timeout => "timeout",
            RunStatus::InvalidInput => "invalid_input",
            RunStatus::Error => "error",
        };
        let processed = r.processed.as_ref();
        stmt.execute(params![
            id,
            bench,
            r.planner,
            r.scene,
            int(r.run),
            r.seed.to_string(),
            status,
            r.setup_time,
            r.planning_time,
            r.postprocessing_time,
            processed.map(|p| p.validity.discrete),
            processed.map(|p| p.validity.strict),
            processed.and_then(|p| p.validity.continuous),
            processed.map(|p| p.metrics.length),
            r.planned.as_ref().map(|p| p.validity.strict),
        ])?;
    }
    Ok(())
}

/// League order of suite sizes on a ranking: the paper-sized suite first, then the default,
/// custom and tiny ones, then any other name.
fn suite_size_order(size: &str) -> u8 {
    match size {
        "paper" => 0,
        "default" => 1,
        "custom" => 2,
        "tiny" => 3,
        _ => 4,
    }
}
