//! The figures of runs and of pairs of runs of the same case, in long format.
//!
//! Every figure is a [`MetricRow`] (case, formulation, other formulation,
//! metric, value, unit), so `metrics.csv` can grow a column of formulations
//! or a new metric without changing its shape: [`run_metrics`] for one run,
//! [`pair_metrics`] for the divergence of two ([`super::divergence`]).

use super::chaos::ChaosProbe;
use super::divergence::PairDivergence;
use crate::record::spread::Spread;
use crate::record::SettingValue;
use crate::run::{EndReason, RunResult, RunSummary};
use crate::state::Shown;
use serde::Serialize;

/// One figure, in long format.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetricRow {
    /// Case name.
    pub case: String,
    /// The formulation the figure is about.
    pub formulation: String,
    /// For a pair metric, the other formulation; empty otherwise.
    pub other: String,
    /// Metric name (snake case, stable).
    pub metric: String,
    /// Value, in `unit`.
    pub value: f64,
    /// Unit (`s`, `J`, `m`, `rad`, `count`, `-` for dimensionless, …).
    pub unit: String,
}

impl MetricRow {
    /// A row (`other` empty for a single run's figure).
    pub fn new(
        case: &str,
        formulation: &str,
        other: &str,
        metric: &str,
        value: f64,
        unit: &str,
    ) -> MetricRow {
        MetricRow {
            case: case.into(),
            formulation: formulation.into(),
            other: other.into(),
            metric: metric.into(),
            value,
            unit: unit.into(),
        }
    }
}

/// The figures of one run: time reached, energy totals (every field of the
/// ledger, [`crate::state::Ledger::FIELDS`]), CPU time in total,
/// per simulated second and per stage, every counter of the formulation
/// with its unit, and its numeric settings.
pub fn run_metrics(run: &RunResult) -> Vec<MetricRow> {
    let s = &run.summary;
    let e = &s.energy;
    let t = &s.timing;
    let mut rows = Vec::new();
    let mut push = |metric: &str, value: f64, unit: &str| {
        rows.push(MetricRow::new(
            &s.case,
            &s.formulation,
            "",
            metric,
            value,
            unit,
        ))
    };
    push("t_reached", s.t_reached, "s");
    push(
        "completed",
        f64::from(u8::from(s.end == EndReason::Completed)),
        "-",
    );
    push("kinetic_initial", e.initial_kinetic, "J");
    push("kinetic_final", e.final_kinetic, "J");
    // The ledger's fields, but those of fracture or crushing cases only
    // (below).
    for (f, v) in e.ledger.values().filter(|(f, _)| f.shown == Shown::Always) {
        push(f.metric, v, f.unit);
    }
    push("residual_final", e.residual, "J");
    push("residual_max_abs", e.max_abs_residual, "J");
    push(
        "residual_rel",
        if e.exchanged > 0.0 {
            e.max_abs_residual / e.exchanged
        } else {
            0.0
        },
        "-",
    );
    if s.fracture_model.is_some() {
        // Fracture cases only (docs/physics.md §9): how many, into how
        // many floes, the energy spent, and the smallest floe at the end.
        push("fractures", s.fractures as f64, "count");
        push("floes_final", s.floes_at_end as f64, "count");
        for (f, v) in e
            .ledger
            .values()
            .filter(|(f, _)| f.shown == Shown::Fracture)
        {
            push(f.metric, v, f.unit);
        }
        push("fracture_kinetic_gain", e.fracture_kinetic_gain, "J");
        let alive = run.floes.iter().filter(|f| f.t_end.is_none());
        let smallest = alive.map(|f| f.area).fold(f64::INFINITY, f64::min);
        if smallest.is_finite() {
            push("floe_area_min_final", smallest, "m^2");
        }
    }
    if s.crushing.is_some() {
        // Crushing cases only (docs/physics.md §10); its volumes and cuts
        // are counters, below.
        for (f, v) in e
            .ledger
            .values()
            .filter(|(f, _)| f.shown == Shown::Crushing)
        {
            push(f.metric, v, f.unit);
        }
    }
    push("cpu_total", t.cpu_total, "s");
    push(
        "cpu_per_simulated_second",
        if s.t_reached > 0.0 {
            t.cpu_total / s.t_reached
        } else {
            0.0
        },
        "s/s",
    );
    push("cpu_detection", t.stages.detection, "s");
    push("cpu_solve", t.stages.solve, "s");
    push("cpu_integration", t.stages.integration, "s");
    if t.stages.lattice > 0.0 {
        push("cpu_lattice", t.stages.lattice, "s");
    }
    if s.crushing.is_some() {
        push("cpu_crushing", t.stages.crushing, "s");
    }
    if let Some(c) = &t.lattice_cost {
        push("cpu_lattice_per_impact", c.per_impact, "s");
        push("cpu_lattice_per_node_step", c.per_node_step, "s");
    }
    push("cpu_other", t.cpu_other, "s");
    push("wall", t.wall, "s");
    push("cpu_timer_overhead", t.timer_overhead, "s");
    push("cpu_clock_reads", t.clock_reads as f64, "count");
    for (c, v) in s.counters.iter() {
        push(c.name, v, c.unit.symbol());
    }
    if let Some(p) = &s.lcp_profile {
        for b in &p.buckets {
            let label = match b.unknowns_max {
                Some(hi) => format!("n{}_{hi}", b.unknowns_min),
                None => format!("n{}_up", b.unknowns_min),
            };
            push(&format!("lcp_{label}_solves"), b.solves as f64, "count");
            push(&format!("lcp_{label}_pivots"), b.pivots as f64, "count");
            push(&format!("lcp_{label}_unknowns"), b.unknowns as f64, "count");
            push(
                &format!("lcp_{label}_min_pivots"),
                b.min_pivots as f64,
                "count",
            );
            push(
                &format!("lcp_{label}_bounded_pivots"),
                b.bounded_pivots as f64,
                "count",
            );
            push(&format!("lcp_{label}_fallback"), b.fallback as f64, "count");
            push(&format!("lcp_{label}_failed"), b.failed as f64, "count");
            push(&format!("cpu_lcp_{label}"), b.seconds, "s");
        }
    }
    for st in &s.settings.0 {
        if let SettingValue::Number(v) = st.value {
            push(st.name, v, st.unit.symbol());
        }
    }
    rows
}

/// The summary figures of a pair of runs (formulation = `a`, other = `b`).
pub fn pair_metrics(case: &str, p: &PairDivergence) -> Vec<MetricRow> {
    let mut rows = Vec::new();
    let mut push = |metric: &str, value: f64, unit: &str| {
        rows.push(MetricRow::new(case, &p.a, &p.b, metric, value, unit))
    };
    push("max_rms_position_rel", p.max_rms_position_rel, "-");
    push("final_rms_position_rel", p.final_rms_position_rel, "-");
    push("max_position_difference", p.max_position_m, "m");
    push("max_angle_difference", p.max_angle_rad, "rad");
    push("divergence_threshold", p.threshold, "-");
    push(
        "diverged",
        f64::from(u8::from(p.diverged_at.is_some())),
        "-",
    );
    if let Some(t) = p.diverged_at {
        push("divergence_time", t, "s");
    }
    rows
}

/// The spread of a run's CPU time over its repeats (`cpu_repeats`,
/// `cpu_median`, `cpu_min`, `cpu_max`, and `cpu_q1`, `cpu_q3` from
/// [`crate::record::spread::IQR_FROM`] repeats on), s.
pub fn cpu_spread_metrics(s: &RunSummary, c: &Spread) -> Vec<MetricRow> {
    let row = |metric: &str, value: f64, unit: &str| {
        MetricRow::new(&s.case, &s.formulation, "", metric, value, unit)
    };
    let mut rows = vec![
        row("cpu_repeats", c.count() as f64, "count"),
        row("cpu_median", c.median, "s"),
        row("cpu_min", c.min, "s"),
        row("cpu_max", c.max, "s"),
    ];
    if let Some((q1, q3)) = c.iqr {
        rows.push(row("cpu_q1", q1, "s"));
        rows.push(row("cpu_q3", q3, "s"));
    }
    rows
}

/// The chaos probe of a case (formulation = the probed one, other =
/// `perturbed`): `perturbation_growth` (`max D / D(0)`),
/// `perturbation_rate` (1/s, when fitted) and `chaotic`.
pub fn chaos_metrics(case: &str, c: &ChaosProbe) -> Vec<MetricRow> {
    let row = |metric: &str, value: f64, unit: &str| {
        MetricRow::new(case, &c.formulation, "perturbed", metric, value, unit)
    };
    let mut rows = vec![row("perturbation_growth", c.growth, "-")];
    if let Some(rate) = c.rate {
        rows.push(row("perturbation_rate", rate, "1/s"));
    }
    rows.push(row("chaotic", f64::from(u8::from(c.chaotic)), "-"));
    rows
}
