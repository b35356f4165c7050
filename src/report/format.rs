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

/// Significant digits of a timing measured once (no spread to say how
/// many its repeats would share): CPU times of one thread vary by a few
/// per cent from run to run, so two.
pub const TIMING_DIGITS: usize = 2;

/// A timing measured once, s (or a ratio of such): [`TIMING_DIGITS`]
/// significant digits, by the rules of [`fmt_num`] (`2.4e-4`, `0.16`,
/// `12`).
pub fn fmt_timing(v: f64) -> String {
    fmt_sig(v, TIMING_DIGITS)
}

/// `a` and `b` rounded by [`fmt_num`], or, where that prints them alike
/// though they differ, in scientific notation with the fewest digits (up to
/// 17) that tell them apart: a printed verdict must agree with the numbers
/// printed beside it (measured `1.000` against a tolerance `1.000`).
pub fn fmt_apart(a: f64, b: f64) -> (String, String) {
    let (fa, fb) = (fmt_num(a), fmt_num(b));
    if fa != fb || a == b || !a.is_finite() || !b.is_finite() {
        return (fa, fb);
    }
    (4..=17)
        .map(|d| (format!("{a:.d$e}"), format!("{b:.d$e}")))
        .find(|(x, y)| x != y)
        .unwrap_or((format!("{a:e}"), format!("{b:e}")))
}

/// Measured figures that share one spread of width `width` (e.g. the
/// median, range and quartiles of repeated CPU times, or the parts of a
/// measured total), each printed only to the digits the spread supports:
/// the last digit printed is at the decade of `width`, the same for all (at
/// least one significant digit of the largest, at most four; as
/// [`fmt_timing`] when the width is zero or unknown: a single timing). The notation (fixed or scientific,
/// by the rule of [`fmt_num`]) is that of the largest, for all.
pub fn fmt_measured(values: &[f64], width: f64) -> Vec<String> {
    let big = values
        .iter()
        .map(|v| v.abs())
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    if !(width > 0.0 && width.is_finite() && big > 0.0) {
        return values.iter().map(|&v| fmt_timing(v)).collect();
    }
    let top = big.log10().floor() as i32;
    let last = (width.log10().floor() as i32).clamp(top - 3, top);
    let fixed = (1e-3..1e5).contains(&big);
    values
        .iter()
        .map(|&x| {
            if x == 0.0 || !x.is_finite() {
                fmt_num(x)
            } else if fixed {
                let decimals = (-last).max(0) as usize;
                format!("{x:.decimals$}")
            } else {
                let sig = (x.abs().log10().floor() as i32 - last + 1).clamp(1, 4) as usize;
                fmt_sig(x, sig)
            }
        })
        .collect()
}

/// A measured figure `v` with its spread `[lo, hi]`, rounded alike
/// ([`fmt_measured`] with the width `hi − lo`): `(v, lo, hi)`.
pub fn fmt_spread(v: f64, lo: f64, hi: f64) -> (String, String, String) {
    let mut s = fmt_measured(&[v, lo, hi], hi - lo).into_iter();
    let mut next = || s.next().unwrap_or_default();
    (next(), next(), next())
}

/// `rows` (the header first) as aligned plain text: each column but the last
/// padded to its widest cell (in characters) and two spaces, each line's
/// trailing blanks trimmed, one line per row.
pub fn aligned_table(rows: &[Vec<String>]) -> String {
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0);
    let mut width = vec![0usize; cols];
    for row in rows {
        for (w, c) in width.iter_mut().zip(row) {
            *w = (*w).max(c.chars().count());
        }
    }
    let mut out = String::new();
    for row in rows {
        let mut s = String::new();
        for (k, c) in row.iter().enumerate() {
            if k + 1 == row.len() {
                s.push_str(c);
            } else {
                s.push_str(&format!("{c:<w$}  ", w = width[k]));
            }
        }
        out.push_str(s.trim_end());
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{fmt_measured, fmt_num, fmt_spread};

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
        // No spread (one run): two significant digits.
        assert_eq!(p(2.345, 2.345, 2.345), "2.3 (2.3-2.3)");
        assert_eq!(
            fmt_measured(&[2.365e-4, 3.582e-5], 0.0),
            ["2.4e-4", "3.6e-5"]
        );
        assert_eq!(p(51.3, 12.0, 90.0), "51 (12-90)");
        assert_eq!(p(1.234e-5, 1.2e-5, 1.3e-5), "1.2e-5 (1.2e-5-1.3e-5)");
        assert_eq!(p(9.9e-4, 8.1e-4, 1.02e-3), "0.0010 (0.0008-0.0010)");
        assert_eq!(fmt_measured(&[0.01234, 4e-4], 0.003), ["0.012", "0.000"]);
        assert_eq!(fmt_measured(&[3e-4, 8.3e-4], 1e-4), ["3e-4", "8e-4"]);
    }
}
