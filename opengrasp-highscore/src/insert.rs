//! Writing one submission inside an open transaction (see [`Store::insert_submission`] and
//! [`Store::insert_batch`](crate::Store::insert_batch)).

use std::collections::BTreeMap;

use rusqlite::{params, Connection, OptionalExtension};

use super::error::{HighscoreError, Result};
use super::{rank, slug, BenchmarkKind, Inserted, Submission, SubmissionId};

/// Writes `submission` on `conn` (inside a transaction or savepoint the caller commits); a
/// submission whose results the same submitter already stored returns the earlier id.
pub(crate) fn insert_in(conn: &Connection, submission: &Submission) -> Result<Inserted> {
    let existing: Option<(i64, String, Option<String>)> = conn
        .query_row(
            "SELECT id, submitter, team FROM submissions WHERE content_hash = ?1",
            [&submission.content_hash],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
        )
        .optional()?;
    if let Some((id, name, team)) = existing {
        return if name == submission.submitter.name && team == submission.submitter.team {
            Ok(Inserted { id: SubmissionId(id), duplicate: true })
        } else {
            Err(HighscoreError::Duplicate { id })
        };
    }
    let known: BTreeMap<String, BenchmarkKind> = {
        let mut stmt = conn.prepare_cached("SELECT id, kind FROM benchmarks")?;
        let rows = stmt.query_map([], |r| Ok((r.get::<_, String>(0)?, r.get::<_, String>(1)?)))?;
        rows.filter_map(|r| r.ok()).filter_map(|(id, kind)| BenchmarkKind::parse(&kind).map(|k| (id, k))).collect()
    };
    let r = &submission.results;
    let p = &r.provenance;
    let provenance = serde_json::to_string(p).unwrap_or_else(|_| "null".into());
    conn.execute(
        "INSERT INTO submissions (submitter, team, suite_version, suite_size, opengrasp_version, git_commit,
                started_at, grasp_seed, motion_seed, provenance, results, content_hash)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)",
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
            submission.content_hash,
        ],
    )?;
    let id = conn.last_insert_rowid();
    let planners = r
        .grasp
        .iter()
        .flat_map(|g| g.planners.iter().map(|p| (BenchmarkKind::Grasp, p)))
        .chain(r.motion.iter().flat_map(|m| m.planners.iter().map(|p| (BenchmarkKind::Motion, p))));
    for (kind, pl) in planners {
        conn.execute(
            "INSERT INTO submission_planners (submission_id, kind, name, parameters) VALUES (?1, ?2, ?3, ?4)",
            params![id, kind.as_str(), pl.name, pl.parameters],
        )?;
    }
    if let Some(g) = &r.grasp {
        insert_cells(conn, id, &g.cells, &known)?;
    }
    if let Some(m) = &r.motion {
        insert_runs(conn, id, &m.runs, &known)?;
    }
    rank::store_entries(conn, id)?;
    Ok(Inserted { id: SubmissionId(id), duplicate: false })
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
    conn: &Connection,
    id: i64,
    cells: &[opengrasp_bench::results::GraspRecord],
    known: &BTreeMap<String, BenchmarkKind>,
) -> Result<()> {
    let mut stmt = conn.prepare(
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
    conn: &Connection,
    id: i64,
    runs: &[opengrasp_motion::benchmark::RunRecord],
    known: &BTreeMap<String, BenchmarkKind>,
) -> Result<()> {
    use opengrasp_motion::benchmark::RunStatus;
    let mut stmt = conn.prepare(
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
