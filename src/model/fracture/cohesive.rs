//! The cohesive rule's keys in the `[fracture]` table (docs/case-format.md;
//! docs/physics.md §7.3, "The cohesive rule"): `strength` goes with
//! `rule = "cohesive"`, and the lattice spacing must be fine enough for the
//! crack band.

use super::{lattice_spacing, FractureModel, FractureSettings, LatticeRule};
use crate::model::settings::SettingsTable;
use crate::model::{CaseError, Floe};

/// The strain at which a bond of the equilateral lattice reaches the peak
/// force `σ_t h w` of the cohesive rule, for a tensile strength `strength`
/// (Pa), Young's modulus `young` (Pa) and Poisson ratio `poisson`
/// (docs/physics.md §7.3): `σ_t (1 − ν) / E` (its bond `κ = E h /
/// (√3 (1 − ν))`, its facet `w = s/√3`).
pub fn cohesive_onset_strain(strength: f64, young: f64, poisson: f64) -> f64 {
    strength * (1.0 - poisson) / young
}

/// The coarsest spacing (m) at which the bonds of the equilateral lattice
/// soften under the cohesive rule (docs/physics.md §7.3): the elastic
/// opening at the peak, `σ_t (1 − ν) s / E`, below the opening
/// `δ_f = 2 G / σ_t` at which the bond has softened to nothing, i.e.
/// `s < 2 E G / ((1 − ν) σ_t²)`; coarser, the softening branch would snap
/// back.
pub fn cohesive_max_spacing(toughness: f64, strength: f64, young: f64, poisson: f64) -> f64 {
    2.0 * toughness / strength / cohesive_onset_strain(strength, young, poisson)
}

impl FractureSettings {
    /// The key `strength` (its value if given) goes with `rule = "cohesive"`, which
    /// needs it with the lattice model, and every floe's lattice spacing
    /// must be fine enough for the crack band ([`cohesive_max_spacing`]).
    pub(super) fn check_cohesive(
        &mut self,
        t: &SettingsTable,
        floes: &[Floe],
        strength: Option<f64>,
    ) -> Result<(), CaseError> {
        let cohesive = self.rule == LatticeRule::Cohesive;
        match strength {
            Some(_) if !cohesive => {
                return Err(t.error(
                    Some("strength"),
                    "strength is the tensile strength of rule = \"cohesive\"; set rule = \"cohesive\" or remove it",
                ))
            }
            Some(v) => self.strength = v,
            None if cohesive && self.model == FractureModel::Lattice => {
                return Err(t.error(
                    Some("rule"),
                    "rule = \"cohesive\" needs strength (the ice's tensile strength, Pa: about 0.2–0.8 MPa for sea ice)",
                ))
            }
            None => {}
        }
        if !cohesive || self.model != FractureModel::Lattice {
            return Ok(());
        }
        let max = cohesive_max_spacing(self.toughness, self.strength, self.young, self.poisson);
        for (i, f) in floes.iter().enumerate() {
            let spacing = lattice_spacing(self, f.area, &f.shape);
            if spacing >= max {
                let key = if self.spacing.is_some() {
                    "spacing"
                } else {
                    "strength"
                };
                return Err(t.error(
                    Some(key),
                    format!(
                        "rule = \"cohesive\": floe {i}'s lattice spacing {spacing} m is too coarse for the crack band: a bond's elastic opening at its peak, σ_t (1 − ν) s / E = {:.3e} m, is past the opening 2 G / σ_t = {:.3e} m at which it has softened to nothing (snap-back); set spacing below 2 E G / ((1 − ν) σ_t²) = {max:.4} m, or strength below {:.0} Pa",
                        cohesive_onset_strain(self.strength, self.young, self.poisson) * spacing,
                        2.0 * self.toughness / self.strength,
                        self.strength * (max / spacing).sqrt(),
                    ),
                ));
            }
        }
        Ok(())
    }
}
