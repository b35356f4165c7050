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
//! [`super::w_into`] for small problems.
//!
//! # References
//!
//! * T. Ogita, S. M. Rump, S. Oishi, "Accurate sum and dot product", SIAM J.
//!   Sci. Comput. 26(6), 2005 (Dot2).
//! * T. A. Davis, *Direct Methods for Sparse Linear Systems*, SIAM, 2006,
//!   ch. 2 (compressed sparse columns).

use super::{dot2_plus, two_prod, two_sum, SUPPORT_MAX_N};

/// Fills the compressed sparse columns (`ptr`, `idx`, `val`) of the
/// non-zero entries of the row-major `n × n` matrix `m`, each value mapped
/// by `f`, rows increasing within each column. Two passes in row order
/// (count per column, then place): the matrix is read along its rows, not
/// down its columns.
pub(crate) fn csc_of_rows(
    m: &[f64],
    n: usize,
    f: impl Fn(f64) -> f64,
    ptr: &mut Vec<usize>,
    idx: &mut Vec<usize>,
    val: &mut Vec<f64>,
) {
    ptr.clear();
    ptr.resize(n + 1, 0);
    for row in m.chunks_exact(n.max(1)).take(n) {
        for (j, &a) in row.iter().enumerate() {
            ptr[j + 1] += usize::from(a != 0.0);
        }
    }
    for j in 0..n {
        ptr[j + 1] += ptr[j];
    }
    let nnz = ptr[n];
    idx.clear();
    idx.resize(nnz, 0);
    val.clear();
    val.resize(nnz, 0.0);
    // ptr[j] is the next free slot of column j while placing, and ends as
    // the start of column j + 1; shifted back below.
    for (i, row) in m.chunks_exact(n.max(1)).take(n).enumerate() {
        for (j, &a) in row.iter().enumerate() {
            if a != 0.0 {
                let at = ptr[j];
                idx[at] = i;
                val[at] = f(a);
                ptr[j] = at + 1;
            }
        }
    }
    for j in (1..=n).rev() {
        ptr[j] = ptr[j - 1];
    }
    ptr[0] = 0;
}

/// The driver's residual `w = M z + q` on the compressed columns of `M`,
/// built at the first evaluation of a solve ([`SparseResidual::reset`]
/// starts a solve); the buffers are kept across solves. See the module doc.
#[derive(Debug, Clone, Default)]
pub(crate) struct SparseResidual {
    built: bool,
    ptr: Vec<usize>,
    idx: Vec<usize>,
    val: Vec<f64>,
    /// Running Dot2 sums and compensations per row.
    p: Vec<f64>,
    s: Vec<f64>,
}

impl SparseResidual {
    /// Forgets the matrix of the previous solve.
    pub(crate) fn reset(&mut self) {
        self.built = false;
    }

    /// `w = M z + q` for the `M` of this solve (the same `m` at every call
    /// between two [`SparseResidual::reset`]s), the number
    /// [`super::w_into`] gives (up to the sign of a zero): up to
    /// [`SUPPORT_MAX_N`] unknowns or for a matrix not known to be finite,
    /// by [`super::w_into`] itself; above, over the compressed columns.
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
            super::w_into(m, q, z, w, m_finite);
            return;
        }
        if !self.built {
            csc_of_rows(m, n, |a| a, &mut self.ptr, &mut self.idx, &mut self.val);
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
            for at in self.ptr[j]..self.ptr[j + 1] {
                let i = self.idx[at];
                let (h, r) = prod(self.val[at], zj);
                let (np, t) = two_sum(self.p[i], h);
                self.p[i] = np;
                self.s[i] += t + r;
            }
        }
    }

    /// `w_i = p_i + s_i`; a row whose sum is not finite (an overflow of the
    /// unscaled sum) is recomputed by [`dot2_plus`] on the dense row, as
    /// [`super::w_into`] does.
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
                crate::lcp::w_into(&m, &q, &z, &mut dense, false);
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
        let (mut p, mut i, mut v) = (Vec::new(), Vec::new(), Vec::new());
        csc_of_rows(&m, 70, |a| 2.0 * a, &mut p, &mut i, &mut v);
        let mut back = vec![0.0; 70 * 70];
        for j in 0..70 {
            assert!(i[p[j]..p[j + 1]].windows(2).all(|w| w[0] < w[1]));
            for at in p[j]..p[j + 1] {
                back[i[at] * 70 + j] = v[at] / 2.0;
            }
        }
        assert_eq!(back, m);
        assert_eq!(p[70], m.iter().filter(|x| **x != 0.0).count());
    }
}
