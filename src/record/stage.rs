//! The stages of the CPU breakdown ([`Stage`]) and the seconds spent in
//! each ([`StageTimes`]), as the stage clock ([`super::clock`]) charges
//! them and `summary.json`'s `timing.stages` reports them.

use serde::Serialize;

/// The stages of a step, after rapier's pipeline: detect, solve, integrate;
/// and the impacts resolved in the floes' lattices (`[fracture] impact =
/// "lattice"`, docs/physics.md §9.10), charged apart from the solve that
/// calls them; and the crush stage's cuts (`[contact] crushing`,
/// docs/physics.md §10).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Contact detection: broad and narrow phase, event location.
    Detection,
    /// Contact problems: assembly and solution (LCP, cone program, …).
    Solve,
    /// Smooth integration of the environment forces.
    Integration,
    /// Impacts resolved in the pair's lattices (nested in a solve region:
    /// its time is taken out of the solve's,
    /// [`super::StageClock::stop`]).
    Lattice,
    /// The crush stage's cuts of the crushed ice (at a safe point).
    Crushing,
}

/// Seconds spent in each stage (CPU time once split, monotonic time while
/// the clock runs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct StageTimes {
    /// Contact detection, s.
    pub detection: f64,
    /// Contact solve, s.
    pub solve: f64,
    /// Smooth integration, s.
    pub integration: f64,
    /// Impacts resolved in the lattices, s (zero without `impact =
    /// "lattice"`).
    pub lattice: f64,
    /// The crush stage's cuts, s (zero without `[contact] crushing`).
    pub crushing: f64,
}

impl StageTimes {
    /// The sum of the stages, s.
    pub fn total(&self) -> f64 {
        self.detection + self.solve + self.integration + self.lattice + self.crushing
    }

    pub(super) fn slot(&mut self, stage: Stage) -> &mut f64 {
        match stage {
            Stage::Detection => &mut self.detection,
            Stage::Solve => &mut self.solve,
            Stage::Integration => &mut self.integration,
            Stage::Lattice => &mut self.lattice,
            Stage::Crushing => &mut self.crushing,
        }
    }
}
