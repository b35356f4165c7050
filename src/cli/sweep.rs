//! `floebench sweep`: run a sweep plan's points (here, or as a Slurm job
//! array), then merge the finished points into the report.

use super::{command_line, count, plural, writable_folder, Outcome, INTERRUPTED};
use floebench::sweep::plan::Plan;
use floebench::sweep::points::Point;
use floebench::sweep::{self, execute, plan, points, slurm};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The arguments of `floebench sweep`.
#[derive(clap::Args)]
pub struct Args {
    /// The plan file (.toml).
    plan: PathBuf,
    /// Output folder [default: sweeps/<plan name>].
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// Runs at a time, at least 1 [default: the number of cores].
    #[arg(short, long, value_parser = clap::value_parser!(u64).range(1..))]
    jobs: Option<u64>,
    /// Write a Slurm job array into DIR (sweep.sbatch, submit.sh, logs/)
    /// and the manifest into the output folder, instead of running.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["task", "collect"])]
    slurm: Option<PathBuf>,
    /// Points per array task (with --slurm).
    #[arg(long, default_value_t = 1, requires = "slurm", value_parser = clap::value_parser!(u64).range(1..))]
    chunk: u64,
    /// Time limit of each array task (with --slurm).
    #[arg(long, default_value = "01:00:00", requires = "slurm")]
    slurm_time: String,
    /// Memory of each array task (with --slurm).
    #[arg(long, default_value = "2G", requires = "slurm")]
    slurm_mem: String,
    /// Run array task K of the manifest in the output folder (what
    /// sweep.sbatch does), and nothing else.
    #[arg(long, value_name = "K", conflicts_with = "collect")]
    task: Option<u64>,
    /// Run nothing: merge the finished points and write the report.
    #[arg(long)]
    collect: bool,
    /// No line per finished point.
    #[arg(short, long)]
    quiet: bool,
}

/// Loads the plan and, by the arguments, writes the Slurm job array, runs
/// one array task, or runs the points here (unless `--collect`) and writes
/// the report; ends with [`INTERRUPTED`] when stopped.
pub fn run(args: Args) -> Outcome {
    let plan = plan::load_plan(&args.plan).map_err(|e| e.to_string())?;
    let points = points::points(&plan);
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| sweep::default_out(&plan));
    if out.exists() && !out.is_dir() {
        return Err(format!("-o: {} exists and is not a folder", out.display()));
    }
    writable_folder("-o", &out)?;
    if let Some(dir) = &args.slurm {
        let opts = slurm::SlurmOptions {
            chunk: count(args.chunk),
            time: args.slurm_time.clone(),
            mem: args.slurm_mem.clone(),
        };
        return write_slurm(&plan, &points, &out, dir, &opts);
    }
    if let Some(k) = args.task {
        let k = count(k);
        let done = slurm::manifest_task(&plan, &points, &out, k)
            .and_then(|t| execute::run_task(&plan, &points, &out, &t))
            .map_err(|e| e.to_string())?;
        println!(
            "task {k}: {} run, {} skipped (already finished), {}",
            plural(done.run, "point"),
            done.skipped,
            plural(done.references, "reference run")
        );
        return Ok(status(interrupted(&done)));
    }
    let mut stopped = false;
    if !args.collect {
        let jobs = args.jobs.map_or_else(
            || std::thread::available_parallelism().map_or(1, |n| n.get()),
            count,
        );
        eprintln!(
            "{}: {} on {}, reference {}, {} at a time",
            plan.file.display(),
            plural(points.len(), "point"),
            plural(plan.cases.len(), "case"),
            plan.reference.label(),
            jobs
        );
        let opts = execute::ExecOptions {
            jobs,
            progress: !args.quiet,
        };
        let done = execute::run_local(&plan, &points, &out, opts).map_err(|e| e.to_string())?;
        println!(
            "sweep: {} run, {} skipped (already finished), {}",
            plural(done.run, "point"),
            done.skipped,
            plural(done.references, "reference run")
        );
        stopped = interrupted(&done);
    }
    let collected = sweep::collect(&plan, points, &out);
    let missing = collected.missing().len();
    let command = command_line();
    let files = floebench::report::sweep::write_report(&collected, &out, &command)
        .map_err(|e| e.to_string())?;
    for f in files {
        println!("wrote {}", f.display());
    }
    if missing > 0 {
        eprintln!(
            "{} of {} not finished (not in the report)",
            plural(missing, "point"),
            collected.points.len()
        );
    }
    Ok(status(stopped))
}

/// `--slurm DIR`: writes the job array into `dir` and the manifest into
/// `out`, and says how to submit it.
fn write_slurm(
    plan: &Plan,
    points: &[Point],
    out: &Path,
    dir: &Path,
    opts: &slurm::SlurmOptions,
) -> Outcome {
    let exe =
        std::env::current_exe().map_err(|e| format!("cannot find the floebench binary: {e}"))?;
    let w = slurm::write_slurm(plan, points, out, dir, &exe, opts).map_err(|e| e.to_string())?;
    for f in &w.files {
        println!("wrote {}", f.display());
    }
    println!(
        "{} array tasks ({} reference runs, then {} points, {} per task): submit with `sh {}`",
        w.tasks,
        w.references,
        points.len(),
        opts.chunk,
        dir.join("submit.sh").display()
    );
    if w.tasks > slurm::DEFAULT_MAX_ARRAY_INDEX + 1 {
        eprintln!(
            "warning: {} tasks exceed Slurm's default MaxArraySize (1001): use a larger --chunk",
            w.tasks
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Whether the points ran in `done` were interrupted (and if so, says how
/// to go on).
fn interrupted(done: &execute::Executed) -> bool {
    if done.interrupted {
        eprintln!("interrupted: the points not finished have no result file; run the same command again to go on");
    }
    done.interrupted
}

/// The exit status of a sweep: [`INTERRUPTED`] if it was stopped.
fn status(stopped: bool) -> ExitCode {
    if stopped {
        ExitCode::from(INTERRUPTED)
    } else {
        ExitCode::SUCCESS
    }
}
