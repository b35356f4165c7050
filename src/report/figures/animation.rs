//! The animation of a case comparison, `animation.gif` ([`animate`]): the
//! floe field over time, drawn as the snapshots are, at the outputs of
//! [`animation_outputs`].

use super::{field_panel, obstacle_polygons, time_stamp};
use crate::analysis::comparison::CaseComparison;
use crate::analysis::divergence::frames;
use crate::report::plot::{self, AnimationFrame};
use crate::report::{plot_err, ReportError};
use crate::run::{EndReason, RunResult, TrajectoryRow};
use std::fmt::Write as _;
use std::path::Path;

/// Most frames of an animation ([`animate`]).
pub const ANIMATION_FRAMES: usize = 60;

/// Most floe polygons an animation draws, over all its frames and panels:
/// a large field gets fewer frames (at least 2), so that drawing its
/// animation takes about a second (4 panels of 20 000 floes: 15 frames;
/// measured by the ignored test `animation::demo_large_field`).
pub const ANIMATION_POLYGONS: usize = 1_200_000;

/// The output indices an animation shows of a run with `outputs` output
/// times and `per_frame` floe polygons in a frame: evenly spaced (rounded
/// to the nearest output), the first and the last always, at most
/// [`ANIMATION_FRAMES`] and at most [`ANIMATION_POLYGONS`]` / per_frame`
/// (but 2) of them; every output when there are fewer.
pub fn animation_outputs(outputs: usize, per_frame: usize) -> Vec<usize> {
    let most = ANIMATION_FRAMES.min((ANIMATION_POLYGONS / per_frame.max(1)).max(2));
    let f = outputs.min(most);
    if f < 2 {
        return (0..f).collect();
    }
    (0..f)
        .map(|i| (i * (outputs - 1) + (f - 1) / 2) / (f - 1))
        .collect()
}

/// The animation of a comparison: its file in the case folder and how to
/// read it.
#[derive(Debug, Clone, PartialEq)]
pub struct Animation {
    /// The file name in the case folder (`animation.gif`).
    pub file: String,
    /// What it shows.
    pub alt: String,
    /// How to read it, for the page: frames, times, sizes.
    pub caption: String,
}

/// Draws `animation.gif` into `dir`: the floe field over time, one panel
/// per run of `comp` that completed (in the comparison's order, titled
/// with its formulation), every panel and frame at the same extent and
/// scale, each frame titled with its time stamp, at the outputs of
/// [`animation_outputs`]. `None` (and no file) when no run completed.
pub fn animate(comp: &CaseComparison, dir: &Path) -> Result<Option<Animation>, ReportError> {
    let scn = &comp.scenario;
    let n = scn.floes.len();
    let (done, left_out): (Vec<&RunResult>, Vec<&RunResult>) = comp
        .runs
        .iter()
        .partition(|r| r.summary.end == EndReason::Completed);
    let per_run: Vec<Vec<&[TrajectoryRow]>> = done.iter().map(|r| frames(r).collect()).collect();
    let Some(outputs) = per_run.first().map(Vec::len) else {
        return Ok(None);
    };
    let picks = animation_outputs(outputs, n * done.len());
    if picks.is_empty() {
        return Ok(None);
    }
    let obstacles = obstacle_polygons(scn);
    let shown: Vec<AnimationFrame> = picks
        .iter()
        .map(|&k| AnimationFrame {
            title: format!("{}: {}", scn.name, time_stamp(scn, per_run[0][k])),
            panels: done
                .iter()
                .zip(&per_run)
                .map(|(r, fr)| {
                    let frame = fr.get(k).copied();
                    let name = &r.summary.formulation;
                    let title = match frame {
                        Some(_) => name.clone(),
                        None => format!("{name}: not reached"),
                    };
                    field_panel(r, frame, title, &obstacles)
                })
                .collect(),
        })
        .collect();
    let file = "animation.gif";
    let path = dir.join(file);
    let (w, h) = plot::animation(done.len(), &shown, &path).map_err(plot_err(&path))?;
    let names: Vec<&str> = done
        .iter()
        .map(|r| r.summary.formulation.as_str())
        .collect();
    let mut caption = format!(
        "the floe field over time, one panel per formulation that completed ({}), every panel and frame at the same extent and scale, the time stamp in the title: {} of the {outputs} output times, evenly spaced from the first to the last (at most {ANIMATION_FRAMES} frames; a large field gets fewer, at most {ANIMATION_POLYGONS} floe polygons in all), {} frames per second, the last held {} s; {w}×{h} px (a panel at most {}×{} px, the image at most {} px wide)",
        names.join(", "),
        picks.len(),
        100 / u32::from(plot::FRAME_DELAY_CS.max(1)),
        f64::from(plot::LAST_FRAME_DELAY_CS) / 100.0,
        plot::PANEL_MAX,
        plot::PANEL_MAX,
        plot::WIDTH_MAX,
    );
    if !left_out.is_empty() {
        let names: Vec<&str> = left_out
            .iter()
            .map(|r| r.summary.formulation.as_str())
            .collect();
        let _ = write!(
            caption,
            "; not shown (did not complete): {}",
            names.join(", ")
        );
    }
    Ok(Some(Animation {
        file: file.into(),
        alt: format!("the floes over time, {}", names.join(", ")),
        caption,
    }))
}
