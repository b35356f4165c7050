//! The compensated arithmetic of the LCP solvers: error-free sums and
//! products, Dot2 dot products (Ogita, Rump & Oishi 2005), `w = M z + q`
//! with them, and the natural-map residual's scale and norm. Every solver
//! judges its candidates by these numbers (see [`super::residual()`]).

use super::scaling;

/// Floor of the denominator of [`super::residual()`]: `f64::EPSILON`.
///
/// When `‖q‖₂ <= RESIDUAL_DENOMINATOR_FLOOR` the residual is effectively an
/// absolute one (divided by `f64::EPSILON`), as in Siconos'
/// `lcp_compute_error`; this only happens for an (almost) zero `q`, whose
/// solution `z = 0` has residual exactly 0.
pub const RESIDUAL_DENOMINATOR_FLOOR: f64 = f64::EPSILON;

/// `M z + q` without size checks; callers guarantee the sizes.
///
/// Each entry is a compensated dot product (Ogita, Rump & Oishi 2005,
/// "Dot2"): as accurate as if computed in twice the working precision, so
/// that the cancellation in `M z` for large `z` cannot hide a negative `w_i`
/// from the acceptance test of [`super::solve()`].
pub(crate) fn w_unchecked(m: &[f64], q: &[f64], z: &[f64]) -> Vec<f64> {
    let mut w = vec![0.0; q.len()];
    w_into(m, q, z, &mut w, false);
    w
}

/// [`w_unchecked`] into a given buffer (`w.len() == q.len()`), without
/// allocation.
///
/// The CPU's fused multiply–add is detected once per call rather than once
/// per row (the rows of a small LCP are a few entries long); every entry is
/// [`dot2_plus`] of its row. When the caller knows `M` to be finite
/// (`m_finite`), up to [`SUPPORT_MAX_N`] unknowns the sums run over the
/// support of `z` only (its non-zero entries, listed once per call): a
/// term `M_ij · 0` of a finite `M_ij` adds exact zeros to both the sum and
/// its compensation, so the result is the same number (at most the sign of
/// a zero `w_i` differs), for the cost of the support's columns only — a
/// candidate of Lemke's method has at most n of its 2n + 1 variables
/// basic, and on the contact LCPs about a third of its `z` is non-zero.
/// (A non-finite `M_ij` times 0 is NaN, which the full sum keeps.)
pub(crate) fn w_into(m: &[f64], q: &[f64], z: &[f64], w: &mut [f64], m_finite: bool) {
    let n = q.len();
    if n == 0 {
        return;
    }
    if m_finite && n <= SUPPORT_MAX_N && z.len() == n {
        let mut idx = [0u16; SUPPORT_MAX_N];
        let mut k = 0;
        for (j, &v) in z.iter().enumerate() {
            idx[k] = j as u16;
            k += usize::from(v != 0.0);
        }
        let support = &idx[..k];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("fma") {
                // SAFETY: the CPU supports FMA, checked just above.
                unsafe { w_support_fma(m, q, z, support, w) };
                return;
            }
        }
        for ((row, &qi), wi) in m.chunks_exact(n).zip(q.iter()).zip(w.iter_mut()) {
            let v = dot2_support(row, z, support, qi, two_prod);
            *wi = if v.is_finite() {
                v
            } else {
                dot2_plus(row, z, qi)
            };
        }
        return;
    }
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports FMA, checked just above.
            unsafe { w_into_fma(m, q, z, w) };
            return;
        }
    }
    for ((row, &qi), wi) in m.chunks_exact(n).zip(q.iter()).zip(w.iter_mut()) {
        *wi = dot2_plus(row, z, qi);
    }
}

/// Largest n for which [`w_into`] sums over the support of `z` (its index
/// list lives on the stack).
pub(crate) const SUPPORT_MAX_N: usize = 64;

/// [`w_into`] over the support, compiled with FMA (the products' errors are
/// `fma(a, b, −ab)`, as in [`dot2_fma`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn w_support_fma(m: &[f64], q: &[f64], z: &[f64], support: &[u16], w: &mut [f64]) {
    let n = q.len();
    for ((row, &qi), wi) in m.chunks_exact(n).zip(q.iter()).zip(w.iter_mut()) {
        let v = dot2_support(row, z, support, qi, |a, b| {
            let h = a * b;
            (h, a.mul_add(b, -h))
        });
        *wi = if v.is_finite() {
            v
        } else {
            dot2_plus(row, z, qi)
        };
    }
}

/// [`dot2_body`] with one lane and unit scalings, over the terms `support`
/// only: `Σ_{j ∈ support} x_j y_j + c`, the same operations in the same
/// order as the full sum without its zero terms. Non-finite when the
/// unscaled sum overflows (the caller then takes [`dot2_plus`]).
#[inline(always)]
fn dot2_support(
    x: &[f64],
    y: &[f64],
    support: &[u16],
    c: f64,
    prod: impl Fn(f64, f64) -> (f64, f64),
) -> f64 {
    let (mut p, mut s) = (c, 0.0_f64);
    for &j in support {
        let j = usize::from(j);
        let (h, r) = prod(x[j], y[j]);
        let (np, t) = two_sum(p, h);
        p = np;
        s += t + r;
    }
    p + s
}

/// [`w_into`] compiled with FMA: each row by [`dot2_fma`] (what
/// [`dot2_plus`] computes on such a CPU), falling back to [`dot2_plus`] for
/// a row whose fast result is not finite (its scaled or non-finite path).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn w_into_fma(m: &[f64], q: &[f64], z: &[f64], w: &mut [f64]) {
    let n = q.len();
    for ((row, &qi), wi) in m.chunks_exact(n).zip(q.iter()).zip(w.iter_mut()) {
        let v = dot2_fma::<1>(row, z, qi, 1.0, 1.0, 1.0);
        *wi = if v.is_finite() {
            v
        } else {
            dot2_plus(row, z, qi)
        };
    }
}

/// Error-free transformation `a + b = s + e`.
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Error-free product `a b = h + r` by Dekker's splitting (Ogita, Rump &
/// Oishi 2005, TwoProduct): exact without a hardware fused multiply–add,
/// which `f64::mul_add` would emulate in software on a baseline x86-64 target.
pub(crate) fn two_prod(a: f64, b: f64) -> (f64, f64) {
    const SPLIT: f64 = 134_217_729.0; // 2^27 + 1
    let h = a * b;
    let split = |x: f64| {
        let c = SPLIT * x;
        let hi = c - (c - x);
        (hi, x - hi)
    };
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let r = al * bl - (((h - ah * bh) - al * bh) - ah * bl);
    (h, r)
}

/// `Σ x_i y_i + c` with Dot2 compensation. Near the top of the
/// floating-point range (where Dekker's splitting overflows) the data are
/// scaled by powers of two first, exactly; non-finite only if the data are
/// or the result overflows.
pub(crate) fn dot2_plus(x: &[f64], y: &[f64], c: f64) -> f64 {
    dot2_plus_lanes::<1>(x, y, c)
}

/// [`dot2_plus`] as four interleaved Dot2 sums combined error-free at the
/// end: the same accuracy (as if in twice the working precision) with four
/// times the instruction-level parallelism, but other last bits. For the
/// basis solves of [`super::pivoting`]; the residual of the driver keeps
/// [`dot2_plus`].
pub(crate) fn dot2_plus_fast(x: &[f64], y: &[f64], c: f64) -> f64 {
    dot2_plus_lanes::<4>(x, y, c)
}

/// [`dot2_plus`] with `L` interleaved sums.
fn dot2_plus_lanes<const L: usize>(x: &[f64], y: &[f64], c: f64) -> f64 {
    let v = dot2_plus_scaled::<L>(x, y, c, 1.0, 1.0, 1.0);
    if v.is_finite() {
        return v;
    }
    if !(x.iter().chain(y.iter()).all(|v| v.is_finite()) && c.is_finite()) {
        return x.iter().zip(y.iter()).map(|(a, b)| a * b).sum::<f64>() + c;
    }
    // Scale x and y to magnitudes near 1 (powers of two: exact), and c by
    // the product of the two scalings, then undo.
    let ex = scaling::pow2_exponent(scaling::max_abs(x));
    let ey = scaling::pow2_exponent(scaling::max_abs(y));
    let fx = scaling::ldexp(1.0, -ex);
    let fy = scaling::ldexp(1.0, -ey);
    if !(fx.is_normal() && fy.is_normal()) {
        return x.iter().zip(y.iter()).map(|(a, b)| a * b).sum::<f64>() + c;
    }
    let v = dot2_plus_scaled::<L>(
        x,
        y,
        scaling::ldexp(scaling::ldexp(c, -ex), -ey),
        fx,
        fy,
        1.0,
    );
    scaling::ldexp(scaling::ldexp(v, ex), ey)
}

/// `Σ (fx x_i)(fy y_i) + fc c` with Dot2 compensation in `L` interleaved
/// sums (`fx`, `fy`, `fc` powers of two). On a CPU with fused
/// multiply–add the error of each product is one `fma` instead of Dekker's
/// splitting: the same exact error (both are error-free for products that
/// neither overflow nor fall into the subnormal range), at a third of the
/// cost.
fn dot2_plus_scaled<const L: usize>(
    x: &[f64],
    y: &[f64],
    c: f64,
    fx: f64,
    fy: f64,
    fc: f64,
) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports FMA, checked just above.
            return unsafe { dot2_fma::<L>(x, y, c, fx, fy, fc) };
        }
    }
    dot2_body::<L>(x, y, c, fx, fy, fc, two_prod)
}

/// [`dot2_plus_scaled`] compiled with FMA, whose products' errors are
/// `fma(a, b, −ab)`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn dot2_fma<const L: usize>(x: &[f64], y: &[f64], c: f64, fx: f64, fy: f64, fc: f64) -> f64 {
    dot2_body::<L>(x, y, c, fx, fy, fc, |a, b| {
        let h = a * b;
        (h, a.mul_add(b, -h))
    })
}

/// The Dot2 loop with the error-free product `prod`: lane `l` sums the
/// terms `i ≡ l (mod L)` (lane 0 also `c` and the tail), and the lanes are
/// added error-free in order. With `L = 1` it is Ogita, Rump & Oishi's
/// Dot2 as written.
#[inline(always)]
fn dot2_body<const L: usize>(
    x: &[f64],
    y: &[f64],
    c: f64,
    fx: f64,
    fy: f64,
    fc: f64,
    prod: impl Fn(f64, f64) -> (f64, f64),
) -> f64 {
    let (mut p, mut s) = ([0.0_f64; L], [0.0_f64; L]);
    p[0] = c * fc;
    let len = x.len().min(y.len());
    let whole = len - len % L;
    for (xc, yc) in x[..whole].chunks_exact(L).zip(y[..whole].chunks_exact(L)) {
        for l in 0..L {
            let (h, r) = prod(xc[l] * fx, yc[l] * fy);
            let (np, t) = two_sum(p[l], h);
            p[l] = np;
            s[l] += t + r;
        }
    }
    for (&a, &b) in x[whole..len].iter().zip(&y[whole..len]) {
        let (h, r) = prod(a * fx, b * fy);
        let (np, t) = two_sum(p[0], h);
        p[0] = np;
        s[0] += t + r;
    }
    let (mut pt, mut st) = (p[0], s[0]);
    for l in 1..L {
        let (np, t) = two_sum(pt, p[l]);
        pt = np;
        st += t + s[l];
    }
    pt + st
}

/// [`super::residual()`] when `w = M z + q` is already known (no allocation).
pub(crate) fn residual_with_w(q: &[f64], z: &[f64], w: &[f64]) -> f64 {
    ResidualScale::of(q).residual(z, w)
}

/// The part of [`super::residual()`] that depends on `q` only (its denominator and
/// whether `q` is finite), computed once for the many candidates of a
/// solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ResidualScale {
    den: f64,
    q_finite: bool,
}

impl ResidualScale {
    /// The scale of the LCPs with this `q`.
    pub(crate) fn of(q: &[f64]) -> Self {
        Self {
            den: norm2(q).max(RESIDUAL_DENOMINATOR_FLOOR),
            q_finite: q.iter().all(|x| x.is_finite()),
        }
    }

    /// [`ResidualScale::of`] given `qmax = max|q_i|` (as
    /// [`scaling::max_abs`] computes it, NaN entries skipped) and whether `q`
    /// is finite: the same scale, without reading `q` for them again.
    pub(crate) fn with_max(q: &[f64], qmax: f64, q_finite: bool) -> Self {
        Self {
            den: scaled_norm(qmax, q.len(), |i| q[i]).max(RESIDUAL_DENOMINATOR_FLOOR),
            q_finite,
        }
    }

    /// [`super::residual()`] of `z` with `w = M z + q` known: `INFINITY` if the sizes
    /// differ or anything is non-finite. The same arithmetic as [`norm2`]
    /// (largest magnitude first, then the scaled sum of squares), with the
    /// finiteness check folded into the first pass ([`scaled_norm`]).
    pub(crate) fn residual(&self, z: &[f64], w: &[f64]) -> f64 {
        if z.len() != w.len() || !self.q_finite {
            return f64::INFINITY;
        }
        let mut s = 0.0_f64;
        let mut finite = true;
        for (a, b) in z.iter().zip(w) {
            finite &= a.is_finite() & b.is_finite();
            s = s.max(a.min(*b).abs());
        }
        if !finite {
            return f64::INFINITY;
        }
        let num = scaled_norm(s, z.len(), |i| z[i].min(w[i]));
        let r = num / self.den;
        if r.is_nan() {
            f64::INFINITY
        } else {
            r
        }
    }
}

/// Euclidean norm, scaled by the largest magnitude so that it neither
/// overflows nor underflows for finite input.
pub(crate) fn norm2(v: &[f64]) -> f64 {
    norm2_by(v.len(), |i| v[i])
}

/// [`norm2`] of the vector `(f(0), …, f(len − 1))` without materialising it.
fn norm2_by(len: usize, f: impl Fn(usize) -> f64) -> f64 {
    let s = (0..len).fold(0.0_f64, |a, i| a.max(f(i).abs()));
    scaled_norm(s, len, f)
}

/// The second pass of [`norm2_by`], given `s`, the largest `|f(i)|`.
fn scaled_norm(s: f64, len: usize, f: impl Fn(usize) -> f64) -> f64 {
    if s == 0.0 || !s.is_finite() {
        return s;
    }
    s * (0..len)
        .map(|i| {
            let x = f(i) / s;
            x * x
        })
        .sum::<f64>()
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic stream in [−1, 1) (SplitMix64).
    fn stream(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut x = s;
            x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            x ^= x >> 31;
            (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    #[test]
    fn w_over_the_support_of_z_is_the_compensated_sum_of_the_whole_rows() {
        let mut u = stream(7);
        for n in (1..=70).chain([SUPPORT_MAX_N, SUPPORT_MAX_N + 1]) {
            for zeros in [0.0, 0.5, 0.9, 1.0] {
                // Entries of very different magnitudes, so that the
                // compensation matters, and z with a share of exact zeros.
                let m: Vec<f64> = (0..n * n).map(|_| u() * 10f64.powf(8.0 * u())).collect();
                let q: Vec<f64> = (0..n).map(|_| u() * 1e8).collect();
                let z: Vec<f64> = (0..n)
                    .map(|_| {
                        if 0.5 * (u() + 1.0) < zeros {
                            0.0
                        } else {
                            u().abs() * 1e8
                        }
                    })
                    .collect();
                let mut w = vec![f64::NAN; n];
                w_into(&m, &q, &z, &mut w, true);
                for i in 0..n {
                    let full = dot2_plus(&m[i * n..(i + 1) * n], &z, q[i]);
                    // Equal as numbers (the sign of a zero may differ).
                    assert!(w[i] == full, "n = {n}, row {i}: {} against {full}", w[i]);
                }
            }
        }
    }
}
