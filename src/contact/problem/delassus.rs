//! The Delassus matrix `HᵀM⁻¹H` of a contact LCP by the block-sparse sum,
//! floe by floe (docs/physics.md §3.1; the module doc of [`super`]), and
//! the dense products it replaced, kept as references for its tests.

use super::{ContactLcp, Gen};
use faer::Mat;

/// `HᵀM⁻¹H` by the dense faer product over every row of `H`
/// (`minv`: the inverse mass of each row): what the assembly computed
/// before the block-sparse sum ([`delassus_blocks`]), kept as the
/// reference of its tests ([`ContactLcp::dense_delassus_reference`]).
fn dense_delassus(h: &Mat<f64>, minv: &[f64]) -> Mat<f64> {
    let mut minv_h = h.clone();
    for r in 0..h.nrows() {
        for c in 0..h.ncols() {
            minv_h[(r, c)] *= minv[r];
        }
    }
    h.transpose() * &minv_h
}

/// Adds the Delassus matrix `HᵀM⁻¹H` into the row-major `a` (leading
/// dimension `n`), floe by floe: for floe `l` (rows `3l..3l + 3` of `H`,
/// inverse masses `minv`) and every pair `(r, c)` of the columns
/// `touching[l]` that are non-zero in those rows,
/// `a_rc ← fma(H_kr, M⁻¹_k H_kc, a_rc)` for `k = 3l, 3l + 1, 3l + 2`.
/// Floes are visited in increasing order, so each entry is the fused sum
/// over `k` in increasing order of its non-zero terms — what the dense
/// product over every row computed (the rows of other floes add exact
/// zeros) — at the cost of `Σ_l 3 |touching[l]|²` instead of
/// `3 n_g · cols²`.
pub(super) fn delassus_blocks(
    h: &Mat<f64>,
    minv: &[f64],
    touching: &[Vec<usize>],
    n: usize,
    a: &mut [f64],
) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports FMA, checked just above.
            unsafe { delassus_blocks_fma(h, minv, touching, n, a) };
            return;
        }
    }
    delassus_blocks_body(h, minv, touching, n, a);
}

/// [`delassus_blocks`] compiled with FMA (`mul_add` is then one
/// instruction instead of a correctly rounded software routine: the same
/// result).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn delassus_blocks_fma(
    h: &Mat<f64>,
    minv: &[f64],
    touching: &[Vec<usize>],
    n: usize,
    a: &mut [f64],
) {
    delassus_blocks_body(h, minv, touching, n, a);
}

#[inline(always)]
fn delassus_blocks_body(
    h: &Mat<f64>,
    minv: &[f64],
    touching: &[Vec<usize>],
    n: usize,
    a: &mut [f64],
) {
    for (l, cols) in touching.iter().enumerate() {
        for &r in cols {
            let hr = [h[(3 * l, r)], h[(3 * l + 1, r)], h[(3 * l + 2, r)]];
            for &c in cols {
                let e = &mut a[r * n + c];
                for (d, &hd) in hr.iter().enumerate() {
                    let k = 3 * l + d;
                    *e = hd.mul_add(h[(k, c)] * minv[k], *e);
                }
            }
        }
    }
}

impl ContactLcp {
    /// The scaled Delassus block `HᵀM⁻¹H / g` (`cols × cols`, row-major,
    /// `cols` the columns of `H`) by the dense faer product over every row
    /// of `H` (what the assembly computed before the block-sparse sum). A
    /// reference for the tests of the block-sparse sum only.
    #[doc(hidden)]
    pub fn dense_delassus_reference(&self) -> Vec<f64> {
        let cols = self.h.ncols();
        let g = dense_delassus(&self.h, &self.minv);
        let mut out = vec![0.0; cols * cols];
        for r in 0..cols {
            for c in 0..cols {
                out[r * cols + c] = g[(r, c)] / self.scale;
            }
        }
        out
    }

    /// The generalised impulses `H (λ, β̃)` per floe by the row sums over
    /// every column of `H` (what [`ContactLcp::impulses`] computed before it
    /// summed over each floe's own columns). A reference for its tests only.
    #[doc(hidden)]
    pub fn dense_impulses_reference(&self, z: &[f64]) -> Vec<Gen> {
        let cols = self.h.ncols();
        let zp = self.physical(z);
        let mut out = vec![[0.0; 3]; self.floes.len()];
        for (l, o) in out.iter_mut().enumerate() {
            for (d, od) in o.iter_mut().enumerate() {
                let r = 3 * l + d;
                *od = zp
                    .iter()
                    .take(cols)
                    .enumerate()
                    .map(|(c, zc)| self.h[(r, c)] * zc)
                    .sum();
            }
        }
        out
    }

    /// The scaled Delassus block `HᵀM⁻¹H / g` (`cols × cols`, row-major)
    /// by the block-sparse sum ([`delassus_blocks`], what the assembly
    /// computes), recomputed from `H` alone, for its tests.
    #[doc(hidden)]
    pub fn block_sparse_delassus(&self) -> Vec<f64> {
        let (rows, cols) = (self.h.nrows(), self.h.ncols());
        let touching: Vec<Vec<usize>> = (0..rows / 3)
            .map(|l| {
                (0..cols)
                    .filter(|&c| (3 * l..3 * l + 3).any(|k| self.h[(k, c)] != 0.0))
                    .collect()
            })
            .collect();
        let mut out = vec![0.0; cols * cols];
        delassus_blocks(&self.h, &self.minv, &touching, cols, &mut out);
        out.iter_mut().for_each(|x| *x /= self.scale);
        out
    }
}
