//! The bounded log of contact impulses and contact events a formulation
//! hands to the runner at the end of a run, read by `floebench check`
//! (Coulomb, energy at impacts) and kept bounded on long field runs.

use serde::Serialize;

/// One contact impulse as a formulation applied it: the normal impulse `λ`
/// and the tangential (friction) impulse `β` of one contact point, N·s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ImpulseRecord {
    /// Time, s.
    pub t: f64,
    /// Normal impulse `λ`, N·s (≥ 0 when pushing).
    pub normal: f64,
    /// Tangential impulse `β`, N·s (signed).
    pub tangent: f64,
    /// Friction coefficient `μ` of the contact.
    pub mu: f64,
    /// Rounding allowance of this impulse, N·s: a tangential impulse below it
    /// is rounding and is left out of the Coulomb ratio (0 for none).
    pub slack: f64,
}

impl ImpulseRecord {
    /// The Coulomb ratio `|β| / (μ λ)` (1 on the cone's boundary); 0 when
    /// `|β|` is within the rounding allowance; infinite for a tangential
    /// impulse without a normal one. This is the one definition used by the
    /// formulations' counters and by `floebench check`.
    pub fn coulomb_ratio(&self) -> f64 {
        let b = self.tangent.abs();
        if b <= self.slack {
            return 0.0;
        }
        let bound = self.mu * self.normal;
        if bound > 0.0 {
            b / bound
        } else {
            f64::INFINITY
        }
    }

    /// The impulse's excess over the Coulomb cone in units of its accuracy
    /// allowance: `(|β| − μ λ) / (μ λ · COULOMB_SLACK + slack)`, where the
    /// allowance is what the solver's accepted residual guarantees (the
    /// relative rounding [`COULOMB_SLACK`] of the bound, plus the impulse
    /// `slack` that the accepted LCP residual corresponds to). At most 1:
    /// in the cone to the solver's accuracy; negative inside the cone;
    /// infinite for a tangential impulse beyond a zero allowance. This is
    /// the one definition of "outside the cone", used by the formulations'
    /// `coulomb_violations` counter and by `floebench check`.
    pub fn cone_excess(&self) -> f64 {
        let bound = self.mu * self.normal;
        let excess = self.tangent.abs() - bound;
        let allowance = bound.max(0.0) * COULOMB_SLACK + self.slack;
        if allowance > 0.0 {
            excess / allowance
        } else if excess > 0.0 {
            f64::INFINITY
        } else {
            0.0
        }
    }

    /// Whether the impulse is outside the Coulomb cone beyond the solver's
    /// accuracy: [`ImpulseRecord::cone_excess`] `> 1`.
    pub fn outside_cone(&self) -> bool {
        self.cone_excess() > 1.0
    }
}

/// Relative allowance of the Coulomb check, `|β| ≤ μ λ (1 + COULOMB_SLACK)
/// + slack`: the rounding of the bound `μ λ` itself (a few ulps of the
/// impulses, far above `f64::EPSILON` after the LCP's scaling and
/// unscaling), on top of each impulse's own `slack` (the accepted LCP
/// residual's impulse, [`ImpulseRecord::slack`]).
pub const COULOMB_SLACK: f64 = 1e-9;

/// One contact resolution that changed velocities: an impact (event-driven),
/// the contact impulses of one step (time stepping), with the kinetic energy
/// of the floes involved just before and just after the impulses, J.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactEvent {
    /// Time (start of the step for time-stepping schemes), s.
    pub t: f64,
    /// Number of contact points involved.
    pub contacts: usize,
    /// Kinetic energy of the floes involved before the impulses, J.
    pub energy_before: f64,
    /// Kinetic energy of the same floes after the impulses, J.
    pub energy_after: f64,
}

impl ContactEvent {
    /// Kinetic energy gained by the impulses (positive: energy created), J.
    /// The one definition used by `floebench check`.
    pub fn energy_gain(&self) -> f64 {
        self.energy_after - self.energy_before
    }
}

/// Aggregates over the records a bounded log did not keep.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Overflow {
    /// Records not kept.
    pub count: u64,
    /// Largest [`ImpulseRecord::coulomb_ratio`] (impulses) or
    /// [`ContactEvent::energy_gain`] (events, J) among them.
    pub max: Option<f64>,
    /// First time among them, s.
    pub first_t: Option<f64>,
}

impl Overflow {
    fn fold(&mut self, v: f64, t: f64) {
        self.count += 1;
        self.max = Some(self.max.map_or(v, |m| m.max(v)));
        self.first_t = Some(self.first_t.map_or(t, |f| f.min(t)));
    }
}

/// A bounded log of contact impulses and contact events: the first
/// [`ContactLog::CAP`] of each are kept, the rest aggregated, so memory stays
/// bounded on long field runs (hundreds of thousands of solves).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct ContactLog {
    /// Whether the formulation records impulses (false: nothing to check).
    pub records_impulses: bool,
    /// Whether the formulation records contact events.
    pub records_events: bool,
    /// The first impulses.
    pub impulses: Vec<ImpulseRecord>,
    /// The impulses beyond the cap (max Coulomb ratio).
    pub impulses_overflow: Overflow,
    /// Largest [`ImpulseRecord::cone_excess`] over every impulse, kept or
    /// not (`None` without any).
    pub max_cone_excess: Option<f64>,
    /// Impulses outside the cone beyond the solver's accuracy
    /// ([`ImpulseRecord::outside_cone`]), kept or not.
    pub impulses_outside_cone: u64,
    /// The first contact events.
    pub events: Vec<ContactEvent>,
    /// The events beyond the cap (max energy gain).
    pub events_overflow: Overflow,
}

impl ContactLog {
    /// Records kept of each kind.
    pub const CAP: usize = 20_000;

    /// A log that records both impulses and events.
    pub fn recording() -> ContactLog {
        ContactLog {
            records_impulses: true,
            records_events: true,
            ..ContactLog::default()
        }
    }

    /// Adds one impulse.
    pub fn push_impulse(&mut self, r: ImpulseRecord) {
        let excess = r.cone_excess();
        self.max_cone_excess = Some(self.max_cone_excess.map_or(excess, |m| m.max(excess)));
        self.impulses_outside_cone += u64::from(excess > 1.0);
        if self.impulses.len() < Self::CAP {
            self.impulses.push(r);
        } else {
            self.impulses_overflow.fold(r.coulomb_ratio(), r.t);
        }
    }

    /// Adds one contact event.
    pub fn push_event(&mut self, e: ContactEvent) {
        if self.events.len() < Self::CAP {
            self.events.push(e);
        } else {
            self.events_overflow.fold(e.energy_gain(), e.t);
        }
    }

    /// Number of impulses recorded, kept or not.
    pub fn impulse_count(&self) -> u64 {
        self.impulses.len() as u64 + self.impulses_overflow.count
    }

    /// Number of events recorded, kept or not.
    pub fn event_count(&self) -> u64 {
        self.events.len() as u64 + self.events_overflow.count
    }

    /// Largest Coulomb ratio over every impulse (0 without any).
    pub fn max_coulomb_ratio(&self) -> f64 {
        self.impulses
            .iter()
            .map(ImpulseRecord::coulomb_ratio)
            .chain(self.impulses_overflow.max)
            .fold(0.0, f64::max)
    }

    /// Largest energy gain over every event, J (`None` without any).
    pub fn max_energy_gain(&self) -> Option<f64> {
        self.events
            .iter()
            .map(ContactEvent::energy_gain)
            .chain(self.events_overflow.max)
            .reduce(f64::max)
    }
}
