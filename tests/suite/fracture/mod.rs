//! Floes that break (docs/physics.md §9): the split conserves what it must,
//! the stress measure has its closed forms, the `[fracture]` table is
//! validated, `model = "none"` is no fracture, and the energy criterion's
//! critical ramming speed is its closed form.
//!
//! This file holds what the submodules share: the relative difference and
//! the ram case `RAM` (also used by `cohesive::`). The tests are in the
//! submodules, one topic each.

mod energy_criterion;
mod outputs;
mod split;
mod stress_criterion;
mod stress_measure;
mod table;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

/// A 10 m square rammed into a coast at `SPEED` (also `cohesive::`).
pub(crate) const RAM: &str = r#"
[case]
version = 1
name = "ram"
duration = 4.0
output_interval = 0.5

[contact]
restitution = 0.5
friction = 0.0

[[floe]]
polygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
thickness = 1.0
velocity = [SPEED, 0.0]

[[obstacle]]
polygon = [[10.02, -50.0], [30.0, -50.0], [30.0, 60.0], [10.02, 60.0]]

[formulation.moreau]
step = 0.5
"#;
