//! The comparison harness: every formulation on the same cases, side by side.
//!
//! [`compare`] runs the cases with the batch runner ([`crate::run::batch`]:
//! every case loaded and every formulation built before any run, runs in
//! parallel, results in order), then measures each case
//! ([`crate::analysis::comparison::assess`]).
//!
//! The result, one [`CaseComparison`] per case, holds the runs, the pair
//! divergences, every figure in long format and the physical checks of
//! every run; [`crate::report::compare`] writes it as data, plots and a page.

use crate::analysis::comparison::{assess, CaseComparison};
use crate::analysis::divergence::TimeMismatch;
use crate::model::{IntegratorKind, Scenario};
use crate::run::batch::{self, BatchError, BatchOptions};
use std::path::PathBuf;

/// Why a comparison could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// The cases could not be loaded or run.
    #[error(transparent)]
    Batch(#[from] BatchError),
    /// Two runs of a case cannot be compared.
    #[error(transparent)]
    Mismatch(#[from] TimeMismatch),
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
        .collect::<Result<_, _>>()
        .map_err(CompareError::from)
}
