//! The options of the LCP driver [`super::solve()`]: the covering vectors of
//! its attempts, the tolerances and caps, and their defaults (the attempts
//! themselves are described in [`super::solve`]).

use super::lemke_options::{LemkeOptions, PivotRule, REVISED_FROM};
use super::scaling::max_abs;
use serde::{Deserialize, Serialize};

/// Choice of the covering vector `d` of an attempt.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Covering {
    /// `d = (1, …, 1)`, the classical choice.
    Ones,
    /// `d_i = max(sqrt(|M_ii| / max_j |M_jj|), 1e-8)`, and `d_i = 1` for all
    /// i if the diagonal is zero or non-finite. With this `d` the Lemke path is
    /// invariant under a symmetric diagonal scaling `D M D`, `D q` of the
    /// problem (up to the 1e-8 floor), unlike with `d = e`.
    Diagonal,
    /// `d_i = max(|M_ii| / max_j |M_jj|, floor)` (the diagonal itself, not its
    /// square root), and `d_i = 1` for all i if the diagonal is zero or
    /// non-finite, or if n is at most [`SMALL_N`] (measured on 2,000 small
    /// dumps: no pivots saved, and the vector costs about a tenth of a solve of
    /// up to 8 unknowns); a floor outside (0, 1] gives an invalid vector (the
    /// attempt reports
    /// [`Termination::InvalidInput`](super::Termination::InvalidInput)); a
    /// floor of 1 is [`Covering::Ones`]. `z0 d` is then the change of `w` that
    /// the impulse `z0` on every unknown at once gives through the diagonal of
    /// `M` alone, each contact as if alone; the rows with a zero diagonal (the
    /// friction cone rows of Stewart–Trinkle) get the floor. The default of the
    /// cold attempts, with [`DEFAULT_COVERING_FLOOR`] (docs/physics.md §3.3,
    /// "The covering vector").
    DiagonalRatio(f64),
    /// A given vector (n finite positive entries, else the attempt reports
    /// [`Termination::InvalidInput`](super::Termination::InvalidInput)).
    Custom(Vec<f64>),
}

/// Floor of [`Covering::DiagonalRatio`] in the default
/// [`SolveOptions::covering`]: 1e-3 of the largest diagonal entry, for the
/// rows whose diagonal is zero or small. Measured on the 40 bay-jam LCPs of
/// more than 800 unknowns, Lemke alone (no polish or fallback): floors
/// 1e-1, 1e-2 and 1e-3 take 76,737, 77,679 and 77,603 pivots (`d = e`:
/// 135,667), all 40 solved; 1e-5 takes 77,633 but leaves 10 of them above
/// the tolerance. Chosen in the flat range, nearer its small end.
pub const DEFAULT_COVERING_FLOOR: f64 = 1e-3;

impl Covering {
    /// The vector for matrix `m` of dimension `n`; `None` means all ones.
    pub fn vector(&self, m: &[f64], n: usize) -> Option<Vec<f64>> {
        match self {
            Self::Ones => None,
            Self::Custom(d) => Some(d.clone()),
            Self::Diagonal => {
                if n.checked_mul(n) != Some(m.len()) {
                    return None;
                }
                let diag: Vec<f64> = (0..n).map(|i| m[i * n + i].abs()).collect();
                let dmax = max_abs(&diag);
                if !(dmax > 0.0 && dmax.is_finite()) {
                    return None;
                }
                Some(diag.iter().map(|&x| (x / dmax).sqrt().max(1e-8)).collect())
            }
            Self::DiagonalRatio(floor) => {
                if n <= SMALL_N || n.checked_mul(n) != Some(m.len()) {
                    return None;
                }
                let dmax = (0..n).fold(0.0_f64, |a, i| a.max(m[i * n + i].abs()));
                if !(dmax > 0.0 && dmax.is_finite()) {
                    return None;
                }
                if !(*floor > 0.0 && *floor <= 1.0) {
                    // Refused by the attempt as an invalid covering vector.
                    return Some(vec![f64::NAN; n]);
                }
                Some(
                    (0..n)
                        .map(|i| (m[i * n + i].abs() / dmax).max(*floor))
                        .collect(),
                )
            }
        }
    }
}

/// Options of [`solve`](super::solve()).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolveOptions {
    /// Acceptance threshold on [`residual`](super::residual()) (original data). Default `1e-10`:
    /// met with margin by random P-matrix LCPs up to n = 60 (measured max
    /// about 1e-15 after polishing), and tight enough that an accepted `z` is
    /// a solution to about ten digits relative to `‖q‖`.
    pub tolerance: f64,
    /// See [`LemkeOptions::pivot_tol`].
    pub pivot_tol: f64,
    /// See [`LemkeOptions::tie_tol`].
    pub tie_tol: f64,
    /// See [`LemkeOptions::lex_tol`].
    pub lex_tol: f64,
    /// See [`LemkeOptions::clamp_tol`].
    pub clamp_tol: f64,
    /// Pivot cap per attempt; see [`LemkeOptions::max_pivots`].
    pub max_pivots: Option<usize>,
    /// Covering vector of the lexicographic and perturbed attempts.
    pub covering: Covering,
    /// Rule of the second attempt; `None` skips it.
    pub alternative_rule: Option<PivotRule>,
    /// Covering vector of the second attempt.
    pub alternative_covering: Covering,
    /// Relative diagonal shifts `ε_rel` of the perturbed attempts, tried in
    /// order; non-finite or non-positive entries are skipped.
    pub perturbations: Vec<f64>,
    /// Polish every candidate: refinement of the final basis, then
    /// principal pivoting from its support (see module doc).
    pub polish: bool,
    /// Basis solves allowed to the principal pivoting of the polish (1: only
    /// the re-solve on the support of the candidate; 0: none). Default 4:
    /// on the 2,841 dumps of the field_200_coast corpus the candidates it
    /// completes need at most 3 (2 solves complete 24 of 25 that end on a
    /// secondary ray next to a solution), and a basis solve costs less than
    /// a tenth of a Lemke run of the same size.
    pub polish_solves: usize,
    /// See [`LemkeOptions::z0_tol`].
    pub z0_tol: f64,
    /// Basis solves allowed to the principal pivoting of a warm start
    /// ([`solve_warm`](super::solve_warm())) before it gives way to the attempts. Default 16:
    /// on field_200_coast (9,000 s, event-driven) the warm starts that are
    /// accepted need 1.3 basis solves on average for 1–8 unknowns, 2.4 for
    /// 9–40, 4.3 for 41–200 and 5.9 for 201–800; with 4 solves allowed 13 %
    /// of the warm starts were rejected (then solved cold, after paying for
    /// them), with 16, 2 %.
    pub warm_solves: usize,
    /// See [`LemkeOptions::revised_from`]: attempts on problems of at least
    /// this many unknowns run on the factorised basis.
    #[serde(default = "default_revised_from")]
    pub revised_from: usize,
    /// Residual (relative to `‖q‖`, compensated, on the original data) at or
    /// below which an accepted candidate of a Lemke run that reported
    /// [`Termination::Solved`](super::Termination::Solved) on a small problem,
    /// of at most [`SMALL_N`] unknowns, is kept as Lemke left it, without the
    /// refinement of its basis (which would only move its last digits, for up
    /// to three more compensated residuals: about a third of a small solve).
    /// Larger problems, a candidate above it, or one from a run that did not
    /// report [`Termination::Solved`](super::Termination::Solved), are polished
    /// as always. Default [`UNPOLISHED_BELOW`] (`1e-13`); `0` refines every
    /// candidate (the driver before this default, bit for bit). Chosen, not
    /// fitted: a thousandth of the default acceptance tolerance, so a kept
    /// candidate still meets it a thousand times over (docs/physics.md §3.3,
    /// "Small problems"). (Until this version two options overlapped here, this
    /// one for every size and `small_unpolished_below` for the small problems,
    /// both off by default; the latter's old name is still read.)
    #[serde(default = "default_unpolished_below", alias = "small_unpolished_below")]
    pub unpolished_below: f64,
    /// With a guessed basis ([`solve_warm`](super::solve_warm())) that
    /// principal pivoting did not accept, run Lemke's path from that basis
    /// ([`Strategy::WarmLemke`](super::Strategy::WarmLemke), docs/physics.md
    /// §3.3 "Warm Lemke") before the cold attempts. Default `false`: on the
    /// jammed bay it cost more CPU than the cold attempts it replaced and moved
    /// the trajectories (§3.3); `false` is the warm start as it was before this
    /// option (principal pivoting, then the cold attempts).
    #[serde(default = "default_warm_lemke")]
    pub warm_lemke: bool,
    /// Pivot cap of the warm Lemke path, per unknown (the cap is
    /// `ceil(warm_lemke_pivots · (n + 1))`, at least 1). Default 1: a cold
    /// path takes about 2.5 n pivots on the large contact LCPs of a jammed
    /// pack, so a warm path that has not ended after n pivots has already
    /// cost about half of a cold solve, which then follows.
    #[serde(default = "default_warm_lemke_pivots")]
    pub warm_lemke_pivots: f64,
    /// Problems of at least this many unknowns start with a cold attempt
    /// with [`PivotRule::Harris`] ([`Strategy::Harris`](super::Strategy::Harris)) before the
    /// lexicographic one; `usize::MAX` never (the default,
    /// [`HARRIS_FROM`]), `0` always. Off by default because the measurement
    /// is mixed (docs/physics.md §3.3, "Harris ratio test"): on the 40
    /// LCPs of more than 800 unknowns of one bay-jam window it removed all
    /// 9 fallbacks (32.5 s of CPU against 41.0 s), on the 6 of another
    /// window it failed on 4 and cost 31.1 s against 25.8 s.
    #[serde(default = "default_harris_from")]
    pub harris_from: usize,
}

/// Default of [`SolveOptions::harris_from`]: `usize::MAX`, no Harris
/// attempt (the plan as before it existed).
pub const HARRIS_FROM: usize = usize::MAX;

fn default_harris_from() -> usize {
    HARRIS_FROM
}

/// Largest number of unknowns of a "small" problem, to which
/// [`SolveOptions::unpolished_below`] applies: 40, every problem of the
/// dense tableau under the default [`SolveOptions::revised_from`] (the
/// contact LCPs of up to ten frictional contacts).
pub const SMALL_N: usize = 40;

/// Default of [`SolveOptions::unpolished_below`]: `1e-13` (relative
/// residual), a thousandth of the default acceptance tolerance `1e-10`.
pub const UNPOLISHED_BELOW: f64 = 1e-13;

fn default_unpolished_below() -> f64 {
    UNPOLISHED_BELOW
}

fn default_warm_lemke() -> bool {
    false
}

fn default_warm_lemke_pivots() -> f64 {
    1.0
}

fn default_revised_from() -> usize {
    REVISED_FROM
}

impl Default for SolveOptions {
    fn default() -> Self {
        let l = LemkeOptions::default();
        Self {
            tolerance: 1e-10,
            pivot_tol: l.pivot_tol,
            tie_tol: l.tie_tol,
            lex_tol: l.lex_tol,
            clamp_tol: l.clamp_tol,
            max_pivots: None,
            covering: Covering::DiagonalRatio(DEFAULT_COVERING_FLOOR),
            alternative_rule: Some(PivotRule::MinRatioLargestPivot),
            alternative_covering: Covering::Diagonal,
            perturbations: vec![1e-12, 1e-9, 1e-6],
            polish: true,
            polish_solves: 4,
            z0_tol: l.z0_tol,
            warm_solves: 16,
            revised_from: l.revised_from,
            unpolished_below: default_unpolished_below(),
            warm_lemke: default_warm_lemke(),
            warm_lemke_pivots: default_warm_lemke_pivots(),
            harris_from: default_harris_from(),
        }
    }
}
