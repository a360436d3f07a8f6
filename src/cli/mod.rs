//! The `opengrasp` command line (clap derive), as a library module so it can be tested and
//! embedded: [`Cli`] parses, [`execute`] runs.
//!
//! ```text
//! opengrasp list [categories|scenes|planners|hands|objects]
//! opengrasp run grasp|motion|all [--size tiny|default|paper] [--planner NAME]... [--runs N]
//!                                [--hand NAME|PATH]... [--object NAME|PATH]...
//!                                [--seed S] [--max-candidates N|all] [--out results.json] [--jobs J]
//!                                [--quiet] [--record out.rrd]
//! opengrasp report results.json [--format table|markdown|csv] [--plots DIR]
//!                                [--plot-format svg|png|both] [--ompl DIR] [--problems PATH]...
//! opengrasp view results.json [--run ID | --grasp ID] [--out file.rrd] [--no-spawn]
//!                                [--problems PATH]...   (feature `rerun`)
//! opengrasp submit results.json --name NAME [--team TEAM] [--db highscore.sqlite]
//! opengrasp submit results.json --name NAME --server http://HOST:PORT [--token TOKEN]
//! opengrasp highscore [BENCHMARK] [--db highscore.sqlite]
//! opengrasp serve [--db highscore.sqlite] [--addr 127.0.0.1:8080] [--max-connections N] [--verify-sample K]
//! opengrasp token issue --team TEAM | list | revoke ID [--db highscore.sqlite]
//! ```

mod args;

pub use args::*;

use std::collections::HashMap;
use std::io::IsTerminal;
use std::sync::Mutex;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::bench::problem_sets::{load_problem_sets, ProblemSetChecker};
use crate::bench::stock;
use crate::motion::validity::cover::GreedyCoverOptions;
use crate::report::{self, Format};
use crate::results::{Category, Error, Result, ResultsFile};
use crate::suite::{Progress, Suite, SuiteSize};

/// Largest results file `opengrasp report` reads (files with every grasp candidate are big).
pub const MAX_REPORT_BYTES: usize = 512 * 1024 * 1024;

/// Loads a results file for `report` and `view` (at most [`MAX_REPORT_BYTES`]).
///
/// # Errors
/// [`Error::Io`] / [`Error::Parse`] (naming the file) / validation errors.
pub fn load_results(file: &std::path::Path) -> std::result::Result<ResultsFile, CliError> {
    let text = crate::highscore::read::read_file_bounded(file, MAX_REPORT_BYTES)?;
    Ok(ResultsFile::from_json(&text).map_err(|e| match e {
        Error::Parse { source, .. } => Error::Parse { path: file.to_path_buf(), source },
        other => other,
    })?)
}

/// Builds the suite `opengrasp run` would run.
///
/// # Errors
/// [`Error::InvalidOption`] for an unknown planner, hand or object, a bad `--max-candidates`
/// or zero jobs; [`Error::Core`] for a hand or object file that does not load.
pub fn build_suite(args: &RunArgs) -> Result<Suite> {
    let size = SuiteSize::from(args.size);
    let mut suite = if args.problems.is_empty() {
        match args.which {
            Which::Grasp => Suite::new().with_reference_grasp(size),
            Which::Motion => Suite::new().with_reference_motion(size),
            Which::All => Suite::standard(size),
        }
    } else {
        let checker = match args.checker {
            CheckerArg::Exact => ProblemSetChecker::Exact,
            CheckerArg::Spheres => ProblemSetChecker::Spheres(GreedyCoverOptions::default()),
        };
        let mut sets = Vec::new();
        for path in &args.problems {
            sets.extend(load_problem_sets(path)?);
        }
        match args.which {
            Which::Grasp => {
                return Err(Error::InvalidOption {
                    name: "problems",
                    reason: "motion problem sets need `run motion` or `run all`".into(),
                })
            }
            Which::Motion => {
                Suite::new().labelled(size.name()).with_problem_sets_checked_by(sets, args.seed, checker)?
            }
            Which::All => {
                Suite::new().with_reference_grasp(size).with_problem_sets_checked_by(sets, args.seed, checker)?
            }
        }
    };
    suite = suite.seed(args.seed);
    if !args.hands.is_empty() {
        suite = suite.hands(args.hands.iter().map(|h| stock::resolve_hand(h)).collect::<Result<_>>()?);
    }
    if !args.objects.is_empty() {
        suite = suite.objects(args.objects.iter().map(|o| stock::resolve_object(o)).collect::<Result<_>>()?);
    }
    if let Some(r) = args.runs {
        suite = suite.runs(r);
    }
    if let Some(m) = &args.max_candidates {
        let max = if m.eq_ignore_ascii_case("all") {
            None
        } else {
            Some(m.parse::<usize>().map_err(|e| Error::InvalidOption {
                name: "max-candidates",
                reason: format!("{m:?}: {e} (expected a number or `all`)"),
            })?)
        };
        suite = suite.max_candidates(max);
    }
    if let Some(n) = args.physics {
        suite = suite.physics_per_cell(n);
    }
    if args.hull_stats {
        suite = suite.hull_statistics(true);
    }
    if args.grasps {
        suite = suite.record_grasps(true);
        if !args.no_tactile {
            let mut tactile = opengrasp_grasp::benchmark::TactileRecording::default();
            if let Some(g) = args.grip_force {
                tactile.grip_force = g;
            }
            suite = suite.record_tactile(Some(tactile));
        }
    }
    if let Some(e) = args.episodes {
        suite = suite.clean_the_table(e);
    }
    if let Some(j) = args.jobs {
        if j == 0 {
            return Err(Error::InvalidOption { name: "jobs", reason: "must be at least 1".into() });
        }
        suite = suite.jobs(j);
    }
    if !args.planners.is_empty() {
        suite = suite.retain_planners(&args.planners)?;
    }
    if !args.scenes.is_empty() {
        suite = suite.retain_scenes(&args.scenes)?;
    }
    if args.protocol != ProtocolArg::Certified {
        suite = suite.protocol(args.protocol.into());
    }
    if let Some(shard) = &args.shard {
        suite = suite.shard(crate::results::Shard::parse(shard)?);
    }
    Ok(suite)
}

/// Progress bars on stderr (one per category), hidden when stderr is not a terminal.
fn progress_bars() -> impl Fn(&Progress) + Send + Sync + 'static {
    let multi = MultiProgress::with_draw_target(if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let bars: Mutex<HashMap<Category, ProgressBar>> = Mutex::new(HashMap::new());
    move |p: &Progress| {
        let Ok(mut bars) = bars.lock() else { return };
        let bar = bars.entry(p.category).or_insert_with(|| {
            let bar = multi.add(ProgressBar::new(p.total as u64));
            let unit = if p.category == Category::Grasp { "cells" } else { "runs" };
            if let Ok(style) = ProgressStyle::with_template(&format!(
                "{{prefix:>6}} [{{elapsed_precise}}] {{bar:30}} {{pos}}/{{len}} {unit} (eta {{eta}}) {{msg}}"
            )) {
                bar.set_style(style);
            }
            bar.set_prefix(p.category.name());
            bar
        });
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
        bar.set_message(p.label.clone());
        if p.done >= p.total {
            bar.finish();
        }
    }
}

/// Runs `opengrasp run`: the suite, the results file and (unless `quiet`) the report, which
/// is returned.
///
/// # Errors
/// As [`build_suite`], [`Suite::run`] and [`ResultsFile::save`].
pub fn run(args: &RunArgs, show_progress: bool) -> Result<(ResultsFile, String)> {
    let mut suite = build_suite(args)?;
    crate::results::check_writable(&args.out)?;
    if show_progress {
        suite = suite.on_progress(progress_bars());
    }
    let results = suite.run()?;
    results.save(&args.out)?;
    let text = if args.quiet { String::new() } else { report::render(&results, Format::Table) };
    Ok((results, text))
}

/// The text of `opengrasp list`.
pub fn list(what: ListWhat) -> String {
    let suite = Suite::standard(SuiteSize::Default);
    let tiny = Suite::standard(SuiteSize::Tiny);
    let mut out = String::new();
    let section = |out: &mut String, title: &str, items: Vec<String>| {
        out.push_str(title);
        out.push_str(":\n");
        for i in items {
            out.push_str("  ");
            out.push_str(&i);
            out.push('\n');
        }
    };
    let all = what == ListWhat::All;
    if all || what == ListWhat::Categories {
        section(&mut out, "categories", vec!["grasp (Tables I, II)".into(), "motion (Table III)".into()]);
    }
    if all || what == ListWhat::Scenes {
        let mut scenes = suite.scene_names();
        scenes.extend(tiny.scene_names().into_iter().map(|s| format!("{s} (tiny suite)")));
        section(&mut out, "motion scenes", scenes);
    }
    if all || what == ListWhat::Planners {
        section(&mut out, "planners", suite.planner_names());
    }
    if all || what == ListWhat::Hands {
        let mut hands: Vec<String> = stock::HAND_NAMES.iter().map(|s| s.to_string()).collect();
        hands.push("or PATH: a hand spec file naming its URDF (--hand PATH)".into());
        section(&mut out, "hands", hands);
    }
    if all || what == ListWhat::Objects {
        let mut objects: Vec<String> = stock::OBJECT_NAMES.iter().map(|s| s.to_string()).collect();
        objects
            .push("or PATH: a mesh with a .json metadata file beside it, or the metadata file (--object PATH)".into());
        section(&mut out, "objects", objects);
    }
    out
}

/// Executes a parsed command line, printing to stdout.
///
/// # Errors
/// The command's errors.
pub fn execute(cli: Cli) -> std::result::Result<(), CliError> {
    match cli.command {
        Command::List { what } => print!("{}", list(what)),
        Command::Run(args) => {
            if let Some(path) = &args.record {
                if !cfg!(feature = "rerun") {
                    return Err(CliError::RerunDisabled { command: "run --record" });
                }
                crate::results::check_writable(path)?;
            }
            let (results, text) = run(&args, true)?;
            print!("{text}");
            eprintln!(
                "wrote {} ({:.1} s on {} jobs)",
                args.out.display(),
                results.provenance.wall_seconds,
                results.provenance.jobs
            );
            if let Some(path) = &args.record {
                let sets = crate::view::load_sets(&args.problems)?;
                crate::view::record(&results, path, &crate::view::Selection::Overview, &sets)?;
            }
        }
        Command::View(args) => {
            crate::view::view(&args)?;
        }
        Command::Merge { files, out } => {
            crate::results::check_writable(&out)?;
            let shards = files.iter().map(ResultsFile::load).collect::<Result<Vec<_>>>()?;
            let merged = crate::results::merge(shards)?;
            merged.save(&out)?;
            eprintln!("merged {} shards into {}", files.len(), out.display());
        }
        Command::Report { file, format, plots, plot_format, ompl, problems } => {
            let results = load_results(&file)?;
            let sets = crate::view::load_sets(&problems)?;
            // Output directories first, so a bad path fails before anything is printed.
            for dir in plots.iter().chain(&ompl) {
                std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.clone(), source })?;
            }
            print!("{}", report::render(&results, format.into()));
            if let Some(dir) = plots {
                for p in crate::plots::plot_all_as(&results, &dir, plot_format.into())? {
                    eprintln!("wrote {}", p.display());
                }
                let section = crate::view::snapshots(&results, &dir, &sets)?;
                if matches!(format, FormatArg::Markdown) && !section.is_empty() {
                    print!("\n{section}");
                }
            }
            if let Some(dir) = ompl {
                let motion = results.motion.as_ref().ok_or_else(|| Error::InvalidOption {
                    name: "ompl",
                    reason: "the results file has no motion results".into(),
                })?;
                for (name, text) in crate::ompl::logs(motion, &results.provenance) {
                    let path = dir.join(name);
                    crate::results::write_atomic(&path, |w| std::io::Write::write_all(w, text.as_bytes()))?;
                    eprintln!("wrote {}", path.display());
                }
            }
        }
        Command::Submit { file, name, team, db, server, token } => {
            let mut who = crate::highscore::Submitter::new(name);
            if let Some(t) = team {
                who = who.with_team(t);
            }
            if let Some(url) = server {
                let token = token.ok_or_else(|| crate::highscore::HighscoreError::Unauthorized {
                    reason: "--server needs --token or $OPENGRASP_TOKEN".into(),
                })?;
                let text = crate::highscore::read::read_file_bounded(&file, crate::highscore::MAX_UPLOAD_BYTES)?;
                let answer = crate::highscore::client::upload(&url, &token, &who, &text)?;
                let verb = if answer.duplicate { "already stored" } else { "uploaded" };
                println!(
                    "{verb} {} as submission {} on {url} ({})",
                    file.display(),
                    answer.id,
                    answer.benchmarks.join(", ")
                );
            } else {
                let id = crate::highscore::submit(&db, &file, who)?;
                println!("stored {} as submission {} in {}", file.display(), id.0, db.display());
            }
        }
        Command::Highscore { benchmark, db } => {
            let rankings = crate::highscore::ranking(&db, benchmark.as_deref())?;
            print!("{}", crate::highscore::render_rankings(&rankings));
        }
        Command::Serve { db, addr, max_connections, verify_sample } => {
            let options = crate::highscore::ServerOptions { max_connections, verify_sample, ..Default::default() };
            let server = crate::highscore::spawn(&db, &addr, options)?;
            eprintln!("serving {} on http://{}/", db.display(), server.addr());
            server.wait()?;
        }
        Command::Token { action, db } => {
            let store = crate::highscore::Store::open(&db)?;
            match action {
                TokenAction::Issue { team } => {
                    let (id, token) = store.issue_token(&team)?;
                    eprintln!("token {id} for team {team} (shown once; only its hash is stored):");
                    println!("{token}");
                }
                TokenAction::List => {
                    for t in store.tokens()? {
                        let state = if t.revoked { "revoked" } else { "active" };
                        println!("{}\t{}\t{}\t{state}", t.id, t.team, t.created_at);
                    }
                }
                TokenAction::Revoke { id } => {
                    if store.revoke_token(id)? {
                        println!("revoked token {id}");
                    } else {
                        println!("no token {id}");
                    }
                }
            }
        }
    }
    Ok(())
}
