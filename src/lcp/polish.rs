//! Dense LU factorisation with partial pivoting, for the basis solves of
//! [`super::pivoting`] (the polish of a candidate and the warm start) and the
//! cone solver's active-set polish.
//!
//! The factorisation works in reusable buffers ([`Lu::refactor`],
//! [`Lu::solve_in_place`]) so that a basis solve allocates nothing once the
//! buffers have grown; [`Lu::factor`] and [`Lu::solve`] are the allocating
//! forms.

/// LU factorisation with partial pivoting of a k×k row-major matrix.
#[derive(Debug, Clone, Default)]
pub(crate) struct Lu {
    k: usize,
    a: Vec<f64>,
    perm: Vec<usize>,
    y: Vec<f64>,
}

impl Lu {
    /// Factors `a` (k×k, row-major); `None` if numerically singular or not finite.
    pub(crate) fn factor(a: Vec<f64>, k: usize) -> Option<Self> {
        let mut lu = Lu { a, ..Lu::default() };
        lu.refactor(k).then_some(lu)
    }

    /// The k×k matrix buffer to fill (row-major) before [`Lu::refactor`].
    pub(crate) fn matrix_mut(&mut self, k: usize) -> &mut [f64] {
        self.a.clear();
        self.a.resize(k * k, 0.0);
        &mut self.a
    }

    /// Factors the k×k matrix held in the buffer in place; `false` if it is
    /// numerically singular (a pivot below `k ε max|a_ij|`) or not finite.
    /// On a CPU with AVX2 the same operations run four to a vector (no
    /// fused multiply–add: bit for bit the same factors).
    pub(crate) fn refactor(&mut self, k: usize) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU supports AVX2, checked just above.
                return unsafe { self.refactor_avx2(k) };
            }
        }
        self.refactor_body(k)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn refactor_avx2(&mut self, k: usize) -> bool {
        self.refactor_body(k)
    }

    #[inline(always)]
    fn refactor_body(&mut self, k: usize) -> bool {
        self.k = k;
        let a = &mut self.a;
        if a.len() != k * k {
            return false;
        }
        let amax = a.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        if !(amax > 0.0 && amax.is_finite()) {
            return false;
        }
        // A pivot below this is treated as zero (numerically singular).
        let tiny = amax * f64::EPSILON * k as f64;
        self.perm.clear();
        self.perm.extend(0..k);
        for c in 0..k {
            let mut p = c;
            for r in c + 1..k {
                if a[r * k + c].abs() > a[p * k + c].abs() {
                    p = r;
                }
            }
            if a[p * k + c].abs() <= tiny {
                return false;
            }
            if p != c {
                for j in 0..k {
                    a.swap(c * k + j, p * k + j);
                }
                self.perm.swap(c, p);
            }
            let piv = a[c * k + c];
            let (top, bottom) = a.split_at_mut((c + 1) * k);
            let prow = &top[c * k + c + 1..c * k + k];
            for row in bottom.chunks_exact_mut(k) {
                let f = row[c] / piv;
                row[c] = f;
                if f != 0.0 {
                    for (x, &p) in row[c + 1..].iter_mut().zip(prow) {
                        *x -= f * p;
                    }
                }
            }
        }
        true
    }

    /// Solves `A x = b` in place (`b.len() == k`), in the internal buffer.
    pub(crate) fn solve_in_place(&mut self, b: &mut [f64]) {
        let mut y = std::mem::take(&mut self.y);
        self.substitute(b, &mut y);
        self.y = y;
    }

    /// Solves `A x = b`.
    pub(crate) fn solve(&self, b: &[f64]) -> Vec<f64> {
        let mut x = b.to_vec();
        self.substitute(&mut x, &mut Vec::with_capacity(self.k));
        x
    }

    /// Forward and back substitution of `b` (overwritten by `x`), with `y`
    /// as scratch.
    fn substitute(&self, b: &mut [f64], y: &mut Vec<f64>) {
        let k = self.k;
        y.clear();
        y.extend(self.perm.iter().map(|&p| b[p]));
        for r in 0..k {
            let row = &self.a[r * k..r * k + r];
            let s: f64 = row.iter().zip(y.iter()).map(|(a, v)| a * v).sum();
            y[r] -= s;
        }
        for r in (0..k).rev() {
            let row = &self.a[r * k + r + 1..(r + 1) * k];
            let s: f64 = row.iter().zip(y[r + 1..].iter()).map(|(a, v)| a * v).sum();
            y[r] = (y[r] - s) / self.a[r * k + r];
        }
        b.copy_from_slice(y);
    }
}
