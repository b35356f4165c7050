//! Lemke's complementary pivoting method on a dense tableau
//! (Cottle–Pang–Stone 1992, Alg. 4.4.5, with the lexicographic rule of §4.9).
//!
//! The augmented system is `w − M z − d z0 = q` with basic variables `w` at
//! the start. Variables are numbered `0..n` for `w`, `n..2n` for `z` and `2n`
//! for `z0`; the tableau `B⁻¹ [I | −M | −d | q]` is stored row-major with one
//! extra column for the right-hand side, so its first n columns are `B⁻¹`
//! itself, which the lexicographic rule reads.
//!
//! Before pivoting, M and q are scaled by powers of two (exact in binary
//! floating point) so that `max|M_ij| ≈ 1` and `max|q_i| ≈ 1`; this makes the
//! absolute tolerances below meaningful and leaves the solution unchanged
//! (`z = (β/α) z'` for `M' = M/α`, `q' = q/β`).

use super::{residual_with_w, w_unchecked};

/// Default iteration cap per unit of dimension: `max_pivots` defaults to
/// `DEFAULT_PIVOTS_PER_DIM * (n + 1)`. Lemke's method needs O(n) pivots on
/// typical problems (about 1–2 n on random P-matrices) but exponentially many
/// on contrived ones (Murty 1978); 50 (n + 1) leaves a wide margin while
/// bounding the cost of a cycling or stalled run at O(50 n³) flops.
pub const DEFAULT_PIVOTS_PER_DIM: usize = 50;

/// How the leaving (blocking) variable is chosen among rows tied in the
/// minimum-ratio test. In every rule, if `z0` is among the tied rows it leaves
/// (the method then terminates with a solution), unless
/// [`LemkeOptions::prefer_z0`] is `false`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum PivotRule {
    /// Lexicographic minimum ratio on the rows `(b_i, (B⁻¹)_{i·}) / c_i`
    /// (CPS §4.9). Provably prevents cycling; the default.
    Lexicographic,
    /// Plain minimum ratio; ties go to the basic variable with the smallest
    /// index (`w_1 < … < w_n < z_1 < … < z_n`). May cycle on degenerate
    /// problems (then stopped by the pivot cap).
    MinRatioSmallestIndex,
    /// Plain minimum ratio; ties go to the row with the largest pivot entry
    /// `c_i` (best numerical stability). May cycle on degenerate problems.
    MinRatioLargestPivot,
}

/// Why Lemke's method stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Termination {
    /// `z0` left the basis (or `q >= 0`): complementary solution found.
    Solved,
    /// Secondary ray: the entering column has no positive entry, so no
    /// solution was found with this covering vector. For copositive-plus M
    /// (e.g. positive semidefinite) this proves the LCP infeasible.
    RayTermination,
    /// The pivot cap was reached (possible cycling without the lexicographic
    /// rule, or an exponentially long path).
    MaxPivots,
    /// Non-finite input or tableau entry, a blocking pivot too small to be
    /// trusted, or a significantly negative `z` after the drift check.
    NumericalFailure,
    /// Inconsistent sizes, an invalid covering vector or invalid options.
    InvalidInput,
}

/// Options of [`lemke`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LemkeOptions {
    /// Tie-breaking rule of the ratio test.
    pub rule: PivotRule,
    /// Covering vector `d` (length n, entries finite and `> 0`); `None` means
    /// all ones. Only its direction matters numerically (it is rescaled so
    /// that `max d_i` is a power of two near 1).
    pub covering: Option<Vec<f64>>,
    /// Pivot tolerance on the scaled tableau: an entry `c_i` of the entering
    /// column blocks only if `c_i > pivot_tol · max(1, ‖c‖∞)`. If no entry
    /// passes but some exceed `pivot_tol · 1e-3 · max(1, ‖c‖∞)`, the step is
    /// undecidable and the run ends with [`Termination::NumericalFailure`]
    /// ("pivot too small"); otherwise it is a secondary ray. Default `1e-11`.
    pub pivot_tol: f64,
    /// Tolerance for ties in the (lexicographic) ratio test, relative to
    /// `max(1, |minimum|)` on the scaled tableau. Default `1e-11`.
    pub tie_tol: f64,
    /// Maximum number of pivots (including the first one, on `z0`); `None`
    /// means `DEFAULT_PIVOTS_PER_DIM * (n + 1)`.
    pub max_pivots: Option<usize>,
    /// Drift guard: after termination, negative entries of the scaled `z` not
    /// below `−clamp_tol · max(1, ‖z‖∞)` are set to 0. Default `1e-9`.
    pub clamp_tol: f64,
    /// If `z0` is among the rows tied in the ratio test, let it leave at once
    /// (CPS Alg. 4.4.5: the method then stops on a solution). Default `true`;
    /// `false` applies the tie-break rule to `z0`'s row like any other.
    pub prefer_z0: bool,
}

impl Default for LemkeOptions {
    fn default() -> Self {
        Self {
            rule: PivotRule::Lexicographic,
            covering: None,
            pivot_tol: 1e-11,
            tie_tol: 1e-11,
            max_pivots: None,
            clamp_tol: 1e-9,
            prefer_z0: true,
        }
    }
}

/// Outcome of [`lemke`].
#[derive(Debug, Clone, PartialEq)]
pub struct LemkeResult {
    /// `z` (length n; all zeros when nothing could be computed). Always
    /// finite. Negative entries remain only with
    /// [`Termination::NumericalFailure`].
    pub z: Vec<f64>,
    /// `w = M z + q` recomputed from the original data (not from the
    /// tableau). Non-finite only if the data are.
    pub w: Vec<f64>,
    /// Number of pivots performed (including the first one, on `z0`).
    pub pivots: usize,
    /// Why the method stopped.
    pub termination: Termination,
    /// [`super::residual`] of `z` on the data given to [`lemke`]
    /// (`f64::INFINITY` if not computable).
    pub residual: f64,
    /// Short human-readable reason for a failure, `None` on success.
    pub detail: Option<&'static str>,
}

/// Runs Lemke's method on `w = M z + q` (M row-major, n = `q.len()`).
///
/// Never panics: inconsistent sizes or bad options give
/// [`Termination::InvalidInput`], non-finite data
/// [`Termination::NumericalFailure`], both with `z = 0`. If `q >= 0` the
/// result is `z = 0` with 0 pivots. After termination `z` is read from the
/// tableau, tiny negative entries are clamped to 0 (see
/// [`LemkeOptions::clamp_tol`]), and `w` and the residual are recomputed from
/// the original `M`, `q`.
pub fn lemke(m: &[f64], q: &[f64], opts: &LemkeOptions) -> LemkeResult {
    let n = q.len();
    if n.checked_mul(n) != Some(m.len()) {
        return early(
            n,
            q,
            Termination::InvalidInput,
            "M is not n×n with n = q.len()",
        );
    }
    if !options_valid(opts) {
        return early(
            n,
            q,
            Termination::InvalidInput,
            "invalid tolerance in LemkeOptions",
        );
    }
    if !m.iter().chain(q.iter()).all(|x| x.is_finite()) {
        return early(
            n,
            q,
            Termination::NumericalFailure,
            "non-finite entry in M or q",
        );
    }
    let d: Vec<f64> = match &opts.covering {
        None => vec![1.0; n],
        Some(d) => {
            if d.len() != n || !d.iter().all(|&x| x.is_finite() && x > 0.0) {
                return early(
                    n,
                    q,
                    Termination::InvalidInput,
                    "covering vector must have n finite positive entries",
                );
            }
            d.clone()
        }
    };
    if q.iter().all(|&x| x >= 0.0) {
        return finish(m, q, vec![0.0; n], 0, Termination::Solved, None);
    }

    let alpha = pow2_scale(max_abs(m));
    let beta = pow2_scale(max_abs(q));
    let gamma = pow2_scale(max_abs(&d));
    let mut tab = Tableau::new(n, m, q, &d, alpha, beta, gamma);
    let max_pivots = opts
        .max_pivots
        .unwrap_or_else(|| DEFAULT_PIVOTS_PER_DIM.saturating_mul(n.saturating_add(1)));

    let (termination, detail) = tab.run(opts, max_pivots);
    let zs = tab.z_scaled();
    let (z, termination, detail) =
        post_process(zs, termination, detail, opts.clamp_tol, beta / alpha);
    finish(m, q, z, tab.pivots, termination, detail)
}

/// Reads back, clamps and unscales `z`; downgrades to a numerical failure if
/// `z` is non-finite or significantly negative.
fn post_process(
    zs: Vec<f64>,
    termination: Termination,
    detail: Option<&'static str>,
    clamp_tol: f64,
    unscale: f64,
) -> (Vec<f64>, Termination, Option<&'static str>) {
    let n = zs.len();
    if !zs.iter().all(|x| x.is_finite()) {
        return (
            vec![0.0; n],
            Termination::NumericalFailure,
            Some("non-finite z read from the tableau"),
        );
    }
    let zmax = max_abs(&zs).max(1.0);
    let mut significant_negative = false;
    let mut z: Vec<f64> = zs
        .into_iter()
        .map(|x| {
            if x >= 0.0 {
                x
            } else if x >= -clamp_tol * zmax {
                0.0
            } else {
                significant_negative = true;
                x
            }
        })
        .collect();
    for x in &mut z {
        *x *= unscale;
    }
    if !z.iter().all(|x| x.is_finite()) {
        return (
            vec![0.0; n],
            Termination::NumericalFailure,
            Some("z overflowed when undoing the scaling"),
        );
    }
    if significant_negative && termination == Termination::Solved {
        return (
            z,
            Termination::NumericalFailure,
            Some("significantly negative z after pivoting (numerical drift)"),
        );
    }
    (z, termination, detail)
}

fn options_valid(o: &LemkeOptions) -> bool {
    let ok = |x: f64| x.is_finite() && x >= 0.0;
    ok(o.pivot_tol) && ok(o.tie_tol) && ok(o.clamp_tol)
}

fn early(n: usize, q: &[f64], termination: Termination, detail: &'static str) -> LemkeResult {
    let z = vec![0.0; n];
    let w = q.to_vec();
    LemkeResult {
        residual: if termination == Termination::InvalidInput {
            f64::INFINITY
        } else {
            residual_with_w(q, &z, &w)
        },
        z,
        w,
        pivots: 0,
        termination,
        detail: Some(detail),
    }
}

fn finish(
    m: &[f64],
    q: &[f64],
    z: Vec<f64>,
    pivots: usize,
    termination: Termination,
    detail: Option<&'static str>,
) -> LemkeResult {
    let w = w_unchecked(m, q, &z);
    let residual = residual_with_w(q, &z, &w);
    LemkeResult {
        z,
        w,
        pivots,
        termination,
        residual,
        detail,
    }
}

pub(crate) fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |a, x| a.max(x.abs()))
}

/// Power of two closest (in log scale) to `x`; 1 for zero or non-finite `x`.
fn pow2_scale(x: f64) -> f64 {
    if !(x > 0.0 && x.is_finite()) {
        return 1.0;
    }
    let e = x.log2().round().clamp(-1000.0, 1000.0) as i32;
    2.0_f64.powi(e)
}

/// Dense Lemke tableau `B⁻¹ [I | −M | −d | q]` with its basis.
struct Tableau {
    n: usize,
    /// Number of columns: 2n + 2.
    cols: usize,
    t: Vec<f64>,
    /// `basis[row]` = index of the basic variable of that row.
    basis: Vec<usize>,
    pivots: usize,
    /// Scratch copy of the pivot row.
    prow: Vec<f64>,
}

/// Result of the ratio test.
enum Step {
    Pivot(usize),
    Ray,
    TooSmall,
}

impl Tableau {
    fn new(n: usize, m: &[f64], q: &[f64], d: &[f64], alpha: f64, beta: f64, gamma: f64) -> Self {
        let cols = 2 * n + 2;
        let mut t = vec![0.0; n * cols];
        for i in 0..n {
            let row = &mut t[i * cols..(i + 1) * cols];
            row[i] = 1.0;
            for j in 0..n {
                row[n + j] = -(m[i * n + j] / alpha);
            }
            row[2 * n] = -(d[i] / gamma);
            row[2 * n + 1] = q[i] / beta;
        }
        Self {
            n,
            cols,
            t,
            basis: (0..n).collect(),
            pivots: 0,
            prow: vec![0.0; cols],
        }
    }

    fn z0(&self) -> usize {
        2 * self.n
    }

    fn rhs(&self) -> usize {
        2 * self.n + 1
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.t[i * self.cols + j]
    }

    fn complement(&self, v: usize) -> Option<usize> {
        if v < self.n {
            Some(v + self.n)
        } else if v < 2 * self.n {
            Some(v - self.n)
        } else {
            None
        }
    }

    /// Main loop; returns the termination and a failure detail.
    fn run(
        &mut self,
        opts: &LemkeOptions,
        max_pivots: usize,
    ) -> (Termination, Option<&'static str>) {
        if max_pivots == 0 {
            return (Termination::MaxPivots, Some("pivot cap is 0"));
        }
        // First pivot: z0 enters; the leaving row minimises q_i / d_i
        // (lexicographically for the lexicographic rule), which makes every
        // right-hand side non-negative.
        let z0 = self.z0();
        let rows: Vec<(usize, f64)> = (0..self.n).map(|i| (i, -self.at(i, z0))).collect();
        let Some(r) = self.select(&rows, opts, false) else {
            return (Termination::NumericalFailure, Some("no initial pivot row"));
        };
        let mut leaving = self.basis[r];
        if !self.pivot(r, z0) {
            return (
                Termination::NumericalFailure,
                Some("non-finite tableau entry"),
            );
        }
        loop {
            if leaving == z0 {
                return (Termination::Solved, None);
            }
            let Some(entering) = self.complement(leaving) else {
                return (
                    Termination::NumericalFailure,
                    Some("internal: no complement"),
                );
            };
            if self.pivots >= max_pivots {
                return (Termination::MaxPivots, Some("pivot cap reached"));
            }
            let r = match self.ratio_test(entering, opts) {
                Step::Pivot(r) => r,
                Step::Ray => {
                    return (
                        Termination::RayTermination,
                        Some("secondary ray: entering column has no positive entry"),
                    )
                }
                Step::TooSmall => {
                    return (
                        Termination::NumericalFailure,
                        Some("pivot too small: blocking entries below the pivot tolerance"),
                    )
                }
            };
            leaving = self.basis[r];
            if !self.pivot(r, entering) {
                return (
                    Termination::NumericalFailure,
                    Some("non-finite tableau entry"),
                );
            }
        }
    }

    /// Minimum-ratio test on the entering column.
    fn ratio_test(&self, entering: usize, opts: &LemkeOptions) -> Step {
        let col: Vec<f64> = (0..self.n).map(|i| self.at(i, entering)).collect();
        let scale = max_abs(&col).max(1.0);
        let thresh = opts.pivot_tol * scale;
        let rows: Vec<(usize, f64)> = col
            .iter()
            .enumerate()
            .filter(|(_, &c)| c > thresh)
            .map(|(i, &c)| (i, c))
            .collect();
        if rows.is_empty() {
            let noise = opts.pivot_tol * 1e-3 * scale;
            return if col.iter().any(|&c| c > noise) {
                Step::TooSmall
            } else {
                Step::Ray
            };
        }
        match self.select(&rows, opts, opts.prefer_z0) {
            Some(r) => Step::Pivot(r),
            None => Step::TooSmall,
        }
    }

    /// Chooses the leaving row among `rows` = (row, divisor > 0) by the
    /// minimum ratio `b_i / divisor_i` and the rule's tie-break.
    fn select(&self, rows: &[(usize, f64)], opts: &LemkeOptions, prefer_z0: bool) -> Option<usize> {
        let rhs = self.rhs();
        let mut ties = min_ties(rows, |i| self.at(i, rhs), opts.tie_tol);
        if ties.len() <= 1 {
            return ties.first().map(|&(i, _)| i);
        }
        if prefer_z0 {
            let z0 = self.z0();
            if let Some(&(i, _)) = ties.iter().find(|&&(i, _)| self.basis[i] == z0) {
                return Some(i);
            }
        }
        match opts.rule {
            PivotRule::Lexicographic => {
                for k in 0..self.n {
                    ties = min_ties(&ties, |i| self.at(i, k), opts.tie_tol);
                    if ties.len() <= 1 {
                        return ties.first().map(|&(i, _)| i);
                    }
                }
                // Only reachable through rounding (rows of B⁻¹ are
                // independent): take the most stable pivot.
                largest_pivot(&ties)
            }
            PivotRule::MinRatioSmallestIndex => ties
                .iter()
                .min_by_key(|&&(i, _)| self.basis[i])
                .map(|&(i, _)| i),
            PivotRule::MinRatioLargestPivot => largest_pivot(&ties),
        }
    }

    /// Pivots on (r, j); returns `false` if a non-finite entry appeared.
    fn pivot(&mut self, r: usize, j: usize) -> bool {
        let cols = self.cols;
        let p = self.t[r * cols + j];
        if !(p.is_finite() && p != 0.0) {
            return false;
        }
        for k in 0..cols {
            self.prow[k] = self.t[r * cols + k] / p;
        }
        self.prow[j] = 1.0;
        self.t[r * cols..(r + 1) * cols].copy_from_slice(&self.prow);
        let mut finite = self.prow.iter().all(|x| x.is_finite());
        for i in 0..self.n {
            if i == r {
                continue;
            }
            let row = &mut self.t[i * cols..(i + 1) * cols];
            let f = row[j];
            if f != 0.0 {
                for (x, &pr) in row.iter_mut().zip(self.prow.iter()) {
                    *x -= f * pr;
                }
                row[j] = 0.0;
                // Only updated rows can become non-finite.
                finite &= row.iter().fold(true, |ok, x| ok & x.is_finite());
            }
        }
        self.basis[r] = j;
        self.pivots += 1;
        finite
    }

    /// Current values of `z` in scaled units (non-basic entries are 0).
    fn z_scaled(&self) -> Vec<f64> {
        let mut z = vec![0.0; self.n];
        let rhs = self.rhs();
        for (i, &v) in self.basis.iter().enumerate() {
            if v >= self.n && v < 2 * self.n {
                z[v - self.n] = self.at(i, rhs);
            }
        }
        z
    }
}

/// Rows of `rows` whose ratio `value(i) / divisor` is within the tie
/// tolerance of the minimum.
fn min_ties(
    rows: &[(usize, f64)],
    value: impl Fn(usize) -> f64,
    tie_tol: f64,
) -> Vec<(usize, f64)> {
    let ratios: Vec<f64> = rows.iter().map(|&(i, c)| value(i) / c).collect();
    let min = ratios.iter().copied().fold(f64::INFINITY, f64::min);
    if !min.is_finite() {
        return rows.to_vec();
    }
    let tol = tie_tol * min.abs().max(1.0);
    rows.iter()
        .zip(ratios.iter())
        .filter(|(_, &v)| v <= min + tol)
        .map(|(&rc, _)| rc)
        .collect()
}

fn largest_pivot(rows: &[(usize, f64)]) -> Option<usize> {
    rows.iter()
        .copied()
        .fold(None, |best: Option<(usize, f64)>, (i, c)| match best {
            Some((_, bc)) if bc >= c => best,
            _ => Some((i, c)),
        })
        .map(|(i, _)| i)
}
