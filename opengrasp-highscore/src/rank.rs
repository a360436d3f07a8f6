//! Ranked entries: computed once per stored submission (`entries` table), ranked per query.

use std::collections::BTreeMap;

use rusqlite::{params, Connection};

use super::error::Result;
use super::{BenchmarkInfo, BenchmarkKind, EntryMetrics, RankedEntry, SubmissionId};

/// Computes the entries (one per benchmark × planner) of submission `id` from its cell and
/// run rows and stores them.
pub(crate) fn store_entries(conn: &Connection, id: i64) -> Result<()> {
    let mut out: Vec<(String, String, EntryMetrics)> = Vec::new();
    {
        let mut stmt = conn.prepare_cached(
            "SELECT benchmark_id, planner, COUNT(DISTINCT object), SUM(evaluated), SUM(palm_contact),
                    SUM(force_closure_palm), SUM(mean_epsilon * force_closure_palm)
             FROM grasp_cells WHERE submission_id = ?1 GROUP BY benchmark_id, planner",
        )?;
        let rows = stmt.query_map([id], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, i64>(2)?,
                r.get::<_, i64>(3)?,
                r.get::<_, i64>(4)?,
                r.get::<_, i64>(5)?,
                r.get::<_, f64>(6)?,
            ))
        })?;
        for row in rows {
            let (bench, planner, objects, evaluated, palm, fc_palm, eps_sum) = row?;
            let metrics = EntryMetrics::Grasp {
                objects: objects.max(0) as u64,
                evaluated: evaluated.max(0) as u64,
                palm_contact: palm.max(0) as u64,
                force_closure_palm: fc_palm.max(0) as u64,
                fc_percent: if palm > 0 { 100.0 * fc_palm as f64 / palm as f64 } else { 0.0 },
                mean_epsilon: if fc_palm > 0 { eps_sum / fc_palm as f64 } else { 0.0 },
            };
            out.push((bench, planner, metrics));
        }
    }
    {
        let mut stmt = conn.prepare_cached(
            "SELECT benchmark_id, planner, status, planning_time, processed_strict, processed_continuous
             FROM motion_runs WHERE submission_id = ?1",
        )?;
        let rows = stmt
            .query_map([id], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?, r.get(5)?)))?
            .collect::<rusqlite::Result<Vec<RunRow>>>()?;
        let mut groups: BTreeMap<(String, String), Vec<RunRow>> = BTreeMap::new();
        for row in rows {
            groups.entry((row.0.clone(), row.1.clone())).or_default().push(row);
        }
        for ((bench, planner), runs) in groups {
            out.push((bench, planner, motion_metrics(&runs)));
        }
    }
    let mut insert = conn.prepare_cached(
        "INSERT INTO entries (submission_id, benchmark_id, planner, metrics) VALUES (?1, ?2, ?3, ?4)",
    )?;
    for (bench, planner, metrics) in out {
        let json = serde_json::to_string(&metrics).unwrap_or_default();
        insert.execute(params![id, bench, planner, json])?;
    }
    Ok(())
}

/// A motion run row: benchmark, planner, status, planning time, processed strict and continuous.
type RunRow = (String, String, String, f64, Option<bool>, Option<bool>);

fn motion_metrics(runs: &[RunRow]) -> EntryMetrics {
    let solved: Vec<_> = runs.iter().filter(|r| r.2 == "solved").collect();
    let mut times: Vec<f64> = solved.iter().map(|r| r.3).collect();
    times.sort_by(f64::total_cmp);
    let median = match times.len() {
        0 => None,
        n if n % 2 == 1 => Some(times[n / 2]),
        n => Some(0.5 * (times[n / 2 - 1] + times[n / 2])),
    };
    let valid = solved.iter().filter(|r| r.4 == Some(true) && r.5 != Some(false)).count();
    let pct = |a: usize, b: usize| if b == 0 { 0.0 } else { 100.0 * a as f64 / b as f64 };
    EntryMetrics::Motion {
        runs: runs.len() as u64,
        solved: solved.len() as u64,
        success_rate: pct(solved.len(), runs.len()),
        median_planning_time: median,
        valid_processed: pct(valid, solved.len()),
    }
}

/// Every entry of a benchmark, ranked: one query joining entries, submissions and planners.
pub(crate) fn ranked_entries(conn: &Connection, info: &BenchmarkInfo) -> Result<Vec<RankedEntry>> {
    let seed = match info.kind {
        BenchmarkKind::Grasp => "s.grasp_seed",
        BenchmarkKind::Motion => "s.motion_seed",
    };
    let mut stmt = conn.prepare_cached(&format!(
        "SELECT e.submission_id, e.planner, e.metrics, s.submitted_at, s.submitter, s.team, {seed},
                s.opengrasp_version, s.suite_size,
                (SELECT p.parameters FROM submission_planners p
                  WHERE p.submission_id = e.submission_id AND p.kind = ?2 AND p.name = e.planner LIMIT 1)
         FROM entries e JOIN submissions s ON s.id = e.submission_id
         WHERE e.benchmark_id = ?1"
    ))?;
    let rows = stmt.query_map(params![info.id, info.kind.as_str()], |r| {
        let metrics: String = r.get(2)?;
        let seed: Option<String> = r.get(6)?;
        Ok((
            metrics,
            RankedEntry {
                rank: 0,
                submission: SubmissionId(r.get(0)?),
                submitted_at: r.get(3)?,
                submitter: r.get(4)?,
                team: r.get(5)?,
                planner: r.get(1)?,
                parameters: r.get(9)?,
                seed: seed.and_then(|s| s.parse().ok()),
                version: r.get(7)?,
                suite_size: r.get(8)?,
                metrics: EntryMetrics::Motion {
                    runs: 0,
                    solved: 0,
                    success_rate: 0.0,
                    median_planning_time: None,
                    valid_processed: 0.0,
                },
            },
        ))
    })?;
    let mut entries = Vec::new();
    for row in rows {
        let (metrics, mut entry) = row?;
        match serde_json::from_str(&metrics) {
            Ok(m) => entry.metrics = m,
            Err(_) => continue, // unreadable row: not ranked
        }
        entries.push(entry);
    }
    rank(&mut entries);
    Ok(entries)
}

/// Sorts entries by league (suite size), then by the ranking rules, then by submission, and
/// assigns ranks (equal entries share one) within each league.
pub(crate) fn rank(entries: &mut [RankedEntry]) {
    entries.sort_by(|a, b| {
        suite_size_order(&a.suite_size)
            .cmp(&suite_size_order(&b.suite_size))
            .then_with(|| a.suite_size.cmp(&b.suite_size))
            .then(a.metrics.compare(&b.metrics))
            .then(a.submission.cmp(&b.submission))
            .then_with(|| a.planner.cmp(&b.planner))
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
}

/// League order of suite sizes on a ranking: the paper-sized suite first, then the default,
/// custom and tiny ones, then any other name.
pub(crate) fn suite_size_order(size: &str) -> u8 {
    match size {
        "paper" => 0,
        "default" => 1,
        "custom" => 2,
        "tiny" => 3,
        _ => 4,
    }
}
