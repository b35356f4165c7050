//! The contact-free formulation: every floe drifts under the environment
//! forces alone, integrated by the shared [`SmoothIntegrator`]. Floes pass
//! through each other and through obstacles. It checks free drift
//! (docs/physics.md §2.2) before any contact solver is involved, and is the
//! smooth part every other formulation must reproduce between impacts.

use super::{Entry, Formulation, FormulationError, FormulationOptions};
use crate::model::Scenario;
use crate::physics::SmoothIntegrator;
use crate::record::{Counters, Settings, Stage, StageClock};
use crate::state::System;

/// The registry entry (see [`crate::formulation::REGISTRY`]).
pub const ENTRY: Entry = Entry {
    name: "free-drift",
    description: "no contacts: every floe drifts under the environment forces alone",
    build: |scn, opts| Ok(Box::new(FreeDrift::new(scn, opts))),
    settings: None,
    resolves_contacts: false,
    dumps_lcps: false,
    not_claimed: &[],
};

/// Free drift without contacts.
#[derive(Debug)]
pub struct FreeDrift {
    integrator: SmoothIntegrator,
}

impl FreeDrift {
    /// Sets up free drift for `scn`.
    pub fn new(scn: &Scenario, opts: &FormulationOptions) -> FreeDrift {
        FreeDrift {
            integrator: SmoothIntegrator::new(scn, opts.integrator),
        }
    }
}

impl Formulation for FreeDrift {
    fn advance(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        t_end: f64,
        clock: &mut StageClock,
    ) -> Result<(), FormulationError> {
        let t0 = sys.t;
        let integrator = &mut self.integrator;
        clock.time(Stage::Integration, || {
            integrator.advance_all(scn, &mut sys.bodies, &mut sys.ledger, t0, t_end)
        })?;
        sys.t = t_end;
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
