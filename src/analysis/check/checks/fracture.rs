//! The checks of fracture (docs/physics.md §9; the table of the module doc
//! of [`crate::analysis::check`]): every split conserves, the critical
//! ramming speed, the lattice's neglected spin pre-stress.

use super::Rows;
use crate::analysis::check::exact::ram_critical_speed_of;
use crate::analysis::check::structure::{
    initial_polygon, no_forcing, self_symmetric, translation_gap,
};
use crate::analysis::check::{FRACTURE_CONSERVATION_TOLERANCE, RAM_CRITICAL_SPEED_TOLERANCE};
use crate::fracture::split::cut;
use crate::fracture::strike::{spin_prestress, SPIN_PRESTRESS_LIMIT};
use crate::geometry::Vec2;
use crate::model::fracture::lattice_spacing;
use crate::model::fracture::FractureModel;

pub(super) fn fracture_conservation(r: &mut Rows) {
    let fr = &r.run.fractures;
    if fr.is_empty() {
        return;
    }
    let worst = fr.iter().map(|f| f.conservation).fold(0.0, f64::max);
    r.push(
        "fracture_conservation",
        "every split conserves area, mass, momenta and kinetic energy",
        worst,
        Some(0.0),
        FRACTURE_CONSERVATION_TOLERANCE,
        "1",
        format!(
            "{} fractures, {} floes at the end",
            fr.len(),
            r.run.summary.floes_at_end
        ),
    )
    .scale = Some(1.0);
}

pub(super) fn ram_critical_speed(r: &mut Rows) {
    let scn = r.scn;
    // The closed form is that of a rigid impact with restitution: not of
    // ice that crushes (docs/physics.md §10.2).
    if scn.fracture.model != FractureModel::Energy
        || scn.contact.crushing.is_some()
        || scn.floes.len() != 1
        || !no_forcing(scn)
        || scn.floes[0].angular_velocity != 0.0
    {
        return;
    }
    let f = &scn.floes[0];
    let v0 = f.velocity.norm();
    if v0 == 0.0 {
        return;
    }
    let d = f.velocity / v0;
    if translation_gap(scn, 0, &d).is_none_or(|(_, rays)| rays < 2)
        || !self_symmetric(scn, f.position, d)
    {
        return;
    }
    let Some(chord) = cut(&initial_polygon(scn, 0), &f.position, &d) else {
        return;
    };
    let vc = ram_critical_speed_of(
        scn.fracture.toughness,
        f.thickness,
        chord.length,
        scn.contact.restitution,
        f.mass,
    );
    if v0 <= vc * (1.0 + RAM_CRITICAL_SPEED_TOLERANCE) {
        return;
    }
    let measured = r
        .run
        .fractures
        .first()
        .map_or(f64::NAN, |fr| v0 * (fr.threshold / fr.measure).sqrt());
    r.push(
        "ram_critical_speed",
        "the critical speed of a floe rammed into a coast (energy criterion)",
        measured,
        Some(vc),
        RAM_CRITICAL_SPEED_TOLERANCE * vc,
        "m/s",
        format!(
            "v0 = {v0} m/s, chord {:.6} m; {} fractures",
            chord.length,
            r.run.fractures.len()
        ),
    )
    .scale = Some(vc);
}

/// `lattice_spin_prestress`: the lattice model starts each percussion
/// unstressed, neglecting the floe's own spin (docs/physics.md §9.8); the
/// largest centrifugal pre-strain, over its bonds' breaking strain, of a
/// floe at its last output before a percussion that broke it (the
/// percussions that broke nothing are not in the run's records). A piece
/// that spins fast but is never struck again is not where the neglect
/// acts, so the floes alive at the outputs are not all taken.
pub(super) fn lattice_spin(r: &mut Rows) {
    let s = &r.scn.fracture;
    if s.model != FractureModel::Lattice {
        return;
    }
    let (mut worst, mut at) = (0.0, None);
    for fr in &r.run.fractures {
        let Some(f) = r.run.floes.iter().find(|f| f.id == fr.parent) else {
            continue;
        };
        // The parent's spin at its last output at or before the fracture.
        let Some(row) = r
            .run
            .trajectory
            .iter()
            .filter(|row| row.floe == fr.parent && row.t <= fr.t)
            .max_by(|a, b| a.t.total_cmp(&b.t))
        else {
            continue;
        };
        let radius = f
            .polygon
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(0.0, f64::max);
        let density = f.mass / (f.area * f.thickness);
        let shape: Vec<Vec2> = f.polygon.iter().map(|p| Vec2::new(p[0], p[1])).collect();
        let spacing = lattice_spacing(s, f.area, &shape);
        let ratio = spin_prestress(s, density, radius, row.omega, spacing);
        if at.is_none() || ratio > worst {
            (worst, at) = (ratio, Some((fr.parent, fr.t)));
        }
    }
    let note = match at {
        Some((floe, t)) => {
            format!("largest for floe {floe} broken at t = {t} s (its spin at the output before)")
        }
        None => "no fracture".to_string(),
    };
    r.push(
        "lattice_spin_prestress",
        "a floe's spin pre-stretches its lattice by little against its bonds' breaking strain when a percussion breaks it",
        worst,
        None,
        SPIN_PRESTRESS_LIMIT,
        "1",
        note,
    );
}
