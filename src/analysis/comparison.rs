//! The comparison of the formulations on one case: the runs, how each pair
//! differs ([`super::divergence`]), every figure in long format
//! ([`super::metrics`]), the physical checks of every run
//! ([`super::check`]), the spread of the CPU times over the repeats
//! ([`crate::record::spread`]), whether the case is chaotic ([`super::chaos`]) and,
//! when floes can break, the floe-size distributions ([`super::floe_sizes`]).

use super::chaos::{self, ChaosProbe};
use super::check::{self, CheckOutcome};
use super::divergence::{self, PairDivergence, TimeMismatch};
use super::floe_sizes::{floe_sizes, FloeSizes};
use super::metrics::{self, MetricRow};
use crate::model::Scenario;
use crate::record::spread::Spread;
use crate::run::batch::CaseRuns;
use crate::run::{RunResult, Timing};
use std::path::PathBuf;

/// The comparison of the formulations on one case.
#[derive(Debug, Clone)]
pub struct CaseComparison {
    /// The case file.
    pub path: PathBuf,
    /// The case.
    pub scenario: Scenario,
    /// One run per formulation, in the order of the options (of its
    /// repeats, the one of median CPU time).
    pub runs: Vec<RunResult>,
    /// The timing of every repeat of each run (same order as `runs`).
    pub timings: Vec<Vec<Timing>>,
    /// The spread of each run's CPU time over its repeats (same order).
    pub cpu: Vec<Spread>,
    /// Repeats whose physics was not bit-identical (findings), one line each.
    pub findings: Vec<String>,
    /// Whether the case is chaotic: the reference run against a run of the
    /// same formulation from a perturbed initial state ([`chaos`]); `None`
    /// when the probe was not run.
    pub chaos: Option<ChaosProbe>,
    /// Every pair of runs (i < j), in order.
    pub pairs: Vec<PairDivergence>,
    /// The physical checks of every run ([`check::check_run`]).
    pub checks: Vec<CheckOutcome>,
    /// Every figure of the runs and of the pairs.
    pub metrics: Vec<MetricRow>,
    /// The floe-size distributions, at the start and at the end of every
    /// run (empty unless floes can break: [`floe_sizes`]).
    pub floe_sizes: Vec<FloeSizes>,
}

/// Measures the runs of one case: the divergence of every pair, every
/// metric, every check, the spread of the CPU times, and the chaos probe
/// when `perturbed` (the reference formulation from [`chaos::perturbed`]
/// initial positions) is given.
pub fn assess(
    case: CaseRuns,
    perturbed: Option<RunResult>,
    threshold: f64,
) -> Result<CaseComparison, TimeMismatch> {
    let CaseRuns {
        path,
        scenario,
        runs,
        timings,
        findings,
    } = case;
    let mut pairs = Vec::new();
    for i in 0..runs.len() {
        for j in i + 1..runs.len() {
            pairs.push(divergence::divergence(
                &scenario, &runs[i], &runs[j], threshold,
            )?);
        }
    }
    let cpu: Vec<Spread> = timings
        .iter()
        .map(|t| Spread::of(&t.iter().map(|t| t.cpu_total).collect::<Vec<f64>>()))
        .collect();
    let chaos = match (perturbed, runs.first()) {
        (Some(p), Some(r)) => Some(chaos::probe(&scenario, r, &p)?),
        _ => None,
    };
    let mut rows: Vec<MetricRow> = Vec::new();
    for (r, c) in runs.iter().zip(&cpu) {
        rows.extend(metrics::run_metrics(r));
        rows.extend(metrics::cpu_spread_metrics(&r.summary, c));
    }
    for p in &pairs {
        rows.extend(metrics::pair_metrics(&scenario.name, p));
    }
    if let Some(c) = &chaos {
        rows.extend(metrics::chaos_metrics(&scenario.name, c));
    }
    let checks = check::check_runs(&scenario, &runs);
    let sizes = floe_sizes(&scenario, &runs);
    Ok(CaseComparison {
        path,
        scenario,
        runs,
        timings,
        cpu,
        findings,
        chaos,
        pairs,
        checks,
        metrics: rows,
        floe_sizes: sizes,
    })
}
