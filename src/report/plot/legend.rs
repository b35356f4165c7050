//! Legends: in the corner (or, failing one, the middle of a side) of a
//! plotting area where it hides least (line charts, plan views), or on one
//! line above it (stacked bars).

use super::style::font;
use super::PlotError;
use plotters::coord::ranged1d::Ranged;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::RGBColor;

/// A pixel rectangle `(x0, y0, x1, y1)`.
pub(super) type Rect = (i32, i32, i32, i32);

/// Draws the legend in the corner of the plotting area where it hides least
/// of the `occupied` pixel rectangles; `entries` are the label texts.
pub(super) fn legend<'a, DB, X, Y>(
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
        // The middles of the sides, last: taken only when every corner
        // covers more (a corner wins a tie).
        (
            SeriesLabelPosition::MiddleRight,
            xr.end - w - 12,
            (yr.start + yr.end - h) / 2,
        ),
        (
            SeriesLabelPosition::MiddleLeft,
            xr.start + 12,
            (yr.start + yr.end - h) / 2,
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

/// Draws a one-line legend (colour swatch and label per entry) centred at
/// the top of `area` and returns the area below it.
pub(super) fn legend_row<DB: DrawingBackend>(
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
