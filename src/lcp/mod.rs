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
//! # Files, lowest first
//!
//! Every file imports only from files above it in this list (no circle);
//! this file declares them and re-exports their public items.
//!
//! 1. `scaling` (powers of two, maxima), `sparse_lu` and `polish` (the
//!    sparse and dense LU), `json_f64` (dump encoding), `lemke_options`
//!    (pivot rules, termination, Lemke's options, [`lemke_options::REVISED_FROM`]):
//!    no import from this folder;
//! 2. `arith`: compensated dot products, `w = M z + q`, the residual's scale;
//! 3. this file's own items: [`Lcp`], [`LcpError`], [`compute_w`], [`residual`];
//! 4. `sparse`: M's compressed columns and the sparse residual;
//! 5. `path`: the `Basis` interface and the pivoting rules of Lemke's path;
//! 6. the basis representations and the polish: `revised` (the factorised
//!    basis, its solves in `revised/factor.rs`) and `pivoting` (principal
//!    pivoting);
//! 7. [`lemke`]: the work space and Lemke's method, its dense tableau in
//!    `lemke/tableau.rs`;
//! 8. [`solve_options`] (the driver's options) and [`solution`] (its records
//!    and results);
//! 9. [`solve`](mod@solve): the driver (attempts, residual check, polish,
//!    fallbacks);
//! 10. [`predict`] (the guessed basis of the warm path) and [`dump`];
//! 11. [`timing`].
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

mod arith;
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

pub use arith::RESIDUAL_DENOMINATOR_FLOOR;

use arith::{residual_with_w, w_unchecked};
use serde::{Deserialize, Serialize};

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
