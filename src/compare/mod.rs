//! The comparison harness: every formulation on the same cases, side by side.
//!
//! [`compare`] runs the cases with the batch runner ([`crate::run::batch`]:
//! every case loaded and every formulation built before any run, runs in
//! parallel, results in order), then measures each case with [`assess`].
//!
//! The result, one [`CaseComparison`] per case, holds the runs, the pair
//! divergences ([`metrics::divergence`]) and every figure in long format
//! ([`metrics::MetricRow`]) and the physical checks of every run
//! ([`check::check_run`]); [`report`] writes it as data, plots and a page.

pub mod figures;
pub mod metrics;
pub mod page;
pub mod report;

use crate::analysis::check::{self, CheckOutcome};
use crate::model::{IntegratorKind, Scenario};
use crate::run::batch::{self, BatchError, BatchOptions};
use crate::run::RunResult;
use metrics::{MetricRow, PairDivergence};
use std::path::PathBuf;

/// Why a comparison could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// The cases could not be loaded or run.
    #[error(transparent)]
    Batch(#[from] BatchError),
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

/// Options of a comparison.
#[derive(Debug, Clone)]
pub struct CompareOptions {
    /// Formulations, in report order; the first is the reference of the
    /// verdicts. Empty (the default): on each case, the formulations that
    /// apply to it ([`batch::default_formulations`]: all, `free-drift` only
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
        let b = BatchOptions::default();
        CompareOptions {
            formulations: b.formulations,
            jobs: b.jobs,
            progress: b.progress,
            divergence_threshold: 0.1,
            integrator: b.integrator,
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

/// Runs every formulation of `opts` on every case (loaded by
/// [`batch::load_cases`]) and measures the differences.
pub fn compare(
    cases: Vec<(PathBuf, Scenario)>,
    opts: &CompareOptions,
) -> Result<Vec<CaseComparison>, CompareError> {
    let bopts = BatchOptions {
        formulations: opts.formulations.clone(),
        jobs: opts.jobs,
        progress: opts.progress,
        integrator: opts.integrator,
    };
    batch::run_cases(cases, &bopts)?
        .into_iter()
        .map(|c| assess(c.path, c.scenario, c.runs, opts.divergence_threshold))
        .collect()
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
    let checks = check::check_runs(&scenario, &runs);
    Ok(CaseComparison {
        path,
        scenario,
        runs,
        pairs,
        checks,
        metrics: rows,
    })
}
