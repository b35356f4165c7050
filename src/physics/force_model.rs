//! The force model: the one force law of the project (docs/physics.md §2),
//! used by every formulation, and the map from forces to accelerations.
//!
//! On a floe with centre of mass `G`, angle `θ`, mass `M` and polar inertia
//! `I` about `G`:
//!
//! - Coriolis: `F_c = −M f k ∧ Ġ` (no torque, no work in exact arithmetic);
//! - air drag at each point `P` of the floe: `τ_a(P) = ρ_a C_a |U_a(P, t)|
//!   U_a(P, t)`, on the absolute wind `U_a` (not relative to the floe). The
//!   wind is evaluated at a world point by the one point function of a fluid's
//!   velocity, [`VelocityField::at`](crate::model::VelocityField::at). While
//!   it is uniform in space ([`air_is_uniform_in_space`]: a constant or a
//!   time series), the force is the closed form `|ω| τ_a` and the torque
//!   about `G` is exactly zero; otherwise (a linear, vortex or gridded wind)
//!   both are integrated over the polygon ([`air_drag_quadrature`]), which
//!   for a uniform wind gives the same to rounding;
//! - water drag at each point: `τ_w(P) = ρ_w C_w |U_w(P, t) − Ṗ| (U_w(P, t) − Ṗ)`
//!   with `Ṗ = Ġ + θ̇ k ∧ GP`, integrated over the polygon; a current
//!   uniform in space is evaluated once per call, a field at each node.
//!
//! The quadrature (Dunavant's 7-point rule on a fan of triangles, see
//! [`super::forces`]) is built once per floe by [`ForceModel::new`]. The
//! accelerations are `G̈ = F / M` and `θ̈ = M_G / I`
//! ([`ForceModel::acceleration`]).

use super::forces::{drag_traction, integrate_traction, Forces, Quadrature};
use crate::geometry::{perp, Vec2};
use crate::model::{Environment, Floe};
use crate::state::BodyState;

/// The wind `U_a(P, t)` at world point `p` (m) and time `t` (s), m/s: the
/// air's [`VelocityField::at`](crate::model::VelocityField::at).
#[inline]
pub fn air_velocity(env: &Environment, p: &Vec2, t: f64) -> Vec2 {
    env.air.velocity.at(p, t, &env.outside)
}

/// Whether the wind of `env` is uniform in space (a constant or a time
/// series), so that the air drag takes its closed form (area × traction, no
/// torque).
#[inline]
pub fn air_is_uniform_in_space(env: &Environment) -> bool {
    env.air.velocity.is_uniform()
}

/// Air drag force (N) and torque about the centre of mass (N·m) on a floe
/// with quadrature `quad` in state `b`, by quadrature of the traction
/// `k |U_a(P)| U_a(P)` of the wind `wind(P)` (m/s) at world point `P` (m),
/// for the drag factor `k = ρ_a C_a` (kg/m³).
pub fn air_drag_quadrature<W>(k: f64, quad: &Quadrature, b: &BodyState, wind: W) -> (Vec2, f64)
where
    W: Fn(&Vec2) -> Vec2,
{
    integrate_traction(quad, b, |p, _r| drag_traction(k, &wind(p)))
}

/// What the force law needs of one floe.
#[derive(Debug, Clone)]
struct FloeProperties {
    quadrature: Quadrature,
    /// Area, m².
    area: f64,
    /// Mass, kg.
    mass: f64,
    /// Polar inertia about the centre of mass, kg·m².
    inertia: f64,
}

/// The force model of a scenario: per-floe quadratures, areas, masses and
/// inertias, and the force law on them.
#[derive(Debug, Clone)]
pub struct ForceModel {
    floes: Vec<FloeProperties>,
}

impl ForceModel {
    /// Builds the model for the scenario's `floes` (in the scenario's order;
    /// floe `i` of the other methods is `floes[i]`).
    pub fn new(floes: &[Floe]) -> ForceModel {
        ForceModel {
            floes: floes
                .iter()
                .map(|f| FloeProperties {
                    quadrature: Quadrature::for_shape(&f.shape),
                    area: f.area,
                    mass: f.mass,
                    inertia: f.inertia,
                })
                .collect(),
        }
    }

    /// The quadrature of floe `i` (nodes in its body frame, weights in m²).
    pub fn quadrature(&self, i: usize) -> &Quadrature {
        &self.floes[i].quadrature
    }

    /// The environment forces (N) and torques about the centre of mass (N·m)
    /// of `env` on floe `i` in state `b` at time `t` (s).
    pub fn forces(&self, env: &Environment, i: usize, t: f64, b: &BodyState) -> Forces {
        let floe = &self.floes[i];
        let ka = env.air.drag_factor();
        let (air, air_torque) = if ka > 0.0 {
            if air_is_uniform_in_space(env) {
                // Closed form of the quadrature below (module doc).
                let ua = air_velocity(env, &b.position, t);
                (drag_traction(ka, &ua) * floe.area, 0.0)
            } else {
                air_drag_quadrature(ka, &floe.quadrature, b, |p| air_velocity(env, p, t))
            }
        } else {
            (Vec2::zeros(), 0.0)
        };
        let kw = env.water.drag_factor();
        let (water, water_torque) = if kw > 0.0 {
            let field = &env.water.velocity;
            if let Some(series) = field.uniform() {
                let uw = series.at(t);
                integrate_traction(&floe.quadrature, b, |_p, r| {
                    let u = uw - b.velocity - perp(r) * b.angular_velocity;
                    drag_traction(kw, &u)
                })
            } else {
                integrate_traction(&floe.quadrature, b, |p, r| {
                    let u =
                        field.at(p, t, &env.outside) - b.velocity - perp(r) * b.angular_velocity;
                    drag_traction(kw, &u)
                })
            }
        } else {
            (Vec2::zeros(), 0.0)
        };
        let coriolis = if env.coriolis != 0.0 {
            -perp(&b.velocity) * (floe.mass * env.coriolis)
        } else {
            Vec2::zeros()
        };
        Forces {
            air,
            air_torque,
            water,
            water_torque,
            coriolis,
        }
    }

    /// The accelerations of floe `i` under `forces`: `[G̈_x, G̈_y, θ̈]` =
    /// `[F_x / M, F_y / M, M_G / I]`, in m/s², m/s² and rad/s².
    pub fn acceleration(&self, i: usize, forces: &Forces) -> [f64; 3] {
        self.wrench_acceleration(i, &forces.force(), forces.torque())
    }

    /// The accelerations of floe `i` under a force `force` (N) and a torque
    /// about its centre of mass `torque` (N·m): `[F_x / M, F_y / M, τ / I]`,
    /// in m/s², m/s² and rad/s².
    pub fn wrench_acceleration(&self, i: usize, force: &Vec2, torque: f64) -> [f64; 3] {
        let floe = &self.floes[i];
        [
            force.x / floe.mass,
            force.y / floe.mass,
            torque / floe.inertia,
        ]
    }
}
