//! The shared run machinery: the [`Runner`] owns the clock, the stopping
//! rule, the recording and the output; a formulation only advances the state.
//!
//! A run records, every `output_interval`, the state of each floe (the
//! trajectory) and the energy ledger: kinetic energy `E`, the cumulative work
//! of air, water and Coriolis forces `W_ext`, the energy dissipated by
//! contacts `D`, and the balance residual `E(t) − E(0) − W_ext + D`, which
//! is zero for an exact integration.

pub mod clock;
pub mod output;

pub use clock::{thread_cpu_seconds, Stage, StageClock, StageTimes};

use crate::formulation::Formulation;
use crate::model::Scenario;
use crate::physics::IntegratorStats;
use crate::state::System;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// A formulation's counters: integer counts and real-valued figures, by name.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Counters {
    /// Event counts (steps, impacts, solves, pivots, fallbacks, …).
    pub counts: BTreeMap<String, u64>,
    /// Real-valued figures with their unit in the name (e.g. `max_penetration_m`).
    pub values: BTreeMap<String, f64>,
}

impl Counters {
    /// Adds `n` to the count `name`.
    pub fn add(&mut self, name: &str, n: u64) {
        *self.counts.entry(name.to_string()).or_insert(0) += n;
    }

    /// Sets the figure `name`.
    pub fn set_value(&mut self, name: &str, v: f64) {
        self.values.insert(name.to_string(), v);
    }

    /// Keeps the largest figure seen under `name`.
    pub fn max_value(&mut self, name: &str, v: f64) {
        let e = self.values.entry(name.to_string()).or_insert(v);
        *e = e.max(v);
    }

    /// Adds the smooth integrator's counts.
    pub fn integrator(&mut self, s: &IntegratorStats) {
        self.add("integrator_steps", s.steps);
        self.add("integrator_rejected_steps", s.rejected);
        self.add("force_evaluations", s.force_evaluations);
    }
}

/// One row of the trajectory: the state of one floe at one time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrajectoryRow {
    /// Time, s.
    pub t: f64,
    /// Floe index (listed floes first, then fields).
    pub floe: usize,
    /// Centre of mass x, m.
    pub x: f64,
    /// Centre of mass y, m.
    pub y: f64,
    /// Angle from the initial orientation, rad.
    pub theta: f64,
    /// Velocity x, m/s.
    pub vx: f64,
    /// Velocity y, m/s.
    pub vy: f64,
    /// Angular velocity, rad/s.
    pub omega: f64,
}

/// One sample of the energy ledger.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnergySample {
    /// Time, s.
    pub t: f64,
    /// Kinetic energy, J.
    pub kinetic: f64,
    /// Cumulative work of the air drag, J.
    pub work_air: f64,
    /// Cumulative work of the water drag, J.
    pub work_water: f64,
    /// Cumulative work of the Coriolis force, J.
    pub work_coriolis: f64,
    /// Cumulative energy dissipated by contacts, J.
    pub dissipated: f64,
    /// Balance residual `E(t) − E(0) − W_ext + D`, J.
    pub residual: f64,
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum EndReason {
    /// Reached the case's duration.
    Completed,
    /// The formulation failed; the run stops at the last good output.
    Failed {
        /// What failed.
        message: String,
    },
    /// The state became non-finite.
    NonFinite {
        /// Which floe.
        floe: usize,
    },
}

/// Energy totals of a run, J.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnergyTotals {
    /// Kinetic energy at t = 0, J.
    pub initial_kinetic: f64,
    /// Kinetic energy at the end, J.
    pub final_kinetic: f64,
    /// Work of the air drag, J.
    pub work_air: f64,
    /// Work of the water drag, J.
    pub work_water: f64,
    /// Work of the Coriolis force, J.
    pub work_coriolis: f64,
    /// Dissipated by contacts, J.
    pub dissipated: f64,
    /// Final balance residual, J.
    pub residual: f64,
    /// Largest |residual| over the samples, J.
    pub max_abs_residual: f64,
    /// Scale of the exchanges, `E(0) + |W_air| + |W_water| + |W_cor| + D`, J:
    /// the residual is judged relative to it.
    pub exchanged: f64,
}

/// CPU and wall time of a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Timing {
    /// CPU time of the run's thread (stepping only, not output), s.
    pub cpu_total: f64,
    /// CPU time per stage, s.
    pub stages: StageTimes,
    /// CPU time outside the named stages (recording, bookkeeping), s.
    pub cpu_other: f64,
    /// Wall-clock time, s.
    pub wall: f64,
}

/// Everything `summary.json` says about a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSummary {
    /// Case name.
    pub case: String,
    /// Formulation name.
    pub formulation: String,
    /// Number of floes.
    pub floes: usize,
    /// Number of obstacles.
    pub obstacles: usize,
    /// Requested duration, s.
    pub duration: f64,
    /// Time reached, s.
    pub t_reached: f64,
    /// How the run ended.
    pub end: EndReason,
    /// Timing.
    pub timing: Timing,
    /// Energy totals.
    pub energy: EnergyTotals,
    /// The formulation's counters.
    pub counters: Counters,
}

/// The recorded result of a run.
#[derive(Debug, Clone)]
pub struct RunResult {
    /// Floe states at each output time.
    pub trajectory: Vec<TrajectoryRow>,
    /// Energy ledger at each output time.
    pub energy: Vec<EnergySample>,
    /// Totals, timing, counters and end.
    pub summary: RunSummary,
    /// The final state.
    pub final_state: System,
    /// What the formulation recorded of its contact impulses and impacts
    /// (bounded; empty for formulations that record nothing).
    pub contacts: ContactLog,
}

/// One contact impulse as a formulation applied it: the normal impulse `λ`
/// and the tangential (friction) impulse `β` of one contact point, N·s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ImpulseRecord {
    /// Time, s.
    pub t: f64,
    /// Normal impulse `λ`, N·s (≥ 0 when pushing).
    pub normal: f64,
    /// Tangential impulse `β`, N·s (signed).
    pub tangent: f64,
    /// Friction coefficient `μ` of the contact.
    pub mu: f64,
    /// Rounding allowance of this impulse, N·s: a tangential impulse below it
    /// is rounding and is left out of the Coulomb ratio (0 for none).
    pub slack: f64,
}

impl ImpulseRecord {
    /// The Coulomb ratio `|β| / (μ λ)` (1 on the cone's boundary); 0 when
    /// `|β|` is within the rounding allowance; infinite for a tangential
    /// impulse without a normal one. This is the one definition used by the
    /// formulations' counters and by `floebench check`.
    pub fn coulomb_ratio(&self) -> f64 {
        let b = self.tangent.abs();
        if b <= self.slack {
            return 0.0;
        }
        let bound = self.mu * self.normal;
        if bound > 0.0 {
            b / bound
        } else {
            f64::INFINITY
        }
    }
}

/// One contact resolution that changed velocities: an impact (event-driven),
/// the contact impulses of one step (time stepping), with the kinetic energy
/// of the floes involved just before and just after the impulses, J.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactEvent {
    /// Time (start of the step for time-stepping schemes), s.
    pub t: f64,
    /// Number of contact points involved.
    pub contacts: usize,
    /// Kinetic energy of the floes involved before the impulses, J.
    pub energy_before: f64,
    /// Kinetic energy of the same floes after the impulses, J.
    pub energy_after: f64,
}

impl ContactEvent {
    /// Kinetic energy gained by the impulses (positive: energy created), J.
    /// The one definition used by `floebench check`.
    pub fn energy_gain(&self) -> f64 {
        self.energy_after - self.energy_before
    }
}

/// Aggregates over the records a bounded log did not keep.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Overflow {
    /// Records not kept.
    pub count: u64,
    /// Largest [`ImpulseRecord::coulomb_ratio`] (impulses) or
    /// [`ContactEvent::energy_gain`] (events, J) among them.
    pub max: Option<f64>,
    /// First time among them, s.
    pub first_t: Option<f64>,
}

impl Overflow {
    fn fold(&mut self, v: f64, t: f64) {
        self.count += 1;
        self.max = Some(self.max.map_or(v, |m| m.max(v)));
        self.first_t = Some(self.first_t.map_or(t, |f| f.min(t)));
    }
}

/// A bounded log of contact impulses and contact events: the first
/// [`ContactLog::CAP`] of each are kept, the rest aggregated, so memory stays
/// bounded on long field runs (hundreds of thousands of solves).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct ContactLog {
    /// Whether the formulation records impulses (false: nothing to check).
    pub records_impulses: bool,
    /// Whether the formulation records contact events.
    pub records_events: bool,
    /// The first impulses.
    pub impulses: Vec<ImpulseRecord>,
    /// The impulses beyond the cap (max Coulomb ratio).
    pub impulses_overflow: Overflow,
    /// The first contact events.
    pub events: Vec<ContactEvent>,
    /// The events beyond the cap (max energy gain).
    pub events_overflow: Overflow,
}

impl ContactLog {
    /// Records kept of each kind.
    pub const CAP: usize = 20_000;

    /// A log that records both impulses and events.
    pub fn recording() -> ContactLog {
        ContactLog {
            records_impulses: true,
            records_events: true,
            ..ContactLog::default()
        }
    }

    /// Adds one impulse.
    pub fn push_impulse(&mut self, r: ImpulseRecord) {
        if self.impulses.len() < Self::CAP {
            self.impulses.push(r);
        } else {
            self.impulses_overflow.fold(r.coulomb_ratio(), r.t);
        }
    }

    /// Adds one contact event.
    pub fn push_event(&mut self, e: ContactEvent) {
        if self.events.len() < Self::CAP {
            self.events.push(e);
        } else {
            self.events_overflow.fold(e.energy_gain(), e.t);
        }
    }

    /// Number of impulses recorded, kept or not.
    pub fn impulse_count(&self) -> u64 {
        self.impulses.len() as u64 + self.impulses_overflow.count
    }

    /// Number of events recorded, kept or not.
    pub fn event_count(&self) -> u64 {
        self.events.len() as u64 + self.events_overflow.count
    }

    /// Largest Coulomb ratio over every impulse (0 without any).
    pub fn max_coulomb_ratio(&self) -> f64 {
        self.impulses
            .iter()
            .map(ImpulseRecord::coulomb_ratio)
            .chain(self.impulses_overflow.max)
            .fold(0.0, f64::max)
    }

    /// Largest energy gain over every event, J (`None` without any).
    pub fn max_energy_gain(&self) -> Option<f64> {
        self.events
            .iter()
            .map(ContactEvent::energy_gain)
            .chain(self.events_overflow.max)
            .reduce(f64::max)
    }
}

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Show a progress bar on stderr when the run lasts more than a second.
    pub progress: bool,
    /// Draw the bar in this group of bars (runs in parallel), shown at once.
    pub multi: Option<indicatif::MultiProgress>,
}

/// Runs formulations on scenarios: owns timing, stopping and recording.
#[derive(Debug, Default)]
pub struct Runner {
    /// Options.
    pub options: RunOptions,
}

/// The output times `k Δ` (s) up to the duration, the duration included.
pub fn output_times(duration: f64, interval: f64) -> Vec<f64> {
    let n = (duration / interval * (1.0 + 1e-12)).floor() as usize;
    let mut ts: Vec<f64> = (1..=n)
        .map(|k| (k as f64 * interval).min(duration))
        .collect();
    if ts.last().is_none_or(|&t| t < duration * (1.0 - 1e-12)) {
        ts.push(duration);
    }
    if let Some(last) = ts.last_mut() {
        *last = duration;
    }
    ts
}

impl Runner {
    /// A runner with these options.
    pub fn new(options: RunOptions) -> Runner {
        Runner { options }
    }

    /// Runs `form` on `scn` from t = 0 to the case's duration.
    pub fn run(&self, scn: &Scenario, form: &mut dyn Formulation) -> RunResult {
        let wall0 = Instant::now();
        let cpu0 = thread_cpu_seconds();
        let mut clock = StageClock::new();
        let mut sys = System::initial(scn);
        let e0 = sys.kinetic_energy(scn);
        let mut trajectory = Vec::new();
        let mut energy = Vec::new();
        record(scn, &sys, e0, &mut trajectory, &mut energy);

        let times = output_times(scn.duration, scn.output_interval);
        let bar = Progress::new(&self.options, times.len() as u64, scn, form.name());
        let mut end = EndReason::Completed;
        for (k, &t) in times.iter().enumerate() {
            let mut next = sys.clone();
            if let Err(e) = form.advance(scn, &mut next, t, &mut clock) {
                end = EndReason::Failed {
                    message: format!("at t = {} s: {e}", sys.t),
                };
                break;
            }
            if let Some(i) = next.bodies.iter().position(|b| !b.is_finite()) {
                end = EndReason::NonFinite { floe: i };
                break;
            }
            sys = next;
            sys.t = t;
            record(scn, &sys, e0, &mut trajectory, &mut energy);
            bar.tick(k as u64 + 1, t);
        }
        bar.finish();

        let cpu_total = thread_cpu_seconds() - cpu0;
        let stages = clock.times();
        let last = energy.last().copied().unwrap_or(EnergySample {
            t: 0.0,
            kinetic: e0,
            work_air: 0.0,
            work_water: 0.0,
            work_coriolis: 0.0,
            dissipated: 0.0,
            residual: 0.0,
        });
        let totals = EnergyTotals {
            initial_kinetic: e0,
            final_kinetic: last.kinetic,
            work_air: last.work_air,
            work_water: last.work_water,
            work_coriolis: last.work_coriolis,
            dissipated: last.dissipated,
            residual: last.residual,
            max_abs_residual: energy.iter().map(|s| s.residual.abs()).fold(0.0, f64::max),
            exchanged: e0
                + last.work_air.abs()
                + last.work_water.abs()
                + last.work_coriolis.abs()
                + last.dissipated.abs(),
        };
        let summary = RunSummary {
            case: scn.name.clone(),
            formulation: form.name().to_string(),
            floes: scn.floes.len(),
            obstacles: scn.obstacles.len(),
            duration: scn.duration,
            t_reached: sys.t,
            end,
            timing: Timing {
                cpu_total,
                stages,
                cpu_other: (cpu_total - stages.detection - stages.solve - stages.integration)
                    .max(0.0),
                wall: wall0.elapsed().as_secs_f64(),
            },
            energy: totals,
            counters: form.counters(),
        };
        RunResult {
            trajectory,
            energy,
            summary,
            final_state: sys,
            contacts: form.take_contact_log(),
        }
    }
}

fn record(
    scn: &Scenario,
    sys: &System,
    e0: f64,
    trajectory: &mut Vec<TrajectoryRow>,
    energy: &mut Vec<EnergySample>,
) {
    for (i, b) in sys.bodies.iter().enumerate() {
        trajectory.push(TrajectoryRow {
            t: sys.t,
            floe: i,
            x: b.position.x,
            y: b.position.y,
            theta: b.angle,
            vx: b.velocity.x,
            vy: b.velocity.y,
            omega: b.angular_velocity,
        });
    }
    let e = sys.kinetic_energy(scn);
    let l = &sys.ledger;
    energy.push(EnergySample {
        t: sys.t,
        kinetic: e,
        work_air: l.work_air,
        work_water: l.work_water,
        work_coriolis: l.work_coriolis,
        dissipated: l.dissipated,
        residual: e - e0 - l.external_work() + l.dissipated,
    });
}

/// A progress bar that appears only once a run has lasted a second.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
}

impl Progress {
    fn new(options: &RunOptions, len: u64, scn: &Scenario, name: &str) -> Progress {
        let bar = options.progress.then(|| {
            let bar = indicatif::ProgressBar::with_draw_target(
                Some(len),
                indicatif::ProgressDrawTarget::hidden(),
            );
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{prefix} [{elapsed_precise}] {bar:30} {msg} (eta {eta})",
            ) {
                bar.set_style(style);
            }
            bar.set_prefix(format!("{} / {}", scn.name, name));
            match &options.multi {
                Some(multi) => multi.add(bar),
                None => bar,
            }
        });
        Progress {
            bar,
            start: Instant::now(),
        }
    }

    fn tick(&self, pos: u64, t: f64) {
        if let Some(bar) = &self.bar {
            if bar.is_hidden() && self.start.elapsed() > Duration::from_secs(1) {
                bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            }
            bar.set_position(pos);
            bar.set_message(format!("t = {t:.3} s"));
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
