//! The benchmark suite: reference planners and your own, graded in one run.
//!
//! A [`Suite`] collects grasp planners (any [`GraspPlanner`]), motion planners (factories of
//! any [`MotionPlanner`]: every scene × planner job gets a fresh instance), hands, objects and
//! motion scenes, runs them in parallel with rayon and returns a [`ResultsFile`] with full
//! provenance. Jobs are independent and seeded (grasp: one job per hand × object, every
//! planner on it; motion: one job per scene × planner with all its runs in order when the
//! scene's environment is shared, so setup work such as a PRM roadmap is reused, otherwise one
//! job per run with a fresh planner), and their results are collected in job order, so the
//! records of a parallel run equal those of a serial one for the same seeds (only the timing
//! fields differ).
//!
//! [`SuiteSize`] picks the reference suite's size:
//!
//! | size | grasp | motion |
//! | --- | --- | --- |
//! | `Tiny` | salt can, Barrett hand, 4 candidates per cell | planar 2-link arm ([`planar_scene`]), RRT-Connect + PRM (200 nodes), 2 runs |
//! | `Default` | the 8 paper objects × ARMAR-III and Barrett hands, at most 128 candidates per cell (even stride over each planner's list), physics hold check of 2 force-closure palm grasps per cell | the 4 scenes of [`crate::scenes`] (ARMAR-III kitchen standard and IK-based, their 7-DoF stand-ins), RRT-Connect, PRM (600 nodes; 150 on the IK-based scenes, whose setup runs every run), IK-RRT (IK-based scenes only), 20 runs; 1 Clean the Table episode for RRT-Connect and IK-RRT |
//! | `Paper` | every candidate (Tables I and II), physics check of 5 grasps per cell | as `Default` with 100 runs (Table III) and 5 Clean the Table episodes |
//!
//! Clean the Table (scene 3, [`crate::clean_table`]) runs whole episodes: its
//! grasp and place queries are filed as runs of [`CLEAN_THE_TABLE_SCENE`] (run
//! `episode · 8 + 2 · object + {0: grasp, 1: place}`) and each episode as an
//! [`EpisodeRecord`](crate::results::EpisodeRecord).
//!
//! The default size finishes in a few minutes on two cores in release mode: `opengrasp run
//! all` took 97 s wall (176 s CPU) on a shared two-core Xeon VM (grasp: 4040 candidates
//! evaluated and 51 physics checks; motion: 200 runs, dominated by post-processing and the PRM
//! roadmaps, and two Clean the Table episodes of about 25 s each, mostly the certified
//! shortcutting of the 11-DoF paths). `SuiteSize::Paper` is the full paper-sized suite.
//!
//! ```
//! use opengrasp_bench::suite::{planar_scene, Suite};
//! use opengrasp_motion::planners::RrtConnect;
//!
//! # fn main() -> opengrasp_bench::Result<()> {
//! let results = Suite::new()
//!     .motion_planner("default options", || Box::new(RrtConnect::default()))
//!     .motion_scene(planar_scene())
//!     .runs(2)
//!     .run()?;
//! assert_eq!(results.motion.unwrap().runs.len(), 2);
//! # Ok(())
//! # }
//! ```

mod run;

use std::sync::Arc;
use std::time::Instant;

use crate::scenes::{armar_ik_scene, armar_standard_scene, ik_scene, standard_scene, CheckerKind};
use nalgebra::{Isometry3, Vector3};
use opengrasp_core::hand::Hand;
use opengrasp_core::model::{samples, JointGroup};
use opengrasp_core::object::ObjectModel;
use opengrasp_grasp::benchmark::GraspBenchmarkConfig;
use opengrasp_grasp::planners::{GraspPlanner, MedialAxisPlanner, SurfaceNormalPlanner};
use opengrasp_motion::benchmark::{BenchmarkOptions, BenchmarkScene, SceneInstance};
use opengrasp_motion::planners::{IkRrt, Prm, PrmOptions, RrtConnect};
use opengrasp_motion::validity::{ObstacleBox, SphereWorld};
use opengrasp_motion::{Goal, MotionPlanner};

use crate::paper::PAPER_OBJECTS;
use crate::results::{Category, Error, PlannerInfo, Provenance, Result, ResultsFile, Shard};
use crate::stock::{stock_hand, stock_object};

/// Scene name of the Clean the Table queries in the results (scene 3).
pub const CLEAN_THE_TABLE_SCENE: &str = crate::clean_table::SCENE_NAME;

/// Size of the reference suite (see the [module docs](self) for what each contains).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SuiteSize {
    /// A seconds-long smoke test.
    Tiny,
    /// A few minutes on two cores in release mode.
    #[default]
    Default,
    /// The paper's sizes (every grasp candidate, 100 motion runs): tens of minutes or more.
    Paper,
}

impl SuiteSize {
    /// `"tiny"`, `"default"` or `"paper"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Tiny => "tiny",
            Self::Default => "default",
            Self::Paper => "paper",
        }
    }

    /// Grasp candidates evaluated per cell at most (`None`: all).
    pub fn max_candidates(self) -> Option<usize> {
        match self {
            Self::Tiny => Some(4),
            Self::Default => Some(128),
            Self::Paper => None,
        }
    }

    /// Clean the Table episodes per motion planner (none in the tiny suite).
    pub fn episodes(self) -> usize {
        match self {
            Self::Tiny => 0,
            Self::Default => 1,
            Self::Paper => 5,
        }
    }

    /// Force-closure palm-contact grasps per grasp cell sent to the physics hold check.
    pub fn physics_per_cell(self) -> usize {
        match self {
            Self::Tiny => 0,
            Self::Default => 2,
            Self::Paper => 5,
        }
    }

    /// Motion runs per planner per scene.
    pub fn runs(self) -> usize {
        match self {
            Self::Tiny => 2,
            Self::Default => 20,
            Self::Paper => 100,
        }
    }
}

/// Progress of a running suite, passed to the [`Suite::on_progress`] callback.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    /// The benchmark the update is about.
    pub category: Category,
    /// Units done (grasp: hand × object cells; motion: runs).
    pub done: usize,
    /// Units in total.
    pub total: usize,
    /// What just finished (e.g. `"barrett/salt_can"` or `"PRM on standard (7-DoF stand-in)"`).
    pub label: String,
}

/// A factory of motion planners given the scene name (each job gets a fresh instance).
pub type MotionPlannerFactory = Box<dyn Fn(&str) -> Box<dyn MotionPlanner> + Send + Sync>;

struct MotionEntry {
    info: PlannerInfo,
    factory: MotionPlannerFactory,
    /// Scenes this planner runs on (`None`: all).
    scenes: Option<Vec<String>>,
}

struct GraspEntry {
    info: PlannerInfo,
    planner: Box<dyn GraspPlanner>,
}

type ProgressFn = Arc<dyn Fn(&Progress) + Send + Sync>;

/// A benchmark suite under construction; [`Suite::run`] runs it.
pub struct Suite {
    size_label: String,
    grasp_planners: Vec<GraspEntry>,
    grasp: GraspBenchmarkConfig,
    motion_planners: Vec<MotionEntry>,
    motion_scenes: Vec<BenchmarkScene>,
    motion: BenchmarkOptions,
    episodes: usize,
    jobs: usize,
    shard: Option<Shard>,
    progress: Option<ProgressFn>,
}

impl Default for Suite {
    fn default() -> Self {
        Self::new()
    }
}

impl Suite {
    /// An empty suite: no planners, no scenes; grasp hands and objects as in
    /// [`GraspBenchmarkConfig::default`] (both hands, the 8 paper objects, every candidate),
    /// motion options as in [`BenchmarkOptions::default`]; all available cores.
    pub fn new() -> Self {
        Self {
            size_label: "custom".into(),
            grasp_planners: Vec::new(),
            grasp: GraspBenchmarkConfig::default(),
            motion_planners: Vec::new(),
            motion_scenes: Vec::new(),
            motion: BenchmarkOptions::default(),
            episodes: 0,
            jobs: std::thread::available_parallelism().map_or(1, |n| n.get()),
            shard: None,
            progress: None,
        }
    }

    /// The reference suite of the given size: both benchmarks.
    pub fn standard(size: SuiteSize) -> Self {
        Self::new().with_reference_grasp(size).with_reference_motion(size).labelled(size.name())
    }

    /// Sets the size label recorded in the provenance (default `"custom"`).
    pub fn labelled(mut self, label: &str) -> Self {
        self.size_label = label.to_string();
        self
    }

    /// Adds the reference grasp planners (medial axis, surface normals) and sets hands,
    /// objects and candidate count for `size`.
    ///
    /// # Panics
    /// Never: the stock hands and objects it names exist (a test builds every one).
    pub fn with_reference_grasp(mut self, size: SuiteSize) -> Self {
        let ma = self.grasp.medial_axis.clone();
        let sn = self.grasp.surface_normal.clone();
        self = self
            .grasp_planner(format!("{ma:?}"), MedialAxisPlanner::new(ma))
            .grasp_planner(format!("{sn:?}"), SurfaceNormalPlanner::new(sn));
        self.grasp.max_candidates = size.max_candidates();
        self.grasp.physics_per_cell = size.physics_per_cell();
        match size {
            SuiteSize::Tiny => {
                self.grasp.objects = vec![stock_object("salt_can").expect("a stock object")];
                self.grasp.hands = vec![stock_hand("barrett").expect("a stock hand")];
            }
            SuiteSize::Default | SuiteSize::Paper => {
                self.grasp.objects =
                    PAPER_OBJECTS.iter().map(|(_, n)| stock_object(n).expect("a stock object")).collect();
                self.grasp.hands = ["armar3", "barrett"].map(|h| stock_hand(h).expect("a stock hand")).to_vec();
            }
        }
        self.size_label = size.name().into();
        self
    }

    /// Adds the reference motion planners and scenes for `size` and sets the runs.
    pub fn with_reference_motion(mut self, size: SuiteSize) -> Self {
        self.motion.runs = size.runs();
        self.episodes = size.episodes();
        match size {
            SuiteSize::Tiny => {
                let prm = PrmOptions { nodes: 200, ..PrmOptions::default() };
                self = self
                    .motion_planner(format!("{:?}", RrtConnect::default().options), || Box::new(RrtConnect::default()))
                    .motion_planner(format!("{prm:?}"), move || Box::new(Prm::new(prm)))
                    .motion_scene(planar_scene());
            }
            SuiteSize::Default | SuiteSize::Paper => {
                let prm = PrmOptions::default();
                // Smaller roadmaps where the environment changes every run (setup per run),
                // as in the paper's IK-based scene.
                let prm_ik = PrmOptions { nodes: 150, ..prm };
                let standard_scenes = [armar_standard_scene(), standard_scene(CheckerKind::Exact)];
                let ik_scenes = [armar_ik_scene(), ik_scene(CheckerKind::Exact)];
                let ik_names: Vec<String> = ik_scenes.iter().map(|s| s.name.clone()).collect();
                let prm_names = ik_names.clone();
                // PRM stays off Clean the Table: its environment changes with every query
                // (objects move), so a roadmap would be rebuilt per query.
                let prm_scenes: Vec<String> =
                    standard_scenes.iter().chain(&ik_scenes).map(|s| s.name.clone()).collect();
                let mut ik_rrt_scenes = ik_names;
                ik_rrt_scenes.push(CLEAN_THE_TABLE_SCENE.to_string());
                self = self
                    .motion_planner(format!("{:?}", RrtConnect::default().options), || Box::new(RrtConnect::default()))
                    .add_motion(
                        Some(prm_scenes),
                        format!("{prm:?}; nodes = {} on the IK-based scenes", prm_ik.nodes),
                        Box::new(move |scene: &str| {
                            Box::new(Prm::new(if prm_names.iter().any(|n| n == scene) { prm_ik } else { prm }))
                        }),
                    )
                    .motion_planner_on(ik_rrt_scenes, format!("{:?}", IkRrt::default().options), || {
                        Box::new(IkRrt::default())
                    });
                for s in standard_scenes.into_iter().chain(ik_scenes) {
                    self = self.motion_scene(s);
                }
            }
        }
        self.size_label = size.name().into();
        self
    }

    /// Adds a grasp planner; `parameters` describes its settings in the results.
    pub fn grasp_planner(mut self, parameters: impl Into<String>, planner: impl GraspPlanner + 'static) -> Self {
        let info = PlannerInfo { name: planner.name().to_string(), parameters: parameters.into() };
        self.grasp_planners.push(GraspEntry { info, planner: Box::new(planner) });
        self
    }

    /// Adds a motion planner, run on every scene; `factory` makes a fresh instance per scene
    /// and `parameters` describes its settings in the results.
    pub fn motion_planner(
        self,
        parameters: impl Into<String>,
        factory: impl Fn() -> Box<dyn MotionPlanner> + Send + Sync + 'static,
    ) -> Self {
        self.add_motion(None, parameters.into(), Box::new(move |_: &str| factory()))
    }

    /// As [`Suite::motion_planner`], run only on the named scenes.
    pub fn motion_planner_on(
        self,
        scenes: Vec<String>,
        parameters: impl Into<String>,
        factory: impl Fn() -> Box<dyn MotionPlanner> + Send + Sync + 'static,
    ) -> Self {
        self.add_motion(Some(scenes), parameters.into(), Box::new(move |_: &str| factory()))
    }

    /// As [`Suite::motion_planner`] with options that depend on the scene: `factory` gets the
    /// scene's name. The planner's name must not depend on it.
    pub fn motion_planner_per_scene(
        self,
        parameters: impl Into<String>,
        factory: impl Fn(&str) -> Box<dyn MotionPlanner> + Send + Sync + 'static,
    ) -> Self {
        self.add_motion(None, parameters.into(), Box::new(factory))
    }

    fn add_motion(mut self, scenes: Option<Vec<String>>, parameters: String, factory: MotionPlannerFactory) -> Self {
        let name = factory("").name().to_string();
        self.motion_planners.push(MotionEntry { info: PlannerInfo { name, parameters }, factory, scenes });
        self
    }

    /// Adds a motion benchmark scene.
    pub fn motion_scene(mut self, scene: BenchmarkScene) -> Self {
        self.motion_scenes.push(scene);
        self
    }

    /// Sets the grasp hands (stock ones from [`crate::stock`], or any [`Hand`]).
    pub fn hands(mut self, hands: Vec<Hand>) -> Self {
        self.grasp.hands = hands;
        self
    }

    /// Sets the grasp objects (stock ones from [`crate::stock`], or any [`ObjectModel`]).
    pub fn objects(mut self, objects: Vec<ObjectModel>) -> Self {
        self.grasp.objects = objects;
        self
    }

    /// Sets the grasp candidates evaluated per cell at most (`None`: all).
    pub fn max_candidates(mut self, max: Option<usize>) -> Self {
        self.grasp.max_candidates = max;
        self
    }

    /// Replaces the grasp benchmark configuration (hands, objects, evaluator, ...); the
    /// reference planners already added keep their options.
    pub fn grasp_config(mut self, config: GraspBenchmarkConfig) -> Self {
        self.grasp = config;
        self
    }

    /// Replaces the motion benchmark options (runs, seed, time limit, validator steps, ...).
    pub fn motion_options(mut self, options: BenchmarkOptions) -> Self {
        self.motion = options;
        self
    }

    /// Sets the Clean the Table episodes per motion planner (0: none). Each episode carries
    /// the red table's four objects to the sideboard (scene 3, see
    /// [`crate::clean_table`]); every motion planner runs them unless it was added
    /// with [`Suite::motion_planner_on`] without [`CLEAN_THE_TABLE_SCENE`] in its list.
    pub fn clean_the_table(mut self, episodes: usize) -> Self {
        self.episodes = episodes;
        self
    }

    /// Sets how many force-closure palm-contact grasps per grasp cell go through the
    /// physics hold check (0: none).
    pub fn physics_per_cell(mut self, n: usize) -> Self {
        self.grasp.physics_per_cell = n;
        self
    }

    /// Keeps every evaluated grasp candidate in the results ([`GraspBenchmarkConfig::record_candidates`]).
    pub fn record_grasps(mut self, record: bool) -> Self {
        self.grasp.record_candidates = record;
        self
    }

    /// Also computes the grasp wrench space hull's volume and facet count of every
    /// force-closure grasp ([`opengrasp_grasp::quality::QualityOptions::hull_statistics`];
    /// the full 6-D hull, several times the cost of the other metrics). Off by default and in
    /// every stock suite size; recorded with [`Suite::record_grasps`].
    pub fn hull_statistics(mut self, on: bool) -> Self {
        self.grasp.evaluator.quality.hull_statistics = on;
        self
    }

    /// With [`Suite::record_grasps`], also stores each closed grasp's static tactile frame
    /// (hands with pads: the stock hands, or layouts given in `recording`;
    /// [`GraspBenchmarkConfig::tactile`]); `None` records none (the default).
    pub fn record_tactile(mut self, recording: Option<opengrasp_grasp::benchmark::TactileRecording>) -> Self {
        self.grasp.tactile = recording;
        self
    }

    /// Sets the motion runs per planner per scene.
    pub fn runs(mut self, runs: usize) -> Self {
        self.motion.runs = runs;
        self
    }

    /// Sets the base seed of both benchmarks.
    pub fn seed(mut self, seed: u64) -> Self {
        self.grasp.seed = seed;
        self.motion.seed = seed;
        self
    }

    /// Sets the worker threads (1: serial; default: all cores).
    pub fn jobs(mut self, jobs: usize) -> Self {
        self.jobs = jobs;
        self
    }

    /// Sets the motion benchmark's protocol (steps, shortcut checks, setup timing; see
    /// [`opengrasp_motion::protocol`]); runs, seed and time limit are kept.
    pub fn protocol(mut self, protocol: opengrasp_motion::protocol::Protocol) -> Self {
        self.motion = protocol.apply(self.motion);
        self
    }

    /// Runs only one slice of the suite (see [`Shard`]); `opengrasp merge` (or
    /// [`crate::results::merge`]) combines the shards' files into the unsharded results.
    pub fn shard(mut self, shard: Shard) -> Self {
        self.shard = Some(shard);
        self
    }

    /// Calls `f` after every finished job.
    pub fn on_progress(mut self, f: impl Fn(&Progress) + Send + Sync + 'static) -> Self {
        self.progress = Some(Arc::new(f));
        self
    }

    /// Keeps only the planners whose name matches one of `names` (ASCII case-insensitive).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the unknown planners if a name matches none.
    pub fn retain_planners(mut self, names: &[String]) -> Result<Self> {
        let matches = |n: &str| names.iter().any(|x| x.eq_ignore_ascii_case(n));
        let unknown: Vec<&String> = names
            .iter()
            .filter(|x| {
                !self.grasp_planners.iter().any(|p| p.info.name.eq_ignore_ascii_case(x))
                    && !self.motion_planners.iter().any(|p| p.info.name.eq_ignore_ascii_case(x))
            })
            .collect();
        if !unknown.is_empty() {
            return Err(Error::InvalidOption {
                name: "planner",
                reason: format!("unknown planner(s) {unknown:?}; known: {:?}", self.planner_names()),
            });
        }
        self.grasp_planners.retain(|p| matches(&p.info.name));
        self.motion_planners.retain(|p| matches(&p.info.name));
        Ok(self)
    }

    /// Keeps only the motion scenes whose name matches one of `names` (ASCII
    /// case-insensitive; [`CLEAN_THE_TABLE_SCENE`] keeps or drops the Clean the Table
    /// episodes).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the unknown scenes if a name matches none.
    pub fn retain_scenes(mut self, names: &[String]) -> Result<Self> {
        let known = self.scene_names();
        let unknown: Vec<&String> = names.iter().filter(|x| !known.iter().any(|k| k.eq_ignore_ascii_case(x))).collect();
        if !unknown.is_empty() {
            return Err(Error::InvalidOption {
                name: "scene",
                reason: format!("unknown scene(s) {unknown:?}; known: {known:?}"),
            });
        }
        let matches = |n: &str| names.iter().any(|x| x.eq_ignore_ascii_case(n));
        self.motion_scenes.retain(|s| matches(&s.name));
        if !matches(CLEAN_THE_TABLE_SCENE) {
            self.episodes = 0;
        }
        Ok(self)
    }

    /// Names of the planners in the suite (grasp, then motion).
    pub fn planner_names(&self) -> Vec<String> {
        self.grasp_planners
            .iter()
            .map(|p| p.info.name.clone())
            .chain(self.motion_planners.iter().map(|p| p.info.name.clone()))
            .collect()
    }

    /// Names of the motion scenes.
    pub fn scene_names(&self) -> Vec<String> {
        let mut names: Vec<String> = self.motion_scenes.iter().map(|s| s.name.clone()).collect();
        if self.episodes > 0 {
            names.push(CLEAN_THE_TABLE_SCENE.to_string());
        }
        names
    }

    /// Runs the suite: the grasp benchmark if it has grasp planners, the motion benchmark if
    /// it has motion planners and scenes.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for zero jobs or an empty suite; grasp benchmark errors
    /// (unknown object, planner errors). Motion failures are recorded in the runs.
    pub fn run(&self) -> Result<ResultsFile> {
        if self.jobs == 0 {
            return Err(Error::InvalidOption { name: "jobs", reason: "must be at least 1".into() });
        }
        let has_motion = !self.motion_planners.is_empty() && !self.scene_names().is_empty();
        if self.grasp_planners.is_empty() && !has_motion {
            return Err(Error::InvalidOption { name: "suite", reason: "no planners (or no scenes) to run".into() });
        }
        let start = Instant::now();
        let mut provenance = Provenance::collect(&self.size_label, self.jobs);
        provenance.shard = self.shard;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.jobs)
            .build()
            .map_err(|e| Error::InvalidOption { name: "jobs", reason: e.to_string() })?;
        let grasp = if self.grasp_planners.is_empty() { None } else { Some(pool.install(|| self.run_grasp())?) };
        let motion = if has_motion { Some(pool.install(|| self.run_motion())) } else { None };
        provenance.finish(start.elapsed().as_secs_f64());
        let mut file = ResultsFile::new(provenance);
        file.grasp = grasp;
        file.motion = motion;
        Ok(file)
    }
}

/// A small motion scene for tests and examples: the planar two-link arm (0.5 m and 0.4 m
/// links) from `(1.2, 0.3)` to `(-1.2, 0.3)` rad around a 0.1 × 0.1 × 0.5 m post at
/// x = 0.6 m (closed-form sphere-model checker). Named `"planar post"`; shared environment.
pub fn planar_scene() -> BenchmarkScene {
    BenchmarkScene {
        name: "planar post".into(),
        shared_environment: true,
        generate: Box::new(|_seed| {
            let robot = Arc::new(samples::planar_arm(&[0.5, 0.4])?);
            let group = JointGroup::all(&robot, "arm")?;
            let post = ObstacleBox::new("post", Isometry3::translation(0.6, 0.0, 0.0), Vector3::new(0.1, 0.1, 0.5));
            let world =
                SphereWorld::new(robot.clone(), group.clone(), vec![0.0, 0.0], Isometry3::identity(), vec![post])?;
            Ok(SceneInstance {
                robot,
                group,
                q_full: vec![0.0, 0.0],
                tip: None,
                start: vec![1.2, 0.3],
                goal: Goal::Configuration(vec![-1.2, 0.3]),
                checker: Box::new(world),
                planning_checker: None,
                certifier: None,
            })
        }),
    }
}
