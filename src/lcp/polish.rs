//! Polishing a candidate solution on the original data.
//!
//! Given a candidate `z`, its support `α = {i : z_i > 0}` is taken as the
//! active set and `M_αα z_α = −q_α` is solved by Gaussian elimination with
//! partial pivoting plus one step of iterative refinement; `z_i = 0` off `α`.
//! This removes the rounding accumulated along a long pivot path and turns a
//! solution of a perturbed problem `M + εI` into one of `M` when both share
//! the active set. The driver keeps the polished point only if its residual
//! is lower.

/// Returns the polished candidate, or `None` if the support is empty, the
/// sizes are inconsistent, `M_αα` is numerically singular, or the result is
/// not finite. Negative components of the solution are clamped to 0.
pub(crate) fn polish(m: &[f64], q: &[f64], z: &[f64]) -> Option<Vec<f64>> {
    let n = q.len();
    if z.len() != n || n.checked_mul(n) != Some(m.len()) {
        return None;
    }
    let idx: Vec<usize> = (0..n).filter(|&i| z[i] > 0.0).collect();
    let k = idx.len();
    if k == 0 {
        return None;
    }
    let mut a = vec![0.0; k * k];
    for (r, &i) in idx.iter().enumerate() {
        for (c, &j) in idx.iter().enumerate() {
            a[r * k + c] = m[i * n + j];
        }
    }
    let b: Vec<f64> = idx.iter().map(|&i| -q[i]).collect();
    let lu = Lu::factor(a.clone(), k)?;
    let mut x = lu.solve(&b);
    let r: Vec<f64> = (0..k)
        .map(|i| {
            b[i] - a[i * k..(i + 1) * k]
                .iter()
                .zip(x.iter())
                .map(|(p, y)| p * y)
                .sum::<f64>()
        })
        .collect();
    let dx = lu.solve(&r);
    for (xi, di) in x.iter_mut().zip(dx.iter()) {
        *xi += di;
    }
    if !x.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut out = vec![0.0; n];
    for (r, &i) in idx.iter().enumerate() {
        out[i] = x[r].max(0.0);
    }
    Some(out)
}

/// LU factorisation with partial pivoting of a k×k row-major matrix (also
/// used by the cone solver's active-set polish).
pub(crate) struct Lu {
    k: usize,
    a: Vec<f64>,
    perm: Vec<usize>,
}

impl Lu {
    /// Factors `a` (k×k, row-major); `None` if numerically singular or not finite.
    pub(crate) fn factor(mut a: Vec<f64>, k: usize) -> Option<Self> {
        let amax = a.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        if !(amax > 0.0 && amax.is_finite()) {
            return None;
        }
        // A pivot below this is treated as zero (numerically singular).
        let tiny = amax * f64::EPSILON * k as f64;
        let mut perm: Vec<usize> = (0..k).collect();
        for c in 0..k {
            let mut p = c;
            for r in c + 1..k {
                if a[r * k + c].abs() > a[p * k + c].abs() {
                    p = r;
                }
            }
            if a[p * k + c].abs() <= tiny {
                return None;
            }
            if p != c {
                for j in 0..k {
                    a.swap(c * k + j, p * k + j);
                }
                perm.swap(c, p);
            }
            let piv = a[c * k + c];
            for r in c + 1..k {
                let f = a[r * k + c] / piv;
                a[r * k + c] = f;
                if f != 0.0 {
                    for j in c + 1..k {
                        a[r * k + j] -= f * a[c * k + j];
                    }
                }
            }
        }
        Some(Self { k, a, perm })
    }

    /// Solves `A x = b`.
    pub(crate) fn solve(&self, b: &[f64]) -> Vec<f64> {
        let k = self.k;
        let mut y: Vec<f64> = self.perm.iter().map(|&p| b[p]).collect();
        for r in 0..k {
            let s: f64 = (0..r).map(|j| self.a[r * k + j] * y[j]).sum();
            y[r] -= s;
        }
        for r in (0..k).rev() {
            let s: f64 = (r + 1..k).map(|j| self.a[r * k + j] * y[j]).sum();
            y[r] = (y[r] - s) / self.a[r * k + r];
        }
        y
    }
}
