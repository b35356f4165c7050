//! The comparison of the formulations on one case: the runs, how each pair
//! differs ([`super::divergence`]), every figure in long format
//! ([`super::metrics`]) and the physical checks of every run
//! ([`super::check`]).

use super::check::{self, CheckOutcome};
use super::divergence::{self, PairDivergence, TimeMismatch};
use super::metrics::{self, MetricRow};
use crate::model::Scenario;
use crate::run::RunResult;
use std::path::PathBuf;

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

/// Measures the runs of one case: the divergence of every pair, every
/// metric and every check.
pub fn assess(
    path: PathBuf,
    scenario: Scenario,
    runs: Vec<RunResult>,
    threshold: f64,
) -> Result<CaseComparison, TimeMismatch> {
    let mut pairs = Vec::new();
    for i in 0..runs.len() {
        for j in i + 1..runs.len() {
            pairs.push(divergence::divergence(
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
