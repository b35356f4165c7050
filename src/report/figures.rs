//! The plots of a case comparison, drawn from the same data the CSV files
//! hold (PNG and SVG each, by [`super::plot`]):
//!
//! - `kinetic`: kinetic energy against time, every formulation;
//! - `dissipated`: energy dissipated by contacts against time;
//! - `lattice_energy_<formulation>` (runs whose impacts the lattices
//!   resolved and left vibrating): the ledger's split against time
//!   (`lattice_energy.rs`);
//! - `divergence`: RMS position difference from the reference (the first
//!   formulation), relative to the median floe diameter, with the threshold;
//! - `paths`: the centre-of-mass paths of up to three floes (those that
//!   travel furthest in the reference run), every formulation;
//! - `snapshots`: the floe field at the start, middle and end, one column
//!   per formulation;
//! - `floe_sizes` (cases whose floes can break): the number of floes of
//!   area at least `A` against `A`, log–log, of the initial floes (black
//!   dashes) and of the floes alive at the end of every run, from the data
//!   of `floe_sizes.csv` ([`crate::analysis::floe_sizes`]);
//! - `crack_<formulation>` (runs of the lattice model that broke a floe):
//!   the crack of the run's percussion of largest lattice loss, from its
//!   `percussion.json` ([`super::crack`]);
//! - `obstacle_force` (cases with obstacles) and `pressure` (cases with
//!   contacts): the magnitude of the mean force on each obstacle and the
//!   pack's mean pressure per output interval against time, every
//!   formulation (`figures/forces.rs`);
//! - `cpu`: CPU time per stage of the run of median CPU time, one stacked bar
//!   per formulation, its ratio to the fastest median above it;
//! - `exact_*`: where the checks know the exact motion
//!   ([`crate::analysis::check::curves`]): the bouncing floe's gap (impact
//!   times and rest marked), the distance slid (stop marked), a drifting
//!   floe's speed against the steady drift speed, the inertial circles.
//!
//! - `animation.gif` ([`animate`]): the floe field over time, one panel per
//!   formulation that completed, drawn as the snapshots are, at most
//!   [`ANIMATION_FRAMES`] evenly spaced outputs.
//!
//! A formulation keeps its palette colour (its position in the comparison)
//! on every chart; exact curves and thresholds are black ([`plot::EXACT`]),
//! dashed so that a run on them stays visible. Every figure has a caption
//! for the page.

mod animation;
mod forces;
mod optional;

pub use animation::{animate, animation_outputs, Animation, ANIMATION_FRAMES, ANIMATION_POLYGONS};

use super::plot::{self, LineChart, Panel, PlanView, Scale, Series, StackedBars};
use super::tables::{fastest, ratio_text};
use super::{plot_err, ReportError};
use crate::analysis::comparison::CaseComparison;
use crate::analysis::divergence::frames;
use crate::geometry::Vec2;
use crate::model::Scenario;
use crate::run::{RunResult, TrajectoryRow};
use forces::force_figures;
use optional::{exact_figures, floe_size_figure};
use std::path::Path;

/// The unit of the divergences in the plots, in words: the median
/// equal-area floe diameter `d_med` of the page
/// ([`crate::model::Scenario::median_floe_diameter`]).
pub const DIAMETER: &str = "median floe diameter d_med";

/// A drawn figure: its alternative text and file stem (without extension).
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// What the figure shows.
    pub alt: String,
    /// The file stem in the case folder: `<stem>.png`, `<stem>.svg`.
    pub stem: String,
    /// How to read it, for the page.
    pub caption: String,
}

/// `points` as `(x, y)` pairs, m.
pub(super) fn polygon(points: impl IntoIterator<Item = Vec2>) -> Vec<(f64, f64)> {
    points.into_iter().map(|p| (p.x, p.y)).collect()
}

/// The obstacles of `scn` as polygons.
pub(super) fn obstacle_polygons(scn: &Scenario) -> Vec<Vec<(f64, f64)>> {
    scn.obstacles
        .iter()
        .map(|o| polygon(o.polygon.iter().copied()))
        .collect()
}

/// The floes of `frame` (one output time of a run of `scn`; `None`: an
/// output the run did not reach, an empty panel) with `obstacles`, titled
/// `title`: the panel of the snapshots and of the animation.
fn field_panel(
    run: &RunResult,
    frame: Option<&[TrajectoryRow]>,
    title: String,
    obstacles: &[Vec<(f64, f64)>],
) -> Panel {
    let mut world = Vec::new();
    // Each floe alive then, the pieces of broken ones included, by its
    // record.
    let (floes, labels) = frame
        .unwrap_or_default()
        .iter()
        .filter_map(|row| {
            let rec = run.floes.get(row.floe)?;
            rec.world_polygon(&Vec2::new(row.x, row.y), row.theta, &mut world);
            Some((polygon(world.iter().copied()), row.floe.to_string()))
        })
        .unzip();
    Panel {
        title,
        floes,
        labels,
        obstacles: obstacles.to_vec(),
        ..Panel::default()
    }
}

/// `t = … s` of `frame`, with as many decimals as the output interval and
/// the duration of `scn` need (at most 6).
fn time_stamp(scn: &Scenario, frame: &[TrajectoryRow]) -> String {
    let t = frame.first().map_or(0.0, |r| r.t);
    let decimals = |v: f64| {
        (0..6)
            .find(|&d| {
                let s = v * 10f64.powi(d);
                (s - s.round()).abs() <= 1e-6 * s.abs().max(1.0)
            })
            .unwrap_or(6) as usize
    };
    let d = decimals(scn.output_interval).max(decimals(scn.duration));
    format!("t = {t:.d$} s")
}

/// The energy series `f` of every run, against time.
fn energy_series(runs: &[RunResult], f: fn(&crate::run::EnergySample) -> f64) -> Vec<Series> {
    runs.iter()
        .enumerate()
        .map(|(i, r)| {
            Series::new(
                r.summary.formulation.clone(),
                i,
                r.energy.iter().map(|e| (e.t, f(e))).collect(),
            )
        })
        .collect()
}

/// The line width (pixels) of the paths of run `i` of `n`: the first
/// widest, 2 pixels more than the next, the last 2, so that runs drawn
/// over the same path leave the earlier ones visible as coloured edges.
fn path_width(i: usize, n: usize) -> u32 {
    2 + 2 * n.saturating_sub(i + 1) as u32
}

/// Up to `k` floes that travel furthest (start to end) in `run`.
fn travelling_floes(run: &RunResult, k: usize) -> Vec<usize> {
    let mut fr = frames(run);
    let (Some(first), Some(last)) = (fr.next(), frames(run).last()) else {
        return Vec::new();
    };
    // A floe that broke is followed to its end: its last output.
    let end = |a: &crate::run::TrajectoryRow| {
        last.iter()
            .find(|b| b.floe == a.floe)
            .or_else(|| run.trajectory.iter().rev().find(|b| b.floe == a.floe))
            .copied()
            .unwrap_or(*a)
    };
    let mut d: Vec<(usize, f64)> = first
        .iter()
        .map(|a| {
            let b = end(a);
            (a.floe, (b.x - a.x).hypot(b.y - a.y))
        })
        .collect();
    d.sort_by(|a, b| b.1.total_cmp(&a.1));
    d.into_iter().take(k).map(|(i, _)| i).collect()
}

/// `kinetic` and `dissipated`: the energies of `runs` (of the case
/// `name`) against time, into `dir`.
fn energy_figures(
    name: &str,
    runs: &[RunResult],
    dir: &Path,
    add: &mut impl FnMut(&str, String, &str),
) -> Result<(), ReportError> {
    type EnergyOf = fn(&crate::run::EnergySample) -> f64;
    let energies: [(&str, &str, &str, &str, EnergyOf); 2] = [
        (
            "kinetic",
            "kinetic energy",
            "kinetic energy (J)",
            "the kinetic energy of all floes at each output",
            |e| e.kinetic,
        ),
        (
            "dissipated",
            "energy dissipated by contacts",
            "dissipated energy (J)",
            "the energy dissipated by contacts since t = 0 (negative: the contacts created energy)",
            |e| e.ledger.dissipated,
        ),
    ];
    for (file, what, y_label, caption, f) in energies {
        let stem = dir.join(file);
        plot::line_chart(
            &LineChart {
                title: &format!("{name}: {what}"),
                x_label: "t (s)",
                y_label,
                series: &energy_series(runs, f),
                x_scale: Scale::Linear,
                y_scale: Scale::Linear,
                marks: &[],
            },
            &stem,
        )
        .map_err(plot_err(&stem))?;
        add(file, format!("{what} against time"), caption);
    }
    Ok(())
}

/// `snapshots`: the floes of every run of `runs` (columns; of the case
/// `scn`, with its `obstacles`) at the first, middle and last output of
/// the first run (rows), into `dir`.
fn snapshot_figure(
    scn: &Scenario,
    runs: &[RunResult],
    obstacles: &[Vec<(f64, f64)>],
    dir: &Path,
    add: &mut impl FnMut(&str, String, &str),
) -> Result<(), ReportError> {
    let Some(reference) = runs.first() else {
        return Ok(());
    };
    let name = &scn.name;
    // Snapshots at the start, the middle and the end of the reference run.
    let count = frames(reference).count();
    let mut rows: Vec<usize> = vec![0, count / 2, count.saturating_sub(1)];
    rows.dedup();
    let mut panels = Vec::new();
    for &k in &rows {
        for r in runs {
            let frame = frames(r).nth(k);
            let title = match frame {
                Some(f) => format!("{}, {}", r.summary.formulation, time_stamp(scn, f)),
                None => format!("{}: not reached", r.summary.formulation),
            };
            panels.push(field_panel(r, frame, title, obstacles));
        }
    }
    let stem = dir.join("snapshots");
    plot::snapshot_grid(
        &format!("{name}: floes at three times"),
        rows.len(),
        runs.len(),
        &panels,
        &stem,
    )
    .map_err(plot_err(&stem))?;
    add(
        "snapshots",
        "the floes at the start, middle and end".into(),
        "the floes of every run (columns) at the first, middle and last output of the first run (rows)",
    );
    Ok(())
}

/// The callback the figure functions report each figure drawn to: it
/// appends the figure (`stem`, `alt` text, `caption`) to `figs`.
fn collect_into(figs: &mut Vec<Figure>) -> impl FnMut(&str, String, &str) + '_ {
    move |stem, alt, caption| {
        figs.push(Figure {
            alt,
            stem: stem.to_string(),
            caption: caption.to_string(),
        })
    }
}

/// Draws the figures of one run `run` of `scn` into `dir` (`floebench run
/// --plot`): `kinetic`, `dissipated` and `snapshots`, as a comparison of
/// that run alone draws them.
pub fn draw_run(scn: &Scenario, run: &RunResult, dir: &Path) -> Result<Vec<Figure>, ReportError> {
    let mut figs = Vec::new();
    let mut add = collect_into(&mut figs);
    let runs = std::slice::from_ref(run);
    energy_figures(&scn.name, runs, dir, &mut add)?;
    snapshot_figure(scn, runs, &obstacle_polygons(scn), dir, &mut add)?;
    drop(add);
    Ok(figs)
}

/// Draws every figure of `comp` into `dir`.
pub fn draw(comp: &CaseComparison, dir: &Path) -> Result<Vec<Figure>, ReportError> {
    let scn = &comp.scenario;
    let name = &scn.name;
    let mut figs = Vec::new();
    let mut add = collect_into(&mut figs);

    energy_figures(name, &comp.runs, dir, &mut add)?;
    super::lattice_energy::figures(comp, dir, &mut add)?;

    if let Some(reference) = comp.runs.first() {
        let rname = &reference.summary.formulation;
        let mut series: Vec<Series> = comp
            .pairs
            .iter()
            .filter(|p| &p.a == rname)
            .map(|p| {
                Series::new(
                    format!("{} vs {}", p.b, p.a),
                    comp.runs
                        .iter()
                        .position(|r| r.summary.formulation == p.b)
                        .unwrap_or(0),
                    p.samples
                        .iter()
                        .map(|s| (s.t, s.rms_position_rel))
                        .collect(),
                )
            })
            .collect();
        if let Some(c) = &comp.chaos {
            series.push(Series {
                dash: Some(2),
                ..Series::new(
                    format!("{rname} vs itself from a {:e} perturbation", c.perturbation),
                    0,
                    c.samples.clone(),
                )
            });
        }
        if !series.is_empty() {
            let thr = comp.pairs.first().map_or(0.1, |p| p.threshold);
            series.push(Series {
                dash: Some(1),
                ..Series::new(
                    format!("threshold {thr}"),
                    plot::EXACT,
                    vec![(0.0, thr), (scn.duration, thr)],
                )
            });
            let stem = dir.join("divergence");
            plot::line_chart(
                &LineChart {
                    title: &format!("{name}: divergence between runs, from {rname}"),
                    x_label: "t (s)",
                    y_label: &format!("RMS position difference / {DIAMETER} (-)"),
                    series: &series,
                    x_scale: Scale::Linear,
                    y_scale: Scale::Auto,
                    marks: &[],
                },
                &stem,
            )
            .map_err(plot_err(&stem))?;
            add(
                "divergence",
                format!("divergence between runs, from {rname}"),
                &format!(
                    "the RMS over floes of the distance between a floe's positions in two runs, in median floe diameters d_med, against the threshold (black dashes); the dotted curve is {rname} against itself started from positions perturbed by 1e-12 d_med: its growth tells whether the case is chaotic"
                ),
            );
        }

        let chosen = travelling_floes(reference, 3);
        // Colour: the formulation; dash: the floe; legend entries for both.
        let mut paths = Vec::new();
        let mut labels = Vec::new();
        for (i, r) in comp.runs.iter().enumerate() {
            for (j, &f) in chosen.iter().enumerate() {
                let points: Vec<(f64, f64)> = frames(r)
                    .filter_map(|fr| fr.iter().find(|row| row.floe == f))
                    .map(|row| (row.x, row.y))
                    .collect();
                if i == 0 {
                    if let Some(&end) = points.last() {
                        labels.push((format!("floe {f}"), end));
                    }
                }
                paths.push(Series {
                    dash: Some(j),
                    width: path_width(i, comp.runs.len()),
                    ..Series::new("", i, points)
                });
            }
        }
        for (i, r) in comp.runs.iter().enumerate() {
            paths.push(Series {
                dash: Some(0),
                width: path_width(i, comp.runs.len()),
                ..Series::new(r.summary.formulation.clone(), i, Vec::new())
            });
        }
        for (j, &f) in chosen.iter().enumerate() {
            paths.push(Series {
                dash: Some(j),
                ..Series::new(format!("floe {f}"), plot::EXACT, Vec::new())
            });
        }
        let obstacles = obstacle_polygons(scn);
        let stem = dir.join("paths");
        plot::plan_view(
            &PlanView {
                title: &format!("{name}: paths of floes {chosen:?}"),
                paths: &paths,
                obstacles: &obstacles,
                labels: &labels,
            },
            &stem,
        )
        .map_err(plot_err(&stem))?;
        add(
            "paths",
            format!("paths of floes {chosen:?}"),
            "the centre-of-mass paths of the floes that travel furthest in the first run: colour is the formulation, the dash pattern the floe (labelled at the end of its path in the first run); a dot marks the start; each run is drawn narrower than the one before it, so that paths that coincide show as nested coloured edges",
        );

        snapshot_figure(scn, &comp.runs, &obstacles, dir, &mut add)?;
        exact_figures(comp, dir, &mut add)?;
    }
    floe_size_figure(comp, dir, &mut add)?;
    force_figures(comp, dir, &mut add)?;
    for r in &comp.runs {
        let Some(rec) = &r.percussion else { continue };
        let form = &r.summary.formulation;
        let file = format!("crack_{form}");
        let stem = dir.join(&file);
        let title = format!(
            "{name}, {form}: floe {} at t = {} s, {} broken bonds, {} pieces",
            rec.floe,
            super::format::fmt_num(rec.t),
            rec.broken.len(),
            rec.children.len()
        );
        super::crack::draw(rec, &title, &stem).map_err(plot_err(&stem))?;
        add(
            &file,
            format!("the crack of {form}'s largest percussion"),
            &super::crack::caption(rec, form),
        );
    }

    let categories: Vec<String> = comp
        .runs
        .iter()
        .map(|r| r.summary.formulation.clone())
        .collect();
    let stage = |f: fn(&RunResult) -> f64| comp.runs.iter().map(f).collect::<Vec<f64>>();
    let mut segments = vec![
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
    ];
    // The lattice stage only where impacts ran in the lattices.
    let lattice = stage(|r| r.summary.timing.stages.lattice);
    if lattice.iter().any(|&t| t > 0.0) {
        segments.push(("lattice impacts".to_string(), lattice));
    }
    segments.push(("other".to_string(), stage(|r| r.summary.timing.cpu_other)));
    let notes: Vec<String> = match fastest(&comp.cpu) {
        Some(f) => comp
            .cpu
            .iter()
            .map(|c| format!("{}× fastest", ratio_text(c, f)))
            .collect(),
        None => Vec::new(),
    };
    let stem = dir.join("cpu");
    plot::bar_chart(
        &StackedBars {
            title: &format!("{name}: CPU time per stage (run of median CPU)"),
            y_label: "thread CPU time (s)",
            categories: &categories,
            segments: &segments,
            y_scale: Scale::Linear,
            notes: &notes,
        },
        &stem,
    )
    .map_err(plot_err(&stem))?;
    add(
        "cpu",
        "CPU time per stage".into(),
        "thread CPU time of each formulation's run of median CPU time, split into contact detection, contact solve and smooth integration (and the impacts resolved in the floes' lattices, where impact = \"lattice\" ran them); \"other\" is the rest of the run's CPU time outside those stages (recording the outputs and the energy ledger, the formulation's bookkeeping between stages, the timer's own cost); above each bar its total and its ratio to the fastest median, to the digits the spread of the repeats supports",
    );
    drop(add);
    Ok(figs)
}
