//! The reporting vocabulary: what a formulation reports with, below both
//! the formulations and the [`crate::run::Runner`] that drives them.
//!
//! - [`counters`]: typed counters, each declared once with its unit
//!   ([`Counter`]), and the settings a formulation ran with ([`Settings`]),
//!   reported apart from the counters;
//! - [`log`]: the bounded log of contact impulses and contact events
//!   ([`ContactLog`], [`ImpulseRecord`], [`ContactEvent`]);
//! - [`clock`]: CPU time per stage ([`StageClock`]) of the stages of
//!   [`stage`] ([`Stage`], [`StageTimes`]);
//! - [`profile`]: LCP solves by size ([`SolveProfile`]);
//! - [`accuracy`]: the residual and work of every contact solve ([`accuracy::Accuracy`]);
//! - [`spread`]: median and spread of repeated measurements (CPU times, [`spread::Spread`]).

pub mod accuracy;
pub mod clock;
pub mod counters;
pub mod log;
pub mod profile;
pub mod spread;
pub mod stage;

pub use clock::{thread_cpu_seconds, Stage, StageClock, StageTimes};
pub use counters::{
    Counter, CounterKind, Counters, Setting, SettingValue, Settings, Unit, UnknownCounter,
};
pub use log::{ContactEvent, ContactLog, ImpulseRecord, Overflow, COULOMB_SLACK};
pub use profile::SolveProfile;
