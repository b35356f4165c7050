//! The look shared by every chart: sizes and margins, fonts, palette
//! colours, dash patterns, the title strip and filled polygons.

use super::{PlotError, PALETTE};
use plotters::coord::ranged1d::Ranged;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontStyle, RGBColor};

/// The one font family used by every chart (registered from the `dejavu` crate).
pub(super) const FONT: &str = "DejaVu Sans";

/// Size of the line charts, bar charts and plan views (pixels).
pub(super) const SIZE: (u32, u32) = (1000, 650);

/// Height of the title strip (pixels).
pub(super) const TITLE_H: u32 = 40;

/// Margin around a chart (pixels).
pub(super) const MARGIN: u32 = 14;

/// Height of the x label area (tick labels and axis description, pixels).
pub(super) const X_AREA: u32 = 58;

/// Maximum number of tick labels per axis.
pub(super) const TICKS: usize = 10;

/// Dash patterns (dash, gap in pixels) by position of a series in its chart; `None` is solid.
pub(super) const DASHES: [Option<(f32, f32)>; 4] =
    [None, Some((12.0, 6.0)), Some((4.0, 4.0)), Some((20.0, 5.0))];

/// Fill of obstacles.
pub(super) const OBSTACLE: RGBColor = RGBColor(0xA0, 0xA0, 0xA0);

/// Marked x values (vertical lines) and their labels.
pub(super) const MARK: RGBColor = RGBColor(0x55, 0x55, 0x55);

/// Outline of obstacles.
pub(super) const OBSTACLE_EDGE: RGBColor = RGBColor(0x60, 0x60, 0x60);

/// The font at `size` pixels.
pub(super) fn font(size: u32) -> FontDesc<'static> {
    (FONT, size).into_font()
}

/// Colour of palette index `i`.
pub(super) fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Draws the title strip on `root` and returns the area below it.
pub(super) fn titled<DB: DrawingBackend>(
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

/// The finite points of `poly` (for filled polygons).
pub(super) fn finite(poly: &[(f64, f64)]) -> Vec<(f64, f64)> {
    poly.iter()
        .copied()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .collect()
}

/// Draws filled polygons with an outline.
pub(super) fn polygons<'p, DB, X, Y>(
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
