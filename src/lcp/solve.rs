//! Robust LCP driver: a fixed sequence of Lemke attempts, each judged by its
//! residual on the original data.
//!
//! Attempts, in order, stopping at the first accepted one:
//!
//! 1. [`Strategy::Lexicographic`]: Lemke with [`PivotRule::Lexicographic`].
//! 2. [`Strategy::AlternativeRule`]: Lemke with
//!    [`SolveOptions::alternative_rule`] (default
//!    [`PivotRule::MinRatioLargestPivot`], which favours numerically large
//!    pivots where the lexicographic rule may pick small ones) and the
//!    covering vector [`SolveOptions::alternative_covering`] (default
//!    [`Covering::Diagonal`]); skipped if `alternative_rule` is `None`. For a
//!    matrix that is not copositive-plus, a secondary ray depends on the
//!    covering vector, so a different `d` can succeed where `d = e` fails.
//! 3. [`Strategy::Perturbed`]: Lemke (lexicographic) on `M + εI` for each
//!    `ε = ε_rel · max|M_ij|` with `ε_rel` from
//!    [`SolveOptions::perturbations`] (default `1e-12, 1e-9, 1e-6`). For a
//!    positive semidefinite or copositive `M` this makes the matrix strictly
//!    copositive/P-like and removes secondary rays and degeneracy.
//!
//! Attempts 1 and 3 use [`SolveOptions::covering`] (default all ones).
//! After **every** attempt, whatever Lemke reported, its `z` is projected
//! onto `z >= 0`, optionally polished (re-solving `M_αα z_α = −q_α` on the
//! support `α` of `z` with the **original** M and q, kept only if better) and
//! its [`residual`] on the original `(M, q)` is computed. The attempt is
//! accepted iff that residual is `<= tolerance`. A perturbed attempt is thus
//! accepted only on the merit of its residual for the original problem.
//!
//! If no attempt is accepted the status is [`SolveStatus::Failed`] and `z` is
//! the finite candidate with the lowest original residual ("best
//! available"), or all zeros if no attempt produced a finite one (non-finite
//! input). `z` is never NaN. The caller owns the last resort: the contact
//! layer is expected to apply one (e.g. drop friction and re-solve the
//! frictionless LCP, or apply no impulse) and to count it.

use super::json_f64;
use super::lemke::{lemke, max_abs, LemkeOptions, PivotRule, Termination};
use super::polish::polish;
use super::{residual, w_unchecked, Lcp};
use serde::{Deserialize, Serialize};

/// Which strategy of the driver produced an attempt.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Strategy {
    /// Lemke with the lexicographic rule on the original problem.
    Lexicographic,
    /// Lemke with the alternative pivot rule on the original problem.
    AlternativeRule,
    /// Lemke (lexicographic) on `M + εI`.
    Perturbed,
}

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
    /// A given vector (n finite positive entries, else the attempt reports
    /// [`Termination::InvalidInput`]).
    Custom(Vec<f64>),
}

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
        }
    }
}

/// Overall outcome of [`solve`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SolveStatus {
    /// The first attempt (lexicographic Lemke) was accepted.
    Solved,
    /// A later attempt was accepted.
    SolvedByFallback,
    /// No attempt met the tolerance; `z` is the best finite candidate or 0.
    Failed,
}

impl SolveStatus {
    /// Name used in logs and dumps: `"Solved"`, `"SolvedByFallback"`,
    /// `"Failed"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Solved => "Solved",
            Self::SolvedByFallback => "SolvedByFallback",
            Self::Failed => "Failed",
        }
    }

    /// `true` for [`SolveStatus::Solved`] and [`SolveStatus::SolvedByFallback`].
    pub fn is_solved(&self) -> bool {
        !matches!(self, Self::Failed)
    }
}

impl std::fmt::Display for SolveStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Options of [`solve`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolveOptions {
    /// Acceptance threshold on [`residual`] (original data). Default `1e-10`:
    /// met with margin by random P-matrix LCPs up to n = 60 (measured max
    /// about 1e-15 after polishing), and tight enough that an accepted `z` is
    /// a solution to about ten digits relative to `‖q‖`.
    pub tolerance: f64,
    /// See [`LemkeOptions::pivot_tol`].
    pub pivot_tol: f64,
    /// See [`LemkeOptions::tie_tol`].
    pub tie_tol: f64,
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
    /// Polish every candidate on its support (see module doc).
    pub polish: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        let l = LemkeOptions::default();
        Self {
            tolerance: 1e-10,
            pivot_tol: l.pivot_tol,
            tie_tol: l.tie_tol,
            clamp_tol: l.clamp_tol,
            max_pivots: None,
            covering: Covering::Ones,
            alternative_rule: Some(PivotRule::MinRatioLargestPivot),
            alternative_covering: Covering::Diagonal,
            perturbations: vec![1e-12, 1e-9, 1e-6],
            polish: true,
        }
    }
}

/// Record of one attempt of [`solve`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Attempt {
    /// Strategy of this attempt.
    pub strategy: Strategy,
    /// Pivot rule used.
    pub rule: PivotRule,
    /// Relative diagonal shift (0 unless [`Strategy::Perturbed`]).
    #[serde(with = "json_f64::scalar")]
    pub epsilon_rel: f64,
    /// Absolute diagonal shift actually added to M (0 unless perturbed).
    #[serde(with = "json_f64::scalar")]
    pub epsilon: f64,
    /// What Lemke reported.
    pub termination: Termination,
    /// Pivots of this attempt.
    pub pivots: usize,
    /// Residual of this attempt's candidate on the original problem
    /// (`Infinity` if none was finite).
    #[serde(with = "json_f64::scalar")]
    pub residual: f64,
    /// Whether the polished point replaced Lemke's `z`.
    pub polished: bool,
    /// Whether this attempt was accepted.
    pub accepted: bool,
}

/// Result of [`solve`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LcpSolution {
    /// Solution (or best candidate); finite and `>= 0`, length n.
    pub z: Vec<f64>,
    /// `w = M z + q` from the original data (non-finite only if the data are).
    #[serde(with = "json_f64::vector")]
    pub w: Vec<f64>,
    /// [`residual`] of `z` on the original data (`Infinity` if not computable).
    #[serde(with = "json_f64::scalar")]
    pub residual: f64,
    /// Total pivots over all attempts.
    pub pivots: usize,
    /// Every attempt, in order.
    pub attempts: Vec<Attempt>,
    /// Strategy of the accepted attempt, if any.
    pub accepted_by: Option<Strategy>,
    /// Overall status.
    pub status: SolveStatus,
}

/// Compact, serialisable summary of an [`LcpSolution`] (for logs/counters).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolveSummary {
    /// Dimension.
    pub n: usize,
    /// Overall status.
    pub status: SolveStatus,
    /// Strategy of the accepted attempt, if any.
    pub accepted_by: Option<Strategy>,
    /// Number of attempts made.
    pub attempts: usize,
    /// Total pivots.
    pub pivots: usize,
    /// Final residual on the original data.
    #[serde(with = "json_f64::scalar")]
    pub residual: f64,
}

impl LcpSolution {
    /// Compact summary for logging and counters.
    pub fn summary(&self) -> SolveSummary {
        SolveSummary {
            n: self.z.len(),
            status: self.status,
            accepted_by: self.accepted_by,
            attempts: self.attempts.len(),
            pivots: self.pivots,
            residual: self.residual,
        }
    }
}

/// Running counters over many solves (e.g. one simulation), serialisable.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SolveCounters {
    /// Number of solves recorded.
    pub solves: u64,
    /// Solved by the first (lexicographic) attempt.
    pub solved: u64,
    /// Solved by a fallback attempt.
    pub solved_by_fallback: u64,
    /// Failed (caller applied its last resort).
    pub failed: u64,
    /// Accepted by [`Strategy::AlternativeRule`].
    pub by_alternative_rule: u64,
    /// Accepted by [`Strategy::Perturbed`].
    pub by_perturbed: u64,
    /// Sum of pivots.
    pub total_pivots: u64,
    /// Largest pivot count of one solve.
    pub max_pivots: u64,
    /// Largest residual among accepted solves.
    #[serde(with = "json_f64::scalar")]
    pub max_accepted_residual: f64,
}

impl SolveCounters {
    /// Adds one solve to the counters.
    pub fn record(&mut self, s: &LcpSolution) {
        self.solves += 1;
        match s.status {
            SolveStatus::Solved => self.solved += 1,
            SolveStatus::SolvedByFallback => self.solved_by_fallback += 1,
            SolveStatus::Failed => self.failed += 1,
        }
        match s.accepted_by {
            Some(Strategy::AlternativeRule) => self.by_alternative_rule += 1,
            Some(Strategy::Perturbed) => self.by_perturbed += 1,
            _ => {}
        }
        let p = s.pivots as u64;
        self.total_pivots += p;
        self.max_pivots = self.max_pivots.max(p);
        if s.status.is_solved() {
            self.max_accepted_residual = self.max_accepted_residual.max(s.residual);
        }
    }
}

/// Solves `lcp` with the attempt sequence described in the module doc.
///
/// Never panics and never returns a non-finite `z`. If the LCP's fields are
/// inconsistent or `opts.tolerance` is not a finite non-negative number, no
/// attempt is made and the result is [`SolveStatus::Failed`] with `z = 0`
/// (length `lcp.q.len()`). With non-finite data only the first attempt is
/// made (every strategy would see the same data).
pub fn solve(lcp: &Lcp, opts: &SolveOptions) -> LcpSolution {
    let (m, q) = (&lcp.m[..], &lcp.q[..]);
    let n = q.len();
    if lcp.check().is_err() || !(opts.tolerance.is_finite() && opts.tolerance >= 0.0) {
        return LcpSolution {
            z: vec![0.0; n],
            w: q.to_vec(),
            residual: f64::INFINITY,
            pivots: 0,
            attempts: Vec::new(),
            accepted_by: None,
            status: SolveStatus::Failed,
        };
    }
    let finite = lcp.is_finite();

    let mut plan: Vec<(Strategy, PivotRule, f64)> =
        vec![(Strategy::Lexicographic, PivotRule::Lexicographic, 0.0)];
    if let Some(rule) = opts.alternative_rule {
        plan.push((Strategy::AlternativeRule, rule, 0.0));
    }
    for &e in &opts.perturbations {
        if e.is_finite() && e > 0.0 {
            plan.push((Strategy::Perturbed, PivotRule::Lexicographic, e));
        }
    }
    let mscale = {
        let s = max_abs(m);
        if s > 0.0 && s.is_finite() {
            s
        } else {
            1.0
        }
    };

    let mut attempts = Vec::with_capacity(plan.len());
    let mut pivots = 0usize;
    let mut best: Option<(Vec<f64>, f64)> = None;
    for (strategy, rule, eps_rel) in plan {
        let covering = if strategy == Strategy::AlternativeRule {
            &opts.alternative_covering
        } else {
            &opts.covering
        };
        let lopts = LemkeOptions {
            rule,
            covering: covering.vector(m, n),
            pivot_tol: opts.pivot_tol,
            tie_tol: opts.tie_tol,
            max_pivots: opts.max_pivots,
            clamp_tol: opts.clamp_tol,
            prefer_z0: true,
        };
        let epsilon = eps_rel * mscale;
        let res = if epsilon > 0.0 {
            let mut mp = m.to_vec();
            for i in 0..n {
                mp[i * n + i] += epsilon;
            }
            lemke(&mp, q, &lopts)
        } else {
            lemke(m, q, &lopts)
        };
        pivots = pivots.saturating_add(res.pivots);
        let candidate = evaluate(m, q, &res.z, opts.polish);
        let (resid, polished) = candidate
            .as_ref()
            .map_or((f64::INFINITY, false), |c| (c.1, c.2));
        let accepted = candidate.is_some() && resid <= opts.tolerance;
        attempts.push(Attempt {
            strategy,
            rule,
            epsilon_rel: eps_rel,
            epsilon,
            termination: res.termination,
            pivots: res.pivots,
            residual: resid,
            polished,
            accepted,
        });
        if let Some((z, r, _)) = candidate {
            if best.as_ref().is_none_or(|b| r < b.1) {
                best = Some((z, r));
            }
        }
        if accepted {
            break;
        }
        if !finite || res.termination == Termination::InvalidInput {
            break;
        }
    }

    let accepted_by = attempts.iter().find(|a| a.accepted).map(|a| a.strategy);
    let status = match accepted_by {
        Some(Strategy::Lexicographic) => SolveStatus::Solved,
        Some(_) => SolveStatus::SolvedByFallback,
        None => SolveStatus::Failed,
    };
    let z = match best {
        Some((z, _)) => z,
        None => vec![0.0; n],
    };
    let w = w_unchecked(m, q, &z);
    let residual = residual(m, q, &z);
    LcpSolution {
        z,
        w,
        residual,
        pivots,
        attempts,
        accepted_by,
        status,
    }
}

/// Projects `z` onto `z >= 0`, optionally polishes it, and returns the better
/// point with its residual on `(m, q)` and whether polishing won. `None` if
/// `z` is not finite.
fn evaluate(m: &[f64], q: &[f64], z: &[f64], do_polish: bool) -> Option<(Vec<f64>, f64, bool)> {
    if !z.iter().all(|x| x.is_finite()) {
        return None;
    }
    let zp: Vec<f64> = z.iter().map(|&x| x.max(0.0)).collect();
    let r = residual(m, q, &zp);
    if do_polish && r > 0.0 {
        if let Some(p) = polish(m, q, &zp) {
            let rp = residual(m, q, &p);
            if rp < r {
                return Some((p, rp, true));
            }
        }
    }
    Some((zp, r, false))
}
