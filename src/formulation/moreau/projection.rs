//! The position projection after a Moreau–Jean step (`[formulation.moreau]
//! projection = true`, docs/physics.md §5.1 step 5; Acary 2012's direct
//! projection of the positions, velocities kept).
//!
//! **Rule.** The contacts are detected at `q_{k+1}` (touching or
//! penetrating). Each connected group with a gap below `−d` (`d` the
//! `projection_depth`) is projected: the frictionless problem
//! `g_j + d + (Jᵀ M⁻¹ J μ)_j ≥ 0 ⟂ μ_j ≥ 0` (`J` the contacts' normal rows
//! at `q_{k+1}`; the least `M`-norm displacement `M⁻¹ J μ` that brings
//! every contact of the group to a depth of at most `d`, to first order)
//! is solved by Gauss–Seidel at the iterative solver's tolerance, and
//! `q_{k+1} += M⁻¹ J μ`. A displacement can push a floe into a neighbour
//! that was not touching (a floe pushed out of the coast pushes the pack
//! behind it, a rotation out of a contact at a corner swings its far
//! side): the problem holds every pair within three times the deepest
//! penetration, their gaps positive, so the displacement respects them to
//! first order (within the deepest penetration only, a floe wedged in the
//! jammed bay was pushed back and forth between two neighbours, and 0.46 m
//! of penetration accumulated in 4,000 s, against 0.18 m with three
//! times). Rotations are linearised: detection and projection are
//! repeated, at most [`PROJECTION_PASSES`] times, until no gap is below
//! `−d`. The velocities are not touched, so the kinetic energy and the
//! ledger are not either. The depth `d > 0` keeps a
//! projected contact active at the next step (its gap within the
//! activation test), so that it rests instead of rattling. A solve stopped
//! at `max_iterations` above its tolerance is applied and counted
//! ([`PROJECTIONS_UNCONVERGED`]).

use super::*;
use crate::iterative::{nsgs, IterativeOptions, Method, SparseContacts};

/// Most detection–projection passes after one step (module doc): the
/// first removes the step's penetrations, the next ones those its
/// displacements made with neighbours and its linearised rotations left.
/// On the jammed bay (200 floes, 4,000 s) 4 passes left 0.18 m of
/// penetration and 12 leave 0.0084 m, for 35 % more CPU
/// (docs/results/2026-12-07-moreau-projection.md).
pub const PROJECTION_PASSES: usize = 12;

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
            let offsets: Vec<f64> = contacts.iter().map(|c| c.geom.gap + depth).collect();
            let centres = sys.centres();
            for g in groups(&contacts, n) {
                if g.contacts.iter().all(|&k| offsets[k] >= 0.0) {
                    continue;
                }
                let deepest = g.contacts.iter().map(|&k| offsets[k]).fold(0.0, f64::min);
                self.counters.max(&PROJECTION_DEPTH_MAX, depth - deepest);
                let mut prob =
                    SparseContacts::build(scn, &centres, &contacts, &g, &zeros, &offsets);
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
                if !outcome.converged {
                    self.counters.add(&PROJECTIONS_UNCONVERGED, 1);
                }
                if dq.iter().flatten().any(|d| !d.is_finite()) {
                    continue;
                }
                for (l, &i) in g.floes.iter().enumerate() {
                    let b = &mut sys.bodies[i];
                    b.position += Vec2::new(dq[l][0], dq[l][1]);
                    b.angle += dq[l][2];
                }
            }
        }
    }
}
