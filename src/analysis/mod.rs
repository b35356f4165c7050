//! Analysis of recorded runs: what the numbers say, before any is printed.
//!
//! - [`check`]: the physical checks with exact answers (docs/physics.md §6)
//!   that every formulation is held to;
//! - [`divergence`]: how two runs of the same case differ over time;
//! - [`metrics`]: every figure of a run and of a pair of runs, in long format;
//! - [`comparison`]: one case's runs with their divergences, figures and checks;
//! - [`chaos`]: whether a case is chaotic (the growth of a 1e-12 perturbation);
//! - [`floe_sizes`]: the floe-size distribution of a fracture case, at the
//!   start and at the end of every run;
//! - the spread of repeated measurements (CPU times) is [`crate::record::spread`];
//! - [`ranking`]: formulations ranked by a figure, with ties (errors to exact
//!   answers, dissipation, CPU time).

pub mod chaos;
pub mod check;
pub mod comparison;
pub mod divergence;
pub mod floe_sizes;
pub mod metrics;
pub mod ranking;
