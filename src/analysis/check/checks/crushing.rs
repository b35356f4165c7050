//! The checks of crushing ice against its closed forms (docs/physics.md
//! §10.3; the table of the module doc of [`crate::analysis::check`]): a
//! floe rammed into a straight coast with a corner (`crush_volume`,
//! `crush_peak_force`, `crush_duration`) or a flat face (`crush_volume`,
//! `crush_force`, `crush_duration`), the ice crushing at a constant
//! strength and all the normal kinetic energy crushed (`e = 0`); the set-up
//! and its measures are [`crate::analysis::check::Ram`]'s.
//!
//! Measures on the run: the crushed volume its summary counts
//! (`crushed_volume_m3`); the largest mean force of an output interval;
//! the time from the first contact to the stop.

use super::Rows;
use crate::analysis::check::ram::{Ram, RamShape};
use crate::analysis::check::{CRUSH_FORCE_TOLERANCE, CRUSH_MASS_TOLERANCE, CRUSH_VOLUME_TOLERANCE};

/// The counter of the crushed volume, m³.
const CRUSHED_VOLUME: &str = "crushed_volume_m3";

/// `crush_mass`: the mass of the floes at the end plus the ice deposited on
/// the coasts, against the case's (every run with crushing; the crushed
/// ice that ridged is in the floes' thickness).
pub(super) fn crush_mass(r: &mut Rows) {
    if r.scn.contact.crushing.is_none() {
        return;
    }
    let initial: f64 = r.scn.floes.iter().map(|f| f.mass).sum();
    let alive: f64 = r
        .run
        .floes
        .iter()
        .filter(|f| f.t_end.is_none())
        .map(|f| f.mass)
        .sum();
    let deposited: f64 = r
        .run
        .summary
        .crushing
        .as_ref()
        .map_or(0.0, |c| c.deposits.iter().map(|d| d.mass_kg).sum());
    r.push(
        "crush_mass",
        "mass is conserved by crushing: floes at the end plus the ice deposited on coasts",
        ((alive + deposited - initial) / initial).abs(),
        None,
        CRUSH_MASS_TOLERANCE,
        "1",
        format!("{initial} kg at the start; {deposited} kg deposited on coasts"),
    );
}

pub(super) fn crushing(r: &mut Rows) {
    let Some(ram) = Ram::of(r.scn) else {
        return;
    };
    let (volume, force, duration) = ram.exact();
    let what = match ram.shape {
        RamShape::Corner(phi) => format!("a corner of {phi:.6} rad"),
        RamShape::Face(w) => format!("a face {w:.6} m wide"),
    };
    let measured = r
        .run
        .summary
        .counters
        .by_name(CRUSHED_VOLUME)
        .ok()
        .flatten()
        .unwrap_or(f64::NAN);
    r.push(
        "crush_volume",
        "the volume of ice crushed by a floe rammed into a coast",
        measured,
        Some(volume),
        CRUSH_VOLUME_TOLERANCE * volume,
        "m^3",
        format!("{what}, V = {} m/s, {}", ram.v0, law_text(&ram.law)),
    )
    .scale = Some(volume);
    let peak = ram
        .interval_forces(r.run)
        .iter()
        .map(|p| p.1)
        .fold(0.0, f64::max);
    let (name, description) = match ram.shape {
        RamShape::Corner(_) => (
            "crush_peak_force",
            "the peak crushing force of a corner rammed into a coast",
        ),
        RamShape::Face(_) => (
            "crush_force",
            "the constant crushing force of a face against a coast",
        ),
    };
    r.push(
        name,
        description,
        peak,
        Some(force),
        CRUSH_FORCE_TOLERANCE * force,
        "N",
        format!("{what}: mean force of each output interval"),
    )
    .scale = Some(force);
    r.push(
        "crush_duration",
        "the time a floe rammed into a coast takes to stop crushing",
        ram.stop_time(r.run),
        Some(duration),
        CRUSH_FORCE_TOLERANCE * duration,
        "s",
        format!("{what}: from the first contact at t = {} s", ram.t_contact),
    )
    .scale = Some(duration);
}

/// The crushing law in words, for a check's note.
fn law_text(law: &crate::model::Crushing) -> String {
    match *law {
        crate::model::Crushing::Strength { strength } => format!("sigma_c = {strength} Pa"),
        crate::model::Crushing::PressureArea { p0, exponent } => {
            format!("p = {p0} Pa x A^{exponent}")
        }
    }
}
