//! Line charts and plan views (one renderer, [`Xy`]): curves cut into
//! dashes in pixel space, equal aspect ratio for plans.

use super::axis::{bounds, is_log, log_bounds, mesh, y_area, Axis};
use super::legend::{legend, Rect};
use super::render::Figure;
use super::style::{
    color, finite, font, polygons, titled, DASHES, MARGIN, MARK, OBSTACLE, OBSTACLE_EDGE, X_AREA,
};
use super::{PlotError, Scale, Series, PALETTE};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;
use std::ops::Range;

/// A line chart or (with `plan`) a plan view.
pub(super) struct Xy<'a> {
    pub(super) title: &'a str,
    pub(super) x_label: &'a str,
    pub(super) y_label: &'a str,
    pub(super) series: &'a [Series],
    pub(super) obstacles: &'a [Vec<(f64, f64)>],
    /// Equal aspect ratio, padded x range.
    pub(super) plan: bool,
    /// A marker at each series' first point (plans only).
    pub(super) starts: bool,
    /// Ignored for plans (equal aspect needs linear axes).
    pub(super) x_scale: Scale,
    pub(super) y_scale: Scale,
    /// Vertical lines at these x values, labelled at the top.
    pub(super) marks: &'a [(f64, String)],
    /// Text labels at data points.
    pub(super) labels: &'a [(String, (f64, f64))],
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
        let (log, xlog) = (y.log, x.log);
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

        let ok = |p: &(f64, f64)| {
            p.0.is_finite() && p.1.is_finite() && (!log || p.1 > 0.0) && (!xlog || p.0 > 0.0)
        };
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
            let style = color(s.color).stroke_width(s.width.max(1));
            // Vary the dash also when the palette wraps around.
            let dash = DASHES[s.dash.unwrap_or(k + s.color / PALETTE.len()) % DASHES.len()];
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
            if self.plan && self.starts {
                if let Some(p) = s.points.iter().find(|p| ok(p)) {
                    chart.draw_series([
                        Circle::new(*p, 6, color(s.color).filled()),
                        Circle::new(*p, 6, BLACK.stroke_width(1)),
                    ])?;
                }
            }
        }
        let (x_range, y_range) = (chart.x_range(), chart.y_range());
        let mark_style = font(13).color(&MARK).pos(Pos::new(HPos::Left, VPos::Top));
        for (k, (x, label)) in self.marks.iter().enumerate() {
            if !x_range.contains(x) {
                continue;
            }
            let (top, bottom) = (y_range.end, y_range.start);
            let px: Vec<(i32, i32)> = [(*x, top), (*x, bottom)]
                .iter()
                .map(|p| {
                    let q = chart.backend_coord(p);
                    (q.0 - xr.start, q.1 - yr.start)
                })
                .collect();
            for piece in strokes(&px, Some((3.0, 4.0))) {
                plot.draw(&PathElement::new(piece, MARK.stroke_width(1)))?;
            }
            // Staggered so that close marks keep readable labels.
            let dy = 4 + 16 * (k % 3) as i32;
            plot.draw(&Text::new(
                label.clone(),
                (px[0].0 + 3, dy),
                mark_style.clone(),
            ))?;
            // The label's own box, as wide as its text (a long label such
            // as "t∞ (rest)" must keep the legend off it).
            let q = chart.backend_coord(&(*x, top));
            let width = plot.estimate_text_size(label, &mark_style)?.0 as i32;
            occupied.push((q.0, q.1, q.0 + 3 + width + 3, q.1 + dy + 16));
        }
        let label_style = font(14)
            .style(FontStyle::Bold)
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Bottom));
        // A label that would overlap one already written is left out.
        let mut written: Vec<Rect> = Vec::new();
        for (text, p) in self.labels {
            if ok(p) {
                let q = chart.backend_coord(p);
                let (w, h) = plot.estimate_text_size(text, &label_style)?;
                let b = (q.0 + 5, q.1 - 5 - h as i32, q.0 + 7 + w as i32, q.1 - 3);
                if written
                    .iter()
                    .any(|o| b.0 < o.2 && o.0 < b.2 && b.1 < o.3 && o.1 < b.3)
                {
                    continue;
                }
                written.push(b);
                let at = (q.0 - xr.start + 6, q.1 - yr.start - 4);
                plot.draw(&Text::new(text.clone(), at, label_style.clone()))?;
                occupied.push((q.0, q.1 - 20, q.0 + 60, q.1));
            }
        }
        if self.plan && self.starts && !self.series.is_empty() {
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
        let xlog = !self.plan && is_log(self.x_scale, self.points().map(|p| p.0));
        let all = || self.points().chain(self.obstacles.iter().flatten());
        let pad = if self.plan { 0.05 } else { 0.0 };
        let x0 = if xlog {
            log_bounds(self.points().filter(|p| p.1.is_finite()).map(|p| p.0), 0.05)
        } else {
            bounds(all().map(|p| p.0), pad)
        };
        let y0 = if log {
            log_bounds(
                self.points()
                    .filter(|p| p.0.is_finite() && (!xlog || p.0 > 0.0))
                    .map(|p| p.1),
                0.05,
            )
        } else {
            bounds(all().map(|p| p.1), 0.05)
        };
        let (mut x, mut y) = (
            Axis {
                range: x0.clone(),
                log: xlog,
            },
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
pub(super) fn equal_aspect(
    x: &Range<f64>,
    y: &Range<f64>,
    (pw, ph): (f64, f64),
) -> (Range<f64>, Range<f64>) {
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
