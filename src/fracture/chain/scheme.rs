//! The parts of the percussion scheme that the 1D chain and the 2D
//! lattice share (the scheme and the stopping rule are described in the
//! module doc of [`super`], the "module doc" cited below): the link law
//! ([`Link`]), the stable step and the kick and drift of velocity
//! Verlet, the stopping rule ([`Settling`]), and the check of a positive
//! parameter ([`positive`]).

use super::{ChainOptions, Stop};

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
