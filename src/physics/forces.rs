//! The pieces of the force law (docs/physics.md §2): the split of the
//! environment forces by origin ([`Forces`]), the quadratic drag traction,
//! and the quadrature of a surface traction over a floe. The law itself,
//! which puts them together for every formulation, is
//! [`ForceModel`](super::ForceModel).
//!
//! The quadrature fans the polygon into triangles from the centroid and
//! applies Dunavant's 7-point rule (degree 5) on each. Its weights sum to the
//! triangle areas, so the integral is exact (to rounding) for a constant
//! traction (a translating floe in water, a wind uniform in space), and its
//! nodes have zero first moment about the centroid, so such a traction has
//! no torque (to rounding). It integrates polynomial tractions of degree ≤ 5
//! exactly. For a spinning floe the water traction is piecewise smooth (it
//! has a kink where the relative velocity vanishes) and the rule is then
//! only approximate.

use crate::geometry::{cross, Vec2};
use crate::state::BodyState;

/// Quadrature nodes of one floe in its body frame: `(GP at θ = 0, weight m²)`.
#[derive(Debug, Clone)]
pub struct Quadrature {
    nodes: Vec<(Vec2, f64)>,
}

impl Quadrature {
    /// Dunavant 7-point rule on the fan of triangles `(G, p_i, p_{i+1})`.
    pub fn for_shape(shape: &[Vec2]) -> Quadrature {
        let s15 = 15f64.sqrt();
        let b1 = (6.0 + s15) / 21.0;
        let a1 = 1.0 - 2.0 * b1;
        let w1 = (155.0 + s15) / 1200.0;
        let b2 = (6.0 - s15) / 21.0;
        let a2 = 1.0 - 2.0 * b2;
        let w2 = (155.0 - s15) / 1200.0;
        let rule: [(f64, f64, f64, f64); 7] = [
            (1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 9.0 / 40.0),
            (a1, b1, b1, w1),
            (b1, a1, b1, w1),
            (b1, b1, a1, w1),
            (a2, b2, b2, w2),
            (b2, a2, b2, w2),
            (b2, b2, a2, w2),
        ];
        let n = shape.len();
        let mut nodes = Vec::with_capacity(7 * n);
        for i in 0..n {
            let p = shape[i];
            let q = shape[(i + 1) % n];
            let area = 0.5 * cross(&p, &q);
            for &(_l0, l1, l2, w) in &rule {
                // The first vertex is the centroid, at the origin.
                nodes.push((p * l1 + q * l2, w * area));
            }
        }
        Quadrature { nodes }
    }

    /// The nodes `(GP at θ = 0, weight)`.
    pub fn nodes(&self) -> &[(Vec2, f64)] {
        &self.nodes
    }
}

/// Environment forces on one floe, split by origin. Forces in N, torques
/// about the centre of mass `G` in N·m (counter-clockwise positive).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Forces {
    /// Air drag force, N.
    pub air: Vec2,
    /// Air drag torque about `G`, N·m (zero for a wind uniform in space).
    pub air_torque: f64,
    /// Water drag force, N.
    pub water: Vec2,
    /// Water drag torque about `G`, N·m.
    pub water_torque: f64,
    /// Coriolis force, N (no torque).
    pub coriolis: Vec2,
}

impl Forces {
    /// Total force, N.
    pub fn force(&self) -> Vec2 {
        self.air + self.water + self.coriolis
    }

    /// Total torque about the centre of mass, N·m.
    pub fn torque(&self) -> f64 {
        self.water_torque + self.air_torque
    }

    /// Power of each force `(air, water, coriolis)` at the body velocity, W:
    /// `F · Ġ + M θ̇` for each origin.
    pub fn powers(&self, b: &BodyState) -> (f64, f64, f64) {
        self.works(&b.velocity, b.angular_velocity)
    }

    /// Work of each force `(air, water, coriolis)`, J, held constant along a
    /// displacement `dg` of the centre (m) and a rotation `dtheta` (rad):
    /// `F · dG + M dθ` for each origin. With a velocity (m/s) and an angular
    /// velocity (rad/s) in their place it is the power, W.
    pub fn works(&self, dg: &Vec2, dtheta: f64) -> (f64, f64, f64) {
        (
            self.air.dot(dg) + self.air_torque * dtheta,
            self.water.dot(dg) + self.water_torque * dtheta,
            self.coriolis.dot(dg),
        )
    }
}

/// The quadratic drag traction `k |u| u`, N/m², for a drag factor `k = ρ C`
/// (kg/m³) and a fluid velocity `u` (m/s) relative to the surface.
#[inline]
pub fn drag_traction(k: f64, u: &Vec2) -> Vec2 {
    u * (k * u.norm())
}

/// The force (N) and the torque about the centre of mass (N·m) of a surface
/// traction over a floe with quadrature `quad` in state `b`, by the rule:
/// `F = Σ_k w_k τ(P_k) ≈ ∫ τ dA`, `M = Σ_k w_k GP_k ∧ τ(P_k) ≈ ∫ GP ∧ τ dA`.
///
/// `traction(p, r)` is the traction at the node, N/m², given its world
/// position `p = G + r` (m) and its world offset `r = GP` from the centre
/// (m). Only `b.position` and `b.angle` are used here; a traction that
/// depends on the motion (drag on the relative velocity) reads it itself.
#[inline]
pub fn integrate_traction<T>(quad: &Quadrature, b: &BodyState, mut traction: T) -> (Vec2, f64)
where
    T: FnMut(&Vec2, &Vec2) -> Vec2,
{
    let (mut force, mut torque) = (Vec2::zeros(), 0.0);
    let (s, c) = b.angle.sin_cos();
    for (r0, w) in quad.nodes() {
        let r = Vec2::new(c * r0.x - s * r0.y, s * r0.x + c * r0.y);
        let p = b.position + r;
        let tau = traction(&p, &r) * *w;
        force += tau;
        torque += cross(&r, &tau);
    }
    (force, torque)
}
