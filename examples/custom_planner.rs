//! Your own planners in the OpenGRASP suite, next to the reference planners, graded by the
//! same evaluator and validators, with the results written like `opengrasp run` writes them.
//!
//! - `random-surface`: a grasp planner that samples random points on the object's surface and
//!   approaches each along the inverted surface normal with a random roll;
//! - `StraightThenRrt`: a motion planner that tries the straight C-space segment first and
//!   falls back to RRT-Connect when it is blocked.
//!
//! ```sh
//! cargo run --release --example custom_planner -- [OUT.json]
//! opengrasp report OUT.json
//! ```

use opengrasp::bench::stock::{stock_hand, stock_object};
use opengrasp::core::nalgebra::Unit;
use opengrasp::grasp::planners::{palm_pose, GraspCandidate, GraspPlanner, GraspRequest, Preshape};
use opengrasp::motion::planners::RrtConnect;
use opengrasp::motion::validate::segment_valid_discrete;
use opengrasp::motion::{Goal, MotionPlanner, PlanningProblem, Solution};
use opengrasp::prelude::*;
use opengrasp::report::{self, Format};
use opengrasp::suite::{planar_scene, Suite};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Random points on the surface, approached along the inverted normal, random roll.
struct RandomSurface {
    /// Candidates per object.
    samples: usize,
}

impl GraspPlanner for RandomSurface {
    fn name(&self) -> &str {
        "random-surface"
    }

    fn plan(&self, request: &GraspRequest<'_>) -> opengrasp::grasp::Result<Vec<GraspCandidate>> {
        let mut rng = ChaCha8Rng::seed_from_u64(request.seed);
        let mesh = request.object;
        let (vertices, triangles) = (mesh.vertices(), mesh.triangles());
        let mut out = Vec::with_capacity(self.samples);
        while out.len() < self.samples && !triangles.is_empty() {
            let [a, b, c] = triangles[rng.random_range(0..triangles.len())].map(|k| vertices[k as usize]);
            let normal = (b - a).cross(&(c - a));
            if normal.norm() < 1e-12 {
                continue;
            }
            // Uniform point in the triangle.
            let (mut u, mut v): (f64, f64) = (rng.random(), rng.random());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let point = a + (b - a) * u + (c - a) * v;
            let approach = Unit::new_normalize(-normal);
            let roll = rng.random_range(0.0..std::f64::consts::TAU);
            let closing = Vector3::new(roll.cos(), roll.sin(), 0.3);
            out.push(GraspCandidate {
                hand_pose: palm_pose(request.hand, &point, &approach, &closing),
                preshape: Preshape::Default,
                approach,
                standoff: 0.0,
            });
        }
        Ok(out)
    }
}

/// The straight segment if it is valid, otherwise RRT-Connect.
#[derive(Default)]
struct StraightThenRrt {
    fallback: RrtConnect,
}

impl MotionPlanner for StraightThenRrt {
    fn name(&self) -> &str {
        "straight-then-RRT"
    }

    fn plan(&mut self, problem: &PlanningProblem<'_>) -> opengrasp::motion::Result<Solution> {
        problem.validate()?;
        if let Goal::Configuration(goal) = problem.goal {
            if segment_valid_discrete(problem.checker, problem.start, goal, problem.step) {
                return Ok(Solution { path: vec![problem.start.to_vec(), goal.clone()], iterations: 1 });
            }
        }
        self.fallback.plan(problem)
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| "target/custom_planner_results.json".into());
    let suite = Suite::new()
        // Grasp: the reference planners and ours, on two objects with the Barrett hand.
        .with_reference_grasp(opengrasp::suite::SuiteSize::Tiny)
        .grasp_planner("samples = 24", RandomSurface { samples: 24 })
        .hands(vec![stock_hand("barrett")?])
        .objects(vec![stock_object("salt_can")?, stock_object("white_cup")?])
        .max_candidates(Some(24))
        // Motion: RRT-Connect and ours on the planar arm scene.
        .motion_planner("default options", || Box::new(RrtConnect::default()))
        .motion_planner("fallback: RRT-Connect defaults", || Box::new(StraightThenRrt::default()))
        .motion_scene(planar_scene())
        .runs(10)
        .seed(7);
    let results = suite.run()?;
    results.save(&out)?;
    println!("{}", report::render(&results, Format::Table));
    println!("results written to {out}");
    Ok(())
}
