//! Complementary bases solved directly, and block principal pivoting from a
//! guessed one.
//!
//! A **complementary basis** is a set `α` of indices whose `z_i` are basic
//! (the others have `w_i` basic): its basic solution is `z_α` from
//! `M_αα z_α = −q_α`, `z_i = 0` off `α`, `w = M z + q`. It solves the LCP iff
//! `z_α ≥ 0` and `w_ᾱ ≥ 0` (then `w_α = 0`, `z_ᾱ = 0`: complementary).
//!
//! [`Pivoting::run`] starts from a guessed `α` and applies **block principal
//! pivoting** (Júdice & Pires 1994; Kostreva 1978): every infeasible index
//! (`z_i < 0` for `i ∈ α`, `w_i < 0` off `α`) switches side; when the number
//! of infeasible indices has not decreased for [`BLOCK_STEPS_WITHOUT_PROGRESS`]
//! steps, only the largest infeasible index switches (Murty's rule, finite
//! for a P-matrix). The run stops at a feasible basis, at a singular one, or
//! after the given number of basis solves. Its candidate is then clamped to
//! `z ≥ 0` and judged by the [`super::residual`] on the original data like
//! every candidate of the driver; the caller decides what to do with it.
//!
//! It serves two purposes in [`super::solve`]: the **polish** of a Lemke
//! candidate (starting from its support: a basis solve on the original data
//! removes the rounding of a long pivot path, and further switches complete
//! a path that ended next to a solution, e.g. on a secondary ray with
//! `z0 ≈ 0`), and the **warm start** (starting from the previous step's
//! basis of the same contacts).
//!
//! **Basis solves.** `M_αα + δI` is factorised (LU with partial pivoting:
//! dense, or in a run with `sparse` the sparse LU of [`super::sparse_lu`]
//! over `M`'s non-zeros, the warm start of large problems;
//! `δ = 2⁻⁴⁰ max_i |M_ii|`, about 1e-12 relative), and a step of iterative
//! refinement against the unshifted `M_αα` in plain arithmetic starts from
//! the current point (the candidate being polished, the previous step's
//! impulses, the previous basis's solution): the switching needs only the
//! signs (the warm start; the polish refines every basis). A basis that
//! looks feasible gets the rest of [`SOLVES_PER_BASIS`] steps with
//! compensated residuals before it is judged.
//! The shift makes the solve defined for the singular but consistent
//! systems of the contact LCPs (two points of facing edges have equal
//! tangential columns: the split of their friction impulse is
//! indeterminate); starting from the current point keeps its component in
//! such a (near-)null space instead of replacing it by the shifted solve's
//! (which turned feasible Lemke candidates into infeasible ones). On a
//! regular basis the error contracts by `δ/λ` a step. Within the
//! iterations the residuals and `w` use the four-lane compensated product
//! ([`super::arith::dot2_plus_fast`]); the judged candidate's `w` is recomputed
//! with the driver's ([`super::arith::dot2_plus`]), so that its residual is the
//! one [`super::residual`] gives.

use super::arith::{dot2_plus, dot2_plus_fast, ResidualScale};
use super::path::NONE;
use super::polish::Lu;
use super::sparse::Columns;
use super::sparse_lu::{colamd_rank, Csc, SparseLu};

/// Solves with the shifted factorisation of a basis that is judged: the
/// first from the starting point (plain), then iterative refinement against
/// the unshifted matrix (compensated).
pub const SOLVES_PER_BASIS: usize = 3;

/// Block steps allowed without a decrease of the number of infeasible
/// indices before Murty's single switch takes over (Júdice & Pires use 3).
pub const BLOCK_STEPS_WITHOUT_PROGRESS: usize = 3;

/// Relative diagonal shift of a basis solve: `2⁻⁴⁰ ≈ 9.1e-13`.
const SHIFT: f64 = 1.0 / (1u64 << 40) as f64;

/// Infeasibility below this fraction of the driver's tolerance (times
/// `‖q‖₂`) is rounding: the index does not switch.
const FEASIBILITY_FRACTION: f64 = 1e-3;

/// A dot product plus a constant, `Σ x_i y_i + c`.
type Dot = fn(&[f64], &[f64], f64) -> f64;

/// `Σ x_i y_i + c` in plain arithmetic, four partial sums.
fn plain_dot(x: &[f64], y: &[f64], c: f64) -> f64 {
    let mut acc = [0.0_f64; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = xc
        .remainder()
        .iter()
        .zip(yc.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in xc.zip(yc) {
        for l in 0..4 {
            acc[l] += a[l] * b[l];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail + c
}

/// Outcome of [`Pivoting::run`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PivotingOutcome {
    /// Basis solves performed.
    pub(crate) solves: usize,
    /// Residual on the original data of the candidate left in
    /// [`Pivoting::z`], [`Pivoting::w`] (`INFINITY` if no basis solve was
    /// judged: infeasible to the end, or singular).
    pub(crate) residual: f64,
}

/// Buffers of the basis solves and of principal pivoting; one lives in the
/// driver's work space.
#[derive(Debug, Clone, Default)]
pub(crate) struct Pivoting {
    /// The complementary set: `alpha[i]` when `z_i` is basic. Set it before
    /// [`Pivoting::run`]; it holds the last basis afterwards.
    pub(crate) alpha: Vec<bool>,
    /// Starting point (set it with `alpha`; entries off `alpha` are
    /// ignored), then the candidate `z` (clamped to `z ≥ 0` when feasible).
    pub(crate) z: Vec<f64>,
    /// `w = M z + q` of the candidate.
    pub(crate) w: Vec<f64>,
    lu: Lu,
    /// The sparse basis solves of a run with `sparse` (boxed: scratch of
    /// large problems only).
    sp: Option<Box<SparseBases>>,
    /// Whether the current run solves its bases sparse.
    sparse: bool,
    idx: Vec<usize>,
    x: Vec<f64>,
    r: Vec<f64>,
    row: Vec<f64>,
    /// The entries of `x` matching `row` (sparse products).
    xrow: Vec<f64>,
    infeasible: Vec<usize>,
}

/// What the sparse basis solves keep over a run: `M` in compressed columns
/// and rows, the COLAMD ranks of its columns, the shifted `M_αα + δI` in
/// compressed columns and its sparse LU.
#[derive(Default)]
struct SparseBases {
    cols: Columns,
    rank: Vec<usize>,
    order: Vec<usize>,
    /// Position of each index in the current support (`self.idx`), [`NONE`]
    /// off it.
    pos: Vec<usize>,
    a: Csc,
    lu: SparseLu,
    /// Permuted right-hand side of a solve.
    t: Vec<f64>,
}

impl std::fmt::Debug for SparseBases {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseBases").finish_non_exhaustive()
    }
}

impl Clone for SparseBases {
    /// Cloned empty: scratch of one run, rebuilt by the next.
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl SparseBases {
    /// Builds `M`'s columns and rows and the ranks of its columns; `false`
    /// if the ordering failed.
    fn prepare(&mut self, m: &[f64], n: usize) -> bool {
        self.cols.scan(m, n);
        self.pos.clear();
        self.pos.resize(n, NONE);
        let cols = &self.cols;
        colamd_rank(n, &cols.ptr, &cols.idx, &mut self.order, &mut self.rank)
    }

    /// Marks the positions of `idx` in `pos` (clearing the previous ones).
    fn mark(&mut self, idx: &[usize]) {
        self.pos.iter_mut().for_each(|p| *p = NONE);
        for (r, &i) in idx.iter().enumerate() {
            self.pos[i] = r;
        }
    }
}

impl Pivoting {
    /// Block principal pivoting from `self.alpha` and the starting point `self.z` on `(m, q)` (n = `q.len()`,
    /// `m` n×n row-major, finite), at most `max_solves` basis solves.
    /// `tolerance` is the driver's acceptance threshold on the residual:
    /// infeasibility below `1e-3 · tolerance · ‖q‖₂` does not switch an
    /// index, and a basic solution whose residual meets the tolerance stops
    /// the run. With `fast`, the bases on the way are solved in plain
    /// arithmetic (one solve each) and only one that looks feasible is
    /// refined with compensated residuals; otherwise every basis is (the
    /// polish, where accuracy matters more than the few solves: measured,
    /// one more of the 2,841 corpus dumps is completed).
    /// A feasible (or accepted) basis leaves its candidate, clamped
    /// to `z ≥ 0`, in `self.z`, `self.w` with its residual; otherwise the
    /// residual is `INFINITY`.
    ///
    /// With `sparse`, the bases are factorised by a sparse LU
    /// ([`SparseLu`], columns in the COLAMD order of `M`'s, computed once
    /// per run) and the products run over `M`'s non-zeros: the cost of a
    /// basis solve follows the non-zeros of the contact group's `M_αα` and
    /// its factors instead of `k³/3` (the dense LU); the same shift,
    /// refinement and judgement, in another order of summation.
    pub(crate) fn run(
        &mut self,
        m: &[f64],
        q: &[f64],
        max_solves: usize,
        tolerance: f64,
        (fast, sparse): (bool, bool),
    ) -> PivotingOutcome {
        let n = q.len();
        let mut out = PivotingOutcome {
            solves: 0,
            residual: f64::INFINITY,
        };
        if self.alpha.len() != n || n.checked_mul(n) != Some(m.len()) {
            return out;
        }
        self.sparse = sparse && self.sp.get_or_insert_with(Box::default).prepare(m, n);
        self.z.resize(n, 0.0);
        let scale = ResidualScale::of(q);
        let tau_w = FEASIBILITY_FRACTION * tolerance * super::arith::norm2(q);
        let tau_z = tau_w / super::scaling::max_abs(m).max(1.0);
        let mut best = usize::MAX;
        let mut patience = BLOCK_STEPS_WITHOUT_PROGRESS;
        while out.solves < max_solves {
            out.solves += 1;
            // The switching only needs signs: for speed, one solve in plain
            // arithmetic, and a basis that looks feasible gets the accurate
            // refinement before it is judged.
            let (steps, dot) = if fast {
                (1, plain_dot as Dot)
            } else {
                (SOLVES_PER_BASIS, dot2_plus_fast as Dot)
            };
            if !(self.factor_basis(m) && self.refine_basis(m, q, steps, dot)) {
                return out;
            }
            if self.infeasible_set(tau_z, tau_w, &scale, tolerance) {
                let more = SOLVES_PER_BASIS - steps;
                if !self.refine_basis(m, q, more, dot2_plus_fast) {
                    return out;
                }
                // A basic solution whose residual (negative z_i count in
                // it) meets the tolerance is judged as it is: switching
                // indices for rounding-level infeasibility of a
                // near-singular basis only leads away from it.
                if self.infeasible_set(tau_z, tau_w, &scale, tolerance) {
                    let feasible = self.infeasible.is_empty();
                    let r = self.clamped_residual(m, q, &scale);
                    if feasible || r <= tolerance {
                        out.residual = r;
                        return out;
                    }
                }
            }
            if self.infeasible.len() < best {
                best = self.infeasible.len();
                patience = BLOCK_STEPS_WITHOUT_PROGRESS;
                self.switch_all();
            } else if patience > 0 {
                patience -= 1;
                self.switch_all();
            } else if let Some(&i) = self.infeasible.last() {
                self.alpha[i] = !self.alpha[i];
            }
        }
        out
    }

    /// Clamps `self.z` to `z ≥ 0`, recomputes `self.w` with the driver's
    /// compensated products ([`dot2_plus`], so that the residual is the one
    /// [`super::residual`] gives) and returns its residual on the original
    /// data.
    fn clamped_residual(&mut self, m: &[f64], q: &[f64], scale: &ResidualScale) -> f64 {
        for v in self.z.iter_mut() {
            *v = v.max(0.0);
        }
        self.idx.clear();
        self.idx.extend((0..q.len()).filter(|&i| self.z[i] != 0.0));
        self.x.clear();
        self.x.extend(self.idx.iter().map(|&i| self.z[i]));
        self.w_from_support(m, q, dot2_plus);
        scale.residual(&self.z, &self.w)
    }

    /// Collects the infeasible indices of the basic solution in
    /// `self.infeasible`; `true` if there are none or the residual
    /// (negative `z_i` counting in it) meets the tolerance.
    fn infeasible_set(
        &mut self,
        tau_z: f64,
        tau_w: f64,
        scale: &ResidualScale,
        tolerance: f64,
    ) -> bool {
        self.infeasible.clear();
        for i in 0..self.alpha.len() {
            let bad = if self.alpha[i] {
                self.z[i] < -tau_z
            } else {
                self.w[i] < -tau_w
            };
            if bad || !(self.z[i].is_finite() && self.w[i].is_finite()) {
                self.infeasible.push(i);
            }
        }
        self.infeasible.is_empty() || scale.residual(&self.z, &self.w) <= tolerance
    }

    fn switch_all(&mut self) {
        for &i in &self.infeasible {
            self.alpha[i] = !self.alpha[i];
        }
    }

    /// Factorises the shifted `M_αα + δI` of `self.alpha` (its indices in
    /// `self.idx`) and starts `self.x` at the current point; `false` if it
    /// is singular.
    fn factor_basis(&mut self, m: &[f64]) -> bool {
        let n = self.alpha.len();
        self.idx.clear();
        self.idx.extend((0..n).filter(|&i| self.alpha[i]));
        let k = self.idx.len();
        self.x.clear();
        if k == 0 {
            return true;
        }
        let dmax = (self.idx.iter()).fold(0.0_f64, |a, &i| a.max(m[i * n + i].abs()));
        let delta = if dmax > 0.0 {
            SHIFT * dmax
        } else {
            SHIFT * super::scaling::max_abs(m)
        };
        if self.sparse {
            if !self.factor_sparse(delta) {
                return false;
            }
        } else {
            let idx = &self.idx;
            let a = self.lu.matrix_mut(k);
            for (r, &i) in idx.iter().enumerate() {
                let mrow = &m[i * n..(i + 1) * n];
                for (c, &j) in idx.iter().enumerate() {
                    a[r * k + c] = mrow[j];
                }
                a[r * k + r] += delta;
            }
            if !self.lu.refactor(k) {
                return false;
            }
        }
        // Start from the current point: its component in a (near-)null
        // space of M_αα is kept, not replaced by the shifted solve's.
        self.x.extend(self.idx.iter().map(|&i| self.z[i]));
        true
    }

    /// `steps` steps of iterative refinement of `self.x` against the
    /// unshifted `M_αα`, the residuals `−q_α − M_αα x` and then `self.w`
    /// computed with `dot`; the basic solution into `self.z`, `self.w`.
    /// `false` if it is not finite.
    fn refine_basis(&mut self, m: &[f64], q: &[f64], steps: usize, dot: Dot) -> bool {
        let n = q.len();
        if !self.idx.is_empty() {
            for _ in 0..steps {
                self.r.clear();
                for t in 0..self.idx.len() {
                    let i = self.idx[t];
                    let r = -self.row_dot(m, i, dot, q[i]);
                    self.r.push(r);
                }
                if self.sparse {
                    self.solve_sparse();
                } else {
                    self.lu.solve_in_place(&mut self.r);
                }
                for (v, d) in self.x.iter_mut().zip(&self.r) {
                    *v += d;
                }
            }
            if !self.x.iter().all(|v| v.is_finite()) {
                return false;
            }
        }
        self.z.clear();
        self.z.resize(n, 0.0);
        for (&i, &v) in self.idx.iter().zip(&self.x) {
            self.z[i] = v;
        }
        self.w_from_support(m, q, dot);
        true
    }

    /// `self.w = M z + q` for `z` given on its support (`self.idx`,
    /// values `self.x`), with the compensated product `dot`.
    fn w_from_support(&mut self, m: &[f64], q: &[f64], dot: Dot) {
        if self.sparse {
            if let Some(sp) = self.sp.as_deref_mut() {
                sp.mark(&self.idx);
            }
        }
        self.w.clear();
        for (i, &qi) in q.iter().enumerate() {
            let wi = self.row_dot(m, i, dot, qi);
            self.w.push(wi);
        }
    }

    /// `Σ_{j ∈ idx} M_ij x_j + c` with the product `dot` (`self.x` holds
    /// `z` on the support `self.idx`): over row i of the dense `m`, or in a
    /// sparse run over the non-zeros of row i on the support (marked in
    /// `pos`).
    fn row_dot(&mut self, m: &[f64], i: usize, dot: Dot, c: f64) -> f64 {
        self.row.clear();
        match self.sp.as_deref() {
            Some(sp) if self.sparse => {
                self.xrow.clear();
                let (cols, vals) = sp.cols.row(i);
                for (&j, &a) in cols.iter().zip(vals) {
                    let p = sp.pos[j];
                    if p != NONE {
                        self.row.push(a);
                        self.xrow.push(self.x[p]);
                    }
                }
                dot(&self.row, &self.xrow, c)
            }
            _ => {
                let n = self.alpha.len();
                let mrow = &m[i * n..(i + 1) * n];
                self.row.extend(self.idx.iter().map(|&j| mrow[j]));
                dot(&self.row, &self.x, c)
            }
        }
    }

    /// Factorises the shifted `M_αα + δI` of `self.idx` by the sparse LU
    /// (columns by the ranks of their indices); `false` if it failed or a
    /// pivot is below `k ε max|a_ij|`, the dense LU's singularity test.
    fn factor_sparse(&mut self, delta: f64) -> bool {
        let Some(sp) = self.sp.as_deref_mut() else {
            return false;
        };
        let idx = &self.idx;
        let k = idx.len();
        sp.mark(idx);
        sp.a.clear();
        let mut amax = 0.0_f64;
        for (c, &j) in idx.iter().enumerate() {
            // Rows increase within a column and `pos` keeps their order;
            // the diagonal is stored even where M_jj = 0.
            let mut diagonal = false;
            let (ptr, rows, vals) = (&sp.cols.ptr, &sp.cols.idx, &sp.cols.val);
            for (&i, &a) in rows[ptr[j]..ptr[j + 1]]
                .iter()
                .zip(&vals[ptr[j]..ptr[j + 1]])
            {
                let r = sp.pos[i];
                if r == NONE {
                    continue;
                }
                if r > c && !diagonal {
                    sp.a.push(c, delta);
                    amax = amax.max(delta.abs());
                    diagonal = true;
                }
                let v = if r == c {
                    diagonal = true;
                    a + delta
                } else {
                    a
                };
                amax = amax.max(v.abs());
                sp.a.push(r, v);
            }
            if !diagonal {
                sp.a.push(c, delta);
                amax = amax.max(delta.abs());
            }
            sp.a.end_column();
        }
        if !(amax > 0.0 && amax.is_finite()) {
            return false;
        }
        let rank = &sp.rank;
        sp.lu.factorise(k, &sp.a, |order| {
            order.extend(0..k);
            order.sort_unstable_by_key(|&c| rank[idx[c]]);
        }) && sp.lu.min_pivot() > amax * f64::EPSILON * k as f64
    }

    /// `self.r ← (M_αα + δI)⁻¹ self.r` by the sparse LU of
    /// [`Pivoting::factor_sparse`].
    fn solve_sparse(&mut self) {
        let Some(sp) = self.sp.as_deref_mut() else {
            return;
        };
        sp.t.clear();
        sp.t.extend(sp.lu.row_fwd().iter().map(|&r| self.r[r]));
        sp.lu.forward_permuted(&mut sp.t);
        for (c, x) in self.r.iter_mut().enumerate() {
            *x = sp.t[sp.lu.col_inv()[c]];
        }
    }
}
