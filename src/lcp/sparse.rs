//! Compressed sparse columns of a dense row-major matrix, and the driver's
//! compensated residual `w = M z + q` over them for large LCPs.
//!
//! The contact LCPs of a jammed pack are large (hundreds to a few thousand
//! unknowns) and sparse: a contact couples only with the contacts sharing
//! one of its floes, so a few percent of `M` is non-zero. The driver
//! ([`super::solve()`]) evaluates `w = M z + q` on the original data after
//! every attempt and every refinement step, each a compensated (Dot2) sum
//! per row (Ogita, Rump & Oishi 2005); over the dense rows that is `n²`
//! error-free products per evaluation. [`SparseResidual`] builds the
//! compressed sparse columns of `M` once per solve and evaluates the same
//! sums over the non-zero entries of the columns where `z_j ≠ 0`: per row
//! `i` it keeps the running sum `p_i` and compensation `s_i` of Dot2 and
//! adds the terms column after column, so each row sees its non-zero terms
//! in increasing `j` — the operations of the dense row sum without its
//! zero terms. A term `M_ij z_j` with `M_ij = 0` or `z_j = 0` (finite `M`)
//! adds exact zeros to both `p_i` and `s_i`, so the result is the same
//! number; only the sign of a zero `w_i` may differ (the dense sum adds
//! `+0` terms). The same argument as the support sums of
//! [`super::arith::w_into`] for small problems.
//!
//! # References
//!
//! * T. Ogita, S. M. Rump, S. Oishi, "Accurate sum and dot product", SIAM J.
//!   Sci. Comput. 26(6), 2005 (Dot2).
//! * T. A. Davis, *Direct Methods for Sparse Linear Systems*, SIAM, 2006,
//!   ch. 2 (compressed sparse columns).

use super::arith::{dot2_plus, two_prod, two_sum, SUPPORT_MAX_N};
use super::scaling::max_abs_finite;

/// The compressed sparse columns of the non-zero entries of a row-major
/// `n × n` matrix (`ptr`, `idx`, `val`; rows increasing within each
/// column), with the scratch of the one pass that builds them.
#[derive(Debug, Clone, Default)]
pub(crate) struct Columns {
    /// Start of each column in `idx` and `val`; `n + 1` entries.
    pub(crate) ptr: Vec<usize>,
    /// Row of each stored entry.
    pub(crate) idx: Vec<usize>,
    /// Value of each stored entry.
    pub(crate) val: Vec<f64>,
    /// The non-zeros gathered row by row (start of each row, column,
    /// value), transposed into the columns.
    row_ptr: Vec<usize>,
    row_col: Vec<usize>,
    row_val: Vec<f64>,
}

impl Columns {
    /// Builds the columns of the row-major `n × n` matrix `m` by **one**
    /// pass over its entries, and returns what the driver needs of that
    /// pass too: `max|M_ij|` (the number [`max_abs`] gives: NaN entries
    /// skipped) and whether every entry is finite. The pass gathers each
    /// row's non-zeros (and, row by row, the maxima); the transposition
    /// into columns then reads only the non-zeros. A NaN entry is stored
    /// (it is not `== 0`).
    ///
    /// [`max_abs`]: super::scaling::max_abs
    pub(crate) fn scan(&mut self, m: &[f64], n: usize) -> (f64, bool) {
        self.row_ptr.clear();
        self.row_ptr.push(0);
        self.row_col.clear();
        self.row_val.clear();
        let mut mmax = 0.0_f64;
        let mut finite = true;
        for row in m.chunks_exact(n.max(1)).take(n) {
            let (a, f) = max_abs_finite(row);
            if a > mmax {
                mmax = a;
            }
            finite &= f;
            for (j, &a) in row.iter().enumerate() {
                if a != 0.0 {
                    self.row_col.push(j);
                    self.row_val.push(a);
                }
            }
            self.row_ptr.push(self.row_col.len());
        }
        let ptr = &mut self.ptr;
        ptr.clear();
        ptr.resize(n + 1, 0);
        for &j in &self.row_col {
            ptr[j + 1] += 1;
        }
        for j in 0..n {
            ptr[j + 1] += ptr[j];
        }
        let nnz = ptr[n];
        self.idx.clear();
        self.idx.resize(nnz, 0);
        self.val.clear();
        self.val.resize(nnz, 0.0);
        // ptr[j] is the next free slot of column j while placing, and ends
        // as the start of column j + 1; shifted back below. Rows are placed
        // in increasing order.
        for (i, w) in self.row_ptr.windows(2).enumerate() {
            for at in w[0]..w[1] {
                let j = self.row_col[at];
                let to = ptr[j];
                self.idx[to] = i;
                self.val[to] = self.row_val[at];
                ptr[j] = to + 1;
            }
        }
        for j in (1..=n).rev() {
            ptr[j] = ptr[j - 1];
        }
        ptr[0] = 0;
        (mmax, finite)
    }
}

impl Columns {
    /// The columns of the row-major `n × n` matrix `m` from a superset of
    /// its non-zero pattern: `candidates(j)` lists rows (in any order,
    /// repeats allowed) outside which column `j` of `m` is zero. Only the
    /// candidates are read, so a caller that knows the pattern (the contact
    /// assembly) saves the pass over all `n²` entries; the result is what
    /// [`Columns::scan`] builds (the candidates that hold a zero are
    /// dropped, rows increasing). `rows` is scratch.
    pub(crate) fn fill_from_candidates<'a>(
        &mut self,
        m: &[f64],
        n: usize,
        candidates: impl Fn(usize) -> &'a [usize],
        rows: &mut Vec<usize>,
    ) {
        self.ptr.clear();
        self.ptr.push(0);
        self.idx.clear();
        self.val.clear();
        // The rows of a previous scan are not these.
        self.row_ptr.clear();
        for j in 0..n {
            rows.clear();
            rows.extend_from_slice(candidates(j));
            rows.sort_unstable();
            rows.dedup();
            for &i in rows.iter() {
                let a = m[i * n + j];
                if a != 0.0 {
                    self.idx.push(i);
                    self.val.push(a);
                }
            }
            self.ptr.push(self.idx.len());
        }
    }

    /// The non-zeros of row `i` (columns increasing, and their values), as
    /// the last [`Columns::scan`] gathered them; empty after
    /// [`Columns::fill_from_candidates`], which does not build the rows.
    pub(crate) fn row(&self, i: usize) -> (&[usize], &[f64]) {
        match (self.row_ptr.get(i), self.row_ptr.get(i + 1)) {
            (Some(&a), Some(&b)) if b <= self.row_col.len() => {
                (&self.row_col[a..b], &self.row_val[a..b])
            }
            _ => (&[], &[]),
        }
    }

    /// The largest `|M_ij|` of the stored entries (NaN skipped) and whether
    /// they are all finite: those of the whole matrix, the others being
    /// zeros.
    pub(crate) fn max_abs_finite(&self) -> (f64, bool) {
        max_abs_finite(&self.val)
    }

    /// Whether `self` and `other` hold the same entries, bit for bit.
    pub(crate) fn same_as(&self, other: &Columns) -> bool {
        self.ptr == other.ptr
            && self.idx == other.idx
            && self.val.len() == other.val.len()
            && self
                .val
                .iter()
                .zip(&other.val)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

/// The driver's residual `w = M z + q` on the compressed columns of `M`,
/// built by [`SparseResidual::scan`] or at the first evaluation of a solve
/// ([`SparseResidual::reset`] starts a solve); the buffers are kept across
/// solves. See the module doc.
#[derive(Debug, Clone, Default)]
pub(crate) struct SparseResidual {
    built: bool,
    cols: Columns,
    /// Running Dot2 sums and compensations per row.
    p: Vec<f64>,
    s: Vec<f64>,
}

impl SparseResidual {
    /// Forgets the matrix of the previous solve.
    pub(crate) fn reset(&mut self) {
        self.built = false;
    }

    /// Builds the columns of this solve's `m` (`n × n`) now, by
    /// [`Columns::scan`], and returns the maximum and finiteness that scan
    /// reads on the way; the driver's one pass over a large `M`.
    pub(crate) fn scan(&mut self, m: &[f64], n: usize) -> (f64, bool) {
        let out = self.cols.scan(m, n);
        self.built = true;
        out
    }

    /// Takes the columns of this solve's `M` from a caller that built them
    /// (a copy of their non-zeros), and returns `max|M_ij|` and whether `M`
    /// is finite, as [`SparseResidual::scan`] would.
    pub(crate) fn adopt(&mut self, cols: &Columns) -> (f64, bool) {
        self.cols.ptr.clone_from(&cols.ptr);
        self.cols.idx.clone_from(&cols.idx);
        self.cols.val.clone_from(&cols.val);
        self.built = true;
        cols.max_abs_finite()
    }

    /// The columns of this solve's `M`, if built.
    pub(crate) fn columns(&self) -> Option<&Columns> {
        self.built.then_some(&self.cols)
    }

    /// `w = M z + q` for the `M` of this solve (the same `m` at every call
    /// between two [`SparseResidual::reset`]s), the number
    /// [`super::arith::w_into`] gives (up to the sign of a zero): up to
    /// [`SUPPORT_MAX_N`] unknowns or for a matrix not known to be finite,
    /// by [`super::arith::w_into`] itself; above, over the compressed columns.
    pub(crate) fn w_into(
        &mut self,
        m: &[f64],
        q: &[f64],
        z: &[f64],
        w: &mut [f64],
        m_finite: bool,
    ) {
        let n = q.len();
        if !m_finite || n <= SUPPORT_MAX_N || z.len() != n || m.len() != n * n {
            super::arith::w_into(m, q, z, w, m_finite);
            return;
        }
        if !self.built {
            self.cols.scan(m, n);
            self.built = true;
        }
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("fma") {
                // SAFETY: the CPU supports FMA, checked just above.
                unsafe { self.sums_fma(q, z) };
                self.finish(m, q, z, w);
                return;
            }
        }
        self.sums(q, z, two_prod);
        self.finish(m, q, z, w);
    }

    /// [`SparseResidual::sums`] compiled with FMA (the products' errors are
    /// `fma(a, b, −ab)`, as in the dense sum on such a CPU).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "fma")]
    unsafe fn sums_fma(&mut self, q: &[f64], z: &[f64]) {
        self.sums(q, z, |a, b| {
            let h = a * b;
            (h, a.mul_add(b, -h))
        });
    }

    /// The Dot2 sums of every row, column by column over the support of `z`.
    #[inline(always)]
    fn sums(&mut self, q: &[f64], z: &[f64], prod: impl Fn(f64, f64) -> (f64, f64)) {
        self.p.clear();
        self.p.extend_from_slice(q);
        self.s.clear();
        self.s.resize(q.len(), 0.0);
        for (j, &zj) in z.iter().enumerate() {
            if zj == 0.0 {
                continue;
            }
            let c = &self.cols;
            for at in c.ptr[j]..c.ptr[j + 1] {
                let i = c.idx[at];
                let (h, r) = prod(c.val[at], zj);
                let (np, t) = two_sum(self.p[i], h);
                self.p[i] = np;
                self.s[i] += t + r;
            }
        }
    }

    /// `w_i = p_i + s_i`; a row whose sum is not finite (an overflow of the
    /// unscaled sum) is recomputed by [`dot2_plus`] on the dense row, as
    /// [`super::arith::w_into`] does.
    fn finish(&self, m: &[f64], q: &[f64], z: &[f64], w: &mut [f64]) {
        let n = q.len();
        for (i, wi) in w.iter_mut().enumerate().take(n) {
            let v = self.p[i] + self.s[i];
            *wi = if v.is_finite() {
                v
            } else {
                dot2_plus(&m[i * n..(i + 1) * n], z, q[i])
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// A sparse row-major matrix with entries spread over 16 binades and
    /// cancelling signs, and a `z` with a third of zeros.
    fn problem(rng: &mut SplitMix64, n: usize, density: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut u = || rng.uniform();
        let mut m = vec![0.0; n * n];
        for x in m.iter_mut() {
            if u() < density {
                *x = (u() - 0.5) * 10f64.powf(16.0 * u() - 8.0);
            }
        }
        let z: Vec<f64> = (0..n)
            .map(|_| {
                if u() < 0.33 {
                    0.0
                } else {
                    u() * 10f64.powf(6.0 * u() - 3.0)
                }
            })
            .collect();
        // Half of the rows cancel to the rounding of their terms (q_i the
        // opposite of the plain sum): there the compensated sum's last bits
        // depend on the order of its terms.
        let q: Vec<f64> = (0..n)
            .map(|i| {
                if i % 2 == 0 {
                    -(0..n).map(|j| m[i * n + j] * z[j]).sum::<f64>()
                } else {
                    (u() - 0.5) * 10f64.powf(4.0 * u() - 2.0)
                }
            })
            .collect();
        (m, q, z)
    }

    #[test]
    fn sparse_residual_equals_the_dense_compensated_sum_bit_for_bit() {
        let mut rng = SplitMix64::new(12);
        let mut sp = SparseResidual::default();
        let mut compared = 0;
        for (n, density) in [(65, 0.3), (150, 0.05), (400, 0.02), (400, 1.0)] {
            for _ in 0..4 {
                let (m, q, z) = problem(&mut rng, n, density);
                let mut dense = vec![0.0; n];
                crate::lcp::arith::w_into(&m, &q, &z, &mut dense, false);
                sp.reset();
                let mut got = vec![f64::NAN; n];
                sp.w_into(&m, &q, &z, &mut got, true);
                // Twice on the same matrix: the columns built once are reused.
                let mut again = vec![f64::NAN; n];
                sp.w_into(&m, &q, &z, &mut again, true);
                for i in 0..n {
                    let same = got[i].to_bits() == dense[i].to_bits()
                        || (got[i] == 0.0 && dense[i] == 0.0);
                    assert!(same, "n = {n}, row {i}: {:e} vs {:e}", got[i], dense[i]);
                    assert_eq!(got[i].to_bits(), again[i].to_bits());
                    compared += usize::from(dense[i] != 0.0);
                }
            }
        }
        assert!(compared > 3000, "{compared}");
    }

    #[test]
    fn compressed_columns_hold_every_non_zero_in_row_order() {
        let mut rng = SplitMix64::new(3);
        let (m, _, _) = problem(&mut rng, 70, 0.1);
        let mut c = Columns::default();
        // Twice: the second scan reuses the buffers of the first.
        for _ in 0..2 {
            let (mmax, finite) = c.scan(&m, 70);
            assert!(finite);
            assert_eq!(mmax, crate::lcp::scaling::max_abs(&m));
            let (p, i, v) = (&c.ptr, &c.idx, &c.val);
            let mut back = vec![0.0; 70 * 70];
            for j in 0..70 {
                assert!(i[p[j]..p[j + 1]].windows(2).all(|w| w[0] < w[1]));
                for at in p[j]..p[j + 1] {
                    back[i[at] * 70 + j] = v[at];
                }
            }
            assert_eq!(back, m);
            assert_eq!(p[70], m.iter().filter(|x| **x != 0.0).count());
        }
        // A non-finite entry is reported (and stored); the maximum skips a NaN.
        let mut bad = m.clone();
        bad[5] = f64::NAN;
        bad[7] = f64::INFINITY;
        let (mmax, finite) = c.scan(&bad, 70);
        assert!(!finite);
        assert_eq!(mmax, f64::INFINITY);
        assert!(c.val.iter().any(|x| x.is_nan()));
    }
}
