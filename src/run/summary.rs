//! What `summary.json` says about a run ([`RunSummary`]): its end, its
//! timing ([`Timing`]), energy totals, settings, counters, and what the
//! crushing left on the coasts ([`CrushingSummary`]).

use super::{EndReason, EnergyTotals};
use crate::fracture::crush::Deposit;
use crate::fracture::impact::{LATTICE_IMPACTS, LATTICE_NODE_STEPS};
use crate::record::{Counters, Settings, SolveProfile, StageTimes};
use serde::Serialize;

/// CPU and wall time of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Timing {
    /// CPU time of the run's thread (stepping and recording, not output
    /// files), s: read from the thread CPU clock at the start and the end.
    pub cpu_total: f64,
    /// CPU time per stage, s: `cpu_total` split in the proportions of the
    /// stages' monotonic times ([`crate::record::clock`]).
    pub stages: StageTimes,
    /// CPU time outside the named stages (recording, bookkeeping), s.
    pub cpu_other: f64,
    /// Wall-clock time, s.
    pub wall: f64,
    /// Monotonic clock reads of the stage clock.
    pub clock_reads: u64,
    /// Estimated CPU time of those reads, s (reads × the measured cost of
    /// one read): the timer's own cost, included in `cpu_total`.
    pub timer_overhead: f64,
    /// The lattice stage's cost per impact and per node-step (runs whose
    /// impacts the lattices resolved, `impact = "lattice"`; absent
    /// otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lattice_cost: Option<LatticeCost>,
}

/// The CPU cost of the impacts resolved in the lattices (docs/physics.md
/// §9.10): the lattice stage's CPU time over the counters
/// `lattice_impacts` and `lattice_impact_node_steps`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct LatticeCost {
    /// CPU time per impact resolved in the lattices, s.
    pub per_impact: f64,
    /// CPU time per node-step of their integration (one velocity Verlet
    /// step of one node), s.
    pub per_node_step: f64,
}

impl LatticeCost {
    /// The cost of `cpu` (s, the lattice stage's) over the run's
    /// `counters`; `None` without an impact resolved in the lattices.
    pub fn of(cpu: f64, counters: &Counters) -> Option<LatticeCost> {
        let count = |c| counters.value(c).ok().flatten().unwrap_or(0.0);
        let impacts = count(&LATTICE_IMPACTS);
        let node_steps = count(&LATTICE_NODE_STEPS);
        (impacts > 0.0 && node_steps > 0.0).then(|| LatticeCost {
            per_impact: cpu / impacts,
            per_node_step: cpu / node_steps,
        })
    }
}

/// Everything `summary.json` says about a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSummary {
    /// Case name.
    pub case: String,
    /// Formulation name.
    pub formulation: String,
    /// Number of floes at the start.
    pub floes: usize,
    /// The case's fracture criterion (`energy`, `stress`), absent without
    /// fracture.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fracture_model: Option<&'static str>,
    /// Number of fractures (0 without a `[fracture]` table).
    pub fractures: usize,
    /// Number of floes at the end.
    pub floes_at_end: usize,
    /// Number of obstacles.
    pub obstacles: usize,
    /// Requested duration, s.
    pub duration: f64,
    /// The earlier run this one starts from (`run --from`), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restart: Option<crate::model::Restart>,
    /// Time reached, s.
    pub t_reached: f64,
    /// How the run ended.
    pub end: EndReason,
    /// Timing.
    pub timing: Timing,
    /// Energy totals.
    pub energy: EnergyTotals,
    /// The settings the formulation ran with, defaults resolved.
    pub settings: Settings,
    /// The formulation's counters (and the topology stage's: the lattice
    /// impacts', the crush stage's volumes and cuts).
    pub counters: Counters,
    /// What the crushed ice left on the coasts (runs with `[contact]
    /// crushing`; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crushing: Option<CrushingSummary>,
    /// The LCP solves by size (formulations that solve LCPs), seconds as
    /// CPU time (split like the stages).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lcp_profile: Option<SolveProfile>,
    /// The stepping counters per simulated hour (1/h): every counter whose
    /// name starts with `steps` (steps taken, rejected, cut by each kind of
    /// event), `integrator_steps`, `integrator_rejected_steps`,
    /// `events_located`, `impacts` and `lcp_solves`, divided by the time
    /// reached in hours ([`per_simulated_hour`]); empty at t = 0.
    pub per_simulated_hour: std::collections::BTreeMap<String, f64>,
}

/// What the crush stage left on the obstacles over a run (docs/physics.md
/// §10); its volumes and cuts are counters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CrushingSummary {
    /// The ice deposited on each obstacle, in the case's order.
    pub deposits: Vec<Deposit>,
}

/// The stepping counters of `counters` per simulated hour over `t` s (see
/// [`RunSummary::per_simulated_hour`]).
pub fn per_simulated_hour(counters: &Counters, t: f64) -> std::collections::BTreeMap<String, f64> {
    const ALSO: [&str; 5] = [
        "integrator_steps",
        "integrator_rejected_steps",
        "events_located",
        "impacts",
        "lcp_solves",
    ];
    if t.is_nan() || t <= 0.0 {
        return Default::default();
    }
    counters
        .iter()
        .filter(|(c, _)| c.name.starts_with("steps") || ALSO.contains(&c.name))
        .map(|(c, v)| (c.name.to_string(), v * 3600.0 / t))
        .collect()
}
