//! Charts for the comparison reports, each written as `<stem>.png` and `<stem>.svg`.
//!
//! The inputs are plain data (no dependency on the rest of the crate), so the
//! report's figures ([`super::figures`]) feed them directly:
//!
//! - [`line_chart`]: curves against a common axis (energy against time, ...);
//! - [`bar_chart`]: stacked bars, one bar per category, one segment per stage;
//! - [`plan_view`]: floe paths in the plane at equal aspect ratio, obstacles in grey
//!   ([`network_view`]: the same without start markers, for a lattice's bonds);
//! - [`snapshot_grid`]: panels of floe polygons sharing the same bounds;
//! - [`case_view`]: one such panel, large, with arrows and a scale bar;
//! - [`animation`]: a looping GIF of snapshot rows, one frame per time,
//!   every frame with the same bounds and scale;
//! - [`marked_panels`]: panels of lines through marked, labelled points on
//!   linear or log axes (a sweep's work–precision plots).
//!
//! Colours come from the colour-blind-safe Okabe–Ito [`PALETTE`], indexed by
//! [`Series::color`] so one formulation keeps its colour across charts. Text
//! uses the DejaVu Sans font shipped by the `dejavu` crate, so rendering needs
//! no system font. Non-finite points are skipped (a curve breaks there);
//! empty or constant data still give a valid chart. Files are written
//! atomically (temporary name in the same folder, then rename).
//!
//! This file holds the public inputs and the entry points; the drawing
//! is behind them, private: `render.rs` (both backends, fonts, files),
//! `glyphs.rs` (the bitmap backend's text, each glyph at its bearing),
//! `style.rs` (sizes, colours, title strip, filled polygons), `axis.rs`
//! (bounds, scales, ticks and their labels, the mesh), `legend.rs`,
//! `line.rs` (line charts and plan views), `bars.rs` (stacked bars),
//! `grid.rs` (snapshot grids) and `animation.rs` (their GIF frames).

mod animation;
mod axis;
mod bars;
mod glyphs;
mod grid;
mod legend;
mod line;
mod marked;
mod render;
mod style;

pub use animation::{FRAME_DELAY_CS, LAST_FRAME_DELAY_CS, PANEL_MAX, WIDTH_MAX};
use bars::Bars;
use grid::Grid;
use line::Xy;
use marked::Marked;
use plotters::prelude::*;
use plotters::style::RGBColor;
use render::render;
use std::path::{Path, PathBuf};

/// The Okabe–Ito colour-blind-safe palette (blue, vermillion, bluish green,
/// reddish purple, orange, sky blue, black, yellow); [`Series::color`] indexes
/// it modulo its length.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0x00, 0x72, 0xB2),
    RGBColor(0xD5, 0x5E, 0x00),
    RGBColor(0x00, 0x9E, 0x73),
    RGBColor(0xCC, 0x79, 0xA7),
    RGBColor(0xE6, 0x9F, 0x00),
    RGBColor(0x56, 0xB4, 0xE9),
    RGBColor(0x00, 0x00, 0x00),
    RGBColor(0xF0, 0xE4, 0x42),
];

/// Why a chart could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The embedded DejaVu Sans font could not be registered.
    #[error("cannot register the DejaVu Sans font")]
    Font,
    /// The input data are inconsistent (e.g. a segment with the wrong number of values).
    #[error("invalid plot input: {0}")]
    Input(String),
    /// The plotting library failed while drawing.
    #[error("drawing failed: {0}")]
    Draw(String),
    /// A file or folder could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError::Draw(e.to_string())
    }
}

/// Height of the title strip of every chart and animation frame (pixels):
/// an animation's time stamp is there.
pub const TITLE_HEIGHT: u32 = style::TITLE_H;

/// Palette index of exact curves and thresholds (black), kept apart from
/// the formulations' colours (the first indices).
pub const EXACT: usize = 6;

/// One named curve (or floe path) with its palette colour.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label; an empty label gives no legend entry.
    pub label: String,
    /// Index into [`PALETTE`] (modulo its length).
    pub color: usize,
    /// The points `(x, y)` in the caller's units; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
    /// Dash pattern (index into the chart's patterns, 0 solid), or `None`
    /// for the pattern of the series' position in the chart.
    pub dash: Option<usize>,
    /// Line width, pixels (2 by [`Series::new`]): a wider line drawn first
    /// stays visible around a narrower one drawn over it.
    pub width: u32,
}

impl Series {
    /// A series dashed by its position in the chart.
    pub fn new(label: impl Into<String>, color: usize, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            color,
            points,
            dash: None,
            width: 2,
        }
    }
}

/// Scale of a value axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear axis.
    #[default]
    Linear,
    /// Logarithmic axis; values `<= 0` are skipped.
    Log,
    /// Logarithmic when the positive values span more than two decades, else linear.
    Auto,
}

/// Curves against a common x axis.
#[derive(Debug, Clone, Copy)]
pub struct LineChart<'a> {
    /// Title above the chart.
    pub title: &'a str,
    /// x axis label with its unit, e.g. `"t (s)"`.
    pub x_label: &'a str,
    /// y axis label with its unit, e.g. `"kinetic energy (J)"`.
    pub y_label: &'a str,
    /// The curves; the n-th is drawn solid, the following ones with dash
    /// patterns so exactly coinciding curves stay distinguishable.
    pub series: &'a [Series],
    /// Scale of the x axis ([`Scale::Log`]: points with `x <= 0` are skipped).
    pub x_scale: Scale,
    /// Scale of the y axis.
    pub y_scale: Scale,
    /// Marked x values (vertical lines, e.g. exact impact times), with a
    /// label drawn at the top of each.
    pub marks: &'a [(f64, String)],
}

/// Stacked bars: one bar per category (e.g. formulation), one segment per
/// stage (e.g. detection, solve, integration, other); segment values are
/// printed inside the segments that are tall enough, totals above the bars.
#[derive(Debug, Clone, Copy)]
pub struct StackedBars<'a> {
    /// Title above the chart.
    pub title: &'a str,
    /// y axis label with its unit, e.g. `"CPU time (s)"`.
    pub y_label: &'a str,
    /// The category names, one bar each, left to right.
    pub categories: &'a [String],
    /// The segments bottom to top: name and one value per category (same
    /// length as `categories`); non-finite and non-positive values are not drawn.
    pub segments: &'a [(String, Vec<f64>)],
    /// Scale of the y axis ([`Scale::Auto`] makes small bars visible next to large ones).
    pub y_scale: Scale,
    /// A note per category printed under its total (e.g. its ratio to the
    /// fastest); empty for none.
    pub notes: &'a [String],
}

/// Floe paths in the plane (metres), at equal aspect ratio, with a start
/// marker per path and obstacles filled grey.
#[derive(Debug, Clone, Copy)]
pub struct PlanView<'a> {
    /// Title above the chart.
    pub title: &'a str,
    /// The paths, points `(x, y)` in metres.
    pub paths: &'a [Series],
    /// Obstacle polygons (vertices in metres).
    pub obstacles: &'a [Vec<(f64, f64)>],
    /// Text labels at points (metres), e.g. a floe's number at the end of
    /// its path; a label that would overlap one written before it is left
    /// out.
    pub labels: &'a [(String, (f64, f64))],
}

/// One panel of a [`snapshot_grid`]: the floes at one time of one run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Panel title, e.g. `"event-driven, t = 3600 s"`.
    pub title: String,
    /// Floe polygons (vertices in metres).
    pub floes: Vec<Vec<(f64, f64)>>,
    /// The floes' labels (their ids), in the order of `floes` (missing or
    /// empty: none); each is written at its floe's centroid when the floe
    /// is drawn wide and tall enough to hold it.
    pub labels: Vec<String>,
    /// Obstacle polygons (vertices in metres).
    pub obstacles: Vec<Vec<(f64, f64)>>,
    /// Arrows drawn over the floes (e.g. the wind, the current, a floe's
    /// velocity), each labelled at its tip; none in the snapshots.
    pub arrows: Vec<Arrow>,
    /// Whether the panel carries a scale bar (a round length in metres, in
    /// its lower left corner).
    pub scale_bar: bool,
}

/// An arrow of a [`Panel`], in metres: a velocity drawn at a length
/// proportional to it (the label gives its value).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Arrow {
    /// Its tail `(x, y)`, m.
    pub from: (f64, f64),
    /// Its head `(x, y)`, m.
    pub to: (f64, f64),
    /// Index into [`PALETTE`] (modulo its length).
    pub color: usize,
    /// Written at its head (empty: none); a label that would overlap a
    /// label already written is left out.
    pub label: String,
}

/// One frame of an [`animation`]: a row of panels at one time.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AnimationFrame {
    /// Title above the row, carrying the frame's time stamp, e.g.
    /// `"head_on: t = 3.5 s"`.
    pub title: String,
    /// The panels, left to right (at most the animation's columns).
    pub panels: Vec<Panel>,
}

/// A line through marked points, each with a label (e.g. the setting it
/// was run at), for [`marked_panels`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MarkedLine {
    /// Legend label; an empty label gives no legend entry.
    pub label: String,
    /// Index into [`PALETTE`] (modulo its length).
    pub color: usize,
    /// The marker shape: circle, triangle, square, cross (modulo 4).
    pub marker: usize,
    /// The points `(x, y, label)`, joined in this order; points that the
    /// axes cannot show (non-finite, or not positive on a log axis) are
    /// skipped.
    pub points: Vec<(f64, f64, String)>,
}

/// One panel of [`marked_panels`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MarkedPanel {
    /// Panel title.
    pub title: String,
    /// x axis label with its unit.
    pub x_label: String,
    /// y axis label with its unit.
    pub y_label: String,
    /// Scale of the x axis.
    pub x_scale: Scale,
    /// Scale of the y axis.
    pub y_scale: Scale,
    /// The lines (a line with the same label in several panels is one
    /// legend entry: give it the same colour and marker in each).
    pub lines: Vec<MarkedLine>,
}

/// Draws `panels`, `cols` per row, under `title` and one legend of every
/// labelled line, into `<stem>.png` and `<stem>.svg`; returns `[png, svg]`.
/// A point label is not written where it would overlap a label already
/// written.
pub fn marked_panels(
    title: &str,
    cols: usize,
    panels: &[MarkedPanel],
    stem: &Path,
) -> Result<[PathBuf; 2], PlotError> {
    render(
        &Marked {
            title,
            cols,
            panels,
        },
        stem,
    )
}

/// Draws `chart` into `<stem>.png` and `<stem>.svg`; returns `[png, svg]`.
pub fn line_chart(chart: &LineChart, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    render(
        &Xy {
            title: chart.title,
            x_label: chart.x_label,
            y_label: chart.y_label,
            series: chart.series,
            obstacles: &[],
            plan: false,
            starts: false,
            x_scale: chart.x_scale,
            y_scale: chart.y_scale,
            marks: chart.marks,
            labels: &[],
        },
        stem,
    )
}

/// Draws `chart` into `<stem>.png` and `<stem>.svg`; returns `[png, svg]`.
///
/// Fails with [`PlotError::Input`] when a segment does not have one value per category.
pub fn bar_chart(chart: &StackedBars, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    if !chart.notes.is_empty() && chart.notes.len() != chart.categories.len() {
        return Err(PlotError::Input(format!(
            "{} notes for {} categories",
            chart.notes.len(),
            chart.categories.len()
        )));
    }
    if let Some((name, v)) = chart
        .segments
        .iter()
        .find(|(_, v)| v.len() != chart.categories.len())
    {
        return Err(PlotError::Input(format!(
            "segment {name:?} has {} values for {} categories",
            v.len(),
            chart.categories.len()
        )));
    }
    render(&Bars(*chart), stem)
}

/// Draws `chart` into `<stem>.png` and `<stem>.svg`; returns `[png, svg]`.
pub fn plan_view(chart: &PlanView, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    plan(chart, true, stem)
}

/// [`plan_view`] without the start markers: for paths that are not
/// trajectories (a lattice's bonds, an arrow).
pub fn network_view(chart: &PlanView, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    plan(chart, false, stem)
}

/// A plan view, with a marker at each path's start when `starts`.
fn plan(chart: &PlanView, starts: bool, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    render(
        &Xy {
            title: chart.title,
            x_label: "x (m)",
            y_label: "y (m)",
            series: chart.paths,
            obstacles: chart.obstacles,
            plan: true,
            starts,
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            marks: &[],
            labels: chart.labels,
        },
        stem,
    )
}

/// Draws a grid of `rows` × `cols` panels (filled row by row) into
/// `<stem>.png` and `<stem>.svg`; returns `[png, svg]`. All panels share
/// the same bounds and an equal aspect ratio.
///
/// Fails with [`PlotError::Input`] when there are more panels than cells.
pub fn snapshot_grid(
    title: &str,
    rows: usize,
    cols: usize,
    panels: &[Panel],
    stem: &Path,
) -> Result<[PathBuf; 2], PlotError> {
    if panels.len() > rows * cols {
        return Err(PlotError::Input(format!(
            "{} panels do not fit a {rows}x{cols} grid",
            panels.len()
        )));
    }
    render(
        &Grid {
            title,
            rows,
            cols,
            panels,
            bounds: grid::shared_bounds(panels.iter()),
            panel_w: grid::PANEL_W,
            square: false,
        },
        stem,
    )
}

/// Draws `panel` alone, large, under `title` (as a panel of
/// [`snapshot_grid`], with its arrows and scale bar) into the PNG file
/// `png` (atomically), and returns it: the picture of a case before it
/// runs (`floebench show`).
pub fn case_view(title: &str, panel: &Panel, png: &Path) -> Result<PathBuf, PlotError> {
    let panels = std::slice::from_ref(panel);
    render::render_png(
        &Grid {
            title,
            rows: 1,
            cols: 1,
            panels,
            bounds: grid::shared_bounds(panels.iter()),
            panel_w: grid::VIEW_W,
            square: false,
        },
        png,
    )
}

/// Writes `frames` as a looping animated GIF at `path` (atomically) and
/// returns its size in pixels: every frame one row of `cols` panels drawn
/// as by [`snapshot_grid`], all sharing the bounds of every panel of every
/// frame (same extent and scale throughout). A panel is at most
/// [`PANEL_MAX`] × [`PANEL_MAX`] pixels and the image at most [`WIDTH_MAX`]
/// wide; each frame shows [`FRAME_DELAY_CS`], the last
/// [`LAST_FRAME_DELAY_CS`] (centiseconds).
///
/// Fails with [`PlotError::Input`] when there is no frame or a frame has
/// more panels than `cols`.
pub fn animation(
    cols: usize,
    frames: &[AnimationFrame],
    path: &Path,
) -> Result<(u32, u32), PlotError> {
    animation::write_gif(cols, frames, path)
}
