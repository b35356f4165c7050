//! The figures of a case comparison drawn from the forces stage's data
//! (`obstacles.csv`, `stress.csv`; [`crate::fracture::forces`]);
//! [`super::draw`] calls them:
//!
//! - `obstacle_force` (cases with obstacles): the magnitude `|F|` of the
//!   mean force on each obstacle per output interval against time, every
//!   formulation. The magnitude, not a component along a normal: an
//!   obstacle is any polygon (a coast, a cape, an island), with no one
//!   normal, and the floes may push it from several sides;
//! - `pressure` (cases whose runs had contacts): the pack's mean pressure
//!   `p = −(σ_xx + σ_yy)/2` (N/m, positive in compression) per output
//!   interval against time, every formulation.

use crate::analysis::comparison::CaseComparison;
use crate::report::plot::{self, LineChart, Scale, Series};
use crate::report::{plot_err, ReportError};
use std::path::Path;

/// `obstacle_force` and `pressure` of `comp` (each only when it has
/// something to show).
pub(super) fn force_figures(
    comp: &CaseComparison,
    dir: &Path,
    add: &mut impl FnMut(&str, String, &str),
) -> Result<(), ReportError> {
    let name = &comp.scenario.name;
    let obstacles = comp.scenario.obstacles.len();
    if obstacles > 0 {
        let mut series = Vec::new();
        for (i, r) in comp.runs.iter().enumerate() {
            for j in 0..obstacles {
                let points = r
                    .obstacle_forces
                    .iter()
                    .filter(|f| f.obstacle == j)
                    .map(|f| (f.t, f.fx.hypot(f.fy)))
                    .collect();
                let label = match obstacles {
                    1 => r.summary.formulation.clone(),
                    _ => format!("{}, obstacle {j}", r.summary.formulation),
                };
                series.push(Series {
                    dash: (j > 0).then_some(j),
                    ..Series::new(label, i, points)
                });
            }
        }
        let stem = dir.join("obstacle_force");
        chart(
            &format!("{name}: force on the obstacles"),
            "|F| (N)",
            &series,
            &stem,
        )?;
        add(
            "obstacle_force",
            "force on the obstacles against time".into(),
            "the magnitude |F| of the mean force of the floes on each obstacle over each output interval (from the contact impulses, so that fixed-step and event-driven runs compare; data in each run's obstacles.csv), every formulation in its colour, the obstacles by dash pattern; an impact shows as one interval's spike of height impulse / interval",
        );
    }
    let contacts = comp
        .runs
        .iter()
        .any(|r| r.stress.iter().any(|s| s.sxx != 0.0 || s.syy != 0.0));
    if contacts {
        let series: Vec<Series> = comp
            .runs
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let points = r.stress.iter().map(|s| (s.t, s.pressure())).collect();
                Series::new(r.summary.formulation.clone(), i, points)
            })
            .collect();
        let stem = dir.join("pressure");
        chart(
            &format!("{name}: mean pressure in the pack"),
            "p (N/m)",
            &series,
            &stem,
        )?;
        add(
            "pressure",
            "mean pressure in the pack against time".into(),
            "the pack's mean pressure p = −(σxx + σyy)/2 over each output interval, N/m (integrated over the thickness; positive in compression), from its Love–Weber mean stress over the floes' area (data in each run's stress.csv), every formulation",
        );
    }
    Ok(())
}

/// A linear line chart of `series` against time, to `stem`.
fn chart(title: &str, y_label: &str, series: &[Series], stem: &Path) -> Result<(), ReportError> {
    plot::line_chart(
        &LineChart {
            title,
            x_label: "t (s)",
            y_label,
            series,
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            marks: &[],
        },
        stem,
    )
    .map_err(plot_err(stem))?;
    Ok(())
}
