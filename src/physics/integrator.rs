//! The smooth integrator: advances floes between impacts under the
//! environment forces, shared by the formulations that need it.
//!
//! It holds the scenario's [`ForceModel`] (the one force law and the map from
//! forces to accelerations) and integrates with it; formulations that
//! evaluate forces without integrating (event-driven impact tests) reach it
//! by [`SmoothIntegrator::model`].
//!
//! Floes do not interact through the smooth forces, so each floe is
//! integrated on its own, with its own steps. The state of a floe is
//! `y = (G, θ, Ġ, θ̇, W_air, W_water, W_cor, W_extra)`: the work of each force is
//! integrated with the motion, so the energy ledger is as accurate as the
//! trajectory.
//!
//! Two methods (docs/physics.md §4.1):
//!
//! - [`IntegratorKind::Dopri5`] (default): the embedded Runge–Kutta pair of
//!   Dormand & Prince (1980), order 5 with a 4th-order error estimate, steps
//!   adapted to a relative tolerance (Hairer, Nørsett & Wanner, *Solving ODEs
//!   I*, II.4). It integrates polynomials of degree ≤ 5 exactly, so under
//!   constant forces (a quadratic trajectory) a single step of any length is
//!   exact to rounding and the error estimate vanishes: the event-driven scheme
//!   can serve as the exact reference.
//! - [`IntegratorKind::Euler`]: explicit Euler as in Rabatel's report, with a
//!   step bounded by the drag stability limit
//!   `Δt_max = ρ_i h / (2 |U_a| sqrt(ρ_a C_a ρ_w C_w))` (origin report eq. 3.6, docs/physics.md §4.2, see
//!   [`Scenario::euler_stability_bound`]) and by `[integrator] max_step`
//!   (never by the output interval: what is saved does not change the
//!   dynamics). First order: kept for fidelity to the report.
//!
//! The wind and current series are piecewise linear: steps stop at their
//! kinks so that the adaptive method never straddles one.
//!
//! **Own step grids and reported states.** The formulations built on this
//! integrator (event-driven, free drift) step on a grid of their own, set
//! by [`SmoothIntegrator::step_bound`] and by their events, never by the
//! output times. The state at an output time inside a step is the exact
//! continuation of that step ([`SmoothIntegrator::continuation`]): a copy of
//! the step's start state integrated to the output time with the step's
//! wrenches, starting from the integrator's step memory at the step start
//! and leaving it untouched, so that the grid, and every state reported at
//! a given time, are the same whatever else is reported.

mod methods;

use super::force_model::ForceModel;
use crate::model::{IntegratorKind, Scenario};
use crate::record::counters::{common, Counters};
use crate::state::{BodyState, Ledger, System};

/// A failure of the smooth integration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrationError {
    /// The adaptive step fell below rounding: the forces are too stiff or not finite.
    #[error("floe {floe}: step size underflow at t = {t} s (forces stiff or not finite)")]
    StepUnderflow {
        /// Floe index.
        floe: usize,
        /// Time reached, s.
        t: f64,
    },
    /// The state became non-finite.
    #[error("floe {floe}: non-finite state at t = {t} s")]
    NonFinite {
        /// Floe index.
        floe: usize,
        /// Time reached, s.
        t: f64,
    },
}

/// Counts of the integrator's work, summed over floes.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct IntegratorStats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps (adaptive method only).
    pub rejected: u64,
    /// Evaluations of the environment forces.
    pub force_evaluations: u64,
}

impl IntegratorStats {
    /// Adds these counts to `c` (`integrator_steps`,
    /// `integrator_rejected_steps`, `force_evaluations`).
    pub fn report(&self, c: &mut Counters) {
        c.add(&common::INTEGRATOR_STEPS, self.steps);
        c.add(&common::INTEGRATOR_REJECTED_STEPS, self.rejected);
        c.add(&common::FORCE_EVALUATIONS, self.force_evaluations);
    }
}

const N: usize = 10;
type Y = [f64; N];

/// A constant force and torque added to the environment forces over a step
/// (the contact forces of an event-driven step).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Wrench {
    /// Force, N.
    pub force: crate::geometry::Vec2,
    /// Torque about the centre of mass, N·m.
    pub torque: f64,
}

/// One step of a formulation's own grid, kept so that the state at any time
/// within it can be reported without perturbing the grid
/// ([`SmoothIntegrator::continuation`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// The state at the start of the step (after the impacts of that
    /// instant).
    pub start: System,
    /// The constant wrench of each floe over the step (empty: none).
    pub wrenches: Vec<Wrench>,
    /// The integrator's step memory at the start of the step
    /// ([`SmoothIntegrator::hints`]).
    pub hints: Vec<f64>,
}

/// The smooth integrator of a scenario, with per-floe step memory.
#[derive(Debug, Clone)]
pub struct SmoothIntegrator {
    kind: IntegratorKind,
    rtol: f64,
    model: ForceModel,
    /// Step bound per floe, s.
    max_step: Vec<f64>,
    /// The smallest drag stability bound `Δt_max` over the floes, s
    /// (infinite without water drag).
    drag_bound: f64,
    /// Last accepted adaptive step per floe, s (0 when unknown).
    hint: Vec<f64>,
    /// Absolute error scales per floe: (length m, speed m/s, energy J).
    scales: Vec<(f64, f64, f64)>,
    breakpoints: Vec<f64>,
    /// Work counters.
    pub stats: IntegratorStats,
}

impl SmoothIntegrator {
    /// Builds the integrator for `scn`, with the case's method or `kind` if given.
    pub fn new(scn: &Scenario, kind: Option<IntegratorKind>) -> SmoothIntegrator {
        let kind = kind.unwrap_or(scn.integrator.method);
        let env = &scn.environment;
        let kw = env.water.drag_factor();
        let ka = env.air.drag_factor();
        let drift = if kw > 0.0 {
            env.air.velocity.max_speed() * (ka / kw).sqrt()
        } else {
            0.0
        };
        let max_step = (0..scn.floes.len())
            .map(|i| {
                let user = scn.integrator.max_step.unwrap_or(f64::INFINITY);
                match kind {
                    IntegratorKind::Dopri5 => user,
                    IntegratorKind::Euler => user.min(scn.euler_stability_bound(i)),
                }
            })
            .collect();
        let drag_bound = (0..scn.floes.len())
            .map(|i| scn.euler_stability_bound(i))
            .fold(f64::INFINITY, f64::min);
        let scales = scn
            .floes
            .iter()
            .map(|f| {
                let v = (f.velocity.norm() + f.angular_velocity.abs() * f.radius)
                    .max(env.water.velocity.max_speed())
                    .max(drift)
                    .max(1e-3);
                (f.radius, v, f.mass * v * v)
            })
            .collect();
        SmoothIntegrator {
            kind,
            rtol: scn.integrator.tolerance,
            model: ForceModel::new(&scn.floes),
            max_step,
            drag_bound,
            hint: vec![0.0; scn.floes.len()],
            scales,
            breakpoints: scn.forcing_breakpoints(),
            stats: IntegratorStats::default(),
        }
    }

    /// Follows a change of the floe set of `scn` (a fracture: floe indices
    /// kept, pieces appended): the per-floe data are rebuilt for the new
    /// floes, the step memory of the floes kept is kept, the work counters
    /// go on.
    pub fn floes_changed(&mut self, scn: &Scenario) {
        let mut fresh = SmoothIntegrator::new(scn, Some(self.kind));
        fresh.stats = self.stats;
        for (h, old) in fresh.hint.iter_mut().zip(&self.hint) {
            *h = *old;
        }
        *self = fresh;
    }

    /// The method in use.
    pub fn kind(&self) -> IntegratorKind {
        self.kind
    }

    /// The force model it integrates with (shared with formulations that
    /// evaluate forces).
    pub fn model(&self) -> &ForceModel {
        &self.model
    }

    /// The largest step this integrator takes for floe `i`, s.
    pub fn max_step(&self, i: usize) -> f64 {
        self.max_step[i]
    }

    /// The explicit Euler step of the scenario when the method is
    /// [`IntegratorKind::Euler`] and its bound is finite: the smallest step
    /// bound over the floes, s (a formulation without contacts steps on the
    /// grid `k h` of it, so that every Euler step is `h`).
    pub fn euler_step(&self) -> Option<f64> {
        let h = self.max_step.iter().copied().fold(f64::INFINITY, f64::min);
        (self.kind == IntegratorKind::Euler && h.is_finite()).then_some(h)
    }

    /// The smallest drag stability bound `Δt_max` over the floes
    /// (docs/physics.md §4.2), s; infinite without water drag.
    pub fn drag_bound(&self) -> f64 {
        self.drag_bound
    }

    /// The step memory: the last accepted adaptive step of each floe, s (0:
    /// none yet). A [`StepRecord`] keeps a copy.
    pub fn hints(&self) -> &[f64] {
        &self.hint
    }

    /// The longest step from `sys` of a formulation stepping on its own grid
    /// (event-driven, free drift), s: the smallest of
    ///
    /// - the drag stability bound [`SmoothIntegrator::drag_bound`] (the time
    ///   scale on which the drag changes the forces);
    /// - the time in which no material point moves more than a quarter of
    ///   the smallest floe radius `r`, from the largest point speed `v` and
    ///   point acceleration `a` (`|G̈| + |θ̈| r_i + θ̇² r_i` from the
    ///   environment forces): the root of `v s + ½ a s² = r/4` (so that no
    ///   floe tunnels through another, and a floe at rest under a force still
    ///   takes finite steps);
    /// - the time to the next kink of the forcing series;
    /// - the time to `end` (the end of the run).
    ///
    /// None of these depends on the output times.
    pub fn step_bound(&mut self, scn: &Scenario, sys: &System, end: f64) -> f64 {
        let t = sys.t;
        let mut bound = self.drag_bound.min(end - t);
        if let Some(&k) = self.breakpoints.iter().find(|&&k| k > t) {
            bound = bound.min(k - t);
        }
        let rmin = scn.min_floe_radius();
        if rmin.is_finite() {
            let (mut v, mut a) = (0.0f64, 0.0f64);
            for (i, b) in sys.bodies.iter().enumerate() {
                let r = scn.floes[i].radius;
                let f = self.model.forces(&scn.environment, i, t, b);
                self.stats.force_evaluations += 1;
                let [ax, ay, alpha] = self.model.acceleration(i, &f);
                v = v.max(b.velocity.norm() + b.angular_velocity.abs() * r);
                a = a.max(
                    ax.hypot(ay) + alpha.abs() * r + b.angular_velocity * b.angular_velocity * r,
                );
            }
            let quarter = 0.25 * rmin;
            // v s + a s²/2 = quarter, in the form without cancellation.
            let root = v + (v * v + 2.0 * a * quarter).sqrt();
            if root > 0.0 {
                bound = bound.min(2.0 * quarter / root);
            }
        }
        bound
    }

    /// Advances every floe of `start` to `t1` (s) with the constant
    /// `wrenches` added to the environment forces (empty: none), the work of
    /// the wrenches booked as dissipation with the opposite sign. With
    /// `hints` (a copy of [`SmoothIntegrator::hints`]) the adaptive steps
    /// start from them and the integrator's own step memory is left
    /// unchanged; without, it is used and updated.
    pub fn advance_system(
        &mut self,
        scn: &Scenario,
        start: &System,
        t1: f64,
        wrenches: &[Wrench],
        hints: Option<&[f64]>,
    ) -> Result<System, IntegrationError> {
        let mut out = start.clone();
        let none = Wrench::default();
        let mut contact_work = 0.0;
        for (i, b) in out.bodies.iter_mut().enumerate() {
            let w = wrenches.get(i).unwrap_or(&none);
            let mut hint = match hints {
                Some(h) => h.get(i).copied().unwrap_or(0.0),
                None => self.hint[i],
            };
            contact_work +=
                self.integrate(scn, i, b, &mut out.ledger, start.t, t1, w, &mut hint)?;
            if hints.is_none() {
                self.hint[i] = hint;
            }
        }
        out.ledger.dissipated -= contact_work;
        out.t = t1;
        Ok(out)
    }

    /// The state at `t` (s, within the step) of the step `rec`: its start
    /// state integrated to `t` with its wrenches, from its step memory,
    /// leaving the integrator's own step memory unchanged.
    pub fn continuation(
        &mut self,
        scn: &Scenario,
        rec: &StepRecord,
        t: f64,
    ) -> Result<System, IntegrationError> {
        self.advance_system(scn, &rec.start, t, &rec.wrenches, Some(&rec.hints))
    }

    /// Advances every floe from `t0` to `t1` (s) and adds the work of the
    /// forces to `ledger`.
    pub fn advance_all(
        &mut self,
        scn: &Scenario,
        bodies: &mut [BodyState],
        ledger: &mut Ledger,
        t0: f64,
        t1: f64,
    ) -> Result<(), IntegrationError> {
        for (i, b) in bodies.iter_mut().enumerate() {
            self.advance(scn, i, b, ledger, t0, t1)?;
        }
        Ok(())
    }

    /// Advances floe `i` from `t0` to `t1` (s), adding the work of the forces
    /// to `ledger`. On error `b` and `ledger` are left unchanged.
    pub fn advance(
        &mut self,
        scn: &Scenario,
        i: usize,
        b: &mut BodyState,
        ledger: &mut Ledger,
        t0: f64,
        t1: f64,
    ) -> Result<(), IntegrationError> {
        self.advance_with(scn, i, b, ledger, t0, t1, &Wrench::default())
            .map(|_| ())
    }

    /// Like [`SmoothIntegrator::advance`], with a constant `extra` wrench added
    /// to the environment forces; returns the work of `extra` (J), which is
    /// not added to the ledger (the caller knows what it is).
    #[allow(clippy::too_many_arguments)]
    pub fn advance_with(
        &mut self,
        scn: &Scenario,
        i: usize,
        b: &mut BodyState,
        ledger: &mut Ledger,
        t0: f64,
        t1: f64,
        extra: &Wrench,
    ) -> Result<f64, IntegrationError> {
        let mut hint = self.hint[i];
        let work = self.integrate(scn, i, b, ledger, t0, t1, extra, &mut hint)?;
        self.hint[i] = hint;
        Ok(work)
    }

    /// [`SmoothIntegrator::advance_with`] with the step memory `hint` (s, 0:
    /// none) given and updated.
    #[allow(clippy::too_many_arguments)]
    fn integrate(
        &mut self,
        scn: &Scenario,
        i: usize,
        b: &mut BodyState,
        ledger: &mut Ledger,
        t0: f64,
        t1: f64,
        extra: &Wrench,
        hint: &mut f64,
    ) -> Result<f64, IntegrationError> {
        if t1 <= t0 {
            return Ok(0.0);
        }
        let mut y: Y = [
            b.position.x,
            b.position.y,
            b.angle,
            b.velocity.x,
            b.velocity.y,
            b.angular_velocity,
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        let mut t = t0;
        // Split at the kinks of the forcing.
        let kinks: Vec<f64> = self
            .breakpoints
            .iter()
            .copied()
            .filter(|&k| k > t0 && k < t1)
            .chain(std::iter::once(t1))
            .collect();
        for end in kinks {
            match self.kind {
                IntegratorKind::Dopri5 => self.dopri5(scn, i, &mut y, t, end, extra, hint)?,
                IntegratorKind::Euler => self.euler(scn, i, &mut y, t, end, extra)?,
            }
            t = end;
        }
        if !y.iter().all(|v| v.is_finite()) {
            return Err(IntegrationError::NonFinite { floe: i, t: t1 });
        }
        *b = unpack(&y);
        ledger.work_air += y[6];
        ledger.work_water += y[7];
        ledger.work_coriolis += y[8];
        Ok(y[9])
    }

    fn rhs(&mut self, scn: &Scenario, i: usize, t: f64, y: &Y, extra: &Wrench) -> Y {
        self.stats.force_evaluations += 1;
        let b = unpack(y);
        let f = self.model.forces(&scn.environment, i, t, &b);
        let [ax, ay, alpha] = self.model.wrench_acceleration(
            i,
            &(f.force() + extra.force),
            f.torque() + extra.torque,
        );
        let (pa, pw, pc) = f.powers(&b);
        let pe = extra.force.dot(&b.velocity) + extra.torque * b.angular_velocity;
        [y[3], y[4], y[5], ax, ay, alpha, pa, pw, pc, pe]
    }
}

fn unpack(y: &Y) -> BodyState {
    BodyState {
        position: crate::geometry::Vec2::new(y[0], y[1]),
        angle: y[2],
        velocity: crate::geometry::Vec2::new(y[3], y[4]),
        angular_velocity: y[5],
    }
}
