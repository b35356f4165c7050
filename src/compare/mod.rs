//! The comparison harness: every formulation on the same cases, side by side.
//!
//! [`compare`] loads every case first (a bad file stops everything before any
//! run), builds every formulation on every case (an unknown name or a case a
//! formulation cannot take also stops before any run), then runs the
//! (case, formulation) jobs on a pool of worker threads. Each run's CPU time
//! is its own thread's CPU time ([`crate::run::thread_cpu_seconds`]), so
//! parallel runs do not distort each other; wall time is kept beside it.
//!
//! The result, one [`CaseComparison`] per case, holds the runs, the pair
//! divergences ([`metrics::divergence`]) and every figure in long format
//! ([`metrics::MetricRow`]) and the physical checks of every run
//! ([`check::check_run`]); [`report`] writes it as data, plots and a page.
//! `floebench check` is the same runs without the report.

pub mod figures;
pub mod metrics;
pub mod page;
pub mod report;

use crate::analysis::check::{self, CheckOutcome};
use crate::formulation::{self, load_case, FormulationOptions};
use crate::model::{IntegratorKind, Scenario};
use crate::run::{RunOptions, RunResult, Runner};
use metrics::{MetricRow, PairDivergence};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Why a comparison could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// A case file is bad (the message names file and line).
    #[error("{0}")]
    Case(String),
    /// A folder or file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A formulation is unknown or cannot take a case.
    #[error("{0}")]
    Formulation(String),
    /// Two runs cannot be compared.
    #[error("{0}")]
    Mismatch(String),
    /// A plot could not be drawn.
    #[error("plot {path}: {message}")]
    Plot {
        /// The plot's file stem.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}

/// Every formulation that handles contacts (all but `free-drift`): the
/// benches' list.
pub fn default_formulations() -> Vec<String> {
    formulation::REGISTRY
        .iter()
        .filter(|e| e.resolves_contacts)
        .map(|e| e.name.to_string())
        .collect()
}

/// Options of a comparison.
#[derive(Debug, Clone)]
pub struct CompareOptions {
    /// Formulations, in report order; the first is the reference of the
    /// verdicts. Empty (the default): on each case, the formulations that
    /// apply to it ([`check::default_formulations`]: all, `free-drift` only
    /// on contact-free cases).
    pub formulations: Vec<String>,
    /// Runs at a time (worker threads); default: the available cores.
    pub jobs: usize,
    /// Progress bars on stderr.
    pub progress: bool,
    /// Divergence threshold on the RMS position difference, as a fraction of
    /// the mean floe diameter (-); default 0.1.
    pub divergence_threshold: f64,
    /// Override of the cases' smooth integrator.
    pub integrator: Option<IntegratorKind>,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            formulations: Vec::new(),
            jobs: std::thread::available_parallelism().map_or(1, |n| n.get()),
            progress: false,
            divergence_threshold: 0.1,
            integrator: None,
        }
    }
}

/// The comparison of the formulations on one case.
#[derive(Debug, Clone)]
pub struct CaseComparison {
    /// The case file.
    pub path: PathBuf,
    /// The case.
    pub scenario: Scenario,
    /// One run per formulation, in the order of the options.
    pub runs: Vec<RunResult>,
    /// Every pair of runs (i < j), in order.
    pub pairs: Vec<PairDivergence>,
    /// The physical checks of every run ([`check::check_run`]).
    pub checks: Vec<CheckOutcome>,
    /// Every figure of the runs and of the pairs.
    pub metrics: Vec<MetricRow>,
}

/// The case files named by `inputs`: files as given, folders expanded to
/// their `*.toml` files (not recursive), sorted by name.
pub fn case_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, CompareError> {
    let mut files = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let io = |source| CompareError::Io {
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
                return Err(CompareError::Case(format!(
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
pub fn load_cases(inputs: &[PathBuf]) -> Result<Vec<(PathBuf, Scenario)>, CompareError> {
    case_files(inputs)?
        .into_iter()
        .map(|p| match load_case(&p) {
            Ok(s) => Ok((p, s)),
            Err(e) => Err(CompareError::Case(e.to_string())),
        })
        .collect()
}

/// Runs every formulation of `opts` on every case and measures the differences.
pub fn compare(
    cases: Vec<(PathBuf, Scenario)>,
    opts: &CompareOptions,
) -> Result<Vec<CaseComparison>, CompareError> {
    for (i, name) in opts.formulations.iter().enumerate() {
        if opts.formulations[..i].contains(name) {
            return Err(CompareError::Formulation(format!(
                "formulation `{name}` is listed twice"
            )));
        }
    }
    let lists: Vec<Vec<String>> = cases
        .iter()
        .map(|(_, scn)| {
            if opts.formulations.is_empty() {
                check::default_formulations(scn)
                    .into_iter()
                    .map(str::to_string)
                    .collect()
            } else {
                opts.formulations.clone()
            }
        })
        .collect();
    let fopts = FormulationOptions {
        integrator: opts.integrator,
        dump_lcp: None,
    };
    // Every formulation must accept every case before anything runs.
    for ((path, scn), list) in cases.iter().zip(&lists) {
        for name in list {
            formulation::build(name, scn, &fopts).map_err(|e| {
                CompareError::Formulation(format!("{}: {name}: {e}", path.display()))
            })?;
        }
    }
    let jobs: Vec<(usize, usize)> = lists
        .iter()
        .enumerate()
        .flat_map(|(c, l)| (0..l.len()).map(move |f| (c, f)))
        .collect();
    let results: Mutex<Vec<Option<Result<RunResult, String>>>> = Mutex::new(vec![None; jobs.len()]);
    let next = AtomicUsize::new(0);
    let multi = opts.progress.then(indicatif::MultiProgress::new);
    let workers = opts.jobs.clamp(1, jobs.len().max(1));
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some(&(c, f)) = jobs.get(k) else { break };
                let scn = &cases[c].1;
                let runner = Runner::new(RunOptions {
                    progress: opts.progress,
                    multi: multi.clone(),
                });
                let out = formulation::build(&lists[c][f], scn, &fopts)
                    .map(|mut form| runner.run(scn, form.name(), form.formulation.as_mut()));
                if let Ok(mut r) = results.lock() {
                    r[k] = Some(out);
                }
            });
        }
    });
    let mut results = results
        .into_inner()
        .map_err(|_| CompareError::Mismatch("a run panicked".into()))?
        .into_iter();
    let mut out = Vec::with_capacity(cases.len());
    for ((path, scenario), list) in cases.into_iter().zip(&lists) {
        let mut runs = Vec::with_capacity(list.len());
        for name in list {
            match results.next().flatten() {
                Some(Ok(r)) => runs.push(r),
                Some(Err(e)) => {
                    return Err(CompareError::Formulation(format!(
                        "{}: {name}: {e}",
                        path.display()
                    )))
                }
                None => {
                    return Err(CompareError::Mismatch(format!(
                        "{}: {name}: the run did not finish (panicked)",
                        path.display()
                    )))
                }
            }
        }
        out.push(assess(path, scenario, runs, opts.divergence_threshold)?);
    }
    Ok(out)
}

/// Measures the runs of one case: pair divergences and every metric.
pub fn assess(
    path: PathBuf,
    scenario: Scenario,
    runs: Vec<RunResult>,
    threshold: f64,
) -> Result<CaseComparison, CompareError> {
    let mut pairs = Vec::new();
    for i in 0..runs.len() {
        for j in i + 1..runs.len() {
            pairs.push(metrics::divergence(
                &scenario, &runs[i], &runs[j], threshold,
            )?);
        }
    }
    let mut rows: Vec<MetricRow> = runs.iter().flat_map(metrics::run_metrics).collect();
    for p in &pairs {
        rows.extend(metrics::pair_metrics(&scenario.name, p));
    }
    let checks = runs
        .iter()
        .flat_map(|r| check::check_run(&scenario, r))
        .collect();
    Ok(CaseComparison {
        path,
        scenario,
        runs,
        pairs,
        checks,
        metrics: rows,
    })
}
