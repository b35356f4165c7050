//! The factorised (revised) basis of Lemke's method, for large sparse LCPs.
//!
//! The dense tableau of [`super::lemke`] stores `B⁻¹ [I | −M | −d | q]` and
//! updates all of it at every pivot: O(n²) work whatever the sparsity of M.
//! On the contact groups of a jammed pack (hundreds of unknowns) that is
//! where the time goes, although the Delassus matrix is block-sparse: a
//! contact couples only with the contacts that share one of its floes.
//!
//! This module keeps instead, as in the revised simplex method (Chvátal
//! 1983, ch. 7; Murty 1988, §2.4 for Lemke's method):
//!
//! * the basis `B` only implicitly, as `B = B₀ E₁ ⋯ E_k`: the basis `B₀` of
//!   the last refactorisation in reduced form (its unit columns, those of
//!   the basic `w_i`, are eliminated exactly, and only the square block `K`
//!   of its `z` and `z0` columns on the rows whose `w` is not basic is
//!   factorised: about half the order on a jammed pack's path; see
//!   [`Revised::refactor`]) by a sparse LU (faer's simplicial LU with a
//!   COLAMD ordering and partial pivoting, called directly so that its
//!   permutations and scratch are kept here; the triangular solves are
//!   this module's own, skipping the columns whose entry is zero, and a
//!   solve allocates nothing; `B₀ = I` at the start, with no
//!   factorisation) and the **eta
//!   matrices** `E_j` of the pivots since then (product form of the
//!   inverse: `E_j` is the identity with its pivot column replaced by the
//!   entering column `B_{j-1}⁻¹ a`, stored dense: with z0 basic that column
//!   has `B⁻¹ d` in it and is full);
//! * the basic values `b = B⁻¹ q`, updated by each pivot like the tableau's
//!   right-hand side and recomputed from the original (scaled) data at every
//!   refactorisation;
//! * M's columns in compressed sparse form, built once per solve.
//!
//! A pivot computes the entering column `c = B⁻¹ a_s` by one forward
//! solve (**FTRAN**: the LU, then the etas in order), which costs the
//! non-zeros of the factors and of the etas, not n². The lexicographic rule
//! needs the rows of `B⁻¹` of the rows tied in the ratio test; they are
//! computed only when ties occur, by one transposed solve each (**BTRAN**:
//! the etas in reverse order, then the transposed LU). The basis is
//! refactorised every [`REFACTOR_EVERY`] pivots, which bounds the length of
//! the eta file (the cost of a solve) and the drift of `b`.
//!
//! The pivoting rules themselves are those of [`super::path`], shared with
//! the dense tableau; only the representation differs.
//!
//! This file holds the basis, its set-up and its `Basis` implementation;
//! the solves (FTRAN, BTRAN, the reduced LU) and the refactorisation are
//! in `revised/factor.rs`.
//!
//! # References
//!
//! * V. Chvátal, *Linear Programming*, Freeman, 1983, ch. 7 (revised simplex
//!   method, product form of the inverse).
//! * K. G. Murty, *Linear Complementarity, Linear and Nonlinear
//!   Programming*, Heldermann, 1988, §2.4 (Lemke's method in revised form).
//! * R. W. Cottle, J.-S. Pang, R. E. Stone, *The Linear Complementarity
//!   Problem*, 1992, §4.4 and §4.9.

use super::path::{Basis, NONE};
use super::scaling::ldexp;
use super::sparse::Columns;
use super::sparse_lu::{Csc, SparseLu};

mod factor;

/// Pivots between two refactorisations of the basis. Each eta adds n (dense)
/// entries to every FTRAN and BTRAN; a sparse LU of a basis of a jammed
/// contact group costs about as much as a few dozen such solves. Measured
/// on the 40 bay-jam LCPs of more than 800 unknowns with merged flush-pair
/// friction (`floebench lcp DIR --time`, one binary per value): 24: 25.3 s,
/// 48: 17.5–19.1 s, 96: 14.8–16.0 s, 192: 16.5 s, the same pivots (the
/// refactorisation takes about 40 % of the time at 48); but on the corpus
/// of the same window without the merge (degenerate, near-equal columns)
/// 96 took 48.0 s against 39.7 s and left one LCP unsolved by every
/// attempt (residual 2.4e-7): a longer eta file drifts more on degenerate
/// paths. Kept at 48 (docs/physics.md §3.3). These figures predate the
/// reduced factorisation of [`Revised::refactor`], which makes a
/// refactorisation cheaper; the period was not re-tuned for it.
pub(crate) const REFACTOR_EVERY: usize = 48;

/// Smallest principal pivot of the crash of a guessed basis
/// ([`Revised::setup_from_basis`]), relative to the largest entry of its
/// column (at least 1, on the scaled data): below it the guessed `z_k`
/// stays non-basic. Well above rounding (a singular `M_αα` leaves pivots of
/// 1e-16 relative) and well below the entries of a regular Delassus
/// diagonal, so that the basis the path starts from is well conditioned;
/// chosen, not tuned.
pub(crate) const CRASH_PIVOT_TOL: f64 = 1e-7;

/// The factorised basis; see the module doc.
#[derive(Default)]
pub(crate) struct Revised {
    n: usize,
    /// Scaled M' = M / 2^ea in compressed sparse columns.
    mp: Vec<usize>,
    mi: Vec<usize>,
    mv: Vec<f64>,
    /// The columns of M when the caller has not built them.
    own: Columns,
    /// Scaled covering vector d'.
    d: Vec<f64>,
    /// Scaled q' = q / 2^eb.
    q: Vec<f64>,
    /// Variable basic in each row (slot) of the basis.
    basis: Vec<usize>,
    /// Row of each variable (2n + 1), [`NONE`] if non-basic.
    row_of: Vec<usize>,
    /// Basic values `B⁻¹ q'`.
    b: Vec<f64>,
    /// `B₀` is kept in reduced form (see [`Revised::refactor`]), valid
    /// while `factorised`; `B₀ = I` otherwise.
    factorised: bool,
    /// Order `k` of the reduced block `K` of `B₀`: the slots of `B₀` whose
    /// variable is a `z_j` or `z0`.
    k: usize,
    /// LU of `K` (`P_r K P_c = L U`); empty when `k = 0`.
    lu: SparseLu,
    /// Rank of each index j in a fill-reducing column ordering of M' (COLAMD
    /// of M', computed once per solve at its first factorisation): `K`'s
    /// columns are eliminated in the order of their variables' ranks.
    rank: Vec<usize>,
    /// Whether `rank` is that of the current problem.
    ranked: bool,
    /// Scratch of the ordering.
    order: Vec<usize>,
    /// Original row of each row of `K` (the rows whose `w` is not basic in
    /// `B₀`), increasing.
    k_rows: Vec<usize>,
    /// Slot of each column of `K`.
    k_slots: Vec<usize>,
    /// Slot of `w_i` in `B₀` for each row i, [`NONE`] for the rows of `K`.
    w_slot: Vec<usize>,
    /// `K` in compressed sparse columns.
    kmat: Csc,
    /// The rows of `B₀`'s `z` columns outside `K` (the coupling `C`, rows
    /// whose `w` is basic), in compressed sparse columns over `K`'s
    /// columns, with original row indices.
    cmat: Csc,
    /// Position in `K` of each original row ([`NONE`]: a row whose `w` is
    /// basic); scratch of [`Revised::refactor`].
    k_pos: Vec<usize>,
    /// Scratch of FTRAN/BTRAN: the input of a reduced solve (n), then the
    /// permuted right-hand side of `K` (k).
    tmp: Vec<f64>,
    /// Eta file: pivot row and pivot entry per pivot since the
    /// refactorisation, and its column stored dense (n entries per eta, 0
    /// in the pivot row): the entering column `B⁻¹ a` has the dense
    /// `B⁻¹ d` mixed in whenever z0 is basic, i.e. along the whole path
    /// (n − 1 non-zeros of n in every eta of the bay-jam corpus), so a
    /// dense axpy costs less than an indexed one.
    eta_r: Vec<usize>,
    eta_p: Vec<f64>,
    eta_d: Vec<f64>,
    /// The loaded entering column and its variable.
    c: Vec<f64>,
    entering: usize,
    /// `max |c_i|` of the loaded column (computed by [`Basis::load`]).
    c_max: f64,
    /// Rows of `B⁻¹` prepared for the lexicographic rule, and the position
    /// of each row among them ([`NONE`] if not prepared).
    lex_rows: Vec<f64>,
    lex_pos: Vec<usize>,
    lex_list: Vec<usize>,
    pivots: usize,
    /// The starting complementary basis (`start[k]`: `z_k` basic, else
    /// `w_k`), the reference of the lexicographic rule; all `false` after
    /// [`Revised::setup`].
    start: Vec<bool>,
}

impl std::fmt::Debug for Revised {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Revised")
            .field("n", &self.n)
            .field("pivots", &self.pivots)
            .field("etas", &self.eta_r.len())
            .field("factorised", &self.factorised)
            .finish()
    }
}

impl Clone for Revised {
    /// A work space is cloned empty: the factorised basis is scratch of one
    /// run, rebuilt by the next.
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl Revised {
    /// Sets up `B = I` for the problem `(m, q)` scaled by `2^-ea`, `2^-eb`,
    /// with the scaled covering vector `d` (all finite, checked by the
    /// caller); `cols`: M's columns if the caller has built them
    /// ([`Columns::scan`] of this `m`), else they are built here.
    pub(crate) fn setup(
        &mut self,
        m: &[f64],
        q: &[f64],
        d: &[f64],
        (ea, eb): (i32, i32),
        cols: Option<&Columns>,
    ) {
        let n = q.len();
        self.n = n;
        // M's columns: the caller's (built by its scan of M), else built
        // here; then scaled.
        let cols = match cols {
            Some(c) => c,
            None => {
                self.own.scan(m, n);
                &self.own
            }
        };
        self.mp.clone_from(&cols.ptr);
        self.mi.clone_from(&cols.idx);
        self.mv.clear();
        self.mv.extend(cols.val.iter().map(|&a| ldexp(a, -ea)));
        self.d.clear();
        self.d.extend_from_slice(d);
        self.q.clear();
        self.q.extend(q.iter().map(|&x| ldexp(x, -eb)));
        self.basis.clear();
        self.basis.extend(0..n);
        self.row_of.clear();
        self.row_of.extend(0..n);
        self.row_of.resize(2 * n + 1, NONE);
        self.b.clear();
        self.b.extend_from_slice(&self.q);
        self.factorised = false;
        self.ranked = false;
        self.clear_etas();
        self.c.clear();
        self.c.resize(n, 0.0);
        self.entering = NONE;
        self.lex_pos.clear();
        self.lex_pos.resize(n, NONE);
        self.lex_list.clear();
        self.pivots = 0;
        self.start.clear();
        self.start.resize(n, false);
    }

    /// Sets up a complementary basis `B_s` near the guess `start`
    /// (`start[k]`: `z_k` basic in row k, else `w_k`) for the problem
    /// `(m, q)` scaled by `2^-ea`, `2^-eb` (all finite, checked by the
    /// caller), with the covering column `d = B_s 1`
    /// (`d_i = [i ∉ α] − Σ_{j ∈ α} M'_ij`), so that the column of `z0` is
    /// `B_s⁻¹(−d) = −1`: Lemke's path on the principal pivot transform of
    /// the LCP on `α` with the covering vector 1 (docs/physics.md §3.3,
    /// "Warm Lemke").
    ///
    /// The guessed `M_αα` is often singular on contact LCPs (two points of
    /// facing edges have equal tangential columns; the guess is the support
    /// of a solution, not a basis), so `B_s` is built by a **crash**: from
    /// `B = I`, `z_k` replaces `w_k` for each guessed `k` in increasing
    /// order (one FTRAN and an eta each: a principal pivot on the diagonal
    /// of the current Schur complement) unless that pivot is below
    /// [`CRASH_PIVOT_TOL`] of its column, in which case `w_k` stays basic.
    /// `α` is the set actually pivoted in; the basis is then refactorised
    /// (the entry cost) and `b = B_s⁻¹ q'` recomputed from the data. The
    /// crash exchanges are not counted as pivots. Returns the number of
    /// guessed indices left out, or `None` if a non-finite entry appeared or
    /// the final factorisation failed.
    pub(crate) fn setup_from_basis(
        &mut self,
        m: &[f64],
        q: &[f64],
        start: &[bool],
        ea: i32,
        eb: i32,
    ) -> Option<usize> {
        let n = q.len();
        let mut d = std::mem::take(&mut self.d);
        d.clear();
        d.resize(n, 1.0);
        self.setup(m, q, &d, (ea, eb), None);
        self.d = d;
        let mut dropped = 0;
        for k in (0..n).filter(|&k| start[k]) {
            if !self.load(n + k) {
                return None;
            }
            let cmax = self.c.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
            if self.c[k].abs() > CRASH_PIVOT_TOL * cmax.max(1.0) {
                if !self.pivot(k) {
                    return None;
                }
                self.start[k] = true;
            } else {
                dropped += 1;
            }
        }
        self.d.iter_mut().enumerate().for_each(|(i, x)| {
            *x = if self.start[i] { 0.0 } else { 1.0 };
        });
        for j in (0..n).filter(|&j| self.start[j]) {
            for p in self.mp[j]..self.mp[j + 1] {
                self.d[self.mi[p]] -= self.mv[p];
            }
        }
        if !self.d.iter().all(|x| x.is_finite()) {
            return None;
        }
        self.pivots = 0;
        // B_s = I when nothing was pivoted in: nothing to factorise.
        if self.start.iter().any(|&s| s) && !self.refactor() {
            return None;
        }
        Some(dropped)
    }

    /// The scaled covering column of the last set-up.
    pub(crate) fn covering(&self) -> &[f64] {
        &self.d
    }

    fn clear_etas(&mut self) {
        self.eta_r.clear();
        self.eta_p.clear();
        self.eta_d.clear();
    }

    /// Writes the column of variable `v` of `[I | −M' | −d']` into `out`
    /// (length n, overwritten).
    fn column(&self, v: usize, out: &mut [f64]) {
        out.iter_mut().for_each(|x| *x = 0.0);
        let n = self.n;
        if v < n {
            out[v] = 1.0;
        } else if v < 2 * n {
            let j = v - n;
            for p in self.mp[j]..self.mp[j + 1] {
                out[self.mi[p]] = -self.mv[p];
            }
        } else {
            for (o, &d) in out.iter_mut().zip(&self.d) {
                *o = -d;
            }
        }
    }
}

impl Basis for Revised {
    fn n(&self) -> usize {
        self.n
    }

    fn basic(&self, i: usize) -> usize {
        self.basis[i]
    }

    fn row_of(&self, v: usize) -> usize {
        self.row_of[v]
    }

    fn load(&mut self, v: usize) -> bool {
        let mut c = std::mem::take(&mut self.c);
        let mut tmp = std::mem::take(&mut self.tmp);
        self.column(v, &mut c);
        self.ftran(&mut c, &mut tmp);
        self.tmp = tmp;
        // Finiteness and the largest magnitude in one pass (the latter is
        // the ratio test's scale, [`Basis::c_max`]).
        let (mut finite, mut cmax) = (true, 0.0_f64);
        for &x in &c {
            finite &= x.is_finite();
            cmax = cmax.max(x.abs());
        }
        self.c = c;
        self.c_max = cmax;
        self.entering = v;
        // Rows prepared for the previous column are stale.
        for &i in &self.lex_list {
            self.lex_pos[i] = NONE;
        }
        self.lex_list.clear();
        finite
    }

    #[inline]
    fn c(&self, i: usize) -> f64 {
        self.c[i]
    }

    fn c_max(&self) -> f64 {
        self.c_max
    }

    #[inline]
    fn b(&self, i: usize) -> f64 {
        self.b[i]
    }

    fn prepare_rows(&mut self, rows: &[usize]) -> bool {
        let n = self.n;
        let mut buf = std::mem::take(&mut self.lex_rows);
        let mut tmp = std::mem::take(&mut self.tmp);
        let mut finite = true;
        for &i in rows {
            if self.lex_pos[i] != NONE {
                continue;
            }
            let at = self.lex_list.len();
            buf.resize((at + 1) * n, 0.0);
            let y = &mut buf[at * n..(at + 1) * n];
            y.iter_mut().for_each(|x| *x = 0.0);
            y[i] = 1.0;
            self.btran(y, &mut tmp);
            finite &= y.iter().all(|x| x.is_finite());
            self.lex_pos[i] = at;
            self.lex_list.push(i);
        }
        self.lex_rows = buf;
        self.tmp = tmp;
        finite
    }

    fn binv(&self, i: usize, v: usize) -> f64 {
        let n = self.n;
        let y = &self.lex_rows[self.lex_pos[i] * n..(self.lex_pos[i] + 1) * n];
        if v < n {
            y[v]
        } else if v < 2 * n {
            // Row i of B⁻¹ times the column −M'_{·j}.
            let j = v - n;
            -(self.mp[j]..self.mp[j + 1])
                .map(|p| y[self.mi[p]] * self.mv[p])
                .sum::<f64>()
        } else {
            -y.iter().zip(&self.d).map(|(a, b)| a * b).sum::<f64>()
        }
    }

    fn reference(&self, k: usize) -> usize {
        if self.start[k] {
            self.n + k
        } else {
            k
        }
    }

    fn pivot(&mut self, r: usize) -> bool {
        let v = self.entering;
        let p = self.c[r];
        if v == NONE || !(p.is_finite() && p != 0.0) {
            return false;
        }
        // Basic values, as the tableau's right-hand side column.
        let theta = self.b[r] / p;
        for (i, (bi, &ci)) in self.b.iter_mut().zip(&self.c).enumerate() {
            if i != r && ci != 0.0 {
                *bi -= ci * theta;
            }
        }
        self.b[r] = theta;
        let leaving = self.basis[r];
        self.basis[r] = v;
        self.row_of[v] = r;
        self.row_of[leaving] = NONE;
        self.entering = NONE;
        self.pivots += 1;
        if self.eta_r.len() + 1 >= REFACTOR_EVERY {
            return self.refactor();
        }
        self.eta_r.push(r);
        self.eta_p.push(p);
        let at = self.eta_d.len();
        self.eta_d.extend_from_slice(&self.c);
        self.eta_d[at + r] = 0.0;
        theta.is_finite()
    }

    fn pivots(&self) -> usize {
        self.pivots
    }
}
