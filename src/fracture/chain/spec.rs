//! What a 1D percussion is given: the material of the bars
//! ([`Material`]), each bar ([`BarSpec`]), when a bond breaks
//! ([`BondRule`], shared with the 2D lattice) and the options of a run
//! ([`ChainOptions`]).

use super::{positive, Cohesive};

/// The material of every bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Density, kg/m³.
    pub density: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Cross-section, m².
    pub area: f64,
}

impl Default for Material {
    /// Sea ice: the project's density (917 kg/m³), Balasoiu's Young's
    /// modulus (8.95 GPa), a unit cross-section.
    fn default() -> Self {
        Material {
            density: crate::model::DEFAULT_ICE_DENSITY,
            young: 8.95e9,
            area: 1.0,
        }
    }
}

impl Material {
    /// Wave speed `√(E/ρ)`, m/s.
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    /// Impedance of the bar `A √(E ρ)` (= `√(k m)` of its chain), N·s/m.
    pub fn impedance(&self) -> f64 {
        self.area * (self.young * self.density).sqrt()
    }
}

/// One bar: placed after the previous one, touching it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarSpec {
    /// Length, m.
    pub length: f64,
    /// Number of masses (cells).
    pub nodes: usize,
    /// Initial velocity along the line, m/s.
    pub velocity: f64,
}

/// When a bond breaks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BondRule {
    /// Never.
    Unbreakable,
    /// When its tension force `k δ` (elastic part) passes this force, N:
    /// `δ_c = F_c / k`, independent of the resolution.
    Force(f64),
    /// When the energy it holds, `½ k δ²`, passes `G A` (J, `G` the
    /// fracture toughness in J/m², this value): `δ_c = √(2 G A / k)`. This
    /// is the origin report's tenacity rule `δ_c = √(2 T L₀ / k)` with
    /// `T = G A / L₀` (J/m); its critical stress `√(2 G E / Δx)` grows as
    /// the cells shrink, as Griffith's does with a crack of length `Δx`.
    Toughness(f64),
    /// When its elongation passes this strain (-) times its rest length:
    /// `δ_c = ε_c L₀`. With a toughness this is `ε_c = √(2 G A / (k L₀²))`,
    /// which grows as the cells shrink (docs/physics.md §7.4).
    Strain(f64),
    /// The cohesive (crack-band) bond of the 2D lattice ([`Cohesive`],
    /// docs/physics.md §7.3): elastic up to the force `σ_t A`, then
    /// softening linearly to nothing at the opening `δ_f = 2 G / σ_t`,
    /// where it breaks having taken `G A`; a bond too coarse to soften
    /// (`σ_t A / k ≥ δ_f`) breaks by the toughness rule.
    Cohesive {
        /// `G`, J/m².
        toughness: f64,
        /// The tensile strength `σ_t`, Pa.
        strength: f64,
    },
}

impl BondRule {
    /// The critical elongation (m) of a bond of stiffness `k` (N/m), rest
    /// length `rest` (m), opening a section of area `section` (m²) when it
    /// breaks: `∞`, `F_c/k`, `√(2 G A/k)` or `ε_c L₀`; for a cohesive
    /// bond `δ_f = 2 G / σ_t`, or the toughness rule's when it cannot
    /// soften ([`Cohesive::new`]).
    pub fn critical(&self, k: f64, rest: f64, section: f64) -> f64 {
        match *self {
            BondRule::Unbreakable => f64::INFINITY,
            BondRule::Force(f) => f / k,
            BondRule::Toughness(g) => (2.0 * g * section / k).sqrt(),
            BondRule::Strain(e) => e * rest,
            BondRule::Cohesive {
                toughness,
                strength,
            } => Cohesive::new(k, section, toughness, strength).map_or_else(
                || BondRule::Toughness(toughness).critical(k, rest, section),
                |c| c.fail,
            ),
        }
    }

    /// Checks that its parameter is finite and positive.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            BondRule::Unbreakable => Ok(()),
            BondRule::Force(f) => positive("bond strength", f),
            BondRule::Toughness(g) => positive("toughness", g),
            BondRule::Strain(e) => positive("critical strain", e),
            BondRule::Cohesive {
                toughness,
                strength,
            } => positive("toughness", toughness).and(positive("strength", strength)),
        }
    }
}

/// The options of a 1D percussion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainOptions {
    /// Dashpot ratio `β` (-): `c = β √(k m)`. Default 0.5, the value with
    /// which the spall threshold converges with resolution (0 = no dashpots).
    pub damping: f64,
    /// When bonds break. Default: never.
    pub bond: BondRule,
    /// Safety factor on the stable step (-), in (0, 1]. Default 0.9.
    pub safety: f64,
    /// Internal energy, as a fraction of the initial energy, under which the
    /// waves have settled (-). Default 1e-3.
    pub settle: f64,
    /// Transit times of the longest bar after the contact ended after which
    /// the run stops even if the waves ring on (-). Default 4.
    pub settle_transits: f64,
    /// Transit times of the longest bar after which the run stops in any
    /// case (-). Default 200.
    pub limit_transits: f64,
}

impl Default for ChainOptions {
    fn default() -> Self {
        ChainOptions {
            damping: 0.5,
            bond: BondRule::Unbreakable,
            safety: 0.9,
            settle: 1e-3,
            settle_transits: 4.0,
            limit_transits: 200.0,
        }
    }
}

impl ChainOptions {
    /// Checks the options (the 2D percussion shares them).
    pub fn validate(&self) -> Result<(), String> {
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(format!(
                "damping must be finite and >= 0, got {}",
                self.damping
            ));
        }
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return Err(format!("safety must be in (0, 1], got {}", self.safety));
        }
        positive("settle", self.settle)?;
        positive("settle_transits", self.settle_transits)?;
        positive("limit_transits", self.limit_transits)?;
        self.bond.validate()
    }
}
