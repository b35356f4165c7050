//! The `[fracture]` table's choices (docs/case-format.md): the criterion,
//! the yield curve, the lattice's bond rule, mesh and trigger, and the
//! impact law, each read from its string with a clear refusal.

use serde::Serialize;

/// Which fracture criterion a run uses (docs/physics.md §9.2, §9.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FractureModel {
    /// No floe breaks (the default, and an absent table).
    #[default]
    None,
    /// The impulse energy of a contact solve against `G h L` (§9.2).
    Energy,
    /// The floe-averaged stress against a yield curve (§9.3).
    Stress,
    /// The percussion of each triggered impact in the struck floe's
    /// mass–spring lattice; its broken bonds give the pieces (§9.8).
    Lattice,
}

impl FractureModel {
    /// The name as written in the case file and in `fractures.csv`.
    pub fn name(self) -> &'static str {
        match self {
            FractureModel::None => "none",
            FractureModel::Energy => "energy",
            FractureModel::Stress => "stress",
            FractureModel::Lattice => "lattice",
        }
    }
}

impl std::str::FromStr for FractureModel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "none" => Ok(FractureModel::None),
            "energy" => Ok(FractureModel::Energy),
            "stress" => Ok(FractureModel::Stress),
            "lattice" => Ok(FractureModel::Lattice),
            other => Err(format!(
                "model = \"{other}\" is not a fracture model; expected \"none\", \"energy\", \"stress\" or \"lattice\""
            )),
        }
    }
}

/// The yield curve of the stress criterion (docs/physics.md §9.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum YieldCurve {
    /// Mohr–Coulomb in principal stresses (the default, as in SubZero).
    #[default]
    Mohr,
    /// Hibler's (1979) elliptical curve.
    Hibler,
}

impl std::str::FromStr for YieldCurve {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "mohr" => Ok(YieldCurve::Mohr),
            "hibler" => Ok(YieldCurve::Hibler),
            other => Err(format!(
                "yield = \"{other}\" is not a yield curve; expected \"mohr\" or \"hibler\""
            )),
        }
    }
}

/// The bond rule of the lattice model (docs/physics.md §7.3, §9.8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LatticeRule {
    /// A bond breaks when the energy it holds reaches `G h w` (`toughness`).
    #[default]
    Toughness,
    /// A bond breaks when its strain passes `critical_strain`.
    Strain,
    /// A cohesive (crack-band) bond: elastic up to the tensile `strength`,
    /// then softening linearly to nothing, having taken `G h w`
    /// (`toughness`).
    Cohesive,
}

impl std::str::FromStr for LatticeRule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "toughness" => Ok(LatticeRule::Toughness),
            "strain" => Ok(LatticeRule::Strain),
            "cohesive" => Ok(LatticeRule::Cohesive),
            other => Err(format!(
                "rule = \"{other}\" is not a bond rule; expected \"toughness\", \"strain\" or \"cohesive\""
            )),
        }
    }
}

/// The lattice model's mesh (docs/physics.md §7.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LatticeMesh {
    /// A seeded Poisson-disc set: disordered and isotropic; `seed` draws
    /// it.
    #[default]
    Random,
    /// An equilateral triangular lattice along x, without disorder: the
    /// mesh of convergence studies (its offset is the `seed`-th of the
    /// variants, §7.2).
    Triangular,
}

impl std::str::FromStr for LatticeMesh {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "random" => Ok(LatticeMesh::Random),
            "triangular" => Ok(LatticeMesh::Triangular),
            other => Err(format!(
                "mesh = \"{other}\" is not a lattice mesh; expected \"random\" or \"triangular\""
            )),
        }
    }
}

/// When the lattice model resolves an impact in the lattice (docs/physics.md §9.8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Trigger {
    /// Only when the impact energy bound reaches the floe's weakest bond.
    #[default]
    Bound,
    /// Every impact (for validation of the bound).
    Always,
}

impl std::str::FromStr for Trigger {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "bound" => Ok(Trigger::Bound),
            "always" => Ok(Trigger::Always),
            other => Err(format!(
                "trigger = \"{other}\" is not a trigger; expected \"bound\" or \"always\""
            )),
        }
    }
}

/// What sets the floes' velocities after an impact (docs/physics.md §9.10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ImpactLaw {
    /// The formulation's rigid law (Poisson's or Newton's, with the case's
    /// `restitution`): the default, and the only law before §9.10.
    #[default]
    Rigid,
    /// The two floes' lattices in unilateral contact, run until they
    /// separate ([`crate::fracture::lattice::pair`]): for each impact of a
    /// single pair, their rigid motions after it replace the rigid law's.
    Lattice,
}

impl ImpactLaw {
    /// The names as written in the case file.
    pub const NAMES: [&'static str; 2] = ["rigid", "lattice"];

    /// The name as written in the case file.
    pub fn name(self) -> &'static str {
        match self {
            ImpactLaw::Rigid => "rigid",
            ImpactLaw::Lattice => "lattice",
        }
    }
}

impl std::str::FromStr for ImpactLaw {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "rigid" => Ok(ImpactLaw::Rigid),
            "lattice" => Ok(ImpactLaw::Lattice),
            other => {
                let hint = crate::model::case::closest(other, &ImpactLaw::NAMES)
                    .map_or(String::new(), |k| format!(" (did you mean \"{k}\"?)"));
                Err(format!(
                    "impact = \"{other}\" is not an impact law{hint}; expected \"rigid\" or \"lattice\""
                ))
            }
        }
    }
}
