//! The contact-free formulation: every floe drifts under the environment
//! forces alone, integrated by the shared [`SmoothIntegrator`]. Floes pass
//! through each other and through obstacles. It checks free drift
//! (physics.md section 2) before any contact solver is involved, and is the
//! smooth part every other formulation must reproduce between impacts.

use super::{Formulation, FormulationError, FormulationOptions};
use crate::model::Scenario;
use crate::physics::SmoothIntegrator;
use crate::run::{Counters, Stage, StageClock};
use crate::state::System;

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
    fn name(&self) -> &'static str {
        "free-drift"
    }

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

    fn counters(&self) -> Counters {
        let mut c = Counters::default();
        c.integrator(&self.integrator.stats);
        c
    }
}
