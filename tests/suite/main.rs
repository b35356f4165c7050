//! The integration tests, one binary (one link of the whole stack): one
//! module per area, and `common` for the helpers they share.
//!
//! `cargo test --release` runs them all; `cargo test --release --test suite
//! moreau::` runs one module.

mod common;

mod animation;
mod case_files;
mod case_warnings;
mod check;
mod cli;
mod cohesive;
mod compare;
mod contact;
mod crack_energy;
mod crushing;
mod crushing_geometry;
mod event_driven;
mod fc2d;
mod fc2d_bad;
mod fc2d_solve;
mod field;
mod flush_pair;
mod forces;
mod forcing;
mod fracture;
mod fuzz;
mod iterative;
mod lattice;
mod lattice_impact;
mod lattwire;
mod lemke;
mod moreau;
mod nonconvex;
mod open_contacts;
mod output_interval;
mod pair_impact;
mod percussion;
mod percussion2d;
mod physics;
mod plot;
mod predict;
mod projection;
mod rapier;
mod registry;
mod repeat;
mod runner;
mod sample_report;
mod sweep;
