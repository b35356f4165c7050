//! What a 1D percussion gives: the broken bonds ([`Break`]), the pieces
//! ([`Fragment`]), why it stopped ([`Stop`]), the energies ([`Energies`])
//! and the whole run's [`Outcome`].

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
    /// A stop was asked for ([`crate::stop`], polled every
    /// [`crate::stop::POLL_EVERY`] steps): the percussion was left where it
    /// was (a run that asked discards it).
    Interrupted,
}

impl Stop {
    /// Its name in outputs.
    pub fn name(&self) -> &'static str {
        match self {
            Stop::Settled => "settled",
            Stop::Rang => "rang",
            Stop::TimeLimit => "time-limit",
            Stop::Interrupted => "interrupted",
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
