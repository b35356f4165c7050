//! The fracture stage: the run's topology stage
//! ([`crate::formulation::context::Topology`]), owned by the
//! [`crate::run::Runner`], the one place where floes break
//! (docs/physics.md §9.5).
//!
//! Formulations report the impulses of their contact solves; the stage
//! asks the case's criterion ([`Fracturer`]) which floes break and where,
//! keeps the decisions until the formulation's next safe point, and then
//! splits the floes in the scenario, the state and the history together
//! ([`Fracturer::apply`]).

use super::{Decision, Fracturer, Load};
use crate::formulation::context::{Reads, Topology};
use crate::model::fracture::FractureModel;
use crate::model::Scenario;
use crate::state::System;

/// The fracture stage of one run (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct FractureStage {
    reads: Reads,
    fracturer: Fracturer,
    /// The decisions waiting for the next safe point, each with the kinetic
    /// energy (J) its solve removed, from which its crack energies are
    /// taken.
    pending: Vec<(Vec<Decision>, f64)>,
}

impl FractureStage {
    /// The stage of a run of `scn`: it reads nothing when the case has no
    /// `[fracture]` table (or `model = "none"`).
    pub fn new(scn: &Scenario) -> FractureStage {
        let enabled = scn.fracture.enabled();
        FractureStage {
            reads: Reads {
                percussions: enabled,
                sustained: enabled && scn.fracture.model == FractureModel::Stress,
            },
            ..FractureStage::default()
        }
    }

    /// The criterion's state (fractures made, percussions run).
    pub fn fracturer(&self) -> &Fracturer {
        &self.fracturer
    }

    fn decide(
        &mut self,
        scn: &Scenario,
        sys: &System,
        loads: &[Load],
        span: (f64, f64),
        dissipated: f64,
    ) {
        let decisions = self.fracturer.decide_over(scn, sys, loads, span.0, span.1);
        if !decisions.is_empty() {
            self.pending.push((decisions, dissipated));
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
            self.decide(scn, sys, loads, (from, to), dissipated);
        }
    }

    fn sustained(&mut self, scn: &Scenario, sys: &System, loads: &[Load], from: f64, to: f64) {
        // Sustained forces remove no kinetic energy of their own: their
        // crack energies are taken from nothing (the stress criterion's
        // are zero).
        if self.reads.sustained {
            self.decide(scn, sys, loads, (from, to), 0.0);
        }
    }

    fn pending(&self) -> bool {
        !self.pending.is_empty()
    }

    fn apply(&mut self, scn: &mut Scenario, sys: &mut System) -> Option<Vec<usize>> {
        if self.pending.is_empty() {
            return None;
        }
        let old = scn.floes.iter().map(|f| f.id).collect();
        for (decisions, dissipated) in std::mem::take(&mut self.pending) {
            self.fracturer.apply(scn, sys, &decisions, dissipated);
        }
        Some(old)
    }
}
