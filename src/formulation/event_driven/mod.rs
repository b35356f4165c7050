//! The event-driven LCP formulation of M. Rabatel (2015), with our own Lemke.
//!
//! **Scheme** (described once, in docs/physics.md §4; the contact problem
//! in §3): advance the smooth dynamics to the next impact, resolve it, go
//! on. From a state at `t`: detect the contacts closer than the contact
//! distance `δ` (§3, §4.3 step 1); resolve every group with an approaching
//! contact by the compression LCP and Poisson's law in Rabatel's
//! energy-consistent form (§3.1, §3.2, §4.3 step 2; `impact.rs`); take a
//! smooth step of the shared integrator (§4.1, §4.2) with the sustained
//! contacts' constant force from the velocity–impulse LCP, the
//! accumulations, flights within `δ` and sticking instants in closed form
//! (§4.3 step 3; `sustained.rs`, `step.rs`); locate the first impact inside
//! the step by root finding on the gaps and cut the step there (§4.3 step
//! 4; `location.rs`); reject a step that penetrates deeper than the
//! tolerance (§4.3 step 5). Parameters and their reasons: §4.4 and
//! `settings.rs`; departures from the origin report: §4.5. Every contact
//! problem goes through the shared [`ContactSolver`] (Lemke with its
//! counted fallbacks, §3.3, or the iterative solvers of §3.5); fractures
//! through the run's topology stage (§9.5).
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

mod impact;
mod location;
mod settings;
mod step;
mod sustained;

pub use location::contact_horizon;
use location::*;
pub use settings::*;

use super::contact_solver::{
    ContactSolver, SolverKind, DEFAULT_MERGE_FRICTION, DEFAULT_PREDICT_FROM, DEFAULT_WARM_LEMKE,
    DEFAULT_WARM_START,
};
use super::group_solver::{read_solver, GroupData, GroupSolver};
use super::{
    reported_state, Context, Entry, Formulation, FormulationError, FormulationOptions, ImpactQuery,
    NotClaimed, OwnState,
};
use crate::contact::problem::{groups, Gen};
use crate::contact::{
    loads_of, signed_distance, Aabb, BroadPhase, Contact, Load, CLIPPED_EDGE_PAIRS,
};
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
    check: None,
    settings: Some(TABLE),
    resolves_contacts: true,
    dumps_lcps: true,
    supports_fracture: true,
    lattice_impacts: true,
    supports_crushing: true,
    not_claimed: &[
        NotClaimed {
            check: "cradle_physical",
            case: None,
            reason: "a simultaneous impact law on touching floes gives the LCP answer ((2-n)/n, 2/n, ...) v0, not the sequential one (docs/physics.md §6); cradle_outcome checks the LCP answer",
        },
    ],
};

/// Why a trial step is cut short (the stick rule adjusts it apart).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cut {
    /// At the apex of a flight that leaves the contact distance.
    Apex,
    /// At the return of a flight within the contact distance.
    Return,
    /// At the accumulation time of a contact.
    Accumulation,
    /// Where a crushing phase ends: the pair stops approaching
    /// (docs/physics.md §10.2).
    CrushStop,
}

impl Cut {
    fn counter(self) -> &'static Counter {
        match self {
            Cut::Apex => &STEPS_CUT_FOR_FLIGHT,
            Cut::Return => &STEPS_CUT_AT_RETURN,
            Cut::Accumulation => &STEPS_CUT_AT_ACCUMULATION,
            Cut::CrushStop => &STEPS_CUT_AT_CRUSH_STOP,
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
    /// The body pairs at their crushing bound over the trial step, and the
    /// work of their forces over it, J (none without crushing).
    crushing: (Vec<(usize, usize)>, f64),
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
            // Every facing edge pair clipped: each end within δ is a closed
            // contact of the sustained problem.
            &CLIPPED_EDGE_PAIRS,
            &mut self.bp,
            &mut out,
        );
        out
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
