//! `floebench lcp`: re-solve a dumped LCP, or time every dump of a folder.

use super::{count, writable_file, Outcome, INTERRUPTED};
use floebench::fsio;
use floebench::lcp::timing::{self, TimingOptions};
use floebench::lcp::{residual, solve, Covering, LcpDump, SolveOptions};
use floebench::report::format::fmt_num;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The arguments of `floebench lcp`.
#[derive(clap::Args)]
pub struct Args {
    /// A dump file `<seq>.json`, or with `--time` a folder of dumps
    /// (its `*.json` files, sorted, not recursive).
    path: PathBuf,
    /// Time every dump of the folder: thread CPU time per solve (median of
    /// `--repeat` batches of at least 1 ms), a summary per size bucket.
    #[arg(long)]
    time: bool,
    /// Timed batches per dump (the median is reported).
    #[arg(long, default_value_t = 5, requires = "time", value_parser = clap::value_parser!(u64).range(1..))]
    repeat: u64,
    /// Warm-start every solve from the dump's own stored solution (the
    /// cost of a warm start whose guess is right).
    #[arg(long, requires = "time")]
    warm: bool,
    /// Solve every dump from a basis predicted by block Gauss–Seidel on
    /// its contact blocks, then the warm Lemke path (docs/physics.md
    /// §3.3, "Predicted basis"); the prediction is in the timed CPU.
    #[arg(long, requires = "time", conflicts_with = "warm")]
    predict: bool,
    /// Sweep cap of the prediction [default: 100].
    #[arg(long, value_name = "N", requires = "predict", value_parser = clap::value_parser!(u64).range(1..))]
    predict_sweeps: Option<u64>,
    /// Also write one CSV row per dump:
    /// file,n,contacts,pivots,status,accepted_attempt,residual,cpu_us,first_termination,first_pivots,predict_sweeps,predict_wrong,predict_ties,support.
    #[arg(long, value_name = "FILE", requires = "time")]
    csv: Option<PathBuf>,
    /// Problems of at least this many unknowns run on the factorised
    /// (revised) Lemke path; 0 always, a large number never [default:
    /// the driver's, 41].
    #[arg(long, value_name = "N", requires = "time")]
    revised_from: Option<usize>,
    /// Residual (relative to ‖q‖) at or below which an accepted Lemke
    /// candidate of at most 40 unknowns is kept without refinement; 0
    /// refines every candidate [default: the driver's, 1e-13]
    #[arg(
        long,
        value_name = "R",
        requires = "time",
        visible_alias = "small-unpolished-below"
    )]
    unpolished_below: Option<f64>,
    /// Pivot tolerance of the Lemke attempts (relative to the largest
    /// entry of the entering column of the scaled tableau) [default:
    /// the driver's, 1e-10]
    #[arg(long, value_name = "T", requires = "time")]
    pivot_tol: Option<f64>,
    /// Problems of at least this many unknowns start with the Harris
    /// attempt, before the lexicographic one; 0 always [default: the
    /// driver's, never]
    #[arg(long, value_name = "N", requires = "time")]
    harris_from: Option<usize>,
    /// Covering vector of the cold Lemke attempts: `ones` (d = e),
    /// `sqrt-diagonal` (the alternative attempt's), or `diagonal:F`
    /// (d_i = max(|M_ii| / max|M_jj|, F), F in (0, 1]) [default: the
    /// driver's, diagonal:1e-3]
    #[arg(long, value_name = "D", requires = "time", value_parser = parse_covering)]
    covering: Option<Covering>,
}

/// With `--time`, times every dump of the folder (or the one file);
/// without, re-solves one dump file and fails when the solve does not.
pub fn run(args: Args) -> Outcome {
    if args.time {
        let opts = timing_options(&args)?;
        if let Some(file) = &args.csv {
            writable_file("--csv", file)?;
        }
        time_lcps(&args.path, &opts, args.csv.as_deref())
    } else if args.path.is_dir() {
        Err(format!(
            "{} is a folder: give one dump file, or --time to time every dump of it",
            args.path.display()
        ))
    } else {
        resolve_lcp(&args.path)
    }
}

/// The timing options of `--time`: the driver's defaults, with what the
/// arguments override (a bad `--unpolished-below` or `--pivot-tol` is an
/// error).
fn timing_options(args: &Args) -> Result<TimingOptions, String> {
    let mut opts = TimingOptions {
        repeats: count(args.repeat),
        warm: args.warm,
        predict: args.predict.then(|| {
            let mut p = floebench::lcp::predict::PredictOptions::default();
            if let Some(k) = args.predict_sweeps {
                p.max_sweeps = count(k);
            }
            p
        }),
        ..Default::default()
    };
    if let Some(k) = args.revised_from {
        opts.solve.revised_from = k;
    }
    if let Some(r) = args.unpolished_below {
        if !(r.is_finite() && r >= 0.0) {
            return Err(format!(
                "--unpolished-below must be a finite number >= 0, got {r}"
            ));
        }
        opts.solve.unpolished_below = r;
    }
    if let Some(t) = args.pivot_tol {
        if !(t.is_finite() && t > 0.0 && t < 1.0) {
            return Err(format!("--pivot-tol must be a number in (0, 1), got {t}"));
        }
        opts.solve.pivot_tol = t;
    }
    if let Some(k) = args.harris_from {
        opts.solve.harris_from = k;
    }
    if let Some(c) = &args.covering {
        opts.solve.covering = c.clone();
    }
    Ok(opts)
}

/// Re-solves the dump `file` and prints its stored and new solutions'
/// residuals and each attempt; fails when the re-solve does not solve.
fn resolve_lcp(file: &Path) -> Outcome {
    let dump = LcpDump::read(file).map_err(|e| e.to_string())?;
    let lcp = dump
        .to_lcp()
        .map_err(|e| format!("{}: {e}", file.display()))?;
    let stored = residual(&lcp.m, &lcp.q, &dump.z);
    let sol = solve(&lcp, &SolveOptions::default());
    println!(
        "{}: n = {}, contacts = {}, t = {} s",
        file.display(),
        lcp.n,
        dump.contacts,
        dump.t
    );
    println!(
        "stored solution: status {}, {} pivots, residual {}",
        dump.status,
        dump.pivots,
        fmt_num(stored)
    );
    println!(
        "re-solved:       status {}, {} pivots, residual {}, accepted by {}",
        sol.status.as_str(),
        sol.pivots,
        fmt_num(sol.residual),
        sol.accepted_by
            .map_or("no attempt".to_string(), |s| format!("{s:?}"))
    );
    for a in &sol.attempts {
        println!(
            "  attempt {:?} (rule {:?}, eps {}): {:?} after {} pivots, residual {}",
            a.strategy,
            a.rule,
            a.epsilon_rel,
            a.termination,
            a.pivots,
            fmt_num(a.residual)
        );
    }
    if sol.status == floebench::lcp::SolveStatus::Interrupted {
        Ok(ExitCode::from(INTERRUPTED))
    } else if sol.status.is_solved() {
        Ok(ExitCode::SUCCESS)
    } else {
        Ok(ExitCode::FAILURE)
    }
}

/// Times every dump of the folder `path` (or the one file `path`), writes
/// the rows to `csv` if given and prints the summary per size bucket.
fn time_lcps(path: &Path, opts: &TimingOptions, csv: Option<&Path>) -> Outcome {
    let files = if path.is_dir() {
        timing::dump_files(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?
    } else {
        vec![path.to_path_buf()]
    };
    if files.is_empty() {
        return Err(format!("no *.json dump in {}", path.display()));
    }
    let mut rows = Vec::with_capacity(files.len());
    for f in &files {
        if floebench::run::interrupt::requested() {
            // A signal: the solves it cut short are no timing.
            eprintln!("interrupted: nothing written");
            return Ok(ExitCode::from(INTERRUPTED));
        }
        rows.push(timing::time_file(f, opts).map_err(|e| e.to_string())?);
    }
    if floebench::run::interrupt::requested() {
        eprintln!("interrupted: nothing written");
        return Ok(ExitCode::from(INTERRUPTED));
    }
    if let Some(file) = csv {
        fsio::write_atomic(file, timing::csv(&rows).as_bytes())
            .map_err(|e| format!("cannot write {}: {e}", file.display()))?;
    }
    println!(
        "{}: {} dumps, thread CPU per solve (median of {} batches of >= 1 ms){}",
        path.display(),
        rows.len(),
        opts.repeats,
        if opts.predict.is_some() {
            ", from a predicted basis (block Gauss-Seidel, then warm Lemke)"
        } else if opts.warm {
            ", warm-started from each dump's stored solution"
        } else {
            ""
        }
    );
    print!("{}", timing::format_summary(&timing::summarize(&rows)));
    Ok(ExitCode::SUCCESS)
}

/// `--covering`: `ones`, `sqrt-diagonal` or `diagonal:F` with F in (0, 1].
fn parse_covering(s: &str) -> Result<Covering, String> {
    match s {
        "ones" => Ok(Covering::Ones),
        "sqrt-diagonal" => Ok(Covering::Diagonal),
        _ => {
            let f = s
                .strip_prefix("diagonal:")
                .and_then(|f| f.parse::<f64>().ok())
                .ok_or_else(|| format!("expected ones, sqrt-diagonal or diagonal:F, got {s:?}"))?;
            if f > 0.0 && f <= 1.0 {
                Ok(Covering::DiagonalRatio(f))
            } else {
                Err(format!(
                    "the floor F of diagonal:F must be in (0, 1], got {f}"
                ))
            }
        }
    }
}
