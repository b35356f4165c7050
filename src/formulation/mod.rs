//! Formulations: strategies for advancing a scenario through its impacts.
//!
//! A formulation owns only how it steps. The floe model, the force model,
//! the integrator, contact detection, the contact-problem solver
//! ([`contact_solver`]), the recording and the timing are shared: the
//! [`crate::run::Runner`] calls [`Formulation::advance`] up to each output
//! time, and the formulation charges its CPU time to the stages of the
//! [`crate::record::StageClock`] of the [`Context`] it is handed, with which
//! come the run's topology stage (fracture: the runner's, once for every
//! formulation, [`context`]) and its stop request.
//!
//! **The registry.** Each formulation is one [`Entry`] of [`REGISTRY`]:
//! its name, a one-line description, its builder, the `[formulation.<table>]`
//! settings it reads with their parser ([`TableSpec`]), whether it resolves
//! contacts, and the checks it does not claim with the reason
//! ([`NotClaimed`]). To add a formulation: write one module here (its
//! `Formulation` implementation and its `pub const ENTRY: Entry`), declare
//! it with `pub mod`, and add one line to [`REGISTRY`]. Run labels come
//! from the entry, not from the instance. To let it break floes
//! (`supports_fracture: true`): report each contact solve's impulses to
//! `cx.topology` ([`Topology::percussion`], built with
//! [`crate::contact::loads_of`]), call [`Context::change_floes`] at the safe
//! points of the scheme, and rebuild in [`Formulation::floes_changed`]
//! (docs/physics.md §9.5). The fracture criteria themselves live in
//! [`crate::fracture`], in one place for every formulation.
//!
//! **Output times do not change the dynamics.** Every formulation steps on
//! a grid of its own, set by its scheme alone, and keeps its state on that
//! grid ([`OwnState`]); the state it reports at an output time is produced
//! without perturbing the grid. The event-driven and free-drift
//! formulations report the exact continuation of the step in progress
//! ([`crate::physics::SmoothIntegrator::continuation`]); the fixed-step
//! schemes (`moreau`, `moreau-cone`, `rapier`) step on `t_k = k h` and
//! refuse a case whose output times are not on that grid
//! ([`check_output_grid`]): they report only states of their own grid,
//! never interpolated ones. That refusal is the formulation's
//! [`Entry::check`], which its builder calls and which
//! [`validate_case`] (`floebench validate`) and the batch (before any run)
//! call too: a case is refused at validation, naming the file, the line and
//! the key, by every check a formulation makes when it is built.

mod checks;
pub mod contact_solver;
pub mod context;
pub mod event_driven;
pub mod free_drift;
pub mod group_solver;
pub mod moreau;
pub mod rapier_ref;

use crate::model::{
    load_case_with, parse_case_with, CaseError, IntegratorKind, Scenario, TableSpec,
};
use crate::physics::{SmoothIntegrator, StepRecord};
use crate::record::{ContactLog, Counters, Settings, SolveProfile};
use crate::state::System;
pub use checks::{check_formulations, check_output_grid, validate_case, Check};
pub use context::{Context, FixedTopology, ImpactAnswer, ImpactQuery, Interrupt, Reads, Topology};

/// The smallest floe radius, or 1 m without floes: the length the default
/// tolerances of the formulations are fractions of, m.
pub fn floe_length_scale(scn: &Scenario) -> f64 {
    let rmin = scn.min_floe_radius();
    if rmin.is_finite() {
        rmin
    } else {
        1.0
    }
}

/// Default penetration tolerance as a fraction of the smallest floe
/// radius: the event-driven `penetration_tolerance` and Moreau–Jean's
/// `projection_depth`, so that both schemes keep floes apart to the same
/// depth.
pub const DEFAULT_PENETRATION_FRACTION: f64 = 1e-4;

/// Default contact distance `δ` as a fraction of the smallest floe radius,
/// when the case leaves `[contact] distance = 0`: the event-driven scheme's
/// contact distance, and the distance within which Moreau–Jean takes the
/// second corner of a facing edge pair as a contact point.
pub const DEFAULT_DISTANCE_FRACTION: f64 = 1e-3;

/// The contact distance `δ` in use on `scn`, m: the case's, or
/// [`DEFAULT_DISTANCE_FRACTION`] of the smallest floe radius.
pub fn contact_distance(scn: &Scenario) -> f64 {
    if scn.contact.distance > 0.0 {
        scn.contact.distance
    } else {
        DEFAULT_DISTANCE_FRACTION * floe_length_scale(scn)
    }
}
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
    /// SIGINT or SIGTERM arrived between two steps of the formulation's own
    /// grid ([`Context::poll_interrupt`]), at the time `t` of its state, s:
    /// the run ends at its last output time, as at an output.
    #[error("interrupted at t = {t} s")]
    Interrupted {
        /// The formulation's own time when it stopped, s.
        t: f64,
    },
}

/// A strategy for advancing a scenario in time.
pub trait Formulation {
    /// Writes into `sys` the state (with its energy ledger) at `t_end` (s),
    /// charging CPU time to `cx.clock`. The formulation advances its own
    /// state on its own step grid ([`OwnState`]), whatever times it is
    /// asked for: `sys` on entry is the state it last wrote (or the initial
    /// state); a caller that passes any other state restarts the grid from
    /// it.
    ///
    /// `scn` is the run's own copy of the case. A formulation never changes
    /// it itself: it reports its contact solves to `cx.topology`, and at the
    /// safe points of its scheme lets the run's topology stage change the
    /// floe set ([`Context::change_floes`], which changes `scn.floes`,
    /// `scn.history` and the state's bodies together), then rebuilds in
    /// [`Formulation::floes_changed`]; without a `[fracture]` table nothing
    /// ever changes. It polls `cx.interrupt` once per step.
    fn advance(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        t_end: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError>;

    /// Rebuilds what depends on the floe set after the topology stage
    /// changed it in `scn` and `sys` (its own state, at `sys.t`); `old`
    /// holds the floe ids before the change, in index order (a piece takes
    /// its parent's index or is appended). The default rebuilds nothing.
    fn floes_changed(
        &mut self,
        scn: &Scenario,
        sys: &System,
        old: &[usize],
    ) -> Result<(), FormulationError> {
        let _ = (scn, sys, old);
        Ok(())
    }

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

/// A formulation's state on its own step grid, kept apart from the states it
/// reports (see [`Formulation::advance`]).
#[derive(Debug, Clone, Default)]
pub struct OwnState {
    internal: Option<System>,
    reported: Option<System>,
}

impl OwnState {
    /// The state to continue from, taken out (give it back with
    /// [`OwnState::keep`]): the formulation's own when `sys` is the state it
    /// last reported, else a copy of `sys` and `true` (the grid restarts
    /// there).
    pub fn resume(&mut self, sys: &System) -> (System, bool) {
        match self.internal.take() {
            Some(own) if self.reported.as_ref() == Some(sys) => (own, false),
            _ => (sys.clone(), true),
        }
    }

    /// Keeps `internal` as the state on the grid.
    pub fn keep(&mut self, internal: System) {
        self.internal = Some(internal);
    }

    /// Writes `out` (the state at `t`, s) into `sys` and remembers it as
    /// the state last reported.
    pub fn report(&mut self, sys: &mut System, mut out: System, t: f64) {
        out.t = t;
        self.reported = Some(out.clone());
        *sys = out;
    }
}

/// The state at `t_end` (s) of a formulation stepping on its own grid with
/// the smooth integrator: `grid` itself when it is at `t_end`, else the
/// exact continuation of the step in progress `last` (which must contain
/// `t_end`), leaving the grid unperturbed.
pub fn reported_state(
    integ: &mut SmoothIntegrator,
    scn: &Scenario,
    grid: &System,
    last: Option<&StepRecord>,
    t_end: f64,
) -> Result<System, FormulationError> {
    if grid.t == t_end {
        return Ok(grid.clone());
    }
    match last {
        Some(rec) if rec.start.t <= t_end && t_end < grid.t => {
            Ok(integ.continuation(scn, rec, t_end)?)
        }
        _ => Err(FormulationError::Other(format!(
            "t = {t_end} s is not within the step in progress (the state is at {} s)",
            grid.t
        ))),
    }
}

/// The grid `t_k = base + k h` of a fixed-step formulation (a fixed step
/// `h`, s, from the time the state was last set, `t = 0` in a run) and the
/// state on it. `begin` resumes the state and says how many steps reach the
/// requested time; after each step `stepped` puts the state's time on the
/// grid; `finish` keeps and reports it.
#[derive(Debug, Clone, Default)]
pub struct FixedGrid {
    own: OwnState,
    h: f64,
    base: f64,
    k: u64,
}

impl FixedGrid {
    /// The grid of step `h`, s.
    pub fn new(h: f64) -> FixedGrid {
        FixedGrid {
            h,
            ..FixedGrid::default()
        }
    }

    /// The step `h`, s.
    pub fn step(&self) -> f64 {
        self.h
    }

    /// The state to continue from (see [`OwnState::resume`]), whether the
    /// grid restarted there, and the number of steps to `t_end` (s); an
    /// error when `t_end` is not a time of the grid ahead.
    pub fn begin(
        &mut self,
        sys: &System,
        t_end: f64,
    ) -> Result<(System, bool, u64), FormulationError> {
        let (cur, fresh) = self.own.resume(sys);
        if fresh {
            (self.base, self.k) = (cur.t, 0);
        }
        match grid_index(self.base, self.h, t_end).filter(|&j| j >= self.k) {
            Some(j) => Ok((cur, fresh, j - self.k)),
            None => Err(FormulationError::Other(format!(
                "t = {t_end} s is not a time of the step grid (step {} s from {} s, now at {} s)",
                self.h, self.base, cur.t
            ))),
        }
    }

    /// After one step of `cur`: its time is the next time of the grid.
    pub fn stepped(&mut self, cur: &mut System) {
        self.k += 1;
        cur.t = self.base + self.k as f64 * self.h;
    }

    /// Keeps `cur` as the state on the grid and reports it into `sys` at
    /// `t_end` (s).
    pub fn finish(&mut self, sys: &mut System, cur: System, t_end: f64) {
        self.own.keep(cur.clone());
        self.own.report(sys, cur, t_end);
    }
}

/// A formulation stepping on a [`FixedGrid`] (`moreau`, `moreau-cone`,
/// `rapier`): its one step, for the shared loop [`advance_on_grid`].
pub trait FixedStep: Formulation {
    /// Its grid.
    fn grid(&mut self) -> &mut FixedGrid;

    /// Called with the state the grid continues from, before the steps
    /// (the default does nothing; rapier syncs its bodies).
    fn resume(&mut self, cur: &System) {
        let _ = cur;
    }

    /// One step of the grid's `h` from `sys` (its time is put on the grid
    /// after it).
    fn fixed_step(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        cx: &mut Context,
    ) -> Result<(), FormulationError>;
}

/// [`Formulation::advance`] of a fixed-step formulation: its steps on the
/// grid `t_k = k h` up to `t_end` (s), polling the interrupt before each,
/// with the safe point of the topology stage between steps (at `t_{k+1}`,
/// docs/physics.md §9.5: the floes break on the lines the step's contact
/// problems chose, carried with the floes), then the state kept and
/// reported.
pub fn advance_on_grid<F: FixedStep + ?Sized>(
    form: &mut F,
    scn: &mut Scenario,
    sys: &mut System,
    t_end: f64,
    cx: &mut Context,
) -> Result<(), FormulationError> {
    let (mut cur, _, steps) = form.grid().begin(sys, t_end)?;
    form.resume(&cur);
    for _ in 0..steps {
        cx.poll_interrupt(cur.t)?;
        form.fixed_step(scn, &mut cur, cx)?;
        form.grid().stepped(&mut cur);
        if let Some(old) = cx.change_floes(scn, &mut cur) {
            form.floes_changed(scn, &cur, &old)?;
        }
    }
    form.grid().finish(sys, cur, t_end);
    Ok(())
}

/// Relative rounding allowed when an output time is matched to a step of a
/// fixed grid (`k Δ` and `j h` computed in floating point).
const GRID_ROUNDING: f64 = 1e-9;

/// The index `j` of the grid time `base + j h` (s) equal to `t` to
/// rounding, if there is one.
pub fn grid_index(base: f64, h: f64, t: f64) -> Option<u64> {
    let j = ((t - base) / h).round();
    let on = j >= 0.0 && (base + j * h - t).abs() <= GRID_ROUNDING * t.abs().max(h);
    on.then_some(j as u64)
}

/// Options shared by every formulation, from the command line.
#[derive(Debug, Clone, Default)]
pub struct FormulationOptions {
    /// Override of the case's smooth integrator.
    pub integrator: Option<IntegratorKind>,
    /// Write every LCP solved into this folder as `<seq>.json` (event-driven,
    /// Moreau–Jean with the LCP solver or a cone fallback).
    pub dump_lcp: Option<std::path::PathBuf>,
    /// Solve each LCP that the warm start solved cold too and count the
    /// differences (`floebench run --warm-check`; a diagnostic, off by
    /// default: see [`contact_solver`]).
    pub warm_check: bool,
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
    /// What it refuses in a case when it is built (its settings against
    /// the case's times), with the file and the line; its builder calls it,
    /// and so do [`validate_case`] and the batch before any run (`None`:
    /// it refuses nothing).
    pub check: Option<Check>,
    /// The `[formulation.<table>]` it reads, with the table's parser (two
    /// entries may read the same table).
    pub settings: Option<TableSpec>,
    /// Whether it resolves contacts (false: it applies only to cases where
    /// contacts cannot happen, [`Scenario::contact_free`]).
    pub resolves_contacts: bool,
    /// Whether `--dump-lcp` writes its contact problems (it solves them as
    /// LCPs by the shared contact solver).
    pub dumps_lcps: bool,
    /// Whether it breaks floes when the case asks for it (a `[fracture]`
    /// table with a model, docs/physics.md §9); one that does not is not
    /// run on such a case (a run of it is refused).
    pub supports_fracture: bool,
    /// Whether it offers its impacts to the topology stage
    /// ([`Topology::impact`]), so that `[fracture] impact = "lattice"`
    /// resolves them in the floes' lattices (docs/physics.md §9.10); one
    /// that does not is not run on such a case (a run of it is refused).
    pub lattice_impacts: bool,
    /// Whether it bounds contact forces by the ice's crushing law
    /// (`[contact] crushing`, docs/physics.md §10); one that does not is
    /// not run on such a case (a run of it is refused).
    pub supports_crushing: bool,
    /// The checks it does not claim; every other check that applies is
    /// claimed.
    pub not_claimed: &'static [NotClaimed],
}

impl Entry {
    /// Whether the formulation applies to `scn` (what `compare` and `check`
    /// run by default).
    pub fn applies(&self, scn: &Scenario) -> bool {
        (self.resolves_contacts || scn.contact_free())
            && (self.supports_fracture || !scn.fracture.enabled())
            && (self.lattice_impacts || !scn.fracture.lattice_impacts())
            && (self.supports_crushing || scn.contact.crushing.is_none())
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
/// reference of the divergences and of the chaos probe).
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
        let known: Vec<&str> = REGISTRY.iter().map(|e| e.name).collect();
        let hint = crate::model::case::closest(name, &known)
            .map_or(String::new(), |k| format!(" (did you mean `{k}`?)"));
        format!(
            "unknown formulation `{name}`{hint}; known: {}",
            known.join(", ")
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

/// The names of the registry's entries for which `pred` holds,
/// comma-separated, in registry order.
fn names_where(pred: impl Fn(&Entry) -> bool) -> String {
    REGISTRY
        .iter()
        .filter(|e| pred(e))
        .map(|e| e.name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The formulation called `name`, set up for `scn`.
pub fn build(name: &str, scn: &Scenario, opts: &FormulationOptions) -> Result<Instance, String> {
    let entry = entry(name)?;
    if scn.fracture.enabled() && !entry.supports_fracture {
        return Err(scn.source.key_error("fracture.model", format!(
            "{name} does not break floes yet, and case `{}` asks for it ([fracture] model = \"{}\"); formulations that do: {}",
            scn.name,
            scn.fracture.model.name(),
            names_where(|e| e.supports_fracture)
        )).to_string());
    }
    if scn.fracture.lattice_impacts() && !entry.lattice_impacts {
        return Err(scn.source.key_error("fracture.impact", format!(
            "{name} has no impact event to resolve in the lattices, and case `{}` asks for it ([fracture] impact = \"lattice\", docs/physics.md §9.10); formulations that do: {}",
            scn.name,
            names_where(|e| e.lattice_impacts)
        )).to_string());
    }
    if scn.contact.crushing.is_some() && !entry.supports_crushing {
        return Err(scn.source.key_error("contact.crushing", format!(
            "{name} cannot bound a contact force by the ice's crushing law, and case `{}` asks for it ([contact] crushing, docs/physics.md §10); formulations that do: {}",
            scn.name,
            names_where(|e| e.supports_crushing)
        )).to_string());
    }
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
