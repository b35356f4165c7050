//! # floebench
//!
//! A research benchmark for the contact mechanics of rigid polygonal sea-ice
//! floes. The same case files are solved by several contact formulations, and
//! their trajectories, dissipated energy and CPU time are compared.
//!
//! ```text
//! cases/*.toml ──load──▶ Scenario ──▶ Runner(formulation) ──▶ RunResult (trajectory, energy ledger, counters)
//!                                                   │
//!                             compare / check / report / plot / bench ◀──┘
//! ```
//!
//! - [`model`]: the case file, validated into a [`model::Scenario`] (floes,
//!   obstacles, environment, contact law, settings);
//! - [`geometry`]: convex polygons, mass properties (the one vector type, [`geometry::Vec2`]);
//! - [`contact`]: shared contact detection (sweep and prune, convex polygon contact points);
//! - [`lcp`]: linear complementarity problems, our Lemke solver with fallbacks, dumps;
//! - [`physics`]: environment forces and the smooth integrator;
//! - [`state`]: the dynamic state and the energy ledger;
//! - [`record`]: what formulations report with: typed counters and settings, the contact log, the stage clock;
//! - [`formulation`]: the [`formulation::Formulation`] trait, the registry ([`formulation::REGISTRY`]) and the formulations;
//! - [`run`]: the [`run::Runner`] (timing, stopping, recording) and output files;
//! - [`compare`]: the comparison harness (parallel runs, metrics, report page);
//! - [`report`]: plots (line charts, stacked bars, plan views, snapshot grids) for the reports;
//! - [`analysis`]: the physical checks of a run ([`analysis::check`]).
//!
//! All quantities are SI and `f64`.

#![warn(missing_docs)]

pub mod analysis;
pub mod compare;
pub mod contact;
pub mod formulation;
pub mod geometry;
pub mod lcp;
pub mod model;
pub mod physics;
pub mod record;
pub mod report;
pub mod rng;
pub mod run;
pub mod state;
