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
use super::sparse_lu::{colamd_rank, Csc, SparseLu};

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

    /// `x ← B⁻¹ x` (FTRAN), with its own scratch (the refinement of a
    /// candidate: a few calls per solve).
    pub(crate) fn solve(&self, x: &mut [f64]) {
        self.ftran(x, &mut Vec::new());
    }

    /// `x ← B⁻¹ x` (FTRAN): the LU of `B₀`, then the etas in order; `tmp`
    /// is scratch.
    fn ftran(&self, x: &mut [f64], tmp: &mut Vec<f64>) {
        let n = self.n;
        if self.factorised {
            self.lu_solve(x, tmp, false);
        }
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU supports AVX2, checked just above.
                unsafe { self.etas_forward_avx2(x, n) };
                return;
            }
        }
        self.etas_forward(x, n);
    }

    /// [`Revised::etas_forward`] compiled for AVX2: the same multiplies and
    /// subtracts (no fused multiply–add: bit for bit the same results),
    /// four to a vector instead of two.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn etas_forward_avx2(&self, x: &mut [f64], n: usize) {
        self.etas_forward(x, n);
    }

    /// `x ← E_k⁻¹ ⋯ E_1⁻¹ x`: the eta file in order, each a dense update of
    /// `x` by its stored column (the hottest loop of a large solve).
    #[inline(always)]
    fn etas_forward(&self, x: &mut [f64], n: usize) {
        for k in 0..self.eta_r.len() {
            let r = self.eta_r[k];
            let xr = x[r] / self.eta_p[k];
            x[r] = xr;
            if xr != 0.0 {
                let eta = &self.eta_d[k * n..(k + 1) * n];
                for (xi, &e) in x.iter_mut().zip(eta) {
                    *xi -= e * xr;
                }
            }
        }
    }

    /// `y ← B⁻ᵀ y` (BTRAN): the etas in reverse order, then the transposed
    /// LU of `B₀`; `tmp` is scratch. With `y = e_i` on entry, `y` is row i
    /// of `B⁻¹`.
    fn btran(&self, y: &mut [f64], tmp: &mut Vec<f64>) {
        let n = self.n;
        for k in (0..self.eta_r.len()).rev() {
            let r = self.eta_r[k];
            let mut acc = y[r];
            let eta = &self.eta_d[k * n..(k + 1) * n];
            for (&e, &yi) in eta.iter().zip(y.iter()) {
                acc -= e * yi;
            }
            y[r] = acc / self.eta_p[k];
        }
        if self.factorised {
            self.lu_solve(y, tmp, true);
        }
    }

    /// `x ← B₀⁻¹ x`, or `x ← B₀⁻ᵀ x` when `transpose`, by the reduced form
    /// of [`Revised::refactor`]; `tmp` is scratch.
    ///
    /// Forward (`x` by rows in, by slots out): `K x_K = a_R` by the LU, then
    /// `x_{slot(w_i)} = a_i − (C x_K)_i` for the rows i whose `w_i` is
    /// basic. Transposed (`y` by slots in, by rows out): `y_i = c_{slot(w_i)}`
    /// for those rows, then `Kᵀ y_R = c_K − Cᵀ y_W` by the LU.
    fn lu_solve(&self, x: &mut [f64], tmp: &mut Vec<f64>, transpose: bool) {
        let (n, k) = (self.n, self.k);
        // The input, read while `x` is overwritten by the output.
        tmp.clear();
        tmp.extend_from_slice(x);
        tmp.resize(n + k, 0.0);
        let (xin, tmp) = tmp.split_at_mut(n);
        if transpose {
            for (i, &s) in self.w_slot.iter().enumerate() {
                if s != NONE {
                    x[i] = xin[s];
                }
            }
            if k == 0 {
                return;
            }
            // r_c = c_{slot(c)} − Σ C_ic y_i, in the LU's column order.
            for (t, &c) in tmp.iter_mut().zip(self.lu.col_fwd()) {
                let mut r = xin[self.k_slots[c]];
                for (&i, &a) in self.cmat.column(c) {
                    r -= a * x[i];
                }
                *t = r;
            }
            // Uᵀ, then Lᵀ.
            self.lu.transposed_permuted(tmp);
            for (&i, &t) in self.k_rows.iter().zip(self.lu.row_inv()) {
                x[i] = tmp[t];
            }
        } else {
            if k > 0 {
                for (t, &r) in tmp.iter_mut().zip(self.lu.row_fwd()) {
                    *t = xin[self.k_rows[r]];
                }
                // L, then U, by columns: a column whose entry is 0 is
                // skipped (the entering column −M'_{·j} is sparse, and so
                // stays much of L⁻¹ of it).
                self.lu.forward_permuted(tmp);
                for (&s, &t) in self.k_slots.iter().zip(self.lu.col_inv()) {
                    x[s] = tmp[t];
                }
            }
            for (i, &s) in self.w_slot.iter().enumerate() {
                if s != NONE {
                    x[s] = xin[i];
                }
            }
            for (c, &s) in self.k_slots.iter().enumerate() {
                let xs = x[s];
                if xs != 0.0 {
                    for (&i, &a) in self.cmat.column(c) {
                        x[self.w_slot[i]] -= a * xs;
                    }
                }
            }
        }
    }

    /// Factorises the current basis as the new `B₀`, empties the eta file and
    /// recomputes `b = B⁻¹ q'`. `false` if the basis is singular or the
    /// factorisation failed.
    ///
    /// Only the block of `B₀` that is not an identity is factorised. A slot
    /// whose variable is `w_i` holds the unit column `e_i`; the other `k`
    /// slots (`z_j`: `−M'_{·j}`, `z0`: `−d'`) and the `k` rows whose `w` is
    /// not basic form the square block `K`, and the rows of the `z` columns
    /// whose `w` is basic form the coupling `C`. Up to a permutation `B₀`
    /// is block triangular, `[[I, C], [0, K]]`, so a solve with `B₀` is a
    /// solve with `K` and a product with `C` ([`Revised::lu_solve`]). On the
    /// bases of a jammed pack's Lemke path about half of the slots are `w`:
    /// the ordering, the LU and the triangular solves work on about half the
    /// order and fewer non-zeros.
    fn refactor(&mut self) -> bool {
        let n = self.n;
        self.factorised = false;
        self.w_slot.clear();
        self.w_slot.resize(n, NONE);
        self.k_slots.clear();
        for (s, &v) in self.basis.iter().enumerate() {
            if v < n {
                self.w_slot[v] = s;
            } else {
                self.k_slots.push(s);
            }
        }
        let mut k_pos = std::mem::take(&mut self.k_pos);
        k_pos.clear();
        k_pos.resize(n, NONE);
        self.k_rows.clear();
        for (i, (pos, &ws)) in k_pos.iter_mut().zip(&self.w_slot).enumerate() {
            if ws == NONE {
                *pos = self.k_rows.len();
                self.k_rows.push(i);
            }
        }
        let k = self.k_slots.len();
        if self.k_rows.len() != k {
            self.k_pos = k_pos;
            return false;
        }
        self.k = k;
        self.kmat.clear();
        self.cmat.clear();
        for &s in &self.k_slots {
            let v = self.basis[s];
            let mut put = |i: usize, a: f64| {
                if k_pos[i] == NONE {
                    self.cmat.push(i, a);
                } else {
                    self.kmat.push(k_pos[i], a);
                }
            };
            if v < 2 * n {
                let j = v - n;
                for p in self.mp[j]..self.mp[j + 1] {
                    put(self.mi[p], -self.mv[p]);
                }
            } else {
                for (i, &d) in self.d.iter().enumerate() {
                    put(i, -d);
                }
            }
            self.kmat.end_column();
            self.cmat.end_column();
        }
        self.k_pos = k_pos;
        if k > 0 && !self.factorise_k() {
            return false;
        }
        self.factorised = true;
        self.clear_etas();
        let mut b = std::mem::take(&mut self.b);
        let mut tmp = std::mem::take(&mut self.tmp);
        b.copy_from_slice(&self.q);
        self.ftran(&mut b, &mut tmp);
        let finite = b.iter().all(|x| x.is_finite());
        self.b = b;
        self.tmp = tmp;
        finite
    }

    /// The ranks of M's columns in COLAMD's ordering of M' (`rank`); `false`
    /// if the ordering failed.
    fn rank_columns_of_m(&mut self) -> bool {
        let ok = colamd_rank(self.n, &self.mp, &self.mi, &mut self.order, &mut self.rank);
        self.ranked = ok;
        ok
    }

    /// The sparse LU of `K` (order `self.k > 0`, in `kmat`), with
    /// partial pivoting. Its columns are ordered by one COLAMD ordering of
    /// M's columns per solve rather than an ordering of each `K`: `K` is
    /// nearly a principal submatrix of M (its rows are those of the basic
    /// `z` but for one), and on the 40 bay-jam LCPs of more than 800
    /// unknowns (`floebench lcp DIR --time`) this took 9.0–10.1 s against
    /// 11.5–13.5 s with COLAMD at every factorisation, the same pivots to
    /// ±2 (rounding).
    fn factorise_k(&mut self) -> bool {
        if !self.ranked && !self.rank_columns_of_m() {
            return false;
        }
        // K's columns by the rank of their variable (z0's column, dense,
        // last): sorting k keys costs far less than an ordering of K.
        let (n, k) = (self.n, self.k);
        let (basis, k_slots, rank) = (&self.basis, &self.k_slots, &self.rank);
        self.lu.factorise(k, &self.kmat, |order| {
            order.extend(0..k);
            order.sort_unstable_by_key(|&c| match basis[k_slots[c]] {
                v if v < 2 * n => rank[v - n],
                _ => n,
            });
        })
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

#[cfg(test)]
mod tests {
    use super::*;

    /// SplitMix64 in [-1, 1): the test data, reproducible.
    fn uniform(state: &mut u64) -> f64 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// `‖B x − a‖∞` for the current basis `B` of `e`, densely.
    fn defect(e: &Revised, x: &[f64], a: &[f64]) -> f64 {
        let n = e.n;
        let mut col = vec![0.0; n];
        let mut bx = vec![0.0; n];
        for (s, &xs) in x.iter().enumerate() {
            e.column(e.basis[s], &mut col);
            for (o, &c) in bx.iter_mut().zip(&col) {
                *o += c * xs;
            }
        }
        bx.iter()
            .zip(a)
            .map(|(u, v)| (u - v).abs())
            .fold(0.0, f64::max)
    }

    /// A dense random M with a dominant diagonal (n = 12) and the basis whose
    /// slot s holds variable `vars[s]`, refactorised; FTRAN and BTRAN are
    /// then checked against the basis densely.
    fn check_basis(vars: &[usize]) {
        let n = vars.len();
        let mut st = 0x0B5E_55ED_u64;
        let mut m: Vec<f64> = (0..n * n).map(|_| uniform(&mut st)).collect();
        for i in 0..n {
            m[i * n + i] += 2.0 * n as f64;
        }
        let q: Vec<f64> = (0..n).map(|_| uniform(&mut st)).collect();
        let mut e = Revised::default();
        e.setup(&m, &q, &vec![1.0; n], (0, 0), None);
        e.row_of.iter_mut().for_each(|r| *r = NONE);
        for (s, &v) in vars.iter().enumerate() {
            e.basis[s] = v;
            e.row_of[v] = s;
        }
        assert!(e.refactor(), "{vars:?}");
        let mut tmp = Vec::new();
        let a: Vec<f64> = (0..n).map(|_| uniform(&mut st)).collect();
        let mut x = a.clone();
        e.ftran(&mut x, &mut tmp);
        assert!(defect(&e, &x, &a) <= 1e-12, "FTRAN {vars:?}");
        let mut col = vec![0.0; n];
        for i in 0..n {
            let mut y = vec![0.0; n];
            y[i] = 1.0;
            e.btran(&mut y, &mut tmp);
            for s in 0..n {
                e.column(e.basis[s], &mut col);
                let ys: f64 = y.iter().zip(&col).map(|(u, v)| u * v).sum();
                let want = if s == i { 1.0 } else { 0.0 };
                assert!((ys - want).abs() <= 1e-12, "BTRAN row {i} {vars:?}");
            }
        }
    }

    #[test]
    fn the_reduced_factorisation_inverts_bases_of_any_mix_of_w_and_z_columns() {
        let n = 12;
        // Only w columns, permuted among the slots: K is empty (k = 0).
        check_basis(&(0..n).map(|s| (s * 5) % n).collect::<Vec<_>>());
        // Only z columns, permuted: K is the whole basis (k = n).
        check_basis(&(0..n).map(|s| n + (s * 7) % n).collect::<Vec<_>>());
        // z0 and a mix, w_i in slots other than i: K of order 5.
        let vars = [2 * n, 3, n + 1, 0, n + 5, 7, 8, n + 11, 2, 10, n + 4, 6];
        check_basis(&vars);
    }

    #[test]
    fn ftran_and_btran_invert_the_basis_through_refactorisations() {
        // A banded sparse M (n = 50), the covering column 1: z0 enters
        // first (the dense column of every later basis), then z_j or w_j
        // in turn on the row of the largest entry of the entering column,
        // for 3 refactorisation periods. After every pivot FTRAN solves
        // B x = a, BTRAN gives the rows of B⁻¹ (y · B = e_i), and b = B⁻¹ q,
        // each to 1e-11, with the basis checked densely.
        let n = 50;
        let mut st = 0x5EED_F10E_0050_u64;
        let mut m = vec![0.0; n * n];
        for i in 0..n {
            m[i * n + i] = 4.0 + uniform(&mut st);
            for j in i.saturating_sub(3)..(i + 4).min(n) {
                if j != i && uniform(&mut st) > 0.0 {
                    m[i * n + j] = uniform(&mut st);
                }
            }
        }
        let q: Vec<f64> = (0..n).map(|_| uniform(&mut st)).collect();
        let mut e = Revised::default();
        e.setup(&m, &q, &vec![1.0; n], (0, 0), None);
        let mut tmp = Vec::new();
        let mut refactorised = 0;
        let mut j = 0;
        while e.pivots() < 3 * REFACTOR_EVERY + 5 {
            let v = if e.pivots() == 0 {
                2 * n
            } else if e.row_of(n + j % n) == NONE {
                n + j % n
            } else {
                j % n
            };
            j += 7;
            if e.row_of(v) != NONE {
                continue;
            }
            assert!(e.load(v));
            let r = (0..n)
                .max_by(|&a, &b| e.c(a).abs().total_cmp(&e.c(b).abs()))
                .unwrap_or(0);
            assert!(e.pivot(r), "pivot {}", e.pivots());
            refactorised += usize::from(e.eta_r.is_empty());
            let a: Vec<f64> = (0..n).map(|_| uniform(&mut st)).collect();
            let mut x = a.clone();
            e.ftran(&mut x, &mut tmp);
            assert!(defect(&e, &x, &a) <= 1e-11, "FTRAN at pivot {}", e.pivots());
            let b: Vec<f64> = (0..n).map(|i| e.b(i)).collect();
            assert!(defect(&e, &b, &e.q) <= 1e-11, "b at pivot {}", e.pivots());
            let mut col = vec![0.0; n];
            for i in [0, n / 2, n - 1] {
                let mut y = vec![0.0; n];
                y[i] = 1.0;
                e.btran(&mut y, &mut tmp);
                for s in 0..n {
                    e.column(e.basis[s], &mut col);
                    let ys: f64 = y.iter().zip(&col).map(|(u, v)| u * v).sum();
                    let want = if s == i { 1.0 } else { 0.0 };
                    assert!(
                        (ys - want).abs() <= 1e-11,
                        "BTRAN row {i} at {}",
                        e.pivots()
                    );
                }
            }
        }
        assert!(refactorised >= 3, "{refactorised} refactorisations");
    }
}
