//! Marked-line panels: lines through a few points, each point marked and
//! labelled (the setting it was run at), on linear or logarithmic axes;
//! one panel per measure, and one legend for all of them under the title
//! (the work–precision and error-against-setting plots of a sweep).

use super::axis::{bounds, is_log, log_bounds, mesh_with_ticks, y_area, Axis};
use super::render::Figure;
use super::style::{color, font, titled, MARGIN, TITLE_H, X_AREA};
use super::{MarkedLine, MarkedPanel, PlotError};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontStyle, RGBColor};

/// Panels of marked lines.
pub(super) struct Marked<'a> {
    pub(super) title: &'a str,
    pub(super) cols: usize,
    pub(super) panels: &'a [MarkedPanel],
}

/// Size of one panel (pixels).
const PANEL: (u32, u32) = (520, 370);

/// Height of a panel's title (pixels).
const PANEL_TITLE: u32 = 26;

/// Height of one row of the legend (pixels).
const LEGEND_ROW: u32 = 22;

/// Width of one column of the legend (pixels).
const LEGEND_COL: u32 = 520;

/// Most tick labels on a panel's x axis (a panel is half as wide as a
/// line chart).
const X_TICKS: usize = 6;

/// Marker size (pixels).
const MARK: i32 = 5;

impl Marked<'_> {
    fn cols(&self) -> usize {
        self.cols.clamp(1, self.panels.len().max(1))
    }

    fn rows(&self) -> usize {
        self.panels.len().div_ceil(self.cols())
    }

    /// The legend entries: each labelled line once, in order of appearance.
    fn entries(&self) -> Vec<&MarkedLine> {
        let mut out: Vec<&MarkedLine> = Vec::new();
        for l in self.panels.iter().flat_map(|p| &p.lines) {
            if !l.label.is_empty() && !out.iter().any(|o| o.label == l.label) {
                out.push(l);
            }
        }
        out
    }

    fn legend_cols(&self) -> usize {
        ((self.cols() as u32 * PANEL.0) / LEGEND_COL).max(1) as usize
    }

    fn legend_height(&self) -> u32 {
        let n = self.entries().len();
        if n == 0 {
            0
        } else {
            n.div_ceil(self.legend_cols()) as u32 * LEGEND_ROW + 8
        }
    }
}

/// The axis of `values` on `scale` (a log axis only for positive values).
fn axis(values: impl Iterator<Item = f64> + Clone, scale: super::Scale) -> Axis {
    if is_log(scale, values.clone()) {
        Axis {
            range: log_bounds(values.filter(|v| v.is_finite()), 0.06),
            log: true,
        }
    } else {
        Axis::linear(bounds(values, 0.06))
    }
}

/// Draws the marker of shape `k` (circle, triangle, square, cross; modulo
/// 4) at the pixel `p` of `area`.
fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    k: usize,
    p: (i32, i32),
    c: RGBColor,
) -> Result<(), PlotError> {
    let (x, y) = p;
    match k % 4 {
        0 => area.draw(&Circle::new(p, MARK, c.filled()))?,
        1 => area.draw(&TriangleMarker::new(p, MARK + 1, c.filled()))?,
        2 => area.draw(&Rectangle::new(
            [(x - MARK + 1, y - MARK + 1), (x + MARK - 1, y + MARK - 1)],
            c.filled(),
        ))?,
        _ => area.draw(&Cross::new(p, MARK, c.stroke_width(2)))?,
    }
    Ok(())
}

impl Marked<'_> {
    fn panel<DB: DrawingBackend>(
        &self,
        cell: &DrawingArea<DB, Shift>,
        p: &MarkedPanel,
    ) -> Result<(), PlotError> {
        let (head, body) = cell.split_vertically(PANEL_TITLE);
        let (w, h) = head.dim_in_pixel();
        let style = font(16)
            .style(FontStyle::Bold)
            .into_text_style(&head)
            .pos(Pos::new(HPos::Center, VPos::Center));
        head.draw_text(&p.title, &style, (w as i32 / 2, h as i32 / 2))?;
        let pts = || p.lines.iter().flat_map(|l| &l.points);
        let x = axis(pts().map(|q| q.0), p.x_scale);
        let y = axis(pts().map(|q| q.1), p.y_scale);
        let (lx, ly) = (x.log, y.log);
        let ok = move |q: &&(f64, f64, String)| {
            q.0.is_finite() && q.1.is_finite() && (!lx || q.0 > 0.0) && (!ly || q.1 > 0.0)
        };
        let yw = y_area(&body, y.labels())?;
        let (xf, yf) = (x.fmt(), y.fmt());
        let mut chart = ChartBuilder::on(&body)
            .margin(MARGIN)
            .margin_right(3 * MARGIN)
            .x_label_area_size(X_AREA)
            .y_label_area_size(yw)
            .build_cartesian_2d(x, y)?;
        let (xfmt, yfmt) = (|v: &f64| xf.fmt(*v), |v: &f64| yf.fmt(*v));
        mesh_with_ticks(
            &mut chart,
            (&p.x_label, &xfmt),
            (&p.y_label, &yfmt),
            true,
            X_TICKS,
        )?;
        let plot = chart.plotting_area().strip_coord_spec();
        let (xr, yr) = plot.get_pixel_range();
        let px = |q: &(f64, f64, String)| {
            let b = chart.backend_coord(&(q.0, q.1));
            (b.0 - xr.start, b.1 - yr.start)
        };
        // Lines first, then markers, then labels (a label already written
        // at nearly the same place is not written again).
        for l in &p.lines {
            let c = color(l.color);
            let path: Vec<(i32, i32)> = l.points.iter().filter(ok).map(px).collect();
            plot.draw(&PathElement::new(path, c.stroke_width(2)))?;
        }
        // The boxes of the labels written: a label that would overlap one
        // (by its measured width) is left out.
        let mut written: Vec<(i32, i32, i32, i32)> = Vec::new();
        let text = font(12).into_text_style(&plot);
        for l in &p.lines {
            let c = color(l.color);
            for q in l.points.iter().filter(ok) {
                let at = px(q);
                draw_marker(&plot, l.marker, at, c)?;
                if q.2.is_empty() {
                    continue;
                }
                let pos = (at.0 + MARK + 3, at.1 - MARK - 12);
                let (w, h) = plot.estimate_text_size(&q.2, &text)?;
                let b = (
                    pos.0 - 1,
                    pos.1 - 1,
                    pos.0 + w as i32 + 1,
                    pos.1 + h as i32 + 1,
                );
                let crowded = written
                    .iter()
                    .any(|o| b.0 < o.2 && o.0 < b.2 && b.1 < o.3 && o.1 < b.3);
                if !crowded {
                    plot.draw_text(&q.2, &text, pos)?;
                    written.push(b);
                }
            }
        }
        if !pts().any(|q| ok(&q)) {
            let (w, h) = plot.dim_in_pixel();
            let style = font(15)
                .into_text_style(&plot)
                .pos(Pos::new(HPos::Center, VPos::Center));
            plot.draw_text(
                "no positive value to show",
                &style,
                (w as i32 / 2, h as i32 / 2),
            )?;
        }
        Ok(())
    }

    /// The legend strip: marker, line and label of every entry, in columns.
    fn legend<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let cols = self.legend_cols();
        let (w, _) = area.dim_in_pixel();
        let col_w = (w / cols as u32) as i32;
        let style = font(14)
            .into_text_style(area)
            .pos(Pos::new(HPos::Left, VPos::Center));
        for (k, e) in self.entries().iter().enumerate() {
            let x = (k % cols) as i32 * col_w + 24;
            let y = (k / cols) as i32 * LEGEND_ROW as i32 + LEGEND_ROW as i32 / 2 + 4;
            let c = color(e.color);
            area.draw(&PathElement::new(
                vec![(x, y), (x + 34, y)],
                c.stroke_width(2),
            ))?;
            draw_marker(area, e.marker, (x + 17, y), c)?;
            area.draw_text(&e.label, &style, (x + 44, y))?;
        }
        Ok(())
    }
}

impl Figure for Marked<'_> {
    fn size(&self) -> (u32, u32) {
        (
            self.cols() as u32 * PANEL.0,
            self.rows().max(1) as u32 * PANEL.1 + TITLE_H + self.legend_height(),
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let area = titled(root, self.title)?;
        let (legend, area) = area.split_vertically(self.legend_height());
        self.legend(&legend)?;
        let rows = self.rows();
        if rows == 0 {
            return Ok(());
        }
        for (cell, p) in area
            .split_evenly((rows, self.cols()))
            .iter()
            .zip(self.panels)
        {
            self.panel(cell, p)?;
        }
        Ok(())
    }
}
