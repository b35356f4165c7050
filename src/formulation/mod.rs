//! Formulations: strategies for advancing a scenario through its impacts.
//!
//! A formulation owns only how it steps. The floe model, the force model,
//! the integrator, contact detection, the contact-problem solver
//! ([`contact_solver`]), the recording and the timing are shared: the
//! [`crate::run::Runner`] calls [`Formulation::advance`] up to each output
//! time, and the formulation charges its CPU time to the stages of the
//! [`StageClock`] it is handed.
//!
//! **The registry.** Each formulation is one [`Entry`] of [`REGISTRY`]:
//! its name, a one-line description, its builder, the `[formulation.<table>]`
//! settings it reads with their parser ([`TableSpec`]), whether it resolves
//! contacts, and the checks it does not claim with the reason
//! ([`NotClaimed`]). To add a formulation: write one module here (its
//! `Formulation` implementation and its `pub const ENTRY: Entry`), declare
//! it with `pub mod`, and add one line to [`REGISTRY`]. Run labels come
//! from the entry, not from the instance.

pub mod contact_solver;
pub mod event_driven;
pub mod free_drift;
pub mod moreau;
pub mod rapier_ref;

use crate::model::{
    load_case_with, parse_case_with, CaseError, IntegratorKind, Scenario, TableSpec,
};
use crate::record::{ContactLog, Counters, Settings, SolveProfile, StageClock};
use crate::state::System;
use std::path::Path;

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

    /// The settings it runs with, defaults resolved (reported apart from
    /// the counters). The default: none.
    fn settings(&self) -> Settings {
        Settings::default()
    }

    /// The LCP solves so far by size, for formulations that solve LCPs
    /// (the default: none).
    fn solve_profile(&self) -> Option<SolveProfile> {
        None
    }

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

/// A check a formulation does not claim to pass, with the measured reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NotClaimed {
    /// Check id (see [`crate::analysis::check`]).
    pub check: &'static str,
    /// Case name, or `None` for every case.
    pub case: Option<&'static str>,
    /// Why the check is not claimed (a measured finding).
    pub reason: &'static str,
}

/// Builds a formulation for a scenario (the error names what is wrong).
pub type Builder = fn(&Scenario, &FormulationOptions) -> Result<Box<dyn Formulation>, String>;

/// One formulation of the registry.
#[derive(Debug, Clone, Copy)]
pub struct Entry {
    /// The name on the command line, in reports and run labels.
    pub name: &'static str,
    /// One line: the scheme.
    pub description: &'static str,
    /// Its builder.
    pub build: Builder,
    /// The `[formulation.<table>]` it reads, with the table's parser (two
    /// entries may read the same table).
    pub settings: Option<TableSpec>,
    /// Whether it resolves contacts (false: it applies only to cases where
    /// contacts cannot happen, [`Scenario::contact_free`]).
    pub resolves_contacts: bool,
    /// Whether `--dump-lcp` writes its contact problems (it solves them as
    /// LCPs by the shared contact solver).
    pub dumps_lcps: bool,
    /// The checks it does not claim; every other check that applies is
    /// claimed.
    pub not_claimed: &'static [NotClaimed],
}

impl Entry {
    /// Whether the formulation applies to `scn` (what `compare` and `check`
    /// run by default).
    pub fn applies(&self, scn: &Scenario) -> bool {
        self.resolves_contacts || scn.contact_free()
    }

    /// The reason the formulation does not claim `check` on `case`, or
    /// `None` when it claims it.
    pub fn not_claimed(&self, check: &str, case: &str) -> Option<&'static str> {
        self.not_claimed
            .iter()
            .find(|c| c.check == check && c.case.is_none_or(|n| n == case))
            .map(|c| c.reason)
    }
}

/// Every formulation, in report order (the first that applies is the
/// reference of the verdicts).
pub const REGISTRY: &[Entry] = &[
    event_driven::ENTRY,
    free_drift::ENTRY,
    rapier_ref::ENTRY,
    moreau::ENTRY,
    moreau::CONE_ENTRY,
];

/// The entry called `name` (surrounding spaces ignored).
pub fn entry(name: &str) -> Result<&'static Entry, String> {
    let name = name.trim();
    REGISTRY.iter().find(|e| e.name == name).ok_or_else(|| {
        format!(
            "unknown formulation `{name}`; known: {}",
            REGISTRY
                .iter()
                .map(|e| e.name)
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

/// A built formulation with its registry entry (which labels its runs).
pub struct Instance {
    /// The entry it was built from.
    pub entry: &'static Entry,
    /// The formulation.
    pub formulation: Box<dyn Formulation>,
}

impl Instance {
    /// The run label: the entry's name.
    pub fn name(&self) -> &'static str {
        self.entry.name
    }
}

/// The formulation called `name`, set up for `scn`.
pub fn build(name: &str, scn: &Scenario, opts: &FormulationOptions) -> Result<Instance, String> {
    let entry = entry(name)?;
    Ok(Instance {
        entry,
        formulation: (entry.build)(scn, opts)?,
    })
}

/// The settings tables of the registry, each once.
pub fn tables() -> Vec<TableSpec> {
    let mut out: Vec<TableSpec> = Vec::new();
    for t in REGISTRY.iter().filter_map(|e| e.settings) {
        if !out.iter().any(|o| o.name == t.name) {
            out.push(t);
        }
    }
    out
}

/// Reads and validates a case file, every `[formulation.<table>]` checked by
/// the formulation that owns it.
pub fn load_case(path: &Path) -> Result<Scenario, CaseError> {
    load_case_with(path, &tables())
}

/// [`load_case`] on case text; `file` names it in messages.
pub fn parse_case(text: &str, file: &Path) -> Result<Scenario, CaseError> {
    parse_case_with(text, file, &tables())
}
