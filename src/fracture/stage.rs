//! The fracture stage: the run's topology stage
//! ([`crate::formulation::context::Topology`]), owned by the
//! [`crate::run::Runner`], the one place where floes break
//! (docs/physics.md §9.5).
//!
//! Formulations report the impulses of their contact solves; the stage
//! asks the case's criterion ([`Fracturer`]) which floes break and where,
//! keeps the decisions until the formulation's next safe point, and then
//! splits the floes in the scenario, the state and the history together
//! ([`Fracturer::apply`]). With `impact = "lattice"` it resolves the
//! impacts of one pair in the floes' lattices ([`super::impact`],
//! docs/physics.md §9.10), and the cracks of those impacts take their
//! energy from the vibration the lattices kept, not from `dissipated`.

use super::impact::{
    COUNTERS, LATTICE_FAILED, LATTICE_IMPACTS, LATTICE_MULTI_PAIR, LATTICE_NODE_STEPS,
    LATTICE_STEPS,
};
use super::{Decision, Fracturer, Load};
use crate::formulation::context::{ImpactAnswer, ImpactQuery, Reads, Topology};
use crate::model::fracture::FractureModel;
use crate::model::Scenario;
use crate::record::{Counters, StageClock};
use crate::state::System;

/// Where the crack energies of a pending decision come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Budget {
    /// The kinetic energy the solve removed, booked in `dissipated`.
    Dissipated,
    /// The vibration (and dashpot) energy of a lattice impact, booked in
    /// `vibration` (docs/physics.md §9.10).
    Vibration,
}

/// The fracture stage of one run (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct FractureStage {
    reads: Reads,
    fracturer: Fracturer,
    /// The decisions waiting for the next safe point, each with the kinetic
    /// energy (J) its solve removed, from which its crack energies are
    /// taken, and the column that holds it.
    pending: Vec<(Vec<Decision>, f64, Budget)>,
    /// The impact coupling's counters (none unless it reads impacts).
    counters: Counters,
}

impl FractureStage {
    /// The stage of a run of `scn`: it reads nothing when the case has no
    /// `[fracture]` table (or `model = "none"`).
    pub fn new(scn: &Scenario) -> FractureStage {
        let enabled = scn.fracture.enabled();
        let impacts = enabled && scn.fracture.lattice_impacts();
        FractureStage {
            reads: Reads {
                percussions: enabled,
                sustained: enabled && scn.fracture.model == FractureModel::Stress,
                impacts,
            },
            counters: Counters::new(if impacts { COUNTERS } else { &[] }),
            ..FractureStage::default()
        }
    }

    /// The criterion's state (fractures made, percussions run).
    pub fn fracturer(&self) -> &Fracturer {
        &self.fracturer
    }

    /// The floes of ids `ids` changed outline (the crush stage cut them,
    /// docs/physics.md §10): what the criterion kept of their shapes is
    /// forgotten.
    pub fn reshaped(&mut self, ids: &[usize]) {
        for &id in ids {
            self.fracturer.forget_shape(id);
        }
    }

    fn decide(
        &mut self,
        scn: &Scenario,
        sys: &System,
        loads: &[Load],
        span: (f64, f64),
        budget: (f64, Budget),
    ) {
        let decisions = self.fracturer.decide_over(scn, sys, loads, span.0, span.1);
        if !decisions.is_empty() {
            self.pending.push((decisions, budget.0, budget.1));
        }
    }
}

impl Topology for FractureStage {
    fn reads(&self) -> Reads {
        self.reads
    }

    fn percussion(
        &mut self,
        scn: &Scenario,
        sys: &System,
        loads: &[Load],
        from: f64,
        to: f64,
        dissipated: f64,
    ) {
        if self.reads.percussions {
            self.decide(
                scn,
                sys,
                loads,
                (from, to),
                (dissipated, Budget::Dissipated),
            );
        }
    }

    fn sustained(&mut self, scn: &Scenario, sys: &System, loads: &[Load], from: f64, to: f64) {
        // Sustained forces remove no kinetic energy of their own: their
        // crack energies are taken from nothing (the stress criterion's
        // are zero).
        if self.reads.sustained {
            self.decide(scn, sys, loads, (from, to), (0.0, Budget::Dissipated));
        }
    }

    fn impact(
        &mut self,
        scn: &Scenario,
        _sys: &System,
        query: &ImpactQuery,
    ) -> Option<ImpactAnswer> {
        if !self.reads.impacts {
            return None;
        }
        if query.pairs > 1 {
            self.counters.add(&LATTICE_MULTI_PAIR, 1);
            return None;
        }
        let Ok((answer, decisions, steps, nodes)) = self.fracturer.pair_impact(scn, query) else {
            self.counters.add(&LATTICE_FAILED, 1);
            return None;
        };
        self.counters.add(&LATTICE_IMPACTS, 1);
        self.counters.add(&LATTICE_STEPS, steps);
        self.counters
            .add(&LATTICE_NODE_STEPS, steps.saturating_mul(nodes));
        if !decisions.is_empty() {
            // The cracks' energies and the pieces' relative motion come out
            // of what the impact left in the lattices (docs/physics.md §9.10).
            let budget = answer.vibration + answer.dashpot;
            self.pending.push((decisions, budget, Budget::Vibration));
        }
        Some(answer)
    }

    fn counters(&self) -> Counters {
        self.counters.clone()
    }

    fn pending(&self) -> bool {
        !self.pending.is_empty()
    }

    fn apply(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        _: &mut StageClock,
    ) -> Option<Vec<usize>> {
        if self.pending.is_empty() {
            return None;
        }
        let old = scn.floes.iter().map(|f| f.id).collect();
        for (decisions, budget, source) in std::mem::take(&mut self.pending) {
            let kept = sys.ledger.dissipated;
            self.fracturer.apply(scn, sys, &decisions, budget);
            if source == Budget::Vibration {
                // What the cracks and the pieces' relative motion took
                // came out of the impact's vibration (docs/physics.md §9.10).
                sys.ledger.vibration -= kept - sys.ledger.dissipated;
                sys.ledger.dissipated = kept;
            }
        }
        Some(old)
    }
}
