//! A sparse LU of a square matrix in compressed columns, with this
//! module's own triangular solves; shared by the factorised basis of
//! Lemke's method ([`super::revised`]) and the sparse basis solves of
//! principal pivoting ([`super::pivoting`]).
//!
//! The numeric factorisation is faer's simplicial (left-looking,
//! Gilbert–Peierls) LU with partial pivoting, called directly so that its
//! permutations and scratch are kept here; the column order is the
//! caller's (typically the ranks of a COLAMD ordering of the whole problem
//! matrix, [`colamd_rank`], computed once per LCP, applied to the columns
//! of each factorised submatrix). The factors are copied without their
//! diagonals into plain compressed columns, `U`'s diagonal as reciprocals,
//! and the solves skip a column whose entry is zero (a sparse right-hand
//! side stays sparse through much of `L⁻¹`) and allocate nothing.
//!
//! # References
//!
//! * J. R. Gilbert, T. Peierls, "Sparse partial pivoting in time
//!   proportional to arithmetic operations", SIAM J. Sci. Stat. Comput. 9,
//!   1988.
//! * T. A. Davis, J. R. Gilbert, S. I. Larimore, E. G. Ng, "A column
//!   approximate minimum degree ordering algorithm", ACM TOMS 30, 2004.
//! * T. A. Davis, *Direct Methods for Sparse Linear Systems*, SIAM, 2006,
//!   ch. 6.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::colamd;
use faer::sparse::linalg::lu::simplicial::{
    factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch, SimplicialLu,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

/// A sparse matrix in compressed columns, filled column by column:
/// [`Csc::push`] the entries of a column, then [`Csc::end_column`].
#[derive(Default)]
pub(crate) struct Csc {
    /// Start of each column in `i`/`v`, and the end of the last one.
    pub(crate) p: Vec<usize>,
    /// Row index of each entry.
    pub(crate) i: Vec<usize>,
    /// Value of each entry.
    pub(crate) v: Vec<f64>,
}

impl Csc {
    /// Empties the matrix, keeping its allocations.
    pub(crate) fn clear(&mut self) {
        self.p.clear();
        self.p.push(0);
        self.i.clear();
        self.v.clear();
    }

    /// Appends the entry `(row, value)` to the current column.
    pub(crate) fn push(&mut self, row: usize, value: f64) {
        self.i.push(row);
        self.v.push(value);
    }

    /// Closes the current column.
    pub(crate) fn end_column(&mut self) {
        self.p.push(self.i.len());
    }

    /// The `(row, value)` entries of column `j` (inlined: called once per
    /// column in the triangular solves).
    #[inline(always)]
    pub(crate) fn column(&self, j: usize) -> impl Iterator<Item = (&usize, &f64)> {
        let range = self.p[j]..self.p[j + 1];
        self.i[range.clone()].iter().zip(&self.v[range])
    }
}

/// The rank of each column of the `n × n` pattern `(ptr, idx)` (compressed
/// columns) in a COLAMD ordering of it, into `rank`; `fwd` is scratch (it
/// ends as the ordering). `false` if the ordering failed.
pub(crate) fn colamd_rank(
    n: usize,
    ptr: &[usize],
    idx: &[usize],
    fwd: &mut Vec<usize>,
    rank: &mut Vec<usize>,
) -> bool {
    if !valid_pattern(n, ptr, idx) {
        return false;
    }
    let sym = SymbolicSparseColMatRef::new_checked(n, n, ptr, None, idx);
    fwd.resize(n, 0);
    rank.resize(n, 0);
    let req = colamd::order_scratch::<usize>(n, n, idx.len());
    MemBuffer::try_new(req).is_ok_and(|mut mem| {
        colamd::order(
            fwd,
            rank,
            sym,
            colamd::Control::default(),
            MemStack::new(&mut mem),
        )
        .is_ok()
    })
}

/// Whether `(ptr, idx)` is a valid `n × n` compressed-column pattern with
/// rows strictly increasing in each column (what faer's constructors
/// assert).
fn valid_pattern(n: usize, ptr: &[usize], idx: &[usize]) -> bool {
    ptr.len() == n + 1
        && ptr[0] == 0
        && ptr[n] == idx.len()
        && ptr.windows(2).all(|w| {
            w[0] <= w[1]
                && w[1] <= idx.len()
                && idx[w[0]..w[1]].iter().all(|&i| i < n)
                && idx[w[0]..w[1]].windows(2).all(|r| r[0] < r[1])
        })
}

/// `P_r A P_c = L U` of a square sparse matrix `A`; see the module doc.
#[derive(Default)]
pub(crate) struct SparseLu {
    /// faer's factors.
    lu: SimplicialLu<usize, f64>,
    /// Order of the matrix `lu` was last factorised for.
    order: usize,
    /// The strictly lower part of `L` (unit diagonal), in compressed sparse
    /// columns, copied from `lu` at each factorisation.
    l: Csc,
    /// The strictly upper part of `U` in compressed sparse columns, and the
    /// reciprocals of its diagonal.
    u: Csc,
    u_inv_diag: Vec<f64>,
    /// Smallest `|U_jj|` of the last factorisation.
    min_pivot: f64,
    /// Row permutation `P_r` (forward: row eliminated at each step;
    /// inverse).
    row_fwd: Vec<usize>,
    row_inv: Vec<usize>,
    /// Column ordering `P_c` (forward: column eliminated at each step;
    /// inverse).
    col_fwd: Vec<usize>,
    col_inv: Vec<usize>,
}

impl SparseLu {
    /// Factorises the `k × k` matrix `a` (compressed columns, rows
    /// increasing in each column) with the column order that `order` writes
    /// into the vector it is given (empty on entry; it must leave a
    /// permutation of `0..k`). `false` if the factorisation failed or a
    /// pivot is not finite, zero or not invertible.
    pub(crate) fn factorise(
        &mut self,
        k: usize,
        a: &Csc,
        order: impl FnOnce(&mut Vec<usize>),
    ) -> bool {
        if k != self.order {
            // faer's simplicial LU keeps the column pointers of a larger
            // previous matrix (it does not shrink them) and then fails its
            // own shape check: start it afresh when the order changes.
            self.lu = SimplicialLu::new();
            self.order = k;
        }
        self.col_fwd.clear();
        order(&mut self.col_fwd);
        if self.col_fwd.len() != k {
            return false;
        }
        self.col_inv.clear();
        self.col_inv.resize(k, usize::MAX);
        for (t, &c) in self.col_fwd.iter().enumerate() {
            if c >= k || self.col_inv[c] != usize::MAX {
                return false;
            }
            self.col_inv[c] = t;
        }
        // faer's constructors panic on invalid input: checked here first.
        if !valid_pattern(k, &a.p, &a.i) || a.v.len() != a.i.len() {
            return false;
        }
        let sym = SymbolicSparseColMatRef::new_checked(k, k, &a.p, None, &a.i);
        let col_perm = faer::perm::PermRef::new_checked(&self.col_fwd, &self.col_inv, k);
        self.row_fwd.resize(k, 0);
        self.row_inv.resize(k, 0);
        let req = factorize_simplicial_numeric_lu_scratch::<usize, f64>(k, k);
        let Ok(mut mem) = MemBuffer::try_new(req) else {
            return false;
        };
        let mat = SparseColMatRef::new(sym, &a.v);
        if factorize_simplicial_numeric_lu(
            &mut self.row_fwd,
            &mut self.row_inv,
            &mut self.lu,
            mat,
            col_perm,
            MemStack::new(&mut mem),
        )
        .is_err()
        {
            return false;
        }
        // The factors without their diagonals, for the solves, and U's
        // diagonal as reciprocals (as faer's own triangular solve applies
        // it).
        let (l, u) = (self.lu.l_factor_unsorted(), self.lu.u_factor_unsorted());
        self.l.clear();
        self.u.clear();
        self.u_inv_diag.clear();
        self.u_inv_diag.resize(k, 0.0);
        self.min_pivot = f64::INFINITY;
        for j in 0..k {
            for (&i, &v) in l.row_idx_of_col_raw(j).iter().zip(l.val_of_col(j)) {
                if i != j {
                    self.l.push(i, v);
                }
            }
            self.l.end_column();
            for (&i, &v) in u.row_idx_of_col_raw(j).iter().zip(u.val_of_col(j)) {
                if i == j {
                    self.u_inv_diag[j] = v.recip();
                    self.min_pivot = self.min_pivot.min(v.abs());
                } else {
                    self.u.push(i, v);
                }
            }
            self.u.end_column();
        }
        self.u_inv_diag.iter().all(|d| d.is_finite())
    }

    /// Smallest `|U_jj|` of the last factorisation (`INFINITY` for k = 0).
    pub(crate) fn min_pivot(&self) -> f64 {
        self.min_pivot
    }

    /// `P_r`: the row of `A` eliminated at each step.
    pub(crate) fn row_fwd(&self) -> &[usize] {
        &self.row_fwd
    }

    /// `P_r⁻¹`: the step at which each row of `A` is eliminated.
    pub(crate) fn row_inv(&self) -> &[usize] {
        &self.row_inv
    }

    /// `P_c`: the column of `A` eliminated at each step.
    pub(crate) fn col_fwd(&self) -> &[usize] {
        &self.col_fwd
    }

    /// `P_c⁻¹`: the step at which each column of `A` is eliminated.
    pub(crate) fn col_inv(&self) -> &[usize] {
        &self.col_inv
    }

    /// `t ← U⁻¹ L⁻¹ t` in the permuted order: on entry `t[s] = b[P_r(s)]`,
    /// on exit `t[s] = x[P_c(s)]` for `A x = b`. By columns; a column whose
    /// entry is 0 is skipped.
    #[inline(always)]
    pub(crate) fn forward_permuted(&self, t: &mut [f64]) {
        let k = self.u_inv_diag.len();
        for j in 0..k {
            let xj = t[j];
            if xj != 0.0 {
                for (&i, &a) in self.l.column(j) {
                    t[i] -= a * xj;
                }
            }
        }
        for j in (0..k).rev() {
            if t[j] != 0.0 {
                let xj = t[j] * self.u_inv_diag[j];
                t[j] = xj;
                for (&i, &a) in self.u.column(j) {
                    t[i] -= a * xj;
                }
            }
        }
    }

    /// `t ← L⁻ᵀ U⁻ᵀ t` in the permuted order: on entry `t[s] = c[P_c(s)]`,
    /// on exit `t[s] = y[P_r(s)]` for `Aᵀ y = c`. Each entry is a dot
    /// product with its column.
    #[inline(always)]
    pub(crate) fn transposed_permuted(&self, t: &mut [f64]) {
        let k = self.u_inv_diag.len();
        for j in 0..k {
            let mut acc = t[j];
            for (&i, &a) in self.u.column(j) {
                acc -= a * t[i];
            }
            t[j] = acc * self.u_inv_diag[j];
        }
        for j in (0..k).rev() {
            let mut acc = t[j];
            for (&i, &a) in self.l.column(j) {
                acc -= a * t[i];
            }
            t[j] = acc;
        }
    }
}
