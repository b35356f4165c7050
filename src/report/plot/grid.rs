//! Snapshot grids: panels of floe polygons sharing the same bounds, at
//! equal aspect ratio.

use super::axis::{bounds, Fmt};
use super::line::equal_aspect;
use super::render::Figure;
use super::style::{color, finite, font, polygons, titled, OBSTACLE, OBSTACLE_EDGE, TITLE_H};
use super::{Arrow, Panel, PlotError};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::ops::Range;

/// A grid of snapshot panels.
pub(super) struct Grid<'a> {
    pub(super) title: &'a str,
    pub(super) rows: usize,
    pub(super) cols: usize,
    pub(super) panels: &'a [Panel],
    /// The data bounds (x, y) every panel shows ([`shared_bounds`]).
    pub(super) bounds: (Range<f64>, Range<f64>),
    /// Panel width (pixels).
    pub(super) panel_w: u32,
    /// Whether a panel may be at most as tall as it is wide (else its
    /// plotting area's aspect ratio is the data's, clamped to 0.5–1.5).
    pub(super) square: bool,
}

/// Panel width of a snapshot grid (pixels).
pub(super) const PANEL_W: u32 = 330;

/// Panel width of a [`super::case_view`] (pixels).
pub(super) const VIEW_W: u32 = 1000;

/// Panel title height (pixels).
const PANEL_TITLE: u32 = 28;

/// Y label area of a panel (pixels).
const PANEL_Y_AREA: u32 = 70;

/// X label area of a panel (pixels).
const PANEL_X_AREA: u32 = 44;

/// Margin inside a panel (pixels).
const PANEL_MARGIN: u32 = 8;

/// The data bounds shared by `panels` (every vertex of every floe and
/// obstacle, both ends of every arrow), padded by 3 %.
pub(super) fn shared_bounds<'p>(
    panels: impl Iterator<Item = &'p Panel> + Clone,
) -> (Range<f64>, Range<f64>) {
    let points = || {
        panels
            .clone()
            .flat_map(|p| {
                p.floes
                    .iter()
                    .chain(&p.obstacles)
                    .flatten()
                    .copied()
                    .chain(p.arrows.iter().flat_map(|a| [a.from, a.to]))
            })
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    (
        bounds(points().map(|p| p.0), 0.03),
        bounds(points().map(|p| p.1), 0.03),
    )
}

impl Grid<'_> {
    /// Plotting area of one panel (pixels).
    fn plot_size(&self) -> (f64, f64) {
        let (x, y) = &self.bounds;
        let pw = self.panel_w.saturating_sub(PANEL_Y_AREA + 2 * PANEL_MARGIN) as f64;
        let aspect = ((y.end - y.start) / (x.end - x.start)).clamp(0.5, 1.5);
        let ph = (pw * aspect).round();
        if self.square {
            let most = self
                .panel_w
                .saturating_sub(PANEL_TITLE + PANEL_X_AREA + 2 * PANEL_MARGIN);
            (pw, ph.min(most as f64))
        } else {
            (pw, ph)
        }
    }
}

impl Figure for Grid<'_> {
    fn size(&self) -> (u32, u32) {
        let (_, ph) = self.plot_size();
        let panel_h = ph as u32 + PANEL_TITLE + PANEL_X_AREA + 2 * PANEL_MARGIN;
        (
            (self.cols as u32 * self.panel_w).max(600),
            self.rows as u32 * panel_h + TITLE_H,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let area = titled(root, self.title)?;
        if self.rows == 0 || self.cols == 0 {
            return Ok(());
        }
        let (w, _) = area.dim_in_pixel();
        let area = area.margin(0, 0, (w - (self.cols as u32 * self.panel_w).min(w)) / 2, 0);
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
        let (x, y) = equal_aspect(&self.bounds.0, &self.bounds.1, plot);
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
            let mut taken = floe_labels(&mut chart, panel)?;
            arrows(&mut chart, &panel.arrows, &mut taken)?;
            if panel.scale_bar {
                scale_bar(&mut chart, &x)?;
            }
        }
        Ok(())
    }
}

/// Height of a floe label's font (pixels).
const LABEL_FONT: u32 = 11;

/// A label's box in pixels, `(x0, y0, x1, y1)`.
type Rect = (i32, i32, i32, i32);

/// The pixel box of `text` (DejaVu Sans digits and letters are about 0.64
/// em wide on average) centred at `c`, in `size`-pixel font, with a margin
/// of 1 pixel.
fn label_box(text: &str, c: (i32, i32), size: u32) -> Rect {
    let w = (text.chars().count() as f64 * 0.64 * size as f64).ceil() as i32;
    let h = size as i32;
    (
        c.0 - w / 2 - 1,
        c.1 - h / 2 - 1,
        c.0 + w / 2 + 1,
        c.1 + h / 2 + 1,
    )
}

/// Whether the boxes `a` and `b` overlap.
fn overlap(a: &Rect, b: &Rect) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// Writes each floe's label of `panel` at its centroid, where the floe is
/// drawn at least as wide as the label plus 4 pixels and as tall as its
/// font plus 4, and the label overlaps none written before it: a few large
/// floes get their ids, a dense field none (the labels would hide the
/// floes). Returns the boxes of the labels written.
fn floe_labels<DB: DrawingBackend>(
    chart: &mut ChartContext<DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    panel: &Panel,
) -> Result<Vec<Rect>, PlotError> {
    let style = font(LABEL_FONT)
        .color(&BLACK.mix(0.8))
        .pos(Pos::new(HPos::Center, VPos::Center));
    let mut texts = Vec::new();
    let mut taken: Vec<Rect> = Vec::new();
    for (poly, label) in panel.floes.iter().zip(&panel.labels) {
        let poly = finite(poly);
        let Some(c) = centroid(&poly) else { continue };
        if label.is_empty() {
            continue;
        }
        let px: Vec<(i32, i32)> = poly.iter().map(|&p| chart.backend_coord(&p)).collect();
        let span = |f: fn(&(i32, i32)) -> i32| {
            px.iter().map(f).max().unwrap_or(0) - px.iter().map(f).min().unwrap_or(0)
        };
        let b = label_box(label, chart.backend_coord(&c), LABEL_FONT);
        let fits = span(|p| p.0) >= b.2 - b.0 + 2 && span(|p| p.1) >= LABEL_FONT as i32 + 4;
        if fits && !taken.iter().any(|t| overlap(t, &b)) {
            taken.push(b);
            texts.push(Text::new(label.clone(), c, style.clone()));
        }
    }
    chart.draw_series(texts)?;
    Ok(taken)
}

/// Height of an arrow label's font (pixels).
const ARROW_FONT: u32 = 13;

/// Draws `arrows` (a shaft and a head of two strokes in pixel space), each
/// label just beyond its head where it lies inside the plotting area and
/// overlaps none of `taken` (which it joins).
fn arrows<DB: DrawingBackend>(
    chart: &mut ChartContext<DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    arrows: &[Arrow],
    taken: &mut Vec<Rect>,
) -> Result<(), PlotError> {
    let area = chart.plotting_area().strip_coord_spec();
    let (xr, yr) = area.get_pixel_range();
    let rel = |q: (i32, i32)| (q.0 - xr.start, q.1 - yr.start);
    for a in arrows {
        let (p, q) = (chart.backend_coord(&a.from), chart.backend_coord(&a.to));
        let style = color(a.color).stroke_width(2);
        let (dx, dy) = ((q.0 - p.0) as f64, (q.1 - p.1) as f64);
        let len = dx.hypot(dy);
        area.draw(&PathElement::new(vec![rel(p), rel(q)], style))?;
        if len >= 1.0 {
            // A head of 9 pixels (at most half the arrow), 25° off the shaft.
            let (ux, uy) = (dx / len, dy / len);
            let h = 9f64.min(0.5 * len);
            let (c, s) = (25f64.to_radians().cos(), 25f64.to_radians().sin());
            for sign in [1.0, -1.0] {
                let (bx, by) = (ux * c - sign * uy * s, sign * ux * s + uy * c);
                let end = (q.0 - (h * bx).round() as i32, q.1 - (h * by).round() as i32);
                area.draw(&PathElement::new(vec![rel(q), rel(end)], style))?;
            }
        }
        if a.label.is_empty() {
            continue;
        }
        // Beyond the head, along the arrow.
        let (ux, uy) = if len >= 1.0 {
            (dx / len, dy / len)
        } else {
            (1.0, 0.0)
        };
        let half = label_box(&a.label, (0, 0), ARROW_FONT);
        let reach = ((half.2 as f64 * ux).abs() + (half.3 as f64 * uy).abs() + 4.0).round();
        let c = (
            q.0 + (reach * ux).round() as i32,
            q.1 + (reach * uy).round() as i32,
        );
        let b = label_box(&a.label, c, ARROW_FONT);
        let inside = b.0 >= xr.start && b.2 <= xr.end && b.1 >= yr.start && b.3 <= yr.end;
        if !inside || taken.iter().any(|t| overlap(t, &b)) {
            continue;
        }
        taken.push(b);
        let text = font(ARROW_FONT)
            .color(&color(a.color))
            .pos(Pos::new(HPos::Center, VPos::Center));
        area.draw(&Text::new(a.label.clone(), rel(c), text))?;
    }
    Ok(())
}

/// Draws a scale bar in the lower left corner of the plotting area: a
/// round length (1, 2 or 5 × 10^k m) near a fifth of the width of `x`,
/// labelled in metres.
fn scale_bar<DB: DrawingBackend>(
    chart: &mut ChartContext<DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    x: &Range<f64>,
) -> Result<(), PlotError> {
    let span = x.end - x.start;
    if !(span > 0.0 && span.is_finite()) {
        return Ok(());
    }
    let len = round_length(span / 5.0);
    // Exactly the decimals of a round length: `20 m`, `0.5 m`.
    let decimals = (-len.log10().floor()).max(0.0) as usize;
    let area = chart.plotting_area().strip_coord_spec();
    let (xr, yr) = area.get_pixel_range();
    let px = (len / span * (xr.end - xr.start) as f64).round() as i32;
    let (x0, y0) = (16, yr.end - yr.start - 18);
    let bar = BLACK.stroke_width(3);
    area.draw(&PathElement::new(vec![(x0, y0), (x0 + px, y0)], bar))?;
    for end in [x0, x0 + px] {
        area.draw(&PathElement::new(
            vec![(end, y0 - 5), (end, y0 + 5)],
            BLACK.stroke_width(2),
        ))?;
    }
    let text = font(14)
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Bottom));
    area.draw(&Text::new(
        format!("{len:.decimals$} m"),
        (x0 + px / 2, y0 - 7),
        text,
    ))?;
    Ok(())
}

/// The round length (1, 2 or 5 × 10^k) at most `target` and above half
/// of it, for a positive finite `target`.
fn round_length(target: f64) -> f64 {
    let decade = 10f64.powf(target.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&l| l <= target)
        .unwrap_or(decade)
}

/// The area centroid of the polygon `poly` (m), its vertices' mean when
/// its area vanishes, `None` when it has no vertex.
fn centroid(poly: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = poly.len();
    if n == 0 {
        return None;
    }
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for (k, p) in poly.iter().enumerate() {
        let q = poly[(k + 1) % n];
        let w = p.0 * q.1 - q.0 * p.1;
        a += w;
        cx += (p.0 + q.0) * w;
        cy += (p.1 + q.1) * w;
    }
    let scale = poly
        .iter()
        .map(|p| p.0.abs().max(p.1.abs()))
        .fold(0.0, f64::max);
    if a.abs() > 1e-12 * scale * scale {
        Some((cx / (3.0 * a), cy / (3.0 * a)))
    } else {
        let m = n as f64;
        Some((
            poly.iter().map(|p| p.0).sum::<f64>() / m,
            poly.iter().map(|p| p.1).sum::<f64>() / m,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::{centroid, round_length};

    #[test]
    fn scale_bars_are_round_lengths() {
        assert_eq!(round_length(23.0), 20.0);
        assert_eq!(round_length(7.0), 5.0);
        assert_eq!(round_length(1.0), 1.0);
        assert_eq!(round_length(0.19), 0.1);
        assert_eq!(round_length(480.0), 200.0);
    }

    #[test]
    fn centroid_of_an_l_is_its_area_centroid() {
        // An L of three unit squares: (0.5,0.5), (1.5,0.5), (0.5,1.5).
        let l = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ];
        let (x, y) = centroid(&l).unwrap();
        assert!((x - 2.5 / 3.0).abs() < 1e-12 && (y - 2.5 / 3.0).abs() < 1e-12);
        // Clockwise gives the same point.
        let mut cw = l;
        cw.reverse();
        let (xc, yc) = centroid(&cw).unwrap();
        assert!((xc - x).abs() < 1e-12 && (yc - y).abs() < 1e-12);
        // No area: the vertices' mean; no vertex: none.
        assert_eq!(centroid(&[(1.0, 1.0), (3.0, 1.0)]), Some((2.0, 1.0)));
        assert_eq!(centroid(&[]), None);
    }
}
