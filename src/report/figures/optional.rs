//! The figures of a case comparison drawn only for some cases:
//! `floe_sizes` (cases whose floes can break) and `exact_*` (where the
//! checks know the exact motion); [`super::draw`] calls them.

use super::obstacle_polygons;
use crate::analysis::check::curves::exact_curves;
use crate::analysis::comparison::CaseComparison;
use crate::analysis::floe_sizes::When;
use crate::report::plot::{self, LineChart, PlanView, Scale, Series};
use crate::report::{plot_err, ReportError};
use crate::run::EndReason;
use std::path::Path;

/// The corners of the staircase of a complementary cumulative count
/// (`points` ascending in area): the count `N_k` holds on `(A_{k−1}, A_k]`
/// and drops to `N_{k+1}` just above `A_k`.
fn staircase(points: &[(f64, usize)]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(2 * points.len());
    for (k, &(a, n)) in points.iter().enumerate() {
        if k > 0 {
            out.push((points[k - 1].0, n as f64));
        }
        out.push((a, n as f64));
    }
    out
}

/// `floe_sizes`: the floe-size distributions of `comp` (none drawn when it
/// has none).
pub(super) fn floe_size_figure(
    comp: &CaseComparison,
    dir: &Path,
    add: &mut impl FnMut(&str, String, &str),
) -> Result<(), ReportError> {
    if comp.floe_sizes.is_empty() {
        return Ok(());
    }
    let series: Vec<Series> = comp
        .floe_sizes
        .iter()
        .map(|d| match d.when {
            When::Start => Series {
                dash: Some(1),
                ..Series::new("start (every run)", plot::EXACT, staircase(&d.points))
            },
            When::End => {
                let i = comp
                    .runs
                    .iter()
                    .position(|r| r.summary.formulation == d.formulation)
                    .unwrap_or(0);
                let label = match comp.runs.get(i) {
                    Some(r) if r.summary.end != EndReason::Completed => format!(
                        "{}, where it stopped (t = {} s)",
                        d.formulation, r.summary.t_reached
                    ),
                    _ => format!("{}, end", d.formulation),
                };
                Series::new(label, i, staircase(&d.points))
            }
        })
        .collect();
    let stem = dir.join("floe_sizes");
    plot::line_chart(
        &LineChart {
            title: &format!(
                "{}: floe sizes at the start and the end",
                comp.scenario.name
            ),
            x_label: "floe area A (m²)",
            y_label: "floes of area ≥ A (count)",
            series: &series,
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            marks: &[],
        },
        &stem,
    )
    .map_err(plot_err(&stem))?;
    add(
        "floe_sizes",
        "floe-size distribution at the start and the end".into(),
        "the number of floes whose area is at least A against A (a complementary cumulative count, log–log; data in floe_sizes.csv): the initial floes in black dashes, the floes alive at the end of each run in its colour; a run that broke floes moves its curve to smaller areas and larger counts, a single size is a dot; the runs' curves are dashed differently so that coinciding ones stay visible, but coinciding dots hide each other (the CSV has every one)",
    );
    Ok(())
}

/// The plots of the exact curves of `comp` ([`exact_curves`]): each run's
/// measurement (its colour) and the exact curve (black dashes), marked
/// instants as vertical lines.
pub(super) fn exact_figures(
    comp: &CaseComparison,
    dir: &Path,
    add: &mut impl FnMut(&str, String, &str),
) -> Result<(), ReportError> {
    let name = &comp.scenario.name;
    for c in exact_curves(&comp.scenario, &comp.runs) {
        let mut series: Vec<Series> = comp
            .runs
            .iter()
            .zip(&c.measured)
            .enumerate()
            .map(|(i, (r, m))| Series::new(r.summary.formulation.clone(), i, m.clone()))
            .collect();
        series.push(Series {
            dash: Some(1),
            ..Series::new(c.exact_label.clone(), plot::EXACT, c.exact.clone())
        });
        let stem = dir.join(c.stem);
        let title = format!("{name}: {}", c.what);
        if c.plan {
            let obstacles = obstacle_polygons(&comp.scenario);
            plot::plan_view(
                &PlanView {
                    title: &title,
                    paths: &series,
                    obstacles: &obstacles,
                    labels: &[],
                },
                &stem,
            )
        } else {
            plot::line_chart(
                &LineChart {
                    title: &title,
                    x_label: &c.x_label,
                    y_label: &c.y_label,
                    series: &series,
                    x_scale: Scale::Linear,
                    y_scale: Scale::Linear,
                    marks: &c.marks,
                },
                &stem,
            )
        }
        .map_err(plot_err(&stem))?;
        add(
            c.stem,
            c.what.clone(),
            &format!(
                "{}: every run against the exact answer of the checks (black dashes: {}){}",
                c.what,
                c.exact_label,
                if c.marks.is_empty() {
                    ""
                } else {
                    "; vertical lines mark the exact instants"
                }
            ),
        );
    }
    Ok(())
}
