//! The plots of a case comparison, drawn from the same data the CSV files
//! hold (PNG and SVG each, by [`super::plot`]):
//!
//! - `kinetic`: kinetic energy against time, every formulation;
//! - `dissipated`: energy dissipated by contacts against time;
//! - `divergence`: RMS position difference from the reference (the first
//!   formulation), relative to the mean floe diameter, with the threshold;
//! - `paths`: the centre-of-mass paths of up to three floes (those that
//!   travel furthest in the reference run), every formulation;
//! - `snapshots`: the floe field at the start, middle and end, one column
//!   per formulation;
//! - `cpu`: CPU time per stage, one stacked bar per formulation.
//!
//! A formulation keeps its palette colour (its position in the comparison)
//! on every chart.

use super::plot::{self, LineChart, Panel, PlanView, Scale, Series, StackedBars};
use super::ReportError;
use crate::analysis::comparison::CaseComparison;
use crate::analysis::divergence::frames;
use crate::geometry::Vec2;
use crate::run::RunResult;
use std::path::Path;

/// A drawn figure: its alternative text and file stem (without extension).
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// What the figure shows.
    pub alt: String,
    /// The file stem in the case folder: `<stem>.png`, `<stem>.svg`.
    pub stem: String,
}

fn plot_err(stem: &Path) -> impl FnOnce(plot::PlotError) -> ReportError + '_ {
    move |e| ReportError::Plot {
        path: stem.to_path_buf(),
        message: e.to_string(),
    }
}

fn polygon(points: impl IntoIterator<Item = Vec2>) -> Vec<(f64, f64)> {
    points.into_iter().map(|p| (p.x, p.y)).collect()
}

/// The energy series `f` of every run, against time.
fn energy_series(comp: &CaseComparison, f: fn(&crate::run::EnergySample) -> f64) -> Vec<Series> {
    comp.runs
        .iter()
        .enumerate()
        .map(|(i, r)| Series {
            label: r.summary.formulation.clone(),
            color: i,
            points: r.energy.iter().map(|e| (e.t, f(e))).collect(),
        })
        .collect()
}

/// Up to `k` floes that travel furthest (start to end) in `run`.
fn travelling_floes(run: &RunResult, n: usize, k: usize) -> Vec<usize> {
    let mut fr = frames(run, n);
    let (Some(first), Some(last)) = (fr.next(), frames(run, n).last()) else {
        return Vec::new();
    };
    let mut d: Vec<(usize, f64)> = first
        .iter()
        .zip(last)
        .map(|(a, b)| (a.floe, (b.x - a.x).hypot(b.y - a.y)))
        .collect();
    d.sort_by(|a, b| b.1.total_cmp(&a.1));
    d.into_iter().take(k).map(|(i, _)| i).collect()
}

/// Draws every figure of `comp` into `dir`.
pub fn draw(comp: &CaseComparison, dir: &Path) -> Result<Vec<Figure>, ReportError> {
    let scn = &comp.scenario;
    let name = &scn.name;
    let n = scn.floes.len();
    let mut figs = Vec::new();
    let mut add = |stem: &str, alt: String| {
        figs.push(Figure {
            alt,
            stem: stem.to_string(),
        })
    };

    type EnergyOf = fn(&crate::run::EnergySample) -> f64;
    let energies: [(&str, &str, &str, EnergyOf); 2] = [
        ("kinetic", "kinetic energy", "kinetic energy (J)", |e| {
            e.kinetic
        }),
        (
            "dissipated",
            "energy dissipated by contacts",
            "dissipated energy (J)",
            |e| e.dissipated,
        ),
    ];
    for (file, what, y_label, f) in energies {
        let stem = dir.join(file);
        plot::line_chart(
            &LineChart {
                title: &format!("{name}: {what}"),
                x_label: "t (s)",
                y_label,
                series: &energy_series(comp, f),
                y_scale: Scale::Linear,
            },
            &stem,
        )
        .map_err(plot_err(&stem))?;
        add(file, format!("{what} against time"));
    }

    if let Some(reference) = comp.runs.first() {
        let rname = &reference.summary.formulation;
        let mut series: Vec<Series> = comp
            .pairs
            .iter()
            .filter(|p| &p.a == rname)
            .map(|p| Series {
                label: format!("{} vs {}", p.b, p.a),
                color: comp
                    .runs
                    .iter()
                    .position(|r| r.summary.formulation == p.b)
                    .unwrap_or(0),
                points: p
                    .samples
                    .iter()
                    .map(|s| (s.t, s.rms_position_rel))
                    .collect(),
            })
            .collect();
        if !series.is_empty() {
            let thr = comp.pairs[0].threshold;
            series.push(Series {
                label: format!("threshold {thr}"),
                color: 7,
                points: vec![(0.0, thr), (scn.duration, thr)],
            });
            let stem = dir.join("divergence");
            plot::line_chart(
                &LineChart {
                    title: &format!("{name}: trajectory difference from {rname}"),
                    x_label: "t (s)",
                    y_label: "RMS position difference / mean floe diameter (-)",
                    series: &series,
                    y_scale: Scale::Linear,
                },
                &stem,
            )
            .map_err(plot_err(&stem))?;
            add("divergence", format!("trajectory difference from {rname}"));
        }

        let chosen = travelling_floes(reference, n, 3);
        let mut paths = Vec::new();
        for (i, r) in comp.runs.iter().enumerate() {
            for &f in &chosen {
                paths.push(Series {
                    label: format!("{} #{f}", r.summary.formulation),
                    color: i,
                    points: frames(r, n).map(|fr| (fr[f].x, fr[f].y)).collect(),
                });
            }
        }
        let obstacles: Vec<Vec<(f64, f64)>> = scn
            .obstacles
            .iter()
            .map(|o| polygon(o.polygon.iter().copied()))
            .collect();
        let stem = dir.join("paths");
        plot::plan_view(
            &PlanView {
                title: &format!("{name}: paths of floes {chosen:?}"),
                paths: &paths,
                obstacles: &obstacles,
            },
            &stem,
        )
        .map_err(plot_err(&stem))?;
        add("paths", format!("paths of floes {chosen:?}"));

        // Snapshots at the start, the middle and the end of the reference run.
        let count = frames(reference, n).count();
        let mut rows: Vec<usize> = vec![0, count / 2, count.saturating_sub(1)];
        rows.dedup();
        let mut panels = Vec::new();
        let mut world = Vec::new();
        for &k in &rows {
            for r in &comp.runs {
                let Some(frame) = frames(r, n).nth(k) else {
                    panels.push(Panel {
                        title: format!("{}: not reached", r.summary.formulation),
                        floes: Vec::new(),
                        obstacles: obstacles.clone(),
                    });
                    continue;
                };
                let floes = frame
                    .iter()
                    .zip(&scn.floes)
                    .map(|(row, floe)| {
                        floe.world_polygon(&Vec2::new(row.x, row.y), row.theta, &mut world);
                        polygon(world.iter().copied())
                    })
                    .collect();
                panels.push(Panel {
                    title: format!("{}, t = {} s", r.summary.formulation, frame[0].t),
                    floes,
                    obstacles: obstacles.clone(),
                });
            }
        }
        let stem = dir.join("snapshots");
        plot::snapshot_grid(
            &format!("{name}: floes at three times"),
            rows.len(),
            comp.runs.len(),
            &panels,
            &stem,
        )
        .map_err(plot_err(&stem))?;
        add("snapshots", "the floes at the start, middle and end".into());
    }

    let categories: Vec<String> = comp
        .runs
        .iter()
        .map(|r| r.summary.formulation.clone())
        .collect();
    let stage = |f: fn(&RunResult) -> f64| comp.runs.iter().map(f).collect::<Vec<f64>>();
    let segments = [
        (
            "detection".to_string(),
            stage(|r| r.summary.timing.stages.detection),
        ),
        (
            "solve".to_string(),
            stage(|r| r.summary.timing.stages.solve),
        ),
        (
            "integration".to_string(),
            stage(|r| r.summary.timing.stages.integration),
        ),
        ("other".to_string(), stage(|r| r.summary.timing.cpu_other)),
    ];
    let stem = dir.join("cpu");
    plot::bar_chart(
        &StackedBars {
            title: &format!("{name}: CPU time per stage"),
            y_label: "thread CPU time (s)",
            categories: &categories,
            segments: &segments,
            y_scale: Scale::Linear,
        },
        &stem,
    )
    .map_err(plot_err(&stem))?;
    add("cpu", "CPU time per stage".into());
    Ok(figs)
}
