//! The grasp planner benchmark of the OpenGRASP paper (Ulbrich et al. 2011, section IV-A,
//! Tables I and II): planners × hands × objects, every candidate graded by the one shared
//! [`GraspEvaluator`].
//!
//! Hands, objects and planners are values: the stock ones of `opengrasp-assets`, a hand loaded
//! from a URDF and a spec file ([`Hand::load`]), an object from a mesh and a metadata file
//! ([`ObjectModel::load`]), any [`GraspPlanner`].
//!
//! For each cell the benchmark reports what the paper reports (candidates tested and the
//! percentage of force-closure grasps among the grasps whose palm touches the object) and more:
//! force closure over all candidates, mean and median Ferrari-Canny epsilon of the force-closure
//! grasps, the physics-check success rate on a subset, and the evaluation throughput.
//!
//! ```
//! use opengrasp_core::hand::{FingerSpec, Hand, HandSpec, PreshapeSpec};
//! use opengrasp_core::model::{samples, TriangleMesh};
//! use opengrasp_core::object::ObjectModel;
//! use opengrasp_grasp::benchmark::{run_grasp_benchmark, GraspBenchmarkConfig};
//! # use nalgebra::{Isometry3, Vector3};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // A two-finger parallel gripper built in code, and a 5 cm cube.
//! let gripper = samples::parallel_gripper(0.1)?;
//! let spec = HandSpec {
//!     urdf: None,
//!     palm_link: "palm".into(),
//!     palm_frame: Isometry3::identity(),
//!     approach: Vector3::z(),
//!     preshapes: vec![PreshapeSpec { name: "open".into(), joints: vec![("left_joint".into(), 0.05)] }],
//!     fingers: vec![
//!         FingerSpec { name: "left".into(), links: vec!["left_finger".into()] },
//!         FingerSpec { name: "right".into(), links: vec!["right_finger".into()] },
//!     ],
//!     closing: vec![("left_joint".into(), -0.05)],
//!     tactile_links: vec![],
//!     actuation: Default::default(),
//! };
//! let cube = ObjectModel::from_mesh("cube", TriangleMesh::cuboid(Vector3::repeat(0.05))?, 0.1, 0.5)?;
//! let config = GraspBenchmarkConfig {
//!     hands: vec![Hand::from_robot(gripper, spec)?],
//!     objects: vec![cube],
//!     max_candidates: Some(4),
//!     ..Default::default()
//! };
//! // The two reference planners (medial axis, surface normals).
//! let results = run_grasp_benchmark(&config)?;
//! assert_eq!(results.cells.len(), 2);
//! println!("{}", results.table("parallel_gripper"));
//! # Ok(())
//! # }
//! ```

use std::time::Instant;

use nalgebra::Isometry3;
use opengrasp_core::hand::Hand;
use opengrasp_core::object::ObjectModel;
use serde::{Deserialize, Serialize};

use crate::contact::ObjectFrame;
use crate::error::Result;
use crate::evaluator::{EvaluationStatus, EvaluatorOptions, GraspEvaluator, PhysicsCheckOptions};
use crate::planners::{
    GraspCandidate, GraspPlanner, GraspRequest, MedialAxisOptions, MedialAxisPlanner, SurfaceNormalOptions,
    SurfaceNormalPlanner,
};
use crate::tactile::sources::{evaluation_contacts, physics_tactile_series, TactileSeriesOptions, DEFAULT_GRIP_FORCE};
use crate::tactile::{CompactFrame, PadSpec, TactileArray};

mod tally;
use tally::PhysicsTally;

/// Configuration of [`run_grasp_benchmark`].
#[derive(Clone, Debug, Default)]
pub struct GraspBenchmarkConfig {
    /// The objects. Default: none (the standard suite uses the paper's eight KIT objects).
    pub objects: Vec<ObjectModel>,
    /// The hands, named in the results by [`Hand::name`]. Default: none (the standard suite
    /// uses the ARMAR-III hand, Table I, and the Barrett hand, Table II).
    pub hands: Vec<Hand>,
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
    /// With [`GraspBenchmarkConfig::record_candidates`], also store each closed candidate's
    /// static tactile frame in [`CandidateRecord::tactile`] (hands with a pad layout only).
    /// Default: `None` (no tactile frames).
    pub tactile: Option<TactileRecording>,
}

/// How the benchmark records tactile frames ([`GraspBenchmarkConfig::tactile`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TactileRecording {
    /// Total normal force of the fingers (N) distributed over the contacts by the force-closure
    /// solver ([`crate::tactile::sources::evaluation_contacts`]). Default:
    /// [`DEFAULT_GRIP_FORCE`] (10 N, nominal).
    pub grip_force: f64,
    /// Pad layouts by hand name; hands not listed use their stock layout
    /// ([`TactileArray::stock`]) if they are stock hands, else record nothing. Default: empty.
    pub layouts: Vec<(String, Vec<PadSpec>)>,
    /// Also record a tactile time series of every physics-checked grasp
    /// ([`CandidateRecord::tactile_series`], [`physics_tactile_series`] on rapier with these
    /// options); `None` records none. Default: `Some(TactileSeriesOptions::default())` (0.3 s
    /// of squeeze, a frame every 25 ms).
    pub series: Option<TactileSeriesOptions>,
}

impl Default for TactileRecording {
    fn default() -> Self {
        Self { grip_force: DEFAULT_GRIP_FORCE, layouts: Vec::new(), series: Some(TactileSeriesOptions::default()) }
    }
}

impl TactileRecording {
    /// The pads of `hand` (see [`TactileRecording::layouts`]), `None` if it has none.
    ///
    /// # Errors
    /// A listed layout that does not fit the hand ([`TactileArray::from_specs`]).
    pub fn array_for(&self, hand: &Hand) -> Result<Option<TactileArray>> {
        match self.layouts.iter().find(|(name, _)| name == hand.name()) {
            Some((_, specs)) => Ok(Some(TactileArray::from_specs(hand, specs)?)),
            None => Ok(TactileArray::stock(hand)),
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
    /// Volume of the grasp wrench space's 6-D hull, with the hull statistics on
    /// ([`crate::quality::QualityOptions::hull_statistics`]; 0 without force closure); absent
    /// otherwise (older files always carry it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<f64>,
    /// Facet count of that hull, with the hull statistics on (0 without force closure);
    /// absent otherwise and from older files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hull_facets: Option<usize>,
    /// Outcome of the physics hold check, if this grasp was simulated.
    pub physics_held: Option<bool>,
    /// Static tactile frame of the closed grasp (nonzero raw cells per pad), if recorded
    /// ([`GraspBenchmarkConfig::tactile`]); absent from older files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tactile: Option<CompactFrame>,
    /// Tactile time series of the physics-checked grasp squeezing the object (gravity off), if
    /// recorded ([`TactileRecording::series`]); absent from older files.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tactile_series: Vec<CompactFrame>,
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
    /// Of those, the ones where some gravity direction made the object slip but not drop.
    #[serde(default)]
    pub physics_slipped: usize,
    /// Of those, the ones where some gravity direction dropped the object.
    #[serde(default)]
    pub physics_dropped: usize,
    /// Of those, the ones where the squeeze alone (no gravity) moved the object farther than the
    /// drop distance: the simulated grip itself pushes it out.
    #[serde(default)]
    pub physics_grip_moved: usize,
    /// Of those, the ones whose simulation diverged (a body beyond 1e6 m or 1e6 m/s,
    /// [`opengrasp_core::CoreError::SimulationDiverged`]): simulated, not held, no other outcome.
    /// Written only when not 0, so records without divergences read as before.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub physics_diverged: usize,
    /// Of the simulated grasps not held (diverged ones aside), those whose squeeze alone, with
    /// gravity off, moved the object beyond the hold tolerance
    /// ([`crate::evaluator::PhysicsOutcome::grip_escapes`]): failures explained by the hand's
    /// actuation (its grip pushes the object out by itself). The rest of the failures
    /// (`physics_tested − physics_held − physics_diverged − physics_grip_escaped`) kept the
    /// grasp without gravity and lost it under gravity.
    #[serde(default)]
    pub physics_grip_escaped: usize,
    /// Of the simulated grasps, those the static torque-limited test
    /// ([`crate::evaluator::static_hold`], the object's friction) finds able to hold the
    /// object's weight in all six directions.
    #[serde(default)]
    pub static_holdable: usize,
    /// Of the simulated grasps whose simulation finished, those where the static test and the
    /// simulation agree (both hold or both do not).
    #[serde(default)]
    pub static_agree: usize,
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
    /// [`GraspError::Json`](crate::GraspError::Json) if serialisation fails.
    pub fn to_json(&self) -> Result<String> {
        Ok(serde_json::to_string_pretty(self)?)
    }

    /// A plain-text table for one hand: a row per object, a column per planner with the
    /// palm-contact candidates, force closure among them and among all candidates (the
    /// harness's reports add the paper's numbers).
    pub fn table(&self, hand: &str) -> String {
        let cells: Vec<&CellResult> = self.cells.iter().filter(|c| c.hand == hand).collect();
        let mut objects: Vec<&str> = Vec::new();
        let mut planners: Vec<&str> = Vec::new();
        for c in &cells {
            if !objects.contains(&c.object.as_str()) {
                objects.push(&c.object);
            }
            if !planners.contains(&c.planner.as_str()) {
                planners.push(&c.planner);
            }
        }
        let mut out = format!("{:<18}", format!("hand: {hand}"));
        for p in &planners {
            out.push_str(&format!(" | {:>26}", format!("{p}: palm/FC%")));
        }
        out.push('\n');
        for o in objects {
            out.push_str(&format!("{o:<18}"));
            for p in &planners {
                match self.cell(p, hand, o) {
                    Some(c) => out.push_str(&format!(
                        " | {:>5} {:>5.1}% (all {:>5.1}%)",
                        c.palm_contact, c.fc_percent_palm, c.fc_percent_all
                    )),
                    None => out.push_str(&format!(" | {:>26}", "-")),
                }
            }
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
/// Planner errors; evaluator errors.
pub fn run_grasp_benchmark_with(
    config: &GraspBenchmarkConfig,
    planners: &[&dyn GraspPlanner],
) -> Result<GraspBenchmarkResults> {
    let mut cells = Vec::new();
    for hand in &config.hands {
        for object in &config.objects {
            let mut evaluator = GraspEvaluator::new(hand, object, config.evaluator.clone())?;
            let info = evaluator.hand_info().clone();
            let tactile = match &config.tactile {
                Some(t) if config.record_candidates => t.array_for(hand)?.map(|a| (a, t.grip_force)),
                _ => None,
            };
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
                let mut physics = PhysicsTally::default();
                let mut held_by_evaluation = vec![None; evaluations.len()];
                let mut series_by_evaluation = vec![Vec::new(); evaluations.len()];
                if config.physics_per_cell > 0 && !fc_palm.is_empty() {
                    let m = config.physics_per_cell.min(fc_palm.len());
                    for j in 0..m {
                        let k = fc_palm[j * fc_palm.len() / m];
                        let check = crate::evaluator::physics_check(hand, object, &evaluations[k], &config.physics);
                        let statics = crate::evaluator::static_hold(
                            hand,
                            object,
                            &evaluations[k],
                            &crate::evaluator::StaticHoldOptions::default(),
                        )?;
                        let Some(held) = physics.add(check, statics.holdable(), config.physics.drop_translation)?
                        else {
                            // A diverged simulation held nothing, and its squeeze has no series.
                            held_by_evaluation[k] = Some(false);
                            continue;
                        };
                        held_by_evaluation[k] = Some(held);
                        if let (Some((array, _)), Some(options)) =
                            (&tactile, config.tactile.as_ref().and_then(|t| t.series.as_ref()))
                        {
                            let series = physics_tactile_series::<opengrasp_core::physics::RapierBackend>(
                                hand,
                                object,
                                &evaluations[k],
                                array,
                                options,
                            )?;
                            series_by_evaluation[k] = series.iter().map(|f| f.compact(array)).collect();
                        }
                    }
                }
                let candidate_records = if config.record_candidates {
                    let quality = &config.evaluator.quality;
                    let stats = quality.compute_hull && quality.hull_statistics;
                    let frames = match &tactile {
                        Some((array, grip)) => tactile_frames(config, hand, object, &evaluations, array, *grip)?,
                        None => vec![None; evaluations.len()],
                    };
                    chosen
                        .iter()
                        .zip(&evaluations)
                        .zip(held_by_evaluation)
                        .zip(frames)
                        .zip(series_by_evaluation)
                        .map(|((((&i, e), held), tactile), tactile_series)| CandidateRecord {
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
                            volume: stats.then(|| e.quality.and_then(|q| q.volume).unwrap_or(0.0)),
                            hull_facets: stats.then(|| e.quality.and_then(|q| q.hull_facets).unwrap_or(0)),
                            physics_held: held,
                            tactile,
                            tactile_series,
                        })
                        .collect()
                } else {
                    Vec::new()
                };
                let pct = |a: usize, b: usize| if b == 0 { 0.0 } else { 100.0 * a as f64 / b as f64 };
                cells.push(CellResult {
                    planner: planner.name().to_string(),
                    hand: hand.name().to_string(),
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
                    physics_tested: physics.tested,
                    physics_held: physics.held,
                    physics_slipped: physics.slipped,
                    physics_dropped: physics.dropped,
                    physics_grip_moved: physics.grip_moved,
                    physics_diverged: physics.diverged,
                    physics_grip_escaped: physics.grip_escaped,
                    static_holdable: physics.static_holdable,
                    static_agree: physics.static_agree,
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

/// Static tactile frames of the closed evaluations (`None` for the others), with the contact
/// model and object frame the evaluator uses.
fn tactile_frames(
    config: &GraspBenchmarkConfig,
    hand: &Hand,
    object: &ObjectModel,
    evaluations: &[crate::evaluator::GraspEvaluation],
    array: &TactileArray,
    grip_force: f64,
) -> Result<Vec<Option<CompactFrame>>> {
    let frame = ObjectFrame::from_points(object.center_of_mass(), object.mesh.vertices())?;
    let mut model = config.evaluator.quality.contact;
    model.friction = config.evaluator.friction.unwrap_or(object.friction);
    evaluations
        .iter()
        .map(|e| {
            if e.status != EvaluationStatus::Closed || e.contacts.is_empty() {
                return Ok(None);
            }
            let contacts = evaluation_contacts(hand, e, &frame, &model, grip_force)?;
            Ok(Some(array.read(&contacts).compact(array)))
        })
        .collect()
}

/// Serde's skip test for counts written only when not 0.
fn is_zero(n: &usize) -> bool {
    *n == 0
}
