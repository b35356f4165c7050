//! The event-driven formulation's settings (`[formulation.event-driven]`),
//! its counters and the constants of its scheme (docs/physics.md §4).

use super::*;

/// `[formulation.event-driven]`.
pub const TABLE: TableSpec = TableSpec {
    name: "event-driven",
    validate: |t| EventDrivenSettings::from_table(t).map(|_| ()),
    limits: &[
        PENETRATION_TOLERANCE,
        PREDICT_FROM,
        TOLERANCE,
        MAX_ITERATIONS,
        RELAXATION,
    ],
};

/// The bound of `predict_from`, unknowns (an LCP size).
pub const PREDICT_FROM: Limit = Limit::range(
    "predict_from",
    "[formulation.event-driven]",
    1.0,
    1e9,
    "",
    "a contact LCP has at most 4 unknowns per contact; 1e9 unknowns would be a dense matrix of 8e18 bytes",
)
.integers();

/// The bound of `penetration_tolerance`, m.
pub const PENETRATION_TOLERANCE: Limit = Limit::range(
    "penetration_tolerance",
    "[formulation.event-driven]",
    1e-6,
    1e3,
    "m",
    "1 µm is still 500 floating-point spacings of a coordinate of 1e7 m; a penetration of 1 km is no contact",
);

/// Settings of the event-driven formulation (`[formulation.event-driven]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventDrivenSettings {
    /// `penetration_tolerance`: penetration tolerated before a step is
    /// rejected, m (default [`DEFAULT_PENETRATION_FRACTION`] of the smallest
    /// floe radius: see [`EventDrivenSettings::penetration_tolerance`]).
    pub penetration_tolerance: Option<f64>,
    /// `solver`: the method of the sustained-contact problems, `"lcp"`
    /// (default: Lemke, exact Coulomb), `"cone"` (the convex relaxation,
    /// clarabel), `"nsgs"` or `"apgd"` (the iterative solvers,
    /// [`crate::iterative`]); impacts are the compression LCP of Poisson's
    /// law (solved by NSGS under `"nsgs"`, docs/case-format.md).
    pub solver: SolverKind,
    /// `warm_start`: start each LCP from the basis of its contacts' last
    /// accepted solution (default [`DEFAULT_WARM_START`]: off, as it changes
    /// results at the rounding level; see [`ContactSolver::with_warm_start`]).
    pub warm_start: bool,
    /// `warm_lemke`: with the warm start on, when principal pivoting from
    /// the guessed basis is rejected, run Lemke's path from that basis
    /// before the cold attempts (default [`DEFAULT_WARM_LEMKE`]; see
    /// [`ContactSolver::with_warm_lemke`]). Without the warm start it does
    /// nothing.
    pub warm_lemke: bool,
    /// `predict_from`: LCPs of at least this many unknowns (and no
    /// warm-start guess) are solved from a basis predicted by block
    /// Gauss–Seidel (default [`DEFAULT_PREDICT_FROM`]: absent, off; see
    /// [`ContactSolver::with_predict_from`]).
    pub predict_from: Option<usize>,
    /// `merge_friction`: one friction resultant per flush edge pair (the
    /// contacts of one body pair whose tangential columns agree to
    /// [`crate::contact::problem::FRICTION_MERGE_TOLERANCE`]) in the LCPs,
    /// bounded by `μ` times the sum of their normal impulses (default
    /// [`DEFAULT_MERGE_FRICTION`]: on; see
    /// [`ContactSolver::with_merge_friction`] and docs/physics.md §3.1).
    /// The cone program keeps one cone per point either way.
    pub merge_friction: bool,
    /// `solver = "nsgs"` or `"apgd"`: the iterative solver of the
    /// sustained problems, with its `tolerance`, `max_iterations`,
    /// `relaxation` (default `None`: the direct `solver`); NSGS solves the
    /// impacts' compression problems too, APGD leaves them to Lemke (see
    /// [`crate::iterative`]).
    pub iterative: Option<IterativeOptions>,
}

impl EventDrivenSettings {
    /// Parses `[formulation.event-driven]` (errors name the line and key).
    pub fn from_table(t: &SettingsTable) -> Result<EventDrivenSettings, CaseError> {
        let mut r = t.read();
        let (solver, iterative) = read_solver(&mut r, SolverKind::Lcp)?;
        let s = EventDrivenSettings {
            penetration_tolerance: r.bounded(&PENETRATION_TOLERANCE)?,
            solver,
            iterative,
            warm_start: r.boolean("warm_start")?.unwrap_or(DEFAULT_WARM_START),
            warm_lemke: r.boolean("warm_lemke")?.unwrap_or(DEFAULT_WARM_LEMKE),
            merge_friction: r
                .boolean("merge_friction")?
                .unwrap_or(DEFAULT_MERGE_FRICTION),
            predict_from: r
                .integer(&PREDICT_FROM)?
                .map_or(DEFAULT_PREDICT_FROM, |k| usize::try_from(k).ok()),
        };
        r.finish()?;
        Ok(s)
    }

    /// The settings of `scn`.
    pub fn of(scn: &Scenario) -> Result<EventDrivenSettings, CaseError> {
        EventDrivenSettings::from_table(&scn.settings_table(TABLE.name))
    }

    /// The penetration tolerance in use on `scn`, m.
    pub fn penetration_tolerance(&self, scn: &Scenario) -> f64 {
        self.penetration_tolerance
            .unwrap_or(DEFAULT_PENETRATION_FRACTION * floe_length_scale(scn))
    }
}

pub use crate::formulation::{
    contact_distance, floe_length_scale, DEFAULT_DISTANCE_FRACTION, DEFAULT_PENETRATION_FRACTION,
};

/// Slow approaches stopped at once (plastic) instead of over the step.
pub const SLOW_APPROACHES_STOPPED: Counter = Counter::sum(
    "slow_approaches_stopped",
    "groups whose closed contacts approached slower than the impact threshold but would close over a tenth of the tolerance within the step, stopped at once (plastic)",
);
/// Contacts given the mean motion of an accumulation, over the sustained solves.
pub const ACCUMULATING_CONTACTS: Counter = Counter::sum(
    "accumulating_contacts",
    "closed contacts given the mean motion of an accumulation of bounces, over the sustained solves",
);
/// Steps cut at the accumulation time of a contact.
pub const STEPS_CUT_AT_ACCUMULATION: Counter = Counter::sum(
    "steps_cut_at_accumulation",
    "trial steps cut at the accumulation time of a contact (its bounces complete, at rest)",
);
/// Flights within the contact distance, followed to their return.
pub const FLIGHTS_WITHIN_DISTANCE: Counter = Counter::sum(
    "flights_within_distance",
    "free flights of a closed contact that stay within the contact distance, followed to their return",
);
/// Steps cut at the return of a flight within the contact distance.
pub const STEPS_CUT_AT_RETURN: Counter = Counter::sum(
    "steps_cut_at_return",
    "trial steps cut at the return of a flight within the contact distance",
);
/// Steps cut where a crushing phase ends (kept only by runs that had one,
/// docs/physics.md §10.2).
pub const STEPS_CUT_AT_CRUSH_STOP: Counter = Counter::sum(
    "steps_cut_at_crush_stop",
    "trial steps cut where a crushing pair stops approaching: its impulse over the step below the bound, at the fraction of the step the bounded force takes to stop it",
);
/// Steps cut where a sliding contact sticks.
pub const STEPS_CUT_FOR_STICK: Counter = Counter::sum(
    "steps_cut_for_stick",
    "trial steps cut at the instant a sliding contact sticks",
);
/// Impacts that increased the kinetic energy of their group.
pub const IMPACT_ENERGY_INCREASES: Counter = Counter::sum(
    "impact_energy_increases",
    "impacts that increased the kinetic energy of their group",
);
/// Closed contacts whose micro-bounce stays within δ, absorbed by the sustained LCP.
pub const MICRO_BOUNCES_ABSORBED: Counter = Counter::sum(
    "micro_bounces_absorbed",
    "closed contacts whose flight stays within the contact distance, absorbed by the sustained LCP",
);
/// Sustained-contact steps that asked a penetrating contact to separate.
pub const POSITION_CORRECTIONS: Counter = Counter::sum(
    "position_corrections",
    "sustained-contact steps with a penetrating contact asked to separate at -g/H (H the nominal step)",
);
/// Sustained-contact problems solved (one per group and trial step).
pub const SUSTAINED_SOLVES: Counter =
    Counter::sum("sustained_solves", "sustained-contact problems solved");
/// Iterations of the event root finding.
pub const ROOT_ITERATIONS: Counter =
    Counter::sum("root_iterations", "iterations of the event root finding");
/// Instants whose impact rounds hit the cap.
pub const IMPACT_ROUNDS_CAPPED: Counter = Counter::sum(
    "impact_rounds_capped",
    "instants whose impact rounds hit the cap",
);
/// Instants with at least one impact.
pub const IMPACT_INSTANTS: Counter =
    Counter::sum("impact_instants", "instants with at least one impact");
/// Trial steps cut at the apex of a flight that leaves the contact distance.
pub const STEPS_CUT_FOR_FLIGHT: Counter = Counter::sum(
    "steps_cut_for_flight",
    "trial steps cut at the apex of a flight that leaves the contact distance",
);
/// Steps cut at a located event.
pub const EVENTS_LOCATED: Counter = Counter::sum("events_located", "steps cut at a located event");
/// Of those, the steps cut by an event of a pair already in contact at the
/// step start (a sustained contact whose other vertex closes).
pub const EVENTS_OF_PAIRS_IN_CONTACT: Counter = Counter::sum(
    "events_of_pairs_in_contact",
    "steps cut at an event of a pair already in contact at the step start",
);
/// Trial steps rejected for a penetration beyond the tolerance.
pub const STEPS_REJECTED_PENETRATION: Counter = Counter::sum(
    "steps_rejected_penetration",
    "trial steps rejected for a penetration beyond the tolerance (retried with half the step)",
);
/// Steps accepted with a penetration beyond the tolerance after the last halving.
pub const PENETRATIONS_BEYOND_TOLERANCE: Counter = Counter::sum(
    "penetrations_beyond_tolerance",
    "steps accepted with a penetration beyond the tolerance after the last halving",
);

/// The counters of the formulation (the contact solver adds its own).
pub(super) const COUNTERS: &[&Counter] = &[
    &STEPS,
    &IMPACTS,
    &SLOW_APPROACHES_STOPPED,
    &ACCUMULATING_CONTACTS,
    &STEPS_CUT_AT_ACCUMULATION,
    &FLIGHTS_WITHIN_DISTANCE,
    &STEPS_CUT_AT_RETURN,
    &STEPS_CUT_FOR_STICK,
    &IMPACT_ENERGY_INCREASES,
    &MICRO_BOUNCES_ABSORBED,
    &POSITION_CORRECTIONS,
    &SUSTAINED_SOLVES,
    &ROOT_ITERATIONS,
    &IMPACT_ROUNDS_CAPPED,
    &IMPACT_INSTANTS,
    &STEPS_CUT_FOR_FLIGHT,
    &EVENTS_LOCATED,
    &EVENTS_OF_PAIRS_IN_CONTACT,
    &STEPS_REJECTED_PENETRATION,
    &PENETRATIONS_BEYOND_TOLERANCE,
    &MAX_PENETRATION,
];

/// Rounding floor of the approach speed that makes an impact, m/s.
pub(super) const APPROACH_TOLERANCE: f64 = 1e-10;
/// Impact rounds at one instant before giving up (counted).
pub(super) const MAX_IMPACT_ROUNDS: usize = 100;
/// Halvings of a step that penetrates before it is accepted anyway (counted).
pub(super) const MAX_REJECTIONS: usize = 12;
/// Cuts of one trial step (flights, returns, accumulations, sticks) before
/// the step is taken as it is: each cut shortens it, and a cut that would
/// shorten it by less than [`MIN_CUT_FRACTION`] is not made.
pub(super) const MAX_CUTS: usize = 50;
/// An event is located where the vertex gap is this fraction of `δ`: an
/// impact happens close to the true contact (a bouncing floe's impacts are
/// early by `δ/(10 v)`, its accumulation time by a fraction `δ/(20 d)` of
/// itself for a drop `d`: 0.035 % on `bouncing_floe`; at `3δ/4`, as before,
/// 0.27 %), with a margin to rounding and to the root tolerance (1e-3 δ).
pub const IMPACT_GAP_FRACTION: f64 = 0.1;
/// An event is located to within this fraction of `δ` of its gap: every
/// impact then happens at the same gap, so that the flights of a bouncing
/// floe between located impacts have the heights and durations of the
/// closed form (with `δ/4`, impacts anywhere in `[δ/2, δ]` shifted the
/// bounces of `bouncing_floe` by up to 2 mm and its rest by 1.5 s).
pub(super) const ROOT_TOLERANCE: f64 = 1e-3;
/// A cut shortens the trial step by at least this fraction.
pub(super) const MIN_CUT_FRACTION: f64 = 1e-6;
/// Adjustments of one step to the instant a sliding pair sticks.
pub(super) const MAX_STICK_MOVES: usize = 3;
/// A sliding contact whose friction impulse is below `(1 − this) μ λ` at the
/// end of the step has stuck within it (Lemke's rounding allowed).
pub(super) const STICK_SLACK: f64 = 1e-9;
