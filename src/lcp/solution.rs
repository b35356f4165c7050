//! What the LCP driver [`super::solve()`] reports: the strategy and record
//! of each attempt, the overall status, the solution with its summary, and
//! the counters over many solves; and the guessed basis a warm solve starts
//! from.

use super::json_f64;
use super::lemke_options::{PivotRule, Termination};
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
    /// Principal pivoting from a guessed basis ([`solve_warm`](super::solve_warm())), before any
    /// Lemke attempt.
    WarmStart,
    /// Lemke's path from the guessed basis
    /// ([`solve_warm`](super::solve_warm()), after a rejected principal
    /// pivoting;
    /// [`SolveOptions::warm_lemke`](super::SolveOptions::warm_lemke)), on the
    /// factorised basis, before the cold attempts.
    WarmLemke,
    /// Lemke with [`PivotRule::Harris`] on the original problem: the first cold
    /// attempt on problems of at least
    /// [`SolveOptions::harris_from`](super::SolveOptions::harris_from)
    /// unknowns, before the lexicographic one.
    Harris,
}

/// Overall outcome of [`solve`](super::solve()).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SolveStatus {
    /// The warm start ([`solve_warm`](super::solve_warm()): its principal
    /// pivoting or its Lemke path) or the first cold Lemke attempt
    /// (lexicographic, or Harris on problems of at least
    /// [`SolveOptions::harris_from`](super::SolveOptions::harris_from)
    /// unknowns) was accepted.
    Solved,
    /// A later attempt was accepted.
    SolvedByFallback,
    /// No attempt met the tolerance; `z` is the best finite candidate or 0.
    Failed,
    /// A stop was asked for during an attempt ([`crate::stop`]): no later
    /// attempt was made; `z` is the best finite candidate or 0, not a
    /// solution (a run discards the step that holds it).
    Interrupted,
}

impl SolveStatus {
    /// Name used in logs and dumps: `"Solved"`, `"SolvedByFallback"`,
    /// `"Failed"`, `"Interrupted"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Solved => "Solved",
            Self::SolvedByFallback => "SolvedByFallback",
            Self::Failed => "Failed",
            Self::Interrupted => "Interrupted",
        }
    }

    /// `true` for [`SolveStatus::Solved`] and [`SolveStatus::SolvedByFallback`].
    pub fn is_solved(&self) -> bool {
        matches!(self, Self::Solved | Self::SolvedByFallback)
    }
}

impl std::fmt::Display for SolveStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Record of one attempt of [`solve`](super::solve()).
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
    /// Basis solves of the principal pivoting in the polish (0 if it did
    /// not run).
    pub basis_solves: usize,
    /// Whether this attempt was accepted.
    pub accepted: bool,
    /// Whether it ran on the factorised (revised) basis rather than the
    /// dense tableau (see [`SolveOptions::revised_from`](super::SolveOptions::revised_from)).
    #[serde(default)]
    pub revised: bool,
}

/// Record of the warm start of [`solve_warm`](super::solve_warm()).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WarmStart {
    /// Basis solves of its principal pivoting.
    pub basis_solves: usize,
    /// Residual of its candidate on the original problem (`Infinity` if it
    /// reached no feasible basis).
    #[serde(with = "json_f64::scalar")]
    pub residual: f64,
    /// Whether it was accepted (then no Lemke attempt was made).
    pub accepted: bool,
}

/// A guessed complementary basis for [`solve_warm`](super::solve_warm()), e.g. the previous
/// step's solution of the same contacts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BasisGuess {
    /// `basic[i]`: `z_i` is basic (in the support); else `w_i` is.
    pub basic: Vec<bool>,
    /// Starting point of the basis solves (entries off the basis ignored).
    pub z: Vec<f64>,
}

/// Result of [`solve`](super::solve()).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LcpSolution {
    /// Solution (or best candidate); finite and `>= 0`, length n.
    pub z: Vec<f64>,
    /// `w = M z + q` from the original data (non-finite only if the data are).
    #[serde(with = "json_f64::vector")]
    pub w: Vec<f64>,
    /// [`residual`](super::residual()) of `z` on the original data (`Infinity` if not computable).
    #[serde(with = "json_f64::scalar")]
    pub residual: f64,
    /// Total pivots over all attempts.
    pub pivots: usize,
    /// Every Lemke attempt, in order (none when the warm start was
    /// accepted).
    pub attempts: Vec<Attempt>,
    /// The warm start, if [`solve_warm`](super::solve_warm()) tried one.
    pub warm: Option<WarmStart>,
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
    /// The warm Lemke attempt ([`Strategy::WarmLemke`]), if one ran.
    pub fn warm_lemke_attempt(&self) -> Option<&Attempt> {
        self.attempts
            .iter()
            .find(|a| a.strategy == Strategy::WarmLemke)
    }

    /// An empty result (no unknowns, failed) to be filled by
    /// [`solve_into`](super::solve_into()).
    pub fn empty() -> Self {
        Self {
            z: Vec::new(),
            w: Vec::new(),
            residual: f64::INFINITY,
            pivots: 0,
            attempts: Vec::new(),
            warm: None,
            accepted_by: None,
            status: SolveStatus::Failed,
        }
    }

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
    /// Solved by the first attempt (see [`SolveStatus::Solved`]).
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
    /// Solves whose warm start was accepted.
    pub warm_hits: u64,
    /// Solves whose warm start was tried and rejected.
    pub warm_misses: u64,
    /// Solves accepted after the principal pivoting of the polish switched
    /// indices (a Lemke path completed next to a solution).
    pub completed_by_pivoting: u64,
    /// Solves accepted by an attempt on the factorised (revised) basis.
    #[serde(default)]
    pub revised: u64,
    /// Solves accepted by the warm Lemke path ([`Strategy::WarmLemke`]).
    #[serde(default)]
    pub warm_lemke_hits: u64,
    /// Solves whose warm Lemke path was run and not accepted (the cold
    /// attempts followed).
    #[serde(default)]
    pub warm_lemke_misses: u64,
    /// Pivots of the warm Lemke paths (included in `total_pivots`).
    #[serde(default)]
    pub warm_lemke_pivots: u64,
    /// Solves accepted by [`Strategy::Harris`].
    #[serde(default)]
    pub by_harris: u64,
}

impl SolveCounters {
    /// Adds one solve to the counters.
    pub fn record(&mut self, s: &LcpSolution) {
        self.solves += 1;
        match s.status {
            SolveStatus::Solved => self.solved += 1,
            SolveStatus::SolvedByFallback => self.solved_by_fallback += 1,
            SolveStatus::Failed => self.failed += 1,
            // Not a failure: the run that asked for the stop discards it
            // (crate::stop); the formulations count it apart.
            SolveStatus::Interrupted => {}
        }
        match s.accepted_by {
            Some(Strategy::AlternativeRule) => self.by_alternative_rule += 1,
            Some(Strategy::Perturbed) => self.by_perturbed += 1,
            Some(Strategy::Harris) => self.by_harris += 1,
            _ => {}
        }
        let p = s.pivots as u64;
        self.total_pivots += p;
        self.max_pivots = self.max_pivots.max(p);
        if s.status.is_solved() {
            self.max_accepted_residual = self.max_accepted_residual.max(s.residual);
        }
        match s.warm {
            Some(w) if w.accepted => self.warm_hits += 1,
            Some(_) => self.warm_misses += 1,
            None => {}
        }
        if s.attempts.iter().any(|a| a.accepted && a.basis_solves >= 2) {
            self.completed_by_pivoting += 1;
        }
        if s.attempts.iter().any(|a| a.accepted && a.revised) {
            self.revised += 1;
        }
        if let Some(a) = s.warm_lemke_attempt() {
            self.warm_lemke_pivots += a.pivots as u64;
            if a.accepted {
                self.warm_lemke_hits += 1;
            } else {
                self.warm_lemke_misses += 1;
            }
        }
    }
}
