//! The dynamic state every formulation advances: per-floe positions and
//! velocities, the clock, and the energy ledger; and the scenario-level
//! helpers every caller shares: world polygons, contact detection of the
//! bodies, point and normal velocities, kinetic energy, largest point speed.

use crate::contact::{detect_compound, BroadPhase, Compound, Contact, NarrowOptions};
use crate::geometry::Vec2;
use crate::model::{Body, Scenario};
use crate::physics::forces::point_velocity;
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
    /// Of the energy contacts removed, the part fractures spent on their
    /// cracks, J (docs/physics.md §9.4; zero without fracture). It is not
    /// in `dissipated`: the balance is `E − E(0) − W_ext + D + F = 0`.
    pub fracture: f64,
}

impl Ledger {
    /// Total work of the external forces, J.
    pub fn external_work(&self) -> f64 {
        self.work_air + self.work_water + self.work_coriolis
    }

    /// Energy removed from the floes by contacts, dissipated or spent on
    /// cracks, `D + F`, J.
    pub fn removed(&self) -> f64 {
        self.dissipated + self.fracture
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
            .map(|(b, f)| f.kinetic_energy(&b.velocity, b.angular_velocity))
            .sum()
    }

    /// Kinetic energy of the floes `floes` (indices), J.
    pub fn group_kinetic_energy(&self, scn: &Scenario, floes: &[usize]) -> f64 {
        floes
            .iter()
            .map(|&i| {
                let b = &self.bodies[i];
                scn.floes[i].kinetic_energy(&b.velocity, b.angular_velocity)
            })
            .sum()
    }

    /// The largest point speed of a floe, `max_i |Ġ_i| + |θ̇_i| r_i` (m/s,
    /// `r_i` the floe's radius about its centre of mass): no material point
    /// moves faster.
    pub fn max_point_speed(&self, scn: &Scenario) -> f64 {
        self.bodies
            .iter()
            .zip(&scn.floes)
            .map(|(b, f)| b.velocity.norm() + b.angular_velocity.abs() * f.radius)
            .fold(0.0, f64::max)
    }

    /// The centre of mass of every floe, m.
    pub fn centres(&self) -> Vec<Vec2> {
        self.bodies.iter().map(|b| b.position).collect()
    }

    /// The generalised velocity `(Ġx, Ġy, θ̇)` of every floe (m/s, m/s,
    /// rad/s), as the contact problems take it.
    pub fn velocities(&self) -> Vec<[f64; 3]> {
        self.bodies
            .iter()
            .map(|b| [b.velocity.x, b.velocity.y, b.angular_velocity])
            .collect()
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

/// The world polygons of every body: floes at `bodies`, then the obstacles
/// (body ids as in [`Scenario::body`]).
pub fn world_polygons(scn: &Scenario, bodies: &[BodyState]) -> Vec<Vec<Vec2>> {
    let mut out = Vec::with_capacity(bodies.len() + scn.obstacles.len());
    for (f, b) in scn.floes.iter().zip(bodies) {
        let mut p = Vec::with_capacity(f.shape.len());
        f.world_polygon(&b.position, b.angle, &mut p);
        out.push(p);
    }
    out.extend(scn.obstacles.iter().map(|o| o.polygon.clone()));
    out
}

/// The contacts between the bodies at `bodies` (floes, then obstacles) closer
/// than `distance` (m), by the shared detection
/// ([`crate::contact::detect_compound`]: convex parts of non-convex bodies),
/// into `out`; `bp` keeps the broad phase's buffers between calls.
pub fn detect_contacts(
    scn: &Scenario,
    bodies: &[BodyState],
    distance: f64,
    bp: &mut BroadPhase,
    out: &mut Vec<Contact>,
) {
    detect_contacts_with(scn, bodies, distance, &NarrowOptions::default(), bp, out);
}

/// [`detect_contacts`] with the contact point tolerances `options` (the
/// event-driven scheme makes a two-point contact of every facing edge pair
/// whose clipped ends are within `distance`, see
/// [`crate::formulation::event_driven`]).
pub fn detect_contacts_with(
    scn: &Scenario,
    bodies: &[BodyState],
    distance: f64,
    options: &NarrowOptions,
    bp: &mut BroadPhase,
    out: &mut Vec<Contact>,
) {
    let polys = world_polygons(scn, bodies);
    let compounds = compounds(scn, &polys);
    let fixed: Vec<bool> = (0..compounds.len())
        .map(|i| matches!(scn.body(i), Body::Obstacle(_)))
        .collect();
    detect_compound(&compounds, &fixed, distance, options, bp, out);
}

/// The bodies of `scn` as [`Compound`]s of their convex parts, over their
/// world polygons `polys` (from [`world_polygons`]).
pub fn compounds<'a>(scn: &'a Scenario, polys: &'a [Vec<Vec2>]) -> Vec<Compound<'a>> {
    polys
        .iter()
        .enumerate()
        .map(|(i, p)| Compound {
            outline: p,
            parts: body_parts(scn, i),
        })
        .collect()
}

/// The convex parts of body `i` (floe or obstacle, ids as in
/// [`Scenario::body`]), as indices into its outline.
pub fn body_parts(scn: &Scenario, i: usize) -> &[Vec<usize>] {
    match scn.body(i) {
        Body::Floe(k) => &scn.floes[k].parts,
        Body::Obstacle(k) => &scn.obstacles[k].parts,
    }
}

/// The velocity of the material point of body `i` at world point `p` (m/s):
/// `Ġ + θ̇ k ∧ GP` for a floe, zero for an obstacle.
pub fn body_point_velocity(scn: &Scenario, bodies: &[BodyState], i: usize, p: &Vec2) -> Vec2 {
    match scn.body(i) {
        Body::Floe(k) => point_velocity(&bodies[k], &(p - bodies[k].position)),
        Body::Obstacle(_) => Vec2::zeros(),
    }
}

/// Normal relative velocity of a contact, `(v_b − v_a) · N` at the contact
/// point (m/s; positive: separating).
pub fn normal_velocity(scn: &Scenario, bodies: &[BodyState], c: &Contact) -> f64 {
    relative_velocity(scn, bodies, c).dot(&c.geom.normal)
}

/// Tangential relative velocity of a contact, `(v_b − v_a) · T` at the
/// contact point (m/s, along the contact's tangent).
pub fn tangential_velocity(scn: &Scenario, bodies: &[BodyState], c: &Contact) -> f64 {
    relative_velocity(scn, bodies, c).dot(&c.geom.tangent)
}

/// `v_b − v_a` at the contact point, m/s.
fn relative_velocity(scn: &Scenario, bodies: &[BodyState], c: &Contact) -> Vec2 {
    body_point_velocity(scn, bodies, c.b, &c.geom.point)
        - body_point_velocity(scn, bodies, c.a, &c.geom.point)
}

/// Makes `bodies` (one per floe, e.g. an earlier run's state read by
/// [`crate::run::output::read_state`]) the initial state of `scn`: each
/// floe's outline is turned by its angle (so the new run's angles start at
/// 0 from that orientation), its centre of mass, velocity and angular
/// velocity replaced. Mass properties do not change under a rotation. The
/// state is taken as an earlier run left it: floes in contact or within
/// that run's penetration tolerance are not re-checked for overlap.
/// `restart` records where it comes from.
pub fn restart(
    scn: &mut Scenario,
    bodies: &[BodyState],
    restart: crate::model::Restart,
) -> Result<(), String> {
    if bodies.len() != scn.floes.len() {
        return Err(format!(
            "{}: {} floes at t = {} s, but case `{}` has {}",
            restart.file.display(),
            bodies.len(),
            restart.t,
            scn.name,
            scn.floes.len()
        ));
    }
    if let Some(i) = bodies.iter().position(|b| !b.is_finite()) {
        return Err(format!(
            "{}: floe {i} at t = {} s is not finite",
            restart.file.display(),
            restart.t
        ));
    }
    for (f, b) in scn.floes.iter_mut().zip(bodies) {
        for v in &mut f.shape {
            *v = crate::geometry::rotate(v, b.angle);
        }
        f.position = b.position;
        f.velocity = b.velocity;
        f.angular_velocity = b.angular_velocity;
    }
    scn.restart = Some(restart);
    Ok(())
}
