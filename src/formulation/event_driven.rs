//! The event-driven LCP formulation of M. Rabatel (2015), with our own Lemke.
//!
//! # Scheme
//!
//! From a state at time `t` (docs/physics.md §3, §4; origin report §3.2):
//!
//! 1. **Detection.** Contacts are found by sweep and prune and exact convex
//!    polygon distances ([`crate::contact`]; a non-convex floe or obstacle
//!    by its convex parts): every vertex–edge point whose gap is below the
//!    contact distance `δ` is *closed*. Every facing edge pair is clipped
//!    ([`CONTACT_POINTS`]), so both corners of a nearly flush pair within
//!    `δ` are contacts of the sustained problem.
//! 2. **Impacts.** If a closed contact approaches faster than the impact
//!    threshold (`u_N < −v_imp`, [`EventDriven::new`]), the connected
//!    group of floes it belongs to goes through an impact: the compression
//!    LCP of docs/physics.md §3.1 with `e = 0` and no external impulse gives `W_c`
//!    and the impulse `P_c`; decompression applies `e P_c` more, i.e. Poisson's
//!    law in Rabatel's energy-consistent form `W⁺ = (1 + e) W_c − e W⁻`, which
//!    never increases the kinetic energy for `e ≤ 1` and conserves it for
//!    `e = 1, μ = 0`. Repeated until no closed contact approaches (a
//!    decompression may push another closed contact into approach). A slower
//!    approach that the step's sustained force would let close more than a
//!    tenth of the penetration tolerance is stopped at once, plastically.
//! 3. **Smooth step with sustained contacts.** A trial step `h` is bounded by
//!    the scheme alone, never by the output times
//!    ([`SmoothIntegrator::step_bound`]: the drag stability bound `Δt_max`
//!    of docs/physics.md §4.2, a quarter of the smallest floe radius of
//!    travel from the largest point speed and acceleration, the forcing
//!    kinks, the end of the run), and with closed contacts by the contact
//!    horizon [`contact_horizon`]. Closed contacts that persist (resting,
//!    sliding) receive a constant contact force over the step: the LCP is
//!    solved with the velocity–impulse form of docs/physics.md §3.1,
//!    `h_free = −M W_free` where `W_free` is the free velocity after `h`
//!    (the external impulse `∫𝓗 dt` included), and its impulse divided by `h`
//!    is added to the environment forces while the step is integrated by the
//!    shared smooth integrator. A constant force balance is therefore exact
//!    (a floe pressed on a wall by a constant wind stays put; a sliding floe
//!    decelerates at exactly `μ a`). A penetrating sustained contact asks for
//!    a separating velocity `−g/H` (Rabatel's relaxed Signorini, `JᵀW⁺ ≥ −c`
//!    with `c = g/H`, docs/physics.md §3.1), `H` the step's nominal length
//!    before cuts and halvings: over a halved step `−g/h` would grow without
//!    bound and put kinetic energy in. A separating contact of an
//!    isolated pair pulled back by the environment (`EventDriven::separation`):
//!    its **accumulation** of bounces completes at its accumulation time
//!    `T = 2u_N/(|a_N|(1 − e))`, by the mean motion (the normal velocity
//!    decaying linearly to rest at `T`, asked of the same LCP, the step cut
//!    at `T`), not at once; or its **flight within the contact distance** is
//!    followed to its return (the pair open meanwhile); otherwise the apex
//!    rule cuts the step at the apex of a flight that leaves the contact
//!    distance. An isolated sliding pair that **sticks** within the step
//!    cuts it where its slip stops (`EventDriven::stick_times`); in a pile
//!    the constant friction force smears the stop over the step.
//! 4. **Event location in time.** After the trial step, every vertex of each
//!    close pair (floes and obstacles both ways) that was open (`d > δ`) and
//!    ends below the impact gap `g_i` ([`IMPACT_GAP_FRACTION`] of `δ`), or
//!    whose path relative to the other body passes within `g_i` of it inside
//!    the step (a transit), is an event: the first instant its
//!    signed distance to the other body reaches `g_i` is found by Illinois
//!    root finding on the re-integrated motion (to `1e-3 δ`), and the step is
//!    cut there. The default `δ` is the report's positive contact distance,
//!    1e-3 of the smallest floe radius: each impact comes early by about
//!    `δ / (10 × approach speed)`, and collisions closer than `δ` are treated
//!    together rather than one by one. A case that sets a tiny
//!    `[contact] distance` (e.g. 1e-9 m) locates each impact at the root of
//!    the gap.
//! 5. **Penetration.** A penetration deeper than the tolerance at the end of
//!    a step rejects it; it is retried with half the step (counted). The
//!    depth of a pair is its minimum translation distance
//!    ([`crate::contact::signed_distance`], as the contact detection and
//!    `floebench check` measure it), not its deepest vertex, which misses
//!    two convex bodies whose edges cross with no vertex inside the other
//!    (the scissored pieces of a split).
//!
//! **Outputs.** The scheme keeps its state on its own grid of steps; the
//! state at an output time inside a step is that step's exact continuation
//! ([`SmoothIntegrator::continuation`]): what is saved never changes the
//! dynamics.
//!
//! Every LCP goes through the shared [`ContactSolver`]: [`crate::lcp::solve()`]
//! (lexicographic Lemke, another pivot rule, a perturbed matrix), whose
//! residual is recomputed on the original data. When all fail, the documented last resort is the
//! frictionless LCP of the same contacts; if that fails too, no impulse is
//! applied. Each outcome is counted. With `solver = "nsgs"` or `"apgd"` the
//! sustained problems are solved iteratively on the sparse problem
//! ([`crate::iterative`], docs/physics.md §3.5) and the impacts stay on
//! Lemke; every contact solve's natural-map residual is recorded.
//!
//! # References
//!
//! - M. Rabatel, S. Labbé, J. Weiss (2015), *Dynamics of an assembly of rigid
//!   ice floes*, J. Geophys. Res. Oceans 120, 5887–5909; M. Rabatel (2015),
//!   PhD thesis, Université Grenoble Alpes.
//! - D. Stewart, J. Trinkle (1996), *An implicit time-stepping scheme for rigid
//!   body dynamics with inelastic collisions and Coulomb friction*, IJNME 39.
//! - R. Cottle, J.-S. Pang, R. Stone (1992), *The Linear Complementarity
//!   Problem*, Academic Press (Lemke's algorithm, lexicographic rule).
//! - F. Pfeiffer, C. Glocker (1996), *Multibody Dynamics with Unilateral
//!   Contacts* (Poisson's impact law).

use super::contact_solver::{
    ContactSolver, SolverKind, DEFAULT_MERGE_FRICTION, DEFAULT_PREDICT_FROM, DEFAULT_WARM_LEMKE,
    DEFAULT_WARM_START,
};
use super::group_solver::{read_solver, GroupData, GroupSolver};
use super::{
    reported_state, Context, Entry, Formulation, FormulationError, FormulationOptions, NotClaimed,
    OwnState, Topology,
};
use crate::contact::problem::{groups, Gen};
use crate::contact::{loads_of, signed_distance, Aabb, BroadPhase, Contact, Load, NarrowOptions};
use crate::geometry::{
    aabb, perp, point_outline_signed_distance, point_polygon_signed_distance, rotate, Vec2,
};
use crate::iterative::{IterativeOptions, MAX_ITERATIONS, RELAXATION, TOLERANCE};
use crate::model::limits::Limit;
use crate::model::{Body, CaseError, Scenario, SettingsTable, TableSpec};
use crate::physics::{SmoothIntegrator, StepRecord, Wrench};
use crate::record::counters::common::{IMPACTS, MAX_PENETRATION, STEPS};
use crate::record::{
    ContactEvent, ContactLog, Counter, Counters, Settings, SolveProfile, Stage, Unit,
};
use crate::state::{
    body_parts, detect_contacts_with, normal_velocity, tangential_velocity, world_polygons,
    BodyState, Ledger, System,
};

/// The registry entry (see [`crate::formulation::REGISTRY`]).
pub const ENTRY: Entry = Entry {
    name: "event-driven",
    description: "Rabatel (2015): advance to each impact, velocity-impulse LCP (Stewart-Trinkle friction) by Lemke, Poisson restitution",
    build: |scn, opts| Ok(Box::new(EventDriven::new(scn, opts)?)),
    settings: Some(TABLE),
    resolves_contacts: true,
    dumps_lcps: true,
    supports_fracture: true,
    not_claimed: &[
        NotClaimed {
            check: "cradle_physical",
            case: None,
            reason: "a simultaneous impact law on touching floes gives the LCP answer ((2-n)/n, 2/n, ...) v0, not the sequential one (docs/physics.md §6); cradle_outcome checks the LCP answer",
        },
    ],
};

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
    /// (default: Lemke, exact Coulomb) or `"cone"` (the convex relaxation);
    /// impacts are always the compression LCP of Poisson's law.
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
    /// `relaxation` (default `None`: the direct `solver`; the impacts'
    /// compression LCPs stay on Lemke; see [`crate::iterative`]).
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

/// The smallest floe radius, or 1 m without floes: the length the default
/// tolerances are fractions of, m.
pub fn floe_length_scale(scn: &Scenario) -> f64 {
    let rmin = scn.min_floe_radius();
    if rmin.is_finite() {
        rmin
    } else {
        1.0
    }
}

/// The contact distance `δ` in use on `scn`, m: the case's, or
/// [`DEFAULT_DISTANCE_FRACTION`] of the smallest floe radius.
pub fn contact_distance(scn: &Scenario) -> f64 {
    if scn.contact.distance > 0.0 {
        scn.contact.distance
    } else {
        DEFAULT_DISTANCE_FRACTION * floe_length_scale(scn)
    }
}

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
const COUNTERS: &[&Counter] = &[
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

/// Default contact distance as a fraction of the smallest floe radius, when
/// the case leaves `[contact] distance = 0`.
pub const DEFAULT_DISTANCE_FRACTION: f64 = 1e-3;
/// Default penetration tolerance as a fraction of the smallest floe radius.
pub const DEFAULT_PENETRATION_FRACTION: f64 = 1e-4;
/// The contact points of the scheme: every facing edge pair is clipped
/// (Box2D's reference/incident clipping at any angle, not only within the
/// shared 1e-6 rad parallel tolerance), and each clipped end within the
/// contact distance `δ` is a closed contact. A vertex within `δ` of the
/// facing edge is then always a contact of the sustained problem: with one
/// point per nearly flush pair (edges a few 1e-4 rad apart), the second
/// corner, already within `δ`, was neither held by the LCP nor located as
/// an event, and turned into the other floe (docs/physics.md §4.3, step 1).
const CONTACT_POINTS: NarrowOptions = NarrowOptions {
    parallel_tolerance: std::f64::consts::FRAC_PI_2,
    merge_fraction: crate::contact::DEFAULT_MERGE_FRACTION,
};
/// Rounding floor of the approach speed that makes an impact, m/s.
const APPROACH_TOLERANCE: f64 = 1e-10;
/// Impact rounds at one instant before giving up (counted).
const MAX_IMPACT_ROUNDS: usize = 100;
/// Halvings of a step that penetrates before it is accepted anyway (counted).
const MAX_REJECTIONS: usize = 12;
/// Cuts of one trial step (flights, returns, accumulations, sticks) before
/// the step is taken as it is: each cut shortens it, and a cut that would
/// shorten it by less than [`MIN_CUT_FRACTION`] is not made.
const MAX_CUTS: usize = 50;
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
const ROOT_TOLERANCE: f64 = 1e-3;
/// A cut shortens the trial step by at least this fraction.
const MIN_CUT_FRACTION: f64 = 1e-6;
/// Adjustments of one step to the instant a sliding pair sticks.
const MAX_STICK_MOVES: usize = 3;
/// A sliding contact whose friction impulse is below `(1 − this) μ λ` at the
/// end of the step has stuck within it (Lemke's rounding allowed).
const STICK_SLACK: f64 = 1e-9;

/// Why a trial step is cut short (the stick rule adjusts it apart).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cut {
    /// At the apex of a flight that leaves the contact distance.
    Apex,
    /// At the return of a flight within the contact distance.
    Return,
    /// At the accumulation time of a contact.
    Accumulation,
}

impl Cut {
    fn counter(self) -> &'static Counter {
        match self {
            Cut::Apex => &STEPS_CUT_FOR_FLIGHT,
            Cut::Return => &STEPS_CUT_AT_RETURN,
            Cut::Accumulation => &STEPS_CUT_AT_ACCUMULATION,
        }
    }
}

/// A closed contact in a free flight that stays within the contact
/// distance: the pair `(min, max)` is left out of the sustained problem
/// until the flight returns, at `until` (s), or earlier if the pair comes
/// back to its starting gap or penetrates (the estimate of the flight
/// assumed a constant normal acceleration).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Flight {
    pair: (usize, usize),
    until: f64,
    /// The smallest gap of the pair's contacts when the flight started, m.
    gap: f64,
}

/// What happens to a closed contact that separates (`u_N > 0`) and is pulled
/// back by the environment (`a_N < 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Separation {
    /// Its bounces accumulate within the contact distance: the mean motion,
    /// at rest after `remaining` s.
    Accumulating { remaining: f64 },
    /// A flight within the contact distance, back after `flight` s.
    FlightWithin { flight: f64 },
    /// Anything else (a flight that leaves the contact distance, a contact
    /// not pulled back): the apex rule of the trial step.
    Other,
}

/// The constant wrenches of a trial step, or where to cut it, and the
/// flights it starts.
#[derive(Debug, Clone)]
struct Sustained {
    wrenches: Vec<Wrench>,
    cut: Option<(f64, Cut)>,
    flights: Vec<Flight>,
    /// Where a sliding pair that stuck by the end stopped (s from the start).
    stick: Option<f64>,
    /// Where a pair still sliding at the end, slower, would stop (s).
    slide_stop: Option<f64>,
    /// The impulses of the sustained solves over the trial step, as loads
    /// of the stress criterion (empty unless `[fracture] model = "stress"`).
    loads: Vec<Load>,
}

/// The earlier of two cuts.
fn earlier(a: Option<(f64, Cut)>, s: f64, why: Cut) -> Option<(f64, Cut)> {
    match a {
        Some((t, _)) if t <= s => a,
        _ => Some((s, why)),
    }
}

/// Margin on the relative travel of two bodies over a step in the transit
/// prefilter (drag makes the forces vary a little over a step).
const TRANSIT_MARGIN: f64 = 1.25;
/// Pieces of the path of a vertex relative to another body in the transit
/// test ([`transit`]): the relative path is curved when the bodies turn.
const TRANSIT_PIECES: usize = 4;

/// The pose `(G, θ)` of a floe at the fraction `σ` of a step of length `h`
/// from `b0` to `b1`: cubic Hermite interpolation of both from their values
/// and rates at the ends (exact for a motion under constant forces without
/// rotation, and second order in `h` otherwise).
fn hermite_pose(b0: &BodyState, b1: &BodyState, h: f64, sigma: f64) -> (Vec2, f64) {
    let s2 = sigma * sigma;
    let s3 = s2 * sigma;
    let (h00, h10, h01, h11) = (
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + sigma,
        -2.0 * s3 + 3.0 * s2,
        s3 - s2,
    );
    (
        b0.position * h00 + b0.velocity * (h10 * h) + b1.position * h01 + b1.velocity * (h11 * h),
        b0.angle * h00
            + b0.angular_velocity * (h10 * h)
            + b1.angle * h01
            + b1.angular_velocity * (h11 * h),
    )
}

/// The motion of body `owner` relative to body `other` over the step of
/// length `h` from `sys` to `end`, at the [`TRANSIT_PIECES`]` + 1` fractions
/// `σ = k / TRANSIT_PIECES` of the step: the rigid maps `x ↦ R(α) x + d`
/// (as `(cos α, sin α, d)`) taking a point of `owner` (its shape for a floe,
/// its world polygon for an obstacle) into the frame of `other`, both poses
/// interpolated by [`hermite_pose`].
fn relative_motion(
    scn: &Scenario,
    sys: &System,
    end: &System,
    h: f64,
    owner: usize,
    other: usize,
) -> Vec<(f64, f64, Vec2)> {
    let pose = |body: usize, sigma: f64| -> (Vec2, f64) {
        match scn.body(body) {
            Body::Floe(i) => hermite_pose(&sys.bodies[i], &end.bodies[i], h, sigma),
            Body::Obstacle(_) => (Vec2::zeros(), 0.0),
        }
    };
    (0..=TRANSIT_PIECES)
        .map(|k| {
            let sigma = k as f64 / TRANSIT_PIECES as f64;
            let ((gv, av), (go, ao)) = (pose(owner, sigma), pose(other, sigma));
            let alpha = av - ao;
            (alpha.cos(), alpha.sin(), rotate(&(gv - go), -ao))
        })
        .collect()
}

/// Whether the point `x` of a body (in the body's own coordinates, see
/// [`relative_motion`]) passes within `grow` (m: the impact gap `g_i`,
/// [`IMPACT_GAP_FRACTION`] of `δ`) of the polygon `local` of another body
/// during the step: its path in that body's frame, given by `motion`, is
/// followed in straight pieces, each clipped against the polygon grown by
/// `grow`. Returns the middle of the first passage as a fraction of the
/// step, if there is one.
///
/// A non-convex body is the union of its convex parts (`part_polys`, from
/// [`part_polygons`] of `local`): the passage is against the
/// nearest-in-time part; `part_polys` is empty for a convex body, whose
/// outline is its one part.
fn transit(
    motion: &[(f64, f64, Vec2)],
    x: &Vec2,
    local: &[Vec2],
    part_polys: &[Vec<Vec2>],
    grow: f64,
) -> Option<f64> {
    let map = |&(c, s, d): &(f64, f64, Vec2)| Vec2::new(c * x.x - s * x.y, s * x.x + c * x.y) + d;
    let pieces = motion.len().saturating_sub(1).max(1) as f64;
    let mut q0 = map(&motion[0]);
    for (piece, m) in motion.iter().enumerate().skip(1) {
        let q1 = map(m);
        let hit = if part_polys.is_empty() {
            clip(&q0, &q1, local, grow)
        } else {
            part_polys
                .iter()
                .filter_map(|p| clip(&q0, &q1, p, grow))
                .reduce(f64::min)
        };
        if let Some(u) = hit {
            return Some((piece as f64 - 1.0 + u) / pieces);
        }
        q0 = q1;
    }
    None
}

/// The convex parts (index lists `parts`) of the outline `poly` as
/// polygons; empty (no allocation) for a convex body, which is its one part.
fn part_polygons(poly: &[Vec2], parts: &[Vec<usize>]) -> Vec<Vec<Vec2>> {
    if parts.len() <= 1 {
        return Vec::new();
    }
    parts
        .iter()
        .map(|ids| ids.iter().map(|&k| poly[k]).collect())
        .collect()
}

/// Signed distance (m) from the point `v` to body `body` of `scn` at its
/// world outline `poly`: the convex formula
/// ([`point_polygon_signed_distance`]) for a convex body, the simple-polygon
/// one ([`point_outline_signed_distance`]) for a non-convex body.
fn body_distance(scn: &Scenario, body: usize, v: &Vec2, poly: &[Vec2]) -> f64 {
    if body_parts(scn, body).len() <= 1 {
        point_polygon_signed_distance(v, poly)
    } else {
        point_outline_signed_distance(v, poly)
    }
}

/// Cyrus–Beck clipping of the segment `q0 → q1` against the convex
/// counter-clockwise polygon `poly` grown by `grow` (m): the middle of the
/// part inside, as a fraction of the segment, if there is one.
fn clip(q0: &Vec2, q1: &Vec2, poly: &[Vec2], grow: f64) -> Option<f64> {
    let dq = q1 - q0;
    let (mut u_in, mut u_out) = (0.0f64, 1.0f64);
    let n = poly.len();
    for e in 0..n {
        let a = poly[e];
        let edge = poly[(e + 1) % n] - a;
        let len = edge.norm();
        if len == 0.0 {
            continue;
        }
        let normal = Vec2::new(edge.y, -edge.x) / len;
        let num = (q0 - a).dot(&normal) - grow;
        let den = dq.dot(&normal);
        if den == 0.0 {
            if num > 0.0 {
                return None;
            }
        } else if den < 0.0 {
            u_in = u_in.max(-num / den);
        } else {
            u_out = u_out.min(-num / den);
        }
        if u_in > u_out {
            return None;
        }
    }
    Some(0.5 * (u_in + u_out))
}

/// The contact horizon `τ_c = (2 ε Δt_max / a_f)^(1/3)`, s, the longest
/// step with closed contacts. A step holds the contact force constant while
/// the environment forces change; the drag changes them on the time scale
/// `Δt_max` (docs/physics.md §4.2), by about `a_f h / Δt_max` over a step
/// `h` (`a_f` the forcing: the drag of the strongest wind and current on the
/// lightest floe at rest, as an acceleration), which drifts a contact by
/// about `a_f h³ / (2 Δt_max)`: at most the penetration tolerance `ε` within
/// `τ_c`. Without water drag or without forcing the forces on a contact do
/// not change between the kinks of the forcing series (where steps stop
/// anyway) and the horizon is infinite.
pub fn contact_horizon(scn: &Scenario, pen_tol: f64, drag_bound: f64) -> f64 {
    let env = &scn.environment;
    let traction = env.air.drag_factor() * env.air.velocity.max_speed().powi(2)
        + env.water.drag_factor() * env.water.velocity.max_speed().powi(2);
    let forcing = scn
        .floes
        .iter()
        .map(|f| traction / f.surface_density())
        .fold(0.0, f64::max);
    if forcing > 0.0 && drag_bound.is_finite() {
        (2.0 * pen_tol * drag_bound / forcing).cbrt()
    } else {
        f64::INFINITY
    }
}

/// Whether the pair `(min, max)` is isolated among `contacts`: no other
/// pair touches either of its floes (obstacles may touch other floes), so
/// that only the environment pulls its contact back.
fn isolated(scn: &Scenario, contacts: &[Contact], pair: (usize, usize)) -> bool {
    let floe = |b: usize| matches!(scn.body(b), Body::Floe(_));
    contacts.iter().all(|d| {
        let p = pair_of(d);
        p == pair
            || !([p.0, p.1]
                .iter()
                .any(|&b| floe(b) && (b == pair.0 || b == pair.1)))
    })
}

/// The pair of a contact, smaller index first.
fn pair_of(c: &Contact) -> (usize, usize) {
    (c.a.min(c.b), c.a.max(c.b))
}

/// The first event of a trial step: its time from the step start (s) and
/// the pair of bodies it belongs to.
type Event = (f64, (usize, usize));

/// One resolved impact, for analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct ImpactRecord {
    /// Time, s.
    pub t: f64,
    /// Floes of the group.
    pub floes: Vec<usize>,
    /// Number of contacts in the LCP.
    pub contacts: usize,
    /// Kinetic energy of the group before and after, J.
    pub energy: (f64, f64),
}

/// The event-driven formulation.
#[derive(Debug)]
pub struct EventDriven {
    integ: SmoothIntegrator,
    distance: f64,
    pen_tol: f64,
    /// Approach speed below which a closed contact is left to the sustained
    /// LCP rather than resolved as an impact, m/s (see [`EventDriven::new`]).
    impact_speed: f64,
    /// The longest step with closed contacts, s ([`contact_horizon`]).
    horizon: f64,
    solver: GroupSolver,
    bp: BroadPhase,
    sweep_bp: BroadPhase,
    counters: Counters,
    impacts: Vec<ImpactRecord>,
    max_penetration: f64,
    /// The state on the scheme's own step grid.
    own: OwnState,
    /// The last step taken: reported states inside it are its continuation.
    last: Option<StepRecord>,
    /// Flights within the contact distance in progress.
    flights: Vec<Flight>,
    /// The loads of the slow approaches stopped at this step's start, for
    /// the stress criterion with the step's sustained impulses.
    step_loads: Vec<Load>,
}

/// Keeps at most this many impact records.
const MAX_IMPACT_RECORDS: usize = 100_000;

impl EventDriven {
    /// Sets up the formulation for `scn` with its `[formulation.event-driven]`
    /// settings.
    pub fn new(scn: &Scenario, opts: &FormulationOptions) -> Result<EventDriven, String> {
        faer::set_global_parallelism(faer::Par::Seq);
        let settings = EventDrivenSettings::of(scn).map_err(|e| e.to_string())?;
        let distance = contact_distance(scn);
        let pen_tol = settings.penetration_tolerance(scn);
        let integ = SmoothIntegrator::new(scn, opts.integrator);
        // An approach slower than ε/τ_c closes less than the penetration
        // tolerance ε over the contact horizon τ_c: it is the drift of a
        // sustained contact, not an impact. A step of length τ_c holding its
        // contact force while the forces change by a_f τ_c/Δt_max leaves
        // drift velocities up to a_f τ_c²/Δt_max = 2ε/τ_c; the threshold is
        // half of that. Without drag the forces do not drift and only the
        // rounding floor remains. None of this depends on the output times.
        let horizon = contact_horizon(scn, pen_tol, integ.drag_bound());
        let impact_speed = APPROACH_TOLERANCE.max(pen_tol / horizon);
        Ok(EventDriven {
            integ,
            distance,
            pen_tol,
            impact_speed,
            horizon,
            solver: GroupSolver::new(
                ContactSolver::with_warm_start(
                    settings.solver,
                    opts.dump_lcp.clone(),
                    settings.warm_start,
                )
                .with_warm_lemke(settings.warm_lemke)
                .with_merge_friction(settings.merge_friction)
                .with_predict_from(settings.predict_from)
                .with_warm_check(opts.warm_check),
                settings.iterative,
            ),
            bp: BroadPhase::new(),
            sweep_bp: BroadPhase::new(),
            counters: Counters::new(COUNTERS),
            impacts: Vec::new(),
            max_penetration: 0.0,
            own: OwnState::default(),
            last: None,
            flights: Vec::new(),
            step_loads: Vec::new(),
        })
    }

    /// The impacts resolved so far (the first [`MAX_IMPACT_RECORDS`]).
    pub fn impacts(&self) -> &[ImpactRecord] {
        &self.impacts
    }

    /// The contact distance `δ` in use, m.
    pub fn distance(&self) -> f64 {
        self.distance
    }

    /// Largest `|β| / (μ λ)` over every contact impulse so far (0 without friction).
    pub fn max_coulomb_ratio(&self) -> f64 {
        self.solver.direct.max_coulomb_ratio()
    }

    fn detect(&mut self, scn: &Scenario, bodies: &[BodyState]) -> Vec<Contact> {
        let mut out = Vec::new();
        detect_contacts_with(
            scn,
            bodies,
            self.distance,
            &CONTACT_POINTS,
            &mut self.bp,
            &mut out,
        );
        out
    }

    /// Resolves the impacts of every group with an approaching closed contact
    /// (a pair in a flight within δ is open). Returns whether any impact
    /// happened.
    ///
    /// With `slow = Some(h)`, the approaches slower than the impact threshold
    /// instead (faster than the rounding floor), those that the sustained
    /// force of a step `h` would let close more than a tenth of the
    /// penetration tolerance (`|u| h / 2`): they are stopped at once,
    /// plastically (`e = 0`; counted apart, not as impacts).
    fn impacts_at(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        contacts: &[Contact],
        slow: Option<f64>,
        topology: &mut dyn Topology,
    ) -> bool {
        let n = scn.floes.len();
        let approaching: Vec<bool> = contacts
            .iter()
            .map(|c| {
                // A pair in a flight within δ is open until it returns.
                if self.flights.iter().any(|f| f.pair == pair_of(c)) {
                    return false;
                }
                let u = normal_velocity(scn, &sys.bodies, c);
                match slow {
                    None => u < -self.impact_speed,
                    Some(h) => u < -APPROACH_TOLERANCE && -u * h > 0.2 * self.pen_tol,
                }
            })
            .collect();
        if !approaching.iter().any(|&a| a) {
            return false;
        }
        let centres = sys.centres();
        let w: Vec<Gen> = sys.velocities();
        let zeros = vec![0.0; contacts.len()];
        let e = if slow.is_some() {
            0.0
        } else {
            scn.contact.restitution
        };
        for g in groups(contacts, n) {
            if !g.contacts.iter().any(|&k| approaching[k]) {
                continue;
            }
            // The compression LCP of Poisson's law, whatever the solver of
            // the sustained contacts.
            let data = GroupData {
                scn,
                centres: &centres,
                contacts,
                group: &g,
                w_free: &w,
                offsets: &zeros,
            };
            let ans = self.solver.solve_impact(&data, sys.t);
            let dv = &ans.dv;
            let before = sys.group_kinetic_energy(scn, &g.floes);
            let w_minus: Vec<BodyState> = g.floes.iter().map(|&i| sys.bodies[i]).collect();
            let apply = |bodies: &mut [BodyState], k: f64| {
                for (l, &i) in g.floes.iter().enumerate() {
                    let b = &mut bodies[i];
                    b.velocity = w_minus[l].velocity + Vec2::new(dv[l][0], dv[l][1]) * k;
                    b.angular_velocity = w_minus[l].angular_velocity + dv[l][2] * k;
                }
            };
            apply(&mut sys.bodies, 1.0 + e);
            // The group's velocities changed: its flights end here.
            self.flights
                .retain(|f| !g.floes.contains(&f.pair.0) && !g.floes.contains(&f.pair.1));
            let after = sys.group_kinetic_energy(scn, &g.floes);
            if after > before * (1.0 + 1e-12) + 1e-300 {
                self.counters.add(&IMPACT_ENERGY_INCREASES, 1);
            }
            sys.ledger.dissipated += before - after;
            if topology.reads().percussions && slow.is_none() {
                // The impulses applied: (1 + e) times the compression's.
                let k = 1.0 + e;
                let normal: Vec<f64> = ans.normal.iter().map(|v| v * k).collect();
                let tangential: Vec<f64> = ans.tangential.iter().map(|v| v * k).collect();
                let group: Vec<&Contact> = g.contacts.iter().map(|&k| &contacts[k]).collect();
                let loads = loads_of(scn, &group, &normal, &tangential);
                topology.percussion(scn, sys, &loads, sys.t, sys.t, before - after);
            } else if slow.is_some() && topology.reads().sustained {
                // A slow approach stopped is part of the sustained contact:
                // the stress criterion reads it with the step's impulses.
                let group: Vec<&Contact> = g.contacts.iter().map(|&k| &contacts[k]).collect();
                self.step_loads
                    .extend(loads_of(scn, &group, &ans.normal, &ans.tangential));
            }
            self.solver.direct.log_mut().push_event(ContactEvent {
                t: sys.t,
                contacts: g.contacts.len(),
                energy_before: before,
                energy_after: after,
            });
            if slow.is_some() {
                self.counters.add(&SLOW_APPROACHES_STOPPED, 1);
                continue;
            }
            self.counters.add(&IMPACTS, 1);
            if self.impacts.len() < MAX_IMPACT_RECORDS {
                self.impacts.push(ImpactRecord {
                    t: sys.t,
                    floes: g.floes.clone(),
                    contacts: g.contacts.len(),
                    energy: (before, after),
                });
            }
        }
        true
    }

    /// The normal relative acceleration of contact `c` from the environment
    /// forces at `sys` (m/s², negative: pulled back into contact), the
    /// centripetal terms included.
    fn normal_acceleration(&mut self, scn: &Scenario, sys: &System, c: &Contact) -> f64 {
        let model = self.integ.model();
        let acc = |i: usize| -> Vec2 {
            let Body::Floe(i) = scn.body(i) else {
                return Vec2::zeros();
            };
            let b = &sys.bodies[i];
            let a = model.acceleration(i, &model.forces(&scn.environment, i, sys.t, b));
            let r = c.geom.point - b.position;
            Vec2::new(a[0], a[1]) + perp(&r) * a[2] - r * b.angular_velocity.powi(2)
        };
        (acc(c.b) - acc(c.a)).dot(&c.geom.normal)
    }

    /// What happens to a closed contact `c` that separates at `u` (m/s,
    /// `> 0`), with restitution `e`, under a constant normal acceleration
    /// `a_N < 0` (docs/physics.md §4.3, step 3): its flight rises by
    /// `H = u²/(2|a_N|)`; its bounces (flights `2u eᵏ/|a_N|`) accumulate after
    /// `T = 2u/(|a_N|(1 − e))`. When `e < 1`, the mean motion over `T` (the
    /// normal velocity decaying linearly to rest, which lifts the contact by
    /// `u T/2 = u²/(|a_N|(1 − e))`) stays within the contact distance, and
    /// `T` is within the drag time scale (the forces are constant enough for
    /// the closed form), the contact accumulates. Otherwise a flight that
    /// stays within the contact distance, faster than the impact threshold,
    /// is followed to its return; anything else is left to the apex rule.
    /// Only for an isolated pair ([`isolated`]): in a pile the neighbours'
    /// contact forces, not the environment, pull a contact back, and the
    /// closed forms do not hold (with them, the mean motion pushed piles of
    /// `field_200_coast` apart against the wind: contacts did 6.8e9 J of
    /// positive work in 6000 s).
    fn separation(&mut self, scn: &Scenario, sys: &System, c: &Contact, u: f64) -> Separation {
        if u <= self.impact_speed {
            // Not a bounce: its return would not be an impact.
            return Separation::Other;
        }
        let a_n = self.normal_acceleration(scn, sys, c);
        if a_n.is_nan() || a_n >= 0.0 {
            return Separation::Other;
        }
        let pull = -a_n;
        let e = scn.contact.restitution;
        let gap = c.geom.gap;
        if e < 1.0 {
            let remaining = 2.0 * u / (pull * (1.0 - e));
            if gap + 0.5 * u * remaining <= self.distance && remaining <= self.integ.drag_bound() {
                return Separation::Accumulating { remaining };
            }
        }
        if gap + u * u / (2.0 * pull) <= self.distance {
            return Separation::FlightWithin {
                flight: 2.0 * u / pull,
            };
        }
        Separation::Other
    }

    /// Constant contact wrenches over a trial step of length `h` for the
    /// closed contacts (sustained contact), from the velocity–impulse LCP;
    /// or where the step must be cut (docs/physics.md §4.3, step 3).
    /// The stick rule's estimates are returned apart
    /// (`EventDriven::stick_times`).
    fn sustained_wrenches(
        &mut self,
        scn: &Scenario,
        sys: &System,
        contacts: &[Contact],
        h: f64,
        nominal: f64,
        cx: &mut Context,
    ) -> Result<Sustained, FormulationError> {
        let n = scn.floes.len();
        let t = sys.t;
        let mut out = Sustained {
            wrenches: vec![Wrench::default(); n],
            cut: None,
            flights: Vec::new(),
            stick: None,
            slide_stop: None,
            loads: Vec::new(),
        };
        if contacts.is_empty() {
            return Ok(out);
        }
        // The separation velocity asked of each contact at the end of the
        // step (m/s): −g/H for a penetration (relaxed Signorini over the
        // nominal step H, not the halved or cut one: a speed −g/h grows
        // without bound as h shrinks, and puts kinetic energy in), the decay
        // of an accumulation, else 0; `None`: open (in a flight within δ).
        let mut target: Vec<Option<f64>> = Vec::with_capacity(contacts.len());
        let mut apex_rule = vec![false; contacts.len()];
        for (k, c) in contacts.iter().enumerate() {
            let pair = pair_of(c);
            if let Some(f) = self.flights.iter().find(|f| f.pair == pair) {
                out.cut = earlier(out.cut, f.until - t, Cut::Return);
                target.push(None);
                continue;
            }
            let mut ask = if c.geom.gap < 0.0 {
                -c.geom.gap / nominal.max(h)
            } else {
                0.0
            };
            let u = normal_velocity(scn, &sys.bodies, c);
            if u > APPROACH_TOLERANCE {
                let separation = if isolated(scn, contacts, pair) {
                    self.separation(scn, sys, c, u)
                } else {
                    Separation::Other
                };
                match separation {
                    Separation::Accumulating { remaining } => {
                        // The normal velocity decays linearly to rest at the
                        // accumulation time.
                        self.counters.add(&ACCUMULATING_CONTACTS, 1);
                        // Cut at the accumulation time unless the decay
                        // stretched over the step stays within δ (a lift
                        // u h/2) and adds less than the penetration
                        // tolerance after it (u (h − T)/2).
                        if c.geom.gap + 0.5 * u * h > self.distance
                            || u * (h - remaining) > 2.0 * self.pen_tol
                        {
                            out.cut = earlier(out.cut, remaining, Cut::Accumulation);
                        }
                        ask = ask.max(u * (1.0 - h / remaining).max(0.0));
                    }
                    Separation::FlightWithin { flight } => {
                        let gap = contacts
                            .iter()
                            .filter(|d| pair_of(d) == pair)
                            .map(|d| d.geom.gap)
                            .fold(f64::INFINITY, f64::min);
                        out.flights.push(Flight {
                            pair,
                            until: t + flight,
                            gap,
                        });
                        out.cut = earlier(out.cut, flight, Cut::Return);
                        target.push(None);
                        continue;
                    }
                    Separation::Other => apex_rule[k] = true,
                }
            }
            target.push(Some(ask));
        }
        // A flight makes its whole pair open.
        for (k, c) in contacts.iter().enumerate() {
            if out.flights.iter().any(|f| f.pair == pair_of(c)) {
                target[k] = None;
            }
        }
        let kept: Vec<usize> = (0..contacts.len())
            .filter(|&k| target[k].is_some())
            .collect();
        let closed: Vec<Contact> = kept.iter().map(|&k| contacts[k]).collect();
        let gs = groups(&closed, n);
        // Free velocities after h of the floes in contact.
        let mut w_free: Vec<Gen> = vec![[0.0; 3]; n];
        let integ = &mut self.integ;
        cx.clock
            .time(Stage::Integration, || -> Result<(), FormulationError> {
                for g in &gs {
                    for &i in &g.floes {
                        let mut b = sys.bodies[i];
                        let mut scratch = Ledger::default();
                        integ.advance(scn, i, &mut b, &mut scratch, t, t + h)?;
                        w_free[i] = [b.velocity.x, b.velocity.y, b.angular_velocity];
                    }
                }
                Ok(())
            })?;
        // The apex rule: a closed contact that separates now but whose free
        // flight returns within h and rises above the contact distance: cut
        // the step at the apex (estimated with a constant normal
        // acceleration) so that the return is located as an event; a
        // micro-bounce that stays within δ (slower than the impact
        // threshold) is absorbed by the sustained LCP (counted).
        let free_bodies: Vec<BodyState> = sys
            .bodies
            .iter()
            .zip(&w_free)
            .map(|(b, w)| BodyState {
                velocity: Vec2::new(w[0], w[1]),
                angular_velocity: w[2],
                ..*b
            })
            .collect();
        for (&k, c) in kept.iter().zip(&closed) {
            if !apex_rule[k] {
                continue;
            }
            let u0 = normal_velocity(scn, &sys.bodies, c);
            let u1 = normal_velocity(scn, &free_bodies, c);
            if u1 < 0.0 {
                let apex = h * u0 / (u0 - u1);
                if c.geom.gap + 0.5 * u0 * apex > self.distance {
                    out.cut = earlier(out.cut, apex, Cut::Apex);
                } else {
                    self.counters.add(&MICRO_BOUNCES_ABSORBED, 1);
                }
            }
        }
        if out.cut.is_some_and(|(s, _)| s < h) {
            return Ok(out);
        }
        let centres = sys.centres();
        let offsets: Vec<f64> = kept.iter().map(|&k| -target[k].unwrap_or(0.0)).collect();
        if closed.iter().any(|c| c.geom.gap < 0.0) {
            self.counters.add(&POSITION_CORRECTIONS, 1);
        }
        let mu = scn.contact.friction;
        // Per closed contact: λ, β, tangential compliance; and the floes'
        // velocities at the end of the step.
        let mut lambda = vec![0.0; closed.len()];
        let mut beta = vec![0.0; closed.len()];
        let mut g_t = vec![0.0; closed.len()];
        let mut end_bodies = free_bodies;
        let solve_start = cx.clock.start(Stage::Solve);
        for g in &gs {
            let data = GroupData {
                scn,
                centres: &centres,
                contacts: &closed,
                group: g,
                w_free: &w_free,
                offsets: &offsets,
            };
            let ans = self.solver.solve(&data, t, h);
            let (l, b) = (&ans.normal, &ans.tangential);
            for (j, &k) in g.contacts.iter().enumerate() {
                lambda[k] = l[j];
                beta[k] = b[j];
                g_t[k] = ans.compliance[j];
            }
            if cx.topology.reads().sustained {
                // The group's impulses over h: loads of the stress criterion
                // (docs/physics.md §9.3, §9.5).
                let group: Vec<&Contact> = g.contacts.iter().map(|&k| &closed[k]).collect();
                out.loads.extend(loads_of(scn, &group, l, b));
            }
            let (p, dv) = (&ans.impulses, &ans.dv);
            for (l, &i) in g.floes.iter().enumerate() {
                out.wrenches[i] = Wrench {
                    force: Vec2::new(p[l][0], p[l][1]) / h,
                    torque: p[l][2] / h,
                };
                end_bodies[i].velocity += Vec2::new(dv[l][0], dv[l][1]);
                end_bodies[i].angular_velocity += dv[l][2];
            }
            self.counters.add(&SUSTAINED_SOLVES, 1);
        }
        cx.clock.stop(Stage::Solve, solve_start);
        if mu > 0.0 {
            (out.stick, out.slide_stop) =
                self.stick_times(scn, sys, &closed, &lambda, &beta, &g_t, &end_bodies, h);
        }
        Ok(out)
    }

    /// The stick rule of a trial step of length `h` (docs/physics.md §4.3,
    /// step 3), for the isolated pairs ([`isolated`]) of `closed` that slide
    /// at the start (slip `u₀`) by more than the contact distance over the
    /// step (in a pile the neighbours share the load, so the pair's own
    /// compliance does not give its stop, and each cut re-solves the whole
    /// group: on `narrow_channel` 192 of 275 steps were cut so; a shorter slip
    /// is below the scheme's resolution and not worth a cut: the constant
    /// friction force smears it over the step; with the penetration
    /// tolerance instead, `narrow_channel` took three times as many stick
    /// cuts for the same result). Returns:
    ///
    /// - the earliest stop of a pair that has stuck by the end (its summed
    ///   friction impulse `B`, along the slip, inside the cone `μΛ` of its
    ///   summed normal impulse): had it slid throughout, its slip at the end
    ///   would be `−G_T (μΛ + B)` (`G_T` the mean tangential compliance of
    ///   its points), so its slip, linear in time under constant forces,
    ///   stopped at `s* = h u₀ / (u₀ + G_T (μΛ + B))`;
    /// - the earliest stop of a pair still sliding at the end with a
    ///   smaller slip `u₁` (same direction), extrapolated linearly:
    ///   `h u₀ / (u₀ − u₁)` (after a cut at `s*`, this corrects `G_T`, which
    ///   overestimates the compliance of a face whose two points share the
    ///   load so that the floe does not turn).
    #[allow(clippy::too_many_arguments)]
    fn stick_times(
        &self,
        scn: &Scenario,
        sys: &System,
        closed: &[Contact],
        lambda: &[f64],
        beta: &[f64],
        g_t: &[f64],
        end_bodies: &[BodyState],
        h: f64,
    ) -> (Option<f64>, Option<f64>) {
        let mu = scn.contact.friction;
        // Per pair: slip at the start and at the end (vectors), Λ, B
        // (vector), Σ G_T, points.
        struct PairSlip {
            pair: (usize, usize),
            start: Vec2,
            end: Vec2,
            lambda: f64,
            beta: Vec2,
            compliance: f64,
            points: f64,
        }
        let mut pairs: Vec<PairSlip> = Vec::new();
        for (k, c) in closed.iter().enumerate() {
            let b = c.geom.tangent * beta[k];
            match pairs.iter_mut().find(|p| p.pair == pair_of(c)) {
                Some(p) => {
                    p.lambda += lambda[k];
                    p.beta += b;
                    p.compliance += g_t[k];
                    p.points += 1.0;
                }
                None => pairs.push(PairSlip {
                    pair: pair_of(c),
                    start: c.geom.tangent * tangential_velocity(scn, &sys.bodies, c),
                    end: c.geom.tangent * tangential_velocity(scn, end_bodies, c),
                    lambda: lambda[k],
                    beta: b,
                    compliance: g_t[k],
                    points: 1.0,
                }),
            }
        }
        let (mut stuck, mut sliding) = (None::<f64>, None::<f64>);
        let min = |a: Option<f64>, b: f64| Some(a.map_or(b, |a: f64| a.min(b)));
        for p in pairs {
            let u0 = p.start.norm();
            // Only an isolated pair: in a pile the neighbours share the
            // load and the pair's own compliance does not give its stop,
            // and every cut re-solves the whole group.
            if !(u0 * h > self.distance && p.lambda > 0.0 && isolated(scn, closed, p.pair)) {
                continue;
            }
            let dir = p.start / u0;
            if p.beta.norm() < (1.0 - STICK_SLACK) * mu * p.lambda {
                let reversal = (p.compliance / p.points) * (mu * p.lambda + p.beta.dot(&dir));
                if reversal > 0.0 {
                    stuck = min(stuck, h * u0 / (u0 + reversal));
                }
            } else {
                let u1 = p.end.dot(&dir);
                if u1 > 0.0 && u1 < u0 {
                    sliding = min(sliding, h * u0 / (u0 - u1));
                }
            }
        }
        (stuck, sliding)
    }

    /// Integrates every floe from `sys` over `s` with `wrenches`.
    fn integrate(
        &mut self,
        scn: &Scenario,
        sys: &System,
        s: f64,
        wrenches: &[Wrench],
    ) -> Result<System, FormulationError> {
        Ok(self
            .integ
            .advance_system(scn, sys, sys.t + s, wrenches, None)?)
    }

    /// Candidate pairs over a step: swept boxes of the start and end states.
    fn swept_pairs(
        &mut self,
        scn: &Scenario,
        p0: &[Vec<Vec2>],
        p1: &[Vec<Vec2>],
    ) -> Vec<(usize, usize)> {
        let boxes: Vec<Aabb> = p0
            .iter()
            .zip(p1)
            .enumerate()
            .map(|(i, (a, b))| {
                let (lo0, hi0) = aabb(a);
                let (lo1, hi1) = aabb(b);
                Aabb {
                    min: lo0.inf(&lo1),
                    max: hi0.sup(&hi1),
                    fixed: matches!(scn.body(i), Body::Obstacle(_)),
                }
            })
            .collect();
        let mut pairs = Vec::new();
        self.sweep_bp.pairs(&boxes, self.distance, &mut pairs);
        pairs
    }

    /// The signed distance (m) between bodies `i` and `j` at their world
    /// outlines `a` and `b`: the minimum translation distance of two convex
    /// polygons ([`signed_distance`]), and for a non-convex body the smallest
    /// over the pairs of their convex parts (a penetration is then the
    /// deepest overlap of two parts).
    fn pair_signed_distance(scn: &Scenario, i: usize, j: usize, a: &[Vec2], b: &[Vec2]) -> f64 {
        let (pa, pb) = (
            part_polygons(a, body_parts(scn, i)),
            part_polygons(b, body_parts(scn, j)),
        );
        if pa.is_empty() && pb.is_empty() {
            return signed_distance(a, b);
        }
        let whole = |poly: &[Vec2]| vec![poly.to_vec()];
        let pa = if pa.is_empty() { whole(a) } else { pa };
        let pb = if pb.is_empty() { whole(b) } else { pb };
        let mut d = f64::INFINITY;
        for qa in &pa {
            for qb in &pb {
                d = d.min(signed_distance(qa, qb));
            }
        }
        d
    }

    /// Finds the first event in `(0, h]`: a vertex that was open and closes.
    #[allow(clippy::too_many_arguments)]
    fn locate(
        &mut self,
        scn: &Scenario,
        sys: &System,
        end: &System,
        h: f64,
        wrenches: &[Wrench],
        p0: &[Vec<Vec2>],
        p1: &[Vec<Vec2>],
    ) -> Result<Option<Event>, FormulationError> {
        let delta = self.distance;
        let target = IMPACT_GAP_FRACTION * delta;
        let mut first: Option<Event> = None;
        for (i, j) in self.swept_pairs(scn, p0, p1) {
            // Vertices open at the start and closing at the end: (owner,
            // index); failing those, vertices open at both ends whose path
            // relative to the other body passes within g_i of it (a transit
            // inside the step), with the middle of that passage.
            let mut cand: Vec<(usize, usize)> = Vec::new();
            let mut transits: Vec<((usize, usize), f64)> = Vec::new();
            // A vertex travels at most `reach` relative to the other body
            // over the step (the largest point speeds at the ends, which
            // bound them between under constant forces, with a margin): it
            // can pass within g_i of it only if d0 + d1 ≤ reach + 2 g_i.
            let speed = |b: usize| match scn.body(b) {
                Body::Floe(f) => {
                    let r = scn.floes[f].radius;
                    let at = |s: &BodyState| s.velocity.norm() + s.angular_velocity.abs() * r;
                    at(&sys.bodies[f]).max(at(&end.bodies[f]))
                }
                Body::Obstacle(_) => 0.0,
            };
            let reach = TRANSIT_MARGIN * (speed(i) + speed(j)) * h + 2.0 * target;
            for (owner, other) in [(i, j), (j, i)] {
                let mut motion = None;
                let local: &[Vec2] = match scn.body(other) {
                    Body::Floe(o) => &scn.floes[o].shape,
                    Body::Obstacle(_) => &p0[other],
                };
                let part_polys = part_polygons(local, body_parts(scn, other));
                for (k, (v0, v1)) in p0[owner].iter().zip(&p1[owner]).enumerate() {
                    let d0 = body_distance(scn, other, v0, &p0[other]);
                    if d0 <= delta {
                        continue;
                    }
                    let d1 = body_distance(scn, other, v1, &p1[other]);
                    if d1 < target {
                        cand.push((owner, k));
                        continue;
                    }
                    if d0 + d1 > reach {
                        continue;
                    }
                    let motion = motion
                        .get_or_insert_with(|| relative_motion(scn, sys, end, h, owner, other));
                    let x = match scn.body(owner) {
                        Body::Floe(f) => scn.floes[f].shape[k],
                        Body::Obstacle(_) => *v0,
                    };
                    if let Some(mid) = transit(motion, &x, local, &part_polys, target) {
                        transits.push(((owner, k), mid * h));
                    }
                }
            }
            let hi_limit = first.map_or(h, |f| f.0).min(h);
            let probes: Vec<f64> = if cand.is_empty() {
                cand = transits.iter().map(|t| t.0).collect();
                let mut p: Vec<f64> = transits
                    .iter()
                    .map(|t| t.1)
                    .filter(|&s| s < hi_limit)
                    .collect();
                p.sort_by(f64::total_cmp);
                p
            } else {
                vec![hi_limit]
            };
            if probes.is_empty() {
                continue;
            }
            // φ(s) = min over candidates of d(s) − g_i.
            let phi = |s: f64, me: &mut Self| -> Result<f64, FormulationError> {
                let mut poly = |idx: usize| -> Result<Vec<Vec2>, FormulationError> {
                    if let Body::Obstacle(_) = scn.body(idx) {
                        return Ok(p0[idx].clone());
                    }
                    let mut b = sys.bodies[idx];
                    let mut scratch = Ledger::default();
                    me.integ.advance_with(
                        scn,
                        idx,
                        &mut b,
                        &mut scratch,
                        sys.t,
                        sys.t + s,
                        &wrenches[idx],
                    )?;
                    let mut p = Vec::new();
                    scn.floes[idx].world_polygon(&b.position, b.angle, &mut p);
                    Ok(p)
                };
                let (pi, pj) = (poly(i)?, poly(j)?);
                let mut m = f64::INFINITY;
                for &(owner, k) in &cand {
                    let (own, oth, other) = if owner == i {
                        (&pi, &pj, j)
                    } else {
                        (&pj, &pi, i)
                    };
                    m = m.min(body_distance(scn, other, &own[k], oth));
                }
                Ok(m - target)
            };
            // Only search below the earliest event found so far, up to the
            // first probe where a candidate is closed.
            let mut closed_at = None;
            for &probe in &probes {
                let f = phi(probe, self)?;
                if f <= 0.0 {
                    closed_at = Some((probe, f));
                    break;
                }
            }
            let Some((hi_start, f_start)) = closed_at else {
                continue; // this pair closes after an earlier event, or not at all
            };
            let (mut lo, mut hi) = (0.0, hi_start);
            let mut f_hi = f_start;
            let mut f_lo = phi(lo, self)?;
            let mut side = 0i8;
            let mut s = hi;
            for _ in 0..200 {
                self.counters.add(&ROOT_ITERATIONS, 1);
                s = if f_lo - f_hi != 0.0 {
                    (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
                } else {
                    0.5 * (lo + hi)
                };
                if !(s > lo && s < hi) {
                    s = 0.5 * (lo + hi);
                }
                let f = phi(s, self)?;
                if f.abs() <= ROOT_TOLERANCE * delta {
                    break;
                }
                if f > 0.0 {
                    lo = s;
                    f_lo = f;
                    if side == 1 {
                        f_hi *= 0.5;
                    }
                    side = 1;
                } else {
                    hi = s;
                    f_hi = f;
                    if side == -1 {
                        f_lo *= 0.5;
                    }
                    side = -1;
                }
                if hi - lo <= 1e-15 * (sys.t + h).abs().max(1e-300) {
                    s = hi;
                    break;
                }
            }
            if first.is_none_or(|f| s < f.0) {
                first = Some((s, (i, j)));
            }
        }
        Ok(first)
    }
}

impl EventDriven {
    /// One step of the scheme's own grid from `sys` (impacts at its start,
    /// then the smooth step with sustained contacts, cut at the first event),
    /// never past `end` (s, the end of the run); keeps its record in
    /// [`EventDriven::last`] for the states reported inside it.
    fn step(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        end: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        // A safe point: fractures decided by the stress criterion at the
        // end of the last step; this instant starts again with the new floe
        // set.
        if let Some(old) = cx.change_floes(scn, sys) {
            return self.floes_changed(scn, sys, &old);
        }
        self.step_loads.clear();
        let n = scn.floes.len();
        let t = sys.t;
        // Flights that have returned are over.
        self.flights
            .retain(|f| f.until - t > 1e-12 * f.until.abs().max(1.0));
        // 1. Closed contacts at this instant.
        let contacts = cx
            .clock
            .time(Stage::Detection, || self.detect(scn, &sys.bodies));
        // A flight whose pair is no longer closed, or is back at its
        // starting gap, is over.
        self.flights.retain(|f| {
            let gap = contacts
                .iter()
                .filter(|c| pair_of(c) == f.pair)
                .map(|c| c.geom.gap)
                .fold(f64::INFINITY, f64::min);
            gap.is_finite() && gap > f.gap
        });
        // 2. Impacts.
        let mut rounds = 0;
        let mut any = false;
        loop {
            let topology = &mut *cx.topology;
            let hit = cx.clock.time(Stage::Solve, || {
                self.impacts_at(scn, sys, &contacts, None, topology)
            });
            if !hit {
                break;
            }
            any = true;
            rounds += 1;
            if cx.topology.pending() {
                break;
            }
            if rounds >= MAX_IMPACT_ROUNDS {
                self.counters.add(&IMPACT_ROUNDS_CAPPED, 1);
                break;
            }
        }
        if any {
            self.counters.add(&IMPACT_INSTANTS, 1);
        }
        // A safe point: fractures at this instant (docs/physics.md §9.5);
        // the floes break after the impact that broke them, and the instant
        // starts again with the new floe set (its contacts detected anew).
        if let Some(old) = cx.change_floes(scn, sys) {
            return self.floes_changed(scn, sys, &old);
        }
        // 3. Trial step with sustained contact forces, bounded by the
        // scheme alone (never by the output times).
        let hints = self.integ.hints().to_vec();
        let mut bound = self.integ.step_bound(scn, sys, end);
        if !contacts.is_empty() {
            bound = bound.min(self.horizon);
        }
        // A closed contact still approaching, slower than the impact
        // threshold, is stopped by the sustained force over the step and
        // closes |u| h / 2: beyond a tenth of the tolerance, it is stopped at
        // once instead.
        let topology = &mut *cx.topology;
        cx.clock.time(Stage::Solve, || {
            self.impacts_at(scn, sys, &contacts, Some(bound), topology)
        });
        let to_end = bound >= end - t;
        let mut h = bound;
        let p0 = world_polygons(scn, &sys.bodies);
        let mut rejections = 0;
        let mut cuts = 0;
        // Stick adjustments of this step (estimate, then linear correction),
        // allowed while no other cut has shortened it.
        let mut stick_moves = 0;
        // The shortest length at which a pair was found to stick: a
        // correction never lengthens the step back to it (it would find
        // the same stick and cut again: a cycle of re-solves).
        let mut stuck_at = f64::INFINITY;
        let mut other_cut = false;
        loop {
            let sustained = self.sustained_wrenches(scn, sys, &contacts, h, bound, cx)?;
            if let Some((shorter, why)) = sustained.cut {
                if shorter < (1.0 - MIN_CUT_FRACTION) * h && cuts < MAX_CUTS {
                    self.counters.add(why.counter(), 1);
                    cuts += 1;
                    other_cut = true;
                    h = shorter;
                    continue;
                }
            }
            if !other_cut && rejections == 0 && stick_moves < MAX_STICK_MOVES {
                let moved = match (sustained.stick, sustained.slide_stop) {
                    (Some(s), _) if s < (1.0 - MIN_CUT_FRACTION) * h => {
                        stuck_at = stuck_at.min(h);
                        Some(s)
                    }
                    (None, Some(s))
                        if stick_moves > 0
                            && s > (1.0 + MIN_CUT_FRACTION) * h
                            && s.min(bound) < (1.0 - MIN_CUT_FRACTION) * stuck_at =>
                    {
                        Some(s.min(bound))
                    }
                    _ => None,
                };
                if let Some(s) = moved {
                    self.counters.add(&STEPS_CUT_FOR_STICK, 1);
                    stick_moves += 1;
                    h = s;
                    continue;
                }
            }
            let wrenches = sustained.wrenches;
            let mut trial = cx.clock.time(Stage::Integration, || {
                self.integrate(scn, sys, h, &wrenches)
            })?;
            if to_end && h == bound {
                trial.t = end;
            }
            let p1 = world_polygons(scn, &trial.bodies);
            // 4. Event location.
            let event = {
                let t0 = cx.clock.start(Stage::Detection);
                let r = self.locate(scn, sys, &trial, h, &wrenches, &p0, &p1);
                cx.clock.stop(Stage::Detection, t0);
                r?
            };
            let located = matches!(event, Some((s, _)) if s < h);
            let next = match event {
                Some((s, (i, j))) if s < h => {
                    self.counters.add(&EVENTS_LOCATED, 1);
                    let pair = (i.min(j), i.max(j));
                    if contacts.iter().any(|c| pair_of(c) == pair) {
                        // The pair was already closed at the step start:
                        // another vertex of a sustained contact closes.
                        self.counters.add(&EVENTS_OF_PAIRS_IN_CONTACT, 1);
                    }
                    cx.clock.time(Stage::Integration, || {
                        self.integrate(scn, sys, s, &wrenches)
                    })?
                }
                _ => trial,
            };
            // 5. Penetration check.
            let p_next = if located {
                world_polygons(scn, &next.bodies)
            } else {
                p1
            };
            // The depth of a pair is its minimum translation distance
            // ([`signed_distance`], the measure of the contact detection and
            // of `floebench check`), not its deepest vertex: two pieces of a
            // split whose cut edges cross, scissored, overlap with no vertex
            // inside the other (docs/physics.md §4.3, step 5).
            let depths: Vec<((usize, usize), f64)> = cx.clock.time(Stage::Detection, || {
                self.swept_pairs(scn, &p_next, &p_next)
                    .iter()
                    .map(|&(i, j)| {
                        let d = Self::pair_signed_distance(scn, i, j, &p_next[i], &p_next[j]);
                        ((i, j), -d)
                    })
                    .collect()
            });
            let depth = depths.iter().map(|d| d.1).fold(0.0, f64::max);
            // A flight whose pair penetrates was misjudged: over.
            let before = self.flights.len();
            self.flights.retain(|f| {
                !depths
                    .iter()
                    .any(|&(p, d)| (p.0.min(p.1), p.0.max(p.1)) == f.pair && d > 0.0)
            });
            if self.flights.len() < before && rejections < MAX_REJECTIONS {
                rejections += 1;
                self.counters.add(&STEPS_REJECTED_PENETRATION, 1);
                continue;
            }
            if depth > self.pen_tol && rejections < MAX_REJECTIONS {
                rejections += 1;
                self.counters.add(&STEPS_REJECTED_PENETRATION, 1);
                h *= 0.5;
                continue;
            }
            if depth > self.pen_tol {
                self.counters.add(&PENETRATIONS_BEYOND_TOLERANCE, 1);
            }
            self.max_penetration = self.max_penetration.max(depth);
            self.counters
                .add(&FLIGHTS_WITHIN_DISTANCE, sustained.flights.len() as u64);
            self.flights.extend(sustained.flights);
            if cx.topology.reads().sustained {
                // The stress criterion reads the impulses delivered over the
                // step [t, next.t]: the sustained wrenches (impulses over h)
                // for the part of h taken, and the slow approaches stopped
                // (docs/physics.md §9.3, §9.5); the floes break at the next
                // step's start, on the lines chosen here, carried with them.
                let taken = ((next.t - t) / h).clamp(0.0, 1.0);
                let mut loads = std::mem::take(&mut self.step_loads);
                loads.extend(sustained.loads.iter().map(|l| Load {
                    impulse: l.impulse * taken,
                    ..*l
                }));
                cx.topology.sustained(scn, sys, &loads, t, next.t);
            }
            self.last = Some(StepRecord {
                start: std::mem::replace(sys, next),
                wrenches,
                hints,
            });
            self.counters.add(&STEPS, 1);
            break;
        }
        if sys.bodies.len() != n {
            return Err(FormulationError::Other("state size changed".into()));
        }
        Ok(())
    }
}

impl Formulation for EventDriven {
    fn advance(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        t_end: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        let (mut cur, fresh) = self.own.resume(sys);
        if fresh {
            self.last = None;
            self.flights.clear();
        }
        let end = scn.duration.max(t_end);
        while cur.t < t_end {
            cx.poll_interrupt(cur.t)?;
            self.step(scn, &mut cur, end, cx)?;
        }
        let out = cx.clock.time(Stage::Integration, || {
            reported_state(&mut self.integ, scn, &cur, self.last.as_ref(), t_end)
        })?;
        self.own.keep(cur);
        self.own.report(sys, out, t_end);
        Ok(())
    }

    fn floes_changed(
        &mut self,
        scn: &Scenario,
        _: &System,
        _: &[usize],
    ) -> Result<(), FormulationError> {
        self.integ.floes_changed(scn);
        // Flights name pairs by body ids, which the new floes shift.
        self.flights.clear();
        self.last = None;
        Ok(())
    }

    fn counters(&self) -> Counters {
        let mut c = self.counters.clone();
        self.integ.stats.report(&mut c);
        c.absorb(&self.solver.counters());
        c.set(&MAX_PENETRATION, self.max_penetration);
        c
    }

    fn settings(&self) -> Settings {
        self.solver.settings(
            Settings::default()
                .number(
                    "impact_speed_threshold_m_per_s",
                    self.impact_speed,
                    Unit::MetrePerSecond,
                )
                .number("contact_distance_m", self.distance, Unit::Metre)
                .number("penetration_tolerance_m", self.pen_tol, Unit::Metre),
        )
    }

    fn solve_profile(&self) -> Option<SolveProfile> {
        Some(self.solver.direct.profile())
    }

    fn take_contact_log(&mut self) -> ContactLog {
        self.solver.direct.take_log()
    }
}
