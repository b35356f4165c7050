//! The law of each spring of a percussion (docs/physics.md §7.3): the
//! chain's [`Link`](crate::fracture::chain) (a spring and a dashpot, elastic
//! until it breaks), or, under the cohesive rule, its softening state
//! ([`Cohesive`]) while it holds: tension, elastic energy and dashpot power
//! through the one or the other.

use super::Percussion;
use crate::fracture::chain::Cohesive;

impl Percussion<'_> {
    /// The softening state of spring `k` under the cohesive rule (`None`
    /// under the other rules and for a bond too coarse to soften, which
    /// breaks by the toughness rule).
    pub fn cohesive_bond(&self, k: usize) -> Option<&Cohesive> {
        self.cohesive.get(k).and_then(Option::as_ref)
    }

    /// The softening state of spring `k` while it holds under the cohesive
    /// rule (`None` for the other rules, a spring that cannot soften, and a
    /// broken one).
    pub(super) fn softening(&self, k: usize) -> Option<&Cohesive> {
        self.cohesive_bond(k).filter(|_| self.links[k].bonded)
    }

    /// The tension (N) of spring `k` at elongation `d` (m) and rate `dv`
    /// (m/s).
    pub(super) fn link_force(&self, k: usize, d: f64, dv: f64) -> f64 {
        match self.softening(k) {
            Some(c) => c.force(self.links[k].c, d, dv),
            None => self.links[k].force(d, dv),
        }
    }

    /// The elastic energy (J) spring `k` holds at elongation `d` (m).
    pub(super) fn link_energy(&self, k: usize, d: f64) -> f64 {
        match self.softening(k) {
            Some(c) => c.energy(d),
            None => self.links[k].energy(d),
        }
    }

    /// The power (W) the dashpot of spring `k` takes out at elongation `d`
    /// (m) and rate `dv` (m/s).
    pub(super) fn link_dissipation(&self, k: usize, d: f64, dv: f64) -> f64 {
        match self.softening(k) {
            Some(c) => c.dissipation(self.links[k].c, d, dv),
            None => self.links[k].dissipation(d, dv),
        }
    }
}
