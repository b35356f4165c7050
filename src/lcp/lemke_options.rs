//! Lemke's options, pivot rules and termination: the types and constants
//! that the pivoting rules of [`super::path`], both basis representations
//! and the driver share (so that they import them from here, below all of
//! them, and not from [`super::lemke`]).
//!
//! The rules themselves are documented in [`super::lemke`] (ratio test,
//! termination) and docs/physics.md §3.3.

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
    /// Harris's two-pass ratio test (Harris 1973; Gill, Murray, Saunders &
    /// Wright 1989): the first pass bounds the step by
    /// `θ* = min_i (max(b_i, 0) + δ) / c_i` with the feasibility tolerance
    /// `δ =` [`HARRIS_FEASIBILITY`] on the scaled tableau, the second takes,
    /// among the rows whose ratio is at most `θ*`, the one with the largest
    /// pivot entry `c_i` (the lowest row among equal entries; `z0` if it is
    /// one of them). A step takes no basic variable that was non-negative
    /// below `−δ`. On the degenerate contact LCPs of a jammed pack the
    /// exact minimum ratio is often taken by an entry of 1e-8 to 1e-10
    /// (nearly equal tangential columns of two points of facing edges):
    /// the lexicographic path pivots on it, the basis inverse grows to
    /// 1e16, basic values go to −0.3 and the path ends on a secondary ray
    /// or a drift failure; this test passes such a row by for one whose
    /// ratio differs by at most `δ / c_i`. No anti-cycling guarantee, and
    /// the infeasibility it allows (up to `δ` a step) can accumulate into a
    /// drift failure: the driver follows it with the lexicographic attempt
    /// ([`super::solve`]), and runs it only when asked
    /// (`SolveOptions::harris_from`).
    Harris,
}

/// Feasibility tolerance `δ` of [`PivotRule::Harris`], on the scaled
/// tableau (where `max|q'_i|` is within √2 of 1): `1e-12`, about 4,500
/// ulps of 1, a thousandth of the drift clamp's `1e-9`. Measured on the 40
/// LCPs of 1,520–1,552 unknowns of a bay-jam window: `1e-12` solves all
/// 40 with residuals at most 1.6e-11 before the polish, `1e-10` solves
/// them too but leaves 16 residuals above the driver's `1e-10`.
pub const HARRIS_FEASIBILITY: f64 = 1e-12;

/// Why Lemke's method stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Termination {
    /// `z0` left the basis, became negligible (see
    /// [`LemkeOptions::z0_tol`]), or `q >= 0`: complementary solution found.
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
    /// A stop was asked for ([`crate::stop::requested`], polled every
    /// [`crate::stop::POLL_EVERY`] pivots): the path was left where it was.
    Interrupted,
}

impl Termination {
    /// Name used in logs and CSV: `"Solved"`, `"RayTermination"`,
    /// `"MaxPivots"`, `"NumericalFailure"`, `"InvalidInput"`, `"Interrupted"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Solved => "Solved",
            Self::RayTermination => "RayTermination",
            Self::MaxPivots => "MaxPivots",
            Self::NumericalFailure => "NumericalFailure",
            Self::InvalidInput => "InvalidInput",
            Self::Interrupted => "Interrupted",
        }
    }
}

impl std::fmt::Display for Termination {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Options of [`super::lemke()`].
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
    /// ("pivot too small"); otherwise it is a secondary ray. Default
    /// `1e-10`. The contact LCPs have genuinely small blocking entries
    /// (nearly equal tangential columns of two points of facing edges): with
    /// `1e-9` a blocking entry of 1.3e-9 was skipped and its basic variable
    /// ended at −1e-9, a candidate the driver could not accept (18 of the
    /// 2,841 dumps of the field_200_coast corpus against 6 with `1e-10`);
    /// with `1e-11` pivots on rounding noise lose the path more often (16).
    /// Measured with the driver's principal-pivoting polish
    /// ([`super::solve`]).
    pub pivot_tol: f64,
    /// Relative tolerance for ties in the minimum-ratio test: rows whose
    /// ratio is at most `min + tie_tol · |min|` are tied. Purely relative, so
    /// that a zero minimum (a degenerate step) ties only with exact zeros; it
    /// absorbs the last-bit differences of ratios that are equal in exact
    /// arithmetic. Default `1e-14`. (Until this version the tolerance was
    /// `1e-11 · max(1, |min|)`, which tied ratios up to 1e-11 apart: the
    /// leaving row was then often not a minimiser, a basic variable went
    /// negative and the path was lost; see the module doc.)
    pub tie_tol: f64,
    /// Tolerance of the lexicographic comparisons among tied rows: entries
    /// `(B⁻¹)_ik / c_i` within `lex_tol · (1 + |min|)` of the minimum are
    /// tied (the rows of `B⁻¹` are O(1) on the scaled tableau). Default
    /// `1e-12`.
    pub lex_tol: f64,
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
    /// Negligible `z0`, on the scaled tableau (where the initial `z0` is
    /// `max(−q'_i / d'_i)`, between about 0.5 and 2). `z0` is made the
    /// leaving variable when the minimum-ratio step would leave it at or
    /// below `z0_tol · c_z0 / max(1, ‖c‖∞)` (then no other basic variable
    /// ends below `−z0_tol`, which the clamp of [`LemkeOptions::clamp_tol`]
    /// absorbs), and a secondary ray met while the basic `z0` is at most
    /// `z0_tol` is reported as [`Termination::Solved`]. Active only with
    /// [`LemkeOptions::prefer_z0`]; `0` keeps only the exact rule. The
    /// driver checks every such solution on the original data. Default
    /// `1e-9`.
    pub z0_tol: f64,
    /// Problems with at least this many unknowns run on the factorised
    /// (revised) basis of [`super::revised`] instead of the dense tableau;
    /// `usize::MAX` never, `0` always. Both follow the same rules; the
    /// revised path costs O(nnz) per pivot instead of O(n²) and pays a sparse
    /// LU every few dozen pivots, so it wins only on large, sparse problems.
    /// Default [`REVISED_FROM`].
    #[serde(default = "default_revised_from")]
    pub revised_from: usize,
}

/// Default of [`LemkeOptions::revised_from`], in unknowns: on the committed
/// dumps of tests/data/lcp the factorised basis was already faster than the
/// dense tableau in the 41–200 bucket and not slower below
/// (docs/physics.md §3.3).
pub const REVISED_FROM: usize = 41;

fn default_revised_from() -> usize {
    REVISED_FROM
}

impl Default for LemkeOptions {
    fn default() -> Self {
        Self {
            rule: PivotRule::Lexicographic,
            covering: None,
            pivot_tol: 1e-10,
            tie_tol: 1e-14,
            lex_tol: 1e-12,
            max_pivots: None,
            clamp_tol: 1e-9,
            prefer_z0: true,
            z0_tol: 1e-9,
            revised_from: REVISED_FROM,
        }
    }
}

pub(crate) fn options_valid(o: &LemkeOptions) -> bool {
    let ok = |x: f64| x.is_finite() && x >= 0.0;
    ok(o.pivot_tol) && ok(o.tie_tol) && ok(o.lex_tol) && ok(o.clamp_tol) && ok(o.z0_tol)
}
