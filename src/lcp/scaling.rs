//! Scaling by powers of two, exact in binary floating point: the largest
//! magnitude of a vector, `x · 2^e` and the exponent of the power of two
//! nearest a number. Lemke's method scales M, q and d by them (see
//! [`super::lemke`]); the compensated dot products of [`super`] scale by
//! them near the top of the range.

/// Largest magnitude of `v` (0 for an empty slice; NaN entries are skipped).
pub(crate) fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |a, x| a.max(x.abs()))
}

/// Largest magnitude and whether every entry is finite, in one pass.
///
/// The same number as [`max_abs`] (NaN entries skipped: a comparison with
/// NaN is false), in four independent running maxima so that the
/// comparisons do not wait on each other.
pub(crate) fn max_abs_finite(v: &[f64]) -> (f64, bool) {
    let mut m = [0.0_f64; 4];
    let mut finite = true;
    let mut chunks = v.chunks_exact(4);
    for c in &mut chunks {
        for (ml, &x) in m.iter_mut().zip(c) {
            let a = x.abs();
            *ml = if a > *ml { a } else { *ml };
            finite &= a < f64::INFINITY;
        }
    }
    for &x in chunks.remainder() {
        let a = x.abs();
        m[0] = if a > m[0] { a } else { m[0] };
        finite &= a < f64::INFINITY;
    }
    let (a, b) = (m[0].max(m[1]), m[2].max(m[3]));
    (a.max(b), finite)
}

/// `2^e` for `-1022 <= e <= 1023` (a normal number), else `None`.
pub(crate) fn exp2_factor(e: i32) -> Option<f64> {
    if (-1022..=1023).contains(&e) {
        Some(f64::from_bits(((e + 1023) as u64) << 52))
    } else {
        None
    }
}

/// `x · 2^e`, exact unless the result under- or overflows, for any `e`.
pub(crate) fn ldexp(mut x: f64, mut e: i32) -> f64 {
    const STEP: i32 = 1000;
    let big = f64::from_bits(((STEP + 1023) as u64) << 52);
    let small = f64::from_bits(((1023 - STEP) as u64) << 52);
    while e > STEP {
        x *= big;
        e -= STEP;
        if !x.is_finite() || x == 0.0 {
            return x;
        }
    }
    while e < -STEP {
        x *= small;
        e += STEP;
        if x == 0.0 || !x.is_finite() {
            return x;
        }
    }
    match exp2_factor(e) {
        Some(f) => x * f,
        None => x,
    }
}

/// Binary exponent `e` of the power of two nearest to `x` in log scale
/// (`2^e ≤ √2·x` and `x < √2·2^e`), computed exactly from the bits, over the
/// whole range including subnormal `x`; 0 for zero or non-finite `x`.
pub fn pow2_exponent(x: f64) -> i32 {
    if !(x > 0.0 && x.is_finite()) {
        return 0;
    }
    let (mut y, mut shift) = (x, 0);
    if y < f64::MIN_POSITIVE {
        y *= f64::from_bits(((64 + 1023) as u64) << 52); // 2^64: now normal
        shift = 64;
    }
    let bits = y.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i32 - 1023;
    let mantissa = f64::from_bits((bits & ((1u64 << 52) - 1)) | (1023u64 << 52)); // in [1, 2)
    let e = if mantissa >= std::f64::consts::SQRT_2 {
        e + 1
    } else {
        e
    };
    e - shift
}
