//! Formulations: strategies for advancing a scenario through its impacts.
//!
//! A formulation owns only how it steps. The floe model, the forces, the
//! integrator, contact detection, the LCP solvers, the recording and the
//! timing are shared: the [`crate::run::Runner`] calls
//! [`Formulation::advance`] up to each output time, and the formulation
//! charges its CPU time to the stages of the [`StageClock`] it is handed.
//!
//! To add a formulation: write a module here implementing [`Formulation`],
//! and add its name to [`NAMES`] and [`build`].

pub mod contact_solver;
pub mod event_driven;
pub mod free_drift;
pub mod moreau;
pub mod rapier_ref;

use crate::model::{IntegratorKind, MoreauSolver, Scenario};
use crate::run::{ContactLog, Counters, StageClock};
use crate::state::System;

/// A failure that stops a run (a failed LCP is not one: it is counted and
/// handled by a fallback inside the formulation).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FormulationError {
    /// The smooth integration failed.
    #[error(transparent)]
    Integration(#[from] crate::physics::IntegrationError),
    /// Anything else, with a message naming the floe or contact.
    #[error("{0}")]
    Other(String),
}

/// A strategy for advancing a scenario in time.
pub trait Formulation {
    /// The name used on the command line and in reports.
    fn name(&self) -> &'static str;

    /// Advances `sys` from `sys.t` to exactly `t_end` (s), updating the
    /// ledger's work and dissipation, and charging CPU time to `clock`.
    fn advance(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        t_end: f64,
        clock: &mut StageClock,
    ) -> Result<(), FormulationError>;

    /// The formulation's counters (steps, events, solves, …) so far.
    fn counters(&self) -> Counters;

    /// Hands over (and clears) the bounded log of contact impulses and
    /// contact events recorded so far; the [`crate::run::Runner`] calls it
    /// at the end of a run. The default records nothing.
    fn take_contact_log(&mut self) -> ContactLog {
        ContactLog::default()
    }
}

/// Options shared by every formulation, from the command line.
#[derive(Debug, Clone, Default)]
pub struct FormulationOptions {
    /// Override of the case's smooth integrator.
    pub integrator: Option<IntegratorKind>,
    /// Write every LCP solved into this folder as `<seq>.json` (event-driven,
    /// Moreau–Jean with the LCP solver or a cone fallback).
    pub dump_lcp: Option<std::path::PathBuf>,
}

/// Names accepted by [`build`], with a one-line description each.
pub const NAMES: &[(&str, &str)] = &[
    (
        "event-driven",
        "Rabatel (2015): advance to each impact, velocity-impulse LCP (Stewart-Trinkle friction) by Lemke, Poisson restitution",
    ),
    (
        "free-drift",
        "no contacts: every floe drifts under the environment forces alone",
    ),
    (
        "rapier",
        "rapier2d-f64 0.36: soft contacts (TGS-soft, substeps), restitution on new contacts only; the regularised reference",
    ),
    (
        "moreau",
        "Moreau-Jean time stepping: fixed step, theta-method, Newton impact law, one contact problem per step and group; solver from the case ([formulation.moreau] solver, default lcp: Lemke)",
    ),
    (
        "moreau-cone",
        "Moreau-Jean time stepping with the Anitescu-Tasora convex cone relaxation solved by clarabel (sliding contacts separate at mu |u_T|)",
    ),
];

/// The formulation called `name`, set up for `scn`.
pub fn build(
    name: &str,
    scn: &Scenario,
    opts: &FormulationOptions,
) -> Result<Box<dyn Formulation>, String> {
    match name {
        "event-driven" => Ok(Box::new(event_driven::EventDriven::new(scn, opts))),
        "free-drift" => Ok(Box::new(free_drift::FreeDrift::new(scn, opts))),
        "rapier" => Ok(Box::new(rapier_ref::RapierReference::new(scn, opts)?)),
        "moreau" => Ok(Box::new(moreau::Moreau::new(scn, opts, None))),
        "moreau-cone" => Ok(Box::new(moreau::Moreau::new(
            scn,
            opts,
            Some(MoreauSolver::Cone),
        ))),
        other => Err(format!(
            "unknown formulation `{other}`; known: {}",
            NAMES.iter().map(|n| n.0).collect::<Vec<_>>().join(", ")
        )),
    }
}
