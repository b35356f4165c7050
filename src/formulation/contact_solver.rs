//! The one contact-problem solver of the formulations that solve contact
//! problems (event-driven, Moreau–Jean): Lemke's LCP and the cone program are
//! two choices of it ([`SolverKind`]), with one set of counters, one
//! fallback chain, one Coulomb check, one row scaling and one dump writer.
//!
//! - **`lcp`**: the velocity–impulse LCP of docs/physics.md §3.1 by
//!   [`crate::lcp::solve()`] (lexicographic Lemke, another pivot rule with
//!   another covering vector, a perturbed matrix), whose residual is
//!   recomputed on the original data. Each Coulomb row
//!   `σ_j = μ λ_j − Eᵀβ̃` comes scaled by the contact's normal Delassus
//!   diagonal ([`ContactLcp::assemble`]) so that every row of `w`
//!   is a velocity and the residual `‖min(z, w)‖/‖q‖` is consistent in units;
//!   the scaling keeps the solutions. When every attempt fails, the last
//!   resort is the frictionless LCP of the same contacts
//!   ([`LCP_LAST_RESORT_FRICTIONLESS`]); if that fails too, no impulse is
//!   applied ([`LCP_UNRESOLVED`]). Every LCP solved is written to the dump
//!   folder when one is given.
//! - **`cone`**: the Anitescu–Tasora relaxation ([`crate::contact::cone`]),
//!   a second-order-cone program solved by clarabel; a failed cone solve is
//!   counted ([`CONE_FAILED`]) and the problem falls back to the `lcp`
//!   chain above ([`CONE_FALLBACK_LCP`]).
//!
//! Every accepted frictional impulse goes through the same Coulomb check
//! ([`ContactSolver::check_coulomb`]) and into the contact log. The returned
//! `z` is never NaN.
//!
//! **Warm start** ([`ContactSolver::with_warm_start`], off in
//! [`ContactSolver::new`]: [`DEFAULT_WARM_START`]). Each contact is known by
//! its [`ContactKey`] (bodies and the vertex/edge features of the narrow
//! phase, stable while the same features touch); the support and impulses
//! of its last accepted solution, at the current solve time or the
//! previous one, give the guessed basis of the next LCP of those contacts
//! ([`crate::lcp::solve_warm`]: principal pivoting on the original data,
//! accepted on the driver's residual test, else the cold attempts). It
//! changes results at the rounding level, which is why it is off by
//! default. With it on, `check cases/` gives the same verdicts (306 checks,
//! 0 claimed failures; only two energy-ledger residuals print other
//! rounding: narrow_channel event-driven 1.5e-10 → 9.8e-11 J and
//! sliding_floe event-driven 2.117e-12 → 2.103e-12 J), and `compare
//! cases/` (4,263 warm hits, 49 misses) moves 51 of its 3,210 metrics: the
//! pivot counts (sliding_floe 5,767 → 7, narrow_channel event-driven
//! 11,807 → 2,101), energy-ledger residuals and zero-level values (kinetic
//! energy 1e-35 J, angle differences 1e-18 rad) at rounding level, and on
//! narrow_channel event-driven, whose event times depend on rounding,
//! `integrator_steps` 20,777 → 20,733, `micro_bounces_absorbed` 998 → 982,
//! `steps_cut_for_flight` 18 → 14 and `max_penetration_m` by 8e-10
//! relative. The cause: a basis solve rounds its solution differently from
//! Lemke's tableau, and a friction LCP with several solutions may be given
//! another one.
//!
//! **Warm-start check** (a diagnostic, off by default: [`ContactSolver::with_warm_check`],
//! `floebench run --warm-check`). Each LCP the warm start solves (by its
//! principal pivoting or by its Lemke path) is solved cold too (the pivots
//! of both summed: [`WARM_CHECK_WARM_PIVOTS`], [`WARM_CHECK_COLD_PIVOTS`]), by the same driver on the same data; the warm solution is the
//! one used, so the run is the warm run. The two solutions `z_w`, `z_c` are
//! compared by `max_i |z_w,i − z_c,i| / max(‖z_w‖∞, ‖z_c‖∞)`: above
//! [`WARM_CHECK_DIFFERENT`] they are counted as different solutions, below
//! it (and non-zero) as rounding. The cold solves are not timed in the
//! profile, but they are in the run's CPU: a run with the check is not a
//! timing.

use crate::contact::cone::{solve_cone, ConeOptions, ConeStatus};
use crate::contact::problem::{ContactLcp, Friction};
use crate::contact::ContactKey;
use crate::lcp::predict::{basis_mismatch, solve_predicted, Blocks, PredictOptions, Prediction};
use crate::lcp::solve::solve_with_columns;
use crate::lcp::SolveStatus;
use crate::lcp::Strategy;
use crate::lcp::{
    solve, solve_warm, BasisGuess, LcpDump, LcpSolution, SolveCounters, SolveOptions,
};
use crate::record::clock::Sampler;
use crate::record::profile::{bucket_of, BUCKET_BOUNDS};
use crate::record::{ContactLog, Counter, Counters, ImpulseRecord, Settings, SolveProfile, Unit};
use std::collections::HashMap;
use std::path::PathBuf;

/// Relative slack of the Coulomb check `|β| ≤ μ λ (1 + 1e-9)`: an accepted
/// LCP solution has residual ≤ 1e-10 relative to `‖q‖`.
pub const COULOMB_SLACK: f64 = 1e-9;

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
/// Contact problems left without impulse (every attempt failed).
pub const LCP_UNRESOLVED: Counter = Counter::sum(
    "lcp_unresolved",
    "contact problems left without impulse: every attempt failed",
);
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
const WARM_COUNTERS: &[&Counter] = &[
    &LCP_WARM_LEMKE_HITS,
    &LCP_WARM_LEMKE_MISSES,
    &LCP_WARM_LEMKE_PIVOTS,
    &LCP_WARM_SUPPORT_CHANGES,
];

/// LCPs solved from a predicted basis ([`ContactSolver::with_predict_from`]).
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
const PREDICT_COUNTERS: &[&Counter] = &[
    &LCP_PREDICT_SOLVES,
    &LCP_PREDICT_HITS,
    &LCP_PREDICT_MISSES,
    &LCP_PREDICT_SWEEPS,
    &LCP_PREDICT_PIVOTS,
    &LCP_PREDICT_WRONG,
];

/// Whether and from which size the LCPs are solved from a predicted basis
/// (the `predict_from` case key, unknowns): `None`, off. On the 40 LCPs of
/// more than 800 unknowns of the jammed bay (event-driven, 100 s) the
/// predicted solve took a median 309 ms against 197 ms cold
/// (docs/physics.md §3.3, "Predicted basis").
pub const DEFAULT_PREDICT_FROM: Option<usize> = None;

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
const WARM_CHECK_COUNTERS: &[&Counter] = &[
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

/// The relative difference above which the warm-start check counts a warm
/// and a cold solution as two solutions (-): an accepted solution has a
/// residual ≤ 1e-10 of `‖q‖`, so two roundings of one solution differ by
/// orders of magnitude less, and two solutions of a friction LCP by a
/// fraction of the impulses.
pub const WARM_CHECK_DIFFERENT: f64 = 1e-6;

/// The unknowns whose side differs between the guessed basis `basic` (`z_i`
/// basic) and the support of the solution `z` (`z_i > 0`).
fn support_changes(basic: &[bool], z: &[f64]) -> u64 {
    basic
        .iter()
        .zip(z)
        .filter(|(b, v)| **b != (**v > 0.0))
        .count() as u64
}

/// `max_i |a_i − b_i| / max(‖a‖∞, ‖b‖∞)`, 0 when both are zero (and 1 for
/// vectors of different lengths).
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return 1.0;
    }
    let scale = a.iter().chain(b).fold(0.0f64, |s, v| s.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
    if diff == 0.0 {
        0.0
    } else {
        diff / scale
    }
}

/// The counters of the `lcp` solver.
const LCP_COUNTERS: &[&Counter] = &[
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
const CONE_COUNTERS: &[&Counter] = &[
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

/// Which method solves a contact problem (`solver = "lcp" | "cone"` in a
/// formulation's settings table).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolverKind {
    /// `"lcp"`: the Stewart–Trinkle LCP by our Lemke (exact Coulomb in 2D).
    Lcp,
    /// `"cone"`: the Anitescu–Tasora convex relaxation by clarabel.
    Cone,
}

impl SolverKind {
    /// The name in settings and reports.
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Lcp => "lcp",
            SolverKind::Cone => "cone",
        }
    }
}

impl std::str::FromStr for SolverKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "lcp" => Ok(SolverKind::Lcp),
            "cone" => Ok(SolverKind::Cone),
            other => Err(format!(
                "unknown solver `{other}`; expected `lcp` or `cone`"
            )),
        }
    }
}

/// Whether [`ContactSolver::new`] warm-starts the LCPs.
pub const DEFAULT_WARM_START: bool = false;

/// Whether a warm start runs Lemke's path from the guessed basis when its
/// principal pivoting is rejected (the `warm_lemke` case key), before the
/// cold attempts: off, as [`crate::lcp::SolveOptions::warm_lemke`] (it
/// cost more than it saved on the jammed bay, docs/physics.md §3.3). Acts
/// only when the warm start is on (off by default).
pub const DEFAULT_WARM_LEMKE: bool = false;

/// The basis and impulses of one contact in an accepted LCP solution:
/// `(λ, β̃⁺, β̃⁻, α)`, the last three only with friction.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ContactBasis {
    basic: [bool; 4],
    z: [f64; 4],
}

/// The bases of the contacts of the last solves, by contact identity
/// ([`ContactKey`]: bodies and features). Entries of the current time and
/// of the previous one are kept; a contact seen at neither has no guess.
#[derive(Debug, Clone, Default)]
struct WarmCache {
    t: f64,
    current: HashMap<ContactKey, ContactBasis>,
    previous: HashMap<ContactKey, ContactBasis>,
}

impl WarmCache {
    /// Starts time `t` (s): the entries of an earlier time become the
    /// previous ones.
    fn at(&mut self, t: f64) {
        if t != self.t {
            self.previous = std::mem::take(&mut self.current);
            self.t = t;
        }
    }

    /// The guess for `lcp`: each matched contact's basis and impulses, an
    /// unmatched one separating (`w` basic, `z = 0`); `None` if no contact
    /// is matched.
    fn guess(&self, lcp: &ContactLcp) -> Option<BasisGuess> {
        let n = lcp.lcp().n;
        let mut g = BasisGuess {
            basic: vec![false; n],
            z: vec![0.0; n],
        };
        let mut matched = false;
        for (j, key) in lcp.keys.iter().enumerate() {
            let Some(b) = self.current.get(key).or_else(|| self.previous.get(key)) else {
                continue;
            };
            matched = true;
            for (k, i) in lcp.unknowns(j).enumerate() {
                if i < n {
                    g.basic[i] = b.basic[k];
                    g.z[i] = b.z[k];
                }
            }
        }
        matched.then_some(g)
    }

    /// Keeps the basis (support) and impulses of an accepted solution `z`.
    fn store(&mut self, lcp: &ContactLcp, z: &[f64]) {
        for (j, key) in lcp.keys.iter().enumerate() {
            let mut b = ContactBasis {
                basic: [false; 4],
                z: [0.0; 4],
            };
            for (k, i) in lcp.unknowns(j).enumerate() {
                let v = z.get(i).copied().unwrap_or(0.0);
                b.basic[k] = v > 0.0;
                b.z[k] = v;
            }
            self.current.insert(*key, b);
        }
    }
}

/// Which warm-start cache a solve uses: the sustained contacts of a step
/// and the compression LCPs of impacts differ in kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Use {
    Sustained,
    Impact,
}

/// Lemke or the cone, with fallbacks, last resort, dumps and the Coulomb check.
#[derive(Debug, Clone)]
pub struct ContactSolver {
    kind: SolverKind,
    opts: SolveOptions,
    cone_opts: ConeOptions,
    dump: Option<PathBuf>,
    dump_seq: u64,
    lcp_counters: SolveCounters,
    counters: Counters,
    max_coulomb_ratio: f64,
    log: ContactLog,
    profile: SolveProfile,
    timer: Sampler,
    /// Warm-start caches (sustained, impact); `None`: warm start off.
    warm: Option<[WarmCache; 2]>,
    /// Whether each warm-solved LCP is solved cold too
    /// ([`ContactSolver::with_warm_check`]).
    warm_check: bool,
    /// Smallest LCP (unknowns) solved from a predicted basis; `None`: off.
    predict_from: Option<usize>,
    /// Options of the prediction.
    predict: PredictOptions,
    /// Whether the LCPs merge the friction of flush edge pairs
    /// ([`ContactSolver::with_merge_friction`]).
    merge_friction: bool,
}

/// Default of `merge_friction` ([`ContactSolver::with_merge_friction`]):
/// on. The two points of a flush edge pair have tangential columns equal up
/// to the angle between the edges; kept apart, they make Lemke's method
/// degenerate (pivots of 1e-10, lost feasibility, ray terminations: 9 of the
/// 40 LCPs of more than 800 unknowns of the jammed bay) and add three
/// unknowns per pair (docs/physics.md §3.1, "Flush edge pairs").
pub const DEFAULT_MERGE_FRICTION: bool = true;

impl ContactSolver {
    /// A solver of `kind` with the default [`SolveOptions`] and
    /// [`ConeOptions`]; with `dump`, every LCP solved is written there as
    /// `<seq>.json` (`000000.json`, …). Warm start as
    /// [`DEFAULT_WARM_START`].
    pub fn new(kind: SolverKind, dump: Option<PathBuf>) -> ContactSolver {
        Self::with_warm_start(kind, dump, DEFAULT_WARM_START)
    }

    /// [`ContactSolver::new`] with the warm start on or off. With it, each
    /// LCP first tries the complementary basis of the last accepted
    /// solution of the same contacts (matched by [`ContactKey`]: bodies and
    /// features; a contact without history starts separating), at this
    /// solve's time or the previous one, with those impulses as starting
    /// point ([`crate::lcp::solve_warm`]); a rejected guess falls back to
    /// the cold attempts. Sustained contacts and impacts keep separate
    /// histories. Counted: [`LCP_WARM_HITS`], [`LCP_WARM_MISSES`].
    pub fn with_warm_start(
        kind: SolverKind,
        dump: Option<PathBuf>,
        warm_start: bool,
    ) -> ContactSolver {
        let mut counters = Counters::new(LCP_COUNTERS);
        if kind == SolverKind::Cone {
            counters.declare(CONE_COUNTERS);
        }
        if warm_start {
            counters.declare(WARM_COUNTERS);
        }
        ContactSolver {
            kind,
            opts: SolveOptions::default(),
            cone_opts: ConeOptions::default(),
            dump,
            dump_seq: 0,
            lcp_counters: SolveCounters::default(),
            counters,
            max_coulomb_ratio: 0.0,
            log: ContactLog::recording(),
            profile: SolveProfile::default(),
            timer: Sampler::new(BUCKET_BOUNDS.len() + 1),
            warm: warm_start.then(Default::default),
            warm_check: false,
            predict_from: DEFAULT_PREDICT_FROM,
            predict: PredictOptions::default(),
            merge_friction: DEFAULT_MERGE_FRICTION,
        }
    }

    /// This solver with the friction of flush edge pairs merged or not
    /// ([`Friction::Merged`]: one friction resultant per group of contacts
    /// of one body pair with equal tangential columns, in the LCPs this
    /// solver is given by [`ContactSolver::friction_layout`]).
    pub fn with_merge_friction(mut self, on: bool) -> ContactSolver {
        self.merge_friction = on;
        self
    }

    /// The friction layout the formulation assembles its problems with: an
    /// impact's compression LCP (`impact`) or the sustained problem of a
    /// Lemke solver merges flush edge pairs (when on); the cone program
    /// keeps one Coulomb cone per point.
    pub fn friction_layout(&self, impact: bool) -> Friction {
        if self.merge_friction && (impact || self.kind == SolverKind::Lcp) {
            Friction::Merged
        } else {
            Friction::PerPoint
        }
    }

    /// This solver with the predicted basis from `from` unknowns on
    /// (`None`: off): an LCP of at least that size without a warm-start
    /// guess is solved by [`crate::lcp::predict::solve_predicted`] (block
    /// Gauss–Seidel on its contact blocks, then Lemke's path from the
    /// predicted basis, then the cold attempts; docs/physics.md §3.3).
    /// Counted: [`LCP_PREDICT_SOLVES`], [`LCP_PREDICT_HITS`],
    /// [`LCP_PREDICT_MISSES`], [`LCP_PREDICT_SWEEPS`],
    /// [`LCP_PREDICT_PIVOTS`], [`LCP_PREDICT_WRONG`].
    pub fn with_predict_from(mut self, from: Option<usize>) -> ContactSolver {
        self.predict_from = from;
        if from.is_some() {
            self.counters.declare(PREDICT_COUNTERS);
        }
        self
    }

    /// This solver with the warm-start check on or off (`floebench run
    /// --warm-check`): each LCP the warm start solves is also solved cold
    /// and the two are compared (see the module doc). Only with the warm
    /// start on; a diagnostic: it doubles the cost of those solves.
    pub fn with_warm_check(mut self, on: bool) -> ContactSolver {
        self.warm_check = on && self.warm.is_some();
        if self.warm_check {
            self.counters.declare(WARM_CHECK_COUNTERS);
        }
        self
    }

    /// This solver with the warm Lemke path on or off
    /// ([`crate::lcp::SolveOptions::warm_lemke`]: when the principal
    /// pivoting of a warm start is rejected, Lemke's path from the guessed
    /// basis before the cold attempts). Acts only with the warm start on.
    pub fn with_warm_lemke(mut self, on: bool) -> ContactSolver {
        self.opts.warm_lemke = on;
        self
    }

    /// Whether the LCPs are warm-started.
    pub fn warm_start(&self) -> bool {
        self.warm.is_some()
    }

    /// `settings` with the solver's own: `solver` (its method),
    /// `warm_start` (`on`/`off`), `predict_from` when on and, with the warm
    /// start on, `warm_lemke`.
    pub fn settings(&self, settings: Settings) -> Settings {
        let s = settings
            .text("solver", self.kind.name())
            .text(
                "merge_friction",
                match (self.merge_friction, self.kind) {
                    (false, _) => "off",
                    (true, SolverKind::Lcp) => "on",
                    (true, SolverKind::Cone) => "impact LCPs only",
                },
            )
            .text("warm_start", if self.warm_start() { "on" } else { "off" });
        let s = match self.predict_from {
            Some(k) => s.text("predict_from", &k.to_string()),
            None => s,
        };
        if self.warm_start() {
            s.text(
                "warm_lemke",
                if self.opts.warm_lemke { "on" } else { "off" },
            )
        } else {
            s
        }
    }

    /// The LCP solves so far by size (with the timer's cost).
    pub fn profile(&self) -> SolveProfile {
        let mut p = self.profile.clone();
        p.timer_overhead = self.timer.overhead();
        p
    }

    /// Lemke with its fallbacks on `lcp`, warm-started from `guess` if
    /// given, timed and profiled by size.
    fn lemke(&mut self, lcp: &ContactLcp, guess: Option<&BasisGuess>) -> LcpSolution {
        let k = bucket_of(lcp.lcp().n);
        let started = self.timer.begin(k);
        let blocks = match (guess, self.predict_from) {
            (None, Some(from)) if lcp.lcp().n >= from => Blocks::new(lcp.lcp().n, lcp.blocks()),
            _ => None,
        };
        let (sol, prediction) = match (guess, &blocks) {
            (Some(g), _) => (solve_warm(lcp.lcp(), &self.opts, g), None),
            (None, Some(b)) => solve_predicted(lcp.lcp(), &self.opts, b, &self.predict),
            (None, None) => match lcp.columns() {
                Some(cols) => (solve_with_columns(lcp.lcp(), cols, &self.opts), None),
                None => (solve(lcp.lcp(), &self.opts), None),
            },
        };
        let seconds = self.timer.end(k, started);
        if let Some(p) = &prediction {
            self.count_prediction(lcp, p, &sol);
        }
        if let Some(b) = self.profile.buckets.get_mut(k) {
            b.solves += 1;
            b.pivots += sol.pivots as u64;
            b.unknowns += lcp.lcp().n as u64;
            if guess.is_none() && prediction.is_none() && sol.status.is_solved() {
                b.min_pivots += crate::lcp::min_cold_pivots(crate::lcp::support(&sol.z)) as u64;
                b.bounded_pivots += sol.pivots as u64;
            }
            if let Some(g) = guess {
                b.warm_tried += 1;
                if sol.accepted_by == Some(Strategy::WarmStart) {
                    b.warm_hits += 1;
                }
                if let Some(a) = sol.warm_lemke_attempt() {
                    b.warm_lemke_pivots += a.pivots as u64;
                    if a.accepted {
                        b.warm_lemke_hits += 1;
                    }
                }
                if sol.status.is_solved() {
                    let changes = support_changes(&g.basic, &sol.z);
                    b.warm_support_changes += changes;
                    self.counters.add(&LCP_WARM_SUPPORT_CHANGES, changes);
                }
            }
            match sol.status {
                SolveStatus::Solved => b.first_attempt += 1,
                SolveStatus::SolvedByFallback => b.fallback += 1,
                SolveStatus::Failed => b.failed += 1,
            }
            b.seconds += seconds.unwrap_or(0.0);
        }
        sol
    }

    /// Counts one solve from a predicted basis `p` with outcome `sol`.
    fn count_prediction(&mut self, lcp: &ContactLcp, p: &Prediction, sol: &LcpSolution) {
        let c = &mut self.counters;
        c.add(&LCP_PREDICT_SOLVES, 1);
        c.add(&LCP_PREDICT_SWEEPS, p.sweeps as u64);
        if let Some(a) = sol.warm_lemke_attempt() {
            c.add(&LCP_PREDICT_PIVOTS, a.pivots as u64);
            c.add(
                if a.accepted {
                    &LCP_PREDICT_HITS
                } else {
                    &LCP_PREDICT_MISSES
                },
                1,
            );
        }
        if sol.status.is_solved() {
            let qn = lcp.lcp().q.iter().map(|v| v * v).sum::<f64>().sqrt();
            let tie = self.opts.tolerance * qn;
            let (wrong, _) = basis_mismatch(&p.guess.basic, &sol.z, &sol.w, tie);
            c.add(&LCP_PREDICT_WRONG, wrong as u64);
        }
    }

    /// The method in use.
    pub fn kind(&self) -> SolverKind {
        self.kind
    }

    /// Largest `|β| / (μ λ)` over every accepted contact impulse so far (0
    /// without friction).
    pub fn max_coulomb_ratio(&self) -> f64 {
        self.max_coulomb_ratio
    }

    /// The log of accepted frictional impulses (with the contact events the
    /// formulation adds to it).
    pub fn log_mut(&mut self) -> &mut ContactLog {
        &mut self.log
    }

    /// Hands over the log and starts a new one.
    pub fn take_log(&mut self) -> ContactLog {
        std::mem::replace(&mut self.log, ContactLog::recording())
    }

    /// The solver's counters: its own, the Lemke pivots and attempts, and
    /// the largest Coulomb ratio.
    pub fn counters(&self) -> Counters {
        let mut c = self.counters.clone();
        let l = &self.lcp_counters;
        c.add(&LEMKE_PIVOTS, l.total_pivots);
        c.add(&LEMKE_MAX_PIVOTS, l.max_pivots);
        c.add(&LCP_SOLVED_FIRST_ATTEMPT, l.solved);
        c.add(&LCP_SOLVED_BY_FALLBACK, l.solved_by_fallback);
        c.add(&LCP_FALLBACK_ALTERNATIVE_RULE, l.by_alternative_rule);
        c.add(&LCP_FALLBACK_PERTURBED, l.by_perturbed);
        c.add(&LCP_FAILED, l.failed);
        c.add(&LCP_WARM_HITS, l.warm_hits);
        c.add(&LCP_WARM_MISSES, l.warm_misses);
        c.add(&LCP_COMPLETED_BY_PIVOTING, l.completed_by_pivoting);
        c.add(&LCP_REVISED, l.revised);
        if self.warm.is_some() {
            c.add(&LCP_WARM_LEMKE_HITS, l.warm_lemke_hits);
            c.add(&LCP_WARM_LEMKE_MISSES, l.warm_lemke_misses);
            c.add(&LCP_WARM_LEMKE_PIVOTS, l.warm_lemke_pivots);
        }
        c.set(&LCP_MAX_ACCEPTED_RESIDUAL, l.max_accepted_residual);
        c.set(&MAX_COULOMB_RATIO, self.max_coulomb_ratio);
        c
    }

    /// The work of every solve so far: Lemke pivots (every attempt) plus
    /// interior-point iterations; the difference over one solve is that
    /// solve's work in the accuracy record ([`crate::record::accuracy`]).
    pub fn work(&self) -> u64 {
        self.lcp_counters.total_pivots + self.counters.count(&CONE_ITERATIONS).unwrap_or(0)
    }

    /// Solves one contact problem by the method in use; returns the LCP
    /// unknowns `z` of the (scaled) problem (never NaN, length `lcp.lcp().n`)
    /// for [`ContactLcp::impulses`] and [`ContactLcp::velocity_changes`].
    /// `t` is the simulation time, s (for the log and the dumps).
    pub fn solve(&mut self, lcp: &ContactLcp, t: f64) -> Vec<f64> {
        match self.kind {
            SolverKind::Lcp => self.solve_lcp_for(lcp, t, Use::Sustained),
            SolverKind::Cone => self.solve_cone(lcp, t),
        }
    }

    /// Solves one contact problem as an LCP whatever the method in use (the
    /// compression LCP of an impact): Lemke with the fallbacks and the last
    /// resort.
    pub fn solve_lcp(&mut self, lcp: &ContactLcp, t: f64) -> Vec<f64> {
        self.solve_lcp_for(lcp, t, Use::Impact)
    }

    /// [`ContactSolver::solve_lcp`] with the warm-start history of `usage`.
    fn solve_lcp_for(&mut self, lcp: &ContactLcp, t: f64, usage: Use) -> Vec<f64> {
        let cache = self.warm.as_mut().map(|c| &mut c[usage as usize]);
        let guess = cache.and_then(|c| {
            c.at(t);
            c.guess(lcp)
        });
        let sol = self.lemke(lcp, guess.as_ref());
        self.record_solve(lcp, &sol, t);
        let warm_solved = matches!(
            sol.accepted_by,
            Some(Strategy::WarmStart | Strategy::WarmLemke)
        );
        if self.warm_check && warm_solved {
            self.check_warm(lcp, &sol, usage);
        }
        if sol.status.is_solved() {
            if let Some(c) = self.warm.as_mut() {
                c[usage as usize].store(lcp, &sol.z);
            }
            return sol.z;
        }
        if lcp.friction {
            self.counters.add(&LCP_LAST_RESORT_FRICTIONLESS, 1);
            let fl = lcp.frictionless();
            let sol2 = self.lemke(&fl, None);
            self.record_solve(&fl, &sol2, t);
            if sol2.status.is_solved() {
                let mut z = vec![0.0; lcp.lcp().n];
                z[..lcp.m].copy_from_slice(&sol2.z);
                return z;
            }
        }
        self.counters.add(&LCP_UNRESOLVED, 1);
        vec![0.0; lcp.lcp().n]
    }

    /// The warm-start check of one warm-solved LCP: solves it cold (not
    /// recorded, not timed, not dumped) and counts how the two solutions
    /// differ.
    fn check_warm(&mut self, lcp: &ContactLcp, warm: &LcpSolution, usage: Use) {
        let cold = solve(lcp.lcp(), &self.opts);
        let (compared, different, rounding) = match usage {
            Use::Sustained => (
                &WARM_CHECK_SUSTAINED,
                &WARM_CHECK_SUSTAINED_DIFFERENT,
                &WARM_CHECK_SUSTAINED_ROUNDING,
            ),
            Use::Impact => (
                &WARM_CHECK_IMPACT,
                &WARM_CHECK_IMPACT_DIFFERENT,
                &WARM_CHECK_IMPACT_ROUNDING,
            ),
        };
        let c = &mut self.counters;
        c.add(compared, 1);
        c.add(&WARM_CHECK_WARM_PIVOTS, warm.pivots as u64);
        c.add(&WARM_CHECK_COLD_PIVOTS, cold.pivots as u64);
        if !cold.status.is_solved() {
            c.add(&WARM_CHECK_COLD_FAILED, 1);
            return;
        }
        let d = relative_difference(&warm.z, &cold.z);
        c.max(&WARM_CHECK_MAX_DIFFERENCE, d);
        if d > WARM_CHECK_DIFFERENT {
            c.add(different, 1);
        } else if d > 0.0 {
            c.add(rounding, 1);
        }
    }

    /// One problem by the cone program, with the LCP chain as fallback.
    fn solve_cone(&mut self, lcp: &ContactLcp, t: f64) -> Vec<f64> {
        let p = lcp.normal_tangent();
        let sol = solve_cone(&p, &self.cone_opts);
        let c = &mut self.counters;
        c.add(&CONE_SOLVES, 1);
        c.add(&CONE_ITERATIONS, u64::from(sol.iterations));
        c.max(&CONE_MAX_ITERATIONS, f64::from(sol.iterations));
        c.add(&CONE_UNKNOWNS_TOTAL, p.dim() as u64);
        match sol.status {
            ConeStatus::Solved => {}
            ConeStatus::AlmostSolved => c.add(&CONE_ALMOST_SOLVED, 1),
            ConeStatus::RescuedByPolish => c.add(&CONE_RESCUED_BY_POLISH, 1),
            ConeStatus::Failed => {
                c.add(&CONE_FAILED, 1);
                c.add(&CONE_FALLBACK_LCP, 1);
                return self.solve_lcp_for(lcp, t, Use::Sustained);
            }
        }
        c.max(&CONE_MAX_PROJECTION_REL, sol.cone_excess);
        if sol.polished {
            c.add(&CONE_POLISHED, 1);
        }
        let mut flat = sol.lambda.clone();
        if p.friction {
            flat.extend_from_slice(&sol.beta);
            self.check_coulomb(t, &sol.lambda, &sol.beta, p.mu, &[]);
        }
        // The artefact: normal speed (with the Newton offset) of the
        // contacts that push, u_N⁺ + c = μ |u_T⁺| while sliding.
        let u = p.velocities(&flat);
        let lam_max = sol.lambda.iter().fold(0.0f64, |s, l| s.max(*l));
        for (l, uj) in sol.lambda.iter().zip(&u) {
            if *l > 1e-9 * lam_max {
                self.counters.max(&CONE_MAX_PUSHING_NORMAL_SPEED, *uj);
            }
        }
        lcp.z_from_impulses(&sol.lambda, &sol.beta)
    }

    fn record_solve(&mut self, lcp: &ContactLcp, sol: &LcpSolution, t: f64) {
        self.lcp_counters.record(sol);
        self.counters.add(&LCP_SOLVES, 1);
        self.counters.add(&LCP_UNKNOWNS_TOTAL, lcp.lcp().n as u64);
        self.counters.max(&LCP_SIZE_MAX, lcp.lcp().n as f64);
        if let Some(dir) = &self.dump {
            let path = dir.join(format!("{:06}.json", self.dump_seq));
            self.dump_seq += 1;
            if LcpDump::from_solution(lcp.lcp(), sol, t, lcp.m, lcp.merged_groups())
                .write(&path)
                .is_err()
            {
                self.counters.add(&LCP_DUMP_FAILURES, 1);
            }
        }
        if sol.status.is_solved() && lcp.friction {
            // Rounding allowance per contact: the impulse that the accepted
            // residual (tolerance × ‖q‖, in velocity units) corresponds to.
            let n = lcp.lcp().n;
            let qn = lcp.lcp().q.iter().map(|v| v * v).sum::<f64>().sqrt();
            let slack: Vec<f64> = (0..lcp.m)
                .map(|j| {
                    // Physical Delassus diagonal (the LCP is scaled by g).
                    let d = lcp.lcp().m[j * n + j] * lcp.scale;
                    if d > 0.0 {
                        self.opts.tolerance * qn / d
                    } else {
                        0.0
                    }
                })
                .collect();
            let beta = lcp.tangential(&sol.z);
            self.check_coulomb(t, &lcp.normal(&sol.z), &beta, lcp.mu, &slack);
        }
    }

    /// Coulomb on accepted impulses `λ`, `β` (N·s) with friction coefficient
    /// `mu`: keeps the largest `|β| / (μ λ)` and counts
    /// [`COULOMB_VIOLATIONS`], i.e. `|β| > μ λ (1 + COULOMB_SLACK) + slack`.
    /// `slack[j]` (N·s, 0 if missing) is the rounding allowance of contact
    /// `j`: a tangential impulse below it is rounding (e.g. 1e-21 N·s beside
    /// `λ = 0`) and is left out of the ratio. Every impulse goes into the log
    /// ([`ImpulseRecord`], at time `t`, s), whose ratio is the one used here.
    pub fn check_coulomb(&mut self, t: f64, lambda: &[f64], beta: &[f64], mu: f64, slack: &[f64]) {
        for (j, (l, b)) in lambda.iter().zip(beta).enumerate() {
            let bound = mu * l;
            let eps = slack.get(j).copied().unwrap_or(0.0);
            let rec = ImpulseRecord {
                t,
                normal: *l,
                tangent: *b,
                mu,
                slack: eps,
            };
            self.log.push_impulse(rec);
            if b.abs() > eps {
                self.max_coulomb_ratio = self.max_coulomb_ratio.max(rec.coulomb_ratio());
                if b.abs() > bound * (1.0 + COULOMB_SLACK) + eps {
                    self.counters.add(&COULOMB_VIOLATIONS, 1);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::relative_difference;

    #[test]
    fn relative_difference_is_scaled_by_the_largest_entry() {
        assert_eq!(relative_difference(&[0.0, 0.0], &[0.0, 0.0]), 0.0);
        assert_eq!(relative_difference(&[1.0, 2.0], &[1.0, 2.0]), 0.0);
        assert_eq!(relative_difference(&[4.0, 0.0], &[0.0, 4.0]), 1.0);
        let d = relative_difference(&[2.0, 1.0], &[2.0, 1.0 + 2e-12]);
        assert!(d > 0.0 && d < 2e-12, "{d:e}");
        assert_eq!(relative_difference(&[1.0], &[1.0, 0.0]), 1.0);
    }
}
