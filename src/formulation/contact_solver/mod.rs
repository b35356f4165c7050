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
//! its [`ContactKey`](crate::contact::ContactKey) (bodies and the vertex/edge features of the narrow
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
//!
//! The parts, each its own file: this one the [`ContactSolver`], its
//! options and what it reports; `lcp_chain.rs` the LCP chain (Lemke with
//! its fallbacks and the last resort, the record, the dumps and the
//! Coulomb check); `cone.rs` the cone program; `warm.rs` the warm start's
//! contact history and the warm-start check; `counters.rs` the counters.

mod cone;
mod counters;
mod lcp_chain;
mod warm;

// Every counter keeps its path `contact_solver::NAME`.
pub use counters::*;
pub use lcp_chain::COULOMB_SLACK;
pub use warm::WARM_CHECK_DIFFERENT;

use crate::contact::cone::ConeOptions;
use crate::contact::problem::{ContactLcp, Friction};
use crate::lcp::predict::PredictOptions;
use crate::lcp::{SolveCounters, SolveOptions};
use crate::record::clock::Sampler;
use crate::record::profile::BUCKET_BOUNDS;
use crate::record::{ContactLog, Counters, Settings, SolveProfile};
use std::path::PathBuf;
use warm::{Use, WarmCache};

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
            other => {
                let hint = crate::model::case::closest(other, &["lcp", "cone"])
                    .map_or(String::new(), |k| format!(" (did you mean `{k}`?)"));
                Err(format!(
                    "unknown solver `{other}`{hint}; expected `lcp` or `cone`"
                ))
            }
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

/// Whether and from which size the LCPs are solved from a predicted basis
/// (the `predict_from` case key, unknowns): `None`, off. On the 40 LCPs of
/// more than 800 unknowns of the jammed bay (event-driven, 100 s) the
/// predicted solve took a median 309 ms against 197 ms cold
/// (docs/physics.md §3.3, "Predicted basis").
pub const DEFAULT_PREDICT_FROM: Option<usize> = None;

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
    /// How the last problem was answered ([`ContactSolver::last_answer`]).
    last: LastAnswer,
}

/// How the last contact problem a [`ContactSolver`] solved was answered:
/// what its solver's own residual and tolerance say
/// ([`crate::record::accuracy`]: the solver's error, apart from the
/// answer's departure from Coulomb's law).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LastAnswer {
    /// Nothing solved yet.
    None,
    /// By the LCP chain: the residual `‖min(z, w)‖/‖q‖` of the answer on
    /// the LCP solved (the frictional one, or the frictionless last
    /// resort's), and whether an attempt met the acceptance tolerance on
    /// the frictional LCP.
    Lcp {
        /// The LCP residual of the answer returned (dimensionless).
        residual: f64,
        /// Whether the frictional LCP was solved to its tolerance.
        met: bool,
    },
    /// By the cone program: whether clarabel met its full accuracy (its
    /// residual on the relaxation is measured by the caller, who holds the
    /// sparse problem).
    Cone {
        /// Whether clarabel reported the problem solved (not only
        /// "almost", or rescued by its polish).
        met: bool,
    },
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
    /// solution of the same contacts (matched by [`ContactKey`](crate::contact::ContactKey): bodies and
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
            last: LastAnswer::None,
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

    /// How the last problem was answered: its solver's own residual and
    /// whether it met its tolerance ([`LastAnswer`]).
    pub fn last_answer(&self) -> LastAnswer {
        self.last
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
}
