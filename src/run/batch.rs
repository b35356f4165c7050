//! The batch runner: several formulations on several cases, on a pool of
//! worker threads. `floebench compare` and `floebench check` both run here.
//!
//! [`load_cases`] loads every case first (a bad file stops everything before
//! any run). [`run_cases`] then builds every formulation on every case (an
//! unknown name, a name listed twice or a case a formulation cannot take
//! also stops before any run), and only then runs the (case, formulation)
//! pairs on `jobs` threads, each with its progress bar. Each run's CPU time
//! is its own thread's CPU time ([`crate::record::thread_cpu_seconds`]), so
//! parallel runs do not distort each other; wall time is kept beside it.
//! The results come back in the order of the cases and, within a case, of
//! its formulations, whatever order the runs finish in. With a repeat
//! count `N` every pair runs `N` times (each repeat a run of its own on the
//! pool), and with `N ≥ 2` a cheap pair is topped up to about
//! [`TOP_UP_CPU`] of CPU time in all (at most [`MAX_REPEATS`] runs), so
//! that its median is measured on enough samples; [`super::repeat::merge`]
//! keeps the run of median CPU time, the timing of every repeat, and a
//! finding for any repeat whose physics is not bit-identical.
//!
//! An interrupt ([`super::interrupt`]) stops the batch: no new run starts,
//! the runs in progress end at their next output time, and only the cases
//! whose runs all finished before it are returned (the caller tells which
//! are missing: [`super::interrupt::requested`] is then true).
//!
//! Which formulations run on a case when none are named:
//! [`default_formulations`], those of the registry that apply to it.

use super::{interrupt, repeat, EndReason, RunOptions, RunResult, Runner, Timing};
use crate::formulation::{self, load_case, FormulationOptions};
use crate::model::{IntegratorKind, Scenario};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Why a batch could not be run.
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// A case file is bad (the message names file and line), or a folder
    /// holds no case file.
    #[error("{0}")]
    Case(String),
    /// A folder could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The folder.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A formulation is unknown, listed twice or cannot take a case.
    #[error("{0}")]
    Formulation(String),
    /// A run panicked instead of returning its result.
    #[error("{0}")]
    Panicked(String),
}

/// Every formulation that handles contacts (all but `free-drift`): the
/// benches' list.
pub fn contact_formulations() -> Vec<String> {
    formulation::REGISTRY
        .iter()
        .filter(|e| e.resolves_contacts)
        .map(|e| e.name.to_string())
        .collect()
}

/// The formulations run on `scn` when none are named: those of the registry
/// that apply to it ([`formulation::Entry::applies`]: all, `free-drift` only
/// on contact-free cases).
pub fn default_formulations(scn: &Scenario) -> Vec<&'static str> {
    formulation::REGISTRY
        .iter()
        .filter(|e| e.applies(scn))
        .map(|e| e.name)
        .collect()
}

/// Options of a batch.
#[derive(Debug, Clone)]
pub struct BatchOptions {
    /// Formulations, in this order on every case. Empty (the default): on
    /// each case, its [`default_formulations`].
    pub formulations: Vec<String>,
    /// Runs at a time (worker threads); default: the available cores.
    pub jobs: usize,
    /// Progress bars on stderr.
    pub progress: bool,
    /// Override of the cases' smooth integrator.
    pub integrator: Option<IntegratorKind>,
    /// Runs of each (case, formulation), at least 1 (default 1).
    pub repeat: usize,
}

impl Default for BatchOptions {
    fn default() -> Self {
        BatchOptions {
            formulations: Vec::new(),
            jobs: std::thread::available_parallelism().map_or(1, |n| n.get()),
            progress: false,
            integrator: None,
            repeat: 1,
        }
    }
}

/// The runs of one case.
#[derive(Debug, Clone)]
pub struct CaseRuns {
    /// The case file.
    pub path: PathBuf,
    /// The case.
    pub scenario: Scenario,
    /// One run per formulation, in the order of the options: of its
    /// repeats, the one of median CPU time ([`repeat::merge`]).
    pub runs: Vec<RunResult>,
    /// The timing of every repeat of each run (same order as `runs`).
    pub timings: Vec<Vec<Timing>>,
    /// Repeats whose physics was not bit-identical, one line each (a
    /// finding: every formulation should be deterministic).
    pub findings: Vec<String>,
}

/// The case files named by `inputs`: files as given, folders expanded to
/// their `*.toml` files (not recursive), sorted by name.
pub fn case_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, BatchError> {
    let mut files = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let io = |source| BatchError::Io {
                path: input.clone(),
                source,
            };
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .map_err(io)?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
                .collect();
            found.sort();
            if found.is_empty() {
                return Err(BatchError::Case(format!(
                    "{}: no case file (*.toml) in this folder",
                    input.display()
                )));
            }
            files.extend(found);
        } else {
            files.push(input.clone());
        }
    }
    Ok(files)
}

/// Loads every case named by `inputs` (see [`case_files`]); the first bad
/// file is the error.
pub fn load_cases(inputs: &[PathBuf]) -> Result<Vec<(PathBuf, Scenario)>, BatchError> {
    case_files(inputs)?
        .into_iter()
        .map(|p| match load_case(&p) {
            Ok(s) => Ok((p, s)),
            Err(e) => Err(BatchError::Case(e.to_string())),
        })
        .collect()
}

/// One case of a batch and what to run on it.
#[derive(Debug, Clone)]
pub struct CaseJob {
    /// The case file.
    pub path: PathBuf,
    /// The case.
    pub scenario: Scenario,
    /// The formulations to run, in this order.
    pub formulations: Vec<String>,
    /// Runs of each formulation (at least 1): the physics of the repeats
    /// must be bit-identical ([`super::repeat`]), their CPU times give the
    /// spread.
    pub repeat: usize,
}

/// The jobs of `cases` under `opts`: the formulations of `opts` (or each
/// case's [`default_formulations`]), `opts.repeat` runs each.
pub fn case_jobs(cases: Vec<(PathBuf, Scenario)>, opts: &BatchOptions) -> Vec<CaseJob> {
    cases
        .into_iter()
        .map(|(path, scenario)| {
            let formulations = if opts.formulations.is_empty() {
                default_formulations(&scenario)
                    .into_iter()
                    .map(str::to_string)
                    .collect()
            } else {
                opts.formulations.clone()
            };
            CaseJob {
                path,
                scenario,
                formulations,
                repeat: opts.repeat.max(1),
            }
        })
        .collect()
}

/// Runs every formulation of `opts` on every case (see the module doc).
pub fn run_cases(
    cases: Vec<(PathBuf, Scenario)>,
    opts: &BatchOptions,
) -> Result<Vec<CaseRuns>, BatchError> {
    run_jobs(case_jobs(cases, opts), opts)
}

/// Runs `jobs` on `opts.jobs` threads (`opts.formulations` and
/// `opts.repeat` are not read: each job says what it runs). Every
/// formulation is built on its case before any run; every repeat of every
/// pair is a run of its own on the pool. The jobs an interrupt left
/// unfinished are left out.
pub fn run_jobs(jobs: Vec<CaseJob>, opts: &BatchOptions) -> Result<Vec<CaseRuns>, BatchError> {
    Ok(run_jobs_aligned(jobs, opts)?
        .into_iter()
        .flatten()
        .collect())
}

/// [`run_jobs`], one entry per job in the order given: `None` for a job an
/// interrupt left unfinished.
pub fn run_jobs_aligned(
    jobs: Vec<CaseJob>,
    opts: &BatchOptions,
) -> Result<Vec<Option<CaseRuns>>, BatchError> {
    for job in &jobs {
        let names = &job.formulations;
        for (i, name) in names.iter().enumerate() {
            if names[..i].contains(name) {
                return Err(BatchError::Formulation(format!(
                    "formulation `{name}` is listed twice"
                )));
            }
        }
    }
    let fopts = FormulationOptions {
        integrator: opts.integrator,
        dump_lcp: None,
        warm_check: false,
    };
    // Every formulation must accept every case before anything runs.
    for job in &jobs {
        for name in &job.formulations {
            // A refusal of the case ([`formulation::Entry::check`]) names
            // its file and line itself.
            if let Some(check) = formulation::entry(name).ok().and_then(|e| e.check) {
                check(&job.scenario).map_err(|e| BatchError::Case(e.to_string()))?;
            }
            formulation::build(name, &job.scenario, &fopts).map_err(|e| {
                // A refusal located in the case file already names it.
                let path = job.path.display().to_string();
                BatchError::Formulation(if e.starts_with(&path) {
                    e
                } else {
                    format!("{path}: {name}: {e}")
                })
            })?;
        }
    }
    let mut runs: Vec<(usize, usize)> = jobs
        .iter()
        .enumerate()
        .flat_map(|(c, j)| (0..j.formulations.len() * j.repeat).map(move |k| (c, k / j.repeat)))
        .collect();
    let multi = opts.progress.then(indicatif::MultiProgress::new);
    let mut results = execute(&jobs, &runs, opts, &fopts, multi.as_ref())?;
    // Cheap pairs measured several times are topped up to TOP_UP_CPU.
    let extra = top_up(&jobs, &runs, &results);
    if !extra.is_empty() && !interrupt::requested() {
        results.extend(execute(&jobs, &extra, opts, &fopts, multi.as_ref())?);
        runs.extend(extra);
    }
    let mut by_pair: Vec<Vec<Vec<Outcome>>> = jobs
        .iter()
        .map(|j| j.formulations.iter().map(|_| Vec::new()).collect())
        .collect();
    for (&(c, f), r) in runs.iter().zip(results) {
        by_pair[c][f].push(r);
    }
    let interrupted = interrupt::requested();
    let mut out = Vec::with_capacity(jobs.len());
    for (job, pairs) in jobs.into_iter().zip(by_pair) {
        let mut case = CaseRuns {
            runs: Vec::with_capacity(job.formulations.len()),
            timings: Vec::with_capacity(job.formulations.len()),
            findings: Vec::new(),
            path: job.path,
            scenario: job.scenario,
        };
        let mut complete = true;
        for (name, pair) in job.formulations.iter().zip(pairs) {
            let wanted = pair.len();
            let mut repeats = Vec::with_capacity(wanted);
            for result in pair {
                match result {
                    Some(Ok(r)) => repeats.push(r),
                    // Not started, or stopped, because of an interrupt: the
                    // case is left out (see the module doc).
                    None if interrupted => {}
                    Some(Err(e)) => {
                        return Err(BatchError::Formulation(format!(
                            "{}: {name}: {e}",
                            case.path.display()
                        )))
                    }
                    None => {
                        return Err(BatchError::Panicked(format!(
                            "{}: {name}: the run did not finish (panicked)",
                            case.path.display()
                        )))
                    }
                }
            }
            let finished = repeats.len() == wanted
                && repeats
                    .iter()
                    .all(|r| !matches!(r.summary.end, EndReason::Interrupted { .. }));
            if !finished {
                complete = false;
                continue;
            }
            let label = format!("{}: {name}", case.scenario.name);
            let Some(merged) = repeat::merge(&label, repeats) else {
                continue;
            };
            case.runs.push(merged.result);
            case.timings.push(merged.timings);
            case.findings.extend(merged.findings);
        }
        out.push(complete.then_some(case));
    }
    Ok(out)
}

/// A pair measured several times (`repeat` ≥ 2) whose repeats take less
/// CPU time in total than this (s) is repeated until they take about this
/// much, at most [`MAX_REPEATS`] times: a run of 50 µs is then timed 200
/// times (201), as its median over a few repeats moves by 1.5× between identical
/// `compare` runs on a shared machine (measured on `cases/`, four runs of
/// `--repeat 3`), while runs of a second keep their `repeat`.
pub const TOP_UP_CPU: f64 = 0.25;

/// The most runs of one pair the top-up ([`TOP_UP_CPU`]) asks for (odd,
/// as every count it asks for).
pub const MAX_REPEATS: usize = 201;

/// The runs in all of a pair whose first `repeat` runs (≥ 2) have the
/// median CPU time `median` (s): enough for [`TOP_UP_CPU`] in all, odd (the
/// run kept, of median CPU time, is then one of them), at most
/// [`MAX_REPEATS`]; `repeat` itself when they already take that much.
pub fn top_up_count(median: f64, repeat: usize) -> usize {
    if median.is_nan() || median <= 0.0 || median * repeat as f64 >= TOP_UP_CPU {
        return repeat;
    }
    let want = (TOP_UP_CPU / median).ceil().min(MAX_REPEATS as f64) as usize;
    let odd = want | 1;
    odd.clamp(repeat, MAX_REPEATS.max(repeat))
}

/// The extra runs that bring every cheap pair measured several times to
/// [`TOP_UP_CPU`] (see there): none for a single repeat, for a pair with a
/// failed or interrupted run, or after an interrupt.
fn top_up(jobs: &[CaseJob], runs: &[(usize, usize)], results: &[Outcome]) -> Vec<(usize, usize)> {
    let mut extra = Vec::new();
    for (c, job) in jobs.iter().enumerate() {
        if job.repeat < 2 {
            continue;
        }
        let mut more = vec![0; job.formulations.len()];
        for (f, more) in more.iter_mut().enumerate() {
            let mut cpu = Vec::with_capacity(job.repeat);
            for (_, r) in runs.iter().zip(results).filter(|(&p, _)| p == (c, f)) {
                match r {
                    Some(Ok(r)) if r.summary.end == EndReason::Completed => {
                        cpu.push(r.summary.timing.cpu_total)
                    }
                    _ => {
                        cpu.clear();
                        break;
                    }
                }
            }
            if cpu.len() != job.repeat {
                continue;
            }
            let median = crate::record::spread::Spread::of(&cpu).median;
            *more = top_up_count(median, job.repeat) - job.repeat;
        }
        // Round robin over the case's formulations, so that a slow spell of
        // the machine falls on all of them, not on one: what the verdicts
        // compare is their ratio.
        while more.iter().any(|&m| m > 0) {
            for (f, m) in more.iter_mut().enumerate().filter(|(_, m)| **m > 0) {
                extra.push((c, f));
                *m -= 1;
            }
        }
    }
    extra
}

/// What became of one run: `None` if it did not start or did not finish.
type Outcome = Option<Result<RunResult, String>>;

/// Runs `runs` (case, formulation index) of `jobs` on `opts.jobs` threads;
/// one entry per run, in order: `None` for a run an interrupt left out (or
/// that panicked).
fn execute(
    jobs: &[CaseJob],
    runs: &[(usize, usize)],
    opts: &BatchOptions,
    fopts: &FormulationOptions,
    multi: Option<&indicatif::MultiProgress>,
) -> Result<Vec<Outcome>, BatchError> {
    let results: Mutex<Vec<Outcome>> = Mutex::new(vec![None; runs.len()]);
    let next = AtomicUsize::new(0);
    let workers = opts.jobs.clamp(1, runs.len().max(1));
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| loop {
                if interrupt::requested() {
                    break;
                }
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some(&(c, f)) = runs.get(k) else { break };
                let scn = &jobs[c].scenario;
                let runner = Runner::new(RunOptions {
                    progress: opts.progress,
                    multi: multi.cloned(),
                    interrupt: Default::default(),
                    ..Default::default()
                });
                let out = formulation::build(&jobs[c].formulations[f], scn, fopts)
                    .map(|mut form| runner.run(scn, form.name(), form.formulation.as_mut()));
                if let Ok(mut r) = results.lock() {
                    r[k] = Some(out);
                }
            });
        }
    });
    results
        .into_inner()
        .map_err(|_| BatchError::Panicked("a run panicked".into()))
}
