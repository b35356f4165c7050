//! The impact of two lattices (docs/physics.md §9.9): both bodies of a
//! rigid impact resolved as lattices ([`super::Lattice`]), each started
//! with its rigid velocity field at the impact, in unilateral penalty
//! contact through their outlines, run until they separate; what comes out
//! is each body's rigid motion after the impact, the energy left in
//! vibration, in the dashpots and in broken bonds, and the effective
//! restitution. A fixed obstacle stays rigid: the percussion's striker of
//! infinite mass, a half-plane through the contact point.
//!
//! **Scheme.** Each body is a [`Percussion`] (its springs, dashpots,
//! torsion springs, bond breaking and velocity Verlet, docs/physics.md
//! §7.3) with no striker (or the obstacle's); one step advances both
//! lattices, adds the contact forces at the new positions, then gives both
//! their last half kick. **Contact law**: every outline node `p` of one
//! body inside the other's outline (its current boundary nodes,
//! counter-clockwise; the crossing-number test) is pushed out towards the
//! nearest point `q = a + t (b − a)`, `t ∈ [0, 1]`, of that outline's
//! segments `a b` by a compression-only link of rest length 0 (the chain's
//! unilateral link): the striker's law, the stiffness `κ̄` the pushing
//! node's lattice's mean spring stiffness and the dashpot `β √(κ̄ μ)`, `μ`
//! the reduced mass of the node and the segment's two nodes, on the gap
//! `g = −|p − q|` (the signed distance to the outline, continuous as the
//! nearest segment changes, so the penalty energy `½ κ̄ g²` is too) and
//! its rate `n · (v_p − (1 − t) v_a − t v_b)`, `n = (q − p)/|q − p|`; the
//! segment's nodes take the reaction in shares `1 − t` and `t`. The force
//! is along `p − q`, so the pair's linear and angular momenta are
//! conserved to round-off. Both outlines push, so
//! two faces pressed flat together are held by up to twice the striker's
//! stiffness. The stable step adds to each outline node's
//! block-Gershgorin row `(2 + ⌈s_o/s⌉) κ̄ (1/m_i + 1/√(m_i m_o))` (one
//! contact as the pushing node, at most about `s_o/s + 1` as the end of the
//! other's segments; `s` the spacings, `m_o` the other's least outline
//! mass).
//!
//! **Start.** The lattices are placed at the floes' poses. Where these
//! overlap (a time-stepping scheme's penetration, docs/physics.md §5),
//! the second body is first moved along `n` by the deepest overlap, again
//! until no outline node of one body is inside the other: the impact
//! starts at first touch, with no energy stored in the contact links (an
//! overlap of depth `d` would hold `½ κ̄ d²` per node and throw the floes
//! apart). Where they are apart (a gap the rigid scheme's contact
//! tolerance leaves, or the outlines' nodes a little off the polygons'),
//! the second body is first moved along `−n` until an outline node meets
//! the other outline: otherwise a slow approach would end the run before
//! the lattices ever touch, and the impact would return the velocities it
//! was given. Only velocities leave the impact, so the move changes no pose;
//! it changes no normal velocity either (`n · perp(n) = 0`).
//!
//! **Stopping rule.** The contact is over when no node touches the other
//! body (nor the obstacle's striker) and the relative normal velocity of
//! the two bodies' rigid motions at the contact point is not negative
//! (they separate); then [`crate::fracture::chain::Settling`] as in the
//! percussion: stop once the internal energy is under `settle` times the
//! impact energy `½ μ u_N²` (`μ` the pair's effective mass along `n` at the
//! contact point), or `settle_transits` transit times of the slower body
//! have passed with the contact over; in any case after `limit_transits`.
//!
//! **Pieces.** When bonds broke, each body's pieces are the connected
//! components of its unbroken springs, as rigid bodies in its lattice's
//! rest frame with their nodes' final velocities turned into it (the
//! percussion's [`super::percussion::Fragment`]s, §9.8): the fracture
//! stage makes floes of them.
//!
//! **Outputs.** Each body's rigid motion: the centre-of-mass velocity of
//! its nodes' linear momentum and the angular velocity of their angular
//! momentum about their centre of mass over the body's rigid inertia (the
//! lattice's lumped masses have the floe's). The relative normal velocity
//! is taken at the impact's configuration (the contact point and the
//! centres of mass at the impact), as the rigid law's:
//! `e_eff = −u_N(after) / u_N(before)`. The dashpots' energy is their
//! power integrated (trapezoid rule over the steps), not a remainder, so
//! that `½ Σ m v² (before) = rigid + vibration + dashpots + fracture (+ the
//! contact links' elastic energy, 0 once apart)` checks the integrator.

use super::percussion::{
    gershgorin_weight, mean_stiffness, step_of_rows, Fragment, Impact, NodeMotion, Percussion,
    RigidMotion,
};
use super::{Lattice, LatticeSpec};
use crate::fracture::chain::{ChainOptions, Settling, Stop};
use crate::geometry::{cross, perp, rotate, Vec2};
use crate::state::BodyState;
use contact::Touch;

mod contact;

/// One body of a two-lattice impact: what a fracture stage has of a floe.
#[derive(Debug, Clone, Copy)]
pub struct PairBody<'a> {
    /// Outline about the centre of mass at angle 0, counter-clockwise, m
    /// ([`crate::model::Floe::shape`]).
    pub shape: &'a [Vec2],
    /// Pose and rigid velocities at the impact.
    pub state: BodyState,
    /// Its lattice ([`crate::fracture::strike::lattice_spec`]).
    pub spec: LatticeSpec,
}

/// A two-lattice impact: a floe against another floe or a fixed obstacle.
#[derive(Debug, Clone, Copy)]
pub struct PairImpact<'a> {
    /// The first floe.
    pub first: PairBody<'a>,
    /// The second floe, or `None` for a fixed obstacle (the half-plane
    /// through `point` with outward normal `−normal`).
    pub second: Option<PairBody<'a>>,
    /// The contact point, m (world).
    pub point: Vec2,
    /// The unit contact normal, from the first body towards the second
    /// (into the obstacle).
    pub normal: Vec2,
    /// The lattices' dashpots, bond rule, step safety and stopping
    /// thresholds ([`crate::fracture::strike::chain_options`]).
    pub options: ChainOptions,
}

/// A body after a two-lattice impact.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyOutcome {
    /// Mass, kg.
    pub mass: f64,
    /// Rigid polar inertia about the centre of mass, kg·m².
    pub inertia: f64,
    /// Centre of mass at the end, m.
    pub centre: Vec2,
    /// Linear momentum of the nodes, kg·m/s.
    pub momentum: Vec2,
    /// Angular momentum of the nodes about their centre of mass, kg·m²/s.
    pub angular_momentum: f64,
    /// Velocity of the centre of mass, m/s.
    pub velocity: Vec2,
    /// Angular velocity (angular momentum over the rigid inertia), rad/s.
    pub angular_velocity: f64,
    /// Kinetic energy of that rigid motion, J.
    pub rigid_energy: f64,
    /// Energy left in vibration: the nodes' kinetic energy less the rigid
    /// one, plus the springs' and torsion springs' elastic energy, J.
    pub vibration: f64,
    /// Energy held by the bonds that broke, J.
    pub fracture: f64,
    /// How many bonds broke.
    pub broken: usize,
    /// The springs that broke, in the order they broke.
    pub bonds: Vec<usize>,
    /// Its breaking energy's least value over its bonds, J
    /// ([`Percussion::weakest_bond_energy`]).
    pub weakest: f64,
    /// When a bond broke: the connected components of its unbroken
    /// springs as rigid bodies in the lattice's rest frame (module doc,
    /// **Pieces**); empty otherwise.
    pub pieces: Vec<Fragment>,
    /// When a bond broke: the nodes' velocities at the end, turned into the
    /// lattice's frame (those of `pieces`), m/s; empty otherwise.
    pub rest_velocities: Vec<Vec2>,
}

/// What a two-lattice impact gives.
#[derive(Debug, Clone, PartialEq)]
pub struct PairOutcome {
    /// Why it stopped.
    pub reason: Stop,
    /// When, s after the impact.
    pub t: f64,
    /// When the contact ended, s.
    pub contact_end: f64,
    /// The step, s.
    pub dt: f64,
    /// Steps taken.
    pub steps: u64,
    /// The bodies (one when the second is an obstacle).
    pub bodies: Vec<BodyOutcome>,
    /// Kinetic energy of the nodes at the impact, J.
    pub initial_energy: f64,
    /// Impact energy `½ μ u_N²`, J.
    pub impact_energy: f64,
    /// Work done by the obstacle's striker, J (0: it is at rest).
    pub work: f64,
    /// Energy taken out by the dashpots (lattices and contacts), J.
    pub damping: f64,
    /// Elastic energy still in the contact links at the end, J (0 once
    /// apart).
    pub contact_energy: f64,
    /// Relative normal velocity of the rigid motions at the contact point,
    /// before and after, m/s (negative approaching).
    pub normal_velocity: [f64; 2],
    /// The effective restitution `−u_N(after) / u_N(before)` (-).
    pub restitution: f64,
    /// Linear momentum of every node, before and after, kg·m/s.
    pub momentum: [Vec2; 2],
    /// Angular momentum of every node about the world origin, before and
    /// after, kg·m²/s.
    pub angular_momentum: [f64; 2],
}

impl PairOutcome {
    /// The bodies' rigid kinetic energy, J.
    pub fn rigid_energy(&self) -> f64 {
        self.bodies.iter().map(|b| b.rigid_energy).sum()
    }

    /// The energy left in vibration, J.
    pub fn vibration(&self) -> f64 {
        self.bodies.iter().map(|b| b.vibration).sum()
    }

    /// The energy of the broken bonds, J.
    pub fn fracture(&self) -> f64 {
        self.bodies.iter().map(|b| b.fracture).sum()
    }

    /// `initial + work − (rigid + vibration + damping + fracture +
    /// contact)`, J: the integrator's energy error.
    pub fn energy_defect(&self) -> f64 {
        self.initial_energy + self.work
            - (self.rigid_energy()
                + self.vibration()
                + self.damping
                + self.fracture()
                + self.contact_energy)
    }
}

/// A body under way: its percussion, outline and rigid data.
struct Body<'a> {
    p: Percussion<'a>,
    /// The outline's nodes in order (counter-clockwise).
    outline: Vec<usize>,
    all: Vec<usize>,
    /// The mean spring stiffness `κ̄`, N/m.
    link_k: f64,
    /// The dashpot ratio `β` (-).
    damping: f64,
    inertia: f64,
    /// Centre of mass at the impact, m.
    start: Vec2,
    /// The body's angle at the impact (its lattice's frame), rad.
    angle: f64,
}

impl Body<'_> {
    fn motion(&self) -> NodeMotion {
        NodeMotion::of(&self.all, &self.p.x, &self.p.v, &self.p.lattice.mass)
    }

    /// Velocity (m/s) and angular velocity (rad/s) of its rigid motion.
    fn rigid(&self) -> (Vec2, f64) {
        let nm = self.motion();
        (nm.velocity, nm.angular_momentum / self.inertia)
    }

    /// The rigid velocity along `n` at `point` (about the centre at the
    /// impact), m/s.
    fn normal_velocity(&self, point: &Vec2, n: &Vec2) -> f64 {
        let (v, w) = self.rigid();
        n.dot(&(v + perp(&(point - self.start)) * w))
    }
}

impl PairImpact<'_> {
    /// Builds both lattices ([`Lattice::build`]) and runs the impact
    /// ([`Self::run_on`]).
    pub fn run(&self) -> Result<PairOutcome, String> {
        let a = Lattice::build(self.first.shape, self.first.spec)?;
        let b = match &self.second {
            Some(s) => Some(Lattice::build(s.shape, s.spec)?),
            None => None,
        };
        self.run_on(&a, b.as_ref())
    }

    /// Runs the impact on the bodies' lattices (built from their shapes
    /// and specs; `second` for the second floe, `None` with an obstacle).
    /// Fails on an invalid option, normal or lattice, or when the bodies
    /// are not approaching at the contact point.
    pub fn run_on(&self, first: &Lattice, second: Option<&Lattice>) -> Result<PairOutcome, String> {
        let n = self.normal;
        let off = (n.norm() - 1.0).abs();
        if off.is_nan() || off >= 1e-9 || !self.point.iter().all(|c| c.is_finite()) {
            return Err(format!(
                "the contact normal must be a unit vector and the point finite, got {n:?} at {:?}",
                self.point
            ));
        }
        let rigid_at = |s: &BodyState| {
            n.dot(&(s.velocity + perp(&(self.point - s.position)) * s.angular_velocity))
        };
        let u0 =
            self.second.as_ref().map_or(0.0, |b| rigid_at(&b.state)) - rigid_at(&self.first.state);
        if u0.is_nan() || u0 >= 0.0 {
            return Err(format!(
                "the bodies are not approaching at the contact point (normal velocity {u0} m/s)"
            ));
        }
        let wall = [Impact {
            point: self.point,
            normal: -n,
            mass: f64::INFINITY,
            speed: -u0,
        }];
        let strikers: &[Impact] = if self.second.is_none() { &wall } else { &[] };
        let mut bodies = vec![body(&self.first, first, strikers, self.options)?];
        match (&self.second, second) {
            (Some(s), Some(l)) => bodies.push(body(s, l, &[], self.options)?),
            (None, None) => {}
            _ => return Err("each floe needs its lattice, and only floes".into()),
        }
        let mut pair = Pair {
            bodies,
            touches: Vec::new(),
            damping: 0.0,
            power: 0.0,
        };
        pair.close(n);
        pair.separate(n)?;
        let dt = self.options.safety * pair.stable_step();
        for b in &mut pair.bodies {
            b.p.dt = dt;
        }
        pair.contact_forces();
        pair.power = pair.dashpot_power();
        let initial_energy: f64 = pair.bodies.iter().map(|b| b.p.energies().kinetic).sum();
        let (momentum, angular) = pair.momentum();
        let inverse_mass: f64 = pair
            .bodies
            .iter()
            .map(|b| {
                let r = cross(&(self.point - b.start), &n);
                1.0 / b.p.lattice.mass.iter().sum::<f64>() + r * r / b.inertia
            })
            .sum();
        let impact_energy = 0.5 * u0 * u0 / inverse_mass;
        let transit = pair.bodies.iter().map(|b| b.p.transit).fold(0.0, f64::max);
        let u_after = |pair: &Pair| {
            let ua = pair.bodies[0].normal_velocity(&self.point, &n);
            pair.bodies
                .get(1)
                .map_or(0.0, |b| b.normal_velocity(&self.point, &n))
                - ua
        };
        let mut settling = Settling::new();
        let options = self.options;
        let reason = loop {
            pair.step(dt);
            let t = pair.bodies[0].p.t;
            let over = pair.touches.is_empty()
                && !pair.bodies.iter().any(|b| b.p.touching())
                && u_after(&pair) >= 0.0;
            let internal = || pair.bodies.iter().map(|b| vibration(b).0).sum::<f64>();
            if let Some(stop) = settling.stop(t, over, internal, impact_energy, transit, &options) {
                break stop;
            }
        };
        let u1 = u_after(&pair);
        let (momentum_end, angular_end) = pair.momentum();
        let contact_energy = pair.contact_energy()
            + pair
                .bodies
                .iter()
                .map(|b| b.p.energies().elastic - b.p.spring_energy())
                .sum::<f64>();
        let first = &pair.bodies[0];
        Ok(PairOutcome {
            reason,
            t: first.p.t,
            contact_end: settling.contact_end,
            dt,
            steps: first.p.steps,
            bodies: pair.bodies.iter().map(outcome).collect(),
            initial_energy,
            impact_energy,
            work: pair.bodies.iter().map(|b| b.p.work).sum(),
            damping: pair.damping,
            contact_energy,
            normal_velocity: [u0, u1],
            restitution: -u1 / u0,
            momentum: [momentum, momentum_end],
            angular_momentum: [angular, angular_end],
        })
    }
}

/// The percussion of one body placed at its pose, with its rigid
/// velocities, struck by `impacts` (the obstacle's, or none).
fn body<'a>(
    b: &PairBody<'_>,
    lattice: &'a Lattice,
    impacts: &[Impact],
    options: ChainOptions,
) -> Result<Body<'a>, String> {
    let motion = RigidMotion {
        velocity: b.state.velocity,
        angular_velocity: b.state.angular_velocity,
    };
    let p = Percussion::placed(
        lattice,
        motion,
        impacts,
        options,
        b.state.position,
        b.state.angle,
    )?;
    let outline: Vec<usize> = (0..lattice.nodes.len())
        .filter(|&i| lattice.on_boundary[i])
        .collect();
    if outline.iter().enumerate().any(|(k, &i)| k != i) {
        return Err("the lattice's outline nodes must come first".into());
    }
    let all: Vec<usize> = (0..lattice.nodes.len()).collect();
    let rest = NodeMotion::of(&all, &lattice.nodes, &p.v, &lattice.mass);
    let link_k = mean_stiffness(lattice);
    let start = NodeMotion::of(&all, &p.x, &p.v, &lattice.mass).centre;
    Ok(Body {
        p,
        outline,
        all,
        link_k,
        damping: options.damping,
        inertia: rest.inertia,
        start,
        angle: b.state.angle,
    })
}

/// A body's energy in vibration (J) and its rigid motion.
fn vibration(b: &Body<'_>) -> (f64, NodeMotion, f64) {
    let e = b.p.energies();
    let nm = b.motion();
    let w = nm.angular_momentum / b.inertia;
    let rigid = 0.5 * nm.mass * nm.velocity.norm_squared() + 0.5 * b.inertia * w * w;
    (
        e.kinetic + b.p.spring_energy() + e.torsion - rigid,
        nm,
        rigid,
    )
}

fn outcome(b: &Body<'_>) -> BodyOutcome {
    let (vib, nm, rigid) = vibration(b);
    let lattice = b.p.lattice;
    let (pieces, rest_velocities) = if b.p.broken.is_empty() {
        (Vec::new(), Vec::new())
    } else {
        let v: Vec<Vec2> = b.p.v.iter().map(|v| rotate(v, -b.angle)).collect();
        let (label, count) = b.p.components();
        let mut lists = vec![Vec::new(); count];
        for (i, &c) in label.iter().enumerate() {
            lists[c].push(i);
        }
        let pieces = lists
            .into_iter()
            .map(|list| Fragment::of_nodes(list, &lattice.nodes, &v, &lattice.mass))
            .collect();
        (pieces, v)
    };
    BodyOutcome {
        mass: nm.mass,
        inertia: b.inertia,
        centre: nm.centre,
        momentum: nm.momentum,
        angular_momentum: nm.angular_momentum,
        velocity: nm.velocity,
        angular_velocity: nm.angular_momentum / b.inertia,
        rigid_energy: rigid,
        vibration: vib,
        fracture: b.p.energies().fracture,
        broken: b.p.broken.len(),
        bonds: b.p.broken.iter().map(|k| k.spring).collect(),
        weakest: b.p.weakest_bond_energy(),
        pieces,
        rest_velocities,
    }
}

/// The two bodies and their contacts.
struct Pair<'a> {
    bodies: Vec<Body<'a>>,
    touches: Vec<Touch>,
    /// Energy taken out by the dashpots so far, J.
    damping: f64,
    /// Their power at the last forces, W.
    power: f64,
}

impl Pair<'_> {
    /// The stable step of both lattices with their contacts (module doc),
    /// before the safety factor.
    fn stable_step(&self) -> f64 {
        let (mut ks, mut cs) = (Vec::new(), Vec::new());
        for (k, b) in self.bodies.iter().enumerate() {
            let (mut bk, mut bc) = b.p.gershgorin_rows();
            if let Some(o) = self.bodies.get(1 - k) {
                let m = &b.p.lattice.mass;
                let mo = o
                    .outline
                    .iter()
                    .map(|&i| o.p.lattice.mass[i])
                    .fold(f64::INFINITY, f64::min);
                let count = 2.0 + (o.p.lattice.spec.spacing / b.p.lattice.spec.spacing).ceil();
                for &i in &b.outline {
                    let link = b.contact_link(m[i], mo);
                    let w = count * gershgorin_weight(m[i], mo);
                    bk[i] += link.k * w;
                    bc[i] += link.c * w;
                }
            }
            ks.extend(bk);
            cs.extend(bc);
        }
        step_of_rows(&ks, &cs)
    }

    /// One velocity Verlet step of both lattices and their contacts.
    fn step(&mut self, dt: f64) {
        for b in &mut self.bodies {
            b.p.advance();
        }
        self.contact_forces();
        let power = self.dashpot_power();
        self.damping += 0.5 * dt * (self.power + power);
        self.power = power;
        for b in &mut self.bodies {
            b.p.finish();
        }
    }

    /// Linear momentum (kg·m/s) and angular momentum about the origin
    /// (kg·m²/s) of every node.
    fn momentum(&self) -> (Vec2, f64) {
        self.bodies
            .iter()
            .map(|b| b.p.momentum())
            .fold((Vec2::zeros(), 0.0), |(p, l), (bp, bl)| (p + bp, l + bl))
    }
}
