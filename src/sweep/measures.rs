//! The error measures of one point, from its run and the reference.
//!
//! | metric | unit | what |
//! | --- | --- | --- |
//! | `cpu` | s | the run's thread CPU time ([`crate::run::Timing::cpu_total`]) |
//! | `completed` | 1 | 1 when the run reached the case's duration, else 0 |
//! | `position` | 1 | the largest, over the output times both runs reached, RMS over floes of the position difference from the reference run, divided by the median floe diameter (`compare`'s `max_rms_position_rel`, [`crate::analysis::divergence`]) |
//! | `kinetic_final` | 1 (J) | `\|E_f − E_f,ref\| / \|E_f,ref\|` of the final kinetic energy |
//! | `dissipated` | 1 (J) | the same for the energy dissipated by contacts |
//! | `first_event` | 1 (s) | `\|t_e − t_1\| / t_1`: the time of the run's first contact event against the exact first impact `t_1` of a bouncing case (docs/physics.md §6.1); the event-driven scheme locates it early by about `δ/(10 v_1)` (its impact gap) |
//! | `check:<id>` | 1 (unit of the check) | `\|measured − expected\| / \|expected\|` of each check with an expected value ([`crate::analysis::check`]); the largest when a check applies several times (one per floe) |
//!
//! An error is relative when its exact value is not zero; when it is zero
//! the error is absolute, in the unit of the quantity (J, or the check's
//! unit), and [`Metric::relative`] says so (`free_drift_velocity` expects
//! 0: its error is the measured `|v − u| / |u|` itself). A non-finite error
//! (a check that measured nothing, such as a first impact that never came)
//! is left out. The position, energy and dissipation errors need a
//! reference run; with `reference = "exact"` only the checks are measured.

use crate::analysis::check::check_run;
use crate::analysis::divergence::{divergence_of_rows, TimeMismatch};
use crate::model::Scenario;
use crate::run::{EndReason, RunResult, TrajectoryRow};
use serde::{Deserialize, Serialize};

/// One measured figure of a point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Metric {
    /// Its name (see the module doc).
    pub name: String,
    /// The value, in `unit`.
    pub value: f64,
    /// `s`, `1`, or the unit of an absolute error.
    pub unit: String,
    /// Whether it is an error relative to the exact or reference value.
    pub relative: bool,
}

/// One check outcome of a point, as measured (bound checks included).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckValue {
    /// The check's id.
    pub check: String,
    /// What it measured (`None`: nothing finite).
    pub measured: Option<f64>,
    /// Its exact value, when it has one.
    pub expected: Option<f64>,
    /// The unit of both.
    pub unit: String,
    /// Whether the run passes the check.
    pub pass: bool,
}

/// What a point is measured against from the reference run of its case.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceData {
    /// The reference run's label (its formulation).
    pub label: String,
    /// Its trajectory.
    pub rows: Vec<TrajectoryRow>,
    /// Its final kinetic energy, J.
    pub kinetic_final: f64,
    /// Its energy dissipated by contacts, J.
    pub dissipated: f64,
}

/// The error of `measured` against `exact` (see the module doc), or `None`
/// when it is not finite.
pub fn error(name: &str, measured: f64, exact: f64, unit: &str) -> Option<Metric> {
    let (value, relative) = if exact != 0.0 {
        ((measured - exact).abs() / exact.abs(), true)
    } else {
        ((measured - exact).abs(), false)
    };
    value.is_finite().then(|| Metric {
        name: name.to_string(),
        value,
        unit: if relative {
            "1".into()
        } else {
            unit.to_string()
        },
        relative,
    })
}

/// Every measure of `run` on the point's scenario `scn` (see the module
/// doc), and its check outcomes.
pub fn measure(
    scn: &Scenario,
    run: &RunResult,
    reference: Option<&ReferenceData>,
) -> Result<(Vec<Metric>, Vec<CheckValue>), TimeMismatch> {
    let s = &run.summary;
    let mut metrics = vec![
        Metric {
            name: "cpu".into(),
            value: s.timing.cpu_total,
            unit: "s".into(),
            relative: false,
        },
        Metric {
            name: "completed".into(),
            value: if s.end == EndReason::Completed {
                1.0
            } else {
                0.0
            },
            unit: "1".into(),
            relative: false,
        },
    ];
    if let Some(r) = reference {
        let d = divergence_of_rows(
            scn,
            (&r.label, &r.rows),
            (&s.formulation, &run.trajectory),
            f64::INFINITY,
        )?;
        metrics.push(Metric {
            name: "position".into(),
            value: d.max_rms_position_rel,
            unit: "1".into(),
            relative: true,
        });
        metrics.extend(error(
            "kinetic_final",
            s.energy.final_kinetic,
            r.kinetic_final,
            "J",
        ));
        metrics.extend(error(
            "dissipated",
            s.energy.ledger.dissipated,
            r.dissipated,
            "J",
        ));
    }
    let outcomes = check_run(scn, run);
    let mut checks: Vec<Metric> = Vec::new();
    for o in &outcomes {
        let Some(x) = o.expected else { continue };
        if o.check == "run_completed" {
            continue; // `completed` says it
        }
        let Some(e) = error(&format!("check:{}", o.check), o.measured, x, &o.unit) else {
            continue;
        };
        match checks.iter_mut().find(|m| m.name == e.name) {
            Some(m) if e.value > m.value => *m = e,
            Some(_) => {}
            None => checks.push(e),
        }
    }
    metrics.extend(checks);
    if let (Some(b), Some(event)) = (
        crate::analysis::check::Bouncing::of(scn),
        run.contacts.events.first(),
    ) {
        metrics.extend(error("first_event", event.t, b.t1, "s"));
    }
    let values = outcomes
        .iter()
        .map(|o| CheckValue {
            check: o.check.clone(),
            measured: o.measured.is_finite().then_some(o.measured),
            expected: o.expected,
            unit: o.unit.clone(),
            pass: o.pass,
        })
        .collect();
    Ok((metrics, values))
}
