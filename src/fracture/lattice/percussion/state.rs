//! The lattice state of a percussion and its integrator (docs/physics.md
//! §7.3): the [`Percussion`] (node positions and velocities, the springs'
//! links, the torsion springs still intact, the strikers), built from a
//! lattice and its impacts; its stable step, its forces (springs, dashpots,
//! torsion springs and the strikers' contacts), bond breaking and the
//! velocity Verlet step; its energies and momenta (the scheme: the module
//! doc of [`super`]).

#[cfg(doc)]
use super::striker::impact_energy_bound;
use super::striker::Striker;
use super::BrokenSpring;
use crate::fracture::chain::{
    damped_stable_step, drift, kick, ChainOptions, Cohesive, Energies, Link,
};
use crate::fracture::lattice::{corner_angle, Lattice};
use crate::geometry::{cross, Vec2};

/// A percussion under way: the lattice's state and the striker's.
#[derive(Debug, Clone)]
pub struct Percussion<'a> {
    pub(in crate::fracture::lattice) lattice: &'a Lattice,
    /// Node positions, m.
    pub x: Vec<Vec2>,
    /// Node velocities, m/s.
    pub v: Vec<Vec2>,
    pub(super) links: Vec<Link>,
    /// The softening state of each spring under the cohesive rule (`None`
    /// for a spring that cannot soften, and under the other rules).
    pub(super) cohesive: Vec<Option<Cohesive>>,
    /// Whether each triangle keeps its torsion springs (until one of its
    /// edges breaks).
    pub(super) intact: Vec<bool>,
    /// The triangles on each side of each spring (`usize::MAX` for none).
    pub(super) sides: Vec<[usize; 2]>,
    /// The strikers (one per impact), each with its contact links.
    pub(super) strikers: Vec<Striker>,
    pub(in crate::fracture::lattice) force: Vec<Vec2>,
    pub(super) contact_moment: f64,
    /// Impulse (N·s) the strikers gave the floe so far.
    pub impulse: Vec2,
    /// Moment of that impulse about the frame's origin, N·m·s.
    pub impulse_moment: f64,
    /// Work (J) done on the floe by the strikers of infinite mass (which
    /// keep their velocity; 0 for a striker at rest and for a finite mass,
    /// whose kinetic energy is counted instead).
    pub work: f64,
    /// Time since the impact, s.
    pub t: f64,
    /// The step, s.
    pub dt: f64,
    /// Steps taken.
    pub steps: u64,
    /// The springs broken so far.
    pub broken: Vec<BrokenSpring>,
    /// Transit time of a P wave across the floe, s.
    pub transit: f64,
    /// The impact energy bound `B` (`½ μ u_N²` for one striker,
    /// [`impact_energy_bound`] for several), J.
    pub impact_energy: f64,
    pub(super) options: ChainOptions,
}

impl<'a> Percussion<'a> {
    /// The stable step of the scheme, s (module doc).
    pub fn stable_step(&self) -> f64 {
        let (ks, cs) = self.gershgorin_rows();
        step_of_rows(&ks, &cs)
    }

    /// The rows of the block-Gershgorin bound (module doc): for each node,
    /// then each striker, `Σ_j κ_ij w_ij` (1/s²) and `Σ_j c_ij w_ij` (1/s)
    /// over its links, `w_ij` the [`gershgorin_weight`].
    pub(in crate::fracture::lattice) fn gershgorin_rows(&self) -> (Vec<f64>, Vec<f64>) {
        let m = &self.lattice.mass;
        let n = m.len();
        let rows = n + self.strikers.len();
        let (mut ks, mut cs) = (vec![0.0; rows], vec![0.0; rows]);
        let mut add = |i: usize, j: usize, mi: f64, mj: f64, l: &Link| {
            let w = gershgorin_weight(mi, mj);
            ks[i] += l.k * w;
            cs[i] += l.c * w;
            let w = gershgorin_weight(mj, mi);
            ks[j] += l.k * w;
            cs[j] += l.c * w;
        };
        for (s, l) in self.lattice.springs.iter().zip(&self.links) {
            let [i, j] = s.nodes;
            add(i, j, m[i], m[j], l);
        }
        // Striker k is unknown n + k (infinite mass: its row is empty).
        for (k, st) in self.strikers.iter().enumerate() {
            for (i, l) in &st.contacts {
                add(*i, n + k, m[*i], st.impact.mass, l);
            }
        }
        // A torsion spring's linearised stiffness is c ∇θ ∇θᵀ: its (i, j)
        // block has norm c |∇_i θ| |∇_j θ|.
        for c in &self.lattice.corners {
            for (&i, gi) in c.nodes.iter().zip(&c.grad) {
                let row: f64 = c
                    .nodes
                    .iter()
                    .zip(&c.grad)
                    .map(|(&j, gj)| gj.norm() / (m[i] * m[j]).sqrt())
                    .sum();
                ks[i] += c.stiffness * gi.norm() * row;
            }
        }
        (ks, cs)
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether the lattice has no node (never, once built).
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Elongation (m), its rate (m/s) and direction of spring `k`.
    fn spring_state(&self, k: usize) -> (f64, f64, Vec2) {
        let [i, j] = self.lattice.springs[k].nodes;
        let d = self.x[j] - self.x[i];
        let l = d.norm();
        let dir = d / l;
        (
            l - self.links[k].rest,
            dir.dot(&(self.v[j] - self.v[i])),
            dir,
        )
    }

    /// The node forces and the striker's at the current state, N.
    pub(super) fn forces(&mut self) {
        self.force.iter_mut().for_each(|f| *f = Vec2::zeros());
        for k in 0..self.links.len() {
            let (d, dv, dir) = self.spring_state(k);
            let f = self.link_force(k, d, dv);
            let [i, j] = self.lattice.springs[k].nodes;
            self.force[i] += dir * f;
            self.force[j] -= dir * f;
        }
        let intact = &self.intact;
        self.lattice
            .torsion_forces(&self.x, |t| intact[t], &mut self.force);
        self.contact_moment = 0.0;
        for k in 0..self.strikers.len() {
            let mut total = 0.0;
            let normal = self.strikers[k].impact.normal;
            for c in 0..self.strikers[k].contacts.len() {
                let (i, link) = self.strikers[k].contacts[c];
                let (g, dg) = self.gap(k, i);
                let f = link.force(g, dg);
                if f != 0.0 {
                    let push = -normal * f;
                    self.force[i] += push;
                    total += f;
                    self.contact_moment += cross(&self.x[i], &push);
                }
            }
            self.strikers[k].force = total;
        }
    }

    /// Breaks every bond stretched past its critical elongation (a cohesive
    /// bond first records its opening, and breaks once softened to nothing,
    /// its energy `G h w`); the triangles on its sides lose their torsion
    /// springs, whose energy goes with the bond's.
    fn break_bonds(&mut self) {
        for k in 0..self.links.len() {
            let (d, _, _) = self.spring_state(k);
            let l = &mut self.links[k];
            let soft = match self.cohesive.get_mut(k) {
                Some(Some(c)) if l.bonded => {
                    c.open(d);
                    Some(c.breaking_energy())
                }
                _ => None,
            };
            if l.bonded && d > l.critical {
                l.bonded = false;
                let mut energy = soft.unwrap_or(0.5 * l.k * d * d);
                for t in self.sides[k] {
                    if t != usize::MAX && self.intact[t] {
                        energy += self.triangle_torsion_energy(t);
                        self.intact[t] = false;
                    }
                }
                self.broken.push(BrokenSpring {
                    spring: k,
                    t: self.t,
                    energy,
                });
            }
        }
    }

    /// The energy of triangle `t`'s torsion springs now, J.
    fn triangle_torsion_energy(&self, t: usize) -> f64 {
        self.lattice
            .corners
            .iter()
            .skip(3 * t)
            .take(3)
            .map(|c| {
                let [o, a, b] = c.nodes;
                let d = corner_angle(&self.x[o], &self.x[a], &self.x[b]).0 - c.angle;
                0.5 * c.stiffness * d * d
            })
            .sum()
    }

    /// One velocity Verlet step.
    pub fn step(&mut self) {
        self.advance();
        self.finish();
    }

    /// The first part of a velocity Verlet step: half a kick, the drift,
    /// bond breaking and the forces at the new positions (the two-body
    /// impact adds its contact forces before [`Self::finish`]).
    pub(in crate::fracture::lattice) fn advance(&mut self) {
        let h = 0.5 * self.dt;
        self.book_contact(h);
        kick(&mut self.v, &self.force, &self.lattice.mass, h);
        self.kick_striker(h);
        drift(&mut self.x, &self.v, self.dt);
        for s in &mut self.strikers {
            s.position += self.dt * s.velocity;
        }
        self.t += self.dt;
        self.steps += 1;
        self.break_bonds();
        self.forces();
    }

    /// The last half kick of a velocity Verlet step.
    pub(in crate::fracture::lattice) fn finish(&mut self) {
        let h = 0.5 * self.dt;
        self.book_contact(h);
        kick(&mut self.v, &self.force, &self.lattice.mass, h);
        self.kick_striker(h);
    }

    /// The energies now (the strikers' kinetic energy when their mass is
    /// finite).
    pub fn energies(&self) -> Energies {
        let striker = self.striker_energy();
        let springs = self.spring_energy();
        let contacts = self.striker_sum(|l, g, _| l.energy(g));
        let torsion: f64 = (0..self.intact.len())
            .filter(|&t| self.intact[t])
            .map(|t| self.triangle_torsion_energy(t))
            .sum();
        Energies {
            torsion,
            kinetic: striker
                + self
                    .lattice
                    .mass
                    .iter()
                    .zip(&self.v)
                    .map(|(m, v)| 0.5 * m * v.norm_squared())
                    .sum::<f64>(),
            elastic: springs + contacts,
            fracture: self.broken.iter().map(|b| b.energy).sum::<f64>()
                + (0..self.links.len())
                    .filter_map(|k| self.softening(k))
                    .map(Cohesive::dissipated)
                    .sum::<f64>(),
        }
    }

    /// The elastic energy of the springs (bonds and compressed broken
    /// ones, not the strikers' contacts), J.
    pub(in crate::fracture::lattice) fn spring_energy(&self) -> f64 {
        (0..self.links.len())
            .map(|k| self.link_energy(k, self.spring_state(k).0))
            .sum()
    }

    /// The power the dashpots take out now (springs and the strikers'
    /// contacts, [`Link::dissipation`]), W.
    pub(in crate::fracture::lattice) fn dashpot_power(&self) -> f64 {
        let springs: f64 = (0..self.links.len())
            .map(|k| {
                let (d, dv, _) = self.spring_state(k);
                self.link_dissipation(k, d, dv)
            })
            .sum();
        springs + self.striker_sum(|l, g, dg| l.dissipation(g, dg))
    }

    /// `Σ f(link, gap, gap rate)` over every striker's contact links.
    fn striker_sum(&self, f: impl Fn(&Link, f64, f64) -> f64) -> f64 {
        self.strikers
            .iter()
            .enumerate()
            .map(|(k, s)| {
                s.contacts
                    .iter()
                    .map(|(i, l)| {
                        let (g, dg) = self.gap(k, *i);
                        f(l, g, dg)
                    })
                    .sum::<f64>()
            })
            .sum()
    }

    /// Linear momentum (kg·m/s) and angular momentum about the frame's
    /// origin (kg·m²/s) of the nodes.
    pub fn momentum(&self) -> (Vec2, f64) {
        let m = &self.lattice.mass;
        (
            (0..self.len()).map(|i| self.v[i] * m[i]).sum(),
            (0..self.len())
                .map(|i| m[i] * cross(&self.x[i], &self.v[i]))
                .sum(),
        )
    }

    /// The smallest energy that breaks a bond, `½ κ δ_c²` over the springs,
    /// J (`∞` for unbreakable bonds): the trigger bound's threshold
    /// (docs/physics.md §9.8).
    pub fn weakest_bond_energy(&self) -> f64 {
        (0..self.links.len())
            .map(|k| self.breaking_energy(k))
            .fold(f64::INFINITY, f64::min)
    }

    /// The energy `½ κ δ_c²` that spring `k` holds when it breaks, J (`∞`
    /// for an unbreakable bond): with a toughness `G`, `G h w`, `w` its
    /// facet (module doc; the crack energy this gives per unit length of a
    /// straight cut: docs/physics.md §7.3); for a cohesive bond that
    /// softens, the area under its envelope, `G h w` too.
    pub fn breaking_energy(&self, k: usize) -> f64 {
        if let Some(c) = self.cohesive_bond(k) {
            return c.breaking_energy();
        }
        let l = &self.links[k];
        0.5 * l.k * l.critical * l.critical
    }

    /// Whether spring `k` still holds.
    pub fn bonded(&self, k: usize) -> bool {
        self.links[k].bonded
    }

    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        self.lattice
    }
}

/// The mean stiffness `κ̄` of the lattice's springs, N/m: the strikers'
/// contact links' (module doc).
pub(in crate::fracture::lattice) fn mean_stiffness(lattice: &Lattice) -> f64 {
    lattice.springs.iter().map(|s| s.stiffness).sum::<f64>() / lattice.springs.len() as f64
}

/// The weight `1/m_i + 1/√(m_i m_j)` of a link between nodes of masses
/// `mi` and `mj` (kg) in row `i` of the block-Gershgorin bound (module
/// doc), 1/kg.
pub(in crate::fracture::lattice) fn gershgorin_weight(mi: f64, mj: f64) -> f64 {
    1.0 / mi + 1.0 / (mi * mj).sqrt()
}

/// The stable step (s) of the block-Gershgorin rows `ks` (1/s²) and `cs`
/// (1/s) ([`Percussion::gershgorin_rows`]): `ω² = max ks`, `ζ = max cs /
/// (2ω)`, [`damped_stable_step`].
pub(in crate::fracture::lattice) fn step_of_rows(ks: &[f64], cs: &[f64]) -> f64 {
    let omega = ks.iter().fold(0.0, |a: f64, &b| a.max(b)).sqrt();
    let gamma = cs.iter().fold(0.0, |a: f64, &b| a.max(b));
    damped_stable_step(omega, gamma / (2.0 * omega))
}

/// The rule a bond breaks by, for a lattice of `spacing` (m) and Young's
/// modulus `young` (Pa): the critical strain `√(4 G / (3 E s))` a toughness
/// `G` amounts to in an equilateral lattice (docs/physics.md §7.3).
pub fn strain_of_toughness(toughness: f64, young: f64, spacing: f64) -> f64 {
    (4.0 * toughness / (3.0 * young * spacing)).sqrt()
}
