//! The shared run machinery: the [`Runner`] owns the clock, the stopping
//! rule, the recording and the output; a formulation only advances the state.
//!
//! A run records, every `output_interval`, the state of each floe (the
//! trajectory) and the energy ledger: kinetic energy `E`, the cumulative work
//! of air, water and Coriolis forces `W_ext`, the energy dissipated by
//! contacts `D`, the energy fractures spent on cracks `F`, and the balance
//! residual `E(t) − E(0) − W_ext + D + F + L`, which is zero for an exact
//! integration ([`energy`]).
//!
//! [`energy`] holds the ledger's samples and totals; [`summary`] what
//! `summary.json` says; [`output`] writes a
//! run's files ([`netcdf_out`] its `trajectory.nc`); [`batch`] runs several formulations on several cases on a
//! pool of threads; [`repeat`] merges the repeats of a run.

pub mod batch;
pub mod energy;
pub mod interrupt;
pub mod netcdf_out;
pub mod output;
pub mod repeat;
pub mod summary;

use crate::formulation::{Context, Formulation, FormulationError, Interrupt};
use crate::fracture::forces::{ForceStage, ObstacleForce, PackStress};
use crate::fracture::topology::RunTopology;
use crate::model::fracture::{FloeRecord, FractureRecord, PercussionRecord};
use crate::model::Scenario;
use crate::record::{thread_cpu_seconds, ContactLog, StageClock};
use crate::state::System;
pub use energy::{EnergySample, EnergyTotals};
use serde::Serialize;
use std::time::{Duration, Instant};
pub use summary::{per_simulated_hour, CrushingSummary, LatticeCost, RunSummary, Timing};

/// One row of the trajectory: the state of one floe at one time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrajectoryRow {
    /// Time, s.
    pub t: f64,
    /// Floe id (listed floes first, then fields, then the pieces of
    /// fractures in the order they were made).
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

impl TrajectoryRow {
    /// The row of floe `floe` in state `b` at time `t` (s).
    pub fn of(t: f64, floe: usize, b: &crate::state::BodyState) -> TrajectoryRow {
        TrajectoryRow {
            t,
            floe,
            x: b.position.x,
            y: b.position.y,
            theta: b.angle,
            vx: b.velocity.x,
            vy: b.velocity.y,
            omega: b.angular_velocity,
        }
    }
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
    /// A quantity of the state or of the energy ledger became non-finite;
    /// the run stops at the last output where everything was finite, and no
    /// output file holds a non-finite number.
    NonFinite {
        /// Which floe (the first one at fault; 0 for a ledger total).
        floe: usize,
        /// When it was found: the output time whose state is not finite, s.
        t: f64,
        /// What is not finite (`position`, `kinetic energy`, `work of the air drag`, …).
        quantity: String,
    },
    /// SIGINT or SIGTERM ([`interrupt`]): the run stopped at the output
    /// time `t`, its outputs written up to it.
    Interrupted {
        /// The last output time reached, s.
        t: f64,
    },
}

impl std::fmt::Display for EndReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EndReason::Completed => write!(f, "completed"),
            EndReason::Failed { message } => write!(f, "failed: {message}"),
            EndReason::NonFinite { floe, t, quantity } => {
                write!(f, "non-finite {quantity} of floe {floe} at t = {t} s")
            }
            EndReason::Interrupted { t } => {
                write!(f, "interrupted at t = {t} s (outputs written up to it)")
            }
        }
    }
}

/// The first quantity of `sys` (or of its energy `sample`) that is not
/// finite: (floe, what).
fn first_non_finite(
    sys: &System,
    scn: &Scenario,
    sample: &EnergySample,
) -> Option<(usize, String)> {
    for (i, b) in sys.bodies.iter().enumerate() {
        let what = if !(b.position.x.is_finite() && b.position.y.is_finite()) {
            "position"
        } else if !b.angle.is_finite() {
            "angle"
        } else if !(b.velocity.x.is_finite() && b.velocity.y.is_finite()) {
            "velocity"
        } else if !b.angular_velocity.is_finite() {
            "angular velocity"
        } else if !scn.floes[i]
            .kinetic_energy(&b.velocity, b.angular_velocity)
            .is_finite()
        {
            "kinetic energy"
        } else {
            continue;
        };
        return Some((scn.floes.get(i).map_or(i, |f| f.id), what.to_string()));
    }
    sample
        .values()
        .find(|(_, v)| !v.is_finite())
        .map(|(c, _)| (0, c.description().to_string()))
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
    /// Every floe that existed during the run (`floes.json`): the initial
    /// ones, then the pieces, by id.
    pub floes: Vec<FloeRecord>,
    /// Every fracture (`fractures.csv`), in time order.
    pub fractures: Vec<FractureRecord>,
    /// The lattice model's percussion of largest loss that broke a floe,
    /// with its crack (`percussion.json`; `None` without one).
    pub percussion: Option<PercussionRecord>,
    /// The mean force on each obstacle per output interval
    /// (`obstacles.csv`, [`crate::fracture::forces`]).
    pub obstacle_forces: Vec<ObstacleForce>,
    /// The pack's mean stress per output interval (`stress.csv`,
    /// [`crate::fracture::forces`]).
    pub stress: Vec<PackStress>,
}

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Show a progress bar on stderr when the run lasts more than a second.
    pub progress: bool,
    /// Draw the bar in this group of bars (runs in parallel), shown at once.
    pub multi: Option<indicatif::MultiProgress>,
    /// The stop request the run polls at each output time and its
    /// formulation at each step (default: the process's, set by SIGINT and
    /// SIGTERM once [`interrupt::install`] ran).
    pub interrupt: Interrupt,
    /// Run without the forces stage ([`crate::fracture::forces`]): no
    /// load is read for it, and `obstacles.csv` and `stress.csv` hold
    /// zeros. Default `false`; for the check that reading the loads
    /// changes no result.
    pub skip_forces: bool,
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

    /// Runs `form` on `scn` from t = 0 to the case's duration; `label` names
    /// the run (the formulation's registry name, see
    /// [`crate::formulation::Instance`]).
    pub fn run(&self, case: &Scenario, label: &str, form: &mut dyn Formulation) -> RunResult {
        // The floe set may change during the run (fracture): the run works
        // on its own copy of the scenario.
        let mut scn_run = case.clone();
        let scn = &mut scn_run;
        // Measure the cost of a clock read before the run, not inside it.
        crate::record::clock::monotonic_read_cost();
        let wall0 = Instant::now();
        let cpu0 = thread_cpu_seconds();
        let mut clock = StageClock::new();
        // The run's topology stage: fracture and crushing, once for every
        // formulation.
        let mut topology = RunTopology::new(scn);
        let times = output_times(scn.duration, scn.output_interval);
        // The forces on the obstacles and the pack's stress (it only reads).
        topology.forces = ForceStage::new(scn, 0.0, &times, !self.options.skip_forces);
        let stop = &self.options.interrupt;
        // The solvers of this thread poll the run's handle inside a step.
        let _current = crate::stop::current(stop);
        let mut sys = System::initial(scn);
        let e0 = sys.kinetic_energy(scn);
        // A point outside a forcing field's extent left by an earlier run
        // of this thread is not this run's.
        let _ = scn.environment.outside.take();
        let mut trajectory = Vec::new();
        let mut energy = Vec::new();
        let mut end = EndReason::Completed;
        match first_non_finite(&sys, scn, &sample(scn, &sys, e0)) {
            None => record(scn, &sys, e0, &mut trajectory, &mut energy),
            Some((floe, quantity)) => {
                end = EndReason::NonFinite {
                    floe,
                    t: 0.0,
                    quantity,
                }
            }
        }

        let mut bar = Progress::new(&self.options, times.len() as u64, scn, label);
        let started = end == EndReason::Completed;
        for (k, &t) in times.iter().enumerate().filter(|_| started) {
            if stop.requested() {
                end = EndReason::Interrupted { t: sys.t };
                break;
            }
            let mut next = sys.clone();
            let mut cx = Context::new(&mut clock, &mut topology, stop);
            match form.advance(scn, &mut next, t, &mut cx) {
                // A stop seen inside a solve of the advance (its answer cut
                // short, crate::stop): the advance is discarded, the run
                // ends at its last output time.
                Ok(()) if stop.requested() => {
                    end = EndReason::Interrupted { t: sys.t };
                    break;
                }
                Ok(()) => {}
                // A signal between two steps: ended as at an output time.
                Err(FormulationError::Interrupted { .. }) => {
                    end = EndReason::Interrupted { t: sys.t };
                    break;
                }
                Err(e) => {
                    end = EndReason::Failed {
                        message: format!("at t = {} s: {e}", sys.t),
                    };
                    break;
                }
            }
            next.t = t;
            // A forcing field evaluated outside its extent ends the run at
            // the last output before (docs/physics.md §2.4).
            if let Some(message) = scn.environment.outside.take() {
                end = EndReason::Failed {
                    message: format!("between t = {} s and t = {t} s: {message}", sys.t),
                };
                break;
            }
            if let Some((floe, quantity)) = first_non_finite(&next, scn, &sample(scn, &next, e0)) {
                end = EndReason::NonFinite { floe, t, quantity };
                break;
            }
            sys = next;
            record(scn, &sys, e0, &mut trajectory, &mut energy);
            topology.forces.close(scn, &sys);
            bar.tick(k as u64 + 1, t);
        }
        bar.finish();

        let elapsed = clock.monotonic_elapsed();
        let cpu_total = thread_cpu_seconds() - cpu0;
        let stages = clock.split(cpu_total, elapsed);
        let cpu_per_monotonic = if elapsed > 0.0 {
            cpu_total / elapsed.max(clock.monotonic_times().total())
        } else {
            0.0
        };
        let lcp_profile = form.solve_profile().map(|mut p| {
            p.buckets
                .iter_mut()
                .for_each(|b| b.seconds *= cpu_per_monotonic);
            p
        });
        let profile_overhead = lcp_profile.as_ref().map_or(0.0, |p| p.timer_overhead);
        // Without a finite sample (a state not finite at t = 0) the totals
        // are zero, not the non-finite initial energy.
        let gain = scn.history.fractures.iter().map(|f| f.kinetic_gain).sum();
        let totals = EnergyTotals::of(&energy, gain);
        // The topology stage's counters (the lattice impacts', §9.10) with
        // the formulation's.
        let mut counters = form.counters();
        counters.absorb(&crate::formulation::Topology::counters(&topology));
        let summary = RunSummary {
            case: scn.name.clone(),
            formulation: label.to_string(),
            floes: case.floes.len(),
            fracture_model: scn.fracture.enabled().then(|| scn.fracture.model.name()),
            fractures: scn.history.fractures.len(),
            floes_at_end: scn.floes.len(),
            obstacles: scn.obstacles.len(),
            duration: scn.duration,
            restart: scn.restart.clone(),
            t_reached: sys.t,
            end,
            timing: Timing {
                cpu_total,
                stages,
                cpu_other: (cpu_total - stages.total()).max(0.0),
                wall: wall0.elapsed().as_secs_f64(),
                clock_reads: clock.reads(),
                timer_overhead: clock.overhead() + profile_overhead,
                lattice_cost: LatticeCost::of(stages.lattice, &counters),
            },
            energy: totals,
            settings: form.settings(),
            per_simulated_hour: per_simulated_hour(&counters, sys.t),
            counters,
            crushing: topology.crush.enabled().then(|| CrushingSummary {
                deposits: topology.crush.deposits().to_vec(),
            }),
            lcp_profile,
        };
        let floes = floe_records(scn, &sys, topology.crush.enabled());
        let (obstacle_forces, stress) = topology.forces.take_rows();
        RunResult {
            trajectory,
            energy,
            summary,
            final_state: sys,
            contacts: form.take_contact_log(),
            floes,
            fractures: scn.history.fractures.clone(),
            percussion: scn.history.percussion.clone(),
            obstacle_forces,
            stress,
        }
    }
}

/// Every floe of a run's scenario at its end (state `sys`): those that
/// ended and those alive, by id; with crushing (`world`), the alive ones
/// with their world outline at the end.
fn floe_records(scn: &Scenario, sys: &System, world: bool) -> Vec<FloeRecord> {
    let mut out: Vec<FloeRecord> = scn.history.ended.clone();
    out.extend(scn.floes.iter().zip(&sys.bodies).map(|(f, b)| {
        let record = FloeRecord::of(f, None);
        match world {
            true => record.at(&b.position, b.angle),
            false => record,
        }
    }));
    out.sort_by_key(|r| r.id);
    out
}

fn record(
    scn: &Scenario,
    sys: &System,
    e0: f64,
    trajectory: &mut Vec<TrajectoryRow>,
    energy: &mut Vec<EnergySample>,
) {
    for (b, f) in sys.bodies.iter().zip(&scn.floes) {
        trajectory.push(TrajectoryRow::of(sys.t, f.id, b));
    }
    energy.push(sample(scn, sys, e0));
}

/// The energy ledger of `sys` (kinetic energy at t = 0: `e0`, J).
fn sample(scn: &Scenario, sys: &System, e0: f64) -> EnergySample {
    EnergySample::new(sys.t, sys.kinetic_energy(scn), sys.ledger, e0)
}

/// A progress bar that appears only once a run has lasted a second.
///
/// Its time estimate follows the measured cost rate: the simulated time
/// advanced per wall second over the last [`Progress::WINDOW`] of wall time
/// (or since the start, if shorter), applied to the simulated time left. A
/// run whose cost per simulated second changes (a pack that jams) is
/// estimated from how fast it goes now, not from its cheap beginning.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
    duration: f64,
    /// (wall time, simulated time) at recent ticks, oldest first.
    recent: std::collections::VecDeque<(Instant, f64)>,
}

impl Progress {
    /// The wall-time window of the rate estimate.
    const WINDOW: Duration = Duration::from_secs(10);

    fn new(options: &RunOptions, len: u64, scn: &Scenario, name: &str) -> Progress {
        let bar = options.progress.then(|| {
            let bar = indicatif::ProgressBar::with_draw_target(
                Some(len),
                indicatif::ProgressDrawTarget::hidden(),
            );
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{prefix} [{elapsed_precise}] {bar:30} {msg}",
            ) {
                bar.set_style(style);
            }
            bar.set_prefix(format!("{} / {}", scn.name, name));
            match &options.multi {
                Some(multi) => multi.add(bar),
                None => bar,
            }
        });
        let start = Instant::now();
        Progress {
            bar,
            start,
            duration: scn.duration,
            recent: std::collections::VecDeque::from([(start, 0.0)]),
        }
    }

    fn tick(&mut self, pos: u64, t: f64) {
        let Some(bar) = &self.bar else { return };
        let now = Instant::now();
        self.recent.push_back((now, t));
        while self.recent.len() > 2
            && self
                .recent
                .get(1)
                .is_some_and(|&(w, _)| now.duration_since(w) > Self::WINDOW)
        {
            self.recent.pop_front();
        }
        if bar.is_hidden() && self.start.elapsed() > Duration::from_secs(1) {
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
        bar.set_position(pos);
        let eta = self.recent.front().and_then(|&(w0, t0)| {
            let wall = now.duration_since(w0).as_secs_f64();
            let rate = (t - t0) / wall;
            (wall > 0.0 && rate > 0.0).then(|| (self.duration - t).max(0.0) / rate)
        });
        bar.set_message(match eta {
            Some(s) => format!("t = {t:.3} s, eta {} at the current rate", human_seconds(s)),
            None => format!("t = {t:.3} s"),
        });
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// `s` seconds as `1h 02m`, `3m 05s` or `12s`.
fn human_seconds(s: f64) -> String {
    let s = s.round().min(1e9) as u64;
    match (s / 3600, s % 3600 / 60, s % 60) {
        (0, 0, sec) => format!("{sec}s"),
        (0, m, sec) => format!("{m}m {sec:02}s"),
        (h, m, _) => format!("{h}h {m:02}m"),
    }
}
