//! Percussion in a 1D granular bar (docs/physics.md §7.1): bars as chains
//! of masses joined by springs and dashpots, bars meeting end-on through a
//! compression-only link, bonds that break at a critical elongation, and a
//! velocity Verlet integrator whose step follows from the chain's highest
//! frequency. The origin report's own 1D model (after Balasoiu 2020),
//! exposed for validation by `floebench percussion-1d`.
//!
//! **Scheme.** A bar of length `L`, cross-section `A`, density `ρ` and
//! Young's modulus `E` is cut into `n` equal cells of length `Δx = L / n`;
//! each cell is a node of mass `m = ρ A Δx` at its centre, and neighbouring
//! nodes are joined by a spring `k = E A / Δx` (rest length `Δx`) in
//! parallel with a dashpot `c = β √(k m)` (`β` the damping ratio). The
//! chain's wave speed is `Δx √(k/m) = √(E/ρ)` and its impedance
//! `Z = √(k m) = A √(E ρ)`, those of the bar.
//!
//! The last node of a bar and the first of the next are joined by a
//! *unilateral* link: the same law, but it only pushes (force
//! `min(0, k δ + c δ̇)` for an elongation `δ < 0`, none for `δ ≥ 0`); its
//! stiffness is that of the two half cells in series, `2 k₁ k₂ / (k₁ + k₂)`
//! (`k` for two bars of the same resolution), and its rest length
//! `(Δx₁ + Δx₂)/2`, so two touching bars of the same resolution in
//! contact are one uniform chain. Both bars are resolved (the striker is
//! not reduced to an effective mass) because Saint-Venant's restitution
//! `L₁/L₂` is a property of the striker's length.
//!
//! A bond breaks, for good, when its elongation passes `δ_c`
//! ([`BondRule`]); a broken bond becomes a unilateral link (the two faces
//! still cannot pass through each other). The energy `½ k δ²` it held is
//! booked as fracture energy.
//!
//! **Integrator.** Velocity Verlet (kick–drift–kick), the dashpots reading
//! the half-step velocity. The step is `Δt = s · (2/ω) (√(1+ζ²) − ζ)`
//! with `ω` the Gershgorin bound of the highest frequency,
//! `ω = max_i √(2 Σ_j k_ij / m_i)` (`2 √(k/m)` for a uniform chain),
//! `ζ = γ / (2ω)` with `γ = max_i 2 Σ_j c_ij / m_i` (`ζ = β` for a uniform
//! chain), and the safety `s` (0.9 by default): the central-difference bound
//! with damping (Belytschko, Liu & Moran 2000, §6.3).
//!
//! **Stopping rule.** The run stops at the first step where (1) every
//! unilateral link is open and each pair of pieces it joins separates (the
//! right piece's mean velocity is at least the left one's): the contact is
//! over; and (2) the waves have settled: the internal energy (kinetic and
//! elastic energy less the pieces' rigid kinetic energy) is at most
//! `settle` times the initial energy, or `settle_transits` transit times of
//! the longest bar have passed since the contact ended (an undamped chain
//! rings for ever). A run that is still going after `limit_transits`
//! transit times stops with [`Stop::TimeLimit`].
//!
//! The 2D lattice's cohesive bond ([`Cohesive`]): `chain/cohesive.rs`.

mod cohesive;
mod outcome;
mod scheme;
mod spec;

pub use cohesive::Cohesive;
pub use outcome::{Break, Energies, Fragment, Outcome, Stop};
pub(crate) use scheme::{damped_stable_step, drift, kick, positive, Link, Settling};
pub use spec::{BarSpec, BondRule, ChainOptions, Material};

/// The chain of every bar, its state and its history.
#[derive(Debug, Clone)]
pub struct Chain {
    /// Node positions, m.
    pub x: Vec<f64>,
    /// Node velocities, m/s.
    pub v: Vec<f64>,
    /// Node masses, kg.
    pub m: Vec<f64>,
    /// The bar of each node.
    pub bar: Vec<usize>,
    /// Rest length of each node's cell, m.
    pub cell: Vec<f64>,
    links: Vec<Link>,
    force: Vec<f64>,
    /// Time, s.
    pub t: f64,
    /// The step, s.
    pub dt: f64,
    /// Steps taken.
    pub steps: u64,
    /// The bonds broken so far.
    pub broken: Vec<Break>,
    /// Transit time of the longest bar, s.
    pub transit: f64,
    options: ChainOptions,
}

impl Chain {
    /// The chain of `bars` (at least one, each with at least two nodes)
    /// of `material`, at time 0, touching end to end from x = 0.
    pub fn new(
        material: &Material,
        bars: &[BarSpec],
        options: ChainOptions,
    ) -> Result<Chain, String> {
        positive("density", material.density)?;
        positive("Young's modulus", material.young)?;
        positive("cross-section", material.area)?;
        if bars.is_empty() {
            return Err("at least one bar is needed".into());
        }
        options.validate()?;
        if let BondRule::Cohesive { .. } = options.bond {
            return Err(
                "the cohesive bond rule is the 2D lattice's: the 1D chain has no softening bond"
                    .into(),
            );
        }
        let mut chain = Chain {
            x: Vec::new(),
            v: Vec::new(),
            m: Vec::new(),
            bar: Vec::new(),
            cell: Vec::new(),
            links: Vec::new(),
            force: Vec::new(),
            t: 0.0,
            dt: 0.0,
            steps: 0,
            broken: Vec::new(),
            transit: 0.0,
            options,
        };
        let mut start = 0.0;
        for (b, s) in bars.iter().enumerate() {
            positive("bar length", s.length)?;
            if s.nodes < 2 {
                return Err(format!("bar {b}: at least 2 nodes, got {}", s.nodes));
            }
            if !s.velocity.is_finite() {
                return Err(format!("bar {b}: velocity must be finite"));
            }
            let dx = s.length / s.nodes as f64;
            let m = material.density * material.area * dx;
            let k = material.young * material.area / dx;
            let c = options.damping * (k * m).sqrt();
            let critical = options.bond.critical(k, dx, material.area);
            if b > 0 {
                // The contact link with the previous bar's last node: the two
                // half cells in series.
                let (kp, mp, dxp) = (
                    *chain.links.last().map(|l| &l.k).unwrap_or(&k),
                    chain.m[chain.m.len() - 1],
                    chain.cell[chain.cell.len() - 1],
                );
                let kc = 2.0 * k * kp / (k + kp);
                let mc = 2.0 * m * mp / (m + mp);
                chain.links.push(Link {
                    k: kc,
                    c: options.damping * (kc * mc).sqrt(),
                    rest: 0.5 * (dx + dxp),
                    bonded: false,
                    critical: f64::INFINITY,
                });
            }
            for j in 0..s.nodes {
                chain.x.push(start + (j as f64 + 0.5) * dx);
                chain.v.push(s.velocity);
                chain.m.push(m);
                chain.bar.push(b);
                chain.cell.push(dx);
                if j + 1 < s.nodes {
                    chain.links.push(Link {
                        k,
                        c,
                        rest: dx,
                        bonded: true,
                        critical,
                    });
                }
            }
            start += s.length;
            chain.transit = chain.transit.max(s.length / material.wave_speed());
        }
        chain.force = vec![0.0; chain.x.len()];
        chain.dt = options.safety * chain.stable_step();
        chain.forces();
        Ok(chain)
    }

    /// The stable step of the scheme, s (module doc): `(2/ω)(√(1+ζ²) − ζ)`.
    pub fn stable_step(&self) -> f64 {
        let n = self.x.len();
        let (mut ks, mut cs) = (vec![0.0; n], vec![0.0; n]);
        for (i, l) in self.links.iter().enumerate() {
            ks[i] += l.k;
            ks[i + 1] += l.k;
            cs[i] += l.c;
            cs[i + 1] += l.c;
        }
        let omega = (0..n)
            .map(|i| (2.0 * ks[i] / self.m[i]).sqrt())
            .fold(0.0, f64::max);
        let gamma = (0..n).map(|i| 2.0 * cs[i] / self.m[i]).fold(0.0, f64::max);
        damped_stable_step(omega, gamma / (2.0 * omega))
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether the chain has no node (never, once built).
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Elongation of link `i`, m.
    fn elongation(&self, i: usize) -> f64 {
        self.x[i + 1] - self.x[i] - self.links[i].rest
    }

    /// The node forces at the current positions and velocities, N.
    fn forces(&mut self) {
        self.force.iter_mut().for_each(|f| *f = 0.0);
        for i in 0..self.links.len() {
            let d = self.elongation(i);
            let f = self.links[i].force(d, self.v[i + 1] - self.v[i]);
            self.force[i] += f;
            self.force[i + 1] -= f;
        }
    }

    /// Breaks every bond stretched past its critical elongation.
    fn break_bonds(&mut self) {
        for i in 0..self.links.len() {
            let d = self.elongation(i);
            let l = &mut self.links[i];
            if l.bonded && d > l.critical {
                l.bonded = false;
                self.broken.push(Break {
                    node: i,
                    t: self.t,
                    energy: 0.5 * l.k * d * d,
                });
            }
        }
    }

    /// One velocity Verlet step.
    pub fn step(&mut self) {
        let h = 0.5 * self.dt;
        kick(&mut self.v, &self.force, &self.m, h);
        drift(&mut self.x, &self.v, self.dt);
        self.t += self.dt;
        self.steps += 1;
        self.break_bonds();
        self.forces();
        kick(&mut self.v, &self.force, &self.m, h);
    }

    /// The energies now.
    pub fn energies(&self) -> Energies {
        Energies {
            kinetic: (0..self.len())
                .map(|i| 0.5 * self.m[i] * self.v[i] * self.v[i])
                .sum(),
            elastic: (0..self.links.len())
                .map(|i| self.links[i].energy(self.elongation(i)))
                .sum(),
            torsion: 0.0,
            fracture: self.broken.iter().map(|b| b.energy).sum(),
        }
    }

    /// Total linear momentum, kg·m/s.
    pub fn momentum(&self) -> f64 {
        (0..self.len()).map(|i| self.m[i] * self.v[i]).sum()
    }

    /// Mass and mean velocity of each bar (as built, broken or not).
    pub fn bars(&self) -> Vec<(f64, f64)> {
        let nb = self.bar.last().map_or(0, |b| b + 1);
        let mut out = vec![(0.0, 0.0); nb];
        for i in 0..self.len() {
            out[self.bar[i]].0 += self.m[i];
            out[self.bar[i]].1 += self.m[i] * self.v[i];
        }
        out.into_iter().map(|(m, p)| (m, p / m)).collect()
    }

    /// The pieces, left to right.
    pub fn fragments(&self) -> Vec<Fragment> {
        let mut out = Vec::new();
        let mut first = 0;
        for i in 0..self.len() {
            if i + 1 == self.len() || !self.links[i].bonded {
                let (mut mass, mut mx, mut mv, mut length) = (0.0, 0.0, 0.0, 0.0);
                for j in first..=i {
                    mass += self.m[j];
                    mx += self.m[j] * self.x[j];
                    mv += self.m[j] * self.v[j];
                    length += self.cell[j];
                }
                out.push(Fragment {
                    first,
                    last: i,
                    mass,
                    length,
                    centre: mx / mass,
                    velocity: mv / mass,
                });
                first = i + 1;
            }
        }
        out
    }

    /// Whether the contact is over (module doc, rule 1).
    fn contact_over(&self, pieces: &[Fragment]) -> bool {
        pieces
            .windows(2)
            .all(|w| self.elongation(w[0].last) >= 0.0 && w[1].velocity >= w[0].velocity)
    }

    /// Whether any unilateral link is closed.
    fn any_closed(&self) -> bool {
        (0..self.links.len()).any(|i| !self.links[i].bonded && self.elongation(i) < 0.0)
    }

    /// Runs to the stopping rule (module doc).
    pub fn run(&mut self) -> Outcome {
        let initial = self.energies().total();
        let momentum = self.momentum();
        let mut settling = Settling::new();
        let mut max_drift: f64 = 0.0;
        let options = self.options;
        let reason = loop {
            if crate::stop::poll(self.steps) {
                break Stop::Interrupted;
            }
            self.step();
            let e = self.energies();
            if self.links.iter().all(|l| l.c == 0.0) {
                max_drift = max_drift.max((e.total() - initial).abs());
            }
            let pieces = self.fragments();
            let over = !self.any_closed() && self.contact_over(&pieces);
            let internal = || {
                let rigid: f64 = pieces
                    .iter()
                    .map(|p| 0.5 * p.mass * p.velocity * p.velocity)
                    .sum();
                e.kinetic + e.elastic - rigid
            };
            if let Some(stop) =
                settling.stop(self.t, over, internal, initial, self.transit, &options)
            {
                break stop;
            }
        };
        let energies = self.energies();
        Outcome {
            reason,
            t: self.t,
            contact_end: settling.contact_end,
            dt: self.dt,
            steps: self.steps,
            initial_energy: initial,
            energies,
            dissipated: initial - energies.total(),
            energy_drift: max_drift,
            initial_momentum: momentum,
            fragments: self.fragments(),
            bars: self.bars(),
            broken: self.broken.clone(),
        }
    }
}
