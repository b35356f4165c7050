//! `floebench check`: the physical checks of cases, as a table.

use super::{
    count, known_formulations, load_cases_for, plural, writable_file, Outcome, INTERRUPTED,
};
use floebench::analysis::check;
use floebench::report::checks::{format_table, markdown_table};
use floebench::run::batch::{self, BatchOptions};
use std::path::PathBuf;
use std::process::ExitCode;

/// The arguments of `floebench check`.
#[derive(clap::Args)]
pub struct Args {
    /// Case files (.toml) or folders (their *.toml files, not subfolders).
    #[arg(required = true)]
    cases: Vec<PathBuf>,
    /// Comma-separated formulations [default: every formulation that applies;
    /// free-drift only on contact-free cases].
    #[arg(short, long, value_delimiter = ',')]
    formulations: Option<Vec<String>>,
    /// Also write the table as Markdown to this file.
    #[arg(long, value_name = "FILE")]
    markdown: Option<PathBuf>,
    /// Runs at a time, at least 1 [default: the number of cores].
    #[arg(short, long, value_parser = clap::value_parser!(u64).range(1..))]
    jobs: Option<u64>,
    /// Runs of each (case, formulation), at least 1: CPU times are reported
    /// as median and spread, and the physics of the repeats must be
    /// bit-identical (a difference is reported as a finding). With 2 or
    /// more, a pair whose repeats take under 0.25 s of CPU in all is run
    /// again until they take about that much (at most 200 runs).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    repeat: u64,
    /// Let a formulation that ignores contacts (free-drift), named in -f,
    /// run a case where contacts can happen (floes pass through each other).
    #[arg(long)]
    allow_contacts: bool,
    /// No progress bars.
    #[arg(short, long)]
    quiet: bool,
}

/// Runs every formulation on the cases, prints the checks' table and the
/// findings; fails when a formulation fails a check it claims to pass, and
/// ends with [`INTERRUPTED`] when stopped.
pub fn run(args: Args) -> Outcome {
    let mut opts = BatchOptions {
        progress: !args.quiet,
        repeat: count(args.repeat),
        ..BatchOptions::default()
    };
    if let Some(f) = args.formulations {
        opts.formulations = f;
    }
    if let Some(j) = args.jobs {
        opts.jobs = count(j);
    }
    known_formulations(&opts.formulations)?;
    if let Some(file) = &args.markdown {
        writable_file("--markdown", file)?;
    }
    let loaded = load_cases_for(&args.cases, &opts.formulations, args.allow_contacts)?;
    let done = batch::run_cases(loaded, &opts).map_err(|e| e.to_string())?;
    let rows: Vec<check::CheckOutcome> = done
        .iter()
        .flat_map(|c| check::check_runs(&c.scenario, &c.runs))
        .collect();
    print!("{}", format_table(&rows));
    for f in done.iter().flat_map(|c| &c.findings) {
        println!("finding: {f}");
    }
    if let Some(file) = &args.markdown {
        floebench::fsio::write_atomic(file, markdown_table(&rows).as_bytes())
            .map_err(|e| format!("cannot write {}: {e}", file.display()))?;
    }
    if floebench::run::interrupt::requested() {
        eprintln!(
            "interrupted: the table holds the {} whose runs all finished",
            plural(done.len(), "case")
        );
        Ok(ExitCode::from(INTERRUPTED))
    } else if check::claimed_failures(&rows) > 0 {
        Ok(ExitCode::FAILURE)
    } else {
        Ok(ExitCode::SUCCESS)
    }
}
