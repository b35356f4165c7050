//! The solves of the factorised basis [`super::Revised`]: FTRAN and BTRAN
//! through the LU of `B₀` and the eta file, the solve with the reduced form
//! of `B₀`, and the refactorisation (the reduced block `K`, its COLAMD
//! ordering and sparse LU). The representation is described in [`super`].

use super::Revised;
use crate::lcp::path::NONE;
use crate::lcp::sparse_lu::colamd_rank;

impl Revised {
    /// `x ← B⁻¹ x` (FTRAN), with its own scratch (the refinement of a
    /// candidate: a few calls per solve).
    pub(crate) fn solve(&self, x: &mut [f64]) {
        self.ftran(x, &mut Vec::new());
    }

    /// `x ← B⁻¹ x` (FTRAN): the LU of `B₀`, then the etas in order; `tmp`
    /// is scratch.
    pub(super) fn ftran(&self, x: &mut [f64], tmp: &mut Vec<f64>) {
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
    pub(super) fn btran(&self, y: &mut [f64], tmp: &mut Vec<f64>) {
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
    pub(super) fn refactor(&mut self) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lcp::path::Basis;
    use crate::lcp::revised::REFACTOR_EVERY;

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
