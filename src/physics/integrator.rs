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
//!   [`Scenario::euler_stability_bound`]) and by `[integrator] max_step`.
//!   First order: kept for fidelity to the report.
//!
//! The wind and current series are piecewise linear: steps stop at their
//! kinks so that the adaptive method never straddles one.

use super::force_model::ForceModel;
use crate::model::{IntegratorKind, Scenario};
use crate::record::counters::{common, Counters};
use crate::state::{BodyState, Ledger};

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

/// The smooth integrator of a scenario, with per-floe step memory.
#[derive(Debug, Clone)]
pub struct SmoothIntegrator {
    kind: IntegratorKind,
    rtol: f64,
    model: ForceModel,
    /// Step bound per floe, s.
    max_step: Vec<f64>,
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
                    IntegratorKind::Euler => user
                        .min(scn.euler_stability_bound(i))
                        .min(scn.output_interval),
                }
            })
            .collect();
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
            hint: vec![0.0; scn.floes.len()],
            scales,
            breakpoints: scn.forcing_breakpoints(),
            stats: IntegratorStats::default(),
        }
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
                IntegratorKind::Dopri5 => self.dopri5(scn, i, &mut y, t, end, extra)?,
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

    fn euler(
        &mut self,
        scn: &Scenario,
        i: usize,
        y: &mut Y,
        t0: f64,
        t1: f64,
        extra: &Wrench,
    ) -> Result<(), IntegrationError> {
        let hmax = self.max_step[i];
        let n = ((t1 - t0) / hmax).ceil().max(1.0);
        let h = (t1 - t0) / n;
        let mut t = t0;
        for _ in 0..n as u64 {
            let k = self.rhs(scn, i, t, y, extra);
            for (yj, kj) in y.iter_mut().zip(k.iter()) {
                *yj += h * kj;
            }
            t += h;
            self.stats.steps += 1;
        }
        if !y.iter().all(|v| v.is_finite()) {
            return Err(IntegrationError::NonFinite { floe: i, t });
        }
        Ok(())
    }

    fn dopri5(
        &mut self,
        scn: &Scenario,
        i: usize,
        y: &mut Y,
        t0: f64,
        t1: f64,
        extra: &Wrench,
    ) -> Result<(), IntegrationError> {
        // Dormand–Prince 5(4) coefficients (Hairer, Nørsett & Wanner, table 5.2).
        const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
        const A: [[f64; 6]; 7] = [
            [0.0; 6],
            [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
            [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
            [
                19372.0 / 6561.0,
                -25360.0 / 2187.0,
                64448.0 / 6561.0,
                -212.0 / 729.0,
                0.0,
                0.0,
            ],
            [
                9017.0 / 3168.0,
                -355.0 / 33.0,
                46732.0 / 5247.0,
                49.0 / 176.0,
                -5103.0 / 18656.0,
                0.0,
            ],
            [
                35.0 / 384.0,
                0.0,
                500.0 / 1113.0,
                125.0 / 192.0,
                -2187.0 / 6784.0,
                11.0 / 84.0,
            ],
        ];
        const B: [f64; 7] = [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
            0.0,
        ];
        const E: [f64; 7] = [
            71.0 / 57600.0,
            0.0,
            -71.0 / 16695.0,
            71.0 / 1920.0,
            -17253.0 / 339200.0,
            22.0 / 525.0,
            -1.0 / 40.0,
        ];
        let (len, speed, energy) = self.scales[i];
        let rtol = self.rtol;
        let atol: Y = [
            rtol * len,
            rtol * len,
            rtol,
            rtol * speed,
            rtol * speed,
            rtol * speed / len,
            rtol * energy,
            rtol * energy,
            rtol * energy,
            rtol * energy,
        ];
        let span = t1 - t0;
        let hmax = self.max_step[i].min(span);
        let mut h = if self.hint[i] > 0.0 {
            self.hint[i].min(hmax)
        } else {
            hmax
        };
        let mut t = t0;
        let mut k = [[0.0; N]; 7];
        while t < t1 {
            let last = t + h >= t1 - 1e-15 * t1.abs().max(1.0);
            let hh = if last { t1 - t } else { h };
            k[0] = self.rhs(scn, i, t, y, extra);
            for s in 1..7 {
                let mut ys = *y;
                for (j, yj) in ys.iter_mut().enumerate() {
                    let mut acc = 0.0;
                    for (r, a) in A[s].iter().enumerate().take(s) {
                        acc += a * k[r][j];
                    }
                    *yj += hh * acc;
                }
                k[s] = self.rhs(scn, i, t + C[s] * hh, &ys, extra);
            }
            let mut ynew = *y;
            let mut err2 = 0.0;
            for j in 0..N {
                let mut acc = 0.0;
                let mut e = 0.0;
                for s in 0..7 {
                    acc += B[s] * k[s][j];
                    e += E[s] * k[s][j];
                }
                ynew[j] += hh * acc;
                let sc = atol[j] + rtol * y[j].abs().max(ynew[j].abs());
                let r = hh * e / sc;
                err2 += r * r;
            }
            let err = (err2 / N as f64).sqrt();
            if !err.is_finite() {
                return Err(IntegrationError::NonFinite { floe: i, t });
            }
            if err <= 1.0 {
                *y = ynew;
                t = if last { t1 } else { t + hh };
                self.stats.steps += 1;
                let grow = if err == 0.0 {
                    5.0
                } else {
                    (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
                };
                if !last || hh >= h {
                    h = (hh * grow).min(hmax);
                    self.hint[i] = h;
                }
            } else {
                self.stats.rejected += 1;
                h = hh * (0.9 * err.powf(-0.2)).clamp(0.1, 0.9);
                if h <= 1e-14 * t.abs().max(span) {
                    return Err(IntegrationError::StepUnderflow { floe: i, t });
                }
            }
        }
        Ok(())
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
