//! Charts for the comparison reports, each written as `<stem>.png` and `<stem>.svg`.
//!
//! The inputs are plain data (no dependency on the rest of the crate), so the
//! comparison harness can feed them directly:
//!
//! - [`line_chart`]: curves against a common axis (energy against time, ...);
//! - [`bar_chart`]: stacked bars, one bar per category, one segment per stage;
//! - [`plan_view`]: floe paths in the plane at equal aspect ratio, obstacles in grey;
//! - [`snapshot_grid`]: panels of floe polygons sharing the same bounds.
//!
//! Colours come from the colour-blind-safe Okabe–Ito [`PALETTE`], indexed by
//! [`Series::color`] so one formulation keeps its colour across charts. Text
//! uses the DejaVu Sans font shipped by the `dejavu` crate, so rendering needs
//! no system font. Non-finite points are skipped (a curve breaks there);
//! empty or constant data still give a valid chart. Files are written
//! atomically (temporary name in the same folder, then rename).

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{register_font, FontStyle, RGBColor};

use crate::run::output::write_atomic;

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

/// The one font family used by every chart (registered from the `dejavu` crate).
const FONT: &str = "DejaVu Sans";
/// Size of the line charts, bar charts and plan views (pixels).
const SIZE: (u32, u32) = (1000, 650);
/// Height of the title strip (pixels).
const TITLE_H: u32 = 40;
/// Margin around a chart (pixels).
const MARGIN: u32 = 14;
/// Height of the x label area (tick labels and axis description, pixels).
const X_AREA: u32 = 58;
/// Maximum number of tick labels per axis.
const TICKS: usize = 10;
/// Dash patterns (dash, gap in pixels) by position of a series in its chart; `None` is solid.
const DASHES: [Option<(f32, f32)>; 4] =
    [None, Some((12.0, 6.0)), Some((4.0, 4.0)), Some((20.0, 5.0))];
/// Fill of obstacles.
const OBSTACLE: RGBColor = RGBColor(0xA0, 0xA0, 0xA0);
/// Outline of obstacles.
const OBSTACLE_EDGE: RGBColor = RGBColor(0x60, 0x60, 0x60);

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

/// One named curve (or floe path) with its palette colour.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label; an empty label gives no legend entry.
    pub label: String,
    /// Index into [`PALETTE`] (modulo its length).
    pub color: usize,
    /// The points `(x, y)` in the caller's units; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
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
    /// Scale of the y axis.
    pub y_scale: Scale,
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
}

/// One panel of a [`snapshot_grid`]: the floes at one time of one run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Panel title, e.g. `"event-driven, t = 3600 s"`.
    pub title: String,
    /// Floe polygons (vertices in metres).
    pub floes: Vec<Vec<(f64, f64)>>,
    /// Obstacle polygons (vertices in metres).
    pub obstacles: Vec<Vec<(f64, f64)>>,
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
            y_scale: chart.y_scale,
        },
        stem,
    )
}

/// Draws `chart` into `<stem>.png` and `<stem>.svg`; returns `[png, svg]`.
///
/// Fails with [`PlotError::Input`] when a segment does not have one value per category.
pub fn bar_chart(chart: &StackedBars, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
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
    render(
        &Xy {
            title: chart.title,
            x_label: "x (m)",
            y_label: "y (m)",
            series: chart.paths,
            obstacles: chart.obstacles,
            plan: true,
            y_scale: Scale::Linear,
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
        },
        stem,
    )
}

// ---------------------------------------------------------------------------
// Rendering to both backends

/// A chart that can be drawn on any backend.
trait Figure {
    /// Image size in pixels.
    fn size(&self) -> (u32, u32) {
        SIZE
    }
    /// Draws the chart on `root` (the whole image).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError>;
}

/// Registers the DejaVu Sans font (regular and bold) once.
fn ensure_font() -> Result<(), PlotError> {
    static OK: OnceLock<bool> = OnceLock::new();
    let ok = *OK.get_or_init(|| {
        register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && register_font(FONT, FontStyle::Bold, dejavu::sans::bold()).is_ok()
    });
    ok.then_some(()).ok_or(PlotError::Font)
}

/// `stem` with `.ext` appended (not replacing a dot already in the name).
fn with_ext(stem: &Path, ext: &str) -> PathBuf {
    let mut s = stem.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Draws `fig` with the SVG and the bitmap backend and writes both files atomically.
fn render<F: Figure>(fig: &F, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    ensure_font()?;
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| PlotError::Io { path, source }
    };
    let (png, svg) = (with_ext(stem, "png"), with_ext(stem, "svg"));
    let dir = match stem.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    let size = fig.size();

    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        fig.draw(&root)?;
        root.present()?;
    }
    write_atomic(&svg, text.as_bytes()).map_err(io(&svg))?;

    // The bitmap backend encodes by file extension: draw into a hidden
    // temporary `.png` next to the target, then rename.
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let name = png.file_name().map(|n| n.to_string_lossy().into_owned());
    let tmp = dir.join(format!(
        ".{}.{}-{}.tmp.png",
        name.unwrap_or_default(),
        std::process::id(),
        COUNT.fetch_add(1, Ordering::Relaxed)
    ));
    let drawn = (|| {
        let root = BitMapBackend::new(&tmp, size).into_drawing_area();
        fig.draw(&root)?;
        root.present()?;
        Ok::<(), PlotError>(())
    })();
    let done = drawn.and_then(|()| std::fs::rename(&tmp, &png).map_err(io(&png)));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done.map(|()| [png, svg])
}

// ---------------------------------------------------------------------------
// Styles, ranges and tick labels

/// The font at `size` pixels.
fn font(size: u32) -> FontDesc<'static> {
    (FONT, size).into_font()
}

/// Colour of palette index `i`.
fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Draws the title strip on `root` and returns the area below it.
fn titled<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<DrawingArea<DB, Shift>, PlotError> {
    root.fill(&WHITE)?;
    let (top, rest) = root.split_vertically(TITLE_H);
    let (w, h) = top.dim_in_pixel();
    let style = font(22)
        .style(FontStyle::Bold)
        .into_text_style(&top)
        .pos(Pos::new(HPos::Center, VPos::Center));
    top.draw_text(title, &style, (w as i32 / 2, h as i32 / 2))?;
    Ok(rest)
}

/// Bounds of the finite values, padded: by `pad` × span, and to a non-empty
/// range when all values are equal (or there are none).
fn bounds(values: impl Iterator<Item = f64>, pad: f64) -> Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    if lo > hi {
        return 0.0..1.0;
    }
    let span = hi - lo;
    if span <= 1e-9 * lo.abs().max(hi.abs()) || span == 0.0 {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return lo - d..hi + d;
    }
    lo - pad * span..hi + pad * span
}

/// Bounds for a log axis of the positive finite values, widened by the
/// factor `pad` on each side.
fn log_bounds(values: impl Iterator<Item = f64>, pad: f64) -> Range<f64> {
    let r = bounds(values.filter(|v| *v > 0.0).map(f64::log10), 0.0);
    let (lo, hi) = if r == (0.0..1.0) {
        (0.0, 1.0)
    } else {
        (r.start, r.end)
    };
    let pad = pad * (hi - lo);
    10f64.powf(lo - pad)..10f64.powf(hi + pad)
}

/// Whether `scale` is logarithmic for these values ([`Scale::Auto`]: span over two decades).
fn is_log(scale: Scale, values: impl Iterator<Item = f64>) -> bool {
    match scale {
        Scale::Linear => false,
        Scale::Log => true,
        Scale::Auto => {
            let r = bounds(values.filter(|v| *v > 0.0 && v.is_finite()), 0.0);
            r.start > 0.0 && r.end / r.start > 100.0
        }
    }
}

/// Compact tick label format: fixed or scientific notation with as many
/// digits as the tick step needs (`1.2e4`, `-1.234e-5`, `0.25`).
#[derive(Debug, Clone, Copy)]
struct Fmt {
    /// Approximate tick step (linear axes) or `None` (log axes: 3 significant digits).
    step: Option<f64>,
    /// Scientific notation for the whole axis, or `None` to decide per value.
    sci: Option<bool>,
}

impl Fmt {
    /// For a linear axis over `r`.
    fn linear(r: &Range<f64>) -> Self {
        let mag = r.start.abs().max(r.end.abs());
        let step = (r.end - r.start) / TICKS as f64;
        Fmt {
            step: (step > 0.0).then_some(step),
            sci: Some(!(1e-3..1e5).contains(&mag)),
        }
    }

    /// For a log axis.
    fn log() -> Self {
        Fmt {
            step: None,
            sci: None,
        }
    }

    /// The label of `v`.
    fn fmt(&self, v: f64) -> String {
        if v == 0.0 || self.step.is_some_and(|s| v.abs() < 1e-6 * s) {
            return "0".into();
        }
        if !v.is_finite() {
            return v.to_string();
        }
        let e = v.abs().log10().floor() as i32;
        let sci = self.sci.unwrap_or(!(-3..5).contains(&e));
        // Decimals the step needs in fixed notation.
        let decimals = self.step.map(|s| 1 - s.log10().floor() as i32);
        let trim = |s: &str| {
            if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                s.to_string()
            }
        };
        if sci {
            let prec = decimals.map_or(2, |d| d + e).clamp(0, 8) as usize;
            let s = format!("{v:.prec$e}");
            match s.split_once('e') {
                Some((m, x)) => format!("{}e{x}", trim(m)),
                None => s,
            }
        } else {
            let d = decimals.unwrap_or(2 - e).clamp(0, 12) as usize;
            let s = trim(&format!("{v:.d$}"));
            if s == "-0" {
                "0".into()
            } else {
                s
            }
        }
    }
}

/// Width of the y label area for these tick labels and an axis description.
fn y_area<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    labels: impl Iterator<Item = String>,
) -> Result<u32, PlotError> {
    let style = font(14).into_text_style(root);
    let mut w = 0;
    for l in labels {
        w = w.max(root.estimate_text_size(&l, &style)?.0);
    }
    Ok(w + 44)
}

/// A value axis over `range`, linear or logarithmic (then `range` is positive).
#[derive(Debug, Clone)]
struct Axis {
    range: Range<f64>,
    log: bool,
}

impl Axis {
    /// A linear axis.
    fn linear(range: Range<f64>) -> Self {
        Axis { range, log: false }
    }

    /// The value on the axis' linear scale.
    fn t(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    /// The tick label format.
    fn fmt(&self) -> Fmt {
        if self.log {
            Fmt::log()
        } else {
            Fmt::linear(&self.range)
        }
    }

    /// The tick labels.
    fn labels(&self) -> impl Iterator<Item = String> {
        let f = self.fmt();
        self.key_points(TICKS).into_iter().map(move |v| f.fmt(v))
    }
}

impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let (a, b) = (self.t(self.range.start), self.t(self.range.end));
        let f = (self.t(*v) - a) / (b - a);
        limit.0 + (f * (limit.1 - limit.0) as f64 + 1e-3).floor() as i32
    }

    /// Linear: plotters' round steps. Log: decades, or 1-2-5 or 1..9 times
    /// the decades when there are too few decades in the range.
    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        let linear = || RangedCoordf64::from(self.range.clone()).key_points(hint.max_num_points());
        if !self.log {
            return linear();
        }
        let (a, b) = (
            self.range.start.log10().floor() as i32,
            self.range.end.log10().ceil() as i32,
        );
        let sets: [&[f64]; 3] = [
            &[1.0],
            &[1.0, 2.0, 5.0],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
        ];
        let max = hint.max_num_points();
        let light = hint.weight().allow_light_points();
        let mut best: Vec<f64> = Vec::new();
        for m in sets {
            let pts: Vec<f64> = (a..=b)
                .flat_map(|e| m.iter().map(move |k| k * 10f64.powi(e)))
                .filter(|v| (self.range.start..=self.range.end).contains(v))
                .collect();
            if pts.len() > max || (!light && best.len() >= 4) {
                break;
            }
            best = pts;
        }
        if best.len() < 2 {
            linear()
        } else {
            best
        }
    }

    fn range(&self) -> Range<f64> {
        self.range.clone()
    }
}

/// Draws the mesh (grid, axes, tick labels and axis descriptions).
fn mesh<DB, X, Y>(
    chart: &mut ChartContext<DB, Cartesian2d<X, Y>>,
    (x_label, xf): (&str, &dyn Fn(&f64) -> String),
    (y_label, yf): (&str, &dyn Fn(&f64) -> String),
    x_grid: bool,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut m = chart.configure_mesh();
    m.x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style(font(16))
        .label_style(font(14))
        .x_labels(TICKS)
        .y_labels(TICKS)
        .x_label_formatter(xf)
        .y_label_formatter(yf)
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(BLACK.mix(0.04))
        .axis_style(BLACK.stroke_width(1));
    if !x_grid {
        m.disable_x_mesh();
    }
    m.draw()?;
    Ok(())
}

/// A pixel rectangle `(x0, y0, x1, y1)`.
type Rect = (i32, i32, i32, i32);

/// Draws the legend in the corner of the plotting area where it hides least
/// of the `occupied` pixel rectangles; `entries` are the label texts.
fn legend<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    entries: &[&str],
    occupied: &[Rect],
) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    X: Ranged,
    Y: Ranged,
{
    if entries.is_empty() {
        return Ok(());
    }
    let area = chart.plotting_area();
    let style = font(15).into_text_style(area);
    let mut w = 0;
    for e in entries {
        w = w.max(area.estimate_text_size(e, &style)?.0 as i32);
    }
    let (w, h) = (w + 70, 24 * entries.len() as i32 + 16);
    let (xr, yr) = area.get_pixel_range();
    let corners = [
        (
            SeriesLabelPosition::UpperRight,
            xr.end - w - 12,
            yr.start + 12,
        ),
        (SeriesLabelPosition::UpperLeft, xr.start + 12, yr.start + 12),
        (
            SeriesLabelPosition::LowerRight,
            xr.end - w - 12,
            yr.end - h - 12,
        ),
        (
            SeriesLabelPosition::LowerLeft,
            xr.start + 12,
            yr.end - h - 12,
        ),
    ];
    let cost = |&(_, x0, y0): &(SeriesLabelPosition, i32, i32)| -> i64 {
        occupied
            .iter()
            .map(|&(a0, b0, a1, b1)| {
                let dx = (a1.max(a0 + 1).min(x0 + w) - a0.max(x0)).max(0) as i64;
                let dy = (b1.max(b0 + 1).min(y0 + h) - b0.max(y0)).max(0) as i64;
                if dx * dy > 0 {
                    dx * dy + 50
                } else {
                    0
                }
            })
            .sum()
    };
    let best = corners
        .iter()
        .min_by_key(|c| cost(c))
        .map_or(SeriesLabelPosition::UpperRight, |c| c.0.clone());
    chart
        .configure_series_labels()
        .position(best)
        .margin(12)
        .legend_area_size(40)
        .label_font(font(15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.6))
        .draw()?;
    Ok(())
}

/// The finite points of `poly` (for filled polygons).
fn finite(poly: &[(f64, f64)]) -> Vec<(f64, f64)> {
    poly.iter()
        .copied()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .collect()
}

/// Draws filled polygons with an outline.
fn polygons<'p, DB, X, Y>(
    chart: &mut ChartContext<DB, Cartesian2d<X, Y>>,
    polys: impl Iterator<Item = &'p Vec<(f64, f64)>>,
    fill: RGBAColor,
    edge: RGBColor,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let polys: Vec<Vec<(f64, f64)>> = polys.map(|p| finite(p)).filter(|p| p.len() >= 2).collect();
    chart.draw_series(polys.iter().map(|p| Polygon::new(p.clone(), fill.filled())))?;
    chart.draw_series(polys.iter().map(|p| {
        let mut closed = p.clone();
        closed.push(p[0]);
        PathElement::new(closed, edge.stroke_width(1))
    }))?;
    Ok(())
}

// ---------------------------------------------------------------------------
// Line charts and plan views

/// A line chart or (with `plan`) a plan view.
struct Xy<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    series: &'a [Series],
    obstacles: &'a [Vec<(f64, f64)>],
    /// Equal aspect ratio, start markers, padded x range.
    plan: bool,
    y_scale: Scale,
}

impl Xy<'_> {
    /// All series points.
    fn points(&self) -> impl Iterator<Item = &(f64, f64)> {
        self.series.iter().flat_map(|s| &s.points)
    }

    /// Draws the chart on the axes `x` and `y`, with a y label area `y_area` pixels wide.
    fn body<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        x: Axis,
        y: Axis,
        y_area: u32,
    ) -> Result<(), PlotError> {
        let (xf, yf) = (x.fmt(), y.fmt());
        let log = y.log;
        let mut chart = ChartBuilder::on(area)
            .margin(MARGIN)
            .margin_right(2 * MARGIN)
            .x_label_area_size(X_AREA)
            .y_label_area_size(y_area)
            .build_cartesian_2d(x, y)?;
        let (xfmt, yfmt) = (|v: &f64| xf.fmt(*v), |v: &f64| yf.fmt(*v));
        mesh(
            &mut chart,
            (self.x_label, &xfmt),
            (self.y_label, &yfmt),
            true,
        )?;
        polygons(
            &mut chart,
            self.obstacles.iter(),
            OBSTACLE.to_rgba(),
            OBSTACLE_EDGE,
        )?;

        let ok = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && (!log || p.1 > 0.0);
        let mut occupied: Vec<Rect> = Vec::new();
        for o in self.obstacles {
            let px: Vec<_> = finite(o).iter().map(|p| chart.backend_coord(p)).collect();
            if let (Some(x0), Some(x1), Some(y0), Some(y1)) = (
                px.iter().map(|p| p.0).min(),
                px.iter().map(|p| p.0).max(),
                px.iter().map(|p| p.1).min(),
                px.iter().map(|p| p.1).max(),
            ) {
                occupied.push((x0, y0, x1, y1));
            }
        }
        let plot = chart.plotting_area().strip_coord_spec();
        let (xr, yr) = plot.get_pixel_range();
        let mut entries = Vec::new();
        for (k, s) in self.series.iter().enumerate() {
            let style = color(s.color).stroke_width(2);
            // Vary the dash also when the palette wraps around.
            let dash = DASHES[(k + s.color / PALETTE.len()) % DASHES.len()];
            if !s.label.is_empty() {
                entries.push(s.label.as_str());
                chart
                    .draw_series(LineSeries::new(std::iter::empty(), style))?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| {
                        let (d, g) = dash.unwrap_or((40.0, 1.0));
                        DashedPathElement::new(vec![(x, y), (x + 30, y)], d, g, style)
                    });
            }
            for run in s.points.split(|p| !ok(p)).filter(|r| !r.is_empty()) {
                // Pixels relative to the plotting area, one point per pixel step:
                // the picture is unchanged, the SVG stays small for long series.
                let mut px: Vec<(i32, i32)> = Vec::new();
                for p in run {
                    let q = chart.backend_coord(p);
                    if px.last() != Some(&(q.0 - xr.start, q.1 - yr.start)) {
                        px.push((q.0 - xr.start, q.1 - yr.start));
                        occupied.push((q.0, q.1, q.0, q.1));
                    }
                }
                if let [one] = px[..] {
                    plot.draw(&Circle::new(one, 4, style.filled()))?;
                }
                for piece in strokes(&px, dash) {
                    plot.draw(&PathElement::new(piece, style))?;
                }
            }
            if self.plan {
                if let Some(p) = s.points.iter().find(|p| ok(p)) {
                    chart.draw_series([
                        Circle::new(*p, 6, color(s.color).filled()),
                        Circle::new(*p, 6, BLACK.stroke_width(1)),
                    ])?;
                }
            }
        }
        if self.plan && !self.series.is_empty() {
            entries.push("start");
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                .label("start")
                .legend(|(x, y)| Circle::new((x + 15, y), 6, BLACK.stroke_width(1)));
        }
        legend(&mut chart, &entries, &occupied)
    }
}

impl Figure for Xy<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let area = titled(root, self.title)?;
        let log = !self.plan && is_log(self.y_scale, self.points().map(|p| p.1));
        let all = || self.points().chain(self.obstacles.iter().flatten());
        let pad = if self.plan { 0.05 } else { 0.0 };
        let x0 = bounds(all().map(|p| p.0), pad);
        let y0 = if log {
            log_bounds(self.points().filter(|p| p.0.is_finite()).map(|p| p.1), 0.05)
        } else {
            bounds(all().map(|p| p.1), 0.05)
        };
        let (mut x, mut y) = (
            Axis::linear(x0.clone()),
            Axis {
                range: y0.clone(),
                log,
            },
        );
        let mut w = y_area(&area, y.labels())?;
        if self.plan {
            // The y labels depend on the widened range and the plotting width on
            // the y labels: two rounds settle it.
            let (aw, ah) = area.dim_in_pixel();
            let ph = ah as f64 - (2 * MARGIN + X_AREA) as f64;
            for _ in 0..2 {
                let pw = aw as f64 - (3 * MARGIN + w) as f64;
                let (xr, yr) = equal_aspect(&x0, &y0, (pw, ph));
                (x, y) = (Axis::linear(xr), Axis::linear(yr));
                w = y_area(&area, y.labels())?;
            }
        }
        self.body(&area, x, y, w)
    }
}

/// Widens `x` or `y` (about its centre) so that one unit takes the same
/// pixels along both in a plotting area of `(pw, ph)` pixels.
fn equal_aspect(x: &Range<f64>, y: &Range<f64>, (pw, ph): (f64, f64)) -> (Range<f64>, Range<f64>) {
    let widen = |r: &Range<f64>, span: f64| {
        let c = 0.5 * (r.start + r.end);
        c - 0.5 * span..c + 0.5 * span
    };
    let (sx, sy) = (x.end - x.start, y.end - y.start);
    if sx / pw > sy / ph {
        (x.clone(), widen(y, sx * ph / pw))
    } else {
        (widen(x, sy * pw / ph), y.clone())
    }
}

/// The pieces of the pixel polyline `px` to stroke: its dashes (`dash` is
/// dash and gap length, `None` solid), each also cut where the line turns
/// back by more than about 100°, where the joins of thick bitmap lines spike.
fn strokes(px: &[(i32, i32)], dash: Option<(f32, f32)>) -> Vec<Vec<(i32, i32)>> {
    let (on, off) = dash.map_or((f64::INFINITY, 0.0), |(d, g)| (d as f64, g as f64));
    let mut out: Vec<Vec<(i32, i32)>> = Vec::new();
    let mut piece: Vec<(f64, f64)> = Vec::new();
    let mut flush = |piece: &mut Vec<(f64, f64)>| {
        if piece.len() > 1 {
            out.push(
                piece
                    .iter()
                    .map(|p| (p.0.round() as i32, p.1.round() as i32))
                    .collect(),
            );
        }
        piece.clear();
    };
    let (mut solid, mut left) = (true, on);
    let mut dir: Option<(f64, f64)> = None;
    for w in px.windows(2) {
        let (a, b) = (
            (w[0].0 as f64, w[0].1 as f64),
            (w[1].0 as f64, w[1].1 as f64),
        );
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        if len == 0.0 {
            continue;
        }
        let d = ((b.0 - a.0) / len, (b.1 - a.1) / len);
        if solid && dir.is_some_and(|o| o.0 * d.0 + o.1 * d.1 < -0.17) {
            let last = piece.last().copied();
            flush(&mut piece);
            piece.extend(last);
        }
        dir = Some(d);
        let mut done = 0.0;
        while done < len {
            let step = left.min(len - done);
            let at = |t: f64| (a.0 + d.0 * t, a.1 + d.1 * t);
            if solid {
                if piece.is_empty() {
                    piece.push(at(done));
                }
                piece.push(at(done + step));
            }
            done += step;
            left -= step;
            if left <= 0.0 {
                if solid {
                    flush(&mut piece);
                }
                solid = !solid;
                left = if solid { on } else { off };
            }
        }
    }
    flush(&mut piece);
    out
}

// ---------------------------------------------------------------------------
// Stacked bars

/// A stacked bar chart.
struct Bars<'a>(StackedBars<'a>);

/// The category axis: `-0.5..n - 0.5` with ticks at the integers.
struct Categories(usize);

impl Ranged for Categories {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;
    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        RangedCoordf64::from(self.range()).map(v, limit)
    }
    fn key_points<H: KeyPointHint>(&self, _: H) -> Vec<f64> {
        (0..self.0).map(|i| i as f64).collect()
    }
    fn range(&self) -> Range<f64> {
        -0.5..self.0.max(1) as f64 - 0.5
    }
}

/// Width of a bar in category units.
const BAR_W: f64 = 0.6;

impl Bars<'_> {
    /// The drawable (finite, positive) value of segment `j` for category `i`.
    fn value(&self, j: usize, i: usize) -> f64 {
        let v = self.0.segments[j].1.get(i).copied().unwrap_or(0.0);
        if v.is_finite() && v > 0.0 {
            v
        } else {
            0.0
        }
    }

    /// Bar totals, one per category.
    fn totals(&self) -> Vec<f64> {
        (0..self.0.categories.len())
            .map(|i| (0..self.0.segments.len()).map(|j| self.value(j, i)).sum())
            .collect()
    }

    /// Draws the chart on the value axis `y` with a y label area `y_area`
    /// pixels wide; `base` is the bottom of the bars.
    fn body<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        y: Axis,
        y_area: u32,
        base: f64,
    ) -> Result<(), PlotError> {
        let c = self.0;
        let yf = y.fmt();
        let area = legend_row(
            area,
            &c.segments
                .iter()
                .enumerate()
                .map(|(j, (label, _))| (label.as_str(), color(j)))
                .collect::<Vec<_>>(),
        )?;
        let n = c.categories.len();
        let mut chart = ChartBuilder::on(&area)
            .margin(MARGIN)
            .margin_right(2 * MARGIN)
            .x_label_area_size(X_AREA - 20)
            .y_label_area_size(y_area)
            .build_cartesian_2d(Categories(n), y)?;
        let name = |v: &f64| {
            let i = v.round();
            (i >= 0.0 && (i - v).abs() < 1e-6)
                .then(|| c.categories.get(i as usize).cloned())
                .flatten()
                .unwrap_or_default()
        };
        let yfmt = |v: &f64| yf.fmt(*v);
        mesh(&mut chart, ("", &name), (c.y_label, &yfmt), false)?;

        let value_font = font(13);
        for (i, total) in self.totals().into_iter().enumerate() {
            let xi = i as f64;
            let mut low = base;
            let mut cum = 0.0;
            let drawn = (0..c.segments.len())
                .filter(|&j| self.value(j, i) > 0.0)
                .count();
            for j in 0..c.segments.len() {
                let v = self.value(j, i);
                if v == 0.0 {
                    continue;
                }
                cum += v;
                let (p0, p1) = ((xi - BAR_W / 2.0, low), (xi + BAR_W / 2.0, cum.max(low)));
                chart.draw_series([
                    Rectangle::new([p0, p1], color(j).filled()),
                    Rectangle::new([p0, p1], WHITE.stroke_width(1)),
                ])?;
                let (b0, b1) = (chart.backend_coord(&p0), chart.backend_coord(&p1));
                if drawn > 1 && b0.1 - b1.1 >= 20 {
                    let mid = if base > 0.0 {
                        (low * cum.max(low)).sqrt()
                    } else {
                        0.5 * (low + cum)
                    };
                    let rgb = color(j);
                    let luma = 0.299 * rgb.0 as f64 + 0.587 * rgb.1 as f64 + 0.114 * rgb.2 as f64;
                    let ink = if luma > 140.0 { BLACK } else { WHITE };
                    let style = value_font
                        .color(&ink)
                        .pos(Pos::new(HPos::Center, VPos::Center));
                    chart.draw_series(std::iter::once(Text::new(yf_value(v), (xi, mid), style)))?;
                }
                low = cum;
            }
            if total > 0.0 {
                let style = value_font
                    .style(FontStyle::Bold)
                    .color(&BLACK)
                    .pos(Pos::new(HPos::Center, VPos::Bottom));
                chart.draw_series(std::iter::once(
                    EmptyElement::at((xi, total)) + Text::new(yf_value(total), (0, -4), style),
                ))?;
            }
        }
        Ok(())
    }
}

/// Draws a one-line legend (colour swatch and label per entry) centred at
/// the top of `area` and returns the area below it.
fn legend_row<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(&str, RGBColor)],
) -> Result<DrawingArea<DB, Shift>, PlotError> {
    if entries.is_empty() {
        return Ok(area.clone());
    }
    let (row, rest) = area.split_vertically(30);
    let style = font(15)
        .into_text_style(&row)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let mut widths = Vec::new();
    for (label, _) in entries {
        widths.push(row.estimate_text_size(label, &style)?.0 as i32);
    }
    let total: i32 = widths.iter().map(|w| w + 56).sum::<i32>() - 24;
    let mut x = (row.dim_in_pixel().0 as i32 - total) / 2;
    for ((label, fill), w) in entries.iter().zip(widths) {
        row.draw(&Rectangle::new([(x, 8), (x + 24, 22)], fill.filled()))?;
        row.draw_text(label, &style, (x + 32, 15))?;
        x += w + 56;
    }
    Ok(rest)
}

/// A printed bar value: three significant digits, compact.
fn yf_value(v: f64) -> String {
    Fmt::log().fmt(v)
}

impl Figure for Bars<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let area = titled(root, self.0.title)?;
        let totals = self.totals();
        let values = || {
            (0..self.0.segments.len())
                .flat_map(move |j| (0..self.0.categories.len()).map(move |i| self.value(j, i)))
                .chain(totals.iter().copied())
        };
        let y = if is_log(self.0.y_scale, values()) {
            let r = log_bounds(values(), 0.0);
            // From a whole decade (slightly below, so that it is labelled),
            // with room above the tallest bar for its total.
            let (lo, hi) = (r.start.log10().floor(), r.end.log10());
            let hi = (hi + 0.12 * (hi - lo).max(1.0)).max(lo + 1.0);
            Axis {
                range: 0.999 * 10f64.powf(lo)..10f64.powf(hi),
                log: true,
            }
        } else {
            let top = totals.iter().copied().fold(0.0, f64::max);
            Axis::linear(0.0..if top > 0.0 { 1.12 * top } else { 1.0 })
        };
        let w = y_area(&area, y.labels())?;
        let base = if y.log { y.range.start } else { 0.0 };
        self.body(&area, y, w, base)
    }
}

// ---------------------------------------------------------------------------
// Snapshot grids

/// A grid of snapshot panels.
struct Grid<'a> {
    title: &'a str,
    rows: usize,
    cols: usize,
    panels: &'a [Panel],
}

/// Panel width (pixels).
const PANEL_W: u32 = 330;
/// Panel title height (pixels).
const PANEL_TITLE: u32 = 28;
/// Y label area of a panel (pixels).
const PANEL_Y_AREA: u32 = 70;
/// X label area of a panel (pixels).
const PANEL_X_AREA: u32 = 44;
/// Margin inside a panel (pixels).
const PANEL_MARGIN: u32 = 8;

impl Grid<'_> {
    /// All vertices of all panels.
    fn points(&self) -> impl Iterator<Item = &(f64, f64)> {
        self.panels
            .iter()
            .flat_map(|p| p.floes.iter().chain(&p.obstacles))
            .flatten()
    }

    /// Shared data bounds, padded by 3 %.
    fn bounds(&self) -> (Range<f64>, Range<f64>) {
        let ok = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
        (
            bounds(self.points().filter(ok).map(|p| p.0), 0.03),
            bounds(self.points().filter(ok).map(|p| p.1), 0.03),
        )
    }

    /// Plotting area of one panel (pixels).
    fn plot_size(&self) -> (f64, f64) {
        let (x, y) = self.bounds();
        let pw = (PANEL_W - PANEL_Y_AREA - 2 * PANEL_MARGIN) as f64;
        let aspect = ((y.end - y.start) / (x.end - x.start)).clamp(0.5, 1.5);
        (pw, (pw * aspect).round())
    }
}

impl Figure for Grid<'_> {
    fn size(&self) -> (u32, u32) {
        let (_, ph) = self.plot_size();
        let panel_h = ph as u32 + PANEL_TITLE + PANEL_X_AREA + 2 * PANEL_MARGIN;
        (
            (self.cols as u32 * PANEL_W).max(600),
            self.rows as u32 * panel_h + TITLE_H,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let area = titled(root, self.title)?;
        if self.rows == 0 || self.cols == 0 {
            return Ok(());
        }
        let (w, _) = area.dim_in_pixel();
        let area = area.margin(0, 0, (w - self.cols as u32 * PANEL_W.min(w)) / 2, 0);
        let cells: Vec<_> = area
            .split_evenly((self.rows, self.cols))
            .iter()
            .map(|c| c.split_vertically(PANEL_TITLE))
            .collect();
        // Every panel gets the plotting area of the first (they differ by a
        // pixel at most), so equal aspect holds for all of them.
        let (cw, ch) = cells[0].1.dim_in_pixel();
        let plot = (
            cw as f64 - (2 * PANEL_MARGIN + PANEL_Y_AREA) as f64,
            ch as f64 - (2 * PANEL_MARGIN + PANEL_X_AREA) as f64,
        );
        let (x, y) = self.bounds();
        let (x, y) = equal_aspect(&x, &y, plot);
        let (xf, yf) = (Fmt::linear(&x), Fmt::linear(&y));
        let (xfmt, yfmt) = (|v: &f64| xf.fmt(*v), |v: &f64| yf.fmt(*v));
        let (fill, edge) = (color(5).mix(0.55), color(0));
        let title_style = font(15)
            .into_text_style(root)
            .pos(Pos::new(HPos::Center, VPos::Center));
        for (k, ((top, cell), panel)) in cells.iter().zip(self.panels).enumerate() {
            let (row, col) = (k / self.cols, k % self.cols);
            // Centred over the plotting area.
            let centre = (PANEL_MARGIN + PANEL_Y_AREA) as i32 + (plot.0 / 2.0) as i32;
            top.draw_text(
                &panel.title,
                &title_style,
                (centre, PANEL_TITLE as i32 / 2 + 2),
            )?;
            let mut chart = ChartBuilder::on(cell)
                .margin(PANEL_MARGIN)
                .x_label_area_size(PANEL_X_AREA)
                .y_label_area_size(PANEL_Y_AREA)
                .build_cartesian_2d(x.clone(), y.clone())?;
            let mut m = chart.configure_mesh();
            m.label_style(font(12))
                .axis_desc_style(font(13))
                .x_labels(5)
                .y_labels(5)
                .x_label_formatter(&xfmt)
                .y_label_formatter(&yfmt)
                .bold_line_style(BLACK.mix(0.08))
                .light_line_style(TRANSPARENT);
            if row + 1 == self.rows || k + self.cols >= self.panels.len() {
                m.x_desc("x (m)");
            } else {
                m.x_labels(0);
            }
            if col == 0 {
                m.y_desc("y (m)");
            } else {
                m.y_labels(0);
            }
            m.draw()?;
            polygons(
                &mut chart,
                panel.obstacles.iter(),
                OBSTACLE.to_rgba(),
                OBSTACLE_EDGE,
            )?;
            polygons(&mut chart, panel.floes.iter(), fill, edge)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_are_compact() {
        let f = Fmt::linear(&(0.0..21600.0));
        assert_eq!(f.fmt(5000.0), "5000");
        let f = Fmt::linear(&(0.0..2e-5));
        assert_eq!(f.fmt(1.2e-5), "1.2e-5");
        assert_eq!(f.fmt(-1.234e-5), "-1.23e-5");
        let f = Fmt::linear(&(0.0..1.0));
        assert_eq!(f.fmt(0.25), "0.25");
        assert_eq!(f.fmt(1e-18), "0");
        let f = Fmt::linear(&(0.0..1.2e6));
        assert_eq!(f.fmt(4e5), "4e5");
        assert_eq!(Fmt::log().fmt(0.01), "0.01");
        assert_eq!(Fmt::log().fmt(1234.4), "1234");
        assert_eq!(Fmt::log().fmt(0.5), "0.5");
        assert_eq!(Fmt::log().fmt(1e5), "1e5");
    }

    #[test]
    fn degenerate_bounds_are_padded() {
        assert_eq!(bounds([].into_iter(), 0.05), 0.0..1.0);
        assert_eq!(bounds([2.0, 2.0].into_iter(), 0.05), 1.8..2.2);
        assert_eq!(bounds([0.0, f64::NAN].into_iter(), 0.05), -1.0..1.0);
    }
}
