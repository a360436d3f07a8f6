//! Motion problem sets from files as benchmark scenes (`opengrasp run motion --problems PATH`).
//!
//! A set (JSON problem set or MotionBenchMaker directory, see
//! [`opengrasp_motion::problem_set`]) becomes one [`BenchmarkScene`] named after the set:
//! run *r* (seed `base_seed + r`) plans problem *r* of the set — the choice depends on the run
//! index only, never on random draws, and runs past the set's size wrap around. The
//! environment differs between problems, so it is not shared (planner setup runs per run).
//! Every run is graded like the kitchen scenes' (validators, metrics, OMPL logs, reports).
//!
//! ```no_run
//! use opengrasp_bench::problem_sets::load_problem_sets;
//! use opengrasp_bench::suite::Suite;
//!
//! # fn main() -> opengrasp_bench::Result<()> {
//! let sets = load_problem_sets("resources/panda/problems/table_pick_panda")?;
//! let results = Suite::new().seed(0).with_problem_sets(sets, 0).run()?;
//! println!("{} runs", results.motion.unwrap().runs.len());
//! # Ok(())
//! # }
//! ```

use std::path::Path;
use std::sync::Arc;

use opengrasp_motion::benchmark::BenchmarkScene;
use opengrasp_motion::planners::{IkRrt, Prm, PrmOptions, RrtConnect, RrtConnectOptions};
use opengrasp_motion::problem_set::{self, LoadedProblemSet, PlanningModel};
use opengrasp_motion::validity::cover::GreedyCoverOptions;
use opengrasp_motion::Goal;

use crate::suite::Suite;
use crate::Result;

/// PRM roadmap size on problem sets (the roadmap is rebuilt every run, as on the kitchen's
/// IK-based scene).
pub const PROBLEM_SET_PRM_NODES: usize = 150;

/// Loads the problem sets at `path` (a JSON problem-set file, an MBM set directory or a
/// directory of MBM sets) with their robots.
///
/// # Errors
/// The loader's errors ([`opengrasp_motion::MotionError`]'s `ProblemSet*` variants, robot
/// loading errors) as [`crate::Error::Motion`].
pub fn load_problem_sets(path: impl AsRef<Path>) -> Result<Vec<LoadedProblemSet>> {
    let sets = problem_set::load(path)?;
    Ok(sets.iter().map(LoadedProblemSet::new).collect::<opengrasp_motion::Result<_>>()?)
}

/// The benchmark scene of a loaded set: run `r` (seed `base_seed + r`) is problem
/// `r mod len`.
pub fn problem_set_scene(set: Arc<LoadedProblemSet>, base_seed: u64) -> BenchmarkScene {
    problem_set_scene_with(set, base_seed, PlanningModel::Exact)
}

/// What the planners of problem-set scenes check states with; the validators always use the
/// exact checker (meshes and primitives).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum ProblemSetChecker {
    /// The exact checker (default).
    #[default]
    Exact,
    /// The robot's guaranteed greedy sphere cover with the SRDF's self-collision pairs
    /// ([`LoadedProblemSet::layered_sphere_model`]); scenes are named `"<set> (spheres)"`.
    Spheres(GreedyCoverOptions),
}

/// Like [`problem_set_scene`], planned on `model` (a sphere-model scene is named
/// `"<set> (spheres)"`).
pub fn problem_set_scene_with(set: Arc<LoadedProblemSet>, base_seed: u64, model: PlanningModel) -> BenchmarkScene {
    let name = match model {
        PlanningModel::Exact => set.name().to_string(),
        PlanningModel::Spheres(_) => format!("{} (spheres)", set.name()),
    };
    BenchmarkScene {
        name,
        shared_environment: false,
        generate: Box::new(move |seed| {
            let run = seed.wrapping_sub(base_seed);
            let index = (run % set.len().max(1) as u64) as usize;
            set.instance_with(index, &model)
        }),
    }
}

fn has_pose_goals(set: &LoadedProblemSet) -> bool {
    (0..set.len()).any(|i| matches!(set.goal(i), Some(Goal::Pose(_))))
}

impl Suite {
    /// Adds the problem sets as motion scenes ([`problem_set_scene`], `base_seed` must be the
    /// suite's seed) with the reference planners — RRT-Connect, PRM
    /// ([`PROBLEM_SET_PRM_NODES`] nodes) and IK-RRT (on sets with pose goals only) — and sets
    /// the runs to the largest set's size, so every problem is planned once per planner.
    pub fn with_problem_sets(self, sets: Vec<LoadedProblemSet>, base_seed: u64) -> Self {
        let scenes = sets.into_iter().map(|set| (set, PlanningModel::Exact)).collect();
        self.with_problem_set_scenes(scenes, base_seed, RrtConnectOptions::default())
    }

    /// Like [`Suite::with_problem_sets`], the planners checking states as `checker` says
    /// (graded by the exact checker either way). On the sphere model RRT-Connect plans with
    /// [`RrtConnectOptions::vamp_like`] (VAMP's tree balancing, range 1.0), the settings the
    /// sphere model's planning times are measured with; on the meshes with the defaults.
    ///
    /// # Errors
    /// The sphere cover's errors ([`LoadedProblemSet::sphere_model`]) as
    /// [`crate::Error::Motion`].
    pub fn with_problem_sets_checked_by(
        self,
        sets: Vec<LoadedProblemSet>,
        base_seed: u64,
        checker: ProblemSetChecker,
    ) -> Result<Self> {
        let scenes = sets
            .into_iter()
            .map(|set| {
                let model = match checker {
                    ProblemSetChecker::Exact => PlanningModel::Exact,
                    ProblemSetChecker::Spheres(o) => PlanningModel::Spheres(Arc::new(set.layered_sphere_model(o)?)),
                };
                Ok((set, model))
            })
            .collect::<Result<_>>()?;
        let rrt = match checker {
            ProblemSetChecker::Exact => RrtConnectOptions::default(),
            ProblemSetChecker::Spheres(_) => RrtConnectOptions::vamp_like(),
        };
        Ok(self.with_problem_set_scenes(scenes, base_seed, rrt))
    }

    fn with_problem_set_scenes(
        mut self,
        sets: Vec<(LoadedProblemSet, PlanningModel)>,
        base_seed: u64,
        rrt: RrtConnectOptions,
    ) -> Self {
        let runs = sets.iter().map(|s| s.0.len()).max().unwrap_or(0);
        let pose: Vec<bool> = sets.iter().map(|s| has_pose_goals(&s.0)).collect();
        let scenes: Vec<BenchmarkScene> =
            sets.into_iter().map(|(set, model)| problem_set_scene_with(Arc::new(set), base_seed, model)).collect();
        let names: Vec<String> = scenes.iter().map(|s| s.name.clone()).collect();
        let pose_sets: Vec<String> = names.iter().zip(&pose).filter(|(_, &p)| p).map(|(n, _)| n.clone()).collect();
        let prm = PrmOptions { nodes: PROBLEM_SET_PRM_NODES, ..PrmOptions::default() };
        self = self
            .motion_planner_on(names.clone(), format!("{rrt:?}"), move || Box::new(RrtConnect::new(rrt)))
            .motion_planner_on(names, format!("{prm:?}"), move || Box::new(Prm::new(prm)));
        if !pose_sets.is_empty() {
            self = self
                .motion_planner_on(pose_sets, format!("{:?}", IkRrt::default().options), || Box::new(IkRrt::default()));
        }
        for scene in scenes {
            self = self.motion_scene(scene);
        }
        self.runs(runs)
    }
}
