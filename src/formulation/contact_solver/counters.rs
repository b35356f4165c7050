//! The counters of the contact solver: the LCP chain's, the warm start's,
//! the predicted basis's, the cone program's and the warm-start check's,
//! each list declared by [`super::ContactSolver`] when its part is on.

use crate::record::{Counter, Unit};

/// LCPs solved (every attempt chain, the frictionless last resort included).
pub const LCP_SOLVES: Counter = Counter::sum("lcp_solves", "LCPs solved");
/// Unknowns over every LCP solved.
pub const LCP_UNKNOWNS_TOTAL: Counter =
    Counter::sum("lcp_unknowns_total", "unknowns over every LCP solved");
/// Largest LCP solved, unknowns.
pub const LCP_SIZE_MAX: Counter =
    Counter::max("lcp_size_max", Unit::Count, "largest LCP solved, unknowns");
/// Dumps that could not be written.
pub const LCP_DUMP_FAILURES: Counter =
    Counter::sum("lcp_dump_failures", "LCP dumps that could not be written");
/// Accepted impulses outside the Coulomb cone beyond the rounding allowance.
pub const COULOMB_VIOLATIONS: Counter = Counter::sum(
    "coulomb_violations",
    "accepted impulses with |β| > μ λ (1 + 1e-9) beyond the rounding allowance",
);
/// Frictional LCPs replaced by the frictionless LCP of the same contacts.
pub const LCP_LAST_RESORT_FRICTIONLESS: Counter = Counter::sum(
    "lcp_last_resort_frictionless",
    "frictional LCPs replaced by the frictionless LCP of the same contacts",
);
/// Contact solves cut short by a stop request (SIGINT, SIGTERM:
/// [`crate::stop`]); the run ends at its last output before them, so their
/// answers reach no output. Not a failure; only listed when not 0.
pub const SOLVES_INTERRUPTED: Counter = Counter::sum(
    "solves_interrupted",
    "contact solves cut short by a stop request (SIGINT, SIGTERM); the run ended at its last output before them",
);
/// Contact problems left without impulse (every attempt failed).
pub const LCP_UNRESOLVED: Counter = Counter::sum(
    "lcp_unresolved",
    "contact problems left without impulse: every attempt failed",
);
/// Iterative answers finished exactly by the pivoting solver (`polish`).
pub const POLISH_SOLVES: Counter = Counter::sum(
    "polish_solves",
    "NSGS answers finished exactly by the pivoting solver from their active set (polish)",
);
/// Polished answers whose active set was the exact one (the basis solve
/// from it was accepted: no Lemke pivot).
pub const POLISH_ACTIVE_SET_EXACT: Counter = Counter::sum(
    "polish_active_set_exact",
    "polished answers whose active set was the exact one (accepted by the basis solve, no Lemke pivot)",
);
/// Polishes that failed: the NSGS answer was kept.
pub const POLISH_FAILED: Counter = Counter::sum(
    "polish_failed",
    "polishes whose LCP no attempt solved: the NSGS answer was kept",
);
/// The polish counters, declared when polish is on.
pub const POLISH_COUNTERS: &[&Counter] =
    &[&POLISH_SOLVES, &POLISH_ACTIVE_SET_EXACT, &POLISH_FAILED];

/// Lemke pivots over every attempt.
pub const LEMKE_PIVOTS: Counter = Counter::sum("lemke_pivots", "Lemke pivots over every attempt");
/// Most pivots of one solve.
pub const LEMKE_MAX_PIVOTS: Counter = Counter::sum("lemke_max_pivots", "most pivots of one solve");
/// LCPs solved by the first attempt.
pub const LCP_SOLVED_FIRST_ATTEMPT: Counter = Counter::sum(
    "lcp_solved_first_attempt",
    "LCPs solved by the first attempt",
);
/// LCPs solved by a fallback attempt.
pub const LCP_SOLVED_BY_FALLBACK: Counter = Counter::sum(
    "lcp_solved_by_fallback",
    "LCPs solved by a fallback attempt",
);
/// LCPs solved by the alternative pivot rule.
pub const LCP_FALLBACK_ALTERNATIVE_RULE: Counter = Counter::sum(
    "lcp_fallback_alternative_rule",
    "LCPs solved by the alternative pivot rule",
);
/// LCPs solved with a perturbed matrix.
pub const LCP_FALLBACK_PERTURBED: Counter = Counter::sum(
    "lcp_fallback_perturbed",
    "LCPs solved with a perturbed matrix",
);
/// LCPs no attempt solved.
pub const LCP_FAILED: Counter = Counter::sum("lcp_failed", "LCPs no attempt solved");
/// LCPs solved by the warm start from the previous basis of their contacts.
pub const LCP_WARM_HITS: Counter = Counter::sum(
    "lcp_warm_hits",
    "LCPs solved by the warm start from the previous basis of their contacts",
);
/// Warm starts tried and rejected (the LCP then solved cold).
pub const LCP_WARM_MISSES: Counter = Counter::sum(
    "lcp_warm_misses",
    "warm starts tried and rejected (the LCP then solved cold)",
);
/// LCPs solved by the warm Lemke path from the previous basis of their
/// contacts (after a rejected principal pivoting).
pub const LCP_WARM_LEMKE_HITS: Counter = Counter::sum(
    "lcp_warm_lemke_hits",
    "LCPs solved by Lemke's path from the previous basis of their contacts (warm Lemke)",
);
/// Warm Lemke paths run and not accepted (the LCP then solved cold).
pub const LCP_WARM_LEMKE_MISSES: Counter = Counter::sum(
    "lcp_warm_lemke_misses",
    "warm Lemke paths run and not accepted (the LCP then solved cold)",
);
/// Pivots of the warm Lemke paths.
pub const LCP_WARM_LEMKE_PIVOTS: Counter = Counter::sum(
    "lcp_warm_lemke_pivots",
    "pivots of the warm Lemke paths (included in lemke_pivots)",
);
/// Indices whose side (z basic or w basic) differs between the guessed
/// basis and the accepted solution's support.
pub const LCP_WARM_SUPPORT_CHANGES: Counter = Counter::sum(
    "lcp_warm_support_changes",
    "unknowns whose side differs between the guessed basis and the accepted solution's support",
);

/// The counters of the warm start (declared only when it is on).
pub(super) const WARM_COUNTERS: &[&Counter] = &[
    &LCP_WARM_LEMKE_HITS,
    &LCP_WARM_LEMKE_MISSES,
    &LCP_WARM_LEMKE_PIVOTS,
    &LCP_WARM_SUPPORT_CHANGES,
];

/// LCPs solved from a predicted basis
/// ([`ContactSolver::with_predict_from`](super::ContactSolver::with_predict_from)).
pub const LCP_PREDICT_SOLVES: Counter = Counter::sum(
    "lcp_predict_solves",
    "LCPs started from a basis predicted by block Gauss-Seidel (predict_from)",
);
/// Predicted solves accepted by the warm Lemke path from the prediction.
pub const LCP_PREDICT_HITS: Counter = Counter::sum(
    "lcp_predict_hits",
    "predicted solves accepted by Lemke's path from the predicted basis",
);
/// Predicted solves that fell back to the cold attempts.
pub const LCP_PREDICT_MISSES: Counter = Counter::sum(
    "lcp_predict_misses",
    "predicted solves whose warm Lemke path was not accepted (then solved cold)",
);
/// Block Gauss–Seidel sweeps of the predictions.
pub const LCP_PREDICT_SWEEPS: Counter = Counter::sum(
    "lcp_predict_sweeps",
    "block Gauss-Seidel sweeps of the predictions",
);
/// Pivots of the warm Lemke paths from a prediction.
pub const LCP_PREDICT_PIVOTS: Counter = Counter::sum(
    "lcp_predict_pivots",
    "pivots of the warm Lemke paths from a predicted basis (included in lemke_pivots)",
);
/// Indices where the predicted basis differs from the accepted solution.
pub const LCP_PREDICT_WRONG: Counter = Counter::sum(
    "lcp_predict_wrong",
    "non-degenerate unknowns whose side differs between the predicted basis and the accepted solution",
);

/// The counters of the predicted basis (declared only when it is on).
pub(super) const PREDICT_COUNTERS: &[&Counter] = &[
    &LCP_PREDICT_SOLVES,
    &LCP_PREDICT_HITS,
    &LCP_PREDICT_MISSES,
    &LCP_PREDICT_SWEEPS,
    &LCP_PREDICT_PIVOTS,
    &LCP_PREDICT_WRONG,
];

/// LCPs accepted after principal pivoting completed a Lemke path.
pub const LCP_COMPLETED_BY_PIVOTING: Counter = Counter::sum(
    "lcp_completed_by_pivoting",
    "LCPs accepted after principal pivoting completed a Lemke path that stopped next to a solution",
);
/// LCPs accepted by an attempt on the factorised (revised) Lemke basis.
pub const LCP_REVISED: Counter = Counter::sum(
    "lcp_revised",
    "LCPs accepted by a Lemke attempt on the factorised (revised) basis (large groups)",
);
/// Largest accepted relative residual.
pub const LCP_MAX_ACCEPTED_RESIDUAL: Counter = Counter::value(
    "lcp_max_accepted_residual",
    Unit::Dimensionless,
    "largest accepted residual ‖min(z, w)‖/‖q‖",
);
/// Largest `|β| / (μ λ)` over accepted impulses.
pub const MAX_COULOMB_RATIO: Counter = Counter::value(
    "max_coulomb_ratio",
    Unit::Dimensionless,
    "largest |β|/(μ λ) over accepted impulses",
);
/// Cone programs solved.
pub const CONE_SOLVES: Counter = Counter::sum("cone_solves", "cone programs solved");
/// Interior-point iterations over every cone solve.
pub const CONE_ITERATIONS: Counter = Counter::sum(
    "cone_iterations",
    "interior-point iterations over every cone solve",
);
/// Most iterations of one cone solve.
pub const CONE_MAX_ITERATIONS: Counter = Counter::max(
    "cone_max_iterations",
    Unit::Count,
    "most interior-point iterations of one cone solve",
);
/// Unknowns over every cone program.
pub const CONE_UNKNOWNS_TOTAL: Counter =
    Counter::sum("cone_unknowns_total", "unknowns over every cone program");
/// Cone solves clarabel reported `AlmostSolved`.
pub const CONE_ALMOST_SOLVED: Counter = Counter::sum(
    "cone_almost_solved",
    "cone solves clarabel reported AlmostSolved",
);
/// Cone solves rescued by the active-set polish.
pub const CONE_RESCUED_BY_POLISH: Counter = Counter::sum(
    "cone_rescued_by_polish",
    "cone solves rescued by the active-set polish",
);
/// Cone solves that failed.
pub const CONE_FAILED: Counter = Counter::sum("cone_failed", "cone solves that failed");
/// Failed cone solves handed to the LCP chain.
pub const CONE_FALLBACK_LCP: Counter = Counter::sum(
    "cone_fallback_lcp",
    "failed cone solves handed to the LCP chain",
);
/// Largest distance of a raw cone solution outside the cone, relative.
pub const CONE_MAX_PROJECTION_REL: Counter = Counter::max(
    "cone_max_projection_rel",
    Unit::Dimensionless,
    "largest distance of a raw cone solution outside the cone, relative to the impulse scale",
);
/// Cone solutions replaced by their active-set polish.
pub const CONE_POLISHED: Counter = Counter::sum(
    "cone_polished",
    "cone solutions replaced by their active-set polish",
);
/// The cone artefact: largest normal speed of a pushing contact, m/s.
pub const CONE_MAX_PUSHING_NORMAL_SPEED: Counter = Counter::max(
    "cone_max_pushing_normal_speed_m_per_s",
    Unit::MetrePerSecond,
    "largest normal speed (with the Newton offset) of a pushing contact: μ|u_T| while sliding",
);

/// Sustained-contact LCPs solved by the warm start and compared with their
/// cold solution (warm-start check).
pub const WARM_CHECK_SUSTAINED: Counter = Counter::sum(
    "warm_check_sustained",
    "sustained-contact LCPs solved by the warm start and solved cold too (warm-start check)",
);
/// Of [`WARM_CHECK_SUSTAINED`], those whose cold solution is another one.
pub const WARM_CHECK_SUSTAINED_DIFFERENT: Counter = Counter::sum(
    "warm_check_sustained_different",
    "of them, the cold solution differs beyond 1e-6 of the largest impulse (another solution)",
);
/// Of [`WARM_CHECK_SUSTAINED`], those whose cold solution differs only by rounding.
pub const WARM_CHECK_SUSTAINED_ROUNDING: Counter = Counter::sum(
    "warm_check_sustained_rounding",
    "of them, the cold solution differs, by at most 1e-6 of the largest impulse (rounding)",
);
/// Impact (compression) LCPs solved by the warm start and compared.
pub const WARM_CHECK_IMPACT: Counter = Counter::sum(
    "warm_check_impact",
    "impact LCPs solved by the warm start and solved cold too (warm-start check)",
);
/// Of [`WARM_CHECK_IMPACT`], those whose cold solution is another one.
pub const WARM_CHECK_IMPACT_DIFFERENT: Counter = Counter::sum(
    "warm_check_impact_different",
    "of them, the cold solution differs beyond 1e-6 of the largest impulse (another solution)",
);
/// Of [`WARM_CHECK_IMPACT`], those whose cold solution differs only by rounding.
pub const WARM_CHECK_IMPACT_ROUNDING: Counter = Counter::sum(
    "warm_check_impact_rounding",
    "of them, the cold solution differs, by at most 1e-6 of the largest impulse (rounding)",
);
/// Compared LCPs that the cold driver failed to solve.
pub const WARM_CHECK_COLD_FAILED: Counter = Counter::sum(
    "warm_check_cold_failed",
    "warm-solved LCPs that the cold driver failed to solve (warm-start check)",
);
/// Largest relative difference of a warm and a cold solution.
pub const WARM_CHECK_MAX_DIFFERENCE: Counter = Counter::max(
    "warm_check_max_difference",
    Unit::Dimensionless,
    "largest max|z_warm − z_cold| / max(‖z_warm‖∞, ‖z_cold‖∞) over the compared LCPs",
);

/// Pivots of the compared warm solves (0 for a principal-pivoting hit).
pub const WARM_CHECK_WARM_PIVOTS: Counter = Counter::sum(
    "warm_check_warm_pivots",
    "Lemke pivots of the warm-solved LCPs compared (warm-start check)",
);
/// Pivots of the cold solves of the same LCPs.
pub const WARM_CHECK_COLD_PIVOTS: Counter = Counter::sum(
    "warm_check_cold_pivots",
    "Lemke pivots of the cold solves of the same LCPs (warm-start check)",
);

/// The counters of the warm-start check.
pub(super) const WARM_CHECK_COUNTERS: &[&Counter] = &[
    &WARM_CHECK_WARM_PIVOTS,
    &WARM_CHECK_COLD_PIVOTS,
    &WARM_CHECK_SUSTAINED,
    &WARM_CHECK_SUSTAINED_DIFFERENT,
    &WARM_CHECK_SUSTAINED_ROUNDING,
    &WARM_CHECK_IMPACT,
    &WARM_CHECK_IMPACT_DIFFERENT,
    &WARM_CHECK_IMPACT_ROUNDING,
    &WARM_CHECK_COLD_FAILED,
    &WARM_CHECK_MAX_DIFFERENCE,
];

/// The counters of the `lcp` solver.
pub(super) const LCP_COUNTERS: &[&Counter] = &[
    &LCP_SOLVES,
    &LCP_UNKNOWNS_TOTAL,
    &LCP_DUMP_FAILURES,
    &COULOMB_VIOLATIONS,
    &LCP_LAST_RESORT_FRICTIONLESS,
    &LCP_UNRESOLVED,
    &LEMKE_PIVOTS,
    &LEMKE_MAX_PIVOTS,
    &LCP_SOLVED_FIRST_ATTEMPT,
    &LCP_SOLVED_BY_FALLBACK,
    &LCP_FALLBACK_ALTERNATIVE_RULE,
    &LCP_FALLBACK_PERTURBED,
    &LCP_FAILED,
    &LCP_WARM_HITS,
    &LCP_WARM_MISSES,
    &LCP_COMPLETED_BY_PIVOTING,
    &LCP_REVISED,
    &LCP_SIZE_MAX,
    &LCP_MAX_ACCEPTED_RESIDUAL,
    &MAX_COULOMB_RATIO,
];

/// The counters the `cone` solver adds.
pub(super) const CONE_COUNTERS: &[&Counter] = &[
    &CONE_SOLVES,
    &CONE_ITERATIONS,
    &CONE_UNKNOWNS_TOTAL,
    &CONE_ALMOST_SOLVED,
    &CONE_RESCUED_BY_POLISH,
    &CONE_FAILED,
    &CONE_FALLBACK_LCP,
    &CONE_POLISHED,
    &CONE_MAX_ITERATIONS,
    &CONE_MAX_PROJECTION_REL,
    &CONE_MAX_PUSHING_NORMAL_SPEED,
];
