//! `opengrasp view` and `opengrasp run --record`: rerun recordings (`.rrd`) of a results file,
//! and the PNG snapshots `opengrasp report --plots` embeds.
//!
//! Recordings need the `rerun` feature (`cargo install --path . --features rerun`, Rust
//! 1.95); without it both commands fail with [`CliError::RerunDisabled`] before doing any
//! work. Motion runs are replayed from their seeds to get their paths (see
//! [`opengrasp_viewer::replay`]); grasps need a results file written with `run grasp --grasps`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use opengrasp_motion::problem_set::LoadedProblemSet;

use crate::cli::CliError;
use crate::results::{Error, Result, ResultsFile};

/// Options of `opengrasp view`.
#[derive(Clone, Debug, PartialEq, clap::Args)]
pub struct ViewArgs {
    /// The results file.
    pub file: PathBuf,
    /// Record only this motion run: `planner/scene/run` (e.g. `RRT-Connect/planar post/0`) or
    /// its position in the file.
    #[arg(long, conflicts_with = "grasp")]
    pub run: Option<String>,
    /// Record only this grasp candidate: `planner/hand/object/index` or its position among
    /// the recorded candidates (needs a file written with `run grasp --grasps`).
    #[arg(long)]
    pub grasp: Option<String>,
    /// The recording to write (default: the results file with extension `.rrd`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Do not start the `rerun` viewer on the recording even when it is installed.
    #[arg(long)]
    pub no_spawn: bool,
    /// The motion problem sets the results were made with (`run --problems`), to rebuild
    /// their scenes.
    #[arg(long = "problems", value_name = "PATH")]
    pub problems: Vec<PathBuf>,
}

/// Loads the problem sets named on the command line.
///
/// # Errors
/// The loader's errors.
pub fn load_sets(paths: &[PathBuf]) -> Result<Vec<Arc<LoadedProblemSet>>> {
    let mut sets = Vec::new();
    for p in paths {
        sets.extend(crate::bench::problem_sets::load_problem_sets(p)?.into_iter().map(Arc::new));
    }
    Ok(sets)
}

/// Writes the PNG snapshots of `results` into `dir` and returns the Markdown section that
/// embeds them (empty if none were written); skipped scenes are reported on stderr.
///
/// # Errors
/// [`CliError::Viewer`] if a file cannot be written.
pub fn snapshots(results: &ResultsFile, dir: &Path, sets: &[Arc<LoadedProblemSet>]) -> Result<String, CliError> {
    let options = opengrasp_viewer::snapshot::SnapshotOptions::default();
    let shots = opengrasp_viewer::snapshot::write_snapshots(results, dir, sets, &options)?;
    for (what, why) in &shots.skipped {
        eprintln!("no snapshot of {what}: {why}");
    }
    let images: Vec<(String, String)> = shots
        .written
        .iter()
        .inspect(|s| eprintln!("wrote {}", s.path.display()))
        .map(|s| (s.caption.clone(), s.path.display().to_string()))
        .collect();
    Ok(if images.is_empty() { String::new() } else { crate::report::images_markdown("Snapshots", &images) })
}

/// The executable `name` on `PATH`, if any.
pub fn on_path(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH")
        .into_iter()
        .flat_map(|p| std::env::split_paths(&p).collect::<Vec<_>>())
        .map(|d| d.join(name))
        .find(|f| f.is_file())
}

/// Runs `opengrasp view`: writes the recording and returns its path (the viewer is started
/// on it unless `--no-spawn` or `rerun` is not on `PATH`).
///
/// # Errors
/// [`CliError::RerunDisabled`] without the `rerun` feature; [`CliError::Bench`] for a results
/// file that does not load; [`CliError::Viewer`] for an unknown run or grasp id, a replay that
/// fails or a recording that cannot be written.
pub fn view(args: &ViewArgs) -> Result<PathBuf, CliError> {
    if !cfg!(feature = "rerun") {
        return Err(CliError::RerunDisabled { command: "view" });
    }
    let results = crate::cli::load_results(&args.file)?;
    let sets = load_sets(&args.problems)?;
    let out = args.out.clone().unwrap_or_else(|| args.file.with_extension("rrd"));
    if out == args.file {
        return Err(Error::InvalidOption { name: "out", reason: "would overwrite the results file".into() }.into());
    }
    let selection = match (&args.run, &args.grasp) {
        (Some(r), _) => Selection::Run(r.clone()),
        (None, Some(g)) => Selection::Grasp(g.clone()),
        (None, None) => Selection::Overview,
    };
    record(&results, &out, &selection, &sets)?;
    if !args.no_spawn {
        if let Some(rerun) = on_path("rerun") {
            match std::process::Command::new(&rerun).arg(&out).spawn() {
                Ok(_) => eprintln!("opened {} in {}", out.display(), rerun.display()),
                Err(e) => eprintln!("could not start {}: {e}", rerun.display()),
            }
        }
    }
    Ok(out)
}

#[cfg(feature = "rerun")]
pub use opengrasp_viewer::record::Selection;

/// What to record (stands in for `opengrasp_viewer::record::Selection` without the `rerun`
/// feature).
#[cfg(not(feature = "rerun"))]
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Selection {
    /// Everything.
    Overview,
    /// One run.
    Run(String),
    /// One grasp.
    Grasp(String),
}

/// Writes the rerun recording of `results` to `out`.
///
/// # Errors
/// [`CliError::RerunDisabled`] without the `rerun` feature; [`CliError::Viewer`] otherwise.
#[cfg(feature = "rerun")]
pub fn record(
    results: &ResultsFile,
    out: &Path,
    selection: &Selection,
    sets: &[Arc<LoadedProblemSet>],
) -> Result<(), CliError> {
    let recorder = opengrasp_viewer::record::Recorder::to_file(out)?;
    let skipped = recorder.log_results(results, selection, sets, 0.02)?;
    recorder.finish()?;
    for (what, why) in skipped {
        eprintln!("not recorded: {what}: {why}");
    }
    eprintln!("wrote {}", out.display());
    Ok(())
}

/// Writes the rerun recording of `results` to `out`.
///
/// # Errors
/// Always [`CliError::RerunDisabled`]: this build has no `rerun` feature.
#[cfg(not(feature = "rerun"))]
pub fn record(
    _results: &ResultsFile,
    _out: &Path,
    _selection: &Selection,
    _sets: &[Arc<LoadedProblemSet>],
) -> Result<(), CliError> {
    Err(CliError::RerunDisabled { command: "record" })
}
