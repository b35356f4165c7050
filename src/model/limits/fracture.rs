//! The limits of the `[fracture]` table (docs/case-format.md, "Limits";
//! the table is read by [`crate::model::fracture::FractureSettings`]) and
//! the material bounds they rest on: the Poisson ratios a lattice of
//! springs and torsion springs reaches (docs/physics.md §7.2), which the
//! lattice model ([`crate::fracture::lattice`]) checks too.

use super::Limit;

/// The Poisson ratio of central springs alone (the Cauchy relation
/// `λ = μ`), the largest a lattice of springs and torsion springs has: 1/3.
pub const POISSON_MAX: f64 = 1.0 / 3.0;

/// The lower bound (excluded) of the Poisson ratio: −1, where the torsion
/// stiffness would be infinite (the 2D isotropic stability bound
/// `λ + μ > 0`, `μ > 0`).
pub const POISSON_MIN: f64 = -1.0;

/// `young`: Young's modulus of the lattice model, Pa.
pub const YOUNG: Limit = Limit::range(
    "young",
    "[fracture]",
    1e6,
    1e12,
    "Pa",
    "from slush-like 1 MPa to above any ice (about 1e10 Pa)",
);
/// `damping`: the dashpot ratio `β` of the lattice model.
pub const DAMPING: Limit = Limit::range(
    "damping",
    "[fracture]",
    0.0,
    10.0,
    "",
    "0 is no dashpot; 10 is far past critical damping of a bond",
);
/// `poisson`: the Poisson ratio of the lattice model (torsion springs below
/// 1/3; docs/physics.md §7.2).
pub const POISSON: Limit = Limit::range(
    "poisson",
    "[fracture]",
    POISSON_MIN,
    POISSON_MAX,
    "",
    "a 2D lattice of central and torsion springs reaches (-1, 1/3]; sea ice is about 0.3",
)
.exclusive_min();
/// `spacing`: the lattice spacing of the lattice model, m.
pub const SPACING: Limit = Limit::range(
    "spacing",
    "[fracture]",
    1e-3,
    1e5,
    "m",
    "a millimetre to 100 km; a floe's lattice needs a few nodes across (with impact = \"lattice\", at least 3 across its narrowest width w: spacing <= w / 2, which the default satisfies)",
)
.exclusive_min();
/// `critical_strain`: the bond strain of `rule = "strain"`.
pub const CRITICAL_STRAIN: Limit = Limit::range(
    "critical_strain",
    "[fracture]",
    0.0,
    1.0,
    "",
    "a strain; ice breaks at about 1e-4",
)
.exclusive_min();
/// `strength`: the tensile strength `σ_t` of `rule = "cohesive"`, Pa.
pub const STRENGTH: Limit = Limit::range(
    "strength",
    "[fracture]",
    0.0,
    1e9,
    "Pa",
    "sea ice's tensile strength is 0.2–0.8 MPa; 1 GPa is above any ice",
)
.exclusive_min();
/// `seed`: the seed of the lattices' Poisson-disc sampling.
pub const SEED: Limit = Limit::range(
    "seed",
    "[fracture]",
    0.0,
    9.007_199_254_740_992e15,
    "",
    "a non-negative integer that a double holds exactly",
)
.integers();

/// `toughness`: the fracture energy `G` of sea ice, J/m².
pub const TOUGHNESS: Limit = Limit::range(
    "toughness",
    "[fracture]",
    1e-3,
    1e6,
    "J/m^2",
    "the physical 1.5–3.5 J/m² and FloeDyn's ×5000 (1.25e4) both fit",
)
.exclusive_min();
/// `min_area`: a floe smaller than this never breaks, m².
pub const MIN_AREA: Limit = Limit::range(
    "min_area",
    "[fracture]",
    0.0,
    1e14,
    "m^2",
    "the area of a 10 000 km square, above any floe",
);
/// `window`: the smoothing window of the stress criterion, s.
pub const WINDOW: Limit = Limit::range(
    "window",
    "[fracture]",
    0.0,
    1e6,
    "s",
    "about 12 days; the mean force of a window needs a duration",
)
.exclusive_min();
/// `mohr_q`: the slope ratio of the Mohr–Coulomb curve.
pub const MOHR_Q: Limit = Limit::range(
    "mohr_q",
    "[fracture]",
    1.0,
    100.0,
    "",
    "q = tan²(π/4 + φ/2) > 1 for a friction angle φ > 0 (1 makes the triangle unbounded); 100 is φ ≈ 79°",
)
.exclusive_min();
/// `mohr_sigma_c`: the uniaxial compressive strength of the Mohr–Coulomb curve, Pa.
pub const MOHR_SIGMA_C: Limit = Limit::range(
    "mohr_sigma_c",
    "[fracture]",
    0.0,
    1e9,
    "Pa",
    "above the strength of any ice (about 1e7 Pa for small samples)",
)
.exclusive_min();
/// `mohr_sigma_11`: the tensile-side principal stress of the Mohr–Coulomb
/// curve at its vertex, Pa.
pub const MOHR_SIGMA_11: Limit = Limit::magnitude(
    "mohr_sigma_11",
    "[fracture]",
    1e9,
    "Pa",
    "above the strength of any ice",
);
/// `hibler_p_star`: Hibler's ice strength `P*`, N/m².
pub const HIBLER_P_STAR: Limit = Limit::range(
    "hibler_p_star",
    "[fracture]",
    0.0,
    1e9,
    "N/m^2",
    "above the strength of any ice",
)
.exclusive_min();
/// `hibler_c`: Hibler's concentration parameter `C`.
pub const HIBLER_C: Limit = Limit::range(
    "hibler_c",
    "[fracture]",
    0.0,
    100.0,
    "",
    "20 is Hibler's; exp(−100) makes open ice of any strength",
);
/// `concentration`: the ice concentration `A` of Hibler's strength.
pub const CONCENTRATION: Limit = Limit::range(
    "concentration",
    "[fracture]",
    0.0,
    1.0,
    "",
    "an area fraction",
);
