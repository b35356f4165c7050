//! `floebench compare`: several formulations on the same cases, and the
//! comparison report.

use super::{
    command_line, count, describe, known_formulations, load_cases_for, plural, writable_folder,
    Outcome, INTERRUPTED,
};
use floebench::compare::{self, CompareOptions};
use floebench::model::IntegratorKind;
use floebench::report;
use std::path::PathBuf;
use std::process::ExitCode;

/// The arguments of `floebench compare`.
#[derive(clap::Args)]
pub struct Args {
    /// Case files, or folders of case files (their *.toml, not recursive).
    #[arg(required = true)]
    cases: Vec<PathBuf>,
    /// Formulations, comma separated, the first being the reference of the
    /// divergences and of the chaos probe (the verdicts against the exact
    /// answers rank every formulation) [default: every formulation that
    /// applies; free-drift only on contact-free cases].
    #[arg(short, long, value_delimiter = ',')]
    formulations: Option<Vec<String>>,
    /// Report folder. A folder holding the cases of an earlier report that
    /// this one does not have is refused before any run (see --replace);
    /// a case folder of the same name is replaced.
    #[arg(short, long, default_value = "reports")]
    out: PathBuf,
    /// Remove, once the new report is written, the case folders of an
    /// earlier report in the output folder that this one does not have,
    /// so the folder holds what its page shows (not when interrupted).
    #[arg(long)]
    replace: bool,
    /// Runs at a time, at least 1 [default: the number of cores].
    #[arg(short, long, value_parser = clap::value_parser!(u64).range(1..))]
    jobs: Option<u64>,
    /// Divergence threshold: RMS position difference between two runs, as a
    /// fraction of the median floe diameter (-).
    #[arg(long, default_value_t = 0.1)]
    threshold: f64,
    /// Smooth integrator of every run, overriding the cases: `dopri5`
    /// (adaptive, exact for constant forces) or `euler` (explicit, as in
    /// Rabatel's report).
    #[arg(long)]
    integrator: Option<IntegratorKind>,
    /// Runs of each (case, formulation), at least 1: CPU times are reported
    /// as median and spread, and the physics of the repeats must be
    /// bit-identical (a difference is reported as a finding). With 2 or
    /// more, a pair whose repeats take under 0.25 s of CPU in all is run
    /// again until they take about that much (at most 200 runs).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    repeat: u64,
    /// Also write each run's trajectory as CF NetCDF (<formulation>/trajectory.nc).
    #[arg(long)]
    netcdf: bool,
    /// Let a formulation that ignores contacts (free-drift), named in -f,
    /// run a case where contacts can happen (floes pass through each other).
    #[arg(long)]
    allow_contacts: bool,
    /// No progress bars.
    #[arg(short, long)]
    quiet: bool,
}

/// Runs the comparison, writes the report and prints each case's verdicts;
/// with `--replace`, removes the case folders of an earlier report not in
/// this one (not when interrupted: then the status is [`INTERRUPTED`]).
/// The arguments and the output folder (that it can be written, and that
/// it holds no earlier case without `--replace`) are checked before any
/// run.
pub fn run(args: Args) -> Outcome {
    let mut opts = CompareOptions {
        progress: !args.quiet,
        divergence_threshold: args.threshold,
        integrator: args.integrator,
        repeat: count(args.repeat),
        ..CompareOptions::default()
    };
    if let Some(f) = args.formulations {
        opts.formulations = f;
    }
    if let Some(j) = args.jobs {
        opts.jobs = count(j);
    }
    let out = args.out.as_path();
    if !(opts.divergence_threshold > 0.0 && opts.divergence_threshold.is_finite()) {
        return Err("--threshold must be a positive number".into());
    }
    known_formulations(&opts.formulations)?;
    let loaded = load_cases_for(&args.cases, &opts.formulations, args.allow_contacts)?;
    let names: Vec<String> = loaded.iter().map(|(_, s)| s.name.clone()).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    // The output folder is checked before any run: a mistake costs nothing.
    report::folder::check(out, &names).map_err(|e| format!("-o: {e}"))?;
    let earlier = report::folder::earlier(out, &names).map_err(|e| format!("-o: {e}"))?;
    if !(earlier.is_empty() || args.replace) {
        return Err(format!(
            "-o: {} holds {} of an earlier report that this one does not have ({}); \
             --replace removes them once this report is written, or choose another -o",
            out.display(),
            plural(earlier.len(), "case folder"),
            earlier.join(", ")
        ));
    }
    writable_folder("-o", out)?;
    for (_, scn) in &loaded {
        eprintln!("{}", describe(scn));
    }
    eprintln!(
        "{}, {} runs at a time",
        plural(loaded.len(), "case"),
        opts.jobs
    );
    let comps = compare::compare(loaded, &opts).map_err(|e| e.to_string())?;
    let interrupted = floebench::run::interrupt::requested();
    let reported: Vec<&str> = comps.iter().map(|c| c.scenario.name.as_str()).collect();
    if interrupted {
        let missing: Vec<&str> = names
            .iter()
            .copied()
            .filter(|n| !reported.contains(n))
            .collect();
        eprintln!(
            "interrupted: {} not reported (runs not finished): {}",
            plural(missing.len(), "case"),
            missing.join(", ")
        );
        if comps.is_empty() {
            return Ok(ExitCode::from(INTERRUPTED));
        }
    }
    let command = command_line();
    let paths = report::compare::write_report_with(&comps, out, &command, args.netcdf)
        .map_err(|e| e.to_string())?;
    for c in &comps {
        println!("{}", c.scenario.name);
        for v in report::verdict::verdict(c) {
            println!("  {v}");
        }
    }
    for p in paths {
        println!("wrote {}", p.display());
    }
    if interrupted {
        // The unfinished cases' earlier folders are kept, not cleared.
        return Ok(ExitCode::from(INTERRUPTED));
    }
    if !args.replace {
        return Ok(ExitCode::SUCCESS);
    }
    let removed = report::folder::remove_stale(out, &reported).map_err(|e| e.to_string())?;
    for dir in removed {
        eprintln!(
            "removed {} (a case of an earlier report into this folder, not in this one: --replace)",
            dir.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}
