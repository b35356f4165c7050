//! `floebench fc2d`: solve Siconos' 2D frictional contact problem files
//! ([`floebench::model::fc2d`]) with our NSGS, APGD or Lemke, and print per
//! file the contacts, the iterations, both accuracy measures and the CPU.

use super::{writable_file, Outcome, INTERRUPTED};
use floebench::fsio;
use floebench::iterative::{solve_fc2d, Fc2dOperator, Fc2dSolver, MAX_ITERATIONS, TOLERANCE};
use floebench::lcp::timing::median;
use floebench::model::fc2d::read_fc2d;
use floebench::record::clock::thread_cpu_seconds;
use floebench::report::format::{aligned_table, fmt_num, fmt_timing};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Default `--max-iterations` of the command: a cold solve of a file, not a
/// warm-started step (Siconos needs 1,461 sweeps on its 7,002-contact file).
const DEFAULT_MAX_ITERATIONS: u64 = 10_000;

/// The cold runs of `--time` (their median CPU is reported).
const TIMED_RUNS: usize = 5;

/// The columns of `--csv`.
pub const CSV_HEADER: &str = "file,contacts,solver,iterations,residual,siconos_error,cpu_us";

/// `--solver`.
#[derive(Clone, Copy, clap::ValueEnum)]
enum SolverArg {
    /// Nonsmooth Gauss–Seidel on Coulomb's law (stops on our residual).
    Nsgs,
    /// Accelerated projected gradient on the cone relaxation (stops on the
    /// relaxation's residual).
    Apgd,
    /// Lemke on the Stewart–Trinkle LCP of W (dense: at most 2,000 contacts).
    Lemke,
}

impl SolverArg {
    fn solver(self) -> Fc2dSolver {
        match self {
            SolverArg::Nsgs => Fc2dSolver::Nsgs,
            SolverArg::Apgd => Fc2dSolver::Apgd,
            SolverArg::Lemke => Fc2dSolver::Lemke,
        }
    }
}

/// The arguments of `floebench fc2d`.
#[derive(clap::Args)]
pub struct Args {
    /// A problem file (.dat), or a folder: its `*.dat` files, sorted, not
    /// recursive. A file that cannot be read is reported (file, line, token,
    /// what was expected) and skipped; the command then exits with status 1.
    path: PathBuf,
    /// Report the median thread CPU of 5 cold solves (default: one solve).
    #[arg(long)]
    time: bool,
    /// The solver.
    #[arg(long, value_enum, default_value = "nsgs")]
    solver: SolverArg,
    /// Relative residual at which NSGS and APGD stop, in [1e-14, 0.5]
    /// (Siconos' default, 1e-6).
    #[arg(
        long,
        default_value_t = 1e-6,
        value_name = "T",
        allow_negative_numbers = true
    )]
    tolerance: f64,
    /// Most sweeps (NSGS) or iterations (APGD), in [1, 1e7].
    #[arg(long, default_value_t = DEFAULT_MAX_ITERATIONS, value_name = "N")]
    max_iterations: u64,
    /// Also write one CSV row per file:
    /// file,contacts,solver,iterations,residual,siconos_error,cpu_us.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
}

/// One file's row.
struct Row {
    file: String,
    contacts: usize,
    solver: Fc2dSolver,
    iterations: u64,
    converged: bool,
    residual: f64,
    siconos_error: f64,
    cpu_us: f64,
}

/// Solves every file of `args.path` and prints the table; status 1 when a
/// file could not be read or solved, or a solve did not converge.
pub fn run(args: Args) -> Outcome {
    TOLERANCE.check("--tolerance", args.tolerance)?;
    MAX_ITERATIONS.check_integer("--max-iterations", args.max_iterations as i128)?;
    if let Some(file) = &args.csv {
        writable_file("--csv", file)?;
    }
    let files = problem_files(&args.path)?;
    let solver = args.solver.solver();
    let mut rows = Vec::with_capacity(files.len());
    let mut failed = false;
    for f in &files {
        if floebench::run::interrupt::requested() {
            eprintln!("interrupted: nothing written");
            return Ok(ExitCode::from(INTERRUPTED));
        }
        match solve_file(f, solver, &args) {
            Ok(row) => {
                failed |= !row.converged;
                rows.push(row);
            }
            Err(e) => {
                eprintln!("error: {e}");
                failed = true;
            }
        }
    }
    if floebench::run::interrupt::requested() {
        eprintln!("interrupted: nothing written");
        return Ok(ExitCode::from(INTERRUPTED));
    }
    if let Some(file) = &args.csv {
        fsio::write_atomic(file, csv(&rows).as_bytes())
            .map_err(|e| format!("cannot write {}: {e}", file.display()))?;
    }
    println!(
        "{}: {} of {} files solved by {}, tolerance {}, thread CPU {}",
        args.path.display(),
        rows.len(),
        files.len(),
        solver.name(),
        args.tolerance,
        if args.time {
            "median of 5 cold solves"
        } else {
            "of one solve"
        }
    );
    print!("{}", table(&rows));
    Ok(if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// The file `path`, or the `*.dat` files of the folder `path`, sorted.
fn problem_files(path: &Path) -> Result<Vec<PathBuf>, String> {
    if !path.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "dat"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(format!("no *.dat file in {}", path.display()));
    }
    Ok(files)
}

/// Reads and solves one file (the CPU: the operator's construction and the
/// solve, from zero reactions; with `--time` the median of
/// [`TIMED_RUNS`]).
fn solve_file(path: &Path, solver: Fc2dSolver, args: &Args) -> Result<Row, String> {
    let prob = read_fc2d(path).map_err(|e| e.to_string())?;
    let runs = if args.time { TIMED_RUNS } else { 1 };
    let mut cpu = Vec::with_capacity(runs);
    let mut last = None;
    for _ in 0..runs {
        let t0 = thread_cpu_seconds();
        let op = Fc2dOperator::new(&prob);
        let a = solve_fc2d(&prob, &op, solver, args.tolerance, args.max_iterations)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        cpu.push((thread_cpu_seconds() - t0).max(0.0) * 1e6);
        last = Some((op, a));
    }
    let Some((op, a)) = last else {
        return Err(format!("{}: no solve", path.display()));
    };
    let (residual, siconos_error) = op.measures(&a.r);
    Ok(Row {
        file: path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        ),
        contacts: prob.contacts,
        solver,
        iterations: a.iterations,
        converged: a.converged,
        residual,
        siconos_error,
        cpu_us: median(&mut cpu),
    })
}

/// The CSV of `rows` ([`CSV_HEADER`]; numbers in Rust's shortest
/// round-trip form).
fn csv(rows: &[Row]) -> String {
    let mut s = format!("{CSV_HEADER}\n");
    for r in rows {
        s.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            r.file,
            r.contacts,
            r.solver.name(),
            r.iterations,
            r.residual,
            r.siconos_error,
            r.cpu_us
        ));
    }
    s
}

/// The table printed: the CSV's columns, whether the solver's stop test was
/// met, and the CPU per contact update (ns: `cpu / (iterations × contacts)`;
/// for Lemke, per pivot and contact).
fn table(rows: &[Row]) -> String {
    let header = [
        "file",
        "contacts",
        "solver",
        "iterations",
        "converged",
        "residual",
        "siconos_error",
        "cpu_us",
        "ns_per_update",
    ];
    let mut t = vec![header.map(String::from).to_vec()];
    for r in rows {
        let updates = (r.iterations as f64 * r.contacts as f64).max(1.0);
        t.push(vec![
            r.file.clone(),
            r.contacts.to_string(),
            r.solver.name().to_string(),
            r.iterations.to_string(),
            if r.converged { "yes" } else { "no" }.to_string(),
            fmt_num(r.residual),
            fmt_num(r.siconos_error),
            fmt_timing(r.cpu_us),
            fmt_timing(r.cpu_us * 1e3 / updates),
        ]);
    }
    aligned_table(&t)
}
