//! The `floebench` command line: parse arguments, call the library.

use clap::{Parser, Subcommand};
use floebench::compare::CompareOptions;
use floebench::formulation::{self, load_case, FormulationOptions};
use floebench::model::{IntegratorKind, Scenario};
use floebench::report::format::fmt_num;
use floebench::run::{output, EndReason, RunOptions, Runner};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "floebench",
    version,
    about = "Contact mechanics of sea-ice floes: run the same cases with several contact formulations",
    long_about = "floebench runs sea-ice floe scenarios (TOML case files, see docs/case-format.md) \
                  with several contact formulations and writes trajectories, energy ledgers \
                  and counters as CSV/JSON.\n\nStart with:\n  floebench validate cases/free_drift_coriolis.toml\n  floebench run cases/free_drift_coriolis.toml"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check case files and print what they contain; reports every bad file
    /// and exits non-zero if there is one.
    Validate {
        /// Case files (.toml) or folders (their *.toml files, not subfolders).
        #[arg(required = true)]
        cases: Vec<PathBuf>,
    },
    /// Run one case with one formulation; writes trajectory.csv, energy.csv and summary.json.
    Run {
        /// The case file (.toml).
        case: PathBuf,
        /// Formulation (see `floebench formulations`).
        #[arg(short = 'f', long = "formulations", visible_alias = "formulation", default_value = DEFAULT_FORMULATION)]
        formulation: String,
        /// Output folder [default: out/<case name>/<formulation>].
        #[arg(short, long)]
        out: Option<PathBuf>,
        /// Smooth integrator, overriding the case: `dopri5` (adaptive, exact for
        /// constant forces) or `euler` (explicit, as in Rabatel's report).
        #[arg(long)]
        integrator: Option<IntegratorKind>,
        /// Write every LCP the formulation solves into DIR as <seq>.json
        /// (keys M, q, z, w, t, contacts, pivots, status; see README); DIR
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
        /// No progress bar.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Run several formulations on the same cases and write a comparison report:
    /// per case metrics.csv, divergence.csv, summary.json, each run's data and the
    /// plots; then index.md and index.html.
    Compare {
        /// Case files, or folders of case files (their *.toml, not recursive).
        #[arg(required = true)]
        cases: Vec<PathBuf>,
        /// Formulations, comma separated, the first being the reference of the
        /// verdicts [default: every formulation that applies; free-drift only on
        /// contact-free cases].
        #[arg(short, long, value_delimiter = ',')]
        formulations: Option<Vec<String>>,
        /// Report folder.
        #[arg(short, long, default_value = "reports")]
        out: PathBuf,
        /// Runs at a time, at least 1 [default: the number of cores].
        #[arg(short, long, value_parser = clap::value_parser!(u64).range(1..))]
        jobs: Option<u64>,
        /// Divergence threshold: RMS position difference between two runs, as a
        /// fraction of the mean floe diameter (-).
        #[arg(long, default_value_t = 0.1)]
        threshold: f64,
        /// Smooth integrator, overriding the cases.
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
        /// No progress bars.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Run the physical checks (docs/physics.md §6) on cases and print a table;
    /// exits non-zero when a formulation fails a check it claims to pass.
    Check {
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
        /// Runs of each (case, formulation), at least 1: CPU times are reported
        /// as median and spread, and the physics of the repeats must be
        /// bit-identical (a difference is reported as a finding). With 2 or
        /// more, a pair whose repeats take under 0.25 s of CPU in all is run
        /// again until they take about that much (at most 200 runs).
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
        repeat: u64,
        /// No progress bars.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Re-solve a dumped LCP (from `run --dump-lcp`) and print its residual;
    /// with `--time`, re-solve and time every dump of a folder.
    Lcp {
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
            alias = "small-unpolished-below"
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
        covering: Option<floebench::lcp::Covering>,
    },
    /// Run a sweep plan (docs/sweep-format.md): every point of cases x
    /// formulations x settings, measured against the reference; writes
    /// points/<id>.json, sweep.csv, orders.csv, plots and index.md/html.
    /// A finished point is never recomputed.
    Sweep {
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
    },
    /// Resolve a 1D percussion of bars in a mass-spring-dashpot chain
    /// (docs/physics.md §7.1): prints the pieces as CSV
    /// (fragment,first,last,mass,length,centre,velocity) and a summary on
    /// stderr.
    #[command(name = "percussion-1d")]
    Percussion1d {
        /// A bar, left to right, touching the previous one:
        /// LENGTH,NODES,VELOCITY (m, number of masses, m/s); give at least one.
        #[arg(long = "bar", required = true, value_name = "L,N,V", value_parser = parse_bar)]
        bars: Vec<floebench::fracture::chain::BarSpec>,
        /// Density, kg/m³.
        #[arg(long, default_value_t = floebench::model::DEFAULT_ICE_DENSITY)]
        density: f64,
        /// Young's modulus, Pa.
        #[arg(long, default_value_t = 8.95e9)]
        young: f64,
        /// Cross-section, m².
        #[arg(long, default_value_t = 1.0)]
        area: f64,
        /// Dashpot ratio beta (-): c = beta sqrt(k m); 0 for none.
        #[arg(long, default_value_t = 0.5)]
        damping: f64,
        /// Bonds break when their tension passes this force, N [default: never].
        #[arg(long, conflicts_with = "toughness")]
        strength: Option<f64>,
        /// Bonds break when their energy passes G A, G in J/m² [default: never].
        #[arg(long)]
        toughness: Option<f64>,
        /// Safety factor on the stable step, in (0, 1].
        #[arg(long, default_value_t = 0.9)]
        safety: f64,
        /// Internal energy, as a fraction of the initial energy, under which
        /// the waves have settled (-).
        #[arg(long, default_value_t = 1e-3)]
        settle: f64,
        /// Transit times of the longest bar after the contact ended after
        /// which the run stops even if the waves ring on.
        #[arg(long, default_value_t = 4.0)]
        settle_transits: f64,
        /// Transit times of the longest bar after which the run stops in any case.
        #[arg(long, default_value_t = 200.0)]
        limit_transits: f64,
        /// Also write the final nodes as CSV (node,bar,fragment,x,v) to FILE.
        #[arg(long, value_name = "FILE")]
        nodes: Option<PathBuf>,
    },
    /// Resolve a 2D percussion in the lattice of a rectangular floe
    /// (docs/physics.md §7.3), struck on its left face along +x: prints
    /// the pieces as CSV (piece,nodes,mass,x,y,vx,vy,omega,hull_area) and a
    /// summary on stderr.
    #[command(name = "percussion-2d")]
    Percussion2d {
        /// Floe size WIDTH,HEIGHT, m.
        #[arg(long, value_name = "W,H", default_value = "10,10", value_parser = parse_pair)]
        size: (f64, f64),
        /// Lattice spacing, m.
        #[arg(long, default_value_t = 0.5)]
        spacing: f64,
        /// Thickness, m.
        #[arg(long, default_value_t = 1.0)]
        thickness: f64,
        /// Density, kg/m³.
        #[arg(long, default_value_t = floebench::model::DEFAULT_ICE_DENSITY)]
        density: f64,
        /// Young's modulus, Pa.
        #[arg(long, default_value_t = 8.95e9)]
        young: f64,
        /// Poisson ratio (-), in (-1, 1/3]: 1/3 is central springs alone,
        /// below it torsion springs at the triangle corners (ice: 0.3).
        #[arg(long, default_value_t = 1.0 / 3.0)]
        poisson: f64,
        /// Seed of the lattice's nodes.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Dashpot ratio beta (-): c = beta sqrt(k m); 0 for none.
        #[arg(long, default_value_t = 0.5)]
        damping: f64,
        /// Bonds break past this strain (-) [default: never].
        #[arg(long, conflicts_with = "toughness")]
        strain: Option<f64>,
        /// Bonds break when their energy passes G h w, G in J/m² [default: never].
        #[arg(long)]
        toughness: Option<f64>,
        /// Relative normal speed of the impact, m/s.
        #[arg(long)]
        speed: f64,
        /// The striker's effective mass, kg [default: a fixed coast, the
        /// floe moving at SPEED into it].
        #[arg(long)]
        mass: Option<f64>,
        /// Height of the contact point on the left face, m [default: its middle].
        #[arg(long)]
        at: Option<f64>,
        /// Draw the lattice, its broken bonds red, into STEM.png and STEM.svg.
        #[arg(long, value_name = "STEM")]
        plot: Option<PathBuf>,
    },
    /// List the formulations.
    Formulations,
}

const DEFAULT_FORMULATION: &str = "event-driven";

/// The exit status of a command stopped by SIGINT or SIGTERM (128 + 2, as
/// shells report a Ctrl-C).
const INTERRUPTED: u8 = 130;

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = floebench::run::interrupt::install() {
        eprintln!("warning: Ctrl-C will not end runs cleanly: {e}");
    }
    match cli.command {
        Command::Validate { cases } => validate(&cases),
        Command::Run {
            case,
            formulation,
            out,
            integrator,
            dump_lcp,
            allow_contacts,
            from,
            at,
            netcdf,
            warm_check,
            quiet,
        } => run(
            &case,
            &formulation,
            RunArgs {
                out,
                integrator,
                dump_lcp,
                allow_contacts,
                from: from.map(|f| (f, at)),
                netcdf,
                warm_check,
                quiet,
            },
        ),
        Command::Compare {
            cases,
            formulations,
            out,
            jobs,
            threshold,
            integrator,
            repeat,
            netcdf,
            quiet,
        } => {
            let mut opts = CompareOptions {
                progress: !quiet,
                divergence_threshold: threshold,
                integrator,
                repeat: usize::try_from(repeat).unwrap_or(usize::MAX),
                ..CompareOptions::default()
            };
            if let Some(f) = formulations {
                opts.formulations = f;
            }
            if let Some(j) = jobs {
                opts.jobs = usize::try_from(j).unwrap_or(usize::MAX);
            }
            compare(&cases, &opts, &out, netcdf)
        }
        Command::Lcp {
            path,
            time,
            repeat,
            warm,
            predict,
            predict_sweeps,
            csv,
            revised_from,
            unpolished_below,
            pivot_tol,
            harris_from,
            covering,
        } => {
            if time {
                let mut opts = floebench::lcp::timing::TimingOptions {
                    repeats: repeat as usize,
                    warm,
                    predict: predict.then(|| {
                        let mut p = floebench::lcp::predict::PredictOptions::default();
                        if let Some(k) = predict_sweeps {
                            p.max_sweeps = usize::try_from(k).unwrap_or(usize::MAX);
                        }
                        p
                    }),
                    ..Default::default()
                };
                if let Some(k) = revised_from {
                    opts.solve.revised_from = k;
                }
                if let Some(r) = unpolished_below {
                    if !(r.is_finite() && r >= 0.0) {
                        eprintln!(
                            "error: --unpolished-below must be a finite number >= 0, got {r}"
                        );
                        return ExitCode::FAILURE;
                    }
                    opts.solve.unpolished_below = r;
                }
                if let Some(t) = pivot_tol {
                    if !(t.is_finite() && t > 0.0 && t < 1.0) {
                        eprintln!("error: --pivot-tol must be a number in (0, 1), got {t}");
                        return ExitCode::FAILURE;
                    }
                    opts.solve.pivot_tol = t;
                }
                if let Some(k) = harris_from {
                    opts.solve.harris_from = k;
                }
                if let Some(c) = covering {
                    opts.solve.covering = c;
                }
                time_lcps(&path, opts, csv.as_deref())
            } else if path.is_dir() {
                eprintln!(
                    "error: {} is a folder: give one dump file, or --time to time every dump of it",
                    path.display()
                );
                ExitCode::FAILURE
            } else {
                resolve_lcp(&path)
            }
        }
        Command::Check {
            cases,
            formulations,
            markdown,
            repeat,
            quiet,
        } => check(
            &cases,
            formulations,
            markdown.as_deref(),
            usize::try_from(repeat).unwrap_or(usize::MAX),
            quiet,
        ),
        Command::Sweep {
            plan,
            out,
            jobs,
            slurm,
            chunk,
            slurm_time,
            slurm_mem,
            task,
            collect,
            quiet,
        } => sweep(
            &plan,
            SweepArgs {
                out,
                jobs: jobs.map_or_else(
                    || std::thread::available_parallelism().map_or(1, |n| n.get()),
                    |j| usize::try_from(j).unwrap_or(usize::MAX),
                ),
                slurm: slurm.map(|dir| {
                    (
                        dir,
                        floebench::sweep::slurm::SlurmOptions {
                            chunk: usize::try_from(chunk).unwrap_or(usize::MAX),
                            time: slurm_time,
                            mem: slurm_mem,
                        },
                    )
                }),
                task: task.map(|k| usize::try_from(k).unwrap_or(usize::MAX)),
                collect,
                quiet,
            },
        ),
        Command::Percussion1d {
            bars,
            density,
            young,
            area,
            damping,
            strength,
            toughness,
            safety,
            settle,
            settle_transits,
            limit_transits,
            nodes,
        } => {
            use floebench::fracture::chain::{BondRule, ChainOptions, Material};
            let material = Material {
                density,
                young,
                area,
            };
            let options = ChainOptions {
                damping,
                bond: match (strength, toughness) {
                    (Some(f), _) => BondRule::Force(f),
                    (None, Some(g)) => BondRule::Toughness(g),
                    (None, None) => BondRule::Unbreakable,
                },
                safety,
                settle,
                settle_transits,
                limit_transits,
            };
            percussion_1d(&material, &bars, options, nodes.as_deref())
        }
        Command::Percussion2d {
            size,
            spacing,
            thickness,
            density,
            young,
            poisson,
            seed,
            damping,
            strain,
            toughness,
            speed,
            mass,
            at,
            plot,
        } => {
            use floebench::fracture::chain::{BondRule, ChainOptions};
            use floebench::fracture::lattice::LatticeSpec;
            let spec = LatticeSpec {
                spacing,
                thickness,
                density,
                young,
                poisson,
                seed,
                ..LatticeSpec::default()
            };
            let options = ChainOptions {
                damping,
                bond: match (strain, toughness) {
                    (Some(e), _) => BondRule::Strain(e),
                    (None, Some(g)) => BondRule::Toughness(g),
                    (None, None) => BondRule::Unbreakable,
                },
                ..ChainOptions::default()
            };
            let strike = Strike {
                size,
                speed,
                mass,
                at: at.unwrap_or(0.5 * size.1),
            };
            percussion_2d(spec, options, strike, plot.as_deref())
        }
        Command::Formulations => {
            for formulation::Entry {
                name,
                description: what,
                ..
            } in formulation::REGISTRY
            {
                println!("{name:<14} {what}");
            }
            ExitCode::SUCCESS
        }
    }
}

/// Every name of `names` is a formulation of the registry (else the error
/// naming the first that is not), checked before any case is loaded.
fn known_formulations(names: &[String]) -> Result<(), String> {
    names
        .iter()
        .try_for_each(|f| formulation::entry(f).map(|_| ()))
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

fn describe(scn: &Scenario) -> String {
    let mass: f64 = scn.floes.iter().map(|f| f.mass).sum();
    let area: f64 = scn.floes.iter().map(|f| f.area).sum();
    let dt = (0..scn.floes.len())
        .map(|i| scn.euler_stability_bound(i))
        .fold(f64::INFINITY, f64::min);
    format!(
        "{}: {} ({} kg, {} m^2), {}, {} s every {} s, e = {}, mu = {}, Euler bound {}",
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
            "none (no drag)".into()
        }
    )
}

fn validate(cases: &[PathBuf]) -> ExitCode {
    let files = match floebench::run::batch::case_files(cases) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut bad = 0;
    for path in &files {
        match load_case(path) {
            Ok(scn) => println!("ok  {}", describe(&scn)),
            Err(e) => {
                eprintln!("error: {e}");
                bad += 1;
            }
        }
    }
    if bad > 0 {
        eprintln!("{} of {} bad", plural(bad, "case file"), files.len());
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// The options of `floebench run`.
struct RunArgs {
    out: Option<PathBuf>,
    integrator: Option<IntegratorKind>,
    dump_lcp: Option<PathBuf>,
    allow_contacts: bool,
    /// A trajectory file and the output time to start from.
    from: Option<(PathBuf, Option<f64>)>,
    /// Also write trajectory.nc.
    netcdf: bool,
    /// Solve each warm-solved LCP cold too and count the differences.
    warm_check: bool,
    quiet: bool,
}

fn run(case: &Path, name: &str, args: RunArgs) -> ExitCode {
    let RunArgs {
        out,
        integrator,
        dump_lcp,
        allow_contacts,
        from,
        netcdf,
        warm_check,
        quiet,
    } = args;
    let entry = match formulation::entry(name) {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut scn = match load_case(case) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Some((file, at)) = from {
        let started = output::read_state(&file, at).and_then(|(t, bodies)| {
            let restart = floebench::model::Restart { file, t };
            floebench::state::restart(&mut scn, &bodies, restart)
        });
        if let Err(e) = started {
            eprintln!("error: --from: {e}");
            return ExitCode::FAILURE;
        }
        if let Some(r) = &scn.restart {
            eprintln!(
                "starting from {} at t = {} s (time starts again at 0)",
                r.file.display(),
                r.t
            );
        }
    }
    if dump_lcp.is_some() && !entry.dumps_lcps {
        eprintln!(
            "error: --dump-lcp: {} writes no LCP dumps (event-driven and moreau do)",
            entry.name
        );
        return ExitCode::FAILURE;
    }
    if !entry.applies(&scn) && !allow_contacts {
        eprintln!(
            "error: {} ignores contacts and {} has obstacles or moving floes; --allow-contacts runs it anyway",
            entry.name,
            case.display()
        );
        return ExitCode::FAILURE;
    }
    if let Some(dir) = &dump_lcp {
        if dir.exists() {
            let empty = std::fs::read_dir(dir).map(|mut d| d.next().is_none());
            if !matches!(empty, Ok(true)) {
                eprintln!(
                    "error: --dump-lcp: {} exists and is not an empty folder (dumps would mix)",
                    dir.display()
                );
                return ExitCode::FAILURE;
            }
        }
        if let Err(e) = std::fs::create_dir_all(dir) {
            eprintln!("error: cannot create {}: {e}", dir.display());
            return ExitCode::FAILURE;
        }
    }
    let opts = FormulationOptions {
        integrator,
        dump_lcp,
        warm_check,
    };
    let mut form = match formulation::build(entry.name, &scn, &opts) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(&scn.name).join(entry.name));
    if out.exists() && !out.is_dir() {
        eprintln!("error: {} exists and is not a folder", out.display());
        return ExitCode::FAILURE;
    }
    eprintln!("{}", describe(&scn));
    let runner = Runner::new(RunOptions {
        progress: !quiet,
        multi: None,
    });
    let result = runner.run(&scn, form.name(), form.formulation.as_mut());
    let written = output::write_run(&out, &result).and_then(|mut paths| {
        if netcdf {
            paths.push(output::write_netcdf(&out, &result, &scn)?);
        }
        Ok(paths)
    });
    match written {
        Ok(paths) => {
            for p in paths {
                println!("wrote {}", p.display());
            }
        }
        Err(e) => {
            eprintln!("error: cannot write to {}: {e}", out.display());
            return ExitCode::FAILURE;
        }
    }
    let s = &result.summary;
    println!(
        "{} / {}: reached t = {} s of {} s; CPU {} s (detection {}, solve {}, integration {}); energy residual {} J of {} J exchanged",
        s.case,
        s.formulation,
        s.t_reached,
        s.duration,
        fmt_num(s.timing.cpu_total),
        fmt_num(s.timing.stages.detection),
        fmt_num(s.timing.stages.solve),
        fmt_num(s.timing.stages.integration),
        fmt_num(s.energy.residual),
        fmt_num(s.energy.exchanged)
    );
    match &s.end {
        EndReason::Completed => ExitCode::SUCCESS,
        EndReason::Interrupted { .. } => {
            eprintln!("run {}", s.end);
            ExitCode::from(INTERRUPTED)
        }
        other => {
            eprintln!("run did not complete: {other}");
            ExitCode::FAILURE
        }
    }
}

fn compare(cases: &[PathBuf], opts: &CompareOptions, out: &Path, netcdf: bool) -> ExitCode {
    use floebench::compare;
    use floebench::report;
    use floebench::run::batch;
    if !(opts.divergence_threshold > 0.0 && opts.divergence_threshold.is_finite()) {
        eprintln!("error: --threshold must be a positive number");
        return ExitCode::FAILURE;
    }
    if let Err(e) = known_formulations(&opts.formulations) {
        eprintln!("error: -f: {e}");
        return ExitCode::FAILURE;
    }
    let loaded = match batch::load_cases(cases) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let names: Vec<String> = loaded.iter().map(|(_, s)| s.name.clone()).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    // The output folder is checked before any run: a mistake costs nothing.
    if let Err(e) = report::folder::check(out, &names) {
        eprintln!("error: -o: {e}");
        return ExitCode::FAILURE;
    }
    for (_, scn) in &loaded {
        eprintln!("{}", describe(scn));
    }
    eprintln!(
        "{}, {} runs at a time",
        plural(loaded.len(), "case"),
        opts.jobs
    );
    let comps = match compare::compare(loaded, opts) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
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
            return ExitCode::from(INTERRUPTED);
        }
    }
    let command = command_line();
    match report::compare::write_report_with(&comps, out, &command, netcdf) {
        Ok(paths) => {
            for c in &comps {
                println!("{}", c.scenario.name);
                for v in report::verdict::verdict(c) {
                    println!("  {v}");
                }
            }
            for p in paths {
                println!("wrote {}", p.display());
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    }
    if interrupted {
        // The unfinished cases' earlier folders are kept, not cleared.
        return ExitCode::from(INTERRUPTED);
    }
    match report::folder::remove_stale(out, &reported) {
        Ok(removed) => {
            for dir in removed {
                eprintln!(
                    "removed {} (a case of an earlier report into this folder, not in this one)",
                    dir.display()
                );
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn check(
    cases: &[PathBuf],
    formulations: Option<Vec<String>>,
    markdown: Option<&Path>,
    repeat: usize,
    quiet: bool,
) -> ExitCode {
    use floebench::analysis::check;
    use floebench::report::checks::{format_table, markdown_table};
    use floebench::run::batch::{self, BatchOptions};
    let mut opts = BatchOptions {
        progress: !quiet,
        repeat,
        ..BatchOptions::default()
    };
    if let Some(f) = formulations {
        opts.formulations = f;
    }
    if let Err(e) = known_formulations(&opts.formulations) {
        eprintln!("error: -f: {e}");
        return ExitCode::FAILURE;
    }
    let done = match batch::load_cases(cases).and_then(|loaded| batch::run_cases(loaded, &opts)) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let rows: Vec<check::CheckOutcome> = done
        .iter()
        .flat_map(|c| check::check_runs(&c.scenario, &c.runs))
        .collect();
    print!("{}", format_table(&rows));
    for f in done.iter().flat_map(|c| &c.findings) {
        println!("finding: {f}");
    }
    if let Some(file) = markdown {
        if let Err(e) = floebench::run::output::write_atomic(file, markdown_table(&rows).as_bytes())
        {
            eprintln!("error: cannot write {}: {e}", file.display());
            return ExitCode::FAILURE;
        }
    }
    if floebench::run::interrupt::requested() {
        eprintln!(
            "interrupted: the table holds the {} whose runs all finished",
            plural(done.len(), "case")
        );
        ExitCode::from(INTERRUPTED)
    } else if check::claimed_failures(&rows) > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// The options of `floebench sweep`.
struct SweepArgs {
    out: Option<PathBuf>,
    jobs: usize,
    slurm: Option<(PathBuf, floebench::sweep::slurm::SlurmOptions)>,
    task: Option<usize>,
    collect: bool,
    quiet: bool,
}

fn sweep(plan_file: &Path, args: SweepArgs) -> ExitCode {
    use floebench::sweep::{self, execute, plan, points, slurm};
    let plan = match plan::load_plan(plan_file) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let points = points::points(&plan);
    let out = args.out.unwrap_or_else(|| sweep::default_out(&plan));
    if out.exists() && !out.is_dir() {
        eprintln!("error: -o: {} exists and is not a folder", out.display());
        return ExitCode::FAILURE;
    }
    let fail = |e: &dyn std::fmt::Display| {
        eprintln!("error: {e}");
        ExitCode::FAILURE
    };
    if let Some((dir, opts)) = &args.slurm {
        let exe = match std::env::current_exe() {
            Ok(e) => e,
            Err(e) => return fail(&format!("cannot find the floebench binary: {e}")),
        };
        return match slurm::write_slurm(&plan, &points, &out, dir, &exe, opts) {
            Ok(w) => {
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
                ExitCode::SUCCESS
            }
            Err(e) => fail(&e),
        };
    }
    let interrupted = |done: &execute::Executed| {
        if done.interrupted {
            eprintln!("interrupted: the points not finished have no result file; run the same command again to go on");
        }
        done.interrupted
    };
    if let Some(k) = args.task {
        let done = slurm::manifest_task(&plan, &points, &out, k)
            .and_then(|t| execute::run_task(&plan, &points, &out, &t));
        return match done {
            Ok(d) => {
                println!(
                    "task {k}: {} run, {} skipped (already finished), {}",
                    plural(d.run, "point"),
                    d.skipped,
                    plural(d.references, "reference run")
                );
                if interrupted(&d) {
                    ExitCode::from(INTERRUPTED)
                } else {
                    ExitCode::SUCCESS
                }
            }
            Err(e) => fail(&e),
        };
    }
    let mut stopped = false;
    if !args.collect {
        eprintln!(
            "{}: {} on {}, reference {}, {} at a time",
            plan.file.display(),
            plural(points.len(), "point"),
            plural(plan.cases.len(), "case"),
            plan.reference.label(),
            args.jobs
        );
        let opts = execute::ExecOptions {
            jobs: args.jobs,
            progress: !args.quiet,
        };
        match execute::run_local(&plan, &points, &out, opts) {
            Ok(d) => {
                println!(
                    "sweep: {} run, {} skipped (already finished), {}",
                    plural(d.run, "point"),
                    d.skipped,
                    plural(d.references, "reference run")
                );
                stopped = interrupted(&d);
            }
            Err(e) => return fail(&e),
        }
    }
    let collected = sweep::collect(&plan, points, &out);
    let missing = collected.missing().len();
    let command = command_line();
    match floebench::report::sweep::write_report(&collected, &out, &command) {
        Ok(files) => {
            for f in files {
                println!("wrote {}", f.display());
            }
        }
        Err(e) => return fail(&e),
    }
    if missing > 0 {
        eprintln!(
            "{} of {} not finished (not in the report)",
            plural(missing, "point"),
            collected.points.len()
        );
    }
    if stopped {
        ExitCode::from(INTERRUPTED)
    } else {
        ExitCode::SUCCESS
    }
}

fn resolve_lcp(file: &Path) -> ExitCode {
    use floebench::lcp::{residual, solve, LcpDump, SolveOptions};
    let dump = match LcpDump::read(file) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let lcp = match dump.to_lcp() {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: {}: {e}", file.display());
            return ExitCode::FAILURE;
        }
    };
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
    if sol.status.is_solved() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

fn time_lcps(
    path: &Path,
    opts: floebench::lcp::timing::TimingOptions,
    csv: Option<&Path>,
) -> ExitCode {
    use floebench::lcp::timing;
    let files = if path.is_dir() {
        match timing::dump_files(path) {
            Ok(f) => f,
            Err(e) => {
                eprintln!("error: cannot read {}: {e}", path.display());
                return ExitCode::FAILURE;
            }
        }
    } else {
        vec![path.to_path_buf()]
    };
    if files.is_empty() {
        eprintln!("error: no *.json dump in {}", path.display());
        return ExitCode::FAILURE;
    }
    let mut rows = Vec::with_capacity(files.len());
    for f in &files {
        match timing::time_file(f, &opts) {
            Ok(r) => rows.push(r),
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    if let Some(file) = csv {
        if let Err(e) = output::write_atomic(file, timing::csv(&rows).as_bytes()) {
            eprintln!("error: cannot write {}: {e}", file.display());
            return ExitCode::FAILURE;
        }
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
    ExitCode::SUCCESS
}

/// A `--bar` of `percussion-1d`: `LENGTH,NODES,VELOCITY`.
fn parse_bar(s: &str) -> Result<floebench::fracture::chain::BarSpec, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [l, n, v] = parts.as_slice() else {
        return Err(format!("expected LENGTH,NODES,VELOCITY, got {s:?}"));
    };
    let num = |x: &str, what: &str| x.parse::<f64>().map_err(|e| format!("{what} {x:?}: {e}"));
    Ok(floebench::fracture::chain::BarSpec {
        length: num(l, "length")?,
        nodes: n
            .parse::<usize>()
            .map_err(|e| format!("nodes {n:?}: {e}"))?,
        velocity: num(v, "velocity")?,
    })
}

/// `W,H` of `percussion-2d --size`.
fn parse_pair(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("expected W,H, got {s:?}"))?;
    let num = |x: &str| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}"));
    Ok((num(a)?, num(b)?))
}

/// The impact of `percussion-2d`.
struct Strike {
    size: (f64, f64),
    speed: f64,
    mass: Option<f64>,
    at: f64,
}

/// `floebench percussion-2d`: build the lattice, run the percussion, print
/// the pieces, draw the crack.
fn percussion_2d(
    spec: floebench::fracture::lattice::LatticeSpec,
    options: floebench::fracture::chain::ChainOptions,
    strike: Strike,
    plot: Option<&Path>,
) -> ExitCode {
    use floebench::fracture::lattice::percussion::{Impact, Percussion, RigidMotion};
    use floebench::geometry::Vec2;
    let (w, h) = strike.size;
    let outline = [
        Vec2::new(0.0, 0.0),
        Vec2::new(w, 0.0),
        Vec2::new(w, h),
        Vec2::new(0.0, h),
    ];
    let fail = |e: String| {
        eprintln!("error: {e}");
        ExitCode::FAILURE
    };
    if !(strike.at > 0.0 && strike.at < h) {
        return fail(format!(
            "--at {} is not on the left face (0, {h})",
            strike.at
        ));
    }
    let lattice = match floebench::fracture::lattice::Lattice::build(&outline, spec) {
        Ok(l) => l,
        Err(e) => return fail(e),
    };
    let (motion, mass) = match strike.mass {
        Some(m) => (RigidMotion::default(), m),
        None => (
            RigidMotion {
                velocity: Vec2::new(-strike.speed, 0.0),
                angular_velocity: 0.0,
            },
            f64::INFINITY,
        ),
    };
    let impact = Impact {
        point: Vec2::new(0.0, strike.at),
        normal: Vec2::new(1.0, 0.0),
        mass,
        speed: strike.speed,
    };
    let mut p = match Percussion::new(&lattice, motion, impact, options) {
        Ok(p) => p,
        Err(e) => return fail(e),
    };
    let o = p.run();
    println!("piece,nodes,mass,x,y,vx,vy,omega,hull_area");
    for (i, f) in o.fragments.iter().enumerate() {
        println!(
            "{i},{},{},{},{},{},{},{},{}",
            f.nodes.len(),
            f.mass,
            f.centre.x,
            f.centre.y,
            f.velocity.x,
            f.velocity.y,
            f.angular_velocity,
            f.area
        );
    }
    eprintln!(
        "{}: t = {} s ({} steps of {} s, {} nodes), contact ended at {} s; {} broken, {} pieces",
        o.reason.name(),
        fmt_num(o.t),
        o.steps,
        fmt_num(o.dt),
        lattice.nodes.len(),
        fmt_num(o.contact_end),
        plural(o.broken.len(), "bond"),
        o.fragments.len()
    );
    eprintln!(
        "energy: initial {} J, impact {} J, striker's work {} J, fracture {} J (broken bonds {} J); hull area error {}; striker {} -> {} m/s",
        fmt_num(o.initial_energy),
        fmt_num(o.impact_energy),
        fmt_num(o.work),
        fmt_num(o.fracture_energy),
        fmt_num(o.energies.fracture),
        fmt_num(o.hull_area_error),
        fmt_num(o.striker_velocity[0]),
        fmt_num(o.striker_velocity[1])
    );
    if let Some(stem) = plot {
        // The springs at rest (the crack pattern on the floe as it was).
        let broken: Vec<usize> = o.broken.iter().map(|b| b.spring).collect();
        let rec = floebench::model::fracture::PercussionRecord {
            bound: o.impact_energy,
            weakest: p.weakest_bond_energy(),
            loss: o.fracture_energy,
            ..floebench::fracture::crack::of_lattice(&lattice, &broken, &[impact])
        };
        let title = format!(
            "percussion at {} m/s: {} broken, {} pieces",
            fmt_num(strike.speed),
            plural(o.broken.len(), "bond"),
            o.fragments.len()
        );
        match floebench::report::crack::draw(&rec, &title, stem) {
            Ok([png, svg]) => eprintln!("wrote {} and {}", png.display(), svg.display()),
            Err(e) => return fail(e.to_string()),
        }
    }
    ExitCode::SUCCESS
}

/// `floebench percussion-1d`: run the chain, print the pieces.
fn percussion_1d(
    material: &floebench::fracture::chain::Material,
    bars: &[floebench::fracture::chain::BarSpec],
    options: floebench::fracture::chain::ChainOptions,
    nodes: Option<&Path>,
) -> ExitCode {
    let mut chain = match floebench::fracture::chain::Chain::new(material, bars, options) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let o = chain.run();
    println!("fragment,first,last,mass,length,centre,velocity");
    for (i, f) in o.fragments.iter().enumerate() {
        println!(
            "{i},{},{},{},{},{},{}",
            f.first, f.last, f.mass, f.length, f.centre, f.velocity
        );
    }
    eprintln!(
        "{}: t = {} s ({} steps of {} s), contact ended at {} s; {} broken, {} pieces",
        o.reason.name(),
        fmt_num(o.t),
        o.steps,
        fmt_num(o.dt),
        fmt_num(o.contact_end),
        plural(o.broken.len(), "bond"),
        o.fragments.len()
    );
    eprintln!(
        "energy: initial {} J, kinetic {} J, elastic {} J, fracture {} J, dissipated {} J",
        fmt_num(o.initial_energy),
        fmt_num(o.energies.kinetic),
        fmt_num(o.energies.elastic),
        fmt_num(o.energies.fracture),
        fmt_num(o.dissipated)
    );
    if o.bars.len() == 2 && bars[0].velocity != bars[1].velocity {
        eprintln!(
            "restitution of bars 0 and 1: {}",
            fmt_num(o.restitution(0, 1, bars[0].velocity, bars[1].velocity))
        );
    }
    if let Some(path) = nodes {
        let pieces = &o.fragments;
        let mut text = String::from("node,bar,fragment,x,v\n");
        for i in 0..chain.len() {
            let frag = pieces
                .iter()
                .position(|f| f.first <= i && i <= f.last)
                .unwrap_or(0);
            text.push_str(&format!(
                "{i},{},{frag},{},{}\n",
                chain.bar[i], chain.x[i], chain.v[i]
            ));
        }
        if let Err(e) = std::fs::write(path, text) {
            eprintln!("error: cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

/// `--covering`: `ones`, `sqrt-diagonal` or `diagonal:F` with F in (0, 1].
fn parse_covering(s: &str) -> Result<floebench::lcp::Covering, String> {
    use floebench::lcp::Covering;
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
