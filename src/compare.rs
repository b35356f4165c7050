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

use crate::analysis::chaos;
use crate::analysis::comparison::{assess, CaseComparison};
use crate::analysis::divergence::TimeMismatch;
use crate::model::{IntegratorKind, Scenario};
use crate::run::batch::{self, BatchError, BatchOptions, CaseJob};
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
    /// divergences and of the chaos probe (the verdicts against the exact
    /// answers rank every formulation, the first included). Empty (the default): on each case, the formulations that
    /// apply to it ([`batch::default_formulations`]: all, `free-drift` only
    /// on contact-free cases).
    pub formulations: Vec<String>,
    /// Runs at a time (worker threads); default: the available cores.
    pub jobs: usize,
    /// Progress bars on stderr.
    pub progress: bool,
    /// Divergence threshold on the RMS position difference, as a fraction of
    /// the median floe diameter (-); default 0.1.
    pub divergence_threshold: f64,
    /// Override of the cases' smooth integrator.
    pub integrator: Option<IntegratorKind>,
    /// Runs of each (case, formulation), at least 1 (default 1): CPU times
    /// are reported as median and spread, and the physics of the repeats
    /// must be bit-identical.
    pub repeat: usize,
    /// Run the reference formulation once more on each case from a
    /// perturbed initial state, to tell whether the case is chaotic
    /// ([`crate::analysis::chaos`]); default true.
    pub chaos_probe: bool,
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
            repeat: b.repeat,
            chaos_probe: true,
        }
    }
}

/// Runs every formulation of `opts` on every case (loaded by
/// [`batch::load_cases`]), `opts.repeat` times each, and the chaos probe's
/// perturbed run of each case's reference in the same pool; then measures
/// the differences.
pub fn compare(
    cases: Vec<(PathBuf, Scenario)>,
    opts: &CompareOptions,
) -> Result<Vec<CaseComparison>, CompareError> {
    let bopts = BatchOptions {
        formulations: opts.formulations.clone(),
        jobs: opts.jobs,
        progress: opts.progress,
        integrator: opts.integrator,
        repeat: opts.repeat.max(1),
    };
    // Each case's perturbed run of its reference comes right after the
    // case's runs, so an interrupt leaves whole cases behind it.
    let mut jobs = Vec::new();
    let mut probed = Vec::new();
    for j in batch::case_jobs(cases, &bopts) {
        let probe = (opts.chaos_probe && !j.formulations.is_empty()).then(|| CaseJob {
            path: j.path.clone(),
            scenario: chaos::perturbed(&j.scenario),
            formulations: vec![j.formulations[0].clone()],
            repeat: 1,
        });
        probed.push(probe.is_some());
        jobs.push(j);
        jobs.extend(probe);
    }
    let mut done = batch::run_jobs_aligned(jobs, &bopts)?.into_iter();
    let mut out = Vec::with_capacity(probed.len());
    for p in probed {
        let case = done.next().flatten();
        let perturbed = if p {
            match done.next().flatten() {
                Some(c) => c.runs.into_iter().next(),
                None => None,
            }
        } else {
            None
        };
        // Interrupted before its runs (or its probe) finished: not reported.
        let probe_done = !p || perturbed.is_some() || !crate::run::interrupt::requested();
        let (Some(case), true) = (case, probe_done) else {
            continue;
        };
        out.push(assess(case, perturbed, opts.divergence_threshold)?);
    }
    Ok(out)
}
