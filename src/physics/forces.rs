//! Environment forces of physics.md section 2: the one force law of the
//! project, used by every formulation.
//!
//! - Coriolis: `F_c = −M f k ∧ Ġ` (no torque, no work in exact arithmetic);
//! - air drag: `τ_a = ρ_a C_a |U_a| U_a`, uniform, so its force is `|ω| τ_a`
//!   and its torque about the centroid is exactly zero;
//! - water drag at each point: `τ_w(P) = ρ_w C_w |U_w − Ṗ| (U_w − Ṗ)` with
//!   `Ṗ = Ġ + θ̇ k ∧ GP`, integrated over the polygon.
//!
//! The quadrature fans the polygon into triangles from the centroid and
//! applies Dunavant's 7-point rule (degree 5) on each. Its weights sum to the
//! triangle areas, so the integral is exact (to rounding) for a translating
//! floe, where the integrand is constant. For a spinning floe it is a
//! degree-5 rule on a piecewise smooth integrand (the traction has a kink where
//! the relative velocity vanishes).

use crate::geometry::{cross, perp, Vec2};
use crate::model::{Environment, Floe};
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

/// Environment forces on one floe, split by origin.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Forces {
    /// Air drag force, N (its torque about `G` is zero).
    pub air: Vec2,
    /// Water drag force, N.
    pub water: Vec2,
    /// Water drag torque about `G`, N·m.
    pub water_torque: f64,
    /// Coriolis force, N.
    pub coriolis: Vec2,
}

impl Forces {
    /// Total force, N.
    pub fn force(&self) -> Vec2 {
        self.air + self.water + self.coriolis
    }

    /// Total torque about the centre of mass, N·m.
    pub fn torque(&self) -> f64 {
        self.water_torque
    }

    /// Power of each force `(air, water, coriolis)` at the body velocity, W.
    pub fn powers(&self, b: &BodyState) -> (f64, f64, f64) {
        (
            self.air.dot(&b.velocity),
            self.water.dot(&b.velocity) + self.water_torque * b.angular_velocity,
            self.coriolis.dot(&b.velocity),
        )
    }
}

/// The quadratic drag traction `k |u| u`, N/m², for a relative velocity `u`.
#[inline]
pub fn drag_traction(k: f64, u: &Vec2) -> Vec2 {
    u * (k * u.norm())
}

/// The environment forces on `floe` in state `b` at time `t` (s).
pub fn environment_forces(
    env: &Environment,
    floe: &Floe,
    quad: &Quadrature,
    t: f64,
    b: &BodyState,
) -> Forces {
    let ka = env.air.drag_factor();
    let air = if ka > 0.0 {
        drag_traction(ka, &env.air.velocity.at(t)) * floe.area
    } else {
        Vec2::zeros()
    };
    let kw = env.water.drag_factor();
    let (mut water, mut water_torque) = (Vec2::zeros(), 0.0);
    if kw > 0.0 {
        let uw = env.water.velocity.at(t);
        let (s, c) = b.angle.sin_cos();
        for (r0, w) in quad.nodes() {
            let r = Vec2::new(c * r0.x - s * r0.y, s * r0.x + c * r0.y);
            let u = uw - b.velocity - perp(&r) * b.angular_velocity;
            let tau = drag_traction(kw, &u) * *w;
            water += tau;
            water_torque += cross(&r, &tau);
        }
    }
    let coriolis = if env.coriolis != 0.0 {
        -perp(&b.velocity) * (floe.mass * env.coriolis)
    } else {
        Vec2::zeros()
    };
    Forces {
        air,
        water,
        water_torque,
        coriolis,
    }
}

/// Velocity of the material point at world offset `r = GP` from the centre, m/s.
#[inline]
pub fn point_velocity(b: &BodyState, r: &Vec2) -> Vec2 {
    b.velocity + perp(r) * b.angular_velocity
}
