//! `floebench run`: one case with one formulation, its output files written.

use super::{
    describe, print_warnings, refuse_ignored_contacts, writable_folder, Outcome, INTERRUPTED,
};
use floebench::formulation::{self, load_case, FormulationOptions};
use floebench::model::IntegratorKind;
use floebench::report::format::{fmt_num, fmt_timing};
use floebench::run::{output, EndReason, RunOptions, Runner};
use std::path::PathBuf;
use std::process::ExitCode;

/// The formulation of `floebench run` without `-f`.
const DEFAULT_FORMULATION: &str = "event-driven";

/// The arguments of `floebench run`.
#[derive(clap::Args)]
pub struct Args {
    /// The case file (.toml).
    case: PathBuf,
    /// Formulation (see `floebench formulations`).
    #[arg(short = 'f', long = "formulation", alias = "formulations", value_name = "NAME", default_value = DEFAULT_FORMULATION)]
    formulation: String,
    /// Output folder [default: out/<case name>/<formulation>].
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// Smooth integrator, overriding the case: `dopri5` (adaptive, exact for
    /// constant forces) or `euler` (explicit, as in Rabatel's report).
    #[arg(long)]
    integrator: Option<IntegratorKind>,
    /// Write every LCP the formulation solves into DIR as <seq>.json
    /// (keys M, q, z, w, t, contacts, pivots, status; see
    /// docs/output-format.md, "LCP dumps"); DIR
    /// must be empty or new, and the formulation one that solves LCPs.
    #[arg(long, value_name = "DIR")]
    dump_lcp: Option<PathBuf>,
    /// Let a formulation that ignores contacts (free-drift) run a case
    /// where contacts can happen (floes pass through each other).
    #[arg(long)]
    allow_contacts: bool,
    /// Start from the state of an earlier run of the same case: its
    /// trajectory.csv (e.g. a jammed pack); time starts again at 0.
    #[arg(long, value_name = "TRAJECTORY")]
    from: Option<PathBuf>,
    /// The output time of --from to start from, s [default: its last].
    #[arg(long, value_name = "T", requires = "from")]
    at: Option<f64>,
    /// Also write the trajectory as CF NetCDF (trajectory.nc: time × floe).
    #[arg(long)]
    netcdf: bool,
    /// Diagnostic: solve every LCP that the warm start solves cold too
    /// and count the solves whose two solutions differ (warm_check_*
    /// counters; needs `warm_start = true`; the CPU is then no timing).
    #[arg(long)]
    warm_check: bool,
    /// After the run, also draw its kinetic and dissipated energy and its
    /// floes at three times into the output folder (kinetic, dissipated,
    /// snapshots: .png and .svg, as `compare` draws them).
    #[arg(long)]
    plot: bool,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

/// Runs the case, writes its files and prints a summary line; fails when
/// the run does not complete, and ends with [`INTERRUPTED`] when stopped.
/// Everything that would make the run useless is refused before it starts.
pub fn run(args: Args) -> Outcome {
    let Args {
        case,
        formulation: name,
        out,
        integrator,
        dump_lcp,
        allow_contacts,
        from,
        at,
        netcdf,
        warm_check,
        plot,
        quiet,
    } = args;
    let entry = formulation::entry(&name).map_err(|e| e.to_string())?;
    let mut scn = load_case(&case).map_err(|e| e.to_string())?;
    print_warnings(&scn);
    if let Some(file) = from {
        output::read_state(&file, at)
            .and_then(|(t, bodies)| {
                let restart = floebench::model::Restart { file, t };
                floebench::state::restart(&mut scn, &bodies, restart)
            })
            .map_err(|e| format!("--from: {e}"))?;
        if let Some(r) = &scn.restart {
            eprintln!(
                "starting from {} at t = {} s (time starts again at 0)",
                r.file.display(),
                r.t
            );
        }
    }
    if dump_lcp.is_some() && !entry.dumps_lcps {
        return Err(format!(
            "--dump-lcp: {} writes no LCP dumps (event-driven and moreau do)",
            entry.name
        ));
    }
    refuse_ignored_contacts(
        std::slice::from_ref(&name),
        [(case.as_path(), &scn)],
        allow_contacts,
    )?;
    if let Some(dir) = &dump_lcp {
        if dir.exists() {
            let empty = std::fs::read_dir(dir).map(|mut d| d.next().is_none());
            if !matches!(empty, Ok(true)) {
                return Err(format!(
                    "--dump-lcp: {} exists and is not an empty folder (dumps would mix)",
                    dir.display()
                ));
            }
        }
        writable_folder("--dump-lcp", dir)?;
    }
    let opts = FormulationOptions {
        integrator,
        dump_lcp,
        warm_check,
    };
    let mut form = formulation::build(entry.name, &scn, &opts).map_err(|e| e.to_string())?;
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(&scn.name).join(entry.name));
    if out.exists() && !out.is_dir() {
        return Err(format!("{} exists and is not a folder", out.display()));
    }
    writable_folder("-o", &out)?;
    eprintln!("{}", describe(&scn));
    let runner = Runner::new(RunOptions {
        progress: !quiet,
        multi: None,
        ..Default::default()
    });
    let result = runner.run(&scn, form.name(), form.formulation.as_mut());
    let paths = output::write_run(&out, &result)
        .and_then(|mut paths| {
            if netcdf {
                paths.push(output::write_netcdf(&out, &result, &scn)?);
            }
            Ok(paths)
        })
        .map_err(|e| format!("cannot write to {}: {e}", out.display()))?;
    for p in paths {
        println!("wrote {}", p.display());
    }
    if plot {
        let figs = floebench::report::figures::draw_run(&scn, &result, &out)
            .map_err(|e| format!("--plot: {e}"))?;
        for f in figs {
            for ext in ["png", "svg"] {
                println!("wrote {}", out.join(format!("{}.{ext}", f.stem)).display());
            }
        }
    }
    let s = &result.summary;
    println!(
        "{} / {}: reached t = {} s of {} s; CPU {} s (detection {}, solve {}, integration {}{}); energy residual {} J of {} J exchanged",
        s.case,
        s.formulation,
        s.t_reached,
        s.duration,
        fmt_timing(s.timing.cpu_total),
        fmt_timing(s.timing.stages.detection),
        fmt_timing(s.timing.stages.solve),
        fmt_timing(s.timing.stages.integration),
        if s.timing.stages.lattice > 0.0 {
            format!(", lattice impacts {}", fmt_timing(s.timing.stages.lattice))
        } else {
            String::new()
        },
        fmt_num(s.energy.residual),
        fmt_num(s.energy.exchanged)
    );
    match &s.end {
        EndReason::Completed => Ok(ExitCode::SUCCESS),
        EndReason::Interrupted { .. } => {
            eprintln!("run {}", s.end);
            Ok(ExitCode::from(INTERRUPTED))
        }
        other => {
            eprintln!("run did not complete: {other}");
            Ok(ExitCode::FAILURE)
        }
    }
}
