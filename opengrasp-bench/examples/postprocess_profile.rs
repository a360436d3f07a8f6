//! Where post-processing time goes on kitchen scene 1: plans RRT-Connect paths (seeds 0..n)
//! and post-processes them as the harness does, counting and timing every checker call.
//!
//! ```sh
//! cargo run --release -p opengrasp-bench --example postprocess_profile -- 10 [exact|fast]
//! ```
//!
//! The default mode post-processes each path twice, exactly and with the scene's certifier,
//! and asserts that the paths are the same; `exact` profiles the exact run, `fast` the
//! certified run alone (for callgrind).
//!
//! With `table` instead, runs RRT-Connect Clean the Table episodes (seeds 0..n) and prints the
//! post-processing time and checks of each query and the episode's sum:
//!
//! ```sh
//! cargo run --release -p opengrasp-bench --example postprocess_profile -- 2 table
//! ```

use std::cell::Cell;
use std::time::{Duration, Instant};

use opengrasp_bench::clean_table::{clean_the_table, CleanTheTableOptions};
use opengrasp_bench::scenes::armar_standard_scene;
use opengrasp_motion::benchmark::{postprocessing_options, BenchmarkOptions};
use opengrasp_motion::certify::{Certificate, SegmentCertifier};
use opengrasp_motion::planners::RrtConnect;
use opengrasp_motion::smoothing::{repair_with, shortcut_with};
use opengrasp_motion::validity::{MotionBound, StateValidityChecker};
use opengrasp_motion::MotionPlanner;

#[derive(Default)]
struct Tally {
    n: Cell<u64>,
    t: Cell<Duration>,
}

impl Tally {
    fn time<R>(&self, f: impl FnOnce() -> R) -> R {
        let t0 = Instant::now();
        let r = f();
        self.n.set(self.n.get() + 1);
        self.t.set(self.t.get() + t0.elapsed());
        r
    }
}

struct Profiled<'a> {
    inner: &'a dyn StateValidityChecker,
    valid: Tally,
    residual: Tally,
    distances: Tally,
    clearance: Tally,
}

impl StateValidityChecker for Profiled<'_> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        self.valid.time(|| self.inner.is_valid(q))
    }
    fn clearance(&self, q: &[f64]) -> Option<f64> {
        self.clearance.time(|| self.inner.clearance(q))
    }
    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        self.distances.time(|| self.inner.link_distances(q, out))
    }
    fn motion_bound(&self) -> Option<&MotionBound> {
        self.inner.motion_bound()
    }
    fn ccd_covers_self_collision(&self) -> bool {
        self.inner.ccd_covers_self_collision()
    }
    fn residual_valid(&self, q: &[f64]) -> Option<bool> {
        self.residual.time(|| self.inner.residual_valid(q))
    }
}

struct ProfiledCertifier<'a> {
    inner: &'a dyn SegmentCertifier,
    yes: Tally,
    no: Tally,
}

impl ProfiledCertifier<'_> {
    /// Tallies a certification that started at `t0` as proven or not.
    fn tally(&self, t0: Instant, proven: bool) {
        let tally = if proven { &self.yes } else { &self.no };
        tally.n.set(tally.n.get() + 1);
        tally.t.set(tally.t.get() + t0.elapsed());
    }
}

impl SegmentCertifier for ProfiledCertifier<'_> {
    fn certify(&self, a: &[f64], b: &[f64], bound: &MotionBound, margin: f64, max_steps: usize) -> Certificate {
        let t0 = Instant::now();
        let r = self.inner.certify(a, b, bound, margin, max_steps);
        self.tally(t0, r == Certificate::Free);
        r
    }

    fn certify_staged(
        &self,
        a: &[f64],
        b: &[f64],
        bound: &MotionBound,
        margin: f64,
        steps: (usize, usize),
        proceed: &mut dyn FnMut() -> bool,
    ) -> Option<Certificate> {
        let t0 = Instant::now();
        let r = self.inner.certify_staged(a, b, bound, margin, steps, proceed);
        self.tally(t0, r == Some(Certificate::Free));
        r
    }
}

/// Post-processing time and checks of every query of Clean the Table episodes `0..n`.
fn table(n: u64) {
    for seed in 0..n {
        let options = CleanTheTableOptions { seed, ..CleanTheTableOptions::default() };
        let report = clean_the_table(&mut RrtConnect::default(), &options).expect("episode");
        for object in &report.objects {
            for r in std::iter::once(&object.grasp).chain(&object.place) {
                println!(
                    "  {:<40} post-processing {:>8.1} ms, {:>6} checks",
                    r.scene,
                    r.postprocessing_time.unwrap_or(0.0) * 1e3,
                    r.postprocessing_checks
                );
            }
        }
        println!(
            "episode {seed}: cleaned {}, post-processing {:.2} s, planning {:.2} s, all valid {}",
            report.totals.cleaned,
            report.totals.postprocessing_time,
            report.totals.planning_time,
            report.totals.all_valid
        );
    }
}

fn main() {
    let n: u64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(10);
    if std::env::args().nth(2).is_some_and(|s| s == "table") {
        return table(n);
    }
    let mode = std::env::args().nth(2).unwrap_or_default();
    let certified = mode != "exact";
    // `fast`: the certified run alone, without the exact reference (for callgrind).
    let compare = mode != "fast";
    let scene = armar_standard_scene();
    let instance = (scene.generate)(0).expect("scene instance");
    let options = BenchmarkOptions::default();
    let limits = instance.group.limits(&instance.robot);
    let mut planner = RrtConnect::default();
    let p = Profiled {
        inner: &*instance.checker,
        valid: Tally::default(),
        residual: Tally::default(),
        distances: Tally::default(),
        clearance: Tally::default(),
    };
    let mut total = Duration::ZERO;
    let (scene, rid, q_full) = {
        let k = opengrasp_assets::scenes::kitchen().expect("kitchen");
        let mut q = k.start_configuration.clone();
        for (j, v) in ["base_x", "base_y", "base_yaw"].iter().zip(opengrasp_bench::scenes::ARMAR_BASE) {
            q[instance.robot.dof_index(j).expect("joint")] = v;
        }
        (k.scene, k.robot, q)
    };
    let (_, group, _, checker) = opengrasp_bench::scenes::armar_kitchen_checker("hip_right_arm").expect("checker");
    let c = opengrasp_bench::scenes::certifier_for(&scene, rid, &group, &q_full, &checker).expect("certifier");
    println!("prims {} obstacles {} pairs {}", c.primitive_count(), c.obstacle_count(), c.pair_count());

    for seed in 0..n {
        let problem = instance.problem(&*instance.checker, Duration::from_secs(10), seed, 0.02);
        let path = planner.plan(&problem).expect("solved").path;
        let so = postprocessing_options(&options, seed);
        let t0 = Instant::now();
        let exact = compare.then(|| {
            let (exact_r, _) = repair_with(&*instance.checker, None, &path, &limits, &so);
            shortcut_with(&*instance.checker, None, &exact_r, &so).0
        });
        let t_exact = t0.elapsed();
        let pc = instance.certifier.as_deref().map(|inner| ProfiledCertifier {
            inner,
            yes: Tally::default(),
            no: Tally::default(),
        });
        let certifier = if certified { pc.as_ref().map(|c| c as &dyn SegmentCertifier) } else { None };
        let t0 = Instant::now();
        let (repaired, rs) = repair_with(&p, certifier, &path, &limits, &so);
        let (smoothed, ss) = shortcut_with(&p, certifier, &repaired, &so);
        let dt = t0.elapsed();
        total += dt;
        if let Some(exact) = exact {
            assert_eq!(smoothed, exact, "certified post-processing differs from the exact one");
        }
        if let Some(c) = &pc {
            println!(
                "  certified {} in {:.1} ms, not {} in {:.1} ms",
                c.yes.n.get(),
                c.yes.t.get().as_secs_f64() * 1e3,
                c.no.n.get(),
                c.no.t.get().as_secs_f64() * 1e3
            );
        }
        println!(
            "seed {seed}: {} -> {} waypoints, exact {:.1} ms, profiled {:.1} ms, repaired {} accepted {} pruned {}",
            path.len(),
            smoothed.len(),
            t_exact.as_secs_f64() * 1e3,
            dt.as_secs_f64() * 1e3,
            rs.repaired,
            ss.accepted,
            ss.pruned
        );
    }
    let per = |t: &Tally| {
        format!(
            "{:>9} calls {:>9.1} ms/path {:>7.2} us/call",
            t.n.get() / n,
            t.t.get().as_secs_f64() * 1e3 / n as f64,
            t.t.get().as_secs_f64() * 1e6 / t.n.get().max(1) as f64
        )
    };
    println!("mean per path {:.1} ms", total.as_secs_f64() * 1e3 / n as f64);
    println!("is_valid        {}", per(&p.valid));
    println!("residual_valid  {}", per(&p.residual));
    println!("link_distances  {}", per(&p.distances));
    println!("clearance       {}", per(&p.clearance));
}
