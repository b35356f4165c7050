//! The step's impacts resolved in the floes' lattices (`[fracture]
//! impact = "lattice"`, docs/physics.md §9.10).
//!
//! **Rule.** A group of the step's active contacts is an impact for the
//! lattices when its approaching contacts (`u_N⁻ < 0` at the start of the
//! step) join one pair of bodies and that pair was not active at the
//! previous step (a pair in sustained contact keeps Newton's law: its
//! contact is resting, not striking). It is handed to the topology stage
//! with the floes' poses `q_k` and free velocities `W_free`, and the pair's
//! velocities after the lattices' impact replace the step's contact
//! problem for that group: `W_{k+1}` of its floes is the lattices' answer,
//! and the step goes on (positions by the θ-method). A group of several
//! pairs keeps Newton's law (the stage counts it). After a fracture the
//! previous step's pairs are forgotten (the floe indices changed).

use super::Moreau;
use crate::contact::problem::{ContactGroup as Group, Gen};
use crate::contact::Contact;
use crate::formulation::{Context, ImpactAnswer, ImpactQuery};
use crate::geometry::Vec2;
use crate::model::Scenario;
use crate::state::{BodyState, System};

/// The pair of bodies of a contact, in order.
fn pair(c: &Contact) -> (usize, usize) {
    (c.a.min(c.b), c.a.max(c.b))
}

impl Moreau {
    /// The lattices' answer for group `g` of `active` (module doc), or
    /// `None` for Newton's law; `u_minus` the contacts' normal velocities at
    /// the start of the step, `closed` whether each contact's predicted gap
    /// is closed (an open contact, kept by `open_contacts = "gap"`, strikes
    /// nothing yet), `w_free` the free velocities.
    pub(super) fn lattice_impact(
        &self,
        scn: &Scenario,
        sys: &System,
        (g, active, u_minus, closed): (&Group, &[Contact], &[f64], &[bool]),
        w_free: &[Gen],
        cx: &mut Context<'_>,
    ) -> Option<(ImpactQuery, ImpactAnswer)> {
        let impacting: Vec<&Contact> = g
            .contacts
            .iter()
            .filter(|&&k| closed[k] && u_minus[k] < 0.0)
            .map(|&k| &active[k])
            .collect();
        if impacting
            .iter()
            .any(|c| self.active_pairs.binary_search(&pair(c)).is_ok())
        {
            return None;
        }
        let state = |i: usize| BodyState {
            velocity: Vec2::new(w_free[i][0], w_free[i][1]),
            angular_velocity: w_free[i][2],
            ..sys.bodies[i]
        };
        let query = ImpactQuery::of(scn, &impacting, state)?;
        let answer = cx.impact(scn, sys, &query)?;
        Some((query, answer))
    }

    /// Keeps the pairs of the step's closed contacts (`closed[k]` for
    /// `active[k]`; an open contact kept by `open_contacts = "gap"` touches
    /// nothing yet) for the next step's rule (module doc).
    pub(super) fn keep_active_pairs(&mut self, active: &[Contact], closed: &[bool]) {
        self.active_pairs = active
            .iter()
            .zip(closed)
            .filter(|&(_, &shut)| shut)
            .map(|(c, _)| pair(c))
            .collect();
        self.active_pairs.sort_unstable();
        self.active_pairs.dedup();
    }

    /// The velocity changes of group `g`'s floes that give the lattices'
    /// `answer` from `w_free` (zero for a floe it does not set).
    pub(super) fn lattice_dv(
        scn: &Scenario,
        g: &Group,
        (query, answer): &(ImpactQuery, ImpactAnswer),
        w_free: &[Gen],
    ) -> Vec<Gen> {
        let mut dv = vec![[0.0; 3]; g.floes.len()];
        for (i, v, w) in answer.floes(scn, query) {
            if let Some(l) = g.floes.iter().position(|&f| f == i) {
                dv[l] = [v.x - w_free[i][0], v.y - w_free[i][1], w - w_free[i][2]];
            }
        }
        dv
    }
}
