//! What the runner hands a formulation with each [`super::Formulation::advance`]:
//! the stage clock, the run's topology stage and the interrupt handle.
//!
//! **Topology belongs to the run.** A change of the floe set (a fracture)
//! or of the floes' outlines (crushing) is decided and carried out by the
//! run's topology stage (the fracture stage and the crush stage,
//! [`crate::fracture::topology::RunTopology`], owned by the
//! [`crate::run::Runner`]), once for every formulation. A formulation only
//! *reports* what its contact solves did, through the narrow interface
//! [`Topology`]:
//!
//! - [`Topology::percussion`]: the impulses of one contact solve (an
//!   impact at an instant, or a time-stepping scheme's step), with the
//!   kinetic energy the solve removed;
//! - [`Topology::sustained`]: the impulses that sustained contact forces
//!   delivered over a step (an event-driven scheme's smooth step);
//! - [`Topology::crushed`]: the pairs of bodies whose normal impulse
//!   reached its crushing bound in a contact solve (`[contact] crushing`,
//!   docs/physics.md §10): the crush stage cuts their overlap at the next
//!   safe point;
//!
//! and, before applying its rigid impact law to a group of contacts, asks
//! [`Topology::impact`] (through [`Context::impact`], which charges it to
//! the clock's lattice stage) whether the stage resolves it instead (`[fracture]
//! impact = "lattice"`: the pair's lattices, docs/physics.md §9.10): the
//! query is built from the group's impacting contacts by
//! [`ImpactQuery::of`], the answer's velocities replace the rigid law's and
//! [`ImpactAnswer::book`] books its energies, the same way in every
//! formulation;
//!
//! and names the *safe points* of its scheme, where the floe set may change
//! (between two steps of a fixed grid; at an impact instant, before the
//! instant starts again): there it calls [`Context::change_floes`], and
//! when the stage changed the floe set, rebuilds what depends on it in
//! [`super::Formulation::floes_changed`]. A formulation never decides a
//! fracture and never splits a floe; a new formulation that reports its
//! solves gets fracture (docs/physics.md §9.5) for free.

use crate::contact::{Contact, Load};
use crate::geometry::Vec2;
use crate::model::{Body, Scenario};
use crate::record::{Counters, Stage, StageClock};
use crate::state::{BodyState, Ledger, System};
pub use crate::stop::Interrupt;

/// Which reports the topology stage reads: a formulation builds loads only
/// when they are read (a case without fracture, without obstacles and with
/// one floe reads none). Building them changes no result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Reads {
    /// The impulses of contact solves ([`Topology::percussion`]): read by
    /// every fracture criterion, and by the forces stage in a case with an
    /// obstacle or two floes (`crate::fracture::forces`).
    pub percussions: bool,
    /// The impulses of sustained contact forces over a step
    /// ([`Topology::sustained`]): read by the stress criterion, which
    /// keeps a window of the floe's stress (docs/physics.md §9.3), and by
    /// the forces stage as the percussions.
    pub sustained: bool,
    /// Whether it resolves impacts ([`Topology::impact`]): `[fracture]
    /// impact = "lattice"` (docs/physics.md §9.10).
    pub impacts: bool,
}

/// An impact of one pair of bodies as a formulation hands it to the
/// topology stage ([`Topology::impact`], docs/physics.md §9.10).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactQuery {
    /// The two bodies (body ids: floes, then obstacles); the first is a
    /// floe.
    pub bodies: [usize; 2],
    /// Their poses and velocities just before the impact (an obstacle's is
    /// the first's, unused).
    pub states: [BodyState; 2],
    /// The contact point: the mean of the pair's impacting contact points,
    /// m (world).
    pub point: Vec2,
    /// The unit normal from the first body towards the second: the mean of
    /// the pair's contact normals.
    pub normal: Vec2,
    /// How many pairs of bodies the group's impacting contacts hold: the
    /// stage resolves a group of one pair only.
    pub pairs: usize,
}

impl ImpactQuery {
    /// The query of a group's impacting contacts `contacts` (at least
    /// one), the floes' states given by `state` (floe index → its pose and
    /// velocities before the impact): the pair of the first contact, its
    /// contacts' mean point and normal; `None` without a contact or when
    /// the normals cancel.
    pub fn of(
        scn: &Scenario,
        contacts: &[&Contact],
        state: impl Fn(usize) -> BodyState,
    ) -> Option<ImpactQuery> {
        let key = |c: &Contact| (c.a.min(c.b), c.a.max(c.b));
        let mut pairs: Vec<(usize, usize)> = contacts.iter().map(|c| key(c)).collect();
        pairs.sort_unstable();
        pairs.dedup();
        let first = contacts.first()?;
        let (mut point, mut normal, mut count) = (Vec2::zeros(), Vec2::zeros(), 0.0);
        for c in contacts.iter().filter(|c| key(c) == key(first)) {
            let sign = if c.a == first.a { 1.0 } else { -1.0 };
            point += c.geom.point;
            normal += c.geom.normal * sign;
            count += 1.0;
        }
        let norm = normal.norm();
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        let (bodies, normal) = match scn.body(first.a) {
            Body::Floe(_) => ([first.a, first.b], normal / norm),
            Body::Obstacle(_) => ([first.b, first.a], -normal / norm),
        };
        let states = bodies.map(|b| match scn.body(b) {
            Body::Floe(i) => state(i),
            Body::Obstacle(_) => state(bodies[0]),
        });
        Some(ImpactQuery {
            bodies,
            states,
            point: point / count,
            normal,
            pairs: pairs.len(),
        })
    }
}

/// How the topology stage resolved an impact ([`Topology::impact`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactAnswer {
    /// The query's bodies' velocities (m/s) and angular velocities (rad/s)
    /// after the impact, in its order (an obstacle's unused).
    pub velocities: [(Vec2, f64); 2],
    /// Energy the lattices kept in vibration (and in their contact
    /// springs, if any), J.
    pub vibration: f64,
    /// Energy their dashpots took, J.
    pub dashpot: f64,
    /// The effective restitution of the impact (-).
    pub restitution: f64,
}

impl ImpactAnswer {
    /// The floes it sets: (floe index, velocity, angular velocity).
    pub fn floes<'a>(
        &'a self,
        scn: &'a Scenario,
        query: &'a ImpactQuery,
    ) -> impl Iterator<Item = (usize, Vec2, f64)> + 'a {
        query
            .bodies
            .iter()
            .zip(&self.velocities)
            .filter_map(|(&b, &(v, w))| match scn.body(b) {
                Body::Floe(i) => Some((i, v, w)),
                Body::Obstacle(_) => None,
            })
    }

    /// Books an impact that took the pair's rigid kinetic energy from
    /// `before` to `after` (J): the lattices' vibration and dashpot
    /// energies in their columns, the rest (the lattice integration's
    /// energy error and the lattices' rigid inertia against the floes') in
    /// `dissipated` (docs/physics.md §9.10), so the ledger closes.
    pub fn book(&self, ledger: &mut Ledger, before: f64, after: f64) {
        ledger.vibration += self.vibration;
        ledger.dashpot += self.dashpot;
        ledger.dissipated += (before - after) - (self.vibration + self.dashpot);
    }
}

/// The run's topology stage as a formulation sees it (see the module doc).
pub trait Topology {
    /// Which reports it reads.
    fn reads(&self) -> Reads;

    /// The impulses `loads` of one contact solve, delivered over
    /// `[from, to]` (s; an instant when equal), on the floes of `sys` (the
    /// state the loads' points refer to); the solve removed `dissipated`
    /// (J) of kinetic energy, from which crack energies are taken.
    fn percussion(
        &mut self,
        scn: &Scenario,
        sys: &System,
        loads: &[Load],
        from: f64,
        to: f64,
        dissipated: f64,
    );

    /// The impulses `loads` that sustained contact forces delivered over
    /// `[from, to]` (s), on the floes of `sys`.
    fn sustained(&mut self, scn: &Scenario, sys: &System, loads: &[Load], from: f64, to: f64);

    /// Resolves the impact `query` in the pair's lattices when the stage
    /// reads impacts ([`Reads::impacts`]), instead of the formulation's
    /// rigid law (docs/physics.md §9.10); `sys` is the state the query's
    /// positions are those of. `None`: the formulation applies its rigid
    /// law (the default; a group of several pairs, counted; a lattice
    /// that fails, counted). The stage may queue fractures from the
    /// impact's impulses, for the next safe point.
    fn impact(
        &mut self,
        scn: &Scenario,
        sys: &System,
        query: &ImpactQuery,
    ) -> Option<ImpactAnswer> {
        let _ = (scn, sys, query);
        None
    }

    /// The pairs of bodies `(a, b)` whose normal impulse reached its
    /// crushing bound in a contact solve on the floes of `sys`
    /// (`[contact] crushing`, docs/physics.md §10): `a` is a floe, `b` a
    /// floe or, from `scn.floes.len()` on, an obstacle (body ids,
    /// [`Scenario::body`]). The stage cuts their overlap at the next safe
    /// point ([`Topology::pending`]). The default ignores them (a run
    /// without crushing).
    fn crushed(&mut self, scn: &Scenario, sys: &System, pairs: &[(usize, usize)]) {
        let _ = (scn, sys, pairs);
    }

    /// Its own counters, added to the formulation's in `summary.json`
    /// (the default: none).
    fn counters(&self) -> Counters {
        Counters::default()
    }

    /// Whether a change of the floe set waits for the formulation's next
    /// safe point.
    fn pending(&self) -> bool;

    /// Carries out the pending change on `scn` and `sys` at `sys.t` (the
    /// scenario's floes, its history and the state's bodies together),
    /// charging the stages it has to `clock` (the crush stage's cuts to
    /// [`Stage::Crushing`]). Returns the floe ids before the change, in
    /// index order, when the floes may have changed: the fracture stage
    /// whenever a fracture was pending (even if every cut of it was
    /// refused: the formulation rebuilds all the same), the crush stage
    /// when it changed a floe (docs/physics.md §10.8); `None` otherwise.
    fn apply(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        clock: &mut StageClock,
    ) -> Option<Vec<usize>>;
}

/// A topology stage that never changes the floe set (a run without
/// fracture, benches and tests that drive a formulation alone).
#[derive(Debug, Clone, Copy, Default)]
pub struct FixedTopology;

impl Topology for FixedTopology {
    fn reads(&self) -> Reads {
        Reads::default()
    }

    fn percussion(&mut self, _: &Scenario, _: &System, _: &[Load], _: f64, _: f64, _: f64) {}

    fn sustained(&mut self, _: &Scenario, _: &System, _: &[Load], _: f64, _: f64) {}

    fn pending(&self) -> bool {
        false
    }

    fn apply(
        &mut self,
        _: &mut Scenario,
        _: &mut System,
        _: &mut StageClock,
    ) -> Option<Vec<usize>> {
        None
    }
}

/// What a formulation gets with each [`super::Formulation::advance`].
pub struct Context<'a> {
    /// The clock it charges its CPU time to, by stage.
    pub clock: &'a mut StageClock,
    /// The run's topology stage.
    pub topology: &'a mut dyn Topology,
    /// The run's stop request.
    pub interrupt: &'a Interrupt,
}

impl<'a> Context<'a> {
    /// The context of a run with these parts.
    pub fn new(
        clock: &'a mut StageClock,
        topology: &'a mut dyn Topology,
        interrupt: &'a Interrupt,
    ) -> Context<'a> {
        Context {
            clock,
            topology,
            interrupt,
        }
    }

    /// [`super::FormulationError::Interrupted`] at `t` (s) if a stop was
    /// asked for: the step loops poll it once per step (an atomic load),
    /// so a run whose outputs are far apart still stops at once.
    pub fn poll_interrupt(&self, t: f64) -> Result<(), super::FormulationError> {
        if self.interrupt.requested() {
            Err(super::FormulationError::Interrupted { t })
        } else {
            Ok(())
        }
    }

    /// The topology stage's answer for the impact `query`
    /// ([`Topology::impact`]), its time charged to the clock's lattice
    /// stage ([`Stage::Lattice`]; nested in the caller's solve region, it
    /// is taken out of the solve's time). Every formulation asks through
    /// here, so the lattices' cost is one stage of the CPU breakdown.
    pub fn impact(
        &mut self,
        scn: &Scenario,
        sys: &System,
        query: &ImpactQuery,
    ) -> Option<ImpactAnswer> {
        let started = self.clock.start(Stage::Lattice);
        let answer = self.topology.impact(scn, sys, query);
        self.clock.stop(Stage::Lattice, started);
        answer
    }

    /// Reports to the topology stage the pairs of bodies whose normal
    /// impulse reached its crushing bound in a contact solve on the floes
    /// of `sys` ([`Topology::crushed`]; body ids, `a` a floe): every
    /// formulation reports through here, after each contact solve of a
    /// case with `[contact] crushing`.
    pub fn crushed(&mut self, scn: &Scenario, sys: &System, pairs: &[(usize, usize)]) {
        if !pairs.is_empty() {
            self.topology.crushed(scn, sys, pairs);
        }
    }

    /// At a safe point of the formulation's scheme: the topology stage's
    /// pending change, carried out on `scn` and `sys` (see
    /// [`Topology::apply`]); the floe ids before it when a change was
    /// pending, for [`super::Formulation::floes_changed`].
    pub fn change_floes(&mut self, scn: &mut Scenario, sys: &mut System) -> Option<Vec<usize>> {
        if self.topology.pending() {
            self.topology.apply(scn, sys, self.clock)
        } else {
            None
        }
    }
}
