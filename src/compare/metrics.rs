//! Metrics of one run and of a pair of runs of the same case.
//!
//! Every figure is a [`MetricRow`] in long format (case, formulation, other
//! formulation, metric, value, unit), so `metrics.csv` can grow a column of
//! formulations or a new metric without changing its shape.
//!
//! Trajectory differences are taken between the states recorded at the same
//! output times: for each time, the position difference of each floe's centre
//! of mass (m) and the difference of its cumulative rotation angle (rad, not
//! wrapped: a floe that turned a full turn more has turned 2π more). The
//! position difference is summarised by its RMS over floes, divided by the
//! mean floe diameter `d̄` (the mean of the equal-area diameters
//! `2·sqrt(A/π)`), and by its maximum over floes, in metres.

use super::CompareError;
use crate::model::Scenario;
use crate::record::SettingValue;
use crate::run::{EndReason, RunResult, TrajectoryRow};
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

/// The difference of two runs at one output time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DivergenceSample {
    /// Time, s.
    pub t: f64,
    /// RMS over floes of the position difference, divided by the mean floe diameter (-).
    pub rms_position_rel: f64,
    /// Largest position difference of a floe, m.
    pub max_position_m: f64,
    /// RMS over floes of the angle difference, rad.
    pub rms_angle_rad: f64,
    /// Largest angle difference of a floe, rad.
    pub max_angle_rad: f64,
}

/// How two runs of the same case differ over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairDivergence {
    /// First formulation (the reference).
    pub a: String,
    /// Second formulation.
    pub b: String,
    /// The difference at each output time both runs reached.
    pub samples: Vec<DivergenceSample>,
    /// Largest RMS relative position difference over time (-).
    pub max_rms_position_rel: f64,
    /// Largest position difference of any floe at any time, m.
    pub max_position_m: f64,
    /// Largest angle difference of any floe at any time, rad.
    pub max_angle_rad: f64,
    /// RMS relative position difference at the last common time (-).
    pub final_rms_position_rel: f64,
    /// The threshold on the RMS relative position difference (-).
    pub threshold: f64,
    /// The first output time at which the RMS relative position difference
    /// exceeds the threshold, s; `None` if it never does.
    pub diverged_at: Option<f64>,
}

/// The mean equal-area floe diameter `mean(2·sqrt(A/π))`, m.
pub fn mean_diameter(scn: &Scenario) -> f64 {
    if scn.floes.is_empty() {
        return 0.0;
    }
    scn.floes
        .iter()
        .map(|f| 2.0 * (f.area / std::f64::consts::PI).sqrt())
        .sum::<f64>()
        / scn.floes.len() as f64
}

/// The trajectory cut into frames: one slice of `n` rows per output time.
pub fn frames(run: &RunResult, n: usize) -> impl Iterator<Item = &[TrajectoryRow]> {
    run.trajectory
        .chunks(n.max(1))
        .filter(move |c| c.len() == n)
}

/// The divergence between runs `a` and `b` of `scn`, over the output times
/// both reached. `threshold` is on the RMS position difference relative to
/// the mean floe diameter.
pub fn divergence(
    scn: &Scenario,
    a: &RunResult,
    b: &RunResult,
    threshold: f64,
) -> Result<PairDivergence, CompareError> {
    let n = scn.floes.len();
    let d = mean_diameter(scn);
    let mut samples = Vec::new();
    for (fa, fb) in frames(a, n).zip(frames(b, n)) {
        let t = fa[0].t;
        if (t - fb[0].t).abs() > 1e-9 * t.abs().max(1.0) {
            return Err(CompareError::Mismatch(format!(
                "{} and {} recorded different output times ({} s and {} s)",
                a.summary.formulation, b.summary.formulation, t, fb[0].t
            )));
        }
        let (mut sp, mut mp, mut sa, mut ma) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for (ra, rb) in fa.iter().zip(fb) {
            let dp = (ra.x - rb.x).hypot(ra.y - rb.y);
            let da = (ra.theta - rb.theta).abs();
            sp += dp * dp;
            mp = mp.max(dp);
            sa += da * da;
            ma = ma.max(da);
        }
        let nf = n.max(1) as f64;
        samples.push(DivergenceSample {
            t,
            rms_position_rel: if d > 0.0 { (sp / nf).sqrt() / d } else { 0.0 },
            max_position_m: mp,
            rms_angle_rad: (sa / nf).sqrt(),
            max_angle_rad: ma,
        });
    }
    let max_of = |f: fn(&DivergenceSample) -> f64| samples.iter().map(f).fold(0.0, f64::max);
    Ok(PairDivergence {
        a: a.summary.formulation.clone(),
        b: b.summary.formulation.clone(),
        max_rms_position_rel: max_of(|s| s.rms_position_rel),
        max_position_m: max_of(|s| s.max_position_m),
        max_angle_rad: max_of(|s| s.max_angle_rad),
        final_rms_position_rel: samples.last().map_or(0.0, |s| s.rms_position_rel),
        threshold,
        diverged_at: samples
            .iter()
            .find(|s| s.rms_position_rel > threshold)
            .map(|s| s.t),
        samples,
    })
}

/// The figures of one run: time reached, energy totals, CPU time in total,
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
    push("work_air", e.work_air, "J");
    push("work_water", e.work_water, "J");
    push("work_coriolis", e.work_coriolis, "J");
    push("dissipated", e.dissipated, "J");
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
