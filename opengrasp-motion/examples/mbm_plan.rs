//! RRT-Connect on the vendored MotionBenchMaker Panda problems, planned on the layered greedy
//! sphere model: a fixed workload (every problem of the sets whose name contains FILTER, seeds
//! `0..SEEDS`, time limit LIMIT s, default 10; `lanes` as a fourth argument checks with
//! `SphereWorld::with_batched_checks` (anything else: one state at a time), a fifth sets
//! `RrtConnectOptions::dynamic_domain` (not a number, e.g. `none`: off), a sixth
//! `RrtConnectOptions::range`) for instruction counts (`perf stat`, `valgrind --tool=callgrind`), which stay
//! comparable on a loaded machine where timings do not. Prints the solved runs, the states
//! checked and the planning time (mean and median per run; the model's pair tables,
//! `SphereWorld::with_pair_tables`, are built with the model, before any timed plan; with the
//! environment variable `NO_PAIR_TABLES` set it plans without them; with `NO_CERTIFICATES`
//! set motions run every test of every state, `SphereWorld::with_certified_motions(false)`;
//! with `VAMP_LIKE` set it plans with `RrtConnectOptions::vamp_like`, range and radius
//! arguments still applying on top).
//!
//! ```sh
//! cargo run --release -p opengrasp-motion --example mbm_plan -- cage 20 10 [lanes|single [RADIUS|none [RANGE]]]
//! ```

use std::time::{Duration, Instant};

use opengrasp_motion::planners::{RrtConnect, RrtConnectOptions};
use opengrasp_motion::problem_set::{self, LoadedProblemSet, PlanningModel};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::validity::CountingChecker;
use opengrasp_motion::MotionPlanner;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mbm/panda/problems");
    let mut args = std::env::args().skip(1);
    let filter = args.next().unwrap_or_default();
    let seeds: u64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(10);
    let limit = Duration::from_secs_f64(args.next().map(|s| s.parse()).transpose()?.unwrap_or(10.0));
    let sets: Vec<LoadedProblemSet> =
        problem_set::load(dir)?.iter().map(LoadedProblemSet::new).collect::<Result<_, _>>()?;
    let lanes = args.next().is_some_and(|a| a == "lanes");
    let dynamic_domain: Option<f64> = args.next().and_then(|s| s.parse().ok());
    // `VAMP_LIKE=1` starts from the problem-set settings (`RrtConnectOptions::vamp_like`).
    let base = if std::env::var_os("VAMP_LIKE").is_some() {
        RrtConnectOptions::vamp_like()
    } else {
        RrtConnectOptions::default()
    };
    let mut options = RrtConnectOptions { dynamic_domain, ..base };
    if let Some(range) = args.next() {
        options.range = range.parse()?;
    }
    // `NO_PAIR_TABLES=1` plans without the pair distance tables, `NO_CERTIFICATES=1` checks
    // every state's tests in motions (same verdicts and states either way).
    let tables = std::env::var_os("NO_PAIR_TABLES").is_none();
    let layered = sets[0]
        .layered_sphere_model(GreedyCoverOptions::default())?
        .with_pair_tables(tables)
        .with_batched_checks(lanes)
        .with_certified_motions(std::env::var_os("NO_CERTIFICATES").is_none());
    let model = PlanningModel::Spheres(std::sync::Arc::new(layered));
    for set in sets.iter().filter(|s| s.name().contains(&filter)) {
        let instances: Vec<_> = (0..set.len()).map(|i| set.instance_with(i, &model)).collect::<Result<_, _>>()?;
        let (mut solved, mut checks, mut times) = (0, 0, Vec::new());
        for seed in 0..seeds {
            for instance in &instances {
                let counter = CountingChecker::new(instance.planner_checker());
                let problem = instance.problem(&counter, limit, seed, 0.02);
                let t = Instant::now();
                solved += usize::from(RrtConnect::new(options).plan(&problem).is_ok());
                times.push(t.elapsed());
                checks += counter.checks();
            }
        }
        let runs = seeds as usize * instances.len();
        let time: Duration = times.iter().sum();
        times.sort();
        println!(
            "{}: {solved}/{runs} solved, {checks} states checked, {:.3} ms per run, median {:.3} ms",
            set.name(),
            time.as_secs_f64() * 1e3 / runs.max(1) as f64,
            times.get(runs / 2).map_or(0.0, |t| t.as_secs_f64() * 1e3)
        );
    }
    Ok(())
}
