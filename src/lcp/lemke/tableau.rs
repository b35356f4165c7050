//! The dense condensed tableau of [`super::Workspace`], one of the two
//! representations of the basis of Lemke's method (the other is the
//! factorised basis of [`crate::lcp::revised`]): its set-up from the scaled
//! data, the exchange step of a pivot and its elimination, the refinement
//! through its `B⁻¹`, and its [`Basis`] implementation read by the pivoting
//! rules of [`crate::lcp::path`]. The tableau's layout and the exchange step
//! are described in [`super`].

use super::Workspace;
use crate::lcp::path::{Basis, NONE};
use crate::lcp::scaling::{exp2_factor, ldexp, max_abs_finite};

impl Workspace {
    /// Sets up the dense tableau of the scaled `(m, q, d)` (after
    /// [`Workspace::scale`]).
    pub(super) fn setup(&mut self, m: &[f64], q: &[f64]) {
        let n = q.len();
        let cols = n + 2;
        self.cols = cols;
        // Every entry of the n rows is written below: no zeroing.
        self.t.resize(n * cols, 0.0);
        let (fa, fb) = (exp2_factor(-self.ea), exp2_factor(-self.eb));
        for i in 0..n {
            let row = &mut self.t[i * cols..(i + 1) * cols];
            let mrow = &m[i * n..(i + 1) * n];
            match fa {
                Some(f) => {
                    for (x, &a) in row[..n].iter_mut().zip(mrow) {
                        *x = -(a * f);
                    }
                }
                None => {
                    for (x, &a) in row[..n].iter_mut().zip(mrow) {
                        *x = -ldexp(a, -self.ea);
                    }
                }
            }
            row[n] = -self.d[i];
            row[n + 1] = match fb {
                Some(f) => q[i] * f,
                None => ldexp(q[i], -self.eb),
            };
        }
        self.basis.clear();
        self.basis.extend(0..n);
        self.nonbasic.clear();
        self.nonbasic.extend(n..=2 * n);
        self.row_of.clear();
        self.row_of.extend(0..n);
        self.row_of.resize(2 * n + 1, NONE);
        self.col_of.clear();
        self.col_of.resize(n, NONE);
        self.col_of.extend(0..=n);
        self.prow.resize(cols, 0.0);
        self.nz.clear();
        self.cand.clear();
        // The scaled M', q' and d' are below √2 in magnitude (scaled by the
        // power of two nearest their largest entry, `pow2_exponent`).
        self.tbound = INITIAL_TABLEAU_BOUND;
    }

    /// Exchange step on row `r`, column `s`; returns `false` if a non-finite
    /// entry appeared.
    pub(super) fn exchange(&mut self, r: usize, s: usize) -> bool {
        let (n, cols) = (self.n, self.cols);
        let p = self.t[r * cols + s];
        if !(p.is_finite() && p != 0.0) {
            return false;
        }
        let mut finite = true;
        let mut pmax = 0.0_f64;
        {
            let row = &mut self.t[r * cols..(r + 1) * cols];
            // The pivot row divided by p, copied as it goes (an element
            // loop: a row of a small tableau is shorter than the call of a
            // memcpy).
            for (x, pr) in row.iter_mut().zip(self.prow.iter_mut()) {
                let v = *x / p;
                *x = v;
                *pr = v;
                finite &= v.is_finite();
                pmax = pmax.max(v.abs());
            }
            let inv = 1.0 / p;
            row[s] = inv;
            self.prow[s] = inv;
            finite &= inv.is_finite();
            pmax = pmax.max(inv.abs());
        }
        // Every other row becomes `row − f · prow` with |row|, |f| at most
        // the bound: at most bound · (1 + pmax), with a margin for the two
        // roundings. Below the overflow-free bound the elimination cannot
        // produce a non-finite entry from these finite ones.
        let bound = (self.tbound * (1.0 + pmax)).max(pmax) * BOUND_ROUNDING_MARGIN;
        let check = !(finite && bound < OVERFLOW_FREE_BOUND);
        // The non-zero positions of the pivot row, for a sparse elimination;
        // not worth listing in a short row (the dense loop is as fast).
        self.nz.clear();
        if cols >= SPARSE_ROW_FROM {
            for (k, &x) in self.prow.iter().enumerate() {
                if x != 0.0 {
                    self.nz.push(k);
                }
            }
        }
        let rows = Eliminate {
            t: &mut self.t[..n * cols],
            cols,
            r,
            s,
            prow: &self.prow,
            nz: &self.nz,
            check,
        };
        finite &= rows.run();
        self.tbound = if check {
            // The entries themselves, if finite: the bound starts again
            // from the largest.
            let (tmax, all_finite) = max_abs_finite(&self.t[..n * cols]);
            finite &= all_finite;
            tmax
        } else {
            bound
        };
        let entering = self.nonbasic[s];
        let leaving = self.basis[r];
        self.basis[r] = entering;
        self.nonbasic[s] = leaving;
        self.row_of[entering] = r;
        self.col_of[entering] = NONE;
        self.row_of[leaving] = NONE;
        self.col_of[leaving] = s;
        self.pivots += 1;
        finite
    }

    /// `x += B⁻¹ ρ` on the dense tableau: basic `w_k` contribute `ρ_k` to
    /// their row, non-basic `w_k` through their stored column.
    pub(super) fn refine_dense(&self, x: &mut [f64], rho: &[f64]) {
        let (n, cols) = (self.n, self.cols);
        for (row, xr) in x.iter_mut().enumerate() {
            let trow = &self.t[row * cols..row * cols + n + 1];
            let mut acc = 0.0;
            for (p, &v) in self.nonbasic.iter().enumerate() {
                if v < n {
                    acc += trow[p] * rho[v];
                }
            }
            let v = self.basis[row];
            if v < n {
                acc += rho[v];
            }
            *xr += acc;
        }
    }
}

/// The dense condensed tableau as a [`Basis`]: every entry is stored, so a
/// column or a row of `B⁻¹` is read in place.
impl Basis for Workspace {
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
        self.s = self.col_of[v];
        self.s != NONE
    }

    #[inline]
    fn c(&self, i: usize) -> f64 {
        self.t[i * self.cols + self.s]
    }

    #[inline]
    fn b(&self, i: usize) -> f64 {
        self.t[i * self.cols + self.n + 1]
    }

    fn prepare_rows(&mut self, _rows: &[usize]) -> bool {
        true
    }

    fn binv(&self, i: usize, v: usize) -> f64 {
        self.t[i * self.cols + self.col_of[v]]
    }

    fn pivot(&mut self, r: usize) -> bool {
        self.exchange(r, self.s)
    }

    fn pivots(&self) -> usize {
        self.pivots
    }
}

/// Rows (tableau columns, n + 2) from which the elimination of a pivot
/// skips the zeros of the pivot row; shorter rows are eliminated densely.
/// The two give the same entries (a zero of the pivot row changes nothing
/// but, at most, the sign of a zero entry).
const SPARSE_ROW_FROM: usize = 16;

/// Bound on the scaled entries of a fresh tableau (they are below √2).
const INITIAL_TABLEAU_BOUND: f64 = 1.5;

/// Below this bound on the tableau's entries an exchange cannot overflow
/// (the largest finite `f64` is about 1.8e308), so its elimination need
/// not test every entry for finiteness.
const OVERFLOW_FREE_BOUND: f64 = 1e300;

/// Margin of the bound of an exchange for the roundings of `row − f · prow`
/// (two roundings of relative size 2⁻⁵³ each; generously).
const BOUND_ROUNDING_MARGIN: f64 = 1.0 + 1e-10;

/// The elimination of a pivot: every row `i ≠ r` of the tableau `t`
/// (rows of `cols` entries) becomes `row − row[s] · prow`, with `row[s]`
/// set to 0 first (the exchanged column; `prow[s] = 1/p`), over the
/// non-zero positions `nz` of the pivot row when they are few. With
/// `check`, every new entry is tested for finiteness; without, the caller
/// has proved that none can overflow (`Workspace::tbound`).
struct Eliminate<'a> {
    t: &'a mut [f64],
    cols: usize,
    r: usize,
    s: usize,
    prow: &'a [f64],
    nz: &'a [usize],
    check: bool,
}

impl Eliminate<'_> {
    /// Runs the elimination; `false` if a non-finite entry appeared. On a
    /// CPU with AVX2 the same operations (a multiply then a subtract, no
    /// fused multiply–add: bit for bit the same results) run four to a
    /// vector instead of two.
    fn run(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU supports AVX2, checked just above.
                return unsafe { self.run_avx2() };
            }
        }
        self.dispatch()
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn run_avx2(self) -> bool {
        self.dispatch()
    }

    /// The tableaux of one and two frictional contacts (n = 4, 8: rows of
    /// 6 and 10 entries) by a loop of constant length, fully unrolled; the
    /// others by the general loop. The same operations in the same order.
    #[inline(always)]
    fn dispatch(self) -> bool {
        match (self.cols, self.check) {
            (6, false) => self.body::<6, false>(),
            (10, false) => self.body::<10, false>(),
            (_, false) => self.body::<0, false>(),
            (6, true) => self.body::<6, true>(),
            (10, true) => self.body::<10, true>(),
            (_, true) => self.body::<0, true>(),
        }
    }

    /// The elimination with rows of `C` entries (`C` = 0: `self.cols`),
    /// testing every new entry for finiteness when `CHECK`.
    #[inline(always)]
    fn body<const C: usize, const CHECK: bool>(self) -> bool {
        let Eliminate {
            t,
            cols,
            r,
            s,
            prow,
            nz,
            check: _,
        } = self;
        let cols = if C == 0 { cols } else { C };
        let Some(prow) = prow.get(..cols) else {
            return false;
        };
        let sparse = cols >= SPARSE_ROW_FROM && 4 * nz.len() < cols;
        let mut finite = true;
        for (i, row) in t.chunks_exact_mut(cols).enumerate() {
            if i == r {
                continue;
            }
            let f = row[s];
            if f == 0.0 {
                continue;
            }
            row[s] = 0.0;
            let mut ok = true;
            if sparse {
                for &k in nz {
                    let v = row[k] - f * prow[k];
                    row[k] = v;
                    if CHECK {
                        ok &= v.is_finite();
                    }
                }
            } else {
                for (x, &pr) in row.iter_mut().zip(prow) {
                    let v = *x - f * pr;
                    *x = v;
                    if CHECK {
                        ok &= v.is_finite();
                    }
                }
            }
            finite &= ok;
        }
        finite
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lcp::scaling::max_abs;
    use crate::rng::SplitMix64;

    /// A random `n × n` matrix with entries over six binades, a dominant
    /// diagonal when `dominant`, and a `q` with negative entries.
    fn problem(rng: &mut SplitMix64, n: usize, dominant: bool) -> (Vec<f64>, Vec<f64>) {
        let mut m: Vec<f64> = (0..n * n)
            .map(|_| (rng.uniform() - 0.5) * 10f64.powf(6.0 * rng.uniform() - 3.0))
            .collect();
        if dominant {
            for i in 0..n {
                m[i * n + i] = m[i * n..(i + 1) * n].iter().map(|x| x.abs()).sum::<f64>() + 1.0;
            }
        }
        let q = (0..n).map(|_| rng.uniform() - 0.7).collect();
        (m, q)
    }

    #[test]
    fn the_tableau_bound_holds_after_every_exchange() {
        // The bound that lets an exchange skip the finiteness test must be
        // an upper bound of every entry after every exchange, on paths with
        // small pivots (entries over six binades, not dominant) and without.
        let mut rng = SplitMix64::new(0x7AB1_EA00);
        let mut exchanges = 0;
        let mut grown = 0;
        for trial in 0..200 {
            let n = 1 + trial % 24;
            let (m, q) = problem(&mut rng, n, trial % 3 == 0);
            let mut ws = Workspace::default();
            let (mmax, _) = max_abs_finite(&m);
            let (qmax, _) = max_abs_finite(&q);
            ws.scale(n, None, mmax, qmax);
            ws.setup(&m, &q);
            assert!(max_abs(&ws.t) <= ws.tbound);
            // Lemke's pivots are not needed for the bound: any sequence of
            // exchanges on the largest entry of a column keeps it.
            for step in 0..2 * n {
                let s = step % (n + 1);
                let col: Vec<f64> = (0..n).map(|i| ws.t[i * ws.cols + s].abs()).collect();
                let (r, &c) = col
                    .iter()
                    .enumerate()
                    .fold((0, &0.0), |a, b| if b.1 > a.1 { b } else { a });
                if c < 1e-12 {
                    continue;
                }
                assert!(ws.exchange(r, s));
                exchanges += 1;
                let tmax = max_abs(&ws.t[..n * ws.cols]);
                assert!(
                    tmax <= ws.tbound,
                    "n = {n}: {tmax:e} > bound {:e}",
                    ws.tbound
                );
                grown += usize::from(ws.tbound > 10.0);
            }
        }
        assert!(exchanges > 2000, "{exchanges}");
        assert!(grown > 100, "{grown}");
    }

    #[test]
    fn an_exchange_past_the_overflow_free_bound_tests_every_entry() {
        // With the bound forced past the overflow-free limit, the exchange
        // runs the checked elimination: an overflow is reported, and
        // without one the bound restarts from the largest entry.
        let n = 2;
        let m = vec![1.0, 1e-3, 1.0, 1.0];
        let q = vec![-1.0, -1.0];
        let mut ws = Workspace::default();
        ws.scale(n, None, 1.0, 1.0);
        ws.setup(&m, &q);
        ws.tbound = 1e305;
        assert!(ws.exchange(0, 0));
        assert_eq!(ws.tbound, max_abs(&ws.t[..n * ws.cols]));
        // Entries near the largest f64 (the pivot is t[0] = −1): row 1
        // becomes 0.75 MAX − 1 · (−0.5 MAX), which overflows and is
        // reported.
        ws.setup(&m, &q);
        ws.t[ws.cols] = 1.0;
        ws.t[ws.cols + 1] = 0.75 * f64::MAX;
        ws.t[1] = 0.5 * f64::MAX;
        ws.tbound = f64::MAX;
        assert!(!ws.exchange(0, 0));
    }
}
