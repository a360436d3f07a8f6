//! The grasp planner benchmark of the OpenGRASP paper (Ulbrich et al. 2011, section IV-A,
//! Tables I and II): planners × hands × objects, every candidate graded by the one shared
//! [`GraspEvaluator`].
//!
//! For each cell the benchmark reports what the paper reports (candidates tested and the
//! percentage of force-closure grasps among the grasps whose palm touches the object) and more:
//! force closure over all candidates, mean and median Ferrari-Canny epsilon of the force-closure
//! grasps, the physics-check success rate on a subset, and the evaluation throughput.
//!
//! ```
//! use opengrasp_grasp::benchmark::{run_grasp_benchmark, BenchmarkHand, GraspBenchmarkConfig};
//!
//! # fn main() -> opengrasp_grasp::Result<()> {
//! // A quick run: one object, one hand, 4 candidates per planner (the full run uses the
//! // defaults: 8 objects, 2 hands, every candidate).
//! let config = GraspBenchmarkConfig {
//!     objects: vec!["salt_can".into()],
//!     hands: vec![BenchmarkHand::Barrett],
//!     max_candidates: Some(4),
//!     ..Default::default()
//! };
//! let results = run_grasp_benchmark(&config)?;
//! assert_eq!(results.cells.len(), 2); // medial axis and surface normals
//! println!("{}", results.table("barrett"));
//! let json = results.to_json()?;
//! assert!(json.contains("\"planner\": \"medial-axis\""));
//! # Ok(())
//! # }
//! ```

use std::time::Instant;

use nalgebra::Isometry3;
use opengrasp_assets::hands::{self, Hand};
use opengrasp_assets::objects::{self, ObjectModel};
use serde::{Deserialize, Serialize};

use crate::error::{GraspError, Result};
use crate::evaluator::{EvaluationStatus, EvaluatorOptions, GraspEvaluator, PhysicsCheckOptions};
use crate::planners::{
    GraspCandidate, GraspPlanner, GraspRequest, MedialAxisOptions, MedialAxisPlanner, SurfaceNormalOptions,
    SurfaceNormalPlanner,
};

/// The eight objects of the paper's Tables I and II: `(row label, asset name)`.
pub const PAPER_OBJECTS: [(&str, &str); 8] = [
    ("Bread box", "bread_box"),
    ("Prismatic box", "chocolate_box"),
    ("Salt box", "salt_box"),
    ("Salt can", "salt_can"),
    ("Detergent", "detergent_bottle"),
    ("Spray", "spray_bottle"),
    ("White cup", "white_cup"),
    ("Green cup", "green_cup"),
];

/// The paper's numbers: `(object, hand, planner, candidates, FC %)`, hands `"armar3"` (Table I)
/// and `"barrett"` (Table II), planners `"medial-axis"` and `"surface-normals"`.
pub const PAPER_RESULTS: [(&str, &str, &str, usize, f64); 32] = [
    ("bread_box", "armar3", "medial-axis", 296, 99.0),
    ("bread_box", "armar3", "surface-normals", 842, 16.5),
    ("chocolate_box", "armar3", "medial-axis", 516, 99.8),
    ("chocolate_box", "armar3", "surface-normals", 520, 43.8),
    ("salt_box", "armar3", "medial-axis", 408, 85.8),
    ("salt_box", "armar3", "surface-normals", 408, 41.2),
    ("salt_can", "armar3", "medial-axis", 1072, 80.0),
    ("salt_can", "armar3", "surface-normals", 616, 48.4),
    ("detergent_bottle", "armar3", "medial-axis", 1022, 87.6),
    ("detergent_bottle", "armar3", "surface-normals", 928, 38.5),
    ("spray_bottle", "armar3", "medial-axis", 590, 77.5),
    ("spray_bottle", "armar3", "surface-normals", 762, 29.5),
    ("white_cup", "armar3", "medial-axis", 732, 81.1),
    ("white_cup", "armar3", "surface-normals", 456, 48.2),
    ("green_cup", "armar3", "medial-axis", 514, 51.8),
    ("green_cup", "armar3", "surface-normals", 496, 52.0),
    ("bread_box", "barrett", "medial-axis", 296, 66.9),
    ("bread_box", "barrett", "surface-normals", 842, 11.8),
    ("chocolate_box", "barrett", "medial-axis", 516, 20.2),
    ("chocolate_box", "barrett", "surface-normals", 520, 19.2),
    ("salt_box", "barrett", "medial-axis", 408, 94.4),
    ("salt_box", "barrett", "surface-normals", 408, 47.3),
    ("salt_can", "barrett", "medial-axis", 1072, 91.4),
    ("salt_can", "barrett", "surface-normals", 616, 44.2),
    ("detergent_bottle", "barrett", "medial-axis", 1022, 49.5),
    ("detergent_bottle", "barrett", "surface-normals", 928, 25.8),
    ("spray_bottle", "barrett", "medial-axis", 590, 44.1),
    ("spray_bottle", "barrett", "surface-normals", 762, 13.9),
    ("white_cup", "barrett", "medial-axis", 732, 63.8),
    ("white_cup", "barrett", "surface-normals", 456, 37.5),
    ("green_cup", "barrett", "medial-axis", 514, 34.8),
    ("green_cup", "barrett", "surface-normals", 496, 36.1),
];

/// A hand of the benchmark.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum BenchmarkHand {
    /// The Barrett BH8-262 ([`hands::barrett`]).
    Barrett,
    /// The ARMAR-III five-finger hand ([`hands::armar3_hand`]).
    Armar3,
}

impl BenchmarkHand {
    /// Short name used in results (`"barrett"`, `"armar3"`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Barrett => "barrett",
            Self::Armar3 => "armar3",
        }
    }

    /// The hand model.
    pub fn hand(self) -> Hand {
        match self {
            Self::Barrett => hands::barrett(),
            Self::Armar3 => hands::armar3_hand(),
        }
    }
}

/// Configuration of [`run_grasp_benchmark`].
#[derive(Clone, Debug)]
pub struct GraspBenchmarkConfig {
    /// Asset names of the objects. Default: the eight objects of [`PAPER_OBJECTS`].
    pub objects: Vec<String>,
    /// Hands. Default: ARMAR-III (Table I) and Barrett (Table II).
    pub hands: Vec<BenchmarkHand>,
    /// Options of the surface-normal planner. Default: OpenRAVE's defaults.
    pub surface_normal: SurfaceNormalOptions,
    /// Options of the medial-axis planner. Default: [`MedialAxisOptions::default`].
    pub medial_axis: MedialAxisOptions,
    /// Options of the shared evaluator. Default: [`EvaluatorOptions::default`].
    pub evaluator: EvaluatorOptions,
    /// Seed handed to the planners. Default: 0.
    pub seed: u64,
    /// Evaluate at most this many candidates per cell (an even stride over the planner's
    /// list); `None` evaluates all. Default: `None`.
    pub max_candidates: Option<usize>,
    /// Physics check of up to this many force-closure, palm-contact grasps per cell (evenly
    /// spread); 0 disables it. Default: 0.
    pub physics_per_cell: usize,
    /// Options of the physics check. Default: [`PhysicsCheckOptions::default`].
    pub physics: PhysicsCheckOptions,
    /// Keep one [`CandidateRecord`] per evaluated candidate in [`CellResult::candidates`]
    /// (about 1.6 kB each in pretty JSON: 6.4 MB for the default suite). Default: false.
    pub record_candidates: bool,
}

impl Default for GraspBenchmarkConfig {
    fn default() -> Self {
        Self {
            objects: PAPER_OBJECTS.iter().map(|(_, n)| n.to_string()).collect(),
            hands: vec![BenchmarkHand::Armar3, BenchmarkHand::Barrett],
            surface_normal: SurfaceNormalOptions::default(),
            medial_axis: MedialAxisOptions::default(),
            evaluator: EvaluatorOptions::default(),
            seed: 0,
            max_candidates: None,
            physics_per_cell: 0,
            physics: PhysicsCheckOptions::default(),
            record_candidates: false,
        }
    }
}

/// One evaluated candidate, for inspecting or re-scoring a planner's grasps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CandidateRecord {
    /// Index in the planner's candidate list.
    pub index: usize,
    /// The candidate as the planner produced it (object frame).
    pub candidate: GraspCandidate,
    /// How the evaluation ended.
    pub status: EvaluationStatus,
    /// Final palm pose in the object frame (after retraction and standoff).
    pub hand_pose: Isometry3<f64>,
    /// Final hand configuration (after closing).
    pub q: Vec<f64>,
    /// True if the palm touches the object (the paper's "tested").
    pub palm_contact: bool,
    /// Fingers touching the object.
    pub fingers_in_contact: usize,
    /// Contacts found.
    pub contacts: usize,
    /// Force closure (QP test).
    pub force_closure: bool,
    /// Ferrari-Canny epsilon (0 without force closure).
    pub epsilon: f64,
    /// Grasp wrench space volume (0 if unavailable).
    pub volume: f64,
    /// Outcome of the physics hold check, if this grasp was simulated.
    pub physics_held: Option<bool>,
}

/// Results of one planner × hand × object cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellResult {
    /// Planner name.
    pub planner: String,
    /// Hand name.
    pub hand: String,
    /// Object asset name.
    pub object: String,
    /// Candidates the planner generated.
    pub generated: usize,
    /// Candidates evaluated (all, or a stride of them with `max_candidates`).
    pub evaluated: usize,
    /// Evaluated candidates whose fingers closed on the object.
    pub closed: usize,
    /// Evaluated candidates with the palm touching the object (the paper's "candidates tested").
    pub palm_contact: usize,
    /// Force-closure grasps among the palm-contact candidates.
    pub force_closure_palm: usize,
    /// Force-closure grasps among all evaluated candidates.
    pub force_closure: usize,
    /// Percentage of force closure among palm-contact candidates (the paper's "FC").
    pub fc_percent_palm: f64,
    /// Percentage of force closure among all evaluated candidates.
    pub fc_percent_all: f64,
    /// Mean Ferrari-Canny epsilon over the force-closure palm-contact grasps, the set the
    /// paper's FC column counts (0 if none).
    pub mean_epsilon: f64,
    /// Median Ferrari-Canny epsilon over the force-closure palm-contact grasps (0 if none).
    pub median_epsilon: f64,
    /// Grasps sent to the physics check.
    pub physics_tested: usize,
    /// Grasps that held the object in the physics check.
    pub physics_held: usize,
    /// Wall time for planning (s).
    pub planning_seconds: f64,
    /// Wall time for evaluation (s).
    pub evaluation_seconds: f64,
    /// Candidates evaluated per second.
    pub evaluations_per_second: f64,
    /// Every evaluated candidate, if [`GraspBenchmarkConfig::record_candidates`] (else empty,
    /// and absent from the JSON).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub candidates: Vec<CandidateRecord>,
}

/// All results of a benchmark run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraspBenchmarkResults {
    /// One entry per planner × hand × object, in run order (hands, objects, planners).
    pub cells: Vec<CellResult>,
    /// Total candidates evaluated.
    pub total_evaluated: usize,
    /// Total evaluation wall time (s).
    pub total_evaluation_seconds: f64,
    /// Overall evaluation throughput (candidates per second, one core).
    pub evaluations_per_second: f64,
}

impl GraspBenchmarkResults {
    /// The cell of a planner, hand and object, if run.
    pub fn cell(&self, planner: &str, hand: &str, object: &str) -> Option<&CellResult> {
        self.cells.iter().find(|c| c.planner == planner && c.hand == hand && c.object == object)
    }

    /// Serialises the results as pretty JSON.
    ///
    /// # Errors
    /// [`GraspError::Other`] if serialisation fails.
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string_pretty(self).map_err(|e| GraspError::Other(Box::new(e)))
    }

    /// The paper-shaped table for one hand: per object, candidates tested and FC % for both
    /// planners, next to the paper's numbers, plus epsilon and physics columns.
    pub fn table(&self, hand: &str) -> String {
        let mut out = String::new();
        out.push_str(&format!(
            "{:<14} | {:>30} | {:>30}\n",
            "hand: ".to_string() + hand,
            "medial-axis: palm/FC%/paper",
            "surface-normals: palm/FC%/paper"
        ));
        let mut objects: Vec<&str> = Vec::new();
        for c in self.cells.iter().filter(|c| c.hand == hand) {
            if !objects.contains(&c.object.as_str()) {
                objects.push(&c.object);
            }
        }
        for o in objects {
            let label = PAPER_OBJECTS.iter().find(|(_, n)| *n == o).map_or(o, |(l, _)| l);
            let mut row = format!("{label:<14}");
            for planner in ["medial-axis", "surface-normals"] {
                let paper = PAPER_RESULTS
                    .iter()
                    .find(|r| r.0 == o && r.1 == hand && r.2 == planner)
                    .map_or("-".to_string(), |r| format!("{}/{:.1}%", r.3, r.4));
                match self.cell(planner, hand, o) {
                    Some(c) => row.push_str(&format!(
                        " | {:>5} {:>5.1}% (all {:>5.1}%) {:>12}",
                        c.palm_contact, c.fc_percent_palm, c.fc_percent_all, paper
                    )),
                    None => row.push_str(&format!(" | {:>30}", "-")),
                }
            }
            out.push_str(&row);
            out.push('\n');
        }
        out
    }
}

/// Runs the two reference planners (medial axis, surface normals) on the configured hands and
/// objects; see [`run_grasp_benchmark_with`] for other planners.
///
/// # Errors
/// As [`run_grasp_benchmark_with`].
pub fn run_grasp_benchmark(config: &GraspBenchmarkConfig) -> Result<GraspBenchmarkResults> {
    let ma = MedialAxisPlanner::new(config.medial_axis.clone());
    let sn = SurfaceNormalPlanner::new(config.surface_normal.clone());
    let planners: [&dyn GraspPlanner; 2] = [&ma, &sn];
    run_grasp_benchmark_with(config, &planners)
}

/// Runs `planners` × the configured hands × objects through the shared evaluator.
///
/// # Errors
/// [`GraspError::Other`] for an unknown object name; planner errors; evaluator errors.
pub fn run_grasp_benchmark_with(
    config: &GraspBenchmarkConfig,
    planners: &[&dyn GraspPlanner],
) -> Result<GraspBenchmarkResults> {
    let objects: Vec<ObjectModel> = config
        .objects
        .iter()
        .map(|n| objects::by_name(n).map_err(|e| GraspError::Other(Box::new(e))))
        .collect::<Result<_>>()?;
    let mut cells = Vec::new();
    for &bh in &config.hands {
        let hand = bh.hand();
        for object in &objects {
            let mut evaluator = GraspEvaluator::new(&hand, object, config.evaluator.clone())?;
            let info = evaluator.hand_info().clone();
            for planner in planners {
                let t0 = Instant::now();
                let request = GraspRequest { hand: &info, object: &object.mesh, seed: config.seed };
                let candidates = planner.plan(&request)?;
                let planning_seconds = t0.elapsed().as_secs_f64();
                let chosen: Vec<usize> = match config.max_candidates {
                    Some(m) if m < candidates.len() => (0..m).map(|i| i * candidates.len() / m).collect(),
                    _ => (0..candidates.len()).collect(),
                };
                let t1 = Instant::now();
                let mut evaluations = Vec::with_capacity(chosen.len());
                for &i in &chosen {
                    evaluations.push(evaluator.evaluate(&candidates[i])?);
                }
                let evaluation_seconds = t1.elapsed().as_secs_f64();
                let closed = evaluations.iter().filter(|e| e.status == EvaluationStatus::Closed).count();
                let palm = evaluations.iter().filter(|e| e.palm_contact).count();
                let fc_palm: Vec<usize> = (0..evaluations.len())
                    .filter(|&k| evaluations[k].palm_contact && evaluations[k].force_closure())
                    .collect();
                let fc_all = evaluations.iter().filter(|e| e.force_closure()).count();
                let mut eps: Vec<f64> = fc_palm.iter().map(|&k| evaluations[k].epsilon()).collect();
                eps.sort_by(f64::total_cmp);
                let mean_epsilon = if eps.is_empty() { 0.0 } else { eps.iter().sum::<f64>() / eps.len() as f64 };
                let median_epsilon = match eps.len() {
                    0 => 0.0,
                    n if n % 2 == 1 => eps[n / 2],
                    n => 0.5 * (eps[n / 2 - 1] + eps[n / 2]),
                };
                let (mut physics_tested, mut physics_held) = (0, 0);
                let mut held_by_evaluation = vec![None; evaluations.len()];
                if config.physics_per_cell > 0 && !fc_palm.is_empty() {
                    let m = config.physics_per_cell.min(fc_palm.len());
                    for j in 0..m {
                        let k = fc_palm[j * fc_palm.len() / m];
                        let outcome = crate::evaluator::physics_check(&hand, object, &evaluations[k], &config.physics)?;
                        physics_tested += 1;
                        physics_held += usize::from(outcome.held());
                        held_by_evaluation[k] = Some(outcome.held());
                    }
                }
                let candidate_records = if config.record_candidates {
                    chosen
                        .iter()
                        .zip(&evaluations)
                        .zip(held_by_evaluation)
                        .map(|((&i, e), held)| CandidateRecord {
                            index: i,
                            candidate: candidates[i].clone(),
                            status: e.status,
                            hand_pose: e.hand_pose,
                            q: e.q.clone(),
                            palm_contact: e.palm_contact,
                            fingers_in_contact: e.fingers_in_contact,
                            contacts: e.contacts.len(),
                            force_closure: e.force_closure(),
                            epsilon: e.epsilon(),
                            volume: e.quality.map_or(0.0, |q| q.volume),
                            physics_held: held,
                        })
                        .collect()
                } else {
                    Vec::new()
                };
                let pct = |a: usize, b: usize| if b == 0 { 0.0 } else { 100.0 * a as f64 / b as f64 };
                cells.push(CellResult {
                    planner: planner.name().to_string(),
                    hand: bh.name().to_string(),
                    object: object.name.clone(),
                    generated: candidates.len(),
                    evaluated: evaluations.len(),
                    closed,
                    palm_contact: palm,
                    force_closure_palm: fc_palm.len(),
                    force_closure: fc_all,
                    fc_percent_palm: pct(fc_palm.len(), palm),
                    fc_percent_all: pct(fc_all, evaluations.len()),
                    mean_epsilon,
                    median_epsilon,
                    physics_tested,
                    physics_held,
                    planning_seconds,
                    evaluation_seconds,
                    evaluations_per_second: if evaluation_seconds > 0.0 {
                        evaluations.len() as f64 / evaluation_seconds
                    } else {
                        0.0
                    },
                    candidates: candidate_records,
                });
            }
        }
    }
    let total_evaluated = cells.iter().map(|c| c.evaluated).sum();
    let total_evaluation_seconds: f64 = cells.iter().map(|c| c.evaluation_seconds).sum();
    Ok(GraspBenchmarkResults {
        cells,
        total_evaluated,
        total_evaluation_seconds,
        evaluations_per_second: if total_evaluation_seconds > 0.0 {
            total_evaluated as f64 / total_evaluation_seconds
        } else {
            0.0
        },
    })
}
