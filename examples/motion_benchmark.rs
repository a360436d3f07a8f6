//! The motion-planning benchmark of the OpenGRASP paper (section IV-B, Table III): seeded runs
//! of RRT-Connect, PRM and IK-RRT on the standard scene (ARMAR-III-like humanoid in the
//! kitchen, hip yaw + right arm) and the IK-based scene (same robot, seeded random object on
//! the red table), their 7-DoF stand-ins, and "Clean the Table" episodes (four objects carried
//! from the red table to the sideboard over base + hip + arm); prints Table-III-style summaries
//! and writes every run as JSON.
//!
//! ```sh
//! cargo run --release --example motion_benchmark -- [RUNS] [OUTPUT.json]
//! ```
//! `RUNS` (default 100) runs per planner on the ARMAR-III standard scene, a fifth of that (at
//! least 5) on the other scenes; output defaults to `target/motion_benchmark.json`.

use std::time::Instant;

use opengrasp::bench::clean_table::{clean_the_table, CleanTheTableOptions};
use opengrasp::bench::scenes::{armar_ik_scene, armar_standard_scene, ik_scene, standard_scene, CheckerKind};
use opengrasp::motion::benchmark::{run_benchmark, BenchmarkOptions, BenchmarkReport, RunRecord, Summary};
use opengrasp::motion::planners::{IkRrt, Prm, PrmOptions, RrtConnect};
use opengrasp::motion::{MotionPlanner, Result, StateValidityChecker};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Validity checks per second on uniformly random configurations of a scene instance.
fn checker_throughput(scene: &opengrasp::motion::benchmark::BenchmarkScene) -> Result<(f64, f64)> {
    let instance = (scene.generate)(0)?;
    let limits = instance.group.limits(&instance.robot);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let samples: Vec<Vec<f64>> =
        (0..2000).map(|_| limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect()).collect();
    let checker: &dyn StateValidityChecker = &*instance.checker;
    let t = Instant::now();
    let valid = samples.iter().filter(|q| checker.is_valid(q)).count();
    let per_second = samples.len() as f64 / t.elapsed().as_secs_f64();
    Ok((per_second, valid as f64 / samples.len() as f64))
}

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let runs: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(100);
    let output = args.next().unwrap_or_else(|| "target/motion_benchmark.json".to_string());

    let standard = [armar_standard_scene()];
    for scene in [armar_standard_scene(), standard_scene(CheckerKind::Exact)].iter() {
        let (cps, free) = checker_throughput(scene)?;
        println!("{}: {:.0} validity checks/s on random configurations ({:.0} % free)", scene.name, cps, free * 100.0);
    }

    let options = BenchmarkOptions { runs, ..BenchmarkOptions::default() };
    let mut planners: Vec<Box<dyn MotionPlanner>> =
        vec![Box::new(RrtConnect::default()), Box::new(Prm::new(PrmOptions::default()))];
    let t = Instant::now();
    let mut report = run_benchmark(&mut planners, &standard, &options);
    println!("standard scene: {runs} runs per planner in {:.1} s", t.elapsed().as_secs_f64());

    let few = BenchmarkOptions { runs: (runs / 5).max(5), ..BenchmarkOptions::default() };
    let t = Instant::now();
    let stand_in = run_benchmark(&mut planners, &[standard_scene(CheckerKind::Exact)], &few);
    let mut ik_planners: Vec<Box<dyn MotionPlanner>> = vec![
        Box::new(IkRrt::default()),
        Box::new(RrtConnect::default()),
        Box::new(Prm::new(PrmOptions { nodes: 150, ..PrmOptions::default() })),
    ];
    let ik = run_benchmark(&mut ik_planners, &[armar_ik_scene(), ik_scene(CheckerKind::Exact)], &few);
    println!("other scenes: {} runs per planner in {:.1} s\n", few.runs, t.elapsed().as_secs_f64());
    for other in [stand_in, ik] {
        report.runs.extend(other.runs);
        report.summaries.extend(other.summaries);
    }

    // Scene 3: Clean the Table, a few seeded episodes of four objects each.
    let episodes = (runs / 50).max(2) as u64;
    let mut table_planners: Vec<Box<dyn MotionPlanner>> =
        vec![Box::new(RrtConnect::default()), Box::new(IkRrt::default())];
    let mut episode_lines = Vec::new();
    let t = Instant::now();
    for planner in table_planners.iter_mut() {
        let mut records = Vec::new();
        for seed in 0..episodes {
            let episode = clean_the_table(planner.as_mut(), &CleanTheTableOptions { seed, ..Default::default() })?;
            episode_lines.push(format!(
                "  {} seed {seed}: {}/4 objects cleaned, all paths valid: {}, planning {:.1} ms, \
                 post-processing {:.0} ms, C-space length {:.2}, palm path {:.2} m",
                episode.planner,
                episode.totals.cleaned,
                episode.totals.all_valid,
                episode.totals.planning_time * 1e3,
                episode.totals.postprocessing_time * 1e3,
                episode.totals.length,
                episode.totals.ee_length
            ));
            for object in episode.objects {
                records.push(object.grasp);
                records.extend(object.place);
            }
        }
        let refs: Vec<&RunRecord> = records.iter().collect();
        report.summaries.push(Summary::from_records(planner.name(), "clean the table (per grasp/place query)", &refs));
        report.runs.extend(records);
    }
    println!("clean the table: {episodes} episodes per planner in {:.1} s", t.elapsed().as_secs_f64());

    print!("{}", report.table());
    println!("== clean the table episodes");
    for line in episode_lines {
        println!("{line}");
    }
    write(&report, &output)?;
    println!("\nall {} runs written to {output}", report.runs.len());
    Ok(())
}

fn write(report: &BenchmarkReport, path: &str) -> Result<()> {
    let json = report.to_json()?;
    std::fs::write(path, json).map_err(|e| opengrasp::motion::MotionError::Other(Box::new(e)))
}
