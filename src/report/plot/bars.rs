//! Stacked bar charts: one bar per category, one segment per stage, the
//! values printed inside the segments, the totals above the bars and a
//! note (e.g. the ratio to the fastest) above each total.

use super::axis::{is_log, log_bounds, mesh, y_area, Axis, Fmt};
use super::legend::legend_row;
use super::render::Figure;
use super::style::{color, font, titled, MARGIN, X_AREA};
use super::{PlotError, StackedBars};
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;
use std::ops::Range;

/// A stacked bar chart.
pub(super) struct Bars<'a>(pub(super) StackedBars<'a>);

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
                if let Some(note) = c.notes.get(i).filter(|n| !n.is_empty()) {
                    let style = value_font
                        .color(&BLACK)
                        .pos(Pos::new(HPos::Center, VPos::Bottom));
                    chart.draw_series(std::iter::once(
                        EmptyElement::at((xi, total)) + Text::new(note.clone(), (0, -22), style),
                    ))?;
                }
            }
        }
        Ok(())
    }
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
            let room = if self.0.notes.is_empty() { 0.12 } else { 0.2 };
            let hi = (hi + room * (hi - lo).max(1.0)).max(lo + 1.0);
            Axis {
                range: 0.999 * 10f64.powf(lo)..10f64.powf(hi),
                log: true,
            }
        } else {
            let top = totals.iter().copied().fold(0.0, f64::max);
            let room = if self.0.notes.is_empty() { 1.12 } else { 1.2 };
            Axis::linear(0.0..if top > 0.0 { room * top } else { 1.0 })
        };
        let w = y_area(&area, y.labels())?;
        let base = if y.log { y.range.start } else { 0.0 };
        self.body(&area, y, w, base)
    }
}
