//! # floebench
//!
//! A research benchmark for the contact mechanics of rigid polygonal sea-ice
//! floes. The same case files are solved by several contact formulations, and
//! their trajectories, dissipated energy and CPU time are compared.
//!
//! ```text
//! cases/*.toml ──load──▶ Scenario ──▶ Runner(formulation) ──▶ RunResult (trajectory, energy ledger, counters)
//!                                                                  │
//!        report (pages, tables, plots) ◀── analysis (checks, divergence, metrics) ◀──┘
//! ```
//!
//! LAYERS: each module imports only modules of its own layer or of the
//! layers before it (`python3 tools/arch/imports.py` lists the imports
//! that do not):
//!
//! 0. geometry, rng, fsio, stop, record, lcp: the foundations (polygons and the broad
//!    phase, the seeded generator, atomic file writes, the stop request polled
//!    inside long solves, the reporting vocabulary, LCPs and their solvers);
//! 1. model: pure data (floes, cases, fields, forcing, limits, material
//!    constants) and its input readers (case files, CF NetCDF forcing,
//!    Siconos' 2D frictional contact problem files);
//! 2. contact: detection and the contact problems;
//! 3. state: the dynamic state, kinematics and the energy ledger;
//! 4. physics: the force law and the smooth integrator;
//! 5. iterative: the iterative contact solvers;
//! 6. formulation: the formulations and their registry;
//! 7. fracture: floes that break, and the ice that crushes at their contacts
//!    (the crush stage, `fracture::crush`; the run's topology, fracture then crushing,
//!    with the forces stage that only reads, `fracture::forces`: the force on each
//!    obstacle and the pack's stress);
//! 8. run: the runner, the output writers, the batch;
//! 9. analysis: checks, divergences, metrics;
//! 10. compare, sweep: the comparison harness, work–precision sweeps;
//! 11. report: everything written for people;
//! 12. cli: the command line, the binary: `src/main.rs` parses the
//!     arguments and `src/cli/` holds one module per command (its clap
//!     arguments and its `run`), calling this library; only it writes
//!     reports.
//!
//! - [`model`]: the case file (and its CF NetCDF forcing), validated into a [`model::Scenario`] (floes,
//!   obstacles, environment, contact law, settings); [`model::fc2d`] reads Siconos' 2D
//!   frictional contact problems;
//! - [`geometry`]: convex polygons, mass properties (the one vector type, [`geometry::Vec2`]),
//!   the sweep-and-prune broad phase;
//! - [`fsio`]: atomic file writes (temporary file, then rename), the probe of an output folder;
//! - [`stop`]: the stop request (SIGINT, SIGTERM) and its poll inside long solves;
//! - [`contact`]: shared contact detection (sweep and prune, convex polygon contact points);
//! - [`lcp`]: linear complementarity problems, our Lemke solver with fallbacks, dumps;
//! - [`iterative`]: the iterative contact solvers of dense packs (NSGS, APGD) on the sparse
//!   contact problem, the contact cache and the natural-map residual of every solver's answer;
//! - [`physics`]: environment forces and the smooth integrator;
//! - [`state`]: the dynamic state and the energy ledger;
//! - [`record`]: what formulations report with: typed counters and settings, the contact log, the stage clock,
//!   the spread of repeated measurements;
//! - [`formulation`]: the [`formulation::Formulation`] trait, the registry ([`formulation::REGISTRY`]) and the formulations;
//! - [`run`]: the [`run::Runner`] (timing, stopping, recording), output files, and the batch
//!   runner ([`run::batch`]: every formulation on every case on a pool of threads);
//! - [`analysis`]: what the runs say: the physical checks ([`analysis::check`]), the divergence
//!   of two runs, every figure in long format, the comparison of one case;
//! - [`compare`]: the comparison harness (the batch, then each case's comparison);
//! - [`sweep`]: work–precision sweeps (plans of cases × formulations × settings, their
//!   points run locally or as a Slurm job array, error measures, convergence orders);
//! - [`report`]: everything written for people: the comparison report (data files, plots,
//!   page), verdicts, tables, the one number formatter ([`report::format::fmt_num`]).
//!
//! All quantities are SI and `f64`.

#![warn(missing_docs)]

pub mod analysis;
pub mod compare;
pub mod contact;
pub mod formulation;
pub mod fracture;
pub mod fsio;
pub mod geometry;
pub mod iterative;
pub mod lcp;
pub mod model;
pub mod physics;
pub mod record;
pub mod report;
pub mod rng;
pub mod run;
pub mod state;
pub mod stop;
pub mod sweep;
