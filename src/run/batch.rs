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
//! its formulations, whatever order the runs finish in.
//!
//! An interrupt ([`super::interrupt`]) stops the batch: no new run starts,
//! the runs in progress end at their next output time, and only the cases
//! whose runs all finished before it are returned (the caller tells which
//! are missing: [`super::interrupt::requested`] is then true).
//!
//! Which formulations run on a case when none are named:
//! [`default_formulations`], those of the registry that apply to it.

use super::{interrupt, EndReason, RunOptions, RunResult, Runner};
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
}

impl Default for BatchOptions {
    fn default() -> Self {
        BatchOptions {
            formulations: Vec::new(),
            jobs: std::thread::available_parallelism().map_or(1, |n| n.get()),
            progress: false,
            integrator: None,
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
    /// One run per formulation, in the order of the options.
    pub runs: Vec<RunResult>,
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

/// Runs every formulation of `opts` on every case (see the module doc).
pub fn run_cases(
    cases: Vec<(PathBuf, Scenario)>,
    opts: &BatchOptions,
) -> Result<Vec<CaseRuns>, BatchError> {
    for (i, name) in opts.formulations.iter().enumerate() {
        if opts.formulations[..i].contains(name) {
            return Err(BatchError::Formulation(format!(
                "formulation `{name}` is listed twice"
            )));
        }
    }
    let lists: Vec<Vec<String>> = cases
        .iter()
        .map(|(_, scn)| {
            if opts.formulations.is_empty() {
                default_formulations(scn)
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
            formulation::build(name, scn, &fopts)
                .map_err(|e| BatchError::Formulation(format!("{}: {name}: {e}", path.display())))?;
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
                if interrupt::requested() {
                    break;
                }
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
        .map_err(|_| BatchError::Panicked("a run panicked".into()))?
        .into_iter();
    let interrupted = interrupt::requested();
    let mut out = Vec::with_capacity(cases.len());
    for ((path, scenario), list) in cases.into_iter().zip(&lists) {
        let mut runs = Vec::with_capacity(list.len());
        for name in list {
            match results.next().flatten() {
                Some(Ok(r)) => runs.push(r),
                // Not started, or stopped, because of an interrupt: the case
                // is left out (see the module doc).
                None if interrupted => {}
                Some(Err(e)) => {
                    return Err(BatchError::Formulation(format!(
                        "{}: {name}: {e}",
                        path.display()
                    )))
                }
                None => {
                    return Err(BatchError::Panicked(format!(
                        "{}: {name}: the run did not finish (panicked)",
                        path.display()
                    )))
                }
            }
        }
        let finished = runs.len() == list.len()
            && runs
                .iter()
                .all(|r| !matches!(r.summary.end, EndReason::Interrupted { .. }));
        if finished {
            out.push(CaseRuns {
                path,
                scenario,
                runs,
            });
        }
    }
    Ok(out)
}
