//! The contact-free formulation: every floe drifts under the environment
//! forces alone, integrated by the shared [`SmoothIntegrator`]. Floes pass
//! through each other and through obstacles. It checks free drift
//! (docs/physics.md §2.2) before any contact solver is involved, and is the
//! smooth part every other formulation must reproduce between impacts.
//!
//! **Steps.** It steps on a grid of its own, the steps of
//! [`SmoothIntegrator::step_bound`] (the drag time scale, a quarter of the
//! smallest radius of travel, the forcing kinks, the end of the run): the
//! same grid as the event-driven scheme between impacts; with explicit
//! Euler, the grid `k h` of the Euler step ([`SmoothIntegrator::euler_step`])
//! so that every Euler step is `h`. The state at an output time inside a
//! step is that step's exact continuation
//! ([`SmoothIntegrator::continuation`]), so what is saved never changes the
//! trajectory.

use super::{
    reported_state, Context, Entry, Formulation, FormulationError, FormulationOptions, OwnState,
};
use crate::model::Scenario;
use crate::physics::{SmoothIntegrator, StepRecord};
use crate::record::{Counters, Settings, Stage};
use crate::state::System;

/// The registry entry (see [`crate::formulation::REGISTRY`]).
pub const ENTRY: Entry = Entry {
    name: "free-drift",
    description: "no contacts: every floe drifts under the environment forces alone",
    build: |scn, opts| Ok(Box::new(FreeDrift::new(scn, opts))),
    check: None,
    settings: None,
    resolves_contacts: false,
    dumps_lcps: false,
    supports_fracture: true,
    lattice_impacts: true,
    supports_crushing: true,
    not_claimed: &[],
};

/// Free drift without contacts.
#[derive(Debug)]
pub struct FreeDrift {
    integrator: SmoothIntegrator,
    own: OwnState,
    /// The last step taken (reported states inside it are its continuation).
    last: Option<StepRecord>,
    /// With explicit Euler: where the grid `base + k h` starts (s) and the
    /// steps taken on it.
    grid: (f64, u64),
}

impl FreeDrift {
    /// Sets up free drift for `scn`.
    pub fn new(scn: &Scenario, opts: &FormulationOptions) -> FreeDrift {
        FreeDrift {
            integrator: SmoothIntegrator::new(scn, opts.integrator),
            own: OwnState::default(),
            last: None,
            grid: (0.0, 0),
        }
    }
}

impl Formulation for FreeDrift {
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
            self.grid = (cur.t, 0);
        }
        let end = scn.duration.max(t_end);
        let integ = &mut self.integrator;
        let last = &mut self.last;
        let grid = &mut self.grid;
        let out = cx.clock.time(
            Stage::Integration,
            || -> Result<System, FormulationError> {
                while cur.t < t_end {
                    let t1 = match integ.euler_step() {
                        Some(h) => {
                            grid.1 += 1;
                            (grid.0 + grid.1 as f64 * h).min(end)
                        }
                        None => {
                            let h = integ.step_bound(scn, &cur, end);
                            if h >= end - cur.t {
                                end
                            } else {
                                cur.t + h
                            }
                        }
                    };
                    let hints = integ.hints().to_vec();
                    let next = integ.advance_system(scn, &cur, t1, &[], None)?;
                    *last = Some(StepRecord {
                        start: std::mem::replace(&mut cur, next),
                        wrenches: Vec::new(),
                        hints,
                    });
                }
                reported_state(integ, scn, &cur, last.as_ref(), t_end)
            },
        )?;
        self.own.keep(cur);
        self.own.report(sys, out, t_end);
        Ok(())
    }

    fn settings(&self) -> Settings {
        Settings::default().text("contacts", "ignored")
    }

    fn counters(&self) -> Counters {
        let mut c = Counters::default();
        self.integrator.stats.report(&mut c);
        c
    }
}
