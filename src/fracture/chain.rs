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

pub use cohesive::Cohesive;

/// The material of every bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Density, kg/m³.
    pub density: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Cross-section, m².
    pub area: f64,
}

impl Default for Material {
    /// Sea ice: the project's density (917 kg/m³), Balasoiu's Young's
    /// modulus (8.95 GPa), a unit cross-section.
    fn default() -> Self {
        Material {
            density: crate::model::DEFAULT_ICE_DENSITY,
            young: 8.95e9,
            area: 1.0,
        }
    }
}

impl Material {
    /// Wave speed `√(E/ρ)`, m/s.
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    /// Impedance of the bar `A √(E ρ)` (= `√(k m)` of its chain), N·s/m.
    pub fn impedance(&self) -> f64 {
        self.area * (self.young * self.density).sqrt()
    }
}

/// One bar: placed after the previous one, touching it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarSpec {
    /// Length, m.
    pub length: f64,
    /// Number of masses (cells).
    pub nodes: usize,
    /// Initial velocity along the line, m/s.
    pub velocity: f64,
}

/// When a bond breaks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BondRule {
    /// Never.
    Unbreakable,
    /// When its tension force `k δ` (elastic part) passes this force, N:
    /// `δ_c = F_c / k`, independent of the resolution.
    Force(f64),
    /// When the energy it holds, `½ k δ²`, passes `G A` (J, `G` the
    /// fracture toughness in J/m², this value): `δ_c = √(2 G A / k)`. This
    /// is the origin report's tenacity rule `δ_c = √(2 T L₀ / k)` with
    /// `T = G A / L₀` (J/m); its critical stress `√(2 G E / Δx)` grows as
    /// the cells shrink, as Griffith's does with a crack of length `Δx`.
    Toughness(f64),
    /// When its elongation passes this strain (-) times its rest length:
    /// `δ_c = ε_c L₀`. With a toughness this is `ε_c = √(2 G A / (k L₀²))`,
    /// which grows as the cells shrink (docs/physics.md §7.4).
    Strain(f64),
    /// The cohesive (crack-band) bond of the 2D lattice ([`Cohesive`],
    /// docs/physics.md §7.3): elastic up to the force `σ_t A`, then
    /// softening linearly to nothing at the opening `δ_f = 2 G / σ_t`,
    /// where it breaks having taken `G A`; a bond too coarse to soften
    /// (`σ_t A / k ≥ δ_f`) breaks by the toughness rule.
    Cohesive {
        /// `G`, J/m².
        toughness: f64,
        /// The tensile strength `σ_t`, Pa.
        strength: f64,
    },
}

impl BondRule {
    /// The critical elongation (m) of a bond of stiffness `k` (N/m), rest
    /// length `rest` (m), opening a section of area `section` (m²) when it
    /// breaks: `∞`, `F_c/k`, `√(2 G A/k)` or `ε_c L₀`; for a cohesive
    /// bond `δ_f = 2 G / σ_t`, or the toughness rule's when it cannot
    /// soften ([`Cohesive::new`]).
    pub fn critical(&self, k: f64, rest: f64, section: f64) -> f64 {
        match *self {
            BondRule::Unbreakable => f64::INFINITY,
            BondRule::Force(f) => f / k,
            BondRule::Toughness(g) => (2.0 * g * section / k).sqrt(),
            BondRule::Strain(e) => e * rest,
            BondRule::Cohesive {
                toughness,
                strength,
            } => Cohesive::new(k, section, toughness, strength).map_or_else(
                || BondRule::Toughness(toughness).critical(k, rest, section),
                |c| c.fail,
            ),
        }
    }

    /// Checks that its parameter is finite and positive.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            BondRule::Unbreakable => Ok(()),
            BondRule::Force(f) => positive("bond strength", f),
            BondRule::Toughness(g) => positive("toughness", g),
            BondRule::Strain(e) => positive("critical strain", e),
            BondRule::Cohesive {
                toughness,
                strength,
            } => positive("toughness", toughness).and(positive("strength", strength)),
        }
    }
}

/// The options of a 1D percussion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainOptions {
    /// Dashpot ratio `β` (-): `c = β √(k m)`. Default 0.5, the value with
    /// which the spall threshold converges with resolution (0 = no dashpots).
    pub damping: f64,
    /// When bonds break. Default: never.
    pub bond: BondRule,
    /// Safety factor on the stable step (-), in (0, 1]. Default 0.9.
    pub safety: f64,
    /// Internal energy, as a fraction of the initial energy, under which the
    /// waves have settled (-). Default 1e-3.
    pub settle: f64,
    /// Transit times of the longest bar after the contact ended after which
    /// the run stops even if the waves ring on (-). Default 4.
    pub settle_transits: f64,
    /// Transit times of the longest bar after which the run stops in any
    /// case (-). Default 200.
    pub limit_transits: f64,
}

impl Default for ChainOptions {
    fn default() -> Self {
        ChainOptions {
            damping: 0.5,
            bond: BondRule::Unbreakable,
            safety: 0.9,
            settle: 1e-3,
            settle_transits: 4.0,
            limit_transits: 200.0,
        }
    }
}

impl ChainOptions {
    /// Checks the options (the 2D percussion shares them).
    pub fn validate(&self) -> Result<(), String> {
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(format!(
                "damping must be finite and >= 0, got {}",
                self.damping
            ));
        }
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return Err(format!("safety must be in (0, 1], got {}", self.safety));
        }
        positive("settle", self.settle)?;
        positive("settle_transits", self.settle_transits)?;
        positive("limit_transits", self.limit_transits)?;
        self.bond.validate()
    }
}

/// A link between two nodes (the chain's neighbours; a 2D lattice's
/// spring; a striker's contact): a spring and a dashpot in parallel that
/// pull and push while `bonded`, and only push once broken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Link {
    /// Stiffness, N/m.
    pub k: f64,
    /// Dashpot, N·s/m.
    pub c: f64,
    /// Rest length, m.
    pub rest: f64,
    /// Whether it still pulls.
    pub bonded: bool,
    /// Critical elongation, m.
    pub critical: f64,
}

impl Link {
    /// The tension (N, positive pulling the two nodes together) for
    /// elongation `d` and elongation rate `dv`.
    pub fn force(&self, d: f64, dv: f64) -> f64 {
        let f = self.k * d + self.c * dv;
        if self.bonded {
            f
        } else if d < 0.0 {
            f.min(0.0)
        } else {
            0.0
        }
    }

    /// The power (W) its dashpot takes out at elongation `d` and rate `dv`:
    /// the tension's power less the rate of the elastic energy it holds,
    /// `(f − k d) ḋ`, while it holds energy (bonded or compressed; a
    /// compressed broken link that lets go also loses the energy it held
    /// at that rate), 0 otherwise.
    pub fn dissipation(&self, d: f64, dv: f64) -> f64 {
        if self.bonded || d < 0.0 {
            (self.force(d, dv) - self.k * d) * dv
        } else {
            0.0
        }
    }

    /// The elastic energy held, J.
    pub fn energy(&self, d: f64) -> f64 {
        if self.bonded || d < 0.0 {
            0.5 * self.k * d * d
        } else {
            0.0
        }
    }
}

/// A bond that broke.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Break {
    /// The node on its left (the bond joins it to the next node).
    pub node: usize,
    /// When, s.
    pub t: f64,
    /// The energy it held, J.
    pub energy: f64,
}

/// A piece: a run of nodes joined by unbroken bonds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fragment {
    /// Its first node.
    pub first: usize,
    /// Its last node.
    pub last: usize,
    /// Mass, kg.
    pub mass: f64,
    /// Rest length (sum of its cells), m.
    pub length: f64,
    /// Centre of mass, m.
    pub centre: f64,
    /// Mean velocity (momentum / mass), m/s.
    pub velocity: f64,
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The contact is over and the internal energy fell under `settle`.
    Settled,
    /// The contact is over and `settle_transits` transit times passed.
    Rang,
    /// `limit_transits` transit times passed.
    TimeLimit,
}

impl Stop {
    /// Its name in outputs.
    pub fn name(&self) -> &'static str {
        match self {
            Stop::Settled => "settled",
            Stop::Rang => "rang",
            Stop::TimeLimit => "time-limit",
        }
    }
}

/// The energies of a chain, J.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Energies {
    /// Kinetic energy.
    pub kinetic: f64,
    /// Elastic energy of the springs (bonds and compressed links).
    pub elastic: f64,
    /// Elastic energy of the torsion springs of the 2D lattice (0 in 1D
    /// and with none).
    pub torsion: f64,
    /// Held by the bonds (and the torsion springs they took with them) when
    /// they broke.
    pub fracture: f64,
}

impl Energies {
    /// Their sum.
    pub fn total(&self) -> f64 {
        self.kinetic + self.elastic + self.torsion + self.fracture
    }
}

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

/// The stable step of velocity Verlet with dashpots (module doc), s:
/// `(2/ω)(√(1+ζ²) − ζ)` for the highest frequency `ω` (rad/s) and the
/// damping ratio `ζ` (-) there.
pub(crate) fn damped_stable_step(omega: f64, zeta: f64) -> f64 {
    (2.0 / omega) * ((1.0 + zeta * zeta).sqrt() - zeta)
}

/// Half a velocity Verlet kick: `v += h f / m` for every node.
pub(crate) fn kick<V>(v: &mut [V], force: &[V], m: &[f64], h: f64)
where
    V: Copy + std::ops::AddAssign + std::ops::Mul<f64, Output = V>,
{
    for ((v, &f), &m) in v.iter_mut().zip(force).zip(m) {
        *v += f * (h / m);
    }
}

/// A velocity Verlet drift: `x += Δt v` for every node.
pub(crate) fn drift<V>(x: &mut [V], v: &[V], dt: f64)
where
    V: Copy + std::ops::AddAssign + std::ops::Mul<f64, Output = V>,
{
    for (x, &v) in x.iter_mut().zip(v) {
        *x += v * dt;
    }
}

/// The stopping rule of a percussion (module doc), shared by the 1D chain
/// and the 2D lattice: fed once per step, it says when to stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Settling {
    /// When the contact was last found over (None while it goes on), s.
    pub over_since: Option<f64>,
    /// When the contact ended, s.
    pub contact_end: f64,
}

impl Settling {
    /// A rule not yet fed.
    pub fn new() -> Settling {
        Settling {
            over_since: None,
            contact_end: 0.0,
        }
    }

    /// Whether to stop at time `t` (s), the contact being over or not, the
    /// internal energy `internal` against the reference `reference` (J),
    /// with `transit` (s) the transit time and `options` the thresholds.
    pub fn stop(
        &mut self,
        t: f64,
        over: bool,
        internal: impl FnOnce() -> f64,
        reference: f64,
        transit: f64,
        options: &ChainOptions,
    ) -> Option<Stop> {
        if over {
            let since = *self.over_since.get_or_insert(t);
            self.contact_end = since;
            if internal() <= options.settle * reference {
                return Some(Stop::Settled);
            }
            if t - since >= options.settle_transits * transit {
                return Some(Stop::Rang);
            }
        } else {
            self.over_since = None;
        }
        (t >= options.limit_transits * transit).then_some(Stop::TimeLimit)
    }
}

/// Checks that `x` (the parameter `name`) is finite and positive.
pub(crate) fn positive(name: &str, x: f64) -> Result<(), String> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} must be finite and positive, got {x}"))
    }
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

/// What a run gives.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Why it stopped.
    pub reason: Stop,
    /// When, s.
    pub t: f64,
    /// When the contact ended, s (0 if it never started).
    pub contact_end: f64,
    /// The step, s.
    pub dt: f64,
    /// Steps taken.
    pub steps: u64,
    /// Initial energy (kinetic + elastic), J.
    pub initial_energy: f64,
    /// Energies at the end.
    pub energies: Energies,
    /// Initial energy less the final kinetic, elastic and fracture energy,
    /// J: what the dashpots took (and the integrator's error).
    pub dissipated: f64,
    /// Without dashpots, the largest `|E(t) − E(0)|` over the run (J) of
    /// `E` = kinetic + elastic + fracture; 0 with dashpots.
    pub energy_drift: f64,
    /// Initial linear momentum, kg·m/s.
    pub initial_momentum: f64,
    /// The pieces, left to right.
    pub fragments: Vec<Fragment>,
    /// Mass (kg) and mean velocity (m/s) of each bar.
    pub bars: Vec<(f64, f64)>,
    /// The broken bonds, in order.
    pub broken: Vec<Break>,
}

impl Outcome {
    /// Effective restitution of bars `a` (striker, on the left) and `b`:
    /// `(V_b − V_a) / (V_a⁰ − V_b⁰)` of their mean velocities, given their
    /// initial velocities.
    pub fn restitution(&self, a: usize, b: usize, va0: f64, vb0: f64) -> f64 {
        (self.bars[b].1 - self.bars[a].1) / (va0 - vb0)
    }
}
