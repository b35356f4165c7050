//! The Moreau–Jean time-stepping formulation (Moreau 1988; Jean 1999;
//! Acary & Brogliato 2008, ch. 10), with one-step contact solvers: the
//! Stewart–Trinkle LCP by our Lemke (`moreau`), the Anitescu–Tasora
//! convex cone relaxation by clarabel (`moreau-cone`), and the iterative
//! NSGS and APGD.
//!
//! **Scheme** (described once, in docs/physics.md §5): fixed steps `h` on
//! the grid `t_k = k h`, impacts not located in time. Per step: the smooth
//! impulse by the θ-method with one predictor pass (§5.1 step 1, the shared
//! [`ForceModel::forces`]); the contacts whose predicted gap
//! `g + h γ u_N` is closed are active (§5.1 step 2); one frictional
//! contact problem per connected group with Newton's impact law on every
//! active contact, `u_N⁺ + e u_N⁻ ≥ 0 ⟂ λ ≥ 0` (§5.1 step 3; the LCP
//! assembly of §3.1, [`crate::contact::problem::ContactLcp::assemble`]), solved by the solver of
//! §5.2 through the shared [`ContactSolver`] (Lemke with its counted
//! fallbacks, §3.3; the cone, §3.4; NSGS or APGD, §3.5); positions by the
//! θ-method, not projected (§5.1 step 4), unless `projection = true`
//! (§5.1 step 5, [`projection`]: Acary's direct projection of the
//! positions onto the contacts' depth `projection_depth`). The energy ledger: §5.3; the
//! parameters and their reasons: §5.4 and `settings.rs`. The steps are
//! taken by the shared fixed-step loop ([`super::advance_on_grid`]);
//! fractures through the run's topology stage (§9.5).
//!
//! # References
//!
//! - J. J. Moreau (1988), *Unilateral contact and dry friction in finite
//!   freedom dynamics*, CISM Courses 302, 1–82.
//! - M. Jean (1999), *The non-smooth contact dynamics method*, CMAME 177,
//!   235–257.
//! - V. Acary, B. Brogliato (2008), *Numerical Methods for Nonsmooth
//!   Dynamical Systems*, Springer, ch. 10 (the Moreau–Jean scheme, index sets
//!   with the predicted gap `g + hγ u_N`).
//! - V. Acary (2012), *Projected event-capturing time-stepping schemes for
//!   nonsmooth mechanical systems with unilateral contact and Coulomb's
//!   friction*, CMAME 256, 224–250 (the projection of the positions).
//! - D. Stewart, J. Trinkle (1996), IJNME 39 (the LCP of docs/physics.md §3.1).
//! - M. Anitescu (2006), Math. Program. 105; A. Tasora, M. Anitescu (2011),
//!   CMAME 200 (the convex cone relaxation and its separation artefact).

mod contacts;
mod lattice;
mod projection;
mod settings;

pub use settings::*;

use super::contact_solver::{
    ContactSolver, SolverKind, DEFAULT_MERGE_FRICTION, DEFAULT_PREDICT_FROM, DEFAULT_WARM_LEMKE,
    DEFAULT_WARM_START,
};
use super::group_solver::{read_solver, GroupAnswer, GroupData, GroupSolver};
use super::{
    advance_on_grid, check_output_grid, Context, Entry, FixedGrid, FixedStep, Formulation,
    FormulationError, FormulationOptions, NotClaimed,
};
use crate::contact::problem::{groups, ContactGroup, Gen};
use crate::contact::{loads_of, BroadPhase, Contact};
use crate::contact::{ContactKey, CLIPPED_EDGE_PAIRS};
use crate::geometry::Vec2;
use crate::iterative::{IterativeOptions, MAX_ITERATIONS, RELAXATION, TOLERANCE};
use crate::model::limits::{Limit, STEP};
use crate::model::{CaseError, Scenario, SettingsTable, TableSpec};
use crate::physics::ForceModel;
use crate::record::counters::common::{FORCE_EVALUATIONS, MAX_PENETRATION, STEPS};
use crate::record::{
    ContactEvent, ContactLog, Counter, Counters, Settings, SolveProfile, Stage, Unit,
};
use crate::state::{detect_contacts, detect_contacts_with, normal_velocity, BodyState, System};
use std::collections::HashSet;

/// Claims shared by both solvers.
const NOT_CLAIMED_BOTH: [NotClaimed; 2] = [
    NotClaimed {
        check: "bouncing_rest",
        case: None,
        reason: "impacts are not located in time: the rebounds shorter than a step are lumped into the step's impulse, so the floe comes to rest on the step grid, not at the accumulation time",
    },
    NotClaimed {
        check: "cradle_physical",
        case: None,
        reason: "one contact problem per step: touching floes get the simultaneous LCP answer (cradle_outcome checks it)",
    },
];

/// The registry entry `moreau`: the solver of the case
/// (`[formulation.moreau] solver`, default Lemke).
pub const ENTRY: Entry = Entry {
    name: "moreau",
    description: "Moreau-Jean time stepping: fixed step, theta-method, Newton impact law, one contact problem per step and group; solver from the case ([formulation.moreau] solver, default lcp: Lemke)",
    build: |scn, opts| Ok(Box::new(Moreau::new(scn, opts, None)?)),
    check: Some(check),
    settings: Some(TABLE),
    resolves_contacts: true,
    dumps_lcps: true,
    supports_fracture: true,
    lattice_impacts: true,
    supports_crushing: true,
    not_claimed: &[
        NotClaimed {
            check: "penetration",
            case: None,
            reason: "a contact activated by the predicted gap ends its step penetrated by O(h u_N) (by default positions are not projected; with projection = true, by up to projection_depth after each step)",
        },
        NOT_CLAIMED_BOTH[0],
        NOT_CLAIMED_BOTH[1],
    ],
};

/// The registry entry `moreau-cone`: always the cone relaxation.
pub const CONE_ENTRY: Entry = Entry {
    name: "moreau-cone",
    description: "Moreau-Jean time stepping with the Anitescu-Tasora convex cone relaxation solved by clarabel (sliding contacts separate at mu |u_T|)",
    build: |scn, opts| Ok(Box::new(Moreau::new(scn, opts, Some(SolverKind::Cone))?)),
    check: Some(check),
    settings: Some(TABLE),
    resolves_contacts: true,
    dumps_lcps: false,
    supports_fracture: true,
    lattice_impacts: true,
    supports_crushing: true,
    not_claimed: &[
        NotClaimed {
            check: "penetration",
            case: None,
            reason: "penetration O(h u_N) as moreau (by default positions are not projected; with projection = true, by up to projection_depth after each step); the cone relaxation also lifts a sliding floe off and lands it again (sliding_floe)",
        },
        NOT_CLAIMED_BOTH[0],
        NOT_CLAIMED_BOTH[1],
    ],
};

/// A step in which contact impulses were applied, for analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactStep {
    /// Start of the step, s.
    pub t: f64,
    /// Step length, s.
    pub h: f64,
    /// Active contacts.
    pub contacts: usize,
    /// Active contacts that approached at the start (`u_N⁻ < 0`).
    pub approaching: usize,
    /// Kinetic energy of the floes in contact before (at `W_free`) and
    /// after the contact impulses, J.
    pub energy: (f64, f64),
}

/// The Moreau–Jean formulation.
#[derive(Debug)]
pub struct Moreau {
    step: f64,
    theta: f64,
    gamma: f64,
    model: ForceModel,
    bp: BroadPhase,
    solver: GroupSolver,
    counters: Counters,
    records: Vec<ContactStep>,
    max_penetration: f64,
    /// Rounding allowance of the activation test, m (see [`ACTIVATION_TOLERANCE_FRACTION`]).
    activation_tolerance: f64,
    /// The distance within which a clipped end of a facing edge pair is a
    /// contact point, m: the contact distance `δ`
    /// ([`crate::formulation::contact_distance`]).
    flush_distance: f64,
    /// What becomes of a contact whose predicted gap is open (§5.1 step 2).
    open_contacts: OpenContacts,
    /// The state on the step grid `t_k = k h`.
    grid: FixedGrid,
    /// The pairs of bodies of the last step's active contacts, sorted (kept
    /// only when the topology stage resolves impacts, [`lattice`]).
    active_pairs: Vec<(usize, usize)>,
    /// The body pairs whose contacts reached their crushing bound in the
    /// step, for the crush stage (docs/physics.md §10).
    crushing_pairs: Vec<(usize, usize)>,
    /// The projection's depth, m (`None`: positions not projected,
    /// [`projection`]).
    projection: Option<f64>,
}

/// What `moreau` and `moreau-cone` refuse in a case ([`Entry::check`]):
/// output times off the grid of the step of `[formulation.moreau]`.
fn check(scn: &Scenario) -> Result<(), CaseError> {
    let s = MoreauSettings::of(scn)?;
    check_output_grid(
        scn,
        "moreau",
        &scn.settings_table(TABLE.name),
        "step",
        s.step,
    )
}

impl Moreau {
    /// Sets up the formulation for `scn` with the case's
    /// `[formulation.moreau]` settings, the solver overridden by `solver`
    /// when given.
    pub fn new(
        scn: &Scenario,
        opts: &FormulationOptions,
        solver: Option<SolverKind>,
    ) -> Result<Moreau, String> {
        faer::set_global_parallelism(faer::Par::Seq);
        check(scn).map_err(|e| e.to_string())?;
        let s = MoreauSettings::of(scn).map_err(|e| e.to_string())?;
        let rmin = scn.min_floe_radius();
        let activation_tolerance = if rmin.is_finite() {
            ACTIVATION_TOLERANCE_FRACTION * rmin
        } else {
            0.0
        };
        Ok(Moreau {
            step: s.step,
            theta: s.theta,
            gamma: s.gamma,
            model: ForceModel::new(&scn.floes),
            bp: BroadPhase::new(),
            solver: GroupSolver::new(
                ContactSolver::with_warm_start(
                    solver.unwrap_or(s.solver),
                    opts.dump_lcp.clone(),
                    s.warm_start,
                )
                .with_warm_lemke(s.warm_lemke)
                .with_merge_friction(s.merge_friction)
                .with_predict_from(s.predict_from)
                .with_warm_check(opts.warm_check),
                match solver {
                    Some(SolverKind::Cone) => None,
                    _ => s.iterative,
                },
            )
            .with_energy_guard(),
            counters: {
                let mut c = Counters::new(COUNTERS);
                if s.projection {
                    c.absorb(&Counters::new(PROJECTION_COUNTERS));
                }
                if s.open_contacts == OpenContacts::Gap {
                    c.absorb(&Counters::new(OPEN_CONTACT_COUNTERS));
                }
                c
            },
            records: Vec::new(),
            max_penetration: 0.0,
            activation_tolerance,
            flush_distance: crate::formulation::contact_distance(scn),
            open_contacts: s.open_contacts,
            grid: FixedGrid::new(s.step),
            active_pairs: Vec::new(),
            crushing_pairs: Vec::new(),
            projection: s.projection_depth(scn),
        })
    }

    /// The one-step solver in use.
    pub fn solver(&self) -> SolverKind {
        self.solver.direct.kind()
    }

    /// The steps in which contact impulses were applied (the first
    /// 100,000).
    pub fn contact_steps(&self) -> &[ContactStep] {
        &self.records
    }

    /// Largest penetration seen at the start of a step, m.
    pub fn max_penetration(&self) -> f64 {
        self.max_penetration
    }

    /// Largest `|β| / (μ λ)` over every contact impulse so far.
    pub fn max_coulomb_ratio(&self) -> f64 {
        self.solver.direct.max_coulomb_ratio()
    }

    /// One step of length `h` from `sys` (see the module doc).
    fn step_once(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        h: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        let n = scn.floes.len();
        let t0 = sys.t;
        let th = self.theta;
        // 1. Smooth impulse by the θ-method with one predictor pass.
        let w_free: Vec<Gen> = cx.clock.time(Stage::Integration, || {
            let mut w_free = Vec::with_capacity(n);
            let mut evals = 0u64;
            for (i, b) in sys.bodies.iter().enumerate() {
                let f0 = self.model.forces(&scn.environment, i, t0, b);
                evals += 1;
                let a0 = self.model.acceleration(i, &f0);
                let p0 = f0.powers(b);
                let (a_th, p1) = if th > 0.0 {
                    let v = b.velocity + Vec2::new(a0[0], a0[1]) * h;
                    let om = b.angular_velocity + a0[2] * h;
                    let pred = BodyState {
                        position: b.position + (b.velocity * (1.0 - th) + v * th) * h,
                        angle: b.angle + h * ((1.0 - th) * b.angular_velocity + th * om),
                        velocity: v,
                        angular_velocity: om,
                    };
                    let f1 = self.model.forces(&scn.environment, i, t0 + h, &pred);
                    evals += 1;
                    let a1 = self.model.acceleration(i, &f1);
                    (
                        [
                            (1.0 - th) * a0[0] + th * a1[0],
                            (1.0 - th) * a0[1] + th * a1[1],
                            (1.0 - th) * a0[2] + th * a1[2],
                        ],
                        f1.powers(&pred),
                    )
                } else {
                    (a0, (0.0, 0.0, 0.0))
                };
                let l = &mut sys.ledger;
                l.work_air += h * ((1.0 - th) * p0.0 + th * p1.0);
                l.work_water += h * ((1.0 - th) * p0.1 + th * p1.1);
                l.work_coriolis += h * ((1.0 - th) * p0.2 + th * p1.2);
                w_free.push([
                    b.velocity.x + h * a_th[0],
                    b.velocity.y + h * a_th[1],
                    b.angular_velocity + h * a_th[2],
                ]);
            }
            self.counters.add(&FORCE_EVALUATIONS, evals);
            w_free
        });
        // 2. Detection and active contacts.
        let active = cx
            .clock
            .time(Stage::Detection, || self.active_contacts(scn, sys, h));
        // 3. Contact problems.
        let w_new = if active.is_empty() {
            self.active_pairs.clear();
            w_free.clone()
        } else {
            let solve = cx.clock.start(Stage::Solve);
            let w_new = self.solve_contacts(scn, sys, h, &active, &w_free, cx);
            cx.clock.stop(Stage::Solve, solve);
            w_new
        };
        // 4. Positions by the θ-method.
        cx.clock.time(Stage::Integration, || {
            for (b, w) in sys.bodies.iter_mut().zip(&w_new) {
                let v1 = Vec2::new(w[0], w[1]);
                b.position += (b.velocity * (1.0 - th) + v1 * th) * h;
                b.angle += h * ((1.0 - th) * b.angular_velocity + th * w[2]);
                b.velocity = v1;
                b.angular_velocity = w[2];
            }
        });
        // 5. The projection of the positions, when asked ([`projection`]).
        if let Some(depth) = self.projection {
            let solve = cx.clock.start(Stage::Solve);
            self.project(scn, sys, depth);
            cx.clock.stop(Stage::Solve, solve);
        }
        self.counters.add(&STEPS, 1);
        if let Some(i) = sys.bodies.iter().position(|b| !b.is_finite()) {
            return Err(FormulationError::Other(format!(
                "floe {i}: non-finite state after the step from t = {t0} s"
            )));
        }
        Ok(())
    }
}

impl FixedStep for Moreau {
    fn grid(&mut self) -> &mut FixedGrid {
        &mut self.grid
    }

    fn fixed_step(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        self.step_once(scn, sys, self.step, cx)
    }
}

impl Formulation for Moreau {
    fn advance(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        t_end: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        // Steps of h on the grid t_k = k h (module doc).
        advance_on_grid(self, scn, sys, t_end, cx)
    }

    fn floes_changed(
        &mut self,
        scn: &Scenario,
        _: &System,
        _: &[usize],
    ) -> Result<(), FormulationError> {
        self.model = ForceModel::new(&scn.floes);
        self.active_pairs.clear();
        Ok(())
    }

    fn counters(&self) -> Counters {
        let mut c = self.counters.clone();
        c.absorb(&self.solver.counters());
        c.set(&MAX_PENETRATION, self.max_penetration);
        c
    }

    fn settings(&self) -> Settings {
        let s = Settings::default()
            .number(
                "activation_tolerance_m",
                self.activation_tolerance,
                Unit::Metre,
            )
            .number("step_s", self.step, Unit::Second)
            .number("theta", self.theta, Unit::Dimensionless)
            .number("gamma", self.gamma, Unit::Dimensionless)
            .text("open_contacts", self.open_contacts.name());
        self.solver.settings(match self.projection {
            Some(depth) => s.number("projection_depth_m", depth, Unit::Metre),
            None => s,
        })
    }

    fn solve_profile(&self) -> Option<SolveProfile> {
        Some(self.solver.direct.profile())
    }

    fn take_contact_log(&mut self) -> ContactLog {
        self.solver.direct.take_log()
    }
}
