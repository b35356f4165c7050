//! The position projection after a Moreau–Jean step (`[formulation.moreau]
//! projection = true`, docs/physics.md §5.1 step 5; Acary 2012's direct
//! projection of the positions, velocities kept).
//!
//! **Rule.** The contacts are detected at `q_{k+1}` (touching or
//! penetrating). Each connected group with a gap below `−d` (`d` the
//! `projection_depth`) is projected: the frictionless problem
//! `g_j + d/2 + (Jᵀ M_t⁻¹ J μ)_j ≥ 0 ⟂ μ_j ≥ 0` (`J` the contacts' normal
//! rows at `q_{k+1}`, `M_t` the floes' masses with their rotations held;
//! the least mass-weighted translation `M_t⁻¹ J μ` that brings every
//! contact of the group to a depth of at most `d/2`) is solved by
//! Gauss–Seidel at the iterative solver's tolerance, and the floes' centres
//! are moved by it.
//!
//! - **Translations only.** For a fixed pair of features (a vertex against
//!   an edge) the gap is linear in the floes' translations, so one solve
//!   reaches its target up to the solver's tolerance. A projection that also
//!   turned the floes was linear in the angles only to first order, and
//!   worse: the narrow phase gives one point for a vertex against an
//!   oblique edge, and the turn that lifted that vertex out pressed the
//!   floe's next vertex in. On the jammed bay with seeds 1 and 2, 12 passes
//!   then left 0.023 and 0.038 m of penetration, and 83 % of the steps used
//!   every pass; held to translations, no step does
//!   (docs/results/2026-12-07-moreau-projection.md, "Translations only").
//! - **To half the depth.** The target `d/2` leaves room for the solver's
//!   tolerance: projected to `d` exactly, a contact ends a few 1e-8 m below
//!   `−d` and the detection–projection loop runs all its passes for it.
//! - **Neighbours.** A displacement can push a floe into a neighbour that
//!   was not touching (a floe pushed out of the coast pushes the pack
//!   behind it): the problem holds every pair within three times the
//!   deepest penetration, their gaps positive, so the displacement respects
//!   them (within the deepest penetration only, a floe wedged in the jammed
//!   bay was pushed back and forth between two neighbours).
//!
//! Detection and projection are repeated, at most [`PROJECTION_PASSES`]
//! times, until no gap is below `−d`; a step whose passes run out with a
//! deeper contact is counted ([`PROJECTIONS_INCOMPLETE`], and the depth it
//! left, [`PROJECTION_LEFT_MAX`]). The velocities are not touched, so the
//! kinetic energy and the ledger are not either. The depth `d > 0` keeps a
//! projected contact active at the next step (its gap within the
//! activation test), so that it rests instead of rattling. A solve stopped
//! at `max_iterations` above its tolerance is applied and counted
//! ([`PROJECTIONS_UNCONVERGED`]).

use super::*;
use crate::iterative::{nsgs, IterativeOptions, Method, SparseContacts};

/// Most detection–projection passes after one step (module doc): the
/// first removes the step's penetrations, the next ones those its
/// displacements made with neighbours or a change of the touching
/// features left. On the jammed bay (200 floes, 10,000 s, seeds 1, 2, 7)
/// one pass does it at almost every step (about 1 projection per step)
/// and no step uses all 12 (docs/results/2026-12-07-moreau-projection.md,
/// "Translations only").
pub const PROJECTION_PASSES: usize = 12;

/// The depth a projection aims at, as a fraction of `projection_depth`
/// (module doc: room for the solver's tolerance).
pub const PROJECTION_TARGET: f64 = 0.5;

impl Moreau {
    /// Projects the positions of `sys` (at `q_{k+1}`) so that no contact
    /// is deeper than `depth` (m; module doc).
    pub(super) fn project(&mut self, scn: &Scenario, sys: &mut System, depth: f64) {
        let n = scn.floes.len();
        let options = self
            .solver
            .iterative
            .as_ref()
            .map_or(IterativeOptions::new(Method::Nsgs), |it| it.options);
        let zeros = vec![[0.0; 3]; n];
        let mut contacts = Vec::new();
        for _ in 0..PROJECTION_PASSES {
            detect_contacts(scn, &sys.bodies, 0.0, &mut self.bp, &mut contacts);
            let deepest = contacts.iter().map(|c| c.geom.gap).fold(0.0, f64::min);
            if deepest >= -depth {
                return;
            }
            // The pairs the displacements can close (module doc): those
            // within three times the deepest penetration (a rotation out
            // of a contact at a corner swings the far side of the floe).
            detect_contacts(
                scn,
                &sys.bodies,
                -3.0 * deepest,
                &mut self.bp,
                &mut contacts,
            );
            let target = PROJECTION_TARGET * depth;
            let offsets: Vec<f64> = contacts.iter().map(|c| c.geom.gap + target).collect();
            let centres = sys.centres();
            for g in groups(&contacts, n) {
                if g.contacts.iter().all(|&k| offsets[k] >= 0.0) {
                    continue;
                }
                let deepest = g.contacts.iter().map(|&k| offsets[k]).fold(0.0, f64::min);
                self.counters.max(&PROJECTION_DEPTH_MAX, target - deepest);
                let mut prob =
                    SparseContacts::build(scn, &centres, &contacts, &g, &zeros, &offsets)
                        .without_rotation();
                prob.mu = 0.0;
                let mut p = vec![[0.0; 2]; prob.len()];
                let (outcome, dq) = nsgs::solve(
                    &prob,
                    &mut p,
                    options.tolerance,
                    options.max_iterations,
                    options.relaxation,
                );
                self.counters.add(&PROJECTIONS, 1);
                self.counters
                    .max(&PROJECTION_RESIDUAL_MAX, outcome.residual);
                if !(outcome.converged || outcome.interrupted) {
                    self.counters.add(&PROJECTIONS_UNCONVERGED, 1);
                }
                if dq.iter().flatten().any(|d| !d.is_finite()) {
                    continue;
                }
                for (l, &i) in g.floes.iter().enumerate() {
                    let b = &mut sys.bodies[i];
                    b.position += Vec2::new(dq[l][0], dq[l][1]);
                }
            }
        }
        // The passes ran out: what they left is counted, not hidden.
        detect_contacts(scn, &sys.bodies, 0.0, &mut self.bp, &mut contacts);
        let deepest = contacts.iter().map(|c| c.geom.gap).fold(0.0, f64::min);
        if deepest < -depth {
            self.counters.add(&PROJECTIONS_INCOMPLETE, 1);
            self.counters.max(&PROJECTION_LEFT_MAX, -deepest);
        }
    }
}
