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
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::fmt_num;

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
}
