//! Linear complementarity problems (LCPs) for floe–floe contact.
//!
//! # Problem
//!
//! Given a dense matrix `M` (n×n, stored row-major in a `Vec<f64>`) and a
//! vector `q` (length n), find `z` such that
//!
//! ```text
//! w = M z + q >= 0,   z >= 0,   zᵀ w = 0
//! ```
//!
//! (componentwise inequalities). In the contact layer `z` holds the normal
//! (and friction) impulses and `w` the post-impact relative velocities.
//!
//! # Algorithm
//!
//! [`lemke::lemke`] is our own implementation of **Lemke's complementary
//! pivoting method** with a covering vector `d > 0` (default all ones) and an
//! artificial variable `z0`, as stated in Cottle, Pang & Stone (1992),
//! Algorithm 4.4.5, on a dense tableau `[I | −M | −d | q]` kept in condensed
//! form (only the non-basic columns, see [`lemke`]). Degeneracy is
//! resolved by the **lexicographic minimum-ratio rule** (CPS §4.9): among rows
//! tied in the ratio test, the leaving row is the lexicographic minimum of
//! `(b_i, (B⁻¹)_{i·}) / c_i` (right-hand side followed by the row of the
//! current basis inverse, divided by the entering-column entry). Because the
//! rows of `B⁻¹` are linearly independent the minimum is unique, every
//! almost-complementary basis stays lexicographically feasible and no basis can
//! repeat, so the method cannot cycle. Ties in the ratio test are exact up to
//! a relative 1e-14 (a looser, absolute tolerance let non-minimal rows leave
//! and lost the path); a basic value that rounding left slightly negative
//! counts as 0 there (see [`lemke`]). A plain minimum-ratio test with a
//! documented tie-break ([`PivotRule`]) is offered as an alternative.
//! If `z0` is among the rows tied in the ratio test it is always chosen (the
//! method then stops on a complementary solution), and so it is when the
//! step would leave it negligible ([`LemkeOptions::z0_tol`]). A
//! [`Workspace`] holds the tableau and scratch vectors; [`solve`] and
//! [`lemke()`] use one per thread, so a solve allocates only its result.
//!
//! For a P-matrix `M` the LCP has a unique solution for every `q` and Lemke's
//! method finds it; for a copositive-plus `M` (e.g. positive semidefinite)
//! termination on a secondary ray proves the LCP infeasible (CPS Thm 4.4.13).
//!
//! [`solve`] is the robust driver used by the simulation: it runs a sequence of
//! attempts (lexicographic rule; alternative rule with another covering
//! vector; lexicographic rule on `M + εI` for a few relative `ε`), re-checks every candidate against the
//! **original** data with [`residual`], optionally polishes it (iterative
//! refinement of the final basis on the original data, else principal
//! pivoting from its support, which completes a path that ended next to a
//! solution), and reports every
//! attempt. It never panics and never returns a non-finite `z`.
//!
//! [`timing`] times the driver on a folder of dumps (`floebench lcp DIR
//! --time`).
//!
//! [`predict`] guesses the complementary basis of a large contact LCP by a
//! block nonsmooth Gauss–Seidel (one block per contact), for the warm Lemke
//! path of the driver.
//!
//! [`dump`] writes and reads JSON LCP dumps for reproducing a solve.
//!
//! # References
//!
//! * R. W. Cottle, J.-S. Pang, R. E. Stone, *The Linear Complementarity
//!   Problem*, Academic Press, 1992 (SIAM Classics 2009), §4.4 (Lemke's
//!   method, Alg. 4.4.5) and §4.9 (degeneracy, lexicographic rule).
//! * C. E. Lemke, "Bimatrix equilibrium points and mathematical programming",
//!   *Management Science* 11 (1965) 681–689.
//! * K. G. Murty, *Linear Complementarity, Linear and Nonlinear Programming*,
//!   Heldermann, 1988, ch. 2.
//! * V. Acary, B. Brogliato, *Numerical Methods for Nonsmooth Dynamical
//!   Systems*, Springer, 2008 (Siconos; natural-map residual of an LCP).

pub mod dump;
mod json_f64;
pub mod lemke;
pub mod lemke_options;
pub(crate) mod path;
pub(crate) mod pivoting;
pub(crate) mod polish;
pub mod predict;
pub(crate) mod revised;
pub mod scaling;
pub mod solution;
pub mod solve;
pub mod solve_options;
pub(crate) mod sparse;
pub(crate) mod sparse_lu;
pub mod timing;

pub use dump::{DumpError, LcpDump};
pub use lemke::{lemke, lemke_with, LemkeResult, Workspace};
pub use lemke_options::{LemkeOptions, PivotRule, Termination};
pub use solution::{
    Attempt, BasisGuess, LcpSolution, SolveCounters, SolveStatus, SolveSummary, Strategy, WarmStart,
};
pub use solve::{solve, solve_into, solve_warm, solve_warm_into, solve_warm_with, solve_with};
pub use solve_options::{Covering, SolveOptions, DEFAULT_COVERING_FLOOR};

use serde::{Deserialize, Serialize};

/// Floor of the denominator of [`residual`]: `f64::EPSILON`.
///
/// When `‖q‖₂ <= RESIDUAL_DENOMINATOR_FLOOR` the residual is effectively an
/// absolute one (divided by `f64::EPSILON`), as in Siconos'
/// `lcp_compute_error`; this only happens for an (almost) zero `q`, whose
/// solution `z = 0` has residual exactly 0.
pub const RESIDUAL_DENOMINATOR_FLOOR: f64 = f64::EPSILON;

/// Error raised when LCP data have inconsistent sizes.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LcpError {
    /// `m` does not hold `n * n` entries.
    #[error("matrix M has {len} entries, expected n*n = {n}*{n}")]
    MatrixSize {
        /// Declared dimension.
        n: usize,
        /// Number of entries supplied.
        len: usize,
    },
    /// `q` does not hold `n` entries.
    #[error("vector q has {len} entries, expected n = {n}")]
    VectorSize {
        /// Declared dimension.
        n: usize,
        /// Number of entries supplied.
        len: usize,
    },
    /// A vector passed together with an LCP does not have length n.
    #[error("vector {name} has {len} entries, expected n = {n}")]
    OperandSize {
        /// Name of the offending vector.
        name: &'static str,
        /// Dimension of the LCP.
        n: usize,
        /// Number of entries supplied.
        len: usize,
    },
    /// A matrix given as rows is not square.
    #[error("row {row} of M has {len} entries, expected {n}")]
    RowLength {
        /// Index of the offending row (0-based).
        row: usize,
        /// Its length.
        len: usize,
        /// Expected length (number of rows).
        n: usize,
    },
}

/// A linear complementarity problem `w = M z + q >= 0, z >= 0, zᵀw = 0`.
///
/// Sizes are validated by the constructors; the entries are not (a
/// non-finite entry makes [`solve`] report a failure instead of panicking).
/// The fields are public, so a hand-built value may be inconsistent: every
/// function of this module checks sizes again and reports a failure status.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Lcp {
    /// Dimension n.
    pub n: usize,
    /// Matrix M, n×n, row-major: `m[i * n + j] = M_ij`.
    pub m: Vec<f64>,
    /// Vector q, length n.
    pub q: Vec<f64>,
}

impl Lcp {
    /// Builds an LCP from a row-major matrix, checking `m.len() == n*n` and
    /// `q.len() == n`.
    pub fn new(n: usize, m: Vec<f64>, q: Vec<f64>) -> Result<Self, LcpError> {
        if n.checked_mul(n) != Some(m.len()) {
            return Err(LcpError::MatrixSize { n, len: m.len() });
        }
        if q.len() != n {
            return Err(LcpError::VectorSize { n, len: q.len() });
        }
        Ok(Self { n, m, q })
    }

    /// Builds an LCP from the rows of M; every row must have `q.len()`
    /// entries and there must be `q.len()` rows.
    pub fn from_rows(rows: &[Vec<f64>], q: Vec<f64>) -> Result<Self, LcpError> {
        let n = q.len();
        if rows.len() != n {
            return Err(LcpError::VectorSize {
                n: rows.len(),
                len: n,
            });
        }
        let mut m = Vec::with_capacity(n * n);
        for (row, r) in rows.iter().enumerate() {
            if r.len() != n {
                return Err(LcpError::RowLength {
                    row,
                    len: r.len(),
                    n,
                });
            }
            m.extend_from_slice(r);
        }
        Ok(Self { n, m, q })
    }

    /// Returns `w = M z + q`; errors if `z.len() != n` or the LCP is
    /// inconsistent.
    pub fn w(&self, z: &[f64]) -> Result<Vec<f64>, LcpError> {
        self.check()?;
        compute_w(&self.m, &self.q, z)
    }

    /// Natural-map residual of `z` for this LCP; see [`residual`].
    pub fn residual(&self, z: &[f64]) -> f64 {
        if self.check().is_err() {
            return f64::INFINITY;
        }
        residual(&self.m, &self.q, z)
    }

    /// Checks that the public fields are mutually consistent.
    pub fn check(&self) -> Result<(), LcpError> {
        if self.q.len() != self.n {
            return Err(LcpError::VectorSize {
                n: self.n,
                len: self.q.len(),
            });
        }
        if self.n.checked_mul(self.n) != Some(self.m.len()) {
            return Err(LcpError::MatrixSize {
                n: self.n,
                len: self.m.len(),
            });
        }
        Ok(())
    }

    /// `true` when every entry of M and q is finite.
    pub fn is_finite(&self) -> bool {
        self.m.iter().chain(self.q.iter()).all(|x| x.is_finite())
    }
}

/// The size of the support of `z`: its entries `z_i > 0` (a NaN does not
/// count).
pub fn support(z: &[f64]) -> usize {
    z.iter().filter(|&&v| v > 0.0).count()
}

/// The fewest pivots in which a cold Lemke path (from the basis of the `w`,
/// `z = 0`) can end at a solution whose support (its `z_i > 0`, see
/// [`support`]) has `support` entries: `0` when `z = 0` (then `q ≥ 0` and no
/// pivot is taken), else `1 + support`. A pivot brings one variable into
/// the basis; `z0` enters first, and each `z_i > 0` of the end point is
/// basic there, so it entered at least once. The ratio of the pivots taken
/// to this bound measures how direct the path was (docs/physics.md §3.3,
/// "The cost of an exact solve of a jammed pack").
pub fn min_cold_pivots(support: usize) -> usize {
    match support {
        0 => 0,
        s => s + 1,
    }
}

/// Computes `w = M z + q` (M row-major, n = `q.len()`).
///
/// Errors if `m.len() != n*n` or `z.len() != n`. Non-finite data propagate
/// into `w` (no check).
pub fn compute_w(m: &[f64], q: &[f64], z: &[f64]) -> Result<Vec<f64>, LcpError> {
    let n = q.len();
    if n.checked_mul(n) != Some(m.len()) {
        return Err(LcpError::MatrixSize { n, len: m.len() });
    }
    if z.len() != n {
        return Err(LcpError::OperandSize {
            name: "z",
            n,
            len: z.len(),
        });
    }
    Ok(w_unchecked(m, q, z))
}

/// `M z + q` without size checks; callers guarantee the sizes.
///
/// Each entry is a compensated dot product (Ogita, Rump & Oishi 2005,
/// "Dot2"): as accurate as if computed in twice the working precision, so
/// that the cancellation in `M z` for large `z` cannot hide a negative `w_i`
/// from the acceptance test of [`solve`].
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
/// basis solves of [`pivoting`]; the residual of the driver keeps
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

/// Natural-map (Siconos-style) residual of `z`:
///
/// ```text
/// w = M z + q,   r = ‖z − max(0, z − w)‖₂ / max(‖q‖₂, RESIDUAL_DENOMINATOR_FLOOR)
/// ```
///
/// `z − max(0, z − w) = min(z, w)` componentwise, which is zero exactly when
/// `z >= 0, w >= 0, z_i w_i = 0`, so `r = 0` iff `z` solves the LCP. It is
/// evaluated as `min(z_i, w_i)`: the literal form cancels when `z_i ≫ |w_i|`
/// (e.g. `z_i = 3e16, w_i = −1` gives 0) and would accept non-solutions;
/// `w` is computed with a compensated dot product for the same reason. The
/// denominator makes `r` invariant under a positive scaling of `(q, z)`; its
/// floor [`RESIDUAL_DENOMINATOR_FLOOR`] (= `f64::EPSILON`, the Siconos
/// convention) avoids a division by zero when `q ≈ 0` and then makes the
/// residual an absolute one.
///
/// Returns `f64::INFINITY` (never NaN) when the sizes are inconsistent
/// (`m.len() != n*n` or `z.len() != n`, n = `q.len()`) or any datum or
/// intermediate value is non-finite.
pub fn residual(m: &[f64], q: &[f64], z: &[f64]) -> f64 {
    let Ok(w) = compute_w(m, q, z) else {
        return f64::INFINITY;
    };
    residual_with_w(q, z, &w)
}

/// [`residual`] when `w = M z + q` is already known (no allocation).
pub(crate) fn residual_with_w(q: &[f64], z: &[f64], w: &[f64]) -> f64 {
    ResidualScale::of(q).residual(z, w)
}

/// The part of [`residual`] that depends on `q` only (its denominator and
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

    /// [`residual`] of `z` with `w = M z + q` known: `INFINITY` if the sizes
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
