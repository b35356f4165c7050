//! The 2D mass–spring lattice of a floe (docs/physics.md §7.2): a seeded
//! Poisson-disc point set inside the (convex) outline ([`Mesh::Random`], the
//! default) or the nodes of an equilateral triangular lattice clipped to it
//! ([`Mesh::Triangular`], no disorder), in both cases with the outline's
//! vertices and points along its edges, their Delaunay
//! triangulation ([`delaunay`], Bowyer–Watson), lumped node masses whose
//! total mass, centre of mass and polar inertia are the rigid floe's, and
//! central springs of stiffness `k / sin θ` per triangle edge (θ the angle
//! opposite the edge, after Balasoiu 2020) and, when the Poisson ratio asked
//! for is below 1/3, torsion (angular) springs of stiffness `c` at every
//! triangle corner (energy `½ c (θ − θ₀)²`, the corner's angle θ measured
//! from the current positions, so a rigid rotation loads nothing). `k` and
//! `c` are calibrated so that the lattice's isotropic (orientation-averaged)
//! affine response has the floe's Young's modulus and Poisson ratio: central
//! springs give the Lamé coefficients `λ = μ` (the Cauchy relation, ν = 1/3)
//! and torsion springs add to `μ` what they take from `λ`
//! (docs/physics.md §7.2).
//!
//! Static solutions ([`Lattice::solve`]) are linear (small displacements):
//! conjugate gradients on the lattice's stiffness matrix, applied without
//! assembling it, with some degrees of freedom prescribed. Stresses are the
//! virial of each triangle's springs ([`Lattice::triangle_stress`]).
//!
//! References: R. Bridson (2007), Fast Poisson disk sampling in arbitrary
//! dimensions, SIGGRAPH sketches; A. Bowyer (1981) and D. F. Watson (1981),
//! *The Computer Journal* 24(2); D. Balasoiu (2020), PhD thesis, Université
//! Grenoble Alpes.
//!
//! [`percussion`] integrates a lattice struck by a rigid impact;
//! [`rectangle`] strikes a rectangular floe on its left face
//! (`floebench percussion-2d`); [`pair`] resolves both bodies of an impact
//! as lattices (docs/physics.md §9.9).

pub mod bars;
pub mod delaunay;
pub mod pair;
pub mod percussion;
pub mod rectangle;

mod build;
mod points;
mod response;

pub use build::lumped_masses;
pub use points::{poisson_disc, triangular_points};
pub use response::moduli;

use crate::geometry::{cross, perp, Vec2};
use crate::model::limits::fracture::POISSON_MAX;
#[cfg(doc)]
use crate::model::limits::fracture::POISSON_MIN;

/// What a lattice is made of and how fine it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeSpec {
    /// Target distance between nodes (the Poisson-disc radius), m.
    pub spacing: f64,
    /// Floe thickness, m.
    pub thickness: f64,
    /// Ice density, kg/m³.
    pub density: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson ratio (-), in `(−1, 1/3]` ([`POISSON_MIN`], [`POISSON_MAX`]).
    /// 1/3 (the default) is central springs alone, no torsion springs;
    /// below it, torsion springs at the triangle corners lower it (ice:
    /// about 0.3).
    pub poisson: f64,
    /// Seed of the Poisson-disc sampling (unused by a triangular mesh).
    pub seed: u64,
    /// How the nodes inside the outline are placed: a seeded Poisson-disc
    /// set ([`Mesh::Random`], the default) or a regular triangular lattice
    /// ([`Mesh::Triangular`]).
    pub mesh: Mesh,
}

/// How the nodes inside a floe's outline are placed (docs/physics.md §7.2).
/// Either way the outline carries its vertices and points at most one
/// spacing apart along each edge, and the nodes inside are at least half a
/// spacing from it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Mesh {
    /// A seeded Poisson-disc set (Bridson 2007): a disordered, isotropic
    /// lattice; its seed is [`LatticeSpec::seed`].
    #[default]
    Random,
    /// The nodes of an equilateral triangular lattice of side the spacing:
    /// elastically isotropic and without disorder (every interior node is
    /// a centre of symmetry, so a uniform strain is an equilibrium inside);
    /// only its boundary cells, where it is clipped to the outline, are
    /// irregular. Its two freedoms are its orientation and its offset.
    Triangular {
        /// The angle of its first lattice direction from the x axis, rad
        /// (it repeats every π/3).
        angle: f64,
        /// The position of one of its nodes relative to the outline's
        /// centroid, in lattice coordinates along its two directions at
        /// `angle` and `angle + π/3` (fractions of the spacing; 0, 0 puts
        /// a node at the centroid).
        offset: [f64; 2],
    },
}

impl Default for LatticeSpec {
    /// Ice at the lattice's usual resolution: spacing 1 m, thickness 1 m,
    /// density 917 kg/m³ (the project's), Young's modulus 8.95 GPa
    /// (Balasoiu's), Poisson ratio 1/3 (central springs alone: no torsion
    /// springs, what the lattice was before they were built), seed 1, the
    /// random mesh.
    fn default() -> Self {
        LatticeSpec {
            spacing: 1.0,
            thickness: 1.0,
            density: 917.0,
            young: 8.95e9,
            poisson: POISSON_MAX,
            seed: 1,
            mesh: Mesh::Random,
        }
    }
}

impl Mesh {
    /// The `k`-th of a sequence of triangular meshes at `angle` (rad) that
    /// differ by their offset, in place of seeds: offset
    /// `frac(k (α₁, α₂))` in lattice coordinates, `α₁ = 0.7548776662`,
    /// `α₂ = 0.5698402910` (the plastic-number sequence of Roberts 2018,
    /// which covers the unit square evenly). `k = 0` is no offset: on a
    /// square whose faces are along the lattice it puts nodes at exactly
    /// half a spacing from a face, where rounding decides whether they are
    /// kept (docs/physics.md §7.2), so variants start at 1.
    pub fn triangular_variant(angle: f64, k: u64) -> Mesh {
        let k = k as f64;
        Mesh::Triangular {
            angle,
            offset: [(k * 0.7548776662).fract(), (k * 0.5698402910).fract()],
        }
    }
}

impl LatticeSpec {
    /// The torsion springs' share of the Lamé coefficients, as the ratio
    /// `Δμ / μ_s` of what they add to `μ` (and take from `λ`) to the
    /// central springs' `μ_s = λ_s`: `(1 − 3ν)/(1 + ν)`, 0 at ν = 1/3
    /// (docs/physics.md §7.2).
    pub fn torsion_ratio(&self) -> f64 {
        (1.0 - 3.0 * self.poisson) / (1.0 + self.poisson)
    }
}

/// A torsion (angular) spring at the corner of a triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corner {
    /// Its nodes: the corner's vertex `o`, then `a` and `b`, the angle
    /// going counter-clockwise from `a − o` to `b − o`.
    pub nodes: [usize; 3],
    /// Stiffness `c`, J/rad² (N·m per radian of angle change, per radian).
    pub stiffness: f64,
    /// Rest angle `θ₀`, rad.
    pub angle: f64,
    /// The gradient of the angle with respect to the three nodes'
    /// positions at rest (same order as `nodes`), 1/m.
    pub grad: [Vec2; 3],
}

impl Corner {
    /// The linearised change of its angle under displacements `u` (m),
    /// rad.
    pub fn angle_change(&self, u: &[Vec2]) -> f64 {
        self.nodes
            .iter()
            .zip(&self.grad)
            .map(|(&i, g)| g.dot(&u[i]))
            .sum()
    }
}

/// The angle (rad) at `o` from `a − o` to `b − o`, counter-clockwise, in
/// `(−π, π]`, and its gradients with respect to `o`, `a`, `b` (1/m): the
/// direction `φ` of a vector `e` has `∂φ/∂e = k ∧ e / |e|²`.
pub fn corner_angle(o: &Vec2, a: &Vec2, b: &Vec2) -> (f64, [Vec2; 3]) {
    let (ea, eb) = (a - o, b - o);
    let theta = cross(&ea, &eb).atan2(ea.dot(&eb));
    let ga = -perp(&ea) / ea.norm_squared();
    let gb = perp(&eb) / eb.norm_squared();
    (theta, [-(ga + gb), ga, gb])
}

/// A central spring between two nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// Its nodes.
    pub nodes: [usize; 2],
    /// Stiffness, N/m (the sum of its triangles' `k / sin θ`).
    pub stiffness: f64,
    /// Rest length, m.
    pub length: f64,
    /// Unit vector from the first node to the second.
    pub dir: Vec2,
}

/// The lattice of one floe.
#[derive(Debug, Clone)]
pub struct Lattice {
    /// Node positions, m (in the outline's frame).
    pub nodes: Vec<Vec2>,
    /// Whether each node lies on the outline.
    pub on_boundary: Vec<bool>,
    /// Node masses, kg.
    pub mass: Vec<f64>,
    /// The Delaunay triangles (counter-clockwise).
    pub triangles: Vec<[usize; 3]>,
    /// The springs, one per triangle edge.
    pub springs: Vec<Spring>,
    /// For each triangle, its three edges: (spring, that triangle's share of
    /// its stiffness `k / sin θ`, N/m).
    pub triangle_springs: Vec<[(usize, f64); 3]>,
    /// The calibrated `k`, N/m.
    pub k: f64,
    /// The torsion springs, three per triangle (those of triangle `t` are
    /// `3t..3t + 3`), or none when the Poisson ratio is 1/3.
    pub corners: Vec<Corner>,
    /// The calibrated torsion stiffness `c` of every corner, J/rad² (0
    /// when there are none).
    pub torsion: f64,
    /// The area covered by the triangles, m².
    pub area: f64,
    /// The spec it was built from.
    pub spec: LatticeSpec,
}
