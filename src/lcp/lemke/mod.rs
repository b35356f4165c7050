//! Lemke's complementary pivoting method on a dense tableau
//! (Cottle–Pang–Stone 1992, Alg. 4.4.5, with the lexicographic rule of §4.9).
//!
//! The augmented system is `w − M z − d z0 = q` with basic variables `w` at
//! the start. Variables are numbered `0..n` for `w`, `n..2n` for `z` and `2n`
//! for `z0`. The tableau is kept in **condensed** (dictionary) form: only the
//! `n + 1` non-basic columns of `B⁻¹ [I | −M | −d]` and the right-hand side
//! `b = B⁻¹ q` are stored (n × (n + 2), row-major); a pivot exchanges the
//! entering variable's column for the leaving variable's (the classical
//! exchange step, Dantzig 1963 §8; Murty 1988 §2.2), which halves the work
//! of a pivot against the full n × (2n + 2) tableau. The columns of `B⁻¹`
//! that the lexicographic rule reads are those of the `w` variables: a
//! stored column when `w_k` is non-basic, the unit vector of its row when
//! `w_k` is basic.
//!
//! Before pivoting, M, q and the covering vector d are scaled by powers of
//! two (exact in binary floating point, over the whole exponent range, see
//! [`super::scaling::pow2_exponent`]) so that `max|M_ij|`, `max|q_i|` and `max d_i` are within
//! a factor √2 of 1; this makes the absolute tolerances below meaningful and
//! leaves the solution unchanged (`z = (β/α) z'` for `M' = M/α`, `q' = q/β`).
//!
//! # Ratio test
//!
//! The ratio of a row is `max(b_i, 0) / c_i`: a basic value that rounding
//! left slightly negative counts as a degenerate 0. Its raw ratio would be
//! negative and win the test however small `c_i`: measured on a dump of
//! field_200_coast, a basic value of −1.2e-12 over an entry of 1.2e-8 gave
//! the ratio −9.7e-5, the pivot drove basic values to −3e3 and the path
//! cycled through four bases to the pivot cap (14,450 pivots).
//!
//! # Termination
//!
//! Besides the textbook stop (`z0` leaves the basis), the method stops with
//! [`Termination::Solved`] as soon as `z0` is *negligible* (see
//! [`LemkeOptions::z0_tol`]): every almost-complementary basic feasible
//! solution with `z0 = 0` is a solution of the LCP (CPS §4.4, the remark
//! after Alg. 4.4.5), so
//!
//! * if the minimum-ratio step would leave `z0` at or below `z0_tol`, `z0`
//!   is made the leaving variable (a generalisation of "z0 leaves when it is
//!   tied", which is exact when the step brings `z0` to 0);
//! * if the entering column has no blocking entry (a secondary ray) while
//!   the basic `z0` is already at or below `z0_tol`, the current point is
//!   returned as the solution instead of a ray termination.
//!
//! Without this, on the degenerate Stewart–Trinkle LCPs of the contact layer
//! the path reached points with `z0 ≈ 1e-17` (a solution up to rounding)
//! and kept pivoting through degenerate bases until a secondary ray.
//!
//! # Work space
//!
//! [`Workspace`] holds the tableau and every scratch vector, so that a solve
//! allocates nothing but its result once the buffers have grown to the
//! largest problem seen; [`lemke`] uses one per thread.
//!
//! The dense tableau itself (its set-up, the exchange step and its
//! elimination, its `Basis` implementation) is in `lemke/tableau.rs`.

use super::arith::residual_with_w;
use super::lemke_options::{options_valid, LemkeOptions, Termination, DEFAULT_PIVOTS_PER_DIM};
use super::path::{self, Basis};
use super::revised::Revised;
use super::scaling::{exp2_factor, ldexp, max_abs, max_abs_finite, pow2_exponent};
use super::sparse::Columns;
use std::cell::RefCell;

mod tableau;

/// Outcome of [`lemke`].
#[derive(Debug, Clone, PartialEq)]
pub struct LemkeResult {
    /// `z` (length n; all zeros when nothing could be computed). Always
    /// finite. Negative entries remain only with
    /// [`Termination::NumericalFailure`].
    pub z: Vec<f64>,
    /// `w = M z + q` recomputed from the original data (not from the
    /// tableau). Non-finite only if the data are.
    pub w: Vec<f64>,
    /// Number of pivots performed (including the first one, on `z0`).
    pub pivots: usize,
    /// Why the method stopped.
    pub termination: Termination,
    /// [`super::residual`] of `z` on the data given to [`lemke`]
    /// (`f64::INFINITY` if not computable).
    pub residual: f64,
    /// Short human-readable reason for a failure, `None` on success.
    pub detail: Option<&'static str>,
}

thread_local! {
    static WORKSPACE: RefCell<Workspace> = RefCell::new(Workspace::default());
}

/// Runs `f` with this thread's [`Workspace`] (a fresh one if it is already
/// borrowed, e.g. by a re-entrant call).
pub(crate) fn with_thread_workspace<R>(f: impl FnOnce(&mut Workspace) -> R) -> R {
    WORKSPACE.with(|cell| match cell.try_borrow_mut() {
        Ok(mut ws) => f(&mut ws),
        Err(_) => f(&mut Workspace::default()),
    })
}

/// Runs Lemke's method on `w = M z + q` (M row-major, n = `q.len()`).
///
/// Never panics: inconsistent sizes or bad options give
/// [`Termination::InvalidInput`], non-finite data
/// [`Termination::NumericalFailure`], both with `z = 0`. If `q >= 0` the
/// result is `z = 0` with 0 pivots. After termination `z` is read from the
/// tableau, tiny negative entries are clamped to 0 (see
/// [`LemkeOptions::clamp_tol`]), and `w` and the residual are recomputed from
/// the original `M`, `q`. Uses this thread's [`Workspace`]; see
/// [`lemke_with`].
pub fn lemke(m: &[f64], q: &[f64], opts: &LemkeOptions) -> LemkeResult {
    with_thread_workspace(|ws| lemke_with(ws, m, q, opts))
}

/// [`lemke`] with an explicit work space (no allocation but the result once
/// `ws` has grown to the problem size).
pub fn lemke_with(ws: &mut Workspace, m: &[f64], q: &[f64], opts: &LemkeOptions) -> LemkeResult {
    let n = q.len();
    let run = ws.run(m, q, opts);
    let mut z = vec![0.0; n];
    let (termination, detail) = if run.tableau {
        ws.read_z(&mut z, run.termination, run.detail, opts.clamp_tol)
    } else {
        (run.termination, run.detail)
    };
    let mut w = vec![0.0; n];
    let residual = if termination == Termination::InvalidInput || n.checked_mul(n) != Some(m.len())
    {
        w.copy_from_slice(q);
        f64::INFINITY
    } else {
        super::arith::w_into(m, q, &z, &mut w, false);
        residual_with_w(q, &z, &w)
    };
    LemkeResult {
        z,
        w,
        pivots: run.pivots,
        termination,
        residual,
        detail,
    }
}

/// What [`Workspace::run`] reports.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Run {
    pub(crate) termination: Termination,
    pub(crate) detail: Option<&'static str>,
    pub(crate) pivots: usize,
    /// Whether the work space holds a tableau of this problem (false for an
    /// early exit: invalid input, non-finite data, `q >= 0`).
    pub(crate) tableau: bool,
}

/// Reusable buffers of Lemke's method: the condensed tableau, the basis and
/// the scratch vectors of the ratio test and of the pivot. Create one with
/// `Workspace::default()` and pass it to [`lemke_with`] or
/// [`super::solve_with`] as often as needed; the buffers grow to the largest
/// problem seen and are then reused without allocation.
#[derive(Debug, Clone, Default)]
pub struct Workspace {
    n: usize,
    /// Row length of the tableau: n + 2 (n + 1 non-basic columns, rhs).
    cols: usize,
    /// Condensed tableau, n × cols, row-major.
    t: Vec<f64>,
    /// `basis[row]`: variable basic in that row.
    basis: Vec<usize>,
    /// `nonbasic[col]`: variable of that column (col < n + 1).
    nonbasic: Vec<usize>,
    /// Row of a basic variable (`NONE` if non-basic), per variable (2n + 1).
    row_of: Vec<usize>,
    /// Column of a non-basic variable (`NONE` if basic), per variable.
    col_of: Vec<usize>,
    /// Copy of the pivot row.
    prow: Vec<f64>,
    /// Non-zero positions of the pivot row.
    nz: Vec<usize>,
    /// An upper bound on `|t_ij|` over the tableau (scaled units), kept by
    /// every exchange; while the bound after an exchange is below
    /// [`OVERFLOW_FREE_BOUND`](tableau::OVERFLOW_FREE_BOUND) no entry can
    /// overflow, and the elimination skips its per-entry finiteness test.
    tbound: f64,
    /// Candidate rows of the ratio test.
    cand: Vec<usize>,
    /// Column of the entering variable (set by [`Basis::load`]).
    s: usize,
    /// The factorised basis of the revised path.
    rev: Revised,
    /// Whether the last run used the revised path (then `rev`, not the
    /// tableau, holds its final basis).
    revised: bool,
    /// Scaled covering vector.
    d: Vec<f64>,
    /// Binary exponents of the scalings of M, q, d.
    ea: i32,
    eb: i32,
    eg: i32,
    pivots: usize,
    /// Scratch vectors of the driver (candidate and best points, a copy of
    /// M + εI, refinement vectors), boxed so that the driver takes them out
    /// of the work space and puts them back by moving a pointer (`None`
    /// only while taken, or before the first solve).
    pub(crate) scratch: Option<Box<Scratch>>,
}

/// Scratch vectors used by the driver, kept with the tableau so that one
/// work space serves a whole solve.
#[derive(Debug, Clone, Default)]
pub(crate) struct Scratch {
    pub(crate) z: Vec<f64>,
    pub(crate) w: Vec<f64>,
    pub(crate) best_z: Vec<f64>,
    pub(crate) best_w: Vec<f64>,
    pub(crate) m_shift: Vec<f64>,
    pub(crate) x: Vec<f64>,
    pub(crate) rho: Vec<f64>,
    pub(crate) z2: Vec<f64>,
    pub(crate) w2: Vec<f64>,
    pub(crate) pivoting: super::pivoting::Pivoting,
    /// The residual over the compressed columns of M, for large problems.
    pub(crate) sparse: super::sparse::SparseResidual,
}

impl Workspace {
    /// Sets up the tableau for `(m, q, d)` and runs the method.
    pub(crate) fn run(&mut self, m: &[f64], q: &[f64], opts: &LemkeOptions) -> Run {
        self.run_from(m, q, opts, None, None)
    }

    /// [`Workspace::run`] for data the caller has already scanned:
    /// `maxima = (max|M_ij|, max|q_i|)` of a finite `M` and `q` (as
    /// [`max_abs`] computes them) and, if that scan built them, M's columns
    /// (for the factorised basis), so that the set-up does not read the
    /// data a second time. The same run as [`Workspace::run`].
    pub(crate) fn run_scanned(
        &mut self,
        m: &[f64],
        q: &[f64],
        opts: &LemkeOptions,
        maxima: (f64, f64),
        cols: Option<&Columns>,
    ) -> Run {
        self.run_from(m, q, opts, None, Some((maxima, cols)))
    }

    /// Runs the method from the guessed complementary basis `start`
    /// (`start[k]`: `z_k` basic, else `w_k`; length n) on the factorised
    /// basis, with the covering column `d = B_s 1` of
    /// [`Revised::setup_from_basis`] (`opts.covering` and
    /// `opts.revised_from` are ignored). A singular guessed basis ends the
    /// run before any pivot ([`Termination::NumericalFailure`], no tableau).
    /// See docs/physics.md §3.3, "Warm Lemke".
    pub(crate) fn run_warm(
        &mut self,
        m: &[f64],
        q: &[f64],
        opts: &LemkeOptions,
        start: &[bool],
    ) -> Run {
        if start.len() != q.len() {
            return Run {
                termination: Termination::InvalidInput,
                detail: Some("guessed basis is not of length n"),
                pivots: 0,
                tableau: false,
            };
        }
        self.run_from(m, q, opts, Some(start), None)
    }

    /// [`Workspace::run`] (`start = None`) or [`Workspace::run_warm`].
    fn run_from(
        &mut self,
        m: &[f64],
        q: &[f64],
        opts: &LemkeOptions,
        start: Option<&[bool]>,
        scanned: Option<((f64, f64), Option<&Columns>)>,
    ) -> Run {
        let n = q.len();
        let early = |termination, detail| Run {
            termination,
            detail: Some(detail),
            pivots: 0,
            tableau: false,
        };
        self.pivots = 0;
        if n.checked_mul(n) != Some(m.len()) {
            return early(Termination::InvalidInput, "M is not n×n with n = q.len()");
        }
        if !options_valid(opts) {
            return early(
                Termination::InvalidInput,
                "invalid tolerance in LemkeOptions",
            );
        }
        let ((mmax, mfinite), (qmax, qfinite), cols) = match scanned {
            Some(((mmax, qmax), cols)) => ((mmax, true), (qmax, true), cols),
            None => (max_abs_finite(m), max_abs_finite(q), None),
        };
        if !(mfinite && qfinite) {
            return early(Termination::NumericalFailure, "non-finite entry in M or q");
        }
        if let Some(d) = &opts.covering {
            if d.len() != n || !d.iter().all(|&x| x.is_finite() && x > 0.0) {
                return early(
                    Termination::InvalidInput,
                    "covering vector must have n finite positive entries",
                );
            }
        }
        if q.iter().all(|&x| x >= 0.0) {
            return Run {
                termination: Termination::Solved,
                detail: None,
                pivots: 0,
                tableau: false,
            };
        }
        let max_pivots = opts
            .max_pivots
            .unwrap_or_else(|| DEFAULT_PIVOTS_PER_DIM.saturating_mul(n.saturating_add(1)));
        let covering = if start.is_some() {
            None
        } else {
            opts.covering.as_deref()
        };
        self.scale(n, covering, mmax, qmax);
        self.revised = start.is_some() || n >= opts.revised_from;
        let mut cand = std::mem::take(&mut self.cand);
        let (termination, detail, pivots) = if let Some(start) = start {
            if self
                .rev
                .setup_from_basis(m, q, start, self.ea, self.eb)
                .is_none()
            {
                self.cand = cand;
                self.revised = false;
                return early(
                    Termination::NumericalFailure,
                    "guessed basis singular or its basic values not finite",
                );
            }
            // The covering column d = B_s 1 (scaled), for the refinement.
            self.d.clear();
            self.d.extend_from_slice(self.rev.covering());
            let out = path::run(&mut self.rev, &mut cand, opts, max_pivots);
            (out.0, out.1, self.rev.pivots())
        } else if self.revised {
            self.rev.setup(m, q, &self.d, (self.ea, self.eb), cols);
            let out = path::run(&mut self.rev, &mut cand, opts, max_pivots);
            (out.0, out.1, self.rev.pivots())
        } else {
            self.setup(m, q);
            let out = path::run(self, &mut cand, opts, max_pivots);
            (out.0, out.1, self.pivots)
        };
        self.cand = cand;
        self.pivots = pivots;
        Run {
            termination,
            detail,
            pivots,
            tableau: true,
        }
    }

    /// The binary exponents of the scalings of M, q and d, and the scaled d.
    fn scale(&mut self, n: usize, covering: Option<&[f64]>, mmax: f64, qmax: f64) {
        self.n = n;
        self.ea = pow2_exponent(mmax);
        self.eb = pow2_exponent(qmax);
        self.d.clear();
        match covering {
            None => {
                self.eg = 0;
                self.d.resize(n, 1.0);
            }
            Some(d) => {
                self.eg = pow2_exponent(max_abs(d));
                self.d.extend(d.iter().map(|&x| ldexp(x, -self.eg)));
            }
        }
    }

    /// Reads `z` (original units) from the tableau into `z` (length n),
    /// clamping tiny negative entries; downgrades the termination to a
    /// numerical failure if `z` is non-finite or significantly negative.
    pub(crate) fn read_z(
        &self,
        z: &mut [f64],
        termination: Termination,
        detail: Option<&'static str>,
        clamp_tol: f64,
    ) -> (Termination, Option<&'static str>) {
        let n = self.n;
        z.iter_mut().for_each(|x| *x = 0.0);
        if z.len() != n {
            return (termination, detail);
        }
        let mut zmax = 1.0_f64;
        let mut finite = true;
        for i in 0..n {
            let v = self.basic_var(i);
            if v >= n && v < 2 * n {
                let x = self.basic_value(i);
                z[v - n] = x;
                finite &= x.is_finite();
                zmax = zmax.max(x.abs());
            }
        }
        if !finite {
            z.iter_mut().for_each(|x| *x = 0.0);
            return (
                Termination::NumericalFailure,
                Some("non-finite z read from the tableau"),
            );
        }
        let mut significant_negative = false;
        let e = self.eb - self.ea;
        let f = exp2_factor(e);
        let mut finite = true;
        for x in z.iter_mut() {
            if *x < 0.0 {
                if *x >= -clamp_tol * zmax {
                    *x = 0.0;
                } else {
                    significant_negative = true;
                }
            }
            *x = match f {
                Some(f) => *x * f,
                None => ldexp(*x, e),
            };
            finite &= x.is_finite();
        }
        if !finite {
            z.iter_mut().for_each(|x| *x = 0.0);
            return (
                Termination::NumericalFailure,
                Some("z overflowed when undoing the scaling"),
            );
        }
        if significant_negative && termination == Termination::Solved {
            return (
                Termination::NumericalFailure,
                Some("significantly negative z after pivoting (numerical drift)"),
            );
        }
        (termination, detail)
    }

    /// One step of iterative refinement of the basic solution on the original
    /// data, with the tableau's `B⁻¹` as approximate inverse.
    ///
    /// `z` (original units, length n) is the current point and `w = M z + q`
    /// its (compensated) image; `x` holds the basic values of the rows
    /// (scaled units), initialised by [`Workspace::basic_values`]. The
    /// equations of the basis are `w_B − M z − d z0 = q` with non-basic
    /// variables at 0; their residual `ρ = (M z + q) − w_B + d z0` is mapped
    /// through `B⁻¹` and added to `x`, and `z` is updated from `x`. Requires
    /// a tableau of this problem (same n).
    pub(crate) fn refine_step(&self, x: &mut [f64], w: &[f64], rho: &mut Vec<f64>, z: &mut [f64]) {
        let n = self.n;
        rho.clear();
        rho.resize(n, 0.0);
        // ρ in scaled units: (w − w_B) / β + d' z0.
        let inv_b = |v: f64| ldexp(v, -self.eb);
        for (i, r) in rho.iter_mut().enumerate() {
            *r = inv_b(w[i]);
        }
        for (row, &xr) in x.iter().enumerate() {
            let v = self.basic_var(row);
            if v < n {
                rho[v] -= xr;
            } else if v == 2 * n {
                for (r, &d) in rho.iter_mut().zip(self.d.iter()) {
                    *r += d * xr;
                }
            }
        }
        if self.revised {
            // Δx = B⁻¹ ρ by the factorised basis.
            self.rev.solve(rho);
            for (xr, &dx) in x.iter_mut().zip(rho.iter()) {
                *xr += dx;
            }
        } else {
            self.refine_dense(x, rho);
        }
        let e = self.eb - self.ea;
        for (row, &xr) in x.iter().enumerate() {
            let v = self.basic_var(row);
            if v >= n && v < 2 * n {
                z[v - n] = ldexp(xr, e).max(0.0);
            }
        }
    }

    /// The basic values of the rows (scaled units) into `x` (length n).
    pub(crate) fn basic_values(&self, x: &mut Vec<f64>) {
        x.clear();
        x.extend((0..self.n).map(|i| self.basic_value(i)));
    }

    /// The variable basic in row `i` of the last run's final basis.
    fn basic_var(&self, i: usize) -> usize {
        if self.revised {
            self.rev.basic(i)
        } else {
            self.basis[i]
        }
    }

    /// The basic value of row `i` (scaled units) of the last run.
    fn basic_value(&self, i: usize) -> f64 {
        if self.revised {
            self.rev.b(i)
        } else {
            Basis::b(self, i)
        }
    }

    /// Whether the last run used the revised (factorised) path.
    pub(crate) fn last_run_revised(&self) -> bool {
        self.revised
    }
}
