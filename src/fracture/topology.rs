//! The run's topology stage: the fracture stage and the crush stage
//! together, with the forces stage that only reads ([`RunTopology`]), the
//! one [`Topology`] the [`crate::run::Runner`] hands its formulation.
//!
//! Each report goes to the stage that reads it (the solves' impulses and
//! impacts to fracture, the crushed pairs to crushing). At a safe point
//! the fractures are carried out first, then the crushing: a floe that
//! broke is no longer the floe whose overlap was reported, and its pieces'
//! overlaps are reported again by the next solve; a floe the crushing cut
//! has a new outline, so the fracture stage forgets what it kept of its
//! shape (its lattice, [`FractureStage::reshaped`]). The forces stage
//! ([`ForceStage`]) reads every solve's impulses too, and changes nothing:
//! it turns them into the forces on the obstacles and the pack's stress.

use super::crush::CrushStage;
use super::forces::ForceStage;
use super::stage::FractureStage;
use crate::contact::Load;
use crate::formulation::context::{ImpactAnswer, ImpactQuery, Reads, Topology};
use crate::model::Scenario;
use crate::record::{Counters, StageClock};
use crate::state::System;

/// The fracture stage and the crush stage of one run (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct RunTopology {
    /// Floes that break (docs/physics.md §9).
    pub fracture: FractureStage,
    /// Ice that crushes (docs/physics.md §10).
    pub crush: CrushStage,
    /// The forces on the obstacles and the pack's stress, per output
    /// interval (reads only).
    pub forces: ForceStage,
}

impl RunTopology {
    /// The stages of a run of `scn` (each does nothing when the case does
    /// not ask for it); its forces stage reads nothing until the runner
    /// sets one ([`ForceStage::new`], which needs the output times).
    pub fn new(scn: &Scenario) -> RunTopology {
        RunTopology {
            fracture: FractureStage::new(scn),
            crush: CrushStage::new(scn),
            forces: ForceStage::default(),
        }
    }
}

impl Topology for RunTopology {
    fn reads(&self) -> Reads {
        let reads = self.fracture.reads();
        let forces = self.forces.reads();
        Reads {
            percussions: reads.percussions || forces,
            sustained: reads.sustained || forces,
            ..reads
        }
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
        self.fracture
            .percussion(scn, sys, loads, from, to, dissipated);
        self.forces.load(scn, sys, loads, from, to);
    }

    fn sustained(&mut self, scn: &Scenario, sys: &System, loads: &[Load], from: f64, to: f64) {
        self.fracture.sustained(scn, sys, loads, from, to);
        self.forces.load(scn, sys, loads, from, to);
    }

    fn impact(
        &mut self,
        scn: &Scenario,
        sys: &System,
        query: &ImpactQuery,
    ) -> Option<ImpactAnswer> {
        self.fracture.impact(scn, sys, query)
    }

    fn crushed(&mut self, scn: &Scenario, sys: &System, pairs: &[(usize, usize)]) {
        self.crush.crushed(scn, sys, pairs);
    }

    fn counters(&self) -> Counters {
        let mut c = self.fracture.counters();
        c.absorb(&self.crush.counters());
        c
    }

    fn pending(&self) -> bool {
        self.fracture.pending() || self.crush.pending()
    }

    fn apply(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        clock: &mut StageClock,
    ) -> Option<Vec<usize>> {
        let fractured = self.fracture.apply(scn, sys, clock);
        let crushed = self.crush.apply(scn, sys, clock);
        self.fracture.reshaped(&self.crush.take_reshaped());
        // The ids before the fractures (the crushing keeps the ids).
        fractured.or(crushed)
    }
}
