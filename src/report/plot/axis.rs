//! Value axes: data bounds, the choice of a log scale, tick positions and
//! compact tick labels, and the mesh (grid, axes, labels).

use super::style::{font, TICKS};
use super::{PlotError, Scale};
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::ops::Range;

/// Bounds of the finite values, padded: by `pad` × span, and to a non-empty
/// range when all values are equal (or there are none).
pub(super) fn bounds(values: impl Iterator<Item = f64>, pad: f64) -> Range<f64> {
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
pub(super) fn log_bounds(values: impl Iterator<Item = f64>, pad: f64) -> Range<f64> {
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
pub(super) fn is_log(scale: Scale, values: impl Iterator<Item = f64>) -> bool {
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
pub(super) struct Fmt {
    /// Approximate tick step (linear axes) or `None` (log axes: 3 significant digits).
    step: Option<f64>,
    /// Scientific notation for the whole axis, or `None` to decide per value.
    sci: Option<bool>,
}

impl Fmt {
    /// For a linear axis over `r`.
    pub(super) fn linear(r: &Range<f64>) -> Self {
        let mag = r.start.abs().max(r.end.abs());
        let step = (r.end - r.start) / TICKS as f64;
        Fmt {
            step: (step > 0.0).then_some(step),
            sci: Some(!(1e-3..1e5).contains(&mag)),
        }
    }

    /// For a log axis.
    pub(super) fn log() -> Self {
        Fmt {
            step: None,
            sci: None,
        }
    }

    /// The label of `v`.
    pub(super) fn fmt(&self, v: f64) -> String {
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
pub(super) fn y_area<DB: DrawingBackend>(
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
pub(super) struct Axis {
    pub(super) range: Range<f64>,
    pub(super) log: bool,
}

impl Axis {
    /// A linear axis.
    pub(super) fn linear(range: Range<f64>) -> Self {
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
    pub(super) fn fmt(&self) -> Fmt {
        if self.log {
            Fmt::log()
        } else {
            Fmt::linear(&self.range)
        }
    }

    /// The tick labels.
    pub(super) fn labels(&self) -> impl Iterator<Item = String> {
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
    /// the decades when there are too few decades in the range, or every
    /// k-th decade when there are too many.
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
        if best.is_empty() {
            // Too many decades: every k-th one, enough to stay within `max`.
            let stride = ((b - a + 1) as usize).div_ceil(max.max(1)).max(1);
            best = (a..=b)
                .filter(|e| e.rem_euclid(stride as i32) == 0)
                .map(|e| 10f64.powi(e))
                .filter(|v| (self.range.start..=self.range.end).contains(v))
                .collect();
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
pub(super) fn mesh<DB, X, Y>(
    chart: &mut ChartContext<DB, Cartesian2d<X, Y>>,
    x: (&str, &dyn Fn(&f64) -> String),
    y: (&str, &dyn Fn(&f64) -> String),
    x_grid: bool,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    mesh_with_ticks(chart, x, y, x_grid, TICKS)
}

/// [`mesh`] with at most `x_ticks` tick labels on the x axis (narrow panels).
pub(super) fn mesh_with_ticks<DB, X, Y>(
    chart: &mut ChartContext<DB, Cartesian2d<X, Y>>,
    (x_label, xf): (&str, &dyn Fn(&f64) -> String),
    (y_label, yf): (&str, &dyn Fn(&f64) -> String),
    x_grid: bool,
    x_ticks: usize,
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
        .x_labels(x_ticks)
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
    fn a_log_axis_over_many_decades_ticks_every_few_decades() {
        let axis = Axis {
            range: 1e-17..1.0,
            log: true,
        };
        let ticks = axis.key_points(TICKS);
        assert!(ticks.len() >= 2 && ticks.len() <= TICKS, "{ticks:?}");
        assert!(ticks.windows(2).all(|w| w[1] / w[0] > 99.9), "{ticks:?}");
    }

    #[test]
    fn degenerate_bounds_are_padded() {
        assert_eq!(bounds([].into_iter(), 0.05), 0.0..1.0);
        assert_eq!(bounds([2.0, 2.0].into_iter(), 0.05), 1.8..2.2);
        assert_eq!(bounds([0.0, f64::NAN].into_iter(), 0.05), -1.0..1.0);
    }
}
