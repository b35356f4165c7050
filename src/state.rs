//! The dynamic state every formulation advances: per-floe positions and
//! velocities, the clock, and the energy ledger.

use crate::geometry::Vec2;
use crate::model::Scenario;
use serde::Serialize;

/// Position and velocity of one floe (3 degrees of freedom).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BodyState {
    /// Centre of mass `G`, m.
    pub position: Vec2,
    /// Angle `θ` from the case's initial orientation, rad.
    pub angle: f64,
    /// Velocity of the centre of mass `Ġ`, m/s.
    pub velocity: Vec2,
    /// Angular velocity `θ̇`, rad/s.
    pub angular_velocity: f64,
}

impl BodyState {
    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.position.x.is_finite()
            && self.position.y.is_finite()
            && self.angle.is_finite()
            && self.velocity.x.is_finite()
            && self.velocity.y.is_finite()
            && self.angular_velocity.is_finite()
    }
}

/// Cumulative energy exchanges since t = 0, J.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Ledger {
    /// Work of the air drag on the floes, J.
    pub work_air: f64,
    /// Work of the water drag, J.
    pub work_water: f64,
    /// Work of the Coriolis force, J (zero in exact arithmetic: `F_c ⟂ Ġ`).
    pub work_coriolis: f64,
    /// Kinetic energy removed by contacts (impacts, friction), J.
    pub dissipated: f64,
}

impl Ledger {
    /// Total work of the external forces, J.
    pub fn external_work(&self) -> f64 {
        self.work_air + self.work_water + self.work_coriolis
    }
}

/// The whole system at time `t`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct System {
    /// Simulated time, s.
    pub t: f64,
    /// One state per floe, in the scenario's order.
    pub bodies: Vec<BodyState>,
    /// Energy exchanges since t = 0.
    pub ledger: Ledger,
}

impl System {
    /// The state at t = 0 of a scenario.
    pub fn initial(scn: &Scenario) -> System {
        System {
            t: 0.0,
            bodies: scn
                .floes
                .iter()
                .map(|f| BodyState {
                    position: f.position,
                    angle: 0.0,
                    velocity: f.velocity,
                    angular_velocity: f.angular_velocity,
                })
                .collect(),
            ledger: Ledger::default(),
        }
    }

    /// Total kinetic energy `Σ ½ M |Ġ|² + ½ I θ̇²`, J.
    pub fn kinetic_energy(&self, scn: &Scenario) -> f64 {
        self.bodies
            .iter()
            .zip(&scn.floes)
            .map(|(b, f)| {
                0.5 * f.mass * b.velocity.norm_squared()
                    + 0.5 * f.inertia * b.angular_velocity * b.angular_velocity
            })
            .sum()
    }

    /// Total linear momentum `Σ M Ġ`, kg·m/s.
    pub fn momentum(&self, scn: &Scenario) -> Vec2 {
        self.bodies
            .iter()
            .zip(&scn.floes)
            .map(|(b, f)| b.velocity * f.mass)
            .fold(Vec2::zeros(), |s, p| s + p)
    }
}
