//! The 2D percussion of a floe (docs/physics.md §7.3): the floe's lattice
//! ([`super::Lattice`]) integrated from a rigid impact, the striker an
//! effective mass in unilateral contact with it, bonds breaking, and the
//! connected components of the broken lattice becoming rigid pieces.
//!
//! **Scheme.** The lattice's springs are geometrically exact central
//! springs (force `κ (|x_j − x_i| − L₀)` along the current direction, so a
//! rigid rotation loads nothing) in parallel with dashpots
//! `c = β √(κ m_ij)` (`m_ij = 2 m_i m_j / (m_i + m_j)`, `β` the chain's
//! damping ratio, 0.5 by default,
//! [`ChainOptions`](crate::fracture::chain::ChainOptions)), and, when the
//! lattice has them (Poisson ratio below 1/3), its torsion springs with
//! their geometrically exact forces
//! ([`Lattice::torsion_forces`](super::Lattice::torsion_forces)),
//! undamped. The striker is a rigid
//! half-plane of effective mass `m*` (kg, `∞` for an obstacle) moving along
//! the impact normal `n` (pointing into the floe); it pushes each outline
//! node through a compression-only penalty link (the chain's unilateral
//! link, rest length 0) of the lattice's mean spring stiffness `κ̄` and its
//! dashpot `β √(κ̄ m_i*)` (`m_i*` the reduced mass of the node and the
//! striker): a penalty, not an exact contact. A half-plane is what a coast
//! is, and a face of another floe near the contact point. Several strikers
//! can act at once ([`Percussion::with_strikers`], a floe squeezed between
//! two bodies), each its own half-plane, mass and contact links; the
//! impact energy bound is then [`impact_energy_bound`] (docs/physics.md §9.8).
//!
//! A bond breaks, for good, when its elongation passes `δ_c`
//! ([`crate::fracture::chain::BondRule::critical`]): with a toughness `G` the energy `½ κ δ²` it
//! holds reaches `G h w`, `w = 2 A_e / L₀` the width of its share of the
//! triangles (`A_e` a third of each adjacent triangle's area): the facet it
//! opens (`s/√3`, the Voronoi facet, in an equilateral lattice of spacing
//! `s`). A broken bond becomes a compression-only link, and the triangles on
//! its sides lose their torsion springs, whose energy is booked with the
//! bond's. Under the cohesive rule ([`crate::fracture::chain::Cohesive`])
//! a bond first softens past the force `σ_t h w` and breaks once softened
//! to nothing, having taken `G h w`; what its softening dissipates is
//! fracture energy as it accrues (docs/physics.md §7.3).
//!
//! **Integrator.** The chain's velocity Verlet ([`super::super::chain`]) at
//! the damped stable step `s (2/ω)(√(1+ζ²) − ζ)`, `ω` the block-Gershgorin
//! bound on the highest frequency of `M^{-½} K M^{-½}` (springs and every
//! possible contact), `ω² ≤ max_i Σ_j κ_ij (1/m_i + 1/√(m_i m_j))` plus
//! the torsion springs' `Σ c |∇_i θ| Σ_j |∇_j θ| / √(m_i m_j)` over the
//! corners of node `i` (their blocks `c ∇_i θ ∇_j θᵀ`), and `ζ`
//! the same bound on the dashpots over `2ω`; safety `s` (0.9 by default).
//! The geometric stiffness of a stretched spring, `O(strain)`, is left out
//! of the bound. A softening cohesive bond's tangent is negative and its
//! secant below `κ`: the step stays the elastic one.
//!
//! **Stopping rule** (the chain's, [`super::super::chain::Stop`]): the
//! contact is over when no outline node touches the striker and the striker
//! is no faster along `n` than the rigid motion of any piece within one
//! lattice spacing of it, at its node nearest the striker (a piece further
//! away, spinning, can have a node moving towards the striker for ever); the waves have settled when the internal energy (kinetic
//! and elastic, less the pieces' and the striker's rigid kinetic energy) is
//! under `settle` times the impact energy `½ μ u_N²` (`μ` the reduced mass
//! of `m*` and the floe), or `settle_transits` transit times (the floe's
//! diameter over the P-wave speed `√(E / (ρ (1 − ν²)))`, ν the lattice's) have passed since
//! the contact ended; in any case after `limit_transits` transit times.
//!
//! References: D. Balasoiu (2020), PhD thesis, Université Grenoble Alpes
//! (the percussion by an effective mass); T. Belytschko, W. K. Liu and
//! B. Moran (2000), *Nonlinear finite elements for continua and
//! structures*, §6.3 (the stable step with damping); A. M. Andrew (1979),
//! *Information Processing Letters* 9(5) (the convex hull).
//!
//! [`critical_ram_speed`] finds, by bisection, the least speed at which a
//! floe rammed into a coast ([`ram`]) breaks.
//!
//! The parts, each its own file: `state.rs` the lattice's state (the
//! [`Percussion`]: nodes, links, strikers), its forces, bond breaking and
//! the velocity Verlet integrator; `build.rs` its construction; `bonds.rs`
//! each spring's law (the chain's link, or a cohesive bond's softening);
//! `striker.rs` the strikers ([`Impact`], [`RigidMotion`],
//! [`impact_energy_bound`]) and their unilateral contact with the outline
//! nodes; `stop.rs` the pieces and the stopping rule ([`Percussion::run`]);
//! `outcome.rs` what a percussion gives ([`Outcome`], [`Fragment`],
//! [`BrokenSpring`]); `ramming.rs` the ramming into a coast and its
//! critical speed.

mod bonds;
mod build;
mod outcome;
mod ramming;
mod state;
mod stop;
mod striker;

pub(super) use outcome::NodeMotion;
pub use outcome::{BrokenSpring, Fragment, Outcome};
pub use ramming::{critical_ram_speed, critical_ram_speed_by, mean_and_deviation, ram, Break};
pub(super) use state::{gershgorin_weight, mean_stiffness, step_of_rows};
pub use state::{strain_of_toughness, Percussion};
pub use striker::{impact_energy_bound, Impact, RigidMotion};
