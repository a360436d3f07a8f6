//! Merging the results files of a sharded run (`opengrasp run --shard K/N`) into the file an
//! unsharded run gives: the same records in the same order, summaries recomputed from the runs,
//! and the shards' provenance kept.

use opengrasp_motion::benchmark::{RunRecord, Summary};

use super::{invalid, GraspSection, MotionSection, ResultsFile};
use crate::error::Result;

/// Merges the files of shards `0..N` of one suite run (any order) into one results file.
///
/// Every shard must come from the same suite (suite version and size, seeds, hands, objects,
/// planners, scenes and motion options) and the set must be complete: shards `0..N` of the same
/// `N`, each once. The merged records are in the order an unsharded run writes them (grasp
/// cells by hand, object and planner; motion runs by scene, planner and run; episodes by
/// planner and index) and the motion summaries are recomputed, so the merged file equals the
/// unsharded one except for timing fields and provenance, which lists the shards.
///
/// # Errors
/// [`crate::Error::Invalid`] naming the first inconsistency (no files, an unsharded file,
/// shards of different suites, a missing or repeated shard).
pub fn merge(files: Vec<ResultsFile>) -> Result<ResultsFile> {
    let Some(first) = files.first() else {
        return Err(invalid("shards", "no results files to merge"));
    };
    let count = shard_of(first, 0)?.count;
    let mut by_index: Vec<Option<ResultsFile>> = vec![None; count];
    for (i, file) in files.into_iter().enumerate() {
        let shard = shard_of(&file, i)?;
        if shard.count != count {
            return Err(invalid(
                format!("shards[{i}]"),
                format!("shard of {}, the first file is of {count}", shard.count),
            ));
        }
        if by_index[shard.index].is_some() {
            return Err(invalid(format!("shards[{i}]"), format!("shard {}/{count} given twice", shard.index)));
        }
        by_index[shard.index] = Some(file);
    }
    let missing: Vec<usize> = (0..count).filter(|&k| by_index[k].is_none()).collect();
    if !missing.is_empty() {
        return Err(invalid("shards", format!("shards {missing:?} of {count} are missing")));
    }
    let shards: Vec<ResultsFile> = by_index.into_iter().flatten().collect();
    let base = &shards[0];
    for (k, s) in shards.iter().enumerate().skip(1) {
        let (p, q) = (&base.provenance, &s.provenance);
        if (&p.suite_version, &p.suite_size) != (&q.suite_version, &q.suite_size) {
            return Err(invalid(format!("shard {k}"), "from another suite version or size"));
        }
        if base.grasp.as_ref().map(grasp_setup) != s.grasp.as_ref().map(grasp_setup) {
            return Err(invalid(format!("shard {k}"), "grasp setup differs (seed, hands, objects, planners)"));
        }
        if base.motion.as_ref().map(motion_setup) != s.motion.as_ref().map(motion_setup) {
            return Err(invalid(format!("shard {k}"), "motion setup differs (options, scenes, planners)"));
        }
    }
    let mut provenance = base.provenance.clone();
    provenance.shard = None;
    provenance.started_at = shards.iter().map(|s| s.provenance.started_at.clone()).min().unwrap_or_default();
    provenance.finished_at = shards.iter().map(|s| s.provenance.finished_at.clone()).max().unwrap_or_default();
    // Shards run side by side: the sweep took as long as its slowest shard.
    provenance.wall_seconds = shards.iter().map(|s| s.provenance.wall_seconds).fold(0.0, f64::max);
    provenance.merged_from = shards.iter().map(|s| s.provenance.clone()).collect();
    let mut merged = ResultsFile::new(provenance);
    merged.grasp = base.grasp.as_ref().map(|g| merge_grasp(g, &shards));
    merged.motion = base.motion.as_ref().map(|m| merge_motion(m, &shards));
    merged.validate()?;
    Ok(merged)
}

fn shard_of(file: &ResultsFile, i: usize) -> Result<super::Shard> {
    file.provenance
        .shard
        .ok_or_else(|| invalid(format!("shards[{i}].provenance.shard"), "not the file of a sharded run"))
}

fn grasp_setup(g: &GraspSection) -> GraspSection {
    GraspSection { cells: Vec::new(), ..g.clone() }
}

fn motion_setup(m: &MotionSection) -> MotionSection {
    MotionSection { runs: Vec::new(), summaries: Vec::new(), episodes: Vec::new(), ..m.clone() }
}

fn position(names: &[String], name: &str) -> usize {
    names.iter().position(|n| n == name).unwrap_or(usize::MAX)
}

fn merge_grasp(base: &GraspSection, shards: &[ResultsFile]) -> GraspSection {
    let planners: Vec<String> = base.planners.iter().map(|p| p.name.clone()).collect();
    let mut cells: Vec<_> = shards.iter().filter_map(|s| s.grasp.as_ref()).flat_map(|g| g.cells.clone()).collect();
    cells.sort_by_key(|r| {
        let c = &r.cell;
        (position(&base.hands, &c.hand), position(&base.objects, &c.object), position(&planners, &c.planner))
    });
    GraspSection { cells, ..base.clone() }
}

fn merge_motion(base: &MotionSection, shards: &[ResultsFile]) -> MotionSection {
    let planners: Vec<String> = base.planners.iter().map(|p| p.name.clone()).collect();
    let sections: Vec<&MotionSection> = shards.iter().filter_map(|s| s.motion.as_ref()).collect();
    let mut runs: Vec<RunRecord> = sections.iter().flat_map(|m| m.runs.clone()).collect();
    runs.sort_by_key(|r| (position(&base.scenes, &r.scene), position(&planners, &r.planner), r.run));
    let mut episodes: Vec<_> = sections.iter().flat_map(|m| m.episodes.clone()).collect();
    episodes.sort_by_key(|e| (position(&planners, &e.planner), e.index));
    // As the suite summarises: every scene × planner pair that ran, scenes then planners in
    // the section's order.
    let mut summaries = Vec::new();
    for scene in &base.scenes {
        for planner in &planners {
            let records: Vec<&RunRecord> = runs.iter().filter(|r| &r.scene == scene && &r.planner == planner).collect();
            if !records.is_empty() {
                summaries.push(Summary::from_records(planner, scene, &records));
            }
        }
    }
    MotionSection { runs, summaries, episodes, ..base.clone() }
}
