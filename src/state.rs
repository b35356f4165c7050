//! The dynamic state every formulation advances: per-floe positions and
//! velocities, the clock, and the energy ledger; and the scenario-level
//! helpers every caller shares: world polygons, contact detection of the
//! bodies, point and normal velocities, kinetic energy, largest point speed.

use crate::contact::{detect_compound, BroadPhase, Compound, Contact, NarrowOptions};
use crate::geometry::{perp, Vec2};
use crate::model::{Body, Scenario};
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

/// Velocity of the material point at world offset `r = GP` from the centre, m/s.
#[inline]
pub fn point_velocity(b: &BodyState, r: &Vec2) -> Vec2 {
    b.velocity + perp(r) * b.angular_velocity
}

/// Cumulative energy exchanges since t = 0, J.
///
/// Its fields are listed once, in [`Ledger::FIELDS`]: every writer and
/// reader of the ledger (`energy.csv`, `summary.json`, `metrics.csv`, the
/// runner's and the writer's finiteness checks, the bit-identical repeat
/// check, the energy balance) iterates that list.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
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
    /// in `dissipated`: the balance is `E − E(0) − W_ext + D + F + L = 0`.
    pub fracture: f64,
    /// Of the energy impacts removed, the part the floes' lattices keep in
    /// internal vibration (`impact = "lattice"`, docs/physics.md §9.10;
    /// zero otherwise), J. Not in `dissipated`.
    pub vibration: f64,
    /// Of the energy impacts removed, the part the lattices' dashpots took
    /// (`impact = "lattice"`, docs/physics.md §9.10; zero otherwise), J.
    /// Not in `dissipated`.
    pub dashpot: f64,
    /// The work of the crushing forces and the kinetic energy of the
    /// crushed ice (`[contact] crushing`, docs/physics.md §10; zero
    /// otherwise), J. Not in `dissipated`.
    pub crushing: f64,
}

/// The cases whose `metrics.csv` has a ledger field (it is zero in the
/// others).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shown {
    /// Every case.
    Always,
    /// Cases whose floes can break (`[fracture]`), with their other
    /// fracture figures.
    Fracture,
    /// Cases whose ice crushes (`[contact] crushing`).
    Crushing,
}

/// How an exchange of the [`Ledger`] enters the energy balance
/// `E − E(0) − W_ext + D + F + L + C = 0` (`L` the lattices' vibration and
/// dashpot energies, docs/physics.md §9.10; `C` the crushing, §10).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exchange {
    /// Work of an external force on the floes, in `W_ext`.
    External,
    /// Energy contacts removed from the floes, in `D + F + L`.
    Removed,
}

/// One field of the [`Ledger`]: its names, unit, what it is, and how to read
/// it.
#[derive(Debug, Clone, Copy)]
pub struct LedgerField {
    /// Its column in `energy.csv` and its key in `summary.json`'s `energy`.
    pub name: &'static str,
    /// Its metric in `metrics.csv`.
    pub metric: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// What it is, in words (the runner's `non-finite …` end of a run).
    pub description: &'static str,
    /// How it enters the energy balance.
    pub exchange: Exchange,
    /// Which cases' `metrics.csv` has it.
    pub shown: Shown,
    /// Its value in a ledger.
    pub get: fn(&Ledger) -> f64,
}

impl Ledger {
    /// Every field of the ledger, in the order of `energy.csv`'s columns
    /// and `summary.json`'s keys.
    pub const FIELDS: &[LedgerField] = &[
        LedgerField {
            name: "work_air",
            metric: "work_air",
            unit: "J",
            description: "work of the air drag",
            exchange: Exchange::External,
            shown: Shown::Always,
            get: |l| l.work_air,
        },
        LedgerField {
            name: "work_water",
            metric: "work_water",
            unit: "J",
            description: "work of the water drag",
            exchange: Exchange::External,
            shown: Shown::Always,
            get: |l| l.work_water,
        },
        LedgerField {
            name: "work_coriolis",
            metric: "work_coriolis",
            unit: "J",
            description: "work of the Coriolis force",
            exchange: Exchange::External,
            shown: Shown::Always,
            get: |l| l.work_coriolis,
        },
        LedgerField {
            name: "dissipated",
            metric: "dissipated",
            unit: "J",
            description: "dissipated energy",
            exchange: Exchange::Removed,
            shown: Shown::Always,
            get: |l| l.dissipated,
        },
        LedgerField {
            name: "fracture",
            metric: "fracture_energy",
            unit: "J",
            description: "fracture energy",
            exchange: Exchange::Removed,
            shown: Shown::Fracture,
            get: |l| l.fracture,
        },
        LedgerField {
            name: "vibration",
            metric: "vibration_energy",
            unit: "J",
            description: "energy left in the lattices' vibration",
            exchange: Exchange::Removed,
            shown: Shown::Fracture,
            get: |l| l.vibration,
        },
        LedgerField {
            name: "dashpot",
            metric: "dashpot_energy",
            unit: "J",
            description: "energy taken by the lattices' dashpots",
            exchange: Exchange::Removed,
            shown: Shown::Fracture,
            get: |l| l.dashpot,
        },
        // Last, so that the residuals of the cases without crushing (a
        // zero added last) stay bit-identical.
        LedgerField {
            name: "crushing",
            metric: "crushing_energy",
            unit: "J",
            description: "work of the crushing forces and kinetic energy of the crushed ice",
            exchange: Exchange::Removed,
            shown: Shown::Crushing,
            get: |l| l.crushing,
        },
    ];

    /// Every field with its value, in the order of [`Ledger::FIELDS`].
    pub fn values(&self) -> impl Iterator<Item = (&'static LedgerField, f64)> + '_ {
        Ledger::FIELDS.iter().map(move |f| (f, (f.get)(self)))
    }

    /// The sum of the fields that enter the balance as `exchange`, added
    /// in the order of [`Ledger::FIELDS`] (0 for none), J.
    fn sum(&self, exchange: Exchange) -> f64 {
        self.values()
            .filter(|(f, _)| f.exchange == exchange)
            .map(|(_, v)| v)
            .reduce(|a, b| a + b)
            .unwrap_or(0.0)
    }

    /// Total work of the external forces, `W_ext`, J.
    pub fn external_work(&self) -> f64 {
        self.sum(Exchange::External)
    }

    /// Energy removed from the floes by contacts, dissipated or spent on
    /// cracks or left in the lattices, `D + F + L`, J.
    pub fn removed(&self) -> f64 {
        self.sum(Exchange::Removed)
    }

    /// The balance residual `E − E(0) − W_ext + D + F + L` of kinetic energy
    /// `kinetic` against `initial_kinetic` (J), which is zero for an exact
    /// integration, J. The removed energies are added one by one, in the
    /// order of [`Ledger::FIELDS`].
    pub fn residual(&self, kinetic: f64, initial_kinetic: f64) -> f64 {
        self.values()
            .filter(|(f, _)| f.exchange == Exchange::Removed)
            .fold(
                kinetic - initial_kinetic - self.external_work(),
                |r, (_, v)| r + v,
            )
    }
}

/// The fields of [`Ledger::FIELDS`], by name, in their order.
impl Serialize for Ledger {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut s = serializer.serialize_struct("Ledger", Ledger::FIELDS.len())?;
        for (f, v) in self.values() {
            s.serialize_field(f.name, &v)?;
        }
        s.end()
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
                    angle: f.angle,
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
/// floe's centre of mass, angle, velocity and angular velocity replaced;
/// its outline is not turned, so the new run's angles go on from the
/// earlier run's, measured from the case's outlines like them, and a run
/// started from a restarted run's output finds its floes turned as they
/// were (an outline turned to the earlier angle and an angle starting at 0
/// would make that second restart turn each floe twice). The
/// state is taken as an earlier run left it: floes in contact or within
/// that run's penetration tolerance are not re-checked for overlap.
/// `restart` records where it comes from.
pub fn restart(
    scn: &mut Scenario,
    bodies: &[BodyState],
    restart: crate::model::Restart,
) -> Result<(), String> {
    if scn.contact.crushing.is_some() {
        // trajectory.csv holds the floes' positions, not the outlines the
        // crushing cut: the case's outlines at the crushed centres would
        // overlap and lose the crushed ice.
        return Err(format!(
            "{}: a case with [contact] crushing cannot start from an earlier run's state: trajectory.csv does not hold the outlines the crushing cut (case `{}`)",
            restart.file.display(),
            scn.name
        ));
    }
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
        f.angle = b.angle;
        f.position = b.position;
        f.velocity = b.velocity;
        f.angular_velocity = b.angular_velocity;
    }
    scn.restart = Some(restart);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`Ledger::FIELDS`] reads every field of the ledger once, under a name
    /// of its own. The literal names every field: a field added to the
    /// ledger must be added to it, with the next value, and then to the
    /// list, or this fails.
    #[test]
    fn the_field_list_reads_every_field_of_the_ledger_once() {
        let l = Ledger {
            work_air: 1.0,
            work_water: 2.0,
            work_coriolis: 3.0,
            dissipated: 4.0,
            fracture: 5.0,
            vibration: 6.0,
            dashpot: 7.0,
            crushing: 8.0,
        };
        let mut read: Vec<f64> = l.values().map(|(_, v)| v).collect();
        read.sort_by(f64::total_cmp);
        let every: Vec<f64> = (1..=Ledger::FIELDS.len()).map(|k| k as f64).collect();
        assert_eq!(read, every);
        assert_eq!(Ledger::FIELDS.len(), 8, "a field added to the literal");
        for (i, a) in Ledger::FIELDS.iter().enumerate() {
            for b in &Ledger::FIELDS[i + 1..] {
                assert!(a.name != b.name && a.metric != b.metric, "{}", a.name);
            }
        }
    }

    /// The balance and its parts add the fields in the order they did when
    /// they were written out: the same bits.
    #[test]
    fn the_balance_adds_the_fields_in_their_order() {
        let l = Ledger {
            work_air: 0.1,
            work_water: -0.7,
            work_coriolis: 1e-17,
            dissipated: 0.3,
            fracture: 0.2,
            vibration: 0.0,
            dashpot: 0.0,
            crushing: 0.0,
        };
        let ext = l.work_air + l.work_water + l.work_coriolis;
        assert_eq!(l.external_work().to_bits(), ext.to_bits());
        assert_eq!(l.removed().to_bits(), (l.dissipated + l.fracture).to_bits());
        let (e, e0) = (1.3, 1.9);
        let r = e - e0 - ext + l.dissipated + l.fracture;
        assert_eq!(l.residual(e, e0).to_bits(), r.to_bits());
    }

    /// A ledger serializes as its fields by name, in the list's order.
    #[test]
    fn a_ledger_serializes_as_its_named_fields() {
        let l = Ledger {
            work_air: 1.5,
            fracture: -0.0,
            ..Ledger::default()
        };
        let json = serde_json::to_string(&l).unwrap();
        assert_eq!(
            json,
            r#"{"work_air":1.5,"work_water":0.0,"work_coriolis":0.0,"dissipated":0.0,"fracture":-0.0,"vibration":0.0,"dashpot":0.0,"crushing":0.0}"#
        );
    }
}
