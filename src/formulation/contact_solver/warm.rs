//! The warm start of the contact solver (the module doc of [`super`]):
//! each contact's basis and impulses in its last accepted solution, by
//! contact identity ([`ContactKey`]), the guess they give the next LCP of
//! those contacts, and the warm-start check (a warm-solved LCP solved cold
//! too and the two compared).

use super::counters::*;
use super::ContactSolver;
use crate::contact::problem::ContactLcp;
use crate::contact::ContactKey;
use crate::lcp::{solve, BasisGuess, LcpSolution};
use std::collections::HashMap;

/// The relative difference above which the warm-start check counts a warm
/// and a cold solution as two solutions (-): an accepted solution has a
/// residual ≤ 1e-10 of `‖q‖`, so two roundings of one solution differ by
/// orders of magnitude less, and two solutions of a friction LCP by a
/// fraction of the impulses.
pub const WARM_CHECK_DIFFERENT: f64 = 1e-6;

/// The unknowns whose side differs between the guessed basis `basic` (`z_i`
/// basic) and the support of the solution `z` (`z_i > 0`).
pub(super) fn support_changes(basic: &[bool], z: &[f64]) -> u64 {
    basic
        .iter()
        .zip(z)
        .filter(|(b, v)| **b != (**v > 0.0))
        .count() as u64
}

/// `max_i |a_i − b_i| / max(‖a‖∞, ‖b‖∞)`, 0 when both are zero (and 1 for
/// vectors of different lengths).
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return 1.0;
    }
    let scale = a.iter().chain(b).fold(0.0f64, |s, v| s.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
    if diff == 0.0 {
        0.0
    } else {
        diff / scale
    }
}

/// The basis and impulses of one contact in an accepted LCP solution:
/// `(λ, β̃⁺, β̃⁻, α)`, the last three only with friction.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ContactBasis {
    basic: [bool; 4],
    z: [f64; 4],
}

/// The bases of the contacts of the last solves, by contact identity
/// ([`ContactKey`]: bodies and features). Entries of the current time and
/// of the previous one are kept; a contact seen at neither has no guess.
#[derive(Debug, Clone, Default)]
pub(super) struct WarmCache {
    t: f64,
    current: HashMap<ContactKey, ContactBasis>,
    previous: HashMap<ContactKey, ContactBasis>,
}

impl WarmCache {
    /// Starts time `t` (s): the entries of an earlier time become the
    /// previous ones.
    pub(super) fn at(&mut self, t: f64) {
        if t != self.t {
            self.previous = std::mem::take(&mut self.current);
            self.t = t;
        }
    }

    /// The guess for `lcp`: each matched contact's basis and impulses, an
    /// unmatched one separating (`w` basic, `z = 0`); `None` if no contact
    /// is matched.
    pub(super) fn guess(&self, lcp: &ContactLcp) -> Option<BasisGuess> {
        let n = lcp.lcp().n;
        let mut g = BasisGuess {
            basic: vec![false; n],
            z: vec![0.0; n],
        };
        let mut matched = false;
        for (j, key) in lcp.keys.iter().enumerate() {
            let Some(b) = self.current.get(key).or_else(|| self.previous.get(key)) else {
                continue;
            };
            matched = true;
            for (k, i) in lcp.unknowns(j).enumerate() {
                if i < n {
                    g.basic[i] = b.basic[k];
                    g.z[i] = b.z[k];
                }
            }
        }
        matched.then_some(g)
    }

    /// Keeps the basis (support) and impulses of an accepted solution `z`.
    pub(super) fn store(&mut self, lcp: &ContactLcp, z: &[f64]) {
        for (j, key) in lcp.keys.iter().enumerate() {
            let mut b = ContactBasis {
                basic: [false; 4],
                z: [0.0; 4],
            };
            for (k, i) in lcp.unknowns(j).enumerate() {
                let v = z.get(i).copied().unwrap_or(0.0);
                b.basic[k] = v > 0.0;
                b.z[k] = v;
            }
            self.current.insert(*key, b);
        }
    }
}

/// Which warm-start cache a solve uses: the sustained contacts of a step
/// and the compression LCPs of impacts differ in kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Use {
    Sustained,
    Impact,
}

impl ContactSolver {
    /// The warm-start check of one warm-solved LCP: solves it cold (not
    /// recorded, not timed, not dumped) and counts how the two solutions
    /// differ.
    pub(super) fn check_warm(&mut self, lcp: &ContactLcp, warm: &LcpSolution, usage: Use) {
        let cold = solve(lcp.lcp(), &self.opts);
        let (compared, different, rounding) = match usage {
            Use::Sustained => (
                &WARM_CHECK_SUSTAINED,
                &WARM_CHECK_SUSTAINED_DIFFERENT,
                &WARM_CHECK_SUSTAINED_ROUNDING,
            ),
            Use::Impact => (
                &WARM_CHECK_IMPACT,
                &WARM_CHECK_IMPACT_DIFFERENT,
                &WARM_CHECK_IMPACT_ROUNDING,
            ),
        };
        let c = &mut self.counters;
        c.add(compared, 1);
        c.add(&WARM_CHECK_WARM_PIVOTS, warm.pivots as u64);
        c.add(&WARM_CHECK_COLD_PIVOTS, cold.pivots as u64);
        if !cold.status.is_solved() {
            c.add(&WARM_CHECK_COLD_FAILED, 1);
            return;
        }
        let d = relative_difference(&warm.z, &cold.z);
        c.max(&WARM_CHECK_MAX_DIFFERENCE, d);
        if d > WARM_CHECK_DIFFERENT {
            c.add(different, 1);
        } else if d > 0.0 {
            c.add(rounding, 1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::relative_difference;

    #[test]
    fn relative_difference_is_scaled_by_the_largest_entry() {
        assert_eq!(relative_difference(&[0.0, 0.0], &[0.0, 0.0]), 0.0);
        assert_eq!(relative_difference(&[1.0, 2.0], &[1.0, 2.0]), 0.0);
        assert_eq!(relative_difference(&[4.0, 0.0], &[0.0, 4.0]), 1.0);
        let d = relative_difference(&[2.0, 1.0], &[2.0, 1.0 + 2e-12]);
        assert!(d > 0.0 && d < 2e-12, "{d:e}");
        assert_eq!(relative_difference(&[1.0], &[1.0, 0.0]), 1.0);
    }
}
