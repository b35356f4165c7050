//! The spread of a figure measured several times (the CPU time of the
//! repeats of a run): median, range and, from four repeats on, the
//! interquartile range.
//!
//! Quantiles interpolate linearly between the sorted samples (the
//! "type 7" definition: the `p`-quantile of `n` sorted samples is at the
//! fractional index `p (n − 1)`), so the median of an even count is the
//! mean of the two middle samples. Two measured times are *tied*
//! ([`Spread::tied_with`]) when the repeats cannot tell them apart: the
//! 95 % confidence intervals of their medians overlap
//! ([`Spread::median_interval`], distribution-free: order statistics; the
//! range for up to 7 samples), or their medians differ by less than
//! [`SPEED_MARGIN`], what the same run's median moves between identical
//! batches. One run gives no spread: it is tied with nothing.

use serde::Serialize;

/// Repeats from which the interquartile range is given.
pub const IQR_FROM: usize = 4;

/// Two medians closer than this ratio are tied whatever their spreads: the
/// median CPU time of one (case, formulation) moves by up to about this
/// much between identical `compare` runs on a shared machine, a spread
/// measured within one batch does not see it (docs of
/// [`crate::run::batch::TOP_UP_CPU`]; docs/physics.md §6.6 gives the measurement).
pub const SPEED_MARGIN: f64 = 1.25;

/// The spread of repeated measurements of one figure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spread {
    /// The samples, in measurement order.
    pub samples: Vec<f64>,
    /// Median.
    pub median: f64,
    /// Smallest sample.
    pub min: f64,
    /// Largest sample.
    pub max: f64,
    /// First and third quartiles, from [`IQR_FROM`] samples on.
    pub iqr: Option<(f64, f64)>,
    /// The 95 % confidence interval of the median
    /// ([`Spread::median_interval`]).
    pub median_ci: (f64, f64),
}

impl Spread {
    /// The spread of `samples` (non-finite samples are kept in `samples`
    /// but not in the statistics); all statistics are NaN without a finite
    /// sample.
    pub fn of(samples: &[f64]) -> Spread {
        let mut s: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
        s.sort_by(f64::total_cmp);
        let q = |p: f64| -> f64 {
            if s.is_empty() {
                return f64::NAN;
            }
            let x = p * (s.len() - 1) as f64;
            let (i, f) = (x.floor() as usize, x - x.floor());
            if i + 1 < s.len() {
                s[i] + f * (s[i + 1] - s[i])
            } else {
                s[i]
            }
        };
        // Distribution-free: the median lies between the order statistics
        // of ranks k and n − 1 − k (from 0) with probability about 95 % for
        // k = ⌊(n − 1.96 √n) / 2⌋ (normal approximation of the binomial);
        // k = 0 (the range) up to 7 samples.
        let median_ci = match s.len() {
            0 => (f64::NAN, f64::NAN),
            n => {
                let k = ((n as f64 - 1.96 * (n as f64).sqrt()) / 2.0)
                    .floor()
                    .max(0.0) as usize;
                (s[k], s[n - 1 - k])
            }
        };
        Spread {
            median_ci,
            samples: samples.to_vec(),
            median: q(0.5),
            min: q(0.0),
            max: q(1.0),
            iqr: (s.len() >= IQR_FROM).then(|| (q(0.25), q(0.75))),
        }
    }

    /// Number of samples.
    pub fn count(&self) -> usize {
        self.samples.len()
    }

    /// Whether the ranges of `self` and `other` overlap.
    pub fn overlaps(&self, other: &Spread) -> bool {
        self.min <= other.max && other.min <= self.max
    }

    /// The 95 % confidence interval of the median: the order statistics of
    /// ranks `k` and `n − 1 − k` (from 0) for `k = ⌊(n − 1.96 √n)/2⌋`, the
    /// range up to 7 samples (201 samples: ranks 86 and 114).
    pub fn median_interval(&self) -> (f64, f64) {
        self.median_ci
    }

    /// Whether the repeats cannot tell `self` and `other` apart: the
    /// confidence intervals of their medians
    /// ([`Spread::median_interval`]) overlap, or their medians are within
    /// [`SPEED_MARGIN`] of each other. Never with fewer than two samples on
    /// either side: one run gives no spread, so no tie is called.
    pub fn tied_with(&self, other: &Spread) -> bool {
        if self.count() < 2 || other.count() < 2 {
            return false;
        }
        let ((a0, a1), (b0, b1)) = (self.median_ci, other.median_ci);
        let (lo, hi) = if self.median <= other.median {
            (self.median, other.median)
        } else {
            (other.median, self.median)
        };
        (a0 <= b1 && b0 <= a1) || hi < SPEED_MARGIN * lo
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate() {
        let s = Spread::of(&[3.0, 1.0, 2.0]);
        assert_eq!((s.median, s.min, s.max, s.iqr), (2.0, 1.0, 3.0, None));
        let s = Spread::of(&[4.0, 1.0, 3.0, 2.0]);
        assert_eq!(s.median, 2.5);
        assert_eq!(s.iqr, Some((1.75, 3.25)));
        assert!(Spread::of(&[1.0, 2.0]).overlaps(&Spread::of(&[2.0, 3.0])));
        assert!(!Spread::of(&[1.0, 2.0]).overlaps(&Spread::of(&[2.5, 3.0])));
        assert!(Spread::of(&[]).median.is_nan());
        // Disjoint ranges, medians 1.5 and 2.0 (ratio 1.33): apart.
        assert!(!Spread::of(&[1.4, 1.5, 1.6]).tied_with(&Spread::of(&[1.9, 2.0, 2.1])));
        // Disjoint ranges, medians 1.5 and 1.7 (ratio 1.13): tied.
        assert!(Spread::of(&[1.45, 1.5, 1.55]).tied_with(&Spread::of(&[1.65, 1.7, 1.75])));
        // Up to 7 samples the interval is the range; from 8 on the
        // outliers fall outside it.
        assert_eq!(Spread::of(&[3.0, 1.0, 2.0]).median_interval(), (1.0, 3.0));
        let wide: Vec<f64> = (0..8).map(f64::from).collect();
        assert_eq!(Spread::of(&wide).median_interval(), (1.0, 6.0));
        let mut a: Vec<f64> = vec![1.0; 200];
        a.push(9.0);
        let (a, b) = (Spread::of(&a), Spread::of(&[3.0; 201]));
        assert_eq!(a.median_interval(), (1.0, 1.0));
        assert!(a.overlaps(&b) && !a.tied_with(&b));
        // One run each: no spread, no tie, even within the margin.
        assert!(!Spread::of(&[1.0]).tied_with(&Spread::of(&[1.1])));
        assert!(!Spread::of(&[1.0]).tied_with(&Spread::of(&[1.0, 1.1, 1.2])));
    }
}
