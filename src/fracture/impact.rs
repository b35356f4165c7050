//! The two-way coupling of the lattice with the rigid schemes
//! (`[fracture] impact = "lattice"`, docs/physics.md §9.10): the fracture
//! stage resolves an impact of one pair of bodies in the two floes'
//! lattices ([`super::lattice::pair`], §9.9; an obstacle stays a fixed
//! half-plane), and the formulation takes the bodies' rigid motions after
//! it instead of its restitution law's.
//!
//! The pair's lattices are those of the lattice model (the case's
//! `spacing`, `young`, `poisson`, `damping`, `seed` and bond rule; each
//! floe's built once and kept with the percussion's): one run decides the
//! bounce, what the lattices keep in vibration and in their dashpots, and
//! the cracks. A floe whose bonds broke into pieces of `min_area` or more
//! is a [`Decision`] with those pieces; their crack energies and relative
//! motion are taken from the impact's vibration, not from `dissipated`
//! ([`super::stage::FractureStage`]).

use super::lattice::pair::{PairBody, PairImpact};
use super::lattice::percussion::Impact;
use super::lattice::Lattice;
use super::strike::{self, LatticeSplit};
use super::{BodyLine, Decision, Fracturer};
use crate::formulation::context::{ImpactAnswer, ImpactQuery};
use crate::model::{Body, Floe, Scenario};
use crate::record::Counter;

/// The rigid kinetic energy a pair impact may gain, as a fraction of its
/// impact energy `½ μ u_N²`, before it is refused (-): velocity Verlet's
/// energy error at the penalty contacts' onsets, measured 3e-4 to 1.3e-3
/// of the initial energy (tests/suite/pair_impact.rs), well below it.
const ENERGY_GAIN_TOLERANCE: f64 = 1e-2;

/// Impacts resolved by the lattices.
pub const LATTICE_IMPACTS: Counter = Counter::sum(
    "lattice_impacts",
    "impacts resolved by the pair's lattices ([fracture] impact = \"lattice\", docs/physics.md §9.10)",
);
/// Groups of several pairs left to the rigid law.
pub const LATTICE_MULTI_PAIR: Counter = Counter::sum(
    "lattice_impacts_multi_pair_rigid",
    "impact groups of several pairs of bodies left to the formulation's rigid law (docs/physics.md §9.10)",
);
/// Pair impacts that failed (the rigid law then).
pub const LATTICE_FAILED: Counter = Counter::sum(
    "lattice_impacts_failed",
    "pair impacts the lattices refused (not approaching at the mean contact point, still approaching when their run ended, an energy gain, a lattice that cannot be built): the rigid law then",
);
/// Steps of the lattices' integration, summed.
pub const LATTICE_STEPS: Counter = Counter::sum(
    "lattice_impact_steps",
    "velocity Verlet steps of the pair impacts' lattices, summed (their cost)",
);
/// Node-steps of the lattices' integration, summed: each impact's steps
/// times the nodes of its lattices (the unit of its cost).
pub const LATTICE_NODE_STEPS: Counter = Counter::sum(
    "lattice_impact_node_steps",
    "velocity Verlet steps of the pair impacts' lattices times their nodes, summed (the unit of their cost)",
);
/// Every counter of the coupling.
pub const COUNTERS: &[&Counter] = &[
    &LATTICE_IMPACTS,
    &LATTICE_MULTI_PAIR,
    &LATTICE_FAILED,
    &LATTICE_STEPS,
    &LATTICE_NODE_STEPS,
];

impl Fracturer {
    /// The lattice of floe `f` (built once per floe id, kept until the
    /// floe breaks; a build that fails is not tried again for that floe).
    pub(super) fn lattice_of(&mut self, scn: &Scenario, f: &Floe) -> Result<&Lattice, String> {
        if let Some(why) = self.unbuildable.get(&f.id) {
            return Err(why.clone());
        }
        match self.lattices.entry(f.id) {
            std::collections::btree_map::Entry::Occupied(e) => Ok(e.into_mut()),
            std::collections::btree_map::Entry::Vacant(e) => {
                match Lattice::build(&f.shape, strike::lattice_spec(&scn.fracture, f)) {
                    Ok(l) => Ok(e.insert(l)),
                    Err(why) => {
                        self.unbuildable.insert(f.id, why.clone());
                        Err(why)
                    }
                }
            }
        }
    }

    /// The impact `q` in the pair's lattices (module doc): the answer,
    /// the floes it broke (their decisions, pieces made by
    /// [`strike::merged`]), and the lattices' steps and nodes (both
    /// lattices').
    pub fn pair_impact(
        &mut self,
        scn: &Scenario,
        q: &ImpactQuery,
    ) -> Result<(ImpactAnswer, Vec<Decision>, u64, u64), String> {
        let s = &scn.fracture;
        let floe = |b: usize| match scn.body(b) {
            Body::Floe(i) => Some(i),
            Body::Obstacle(_) => None,
        };
        let first = floe(q.bodies[0]).ok_or("the first body of an impact must be a floe")?;
        let second = floe(q.bodies[1]);
        for i in std::iter::once(first).chain(second) {
            self.lattice_of(scn, &scn.floes[i])?;
        }
        let lattice = |i: usize| {
            self.lattices
                .get(&scn.floes[i].id)
                .ok_or_else(|| format!("floe {i}: no lattice"))
        };
        let body = |i: usize, k: usize| PairBody {
            shape: &scn.floes[i].shape,
            state: q.states[k],
            spec: strike::lattice_spec(s, &scn.floes[i]),
        };
        let impact = PairImpact {
            first: body(first, 0),
            second: second.map(|i| body(i, 1)),
            point: q.point,
            normal: q.normal,
            options: strike::chain_options(s),
        };
        let (one, two) = (lattice(first)?, second.map(lattice).transpose()?);
        let nodes = one.nodes.len() + two.map_or(0, |l| l.nodes.len());
        let out = impact.run_on(one, two)?;
        // A passive impact cannot raise the pair's rigid kinetic energy: an
        // answer that does (by more than the integrator's error, a
        // hundredth of the impact energy) is refused, and the rigid law
        // resolves the impact (counted in `lattice_impacts_failed`).
        let gain = out.rigid_energy() - (out.initial_energy + out.work);
        if gain.is_nan() || gain > ENERGY_GAIN_TOLERANCE * out.impact_energy {
            return Err(format!(
                "the lattices' impact raised the rigid kinetic energy by {gain} J \
                 (impact energy {} J)",
                out.impact_energy
            ));
        }
        // An answer that leaves the pair approaching (the run stopped by
        // its time limit) resolved nothing: the scheme would ask again.
        let after = out.normal_velocity[1];
        if after.is_nan() || after < 0.0 {
            return Err(format!(
                "the lattices' impact ended with the bodies still approaching \
                 ({after} m/s at the contact point, {} m/s before; stopped: {} at {} s, \
                 the contact last over at {} s)",
                out.normal_velocity[0],
                out.reason.name(),
                out.t,
                out.contact_end
            ));
        }
        let mut velocities = [(q.states[0].velocity, q.states[0].angular_velocity); 2];
        let mut decisions = Vec::new();
        for (k, b) in out.bodies.iter().enumerate() {
            velocities[k] = (b.velocity, b.angular_velocity);
            let Some(i) = floe(q.bodies[k]) else {
                continue;
            };
            let f = &scn.floes[i];
            if b.pieces.len() < 2 || f.area < s.min_area {
                continue;
            }
            // The impact as this floe saw it, in its frame (the crack's
            // record): the other body pushing into it along ∓n.
            let into = if k == 0 { -q.normal } else { q.normal };
            let line = BodyLine::of_world(&q.states[k], &q.point, &into);
            let other = floe(q.bodies[1 - k]).map_or(f64::INFINITY, |j| scn.floes[j].mass);
            let split = LatticeSplit {
                pieces: b.pieces.clone(),
                loss: b.fracture,
                broken: b.broken,
                bonds: b.bonds.clone(),
                impacts: vec![Impact {
                    point: line.point,
                    normal: line.dir,
                    mass: other,
                    speed: -out.normal_velocity[0],
                }],
            };
            let lattice = lattice(i)?;
            let area_density = f.density * f.thickness;
            let Some(split) =
                strike::merged(split, lattice, &b.rest_velocities, s.min_area, area_density)
            else {
                continue;
            };
            decisions.push(Decision {
                floe: i,
                line,
                length: 0.0,
                measure: out.impact_energy,
                threshold: b.weakest,
                crack_energy: split.loss,
                lattice: Some(split),
            });
        }
        let answer = ImpactAnswer {
            velocities,
            vibration: out.vibration() + out.contact_energy + out.fracture(),
            dashpot: out.damping,
            restitution: out.restitution,
        };
        Ok((answer, decisions, out.steps, nodes as u64))
    }
}
