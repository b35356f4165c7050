//! Numbers for people: the one rounding rule of everything floebench prints
//! for reading (the report page, the verdicts, the check tables, the command
//! line's summaries). The data files (CSV, JSON) are never rounded: they
//! hold Rust's shortest round-trip form (`{}`, serde).

/// A computed number rounded for people: four significant digits.
///
/// - `0` (and `-0`) is `0`; non-finite values are written as Rust does
///   (`NaN`, `inf`, `-inf`);
/// - a magnitude in `[1e-3, 1e5)` is written in fixed notation with four
///   significant digits, and every integer digit from `1e4` on
///   (`0.005011`, `21.94`, `267.0`, `11462`);
/// - smaller or larger magnitudes in scientific notation with four
///   significant digits (`9.714e-16`, `5.155e5`).
///
/// Values quoted from a case file (`e`, `μ`, a threshold, an output time)
/// are printed as given (`{}`), not through this function.
pub fn fmt_num(v: f64) -> String {
    fmt_sig(v, 4)
}

/// `v` rounded to `sig` significant digits (1 to 4), by the rules of
/// [`fmt_num`] (fixed notation in `[1e-3, 1e5)`, every integer digit from
/// `1e4` on, scientific notation outside).
pub fn fmt_sig(v: f64, sig: usize) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let sig = sig.clamp(1, 4);
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let decimals = (sig as i32 - 1 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.decimals$}")
    } else {
        let decimals = sig - 1;
        format!("{v:.decimals$e}")
    }
}

/// A measured figure `v` with its spread `[lo, hi]` (e.g. the median of
/// repeated CPU times and their range), each printed only to the digits
/// the spread supports: the last digit printed is at the decade of the
/// spread's width `hi − lo`, the same for all three (at least one
/// significant digit of the largest, at most four; four when the width is
/// zero, as [`fmt_num`]). The notation (fixed or scientific, by the rule of
/// [`fmt_num`]) is that of the largest of the three, for all three.
/// Returns `(v, lo, hi)` rounded alike.
pub fn fmt_spread(v: f64, lo: f64, hi: f64) -> (String, String, String) {
    let w = hi - lo;
    let big = v.abs().max(lo.abs()).max(hi.abs());
    if !(w > 0.0 && w.is_finite() && big.is_finite()) {
        return (fmt_num(v), fmt_num(lo), fmt_num(hi));
    }
    let top = big.log10().floor() as i32;
    let last = (w.log10().floor() as i32).clamp(top - 3, top);
    let one = |x: f64| -> String {
        if x == 0.0 {
            "0".into()
        } else if (1e-3..1e5).contains(&big) {
            let decimals = (-last).max(0) as usize;
            format!("{x:.decimals$}")
        } else {
            let sig = (x.abs().log10().floor() as i32 - last + 1).clamp(1, 4) as usize;
            fmt_sig(x, sig)
        }
    };
    (one(v), one(lo), one(hi))
}

/// `v`, a part of a measured figure whose spread has the width `width`,
/// printed to the digits that spread supports (see [`fmt_spread`]).
pub fn fmt_within(v: f64, width: f64) -> String {
    fmt_spread(v, v - 0.5 * width, v + 0.5 * width).0
}

#[cfg(test)]
mod tests {
    use super::{fmt_num, fmt_spread, fmt_within};

    #[test]
    fn four_significant_digits() {
        let cases = [
            (0.0, "0"),
            (-0.0, "0"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
            (0.005011234, "0.005011"),
            (21.9449, "21.94"),
            (267.0, "267.0"),
            (-1.0, "-1.000"),
            (11462.4, "11462"),
            (9.714045e-16, "9.714e-16"),
            (515512.0, "5.155e5"),
            (-2.9104e-11, "-2.910e-11"),
        ];
        for (v, s) in cases {
            assert_eq!(fmt_num(v), s, "{v}");
        }
    }

    #[test]
    fn spread_digits() {
        let p = |v, lo, hi| {
            let (a, b, c) = fmt_spread(v, lo, hi);
            format!("{a} ({b}-{c})")
        };
        assert_eq!(p(0.04873, 0.0475, 0.0512), "0.049 (0.048-0.051)");
        assert_eq!(p(2.345, 2.2, 2.5), "2.3 (2.2-2.5)");
        assert_eq!(p(2.345, 2.345, 2.345), "2.345 (2.345-2.345)");
        assert_eq!(p(51.3, 12.0, 90.0), "51 (12-90)");
        assert_eq!(p(1.234e-5, 1.2e-5, 1.3e-5), "1.2e-5 (1.2e-5-1.3e-5)");
        assert_eq!(p(9.9e-4, 8.1e-4, 1.02e-3), "0.0010 (0.0008-0.0010)");
        assert_eq!(fmt_within(0.01234, 0.003), "0.012");
    }
}
