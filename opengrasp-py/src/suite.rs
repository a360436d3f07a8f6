//! `opengrasp.Suite`: the standard benchmark suite with Python planners next to the Rust
//! reference planners; `opengrasp.Results`; results files as dicts; high-score submission.
//!
//! The suite runs in Rust with the GIL released, on its worker threads; a Python planner's
//! `plan` takes the GIL, so Python planners run one at a time while Rust planners and the
//! evaluation (grasp evaluator, validators, metrics) keep running in parallel.

use std::path::PathBuf;
use std::time::Duration;

use opengrasp_bench::report::{self, Format};
use opengrasp_bench::results::ResultsFile;
use opengrasp_bench::suite::{Suite, SuiteSize};
use opengrasp_highscore::{BenchmarkKind, Submitter};
use opengrasp_motion::benchmark::BenchmarkOptions;
use opengrasp_motion::MotionPlanner;
use pyo3::prelude::*;

use crate::convert::to_py;
use crate::errors::{guard, Error, Result};
use crate::planners::{planner_name, PyGraspPlanner, PyMotionPlanner};
use crate::scene::scene_by_name;

fn size(name: &str) -> Result<SuiteSize> {
    match name.to_ascii_lowercase().as_str() {
        "tiny" => Ok(SuiteSize::Tiny),
        "default" => Ok(SuiteSize::Default),
        "paper" => Ok(SuiteSize::Paper),
        _ => Err(Error::input(format!("unknown suite size {name:?}; known: tiny, default, paper"))),
    }
}

fn format(name: &str) -> Result<Format> {
    match name.to_ascii_lowercase().as_str() {
        "table" | "text" => Ok(Format::Table),
        "markdown" | "md" => Ok(Format::Markdown),
        "csv" => Ok(Format::Csv),
        _ => Err(Error::input(format!("unknown report format {name:?}; known: table, markdown, csv"))),
    }
}

/// A benchmark suite under construction (a builder: each method returns the suite).
///
/// `Suite()` is empty; `Suite("tiny" | "default" | "paper")` is the reference suite of that
/// size (Rust reference planners, stock hands, objects and scenes). Add Python planners with
/// `grasp_planner` and `motion_planner`, then `run()`.
#[pyclass(name = "Suite", module = "opengrasp")]
pub struct PySuite {
    suite: Option<Suite>,
    runs: usize,
    seed: u64,
    time_limit: Option<f64>,
    /// The seed the problem sets were added with (their run r is seed + r).
    problem_set_seed: Option<u64>,
}

impl PySuite {
    fn update(&mut self, f: impl FnOnce(Suite) -> Result<Suite>) -> Result<()> {
        let suite = self.suite.take().ok_or_else(|| Error::input("the suite is being run"))?;
        // `Suite` methods take it by value: on error the suite is lost, so rebuild an empty
        // one rather than leave the object unusable.
        match f(suite) {
            Ok(s) => {
                self.suite = Some(s);
                Ok(())
            }
            Err(e) => {
                self.suite = Some(Suite::new());
                Err(e)
            }
        }
    }
}

#[pymethods]
impl PySuite {
    #[new]
    #[pyo3(signature = (size = None))]
    fn py_new(size: Option<&str>) -> PyResult<Self> {
        let defaults = BenchmarkOptions::default();
        Ok(match size {
            None => Self {
                suite: Some(Suite::new()),
                runs: defaults.runs,
                seed: defaults.seed,
                time_limit: None,
                problem_set_seed: None,
            },
            Some(s) => {
                let s = self::size(s)?;
                Self {
                    suite: Some(Suite::standard(s)),
                    runs: s.runs(),
                    seed: defaults.seed,
                    time_limit: None,
                    problem_set_seed: None,
                }
            }
        })
    }

    /// Adds the reference grasp planners with the hands, objects and candidate count of `size`.
    fn with_reference_grasp(mut slf: PyRefMut<'_, Self>, size: String) -> PyResult<PyRefMut<'_, Self>> {
        let s = self::size(&size)?;
        slf.update(|suite| Ok(suite.with_reference_grasp(s)))?;
        Ok(slf)
    }

    /// Adds the reference motion planners and scenes of `size` and its runs.
    fn with_reference_motion(mut slf: PyRefMut<'_, Self>, size: String) -> PyResult<PyRefMut<'_, Self>> {
        let s = self::size(&size)?;
        slf.runs = s.runs();
        slf.update(|suite| Ok(suite.with_reference_motion(s)))?;
        Ok(slf)
    }

    /// Adds a Python grasp planner: an object with `plan(request) -> list[GraspCandidate]`
    /// (see `opengrasp.GraspPlanner`); `parameters` describes its settings in the results.
    #[pyo3(signature = (planner, parameters = String::new()))]
    fn grasp_planner<'py>(
        mut slf: PyRefMut<'py, Self>,
        planner: &Bound<'py, PyAny>,
        parameters: String,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let p = PyGraspPlanner::new(planner)?;
        slf.update(|suite| Ok(suite.grasp_planner(parameters, p)))?;
        Ok(slf)
    }

    /// Adds a Python motion planner: `factory` (a class or a function) makes a fresh planner,
    /// an object with `plan(problem)` and optionally `setup(problem)` (see
    /// `opengrasp.MotionPlanner`), for every job. `scenes` restricts it to those scene names.
    #[pyo3(signature = (factory, parameters = String::new(), scenes = None))]
    fn motion_planner<'py>(
        mut slf: PyRefMut<'py, Self>,
        factory: &Bound<'py, PyAny>,
        parameters: String,
        scenes: Option<Vec<String>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        if !factory.is_callable() {
            return Err(
                Error::input("motion_planner takes a factory: a class or a function returning a planner").into()
            );
        }
        let probe = factory.call0()?;
        if !probe.hasattr("plan")? {
            return Err(Error::input("a motion planner needs a plan(problem) method").into());
        }
        let name = planner_name(&probe);
        let factory = factory.clone().unbind();
        let make = move || -> Box<dyn MotionPlanner> {
            Box::new(Python::attach(|py| PyMotionPlanner::create(py, &factory, &name)))
        };
        slf.update(|suite| {
            Ok(match scenes {
                Some(s) => suite.motion_planner_on(s, parameters, make),
                None => suite.motion_planner(parameters, make),
            })
        })?;
        Ok(slf)
    }

    /// Adds a motion scene by name (see `scene_names()`).
    fn motion_scene(mut slf: PyRefMut<'_, Self>, name: String) -> PyResult<PyRefMut<'_, Self>> {
        let scene = scene_by_name(&name)?;
        slf.update(|suite| Ok(suite.motion_scene(scene)))?;
        Ok(slf)
    }

    /// Sets the grasp hands (stock names or hand spec files).
    fn hands(mut slf: PyRefMut<'_, Self>, hands: Vec<String>) -> PyResult<PyRefMut<'_, Self>> {
        let hands = hands
            .iter()
            .map(|h| opengrasp_bench::stock::resolve_hand(h))
            .collect::<std::result::Result<Vec<_>, _>>()
            .map_err(Error::from)?;
        slf.update(|suite| Ok(suite.hands(hands)))?;
        Ok(slf)
    }

    /// Sets the grasp objects (stock names or mesh / metadata files).
    fn objects(mut slf: PyRefMut<'_, Self>, objects: Vec<String>) -> PyResult<PyRefMut<'_, Self>> {
        let objects = objects
            .iter()
            .map(|o| opengrasp_bench::stock::resolve_object(o))
            .collect::<std::result::Result<Vec<_>, _>>()
            .map_err(Error::from)?;
        slf.update(|suite| Ok(suite.objects(objects)))?;
        Ok(slf)
    }

    /// Sets the grasp candidates evaluated per hand × object cell at most (`None`: all).
    fn max_candidates(mut slf: PyRefMut<'_, Self>, n: Option<usize>) -> PyResult<PyRefMut<'_, Self>> {
        slf.update(|suite| Ok(suite.max_candidates(n)))?;
        Ok(slf)
    }

    /// Sets the force-closure palm grasps per cell sent to the physics hold check.
    fn physics_per_cell(mut slf: PyRefMut<'_, Self>, n: usize) -> PyResult<PyRefMut<'_, Self>> {
        slf.update(|suite| Ok(suite.physics_per_cell(n)))?;
        Ok(slf)
    }

    /// Sets the Clean the Table episodes per motion planner (0: none).
    fn clean_the_table(mut slf: PyRefMut<'_, Self>, episodes: usize) -> PyResult<PyRefMut<'_, Self>> {
        slf.update(|suite| Ok(suite.clean_the_table(episodes)))?;
        Ok(slf)
    }

    /// Sets the motion runs per planner per scene.
    fn runs(mut slf: PyRefMut<'_, Self>, runs: usize) -> PyResult<PyRefMut<'_, Self>> {
        slf.runs = runs;
        slf.update(|suite| Ok(suite.runs(runs)))?;
        Ok(slf)
    }

    /// Adds the motion problem sets at `path` (see `load_problem_sets`) as scenes with the
    /// reference planners (RRT-Connect, PRM; IK-RRT on sets with pose goals) and sets the runs
    /// to the largest set's size, so each planner plans every problem once (run r is problem
    /// r). Set the seed first: it cannot change once problem sets are in.
    fn problem_sets<'py>(
        mut slf: PyRefMut<'py, Self>,
        py: Python<'py>,
        path: PathBuf,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let sets = crate::world::load_sets(py, &path)?;
        let seed = slf.seed;
        slf.runs = sets.iter().map(|s| s.len()).max().unwrap_or(0);
        slf.problem_set_seed = Some(seed);
        slf.update(|suite| Ok(suite.with_problem_sets(sets, seed)))?;
        Ok(slf)
    }

    /// Sets the base seed of both benchmarks.
    fn seed(mut slf: PyRefMut<'_, Self>, seed: u64) -> PyResult<PyRefMut<'_, Self>> {
        if slf.problem_set_seed.is_some_and(|s| s != seed) {
            return Err(
                Error::input("seed: set the seed before adding problem sets (their runs follow the seed)").into()
            );
        }
        slf.seed = seed;
        slf.update(|suite| Ok(suite.seed(seed)))?;
        Ok(slf)
    }

    /// Sets the motion planners' time limit per run (s; default 10).
    fn time_limit(mut slf: PyRefMut<'_, Self>, seconds: f64) -> PyResult<PyRefMut<'_, Self>> {
        if !(seconds > 0.0 && seconds.is_finite()) {
            return Err(Error::input(format!("time_limit: must be finite and > 0, got {seconds}")).into());
        }
        slf.time_limit = Some(seconds);
        Ok(slf)
    }

    /// Sets the worker threads (1: serial; default: all cores).
    fn jobs(mut slf: PyRefMut<'_, Self>, jobs: usize) -> PyResult<PyRefMut<'_, Self>> {
        slf.update(|suite| Ok(suite.jobs(jobs)))?;
        Ok(slf)
    }

    /// Keeps only the planners with these names (case-insensitive).
    fn retain_planners(mut slf: PyRefMut<'_, Self>, names: Vec<String>) -> PyResult<PyRefMut<'_, Self>> {
        slf.update(|suite| Ok(suite.retain_planners(&names)?))?;
        Ok(slf)
    }

    /// Keeps only the motion scenes with these names (case-insensitive).
    fn retain_scenes(mut slf: PyRefMut<'_, Self>, names: Vec<String>) -> PyResult<PyRefMut<'_, Self>> {
        slf.update(|suite| Ok(suite.retain_scenes(&names)?))?;
        Ok(slf)
    }

    /// Names of the planners (grasp, then motion).
    #[getter]
    fn planner_names(&self) -> Vec<String> {
        self.suite.as_ref().map(Suite::planner_names).unwrap_or_default()
    }

    /// Names of the motion scenes.
    #[getter]
    fn scene_names(&self) -> Vec<String> {
        self.suite.as_ref().map(Suite::scene_names).unwrap_or_default()
    }

    /// Runs the suite (GIL released; Python planners take it in turn) and returns the results.
    fn run(&mut self, py: Python<'_>) -> PyResult<PyResults> {
        let mut suite = self.suite.take().ok_or_else(|| Error::input("the suite is already running"))?;
        if let Some(t) = self.time_limit {
            let options = BenchmarkOptions {
                runs: self.runs,
                seed: self.seed,
                time_limit: Duration::from_secs_f64(t),
                ..BenchmarkOptions::default()
            };
            suite = suite.motion_options(options);
        }
        let result = py.detach(|| guard(|| Ok(suite.run()?)));
        self.suite = Some(suite);
        Ok(PyResults { file: result? })
    }

    fn __repr__(&self) -> String {
        format!("Suite(planners={:?}, scenes={:?})", self.planner_names(), self.scene_names())
    }
}

/// A results file: provenance, grasp and motion sections.
#[pyclass(name = "Results", module = "opengrasp", frozen)]
pub struct PyResults {
    file: ResultsFile,
}

#[pymethods]
impl PyResults {
    /// Loads and validates a results file.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        Ok(Self { file: ResultsFile::load(&path).map_err(Error::from)? })
    }

    /// Parses and validates results JSON text.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        Ok(Self { file: ResultsFile::from_json(text).map_err(Error::from)? })
    }

    /// The results as plain Python objects (dicts, lists, numbers), as in the JSON file.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(to_py(py, &self.file)?)
    }

    /// The results file's JSON text.
    fn to_json(&self) -> PyResult<String> {
        Ok(self.file.to_json().map_err(Error::from)?)
    }

    /// Writes the results file (atomically).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        Ok(self.file.save(&path).map_err(Error::from)?)
    }

    /// Checks the results' invariants (raises `ResultsError`).
    fn validate(&self) -> PyResult<()> {
        Ok(self.file.validate().map_err(Error::from)?)
    }

    /// The paper's Tables I–III: `format` is `"table"`, `"markdown"` or `"csv"`.
    #[pyo3(signature = (format = "table"))]
    fn report(&self, format: &str) -> PyResult<String> {
        Ok(report::render(&self.file, self::format(format)?))
    }

    /// One score entry per planner and benchmark (what the high-score board ranks).
    fn scores<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(to_py(py, &self.file.scores())?)
    }

    fn __repr__(&self) -> String {
        format!(
            "Results(grasp cells={}, motion runs={})",
            self.file.grasp.as_ref().map_or(0, |g| g.cells.len()),
            self.file.motion.as_ref().map_or(0, |m| m.runs.len())
        )
    }
}

/// Loads and validates a results file, returning it as plain Python objects.
#[pyfunction]
pub fn load_results<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let file = ResultsFile::load(&path).map_err(Error::from)?;
    Ok(to_py(py, &file)?)
}

/// Submits a results file to the high-score database `db` (created if missing) as `name`
/// (with `team`); returns the submission id. Validates exactly like `opengrasp submit`.
#[pyfunction]
#[pyo3(signature = (db, results, name, team = None))]
pub fn submit(py: Python<'_>, db: PathBuf, results: PathBuf, name: String, team: Option<String>) -> PyResult<i64> {
    let mut submitter = Submitter::new(name);
    if let Some(t) = team {
        submitter = submitter.with_team(t);
    }
    let id = py.detach(|| guard(|| Ok(opengrasp_highscore::submit(&db, &results, submitter)?)))?;
    Ok(id.0)
}

/// Rankings of the high-score database: every benchmark, or the one with id `benchmark`
/// (e.g. `"motion/planar-post"`), as dicts.
#[pyfunction]
#[pyo3(signature = (db, benchmark = None))]
pub fn ranking<'py>(py: Python<'py>, db: PathBuf, benchmark: Option<String>) -> PyResult<Bound<'py, PyAny>> {
    let r = opengrasp_highscore::ranking(&db, benchmark.as_deref()).map_err(Error::from)?;
    Ok(to_py(py, &r)?)
}

/// Registers a benchmark (`kind` `"grasp"` with a hand name, or `"motion"` with a scene
/// name) on the board; returns its id.
#[pyfunction]
pub fn register_benchmark(db: PathBuf, kind: &str, target: &str, description: &str) -> PyResult<String> {
    let kind = BenchmarkKind::parse(kind)
        .ok_or_else(|| Error::input(format!("unknown benchmark kind {kind:?}: grasp or motion")))?;
    Ok(opengrasp_highscore::register_benchmark(&db, kind, target, description).map_err(Error::from)?)
}
