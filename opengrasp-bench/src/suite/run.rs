//! Running a suite: grasp cells and motion runs as parallel, seeded jobs collected in job
//! order, and Clean the Table episodes.

use std::sync::atomic::{AtomicUsize, Ordering};

use crate::clean_table::{clean_the_table, CleanTheTableOptions, EpisodeTotals, TABLE_OBJECTS};
use opengrasp_core::hand::Hand;
use opengrasp_core::object::ObjectModel;
use opengrasp_grasp::benchmark::{run_grasp_benchmark_with, GraspBenchmarkConfig};
use opengrasp_grasp::planners::GraspPlanner;
use opengrasp_motion::benchmark::{run_benchmark, BenchmarkOptions, BenchmarkScene, RunRecord, RunStatus, Summary};
use rayon::prelude::*;

use crate::results::{Category, EpisodeRecord, GraspRecord, GraspSection, MotionSection, Result};

use super::{MotionEntry, Progress, Suite, CLEAN_THE_TABLE_SCENE};

impl Suite {
    /// The jobs of this suite's shard (all of them when unsharded), in job order.
    fn owned<T>(&self, jobs: Vec<T>) -> Vec<T> {
        match self.shard {
            None => jobs,
            Some(shard) => jobs.into_iter().enumerate().filter(|(i, _)| shard.owns(*i)).map(|(_, j)| j).collect(),
        }
    }

    pub(super) fn report(&self, category: Category, done: &AtomicUsize, add: usize, total: usize, label: String) {
        let done = done.fetch_add(add, Ordering::Relaxed) + add;
        if let Some(f) = &self.progress {
            f(&Progress { category, done, total, label });
        }
    }

    pub(super) fn run_grasp(&self) -> Result<GraspSection> {
        let jobs: Vec<(&Hand, &ObjectModel)> =
            self.owned(self.grasp.hands.iter().flat_map(|h| self.grasp.objects.iter().map(move |o| (h, o))).collect());
        let planners: Vec<&dyn GraspPlanner> = self.grasp_planners.iter().map(|p| &*p.planner).collect();
        let done = AtomicUsize::new(0);
        let run_job = |&(hand, object): &(&Hand, &ObjectModel)| -> Result<Vec<GraspRecord>> {
            let config =
                GraspBenchmarkConfig { hands: vec![hand.clone()], objects: vec![object.clone()], ..self.grasp.clone() };
            let results = run_grasp_benchmark_with(&config, &planners)?;
            self.report(Category::Grasp, &done, 1, jobs.len(), format!("{}/{}", hand.name(), object.name));
            Ok(results.cells.into_iter().map(|cell| GraspRecord { seed: config.seed, cell }).collect())
        };
        let per_job: Vec<Result<Vec<GraspRecord>>> =
            if self.jobs == 1 { jobs.iter().map(run_job).collect() } else { jobs.par_iter().map(run_job).collect() };
        let mut cells = Vec::new();
        for r in per_job {
            cells.extend(r?);
        }
        Ok(GraspSection {
            seed: self.grasp.seed,
            hands: self.grasp.hands.iter().map(|h| h.name().to_string()).collect(),
            objects: self.grasp.objects.iter().map(|o| o.name.clone()).collect(),
            max_candidates: self.grasp.max_candidates,
            planners: self.grasp_planners.iter().map(|p| p.info.clone()).collect(),
            cells,
        })
    }

    pub(super) fn run_motion(&self) -> MotionSection {
        let admits =
            |p: &MotionEntry, scene: &str| p.scenes.as_ref().is_none_or(|names| names.iter().any(|n| n == scene));
        let pairs: Vec<(&BenchmarkScene, &MotionEntry)> = self
            .motion_scenes
            .iter()
            .flat_map(|s| self.motion_planners.iter().filter(|p| admits(p, &s.name)).map(move |p| (s, p)))
            .collect();
        let table_planners: Vec<&MotionEntry> = if self.episodes == 0 {
            Vec::new()
        } else {
            self.motion_planners.iter().filter(|p| admits(p, CLEAN_THE_TABLE_SCENE)).collect()
        };
        // Shared environments: all runs of a pair in one job (the planner's setup, e.g. a PRM
        // roadmap, is reused across them). Otherwise setup runs per run anyway, so every run
        // is its own job with a fresh planner. Each Clean the Table episode is a job of its
        // own. The split never depends on `jobs`.
        let runs = self.motion.runs;
        let mut jobs: Vec<MotionJob> = pairs
            .iter()
            .enumerate()
            .flat_map(|(k, (scene, _))| {
                let ranges: Vec<std::ops::Range<usize>> = if scene.shared_environment {
                    std::iter::once(0..runs).collect()
                } else {
                    (0..runs).map(|r| r..r + 1).collect()
                };
                ranges.into_iter().filter(|r| !r.is_empty()).map(move |r| MotionJob::Scene(k, r))
            })
            .collect();
        for p in 0..table_planners.len() {
            jobs.extend((0..self.episodes).map(|e| MotionJob::Episode(p, e)));
        }
        let jobs = self.owned(jobs);
        let total = jobs
            .iter()
            .map(|j| match j {
                MotionJob::Scene(_, range) => range.len(),
                MotionJob::Episode(..) => 2 * TABLE_OBJECTS.len(),
            })
            .sum();
        let done = AtomicUsize::new(0);
        let run_job = |job: &MotionJob| -> (Vec<RunRecord>, Option<EpisodeRecord>) {
            match job {
                MotionJob::Scene(k, range) => {
                    let (scene, entry) = pairs[*k];
                    let options = BenchmarkOptions {
                        runs: range.len(),
                        seed: self.motion.seed.wrapping_add(range.start as u64),
                        ..self.motion.clone()
                    };
                    let mut planners = vec![(entry.factory)(&scene.name)];
                    let mut report = run_benchmark(&mut planners, std::slice::from_ref(scene), &options);
                    for r in &mut report.runs {
                        r.run += range.start;
                    }
                    let label = format!("{} on {}", entry.info.name, scene.name);
                    self.report(Category::Motion, &done, range.len(), total, label);
                    (report.runs, None)
                }
                MotionJob::Episode(p, index) => {
                    let entry = table_planners[*p];
                    let (runs, episode) = self.run_episode(entry, *index);
                    let label = format!("{} on {CLEAN_THE_TABLE_SCENE} #{index}", entry.info.name);
                    self.report(Category::Motion, &done, 2 * TABLE_OBJECTS.len(), total, label);
                    (runs, Some(episode))
                }
            }
        };
        let per_job: Vec<(Vec<RunRecord>, Option<EpisodeRecord>)> =
            if self.jobs == 1 { jobs.iter().map(run_job).collect() } else { jobs.par_iter().map(run_job).collect() };
        let mut all: Vec<RunRecord> = Vec::new();
        let mut episodes = Vec::new();
        for (runs, episode) in per_job {
            all.extend(runs);
            episodes.extend(episode);
        }
        let summaries: Vec<Summary> = pairs
            .iter()
            .map(|(scene, entry)| (scene.name.as_str(), *entry))
            .chain(table_planners.iter().map(|entry| (CLEAN_THE_TABLE_SCENE, *entry)))
            .filter_map(|(scene, entry)| {
                let records: Vec<&RunRecord> =
                    all.iter().filter(|r| r.scene == scene && r.planner == entry.info.name).collect();
                // A shard summarises only the pairs it ran.
                (self.shard.is_none() || !records.is_empty())
                    .then(|| Summary::from_records(&entry.info.name, scene, &records))
            })
            .collect();
        MotionSection {
            options: self.motion.clone(),
            scenes: self.scene_names(),
            planners: self.motion_planners.iter().map(|p| p.info.clone()).collect(),
            runs: all,
            summaries,
            episodes,
        }
    }

    /// Runs Clean the Table episode `index` (seed `motion seed + index`) with a fresh planner.
    /// Its queries become runs `index · 2 · objects + query` of [`CLEAN_THE_TABLE_SCENE`].
    pub(super) fn run_episode(&self, entry: &MotionEntry, index: usize) -> (Vec<RunRecord>, EpisodeRecord) {
        let seed = self.motion.seed.wrapping_add(index as u64);
        let queries = 2 * TABLE_OBJECTS.len();
        let mut planner = (entry.factory)(CLEAN_THE_TABLE_SCENE);
        let options = CleanTheTableOptions {
            objects: TABLE_OBJECTS.len(),
            seed,
            benchmark: BenchmarkOptions { runs: 1, seed, ..self.motion.clone() },
        };
        let mut episode = EpisodeRecord {
            planner: entry.info.name.clone(),
            index,
            seed,
            objects: TABLE_OBJECTS.iter().map(|o| o.to_string()).collect(),
            totals: EpisodeTotals { all_valid: false, ..EpisodeTotals::empty() },
            error: None,
        };
        match clean_the_table(planner.as_mut(), &options) {
            Ok(report) => {
                let mut runs = Vec::with_capacity(queries);
                for object in report.objects {
                    runs.push(object.grasp);
                    runs.extend(object.place);
                }
                for r in &mut runs {
                    r.scene = CLEAN_THE_TABLE_SCENE.to_string();
                    r.planner = entry.info.name.clone();
                    r.run += index * queries;
                }
                episode.totals = report.totals;
                (runs, episode)
            }
            Err(e) => {
                let mut run = RunRecord::unfinished(
                    &entry.info.name,
                    CLEAN_THE_TABLE_SCENE,
                    index * queries,
                    seed,
                    RunStatus::Error,
                    0.0,
                );
                run.message = Some(e.to_string());
                episode.error = Some(e.to_string());
                (vec![run], episode)
            }
        }
    }
}

/// A unit of parallel motion work.
enum MotionJob {
    /// Runs `range` of scene × planner pair `k`.
    Scene(usize, std::ops::Range<usize>),
    /// Clean the Table episode `index` of Clean the Table planner `p`.
    Episode(usize, usize),
}
