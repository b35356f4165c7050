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
use crate::contact::problem::{groups, Gen};
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
    settings: Some(TABLE),
    resolves_contacts: true,
    dumps_lcps: true,
    supports_fracture: true,
    lattice_impacts: true,
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
    settings: Some(TABLE),
    resolves_contacts: true,
    dumps_lcps: false,
    supports_fracture: true,
    lattice_impacts: true,
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
    /// The projection's depth, m (`None`: positions not projected,
    /// [`projection`]).
    projection: Option<f64>,
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
        let s = MoreauSettings::of(scn).map_err(|e| e.to_string())?;
        let name = match solver {
            Some(SolverKind::Cone) => CONE_ENTRY.name,
            _ => ENTRY.name,
        };
        check_output_grid(scn, name, "[formulation.moreau] step", s.step)?;
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

    /// Whether a contact of gap `gap` (m) and normal velocity `u` (m/s) at
    /// the start of a step of `h` is closed: its predicted gap
    /// `g + h γ u_N` within the rounding allowance `ε`.
    fn closed(&self, gap: f64, u: f64, h: f64) -> bool {
        gap + h * self.gamma * u <= self.activation_tolerance
    }

    /// Contacts at `q_k` whose predicted gap `g + h γ u_N` is closed (and,
    /// with `open_contacts = "gap"`, the open ones within the detection
    /// margin too); updates the penetration record from the gaps. A facing edge pair gives the
    /// narrow phase's points within the step's reach, plus each clipped end
    /// of the pair within the contact distance `δ` (the second corner of a
    /// nearly flush pair; docs/physics.md §5.1 step 2).
    fn active_contacts(&mut self, scn: &Scenario, sys: &System, h: f64) -> Vec<Contact> {
        let margin = 2.0 * h * self.gamma * sys.max_point_speed(scn);
        let mut contacts = Vec::new();
        detect_contacts(scn, &sys.bodies, margin, &mut self.bp, &mut contacts);
        let mut flush = Vec::new();
        detect_contacts_with(
            scn,
            &sys.bodies,
            self.flush_distance,
            &CLIPPED_EDGE_PAIRS,
            &mut self.bp,
            &mut flush,
        );
        let known: HashSet<ContactKey> = contacts.iter().map(Contact::key).collect();
        contacts.extend(flush.into_iter().filter(|c| !known.contains(&c.key())));
        for c in &contacts {
            self.max_penetration = self.max_penetration.max(-c.geom.gap);
        }
        if self.open_contacts == OpenContacts::Inactive {
            contacts.retain(|c| self.closed(c.geom.gap, normal_velocity(scn, &sys.bodies, c), h));
        }
        contacts
    }

    /// Solves the contact problem of every group of `active` and writes the
    /// new velocities (`w_free` where no contact acts); books the
    /// dissipation and reports the impulses to the topology stage.
    fn solve_contacts(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        h: f64,
        active: &[Contact],
        w_free: &[Gen],
        cx: &mut Context<'_>,
    ) -> Vec<Gen> {
        let mut w_new = w_free.to_vec();
        let n = scn.floes.len();
        let e = scn.contact.restitution;
        let u_minus: Vec<f64> = active
            .iter()
            .map(|c| normal_velocity(scn, &sys.bodies, c))
            .collect();
        // Newton's law on every closed contact (module doc); the
        // linearised gap on the open ones (`open_contacts = "gap"`: the
        // positions' θ-method keeps `g + h ((1 − θ) u⁻ + θ u⁺) ≥ 0`), never
        // slower than the pair's own approach `−u⁻` (its impact is Newton's,
        // at the step that closes it).
        let closed: Vec<bool> = active
            .iter()
            .zip(&u_minus)
            .map(|(c, &u)| self.closed(c.geom.gap, u, h))
            .collect();
        let offsets: Vec<f64> = active
            .iter()
            .zip(&u_minus)
            .zip(&closed)
            .map(|((c, &u), &shut)| match shut {
                true => e * u,
                false => ((c.geom.gap + h * (1.0 - self.theta) * u) / (h * self.theta)).max(-u),
            })
            .collect();
        let open = closed.iter().filter(|&&shut| !shut).count();
        if self.open_contacts == OpenContacts::Gap {
            self.counters.add(&OPEN_CONTACTS, open as u64);
        }
        let centres = sys.centres();
        let gs = groups(active, n);
        self.counters.add(&ACTIVE_CONTACTS, active.len() as u64);
        self.counters.max(&ACTIVE_CONTACTS_MAX, active.len() as f64);
        self.counters.add(&CONTACT_GROUPS, gs.len() as u64);
        let mut any = false;
        let (mut e_before, mut e_after) = (0.0, 0.0);
        for g in &gs {
            let data = GroupData {
                scn,
                centres: &centres,
                contacts: active,
                group: g,
                w_free,
                offsets: &offsets,
            };
            // An impact of one pair may be resolved in the lattices
            // (`impact = "lattice"`, [`lattice`]).
            let lattice = cx.topology.reads().impacts.then(|| {
                let group = (g, active, &u_minus[..], &closed[..]);
                self.lattice_impact(scn, sys, group, w_free, cx)
            });
            let (rigid, dv) = match lattice.flatten() {
                Some(answer) => (Err(answer), Moreau::lattice_dv(scn, g, &answer, w_free)),
                None => {
                    let GroupAnswer {
                        normal,
                        tangential,
                        dv,
                        ..
                    } = self.solver.solve(&data, sys.t, h);
                    let pushing = g
                        .contacts
                        .iter()
                        .zip(&normal)
                        .filter(|&(&k, &l)| !closed[k] && l > 0.0)
                        .count();
                    if self.open_contacts == OpenContacts::Gap {
                        self.counters.add(&OPEN_CONTACTS_PUSHING, pushing as u64);
                    }
                    (Ok((normal, tangential)), dv)
                }
            };
            let v_scale = g
                .floes
                .iter()
                .flat_map(|&i| w_free[i])
                .fold(0.0f64, |m, v| m.max(v.abs()));
            let negligible = NEGLIGIBLE_VELOCITY_FRACTION * v_scale + 1e-300;
            if dv.iter().flatten().any(|d| d.abs() > negligible) {
                any = true;
            }
            let before = group_energy(scn, w_free, &g.floes);
            for (l, &i) in g.floes.iter().enumerate() {
                for d in 0..3 {
                    w_new[i][d] = w_free[i][d] + dv[l][d];
                }
            }
            let after = group_energy(scn, &w_new, &g.floes);
            if crate::iterative::creates_energy(before, after) {
                self.counters.add(&CONTACT_ENERGY_INCREASES, 1);
                self.counters
                    .max(&CONTACT_ENERGY_INCREASE_MAX, after - before);
            }
            let impulses = match rigid {
                Ok(impulses) => {
                    sys.ledger.dissipated += before - after;
                    Some(impulses)
                }
                // The stage queued the impact's cracks itself.
                Err((_, answer)) => {
                    answer.book(&mut sys.ledger, before, after);
                    None
                }
            };
            if let (true, Some((normal, tangential))) = (cx.topology.reads().percussions, impulses)
            {
                // The step's impulses, on the floes at q_k, delivered over
                // the step [t_k, t_k + h] (docs/physics.md §9.3); the floes
                // break between steps (§9.5).
                let group: Vec<&Contact> = g.contacts.iter().map(|&k| &active[k]).collect();
                let loads = loads_of(scn, &group, &normal, &tangential);
                cx.topology
                    .percussion(scn, sys, &loads, sys.t, sys.t + h, before - after);
            }
            if dv.iter().flatten().any(|d| d.abs() > negligible) {
                self.solver.direct.log_mut().push_event(ContactEvent {
                    t: sys.t,
                    contacts: g.contacts.len(),
                    energy_before: before,
                    energy_after: after,
                });
            }
            e_before += before;
            e_after += after;
        }
        if cx.topology.reads().impacts {
            self.keep_active_pairs(active, &closed);
        }
        if any {
            self.counters.add(&STEPS_WITH_IMPULSES, 1);
            if self.records.len() < MAX_RECORDS {
                self.records.push(ContactStep {
                    t: sys.t,
                    h,
                    contacts: active.len(),
                    approaching: u_minus.iter().filter(|&&u| u < 0.0).count(),
                    energy: (e_before, e_after),
                });
            }
        }
        w_new
    }
}

fn group_energy(scn: &Scenario, w: &[Gen], floes: &[usize]) -> f64 {
    floes
        .iter()
        .map(|&i| scn.floes[i].kinetic_energy(&Vec2::new(w[i][0], w[i][1]), w[i][2]))
        .sum()
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
