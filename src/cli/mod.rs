//! The commands of `floebench`: one module per command (or group of
//! commands), each with its clap arguments ([`clap::Args`]) and its `run`,
//! which calls the library and prints what it did.
//!
//! A command ends with an [`Outcome`]: its exit status, or the error that
//! stopped it, printed by [`Command::run`] as `error: …` with status 1.

mod check;
mod compare;
mod fc2d;
mod lcp;
mod percussion;
mod run;
mod show;
mod sweep;
mod validate;

use clap::{Parser, Subcommand};
use floebench::formulation;
use floebench::model::Scenario;
use floebench::report::format::fmt_num;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The command line.
#[derive(Parser)]
#[command(
    name = "floebench",
    version,
    about = "Contact mechanics of sea-ice floes: run the same cases with several contact formulations",
    long_about = "floebench runs sea-ice floe scenarios (TOML case files, see docs/case-format.md) \
                  with several contact formulations and writes trajectories, energy ledgers \
                  and counters as CSV/JSON.\n\nStart with (from the repository's folder, as in the README):\n  floebench compare cases/head_on.toml   # every formulation on a bundled case, report in reports/\n  floebench validate cases/              # what each case holds; a bad file is named with its line"
)]
pub struct Cli {
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands (their doc comments are their help).
#[derive(Subcommand)]
pub enum Command {
    /// Check case files and print what they contain; reports every bad file
    /// and exits non-zero if there is one.
    Validate(validate::Args),
    /// Draw a case before running it: its floes (those of [[field]] tables
    /// included), obstacles, the wind, the current and the floes' initial
    /// velocities as arrows, a scale bar; writes <case name>.png (or -o).
    Show(show::Args),
    /// Run one case with one formulation; writes trajectory.csv, energy.csv,
    /// summary.json, floes.json, fractures.csv and stress.csv (and
    /// obstacles.csv for a case with obstacles, percussion.json when a
    /// lattice run broke a floe).
    Run(run::Args),
    /// Run several formulations on the same cases and write a comparison report:
    /// per case metrics.csv, divergence.csv, summary.json, each run's data and the
    /// plots; then index.md and index.html.
    Compare(compare::Args),
    /// Run the physical checks (docs/physics.md §6) on cases and print a table;
    /// exits non-zero when a formulation fails a check it claims to pass.
    Check(check::Args),
    /// Re-solve a dumped LCP (from `run --dump-lcp`) and print its residual;
    /// with `--time`, re-solve and time every dump of a folder.
    Lcp(lcp::Args),
    /// Solve Siconos' 2D frictional contact problem files (a file, or a
    /// folder's *.dat) with our NSGS, APGD or Lemke: per file the contacts,
    /// iterations, our residual, Siconos' error and the thread CPU; exits
    /// non-zero when a file cannot be read or a solve does not converge.
    Fc2d(fc2d::Args),
    /// Run a sweep plan (docs/sweep-format.md): every point of cases x
    /// formulations x settings, measured against the reference; writes
    /// points/<id>.json, sweep.csv, orders.csv, plots and index.md/html.
    /// A finished point is never recomputed.
    Sweep(sweep::Args),
    /// Resolve a 1D percussion of bars in a mass-spring-dashpot chain
    /// (docs/physics.md §7.1): prints the pieces as CSV
    /// (fragment,first,last,mass,length,centre,velocity) and a summary on
    /// stderr.
    #[command(name = "percussion-1d")]
    Percussion1d(percussion::Args1d),
    /// Resolve a 2D percussion in the lattice of a rectangular floe
    /// (docs/physics.md §7.3), struck on its left face along +x: prints
    /// the pieces as CSV (piece,nodes,mass,x,y,vx,vy,omega,hull_area) and a
    /// summary on stderr.
    #[command(name = "percussion-2d")]
    Percussion2d(percussion::Args2d),
    /// List the formulations.
    Formulations,
}

/// What a command ends with: its exit status, or the error that stopped it
/// (printed as `error: <it>`, exit status 1).
pub type Outcome = Result<ExitCode, String>;

/// The exit status of a command stopped by SIGINT or SIGTERM (128 + 2, as
/// shells report a Ctrl-C).
const INTERRUPTED: u8 = 130;

impl Command {
    /// Runs the command; an error is printed on stderr as `error: …`, exit
    /// status 1.
    pub fn run(self) -> ExitCode {
        let outcome = match self {
            Command::Validate(a) => validate::run(a),
            Command::Show(a) => show::run(a),
            Command::Run(a) => run::run(a),
            Command::Compare(a) => compare::run(a),
            Command::Check(a) => check::run(a),
            Command::Lcp(a) => lcp::run(a),
            Command::Fc2d(a) => fc2d::run(a),
            Command::Sweep(a) => sweep::run(a),
            Command::Percussion1d(a) => percussion::run_1d(a),
            Command::Percussion2d(a) => percussion::run_2d(a),
            Command::Formulations => list_formulations(),
        };
        outcome.unwrap_or_else(|e| {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        })
    }
}

/// `floebench formulations`: one line per formulation of the registry.
fn list_formulations() -> Outcome {
    for formulation::Entry {
        name,
        description: what,
        ..
    } in formulation::REGISTRY
    {
        println!("{name:<14} {what}");
    }
    Ok(ExitCode::SUCCESS)
}

/// `usize` of a count parsed as `u64` (saturating).
fn count(n: u64) -> usize {
    usize::try_from(n).unwrap_or(usize::MAX)
}

/// Every name of `names` is a formulation of the registry (else the error
/// `-f: …` naming the first that is not), checked before any case is loaded.
fn known_formulations(names: &[String]) -> Result<(), String> {
    names
        .iter()
        .try_for_each(|f| formulation::entry(f).map(|_| ()))
        .map_err(|e| format!("-f: {e}"))
}

/// Refuses, before any run, a formulation of `names` that ignores contacts
/// (free-drift) on a case of `cases` where contacts can happen (its floes
/// would pass through each other and the obstacles), unless `allow`
/// (`--allow-contacts`): the one rule of `run`, `compare` and `check`.
fn refuse_ignored_contacts<'a>(
    names: &[String],
    cases: impl IntoIterator<Item = (&'a Path, &'a Scenario)>,
    allow: bool,
) -> Result<(), String> {
    if allow {
        return Ok(());
    }
    let entries = names
        .iter()
        .map(|n| formulation::entry(n))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| format!("-f: {e}"))?;
    for (path, scn) in cases {
        if let Some(e) = entries
            .iter()
            .find(|e| !(e.resolves_contacts || scn.contact_free()))
        {
            return Err(format!(
                "{} ignores contacts and {} has obstacles or moving floes; --allow-contacts runs it anyway",
                e.name,
                path.display()
            ));
        }
    }
    Ok(())
}

/// The cases of `inputs` (files, or folders of `*.toml`), loaded, for the
/// formulations `names` ([`refuse_ignored_contacts`] with `allow`).
fn load_cases_for(
    inputs: &[PathBuf],
    names: &[String],
    allow: bool,
) -> Result<Vec<(PathBuf, Scenario)>, String> {
    let loaded = floebench::run::batch::load_cases(inputs).map_err(|e| e.to_string())?;
    for (_, scn) in &loaded {
        print_warnings(scn);
    }
    refuse_ignored_contacts(names, loaded.iter().map(|(p, s)| (p.as_path(), s)), allow)?;
    Ok(loaded)
}

/// The warnings of a loaded case on stderr, one a line:
/// `warning: <file>:<line>: …` (docs/case-format.md, "Warnings").
fn print_warnings(scn: &Scenario) {
    for w in &scn.source.warnings {
        eprintln!("warning: {w}");
    }
}

/// Refuses, before any run, an output folder `dir` that cannot be written
/// (it is created, a probe file written and removed:
/// [`floebench::fsio::probe_folder`]); the error names the option `flag`,
/// the path and the OS's reason on one line.
fn writable_folder(flag: &str, dir: &Path) -> Result<(), String> {
    floebench::fsio::probe_folder(dir)
        .map_err(|e| format!("{flag}: cannot write to {}: {e}", dir.display()))
}

/// [`writable_folder`] for an output file `file` (its folder is probed:
/// [`floebench::fsio::probe_file`]).
fn writable_file(flag: &str, file: &Path) -> Result<(), String> {
    floebench::fsio::probe_file(file)
        .map_err(|e| format!("{flag}: cannot write {}: {e}", file.display()))
}

/// The command line, for the report pages (newlines and backquotes as spaces).
fn command_line() -> String {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .map(|a| a.replace(['\n', '`'], " "))
        .collect();
    format!("floebench {}", args.join(" "))
}

/// `n thing` or `n things`.
fn plural(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

/// One line on a case: its floes, obstacles, times, contact law and the
/// explicit-Euler stability bound of the drag (docs/physics.md §4.2).
fn describe(scn: &Scenario) -> String {
    let mass: f64 = scn.floes.iter().map(|f| f.mass).sum();
    let area: f64 = scn.floes.iter().map(|f| f.area).sum();
    let dt = (0..scn.floes.len())
        .map(|i| scn.euler_stability_bound(i))
        .fold(f64::INFINITY, f64::min);
    // The bound (origin report eq. 3.6) is the water drag's: infinite
    // without water drag, whatever the wind, and without wind, current or
    // initial motion.
    let unbounded = if scn.environment.water.drag_factor() > 0.0 {
        "none (no wind, current or initial motion)"
    } else {
        "none (no water drag)"
    };
    format!(
        "{}: {} ({} kg, {} m^2), {}, {} s every {} s, e = {}, mu = {}, explicit-Euler stability bound of the drag {}",
        scn.name,
        plural(scn.floes.len(), "floe"),
        fmt_num(mass),
        fmt_num(area),
        plural(scn.obstacles.len(), "obstacle"),
        scn.duration,
        scn.output_interval,
        scn.contact.restitution,
        scn.contact.friction,
        if dt.is_finite() {
            format!("{} s", fmt_num(dt))
        } else {
            unbounded.into()
        }
    )
}
